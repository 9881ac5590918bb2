"""The figure of each term of the model search (calibration/model_search.hpp): each term the
search kept, drawn as the search fitted it, and the candidate its last step named but did not
keep, drawn with the data and the model held but no fitted effect. What is drawn is what the
C++ side wrote (cli/search_figure_data.hpp, cli/term_figure_tables.hpp): the residuals of the
whole record under the final calibration, each kept term's fitted curve, bins, chain or mixture
density, with the values the calibration file holds. This module bins residuals and draws; it
evaluates no model. Each function draws one PNG into DIR/figures/ and returns a
report_style.Figure.
"""

import math
import os
import re

import numpy as np

from report_style import (MODE_COLOURS, Figure, binned_means, equal_count_edges, histogram_bins,
                          legend_right, plt, resolution_mm, save)

# Bins of the time since power-on: 0-15 s, then doubling up to 32 min, then the rest.
POWER_ON_EDGES_S = [0.0, 15.0, 30.0, 60.0, 120.0, 240.0, 480.0, 960.0, 1920.0, math.inf]
TAIL_LEVELS = [0.93, 0.96, 0.98, 0.99, 0.995, 0.998, 1.0]  # heating-rate quantiles, the tail
COVARIATE_NAMES = {
    "junction_temperature": r"junction temperature $\hat{t}^j$",
    "heating_rate": r"junction heating rate $d\hat{t}^j/dt$",
    "time_since_power_on": "time since the last power-on",
    "time": "time since the start of the record",
    "ambient": "ambient temperature",
    "junction_lag": r"the junction's lag $L_\tau(\hat{t}^j) - \hat{t}^j$",
}
KEPT_COLOUR = "#d1495b"
OUTLIER_COLOUR = "#6a4c93"  # apart from the modes' colours


def covariate_label(entry):
    name = COVARIATE_NAMES.get(entry["covariate"], entry["covariate"])
    unit = entry.get("covariate_unit")
    return f"{name} ({unit})" if unit else name


def _number(value, spec=".4g"):
    return format(value, spec) if isinstance(value, (int, float)) else "–"


def verdict_text(entry, alpha_text):
    """Whether the search kept the term, with the step's numbers."""
    p, critical = _number(entry.get("p_value"), ".3g"), _number(entry.get("critical_p"), ".3g")
    if entry.get("kept"):
        return (f"Kept at step {entry['step']} of the search: held-out p-value {p} ≤ "
                f"{critical} ({alpha_text}).")
    return (f"Named at step {entry['step']} but NOT KEPT: held-out p-value {p} > {critical} "
            f"({alpha_text}). The search did not add it, so no fitted effect is drawn: the points "
            f"are the data under the model held (the trained model with the kept terms).")


def fitted_text(entry):
    """The fitted values the calibration holds of a kept term, as the caption gives them."""
    f = entry.get("fitted")
    if not f:
        return ""
    form = entry.get("form")
    unit = entry.get("covariate_unit", "")
    if "coefficients_mm" in f:
        c = f["coefficients_mm"]
        if form == "decay":
            return (f"Fitted: γ = {c[0]:.4g} mm, τ = {f['time_constant_s']:.4g} s: the curve is "
                    f"γ·exp(−c/τ).")
        if form == "linear":
            lag = (f", τ = {f['time_constant_s']:.4g} s" if "time_constant_s" in f else "")
            held = (f", constant outside {f['covariate_range'][0]:.4g} to "
                    f"{f['covariate_range'][1]:.4g} {unit}" if "covariate_range" in f else "")
            return (f"Fitted: γ = {c[0]:.4g} mm on (c − {f['centre']:.4g}) / {f['scale']:.4g}, "
                    f"{f['slope_mm_per_unit']:.4g} mm per {unit}{lag}{held}.")
        return (f"Fitted: coefficients {', '.join(format(x, '.4g') for x in c)} mm on hat "
                f"functions at the knots {', '.join(format(x, '.4g') for x in f['knots'])} "
                f"{unit}.")
    if "transition" in f:
        stay = ", ".join(f"a{i + 1}{i + 1} = {row[i]:.4g}" for i, row in enumerate(f["transition"]))
        return f"Fitted chain: {stay} (the chance that the next range stays in the mode)."
    if "outlier_weight" in f:
        return (f"Fitted: outlier weight ε = {f['outlier_weight']:.4g}, uniform over "
                f"{f['outlier_span_mm']:.4g} mm.")
    if "modes" in f:
        return "Fitted modes: " + "; ".join(
            f"μ = {m['offset_mm']:.4g} mm, σ = {m['std_mm']:.4g} mm, π = {m['weight']:.3g}"
            for m in f["modes"]) + "."
    if "edges" in f:
        what = "variances (mm²)" if "variances_mm2" in f else "weights"
        table = f.get("variances_mm2", f.get("weights"))
        return (f"Fitted {what} per bin (edges {', '.join(format(x, '.4g') for x in f['edges'])} "
                f"{unit}): " + "; ".join("[" + ", ".join(format(x, ".4g") for x in row) + "]"
                                          for row in table) + ".")
    return ""


def _edges_and_axis(entry, x, ax):
    """Bins of the covariate for binned means, and the axis scale: the time since power-on and
    the heating rate are logarithmic beyond where most ranges are."""
    if entry["covariate"] == "time_since_power_on":
        edges = np.array(POWER_ON_EDGES_S)
        edges[-1] = max(float(np.max(x)), edges[-2] + 1.0)
        ax.set_xscale("symlog", linthresh=15.0, linscale=0.6)
        return edges, 10
    if entry["covariate"] == "heating_rate" and np.ptp(x) > 0.0:
        ax.set_xscale("symlog", linthresh=max(float(np.quantile(np.abs(x), 0.9)), 1e-6),
                      linscale=2.0)
        levels = np.concatenate([np.linspace(0.0, 0.9, 10), TAIL_LEVELS])
        return np.unique(np.quantile(x, levels)), 10
    return equal_count_edges(x, 24), 30


def curve_figure(entry, directory, name):
    ranges = entry["tables"]["ranges"]
    acts = ranges["in_term"] == 1
    x, y = ranges["covariate"][acts], ranges["partial_residual_mm"][acts]
    fig, ax = plt.subplots(figsize=(6.5, 4))
    edges, least = _edges_and_axis(entry, x, ax)
    centre, mean, half_width = binned_means(x, y, edges, least)
    whose = (f"ranges of mode {entry['mode']}" if entry["parameter"] == "mode_offset"
             else "ranges")
    curve = entry["tables"].get("curve")
    ax.errorbar(centre, mean, yerr=half_width, marker="o", capsize=3, linestyle="none",
                color="#1f4e9c", label=("partial residual" if curve is not None else "residual")
                + f", bin means of the {whose} (95 %)")
    if curve is not None:
        ax.plot(curve["covariate"], curve["fitted_mm"], color=KEPT_COLOUR, linewidth=1.6,
                label="the term as the search fitted it")
    ax.axhline(0.0, color="k", linewidth=0.8)
    ax.set_xlabel(covariate_label(entry))
    ax.set_ylabel("residual (mm)")
    ax.set_title(("" if entry.get("kept") else "Not kept: ") + entry["effect"])
    legend_right(ax)
    what = ("the residual e = y − d − Hθ̂ − the bias terms − μ̂ of each range's most probable mode "
            "(and its shift) under the final calibration"
            + (", with this term's own contribution added back (the partial residual)"
               if curve is not None else ", the model held"))
    if entry["parameter"] == "mode_offset":
        what += f", on the ranges of mode {entry['mode']}"
    drawn = ("in red, the term as the search fitted it on the whole record, the curve the "
             "calibration file's values give. Look for: the points along the curve."
             if curve is not None else "no curve, as the term was not kept.")
    return Figure(entry["term"], save(fig, directory, name),
                  f"In blue, bin means of {what}, against {covariate_label(entry)}; {drawn}")


def bins_figure(entry, directory, name):
    table = entry["tables"]["bins"]
    spread = entry["parameter"] == "spread"
    fig, ax = plt.subplots(figsize=(6.5, 4))
    modes = sorted(set(table["mode"].astype(int)))
    for i in modes:
        rows = table["mode"] == i
        colour = MODE_COLOURS[(i - 1) % 4]
        ax.plot(table["covariate_mean"][rows], table["observed"][rows], marker="o",
                linestyle="none", color=colour, label=f"mode {i}: observed")
        if np.isfinite(table["fitted"][rows]).any():
            ax.hlines(table["fitted"][rows], table["low"][rows], table["high"][rows], color=colour,
                      linewidth=2.0, label=f"mode {i}: fitted per bin")
        if np.isfinite(table["held"][rows]).any():
            ax.axhline(float(np.nanmean(table["held"][rows])), color=colour, linestyle="--",
                       linewidth=1, label=f"mode {i}: the model held (one value)")
    ax.set_xlabel(covariate_label(entry))
    ax.set_ylabel("spread σ of e (mm)" if spread else "weight of the mode")
    ax.set_ylim(bottom=0)
    ax.set_title(("" if entry.get("kept") else "Not kept: ") + entry["effect"])
    legend_right(ax)
    observed = ("the mode's spread over the bin's ranges, each weighted by its posterior of the "
                "mode" if spread else "the mode's share of the bin's ranges by their posteriors")
    return Figure(entry["term"], save(fig, directory, name),
                  f"Per bin of {covariate_label(entry)} and per mode: markers, {observed} "
                  f"(under the final calibration: what one M-step on the bin's ranges gives); "
                  + ("lines, the value per bin the search fitted (the calibration's)."
                     if entry.get("kept") else "dashed, the single value the model holds."))


def runs_figure(entry, directory, name):
    runs = entry["tables"]["runs"]
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for i in sorted(set(runs["mode"].astype(int))):
        rows = runs["mode"] == i
        colour = MODE_COLOURS[(i - 1) % 4]
        shown = rows & (runs["observed"] > 0)
        ax.semilogy(runs["length"][shown], runs["observed"][shown], marker="o", linestyle="none",
                    markersize=4, color=colour, label=f"mode {i}: observed runs")
        if np.isfinite(runs["chain"][rows]).any():
            ax.semilogy(runs["length"][rows], runs["chain"][rows], color=colour, linewidth=1.6,
                        label=f"mode {i}: the fitted chain")
        ax.semilogy(runs["length"][rows], runs["independent"][rows], color=colour,
                    linestyle="--", linewidth=1, label=f"mode {i}: independent draws")
    ax.set_ylim(bottom=0.5)
    ax.set_xlabel("run length (consecutive ranges in the mode)")
    ax.set_ylabel("number of runs")
    ax.set_title(("" if entry.get("kept") else "Not kept: ") + entry["effect"])
    legend_right(ax)
    return Figure(entry["term"], save(fig, directory, name),
                  "The runs of each range's most probable mode by length (markers), against "
                  "what independent draws with the modes' weights give (dashed)"
                  + (" and what the fitted chain gives (solid), each scaled to the mode's "
                     "observed number of runs." if entry.get("kept") else
                     ", scaled to the mode's observed number of runs; no chain is drawn."))


def density_figure(entry, directory, name, residuals):
    density = entry["tables"]["density"]
    values = residuals["residual_mm"]
    width = resolution_mm(values)
    edges = histogram_bins(values, width)
    outliers = entry["parameter"] == "outliers"
    fig, ax = plt.subplots(figsize=(6.5, 4))
    counts, _, _ = ax.hist(values, edges, color="0.7", label=r"$y - d - $ the bias")
    scale = values.size * width  # density (1/mm) to ranges per bin
    x = density["residual_mm"]

    def shown(column):  # ranges per bin; on a log axis, nothing below a tenth of a range
        v = density[column] * scale
        return np.where(v >= 0.1, v, np.nan) if outliers else v

    modes = sorted(int(c[4:]) for c in density if re.fullmatch(r"mode\d+", c))
    for i in modes:
        ax.plot(x, shown(f"mode{i}"), color=MODE_COLOURS[(i - 1) % 4], linestyle="--",
                linewidth=1, label=f"mode {i}")
    if "outliers" in density:
        ax.plot(x, shown("outliers"), color=OUTLIER_COLOUR, linestyle="--", linewidth=1,
                label="outlier component")
    ax.plot(x, shown("total"), color="k", linewidth=1.4,
            label=("the fitted mixture" if entry.get("kept") else "the mixture held"))
    if outliers:
        ax.set_yscale("log")
        ax.set_ylim(0.5, 3.0 * max(float(np.max(counts)), 1.0))
        ax.set_xlim(edges[0], edges[-1])
    else:
        inner = np.quantile(values, [0.001, 0.999])
        ax.set_xlim(inner[0] - 3 * width, inner[1] + 3 * width)
    ax.set_xlabel(r"residual $y - d - H\hat{\theta} -$ the bias terms (mm)")
    ax.set_ylabel(f"ranges per {width:g} mm bin" + (" (log)" if outliers else ""))
    ax.set_title(("" if entry.get("kept") else "Not kept: ") + entry["effect"])
    legend_right(ax)
    drawn = (f"the mixture the search fitted ({len(modes)} modes"
             + (" and the outlier component" if "outliers" in density else "") + ")"
             if entry.get("kept") else
             f"the mixture the model holds ({len(modes)} modes), without the candidate")
    return Figure(entry["term"], save(fig, directory, name),
                  f"The histogram of y − d less the bias of the final calibration on the whole "
                  f"record, against {drawn}, its density averaged over the ranges' noise states "
                  f"and mode shifts.")


def draw_term_figures(data, directory, progress):
    """The figure of each entry of the context's search_terms, in order: [(entry, Figure)]. A
    term figure of an earlier report in the same directory not drawn now is removed."""
    figures_dir = os.path.join(directory, "figures")
    os.makedirs(figures_dir, exist_ok=True)
    drawn = []
    for entry in data.search_terms:
        progress(f"the figure of the search's term {entry['index']} ({entry['term']})")
        name = f"term{entry['index']}.png"
        kind = entry.get("figure")
        if kind == "curve":
            figure = curve_figure(entry, directory, name)
        elif kind == "bins":
            figure = bins_figure(entry, directory, name)
        elif kind == "runs":
            figure = runs_figure(entry, directory, name)
        else:
            figure = density_figure(entry, directory, name, data.search_residuals)
        drawn.append((entry, figure))
    files = {os.path.basename(f.file) for _, f in drawn}
    for name in os.listdir(figures_dir):
        if re.fullmatch(r"term\d+\.png", name) and name not in files:
            os.remove(os.path.join(figures_dir, name))
    return drawn
