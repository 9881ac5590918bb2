"""The evidence figure of each residual test (core/residual_diagnosis.hpp): what each of the
nine tests measures, drawn on what the test ran on: the whole record under the trained model the
search started from (DIR/data/diagnosis_samples.csv and the context's diagnosis_calibration).
The tests are evidence, not the verdict: the model search names and keeps, and the figure of each
term it kept draws the term as fitted (report_figures_terms). So these figures draw the data and
the trained model (the tests' null), never a fitted effect. The quantities the tests use are the
C++ side's (cli/report_figure_data.hpp), read, not recomputed: the residual y − d − Hθ̂, the most
probable mode under the mixture (Eq. 18, with the true distance, as the tests do),
e = y − d − Hθ̂ − μ̂ of that mode, the junction's heating rate as the tests used it and the time
since the last power-on. Each function draws one PNG into DIR/figures/ and returns a
report_style.Figure, or None when the data do not allow it.
"""

import math
import os
import re

import numpy as np

from report_style import (MODE_COLOURS, Figure, binned_means, equal_count_edges, histogram_bins,
                          legend_right, plt, resolution_mm, save)

TAIL_Z = 8.0  # core/residual_diagnosis.hpp: DiagnosisOptions::tail_z
LAGS = 20  # core/residual_diagnosis.hpp: DiagnosisOptions::ljung_box_lags
WARM_UP_EDGES_S = [0.0, 15.0, 30.0, 60.0, 120.0, 240.0, 480.0, 960.0, 1920.0, math.inf]
TAIL_LEVELS = [0.93, 0.96, 0.98, 0.99, 0.995, 0.998, 1.0]  # heating-rate quantiles, the tail
ON_THE_RECORD = ("Evidence: drawn on the whole record under the trained model the test ran on "
                 "(none of the search's terms in it), no fitted effect.")


class Residuals:
    """What the diagnosis computed of each range it tested (DIR/data/diagnosis_samples.csv), and
    the modes of the calibration it ran under."""

    def __init__(self, samples, modes, computed):
        self.time_s = samples["time_s"]
        self.time_since_power_on_s = samples["time_since_power_on_s"]
        self.junction_c = samples["junction_c"]
        self.residual = samples["residual_mm"]
        self.mu = np.array([m["offset_mm"] for m in modes], dtype=float)
        self.sigma = np.array([m["std_mm"] for m in modes], dtype=float)
        self.weight = np.array([m["weight"] for m in modes], dtype=float)
        self.mode = samples["mode"].astype(int)
        self.e = samples["e_mm"]
        self.heating_rate_c_per_min = samples["heating_rate_c_per_min"]
        # What the C++ side computed beside the samples (context.json's diagnosis_samples): the
        # half window of the heating rate.
        self.rate_half_window_s = computed["heating_rate_half_window_s"]
        self.n = self.residual.size
        self.step_mm = resolution_mm(samples["range_mm"])  # the scanner's range step
        # The outliers' test: each mode's robust scale, the lasing modes, the expected count
        # beyond (its finding's mode_scale_mm, lasing_modes and null_mean); set by
        # draw_finding_figures.
        self.outlier_scale = None
        self.lasing_modes = []
        self.outlier_expected = None
        self.outlier_resolution_mm = 0.0


def autocorrelation(x, lags):
    x = x - np.mean(x)
    total = float(x @ x)
    return np.array([float(x[:-k] @ x[k:]) / total for k in range(1, lags + 1)])


def run_lengths(labels):
    """The label and the length of each run of equal labels, in order."""
    change = np.flatnonzero(np.diff(labels)) + 1
    starts = np.concatenate([[0], change])
    ends = np.concatenate([change, [labels.size]])
    return labels[starts], ends - starts


def _mode_label(i):
    return f"mode {i + 1}"


def mode_persistence(r, directory, name):
    if r.mu.size < 2:
        return None
    first = (r.mode == 0).astype(int)
    p1 = first.mean()
    if p1 in (0.0, 1.0):
        return None
    label, length = run_lengths(first)
    fig, (left, right) = plt.subplots(1, 2, figsize=(9.5, 3.9))
    rest = "mode 2" if r.mu.size == 2 else f"modes 2..{r.mu.size}"
    longest = int(length.max())
    span = np.arange(1, min(longest, 60) + 1)
    for state, p, text, colour in ((1, p1, "mode 1", MODE_COLOURS[0]),
                                   (0, 1.0 - p1, rest, MODE_COLOURS[1])):
        observed = np.bincount(length[label == state], minlength=span.size + 1)[1:span.size + 1]
        expected = r.n * (1.0 - p) ** 2 * p ** span  # runs of length L under independence
        shown = observed > 0
        left.semilogy(span[shown], observed[shown], marker="o", linestyle="none",
                      markersize=4, color=colour, label=f"runs of {text}: observed")
        left.semilogy(span, expected, color=colour, linewidth=1.2,
                      label=f"runs of {text}: independent draws (geometric)")
    left.set_ylim(bottom=0.5)
    left.set_xlabel("run length (consecutive ranges)")
    left.set_ylabel("number of runs")
    left.set_title("Runs of the most probable mode")
    left.legend(loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2, fontsize=8)
    lags = np.arange(1, LAGS + 1)
    acf = autocorrelation(first.astype(float), LAGS)
    band = 1.96 / math.sqrt(r.n)
    right.bar(lags, acf, color=MODE_COLOURS[0], width=0.6)
    right.axhspan(-band, band, color="0.85", zorder=0,
                  label="±1.96/√n (independent draws)")
    right.axhline(0.0, color="k", linewidth=0.8)
    right.set_xlabel("lag (ranges)")
    right.set_ylabel("autocorrelation of the mode-1 indicator")
    right.set_title("Autocorrelation of the mode")
    right.legend(loc="upper center", bbox_to_anchor=(0.5, -0.2), fontsize=8)
    fig.tight_layout()
    runs = length.size
    expected_runs = 2.0 * r.n * p1 * (1.0 - p1) + 1.0
    return Figure("runs test on the order of the most probable modes",
                  save(fig, directory, name),
                  f"Left: how many runs of each length the sequence of most probable modes has "
                  f"(markers) against what independent draws with the same shares give (lines, "
                  f"geometric). Right: the autocorrelation of the indicator of mode 1 at lags "
                  f"1..{LAGS}. Look for: a persistent mode has more long runs than the geometric "
                  f"line and a positive autocorrelation outside the band; independent draws "
                  f"follow the line and stay inside the band. An autocorrelation that is "
                  f"positive and level at every lag is a share of the modes that changes slowly "
                  f"(with a drift or the temperature), not persistence, which decays with the "
                  f"lag. These ranges have {runs} runs "
                  f"where independent draws would give about {expected_runs:.0f}. "
                  f"The most probable mode is recomputed from samples.csv under the trained "
                  f"mixture, as the diagnosis does. {ON_THE_RECORD}")


def temperature_dependent_weights(r, directory, name):
    if r.mu.size < 2:
        return None
    order = np.argsort(r.junction_c, kind="stable")
    quartile = np.empty(r.n, dtype=int)
    quartile[order] = np.arange(r.n) * 4 // r.n  # by rank, as the test does
    fig, ax = plt.subplots(figsize=(6.5, 4))
    positions = np.arange(4)
    labels = []
    for q in range(4):
        t = r.junction_c[quartile == q]
        labels.append(f"{t.min():.2f}–{t.max():.2f}")
    offsets = np.linspace(-0.12, 0.12, r.mu.size)
    for i in range(r.mu.size):
        colour = MODE_COLOURS[i % 4]
        share, half_width = [], []
        for q in range(4):
            chosen = r.mode[quartile == q] == i
            p = chosen.mean()
            share.append(p)
            half_width.append(1.96 * math.sqrt(p * (1.0 - p) / chosen.size))
        ax.errorbar(positions + offsets[i], share, yerr=half_width, marker="o", capsize=3,
                    color=colour, label=f"share of {_mode_label(i)} (95 % interval)")
        ax.axhline(np.mean(r.mode == i), color=colour, linestyle="--", linewidth=1,
                   label=f"{_mode_label(i)} over all ranges")
    ax.set_xticks(positions)
    ax.set_xticklabels(labels)
    ax.set_xlabel(r"junction-temperature quartile, $\hat{t}^j$ (°C)")
    ax.set_ylabel("share of ranges in the mode")
    ax.set_title("Mode shares per junction-temperature quartile")
    legend_right(ax)
    return Figure("χ² independence of the most probable mode and the temperature quartile",
                  save(fig, directory, name),
                  "The share of ranges whose most probable mode is each mode, in each quartile of "
                  "the junction temperature (the contingency table of the χ² test), with 95 % "
                  "binomial intervals; dashed, each mode's share over all ranges. Look for: "
                  "shares that climb or fall across the quartiles, beyond their intervals, mean "
                  "weights that depend on temperature; flat shares on the dashed lines mean they "
                  f"do not. {ON_THE_RECORD}")


def temperature_dependent_spread(r, directory, name):
    bins = 10
    edges = equal_count_edges(r.junction_c, bins)
    index = np.clip(np.searchsorted(edges, r.junction_c, side="right") - 1, 0, edges.size - 2)
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for i in range(r.mu.size):
        colour = MODE_COLOURS[i % 4]
        centre, spread, half_width = [], [], []
        for b in range(edges.size - 1):
            chosen = (index == b) & (r.mode == i)
            if chosen.sum() < 10:
                continue
            s = 1.4826 * np.median(np.abs(r.e[chosen]))
            centre.append(np.mean(r.junction_c[chosen]))
            spread.append(s)
            half_width.append(1.96 * 1.166 * s / math.sqrt(chosen.sum()))
        if centre:
            ax.errorbar(centre, spread, yerr=half_width, marker="o", capsize=3, color=colour,
                        label=f"{_mode_label(i)}: robust σ of e (95 % interval)")
        ax.axhline(r.sigma[i], color=colour, linestyle="--", linewidth=1,
                   label=rf"{_mode_label(i)}: trained $\hat{{\sigma}}_{i + 1}$")
    ax.set_xlabel(r"junction temperature $\hat{t}^j$ (°C)")
    ax.set_ylabel("spread of e, 1.4826 × median |e| (mm)")
    ax.set_title("Spread of the mode-compensated residual against temperature")
    ax.set_ylim(bottom=0)
    legend_right(ax)
    return Figure("rank correlation of |z| with the junction temperature",
                  save(fig, directory, name),
                  f"The spread of the mode-compensated residual e = y − d − Hθ̂ − μ̂ of each "
                  f"range's most probable mode, per mode, in {edges.size - 1} equal-count bins of "
                  f"the junction temperature (1.4826 × the median |e|, which a few outliers do "
                  f"not move, as the test's ranks are not), against the trained σ̂ of each mode "
                  f"(dashed). Look for: a spread that rises or falls with temperature; level "
                  f"points on the dashed lines mean the mode variances do not depend on it. "
                  f"{ON_THE_RECORD}")


def outliers(r, directory, name):
    """The test's own bound (core/residual_diagnosis.cpp, tail_count): each range's distance from
    the nearest lasing mode, less half the rounding, in that mode's robust scale (the finding's
    mode_scale_mm, lasing_modes and resolution_mm); beyond TAIL_Z from every lasing mode is an
    outlier."""
    if r.outlier_scale is None or not r.lasing_modes:
        return None
    lasing = np.array(r.lasing_modes, dtype=int)
    mu, scale = r.mu[lasing], r.outlier_scale[lasing]
    x = np.min((np.abs(r.residual[:, None] - mu) - 0.5 * r.outlier_resolution_mm) / scale, axis=1)
    x = np.maximum(x, 0.0)
    span = float(np.max(x))
    width = max(0.25, span / 300.0)
    edges = np.arange(0.0, span + 2 * width, width)
    beyond = int(np.sum(x > TAIL_Z))
    fig, ax = plt.subplots(figsize=(6.5, 4))
    ax.hist(x, edges, color="0.6", label="ranges")
    ax.axvline(TAIL_Z, color="#d1495b", linestyle="--", linewidth=1.2,
               label=f"{TAIL_Z:g} robust σ: {beyond} ranges beyond")
    counts, _ = np.histogram(x, edges)
    ax.set_yscale("log")
    ax.set_ylim(0.5, 3.0 * max(counts.max(), 1))
    ax.set_xlabel("distance from the nearest lasing mode, less half the rounding, "
                  "in its robust σ")
    ax.set_ylabel(f"ranges per {width:g} σ bin (log)")
    ax.set_title("Residuals from the nearest lasing mode")
    legend_right(ax)
    scales = ", ".join(f"{_mode_label(int(i))} {s:.2f} mm" for i, s in zip(lasing, scale))
    expected = r.outlier_expected
    expected_text = f"{expected:.1g}" if expected is not None else "almost none"
    return Figure(f"ranges beyond {TAIL_Z:g} robust σ of every lasing mode",
                  save(fig, directory, name),
                  f"Each residual y − d − Hθ̂'s distance from the nearest lasing mode's offset, "
                  f"less half the rounding (a rounded range beyond the bound was beyond it "
                  f"before the rounding), in that mode's robust σ: 1.4826 × the median "
                  f"|y − d − Hθ̂ − μ̂| of its ranges, each weighted by its responsibility (σ̂ for "
                  f"Gaussian modes; a mode the EM widened to hold outliers keeps its core's). "
                  f"The lasing modes are those no wider than the LMS 200's statistical error of "
                  f"a range ({scales}). Look for: counts beyond the dashed {TAIL_Z:g} σ bound, "
                  f"where Gaussian modes would put {expected_text} of these {r.n} ranges; here "
                  f"{beyond} lie beyond. {ON_THE_RECORD}")


def _draw_bin_means(ax, r, x, edges, least):
    """Binned means of e against x, and of y − d − Hθ̂ less its mean, with 95 % intervals;
    returns each series as (values, label text, colour, the bins' mean x)."""
    series = ((r.e, "e (the tested residual)", "#1f4e9c", "o"),
              (r.residual - np.mean(r.residual), r"$y - d - H\hat{\theta}$ less its mean",
               "#e9a03b", "s"))
    drawn = []
    for values, text, colour, marker in series:
        centre, mean, half_width = binned_means(x, values, edges, least)
        ax.errorbar(centre, mean, yerr=half_width, marker=marker, capsize=3, linestyle="none",
                    color=colour, label=f"{text}: bin means (95 % interval)")
        drawn.append((values, text, colour, centre))
    return drawn


def _binned_residual(r, x, edges, xlabel, title, directory, name, linear_up_to=None, least=30):
    """Binned means of e against x, and of y − d − Hθ̂ less its mean: the mode left in, so that
    a shift that moves ranges across the modes' midpoint (and e to the other mode) still shows.
    No line or curve: a fitted effect is the search's, drawn in its term's figure."""
    fig, ax = plt.subplots(figsize=(6.5, 4))
    if linear_up_to is not None:
        ax.set_xscale("symlog", linthresh=linear_up_to, linscale=2.0)
    _draw_bin_means(ax, r, x, edges, least)
    ax.axhline(0.0, color="k", linewidth=0.8)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("residual (mm)")
    ax.set_title(title)
    legend_right(ax)
    return save(fig, directory, name)


BOTH_RESIDUALS = ("In orange, the same for y − d − Hθ̂ less its mean (the mode left in): "
                  "under a shift that carries ranges past the midpoint between two modes, e "
                  "jumps to the other mode and its means understate the shift, these do not.")


def heating_hysteresis(r, directory, name):
    rate = r.heating_rate_c_per_min
    if np.ptp(rate) <= 0.0:
        return None
    linear_up_to = float(np.quantile(np.abs(rate), 0.9))
    # Equal-count bins of 10 % up to the 90 % quantile, then narrower ones into the tail, where
    # the fast heating after a power-on is.
    levels = np.concatenate([np.linspace(0.0, 0.9, 10), TAIL_LEVELS])
    edges = np.unique(np.quantile(rate, levels))
    file = _binned_residual(
        r, rate, edges, r"junction heating rate $d\hat{t}^j/dt$ (°C/min)",
        "Residual against the heating rate", directory, name, linear_up_to=linear_up_to,
        least=10)
    return Figure("correlation of e with the junction's heating rate", file,
                  f"In blue, the mean of the mode-compensated residual e = y − d − Hθ̂ − μ̂ of "
                  f"each range's most probable mode (the residual the test correlates) in bins "
                  f"of the junction's heating rate, 10 % of the ranges each up to the 90 % "
                  f"quantile, then 3, 3, 2, 1, 0.5, 0.3 and 0.2 % (the least-squares slope of "
                  f"t̂ʲ over ±{r.rate_half_window_s:g} s, as the diagnosis computed it; the axis "
                  f"is linear up to ±{linear_up_to:.3g} °C/min, "
                  f"where 90 % of the ranges are, logarithmic beyond). {BOTH_RESIDUALS} Look "
                  f"for: a slope, "
                  f"a range that depends on whether the junction heats or cools at the same "
                  f"temperature; level points within their intervals mean no hysteresis. "
                  f"{ON_THE_RECORD}")


def time_drift(r, directory, name):
    hours = r.time_s / 3600.0
    if np.ptp(hours) <= 0.0:
        return None
    file = _binned_residual(
        r, hours, equal_count_edges(hours, 24), "time since the start of the record (h)",
        "Residual against time", directory, name)
    return Figure("correlation of e with time", file,
                  f"In blue, the mean of the mode-compensated residual e = y − d − Hθ̂ − μ̂ of "
                  f"each range's most probable mode (the residual the test correlates) in 24 "
                  f"equal-count bins of time. {BOTH_RESIDUALS} Look for: a trend with time that "
                  f"the temperature does not explain; points about a level line within their "
                  f"intervals mean no drift. {ON_THE_RECORD}")


def warm_up(r, directory, name):
    t_on = r.time_since_power_on_s
    if np.ptp(t_on) <= 0.0:
        return None
    edges = np.array(WARM_UP_EDGES_S)
    edges[-1] = max(float(np.max(t_on)), edges[-2] + 1.0)
    fig, ax = plt.subplots(figsize=(6.5, 4))
    ax.set_xscale("symlog", linthresh=15.0, linscale=0.6)
    _draw_bin_means(ax, r, t_on, edges, 10)
    ax.axhline(0.0, color="k", linewidth=0.8)
    ax.set_xlabel("time since the last power-on (s)")
    ax.set_ylabel("residual (mm)")
    ax.set_title("Residual against the time since power-on")
    legend_right(ax)
    return Figure("correlation of e with exp(−t_on/τ), the best τ of the grid",
                  save(fig, directory, name),
                  f"In blue, the mean of the mode-compensated residual e = y − d − Hθ̂ − μ̂ of "
                  f"each range's most probable mode (the residual the test correlates with "
                  f"exp(−t_on/τ) for each τ of the grid 30 s … 32 min) in bins of the time since "
                  f"the scanner was last switched on (0–15 s, then doubling up to 32 min, then "
                  f"the rest; the axis is linear up to 15 s, logarithmic beyond). The trained "
                  f"bias Hθ̂ has absorbed part of a transient into the temperature, so these "
                  f"means understate it: the amplitude and time constant are the search's, in "
                  f"its term's figure when it kept one. {BOTH_RESIDUALS} Look for: the first "
                  f"minutes after a power-on away from the rest, a transient the junction's "
                  f"temperature does not explain; points level within their intervals mean no "
                  f"warm-up. {ON_THE_RECORD}")


def extra_mode(r, directory, name):
    width = r.step_mm
    edges = histogram_bins(r.residual, width)
    observed, _ = np.histogram(r.residual, edges)
    erf = np.frompyfunc(math.erf, 1, 1)
    cdf = np.zeros(edges.size)
    for mu, sigma, weight in zip(r.mu, r.sigma, r.weight):
        cdf += weight * 0.5 * (1.0 + erf((edges - mu) / (sigma * math.sqrt(2.0))).astype(float))
    expected = r.n * np.diff(cdf)
    centres = 0.5 * (edges[:-1] + edges[1:])
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(6.5, 5.4), sharex=True,
                                      gridspec_kw={"height_ratios": [3, 1.4]})
    top.bar(centres, observed, width=width, color="0.7", label=r"$y - d - H\hat{\theta}$")
    grid = np.linspace(edges[0], edges[-1], 600)
    density = sum(w * np.exp(-0.5 * ((grid - mu) / sigma) ** 2) / (sigma * math.sqrt(2 * math.pi))
                  for mu, sigma, w in zip(r.mu, r.sigma, r.weight))
    top.plot(grid, r.n * width * density, color="k", linewidth=1.4,
             label=f"trained mixture of {r.mu.size} modes (Eq. 8)")
    for i, mu in enumerate(r.mu):
        top.axvline(mu, color=MODE_COLOURS[i % 4], linestyle="--", linewidth=1,
                    label=rf"$\hat{{\mu}}_{i + 1}$ = {mu:.2f} mm")
    top.set_ylabel(f"ranges per {width:g} mm bin")
    top.set_title("Residual against the trained mixture")
    legend_right(top)
    shown = expected >= 1.0
    pearson = (observed[shown] - expected[shown]) / np.sqrt(expected[shown])
    bottom.bar(centres[shown], pearson, width=width, color="#1f4e9c")
    bottom.axhspan(-2.0, 2.0, color="0.85", zorder=0)
    bottom.axhline(0.0, color="k", linewidth=0.8)
    bottom.set_ylabel("(observed − mixture)\n/ √mixture")
    bottom.set_xlabel(r"residual $y - d - H\hat{\theta}$ (mm)")
    return Figure("split likelihood ratio of M + 1 modes against M", save(fig, directory, name),
                  f"The histogram of the residual y − d − Hθ̂ of the {r.n} ranges against the "
                  f"count the trained mixture of {r.mu.size} lasing modes predicts per bin "
                  f"({width:g} mm, the scanner's step); below, the difference in units of its "
                  f"Poisson deviation (bins the mixture expects at least one range in; grey: "
                  f"±2). Differences beyond ±2 are a misfit of the trained mixture, not by "
                  f"themselves a missing mode: any effect that moves the residual over the "
                  f"record (a drift, a warm-up, a bias with the heating rate) widens and skews "
                  f"the bands as well. A missing mode is a bump away from the trained offsets "
                  f"that the test's held-out gain confirms and the search keeps (both verdicts "
                  f"open this caption). The statistic is the log of the split likelihood ratio, "
                  f"the held-out log-likelihood gain of M + 1 modes over M. {ON_THE_RECORD}")


def serial_dependence(r, directory, name):
    lags = np.arange(1, LAGS + 1)
    acf = autocorrelation(r.e, LAGS)
    q = r.n * (r.n + 2) * float(np.sum(acf ** 2 / (r.n - lags)))
    band = 1.96 / math.sqrt(r.n)
    fig, ax = plt.subplots(figsize=(6.5, 4))
    ax.bar(lags, acf, width=0.6, color="#1f4e9c",
           label=f"autocorrelation of e (Ljung–Box Q = {q:.4g} on these ranges)")
    ax.axhspan(-band, band, color="0.85", zorder=0, label="±1.96/√n (white noise)")
    ax.axhline(0.0, color="k", linewidth=0.8)
    ax.set_xticks(lags)
    ax.set_xlabel("lag (ranges)")
    ax.set_ylabel("autocorrelation of e")
    ax.set_title("Serial dependence of the mode-compensated residual")
    legend_right(ax)
    return Figure("Ljung–Box on e, lags 1..20", save(fig, directory, name),
                  f"The autocorrelation of the mode-compensated residual e = y − d − Hθ̂ − μ̂ at "
                  f"lags 1..{LAGS} ranges, with the ±1.96/√n band of white noise (n = {r.n}). "
                  f"Look for: bars outside the band, above all at the first lags: structure in "
                  f"time the model lacks (a drift, a hysteresis or a persistent mode each show "
                  f"here too); bars inside the band mean independent residuals. {ON_THE_RECORD}")


# The effect names of core::effect_name and the function that draws each one's figure.
FINDING_FIGURES = {
    "mode persistence": mode_persistence,
    "temperature-dependent mode weights": temperature_dependent_weights,
    "temperature-dependent spread": temperature_dependent_spread,
    "outliers": outliers,
    "heating hysteresis": heating_hysteresis,
    "time drift": time_drift,
    "warm-up after power-on": warm_up,
    "one more lasing mode": extra_mode,
    "serial dependence": serial_dependence,
}


def slug(effect):
    return re.sub(r"[^a-z0-9]+", "-", effect.lower()).strip("-")


def draw_finding_figures(data, directory, progress):
    """The figure of each finding in the diagnosis JSON: {effect: Figure}. An effect whose figure
    the data do not allow (one trained mode, an unknown effect) has none. A finding figure of an
    earlier report in the same directory that is not drawn now is removed."""
    figures_dir = os.path.join(directory, "figures")
    os.makedirs(figures_dir, exist_ok=True)
    findings = data.diagnosis.get("findings") or []
    modes = data.context.get("diagnosis_calibration", {}).get("modes", [])
    residuals = (Residuals(data.diagnosis_samples, modes, data.context["diagnosis_samples"])
                 if modes else None)
    for finding in findings:
        if residuals is not None and finding.get("effect") == "outliers":
            scale = finding.get("mode_scale_mm")
            residuals.outlier_scale = np.array(scale, dtype=float) if scale else None
            residuals.lasing_modes = finding.get("lasing_modes") or []
            residuals.outlier_expected = finding.get("null_mean")
            residuals.outlier_resolution_mm = float(finding.get("resolution_mm") or 0.0)
    drawn = {}
    for i, finding in enumerate(findings):
        effect = finding.get("effect")
        draw = FINDING_FIGURES.get(effect)
        progress(f"the figure of finding {i + 1}/{len(findings)} ({effect})")
        if draw is None or residuals is None:
            continue
        figure = draw(residuals, directory, f"finding_{slug(effect).replace('-', '_')}.png")
        if figure is not None:
            drawn[effect] = figure
    files = {os.path.basename(f.file) for f in drawn.values()}
    for name in os.listdir(figures_dir):
        if re.fullmatch(r"finding_\w+\.png", name) and name not in files:
            os.remove(os.path.join(figures_dir, name))
    return drawn
