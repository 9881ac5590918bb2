"""The paper's figures (Alhashimi et al., Sensors 2015) drawn on the data of a diagnosis report.

One function per paper figure: it draws the PNG into DIR/figures/ with matplotlib (Agg backend)
and returns a Figure (its paper number, file and caption), or None when the data do not allow it
(the reason is then in `skipped`). The data come from report_data.ReportData.
"""

import os
import re
from dataclasses import dataclass

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
import numpy as np  # noqa: E402

from report_data import most_probable_mode, mode_count  # noqa: E402

DPI = 110
MODE_COLOURS = ["#1f4e9c", "#d1495b", "#2a9d8f", "#e9a03b"]
ESTIMATORS = [  # the three estimators of §8.4, Fig. 17-19
    ("raw_mean", r"$\bar{y}$ (window mean of raw ranges)", "#d1495b"),
    ("bias_corrected_mean", r"$\overline{y - H\hat{\theta}}$ (temperature bias removed)",
     "#e9a03b"),
    ("em_distance", r"$\hat{d}$ (EM testing, §6)", "#1f4e9c"),
]

plt.rcParams.update({
    "font.size": 10,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "legend.fontsize": 9,
    "figure.dpi": DPI,
})


@dataclass
class Figure:
    paper: str  # what the paper's figure shows
    file: str  # relative to the report directory
    caption: str  # what it shows on these data
    number: str = ""  # the paper's figure number, set by draw_figures from FIGURES


def _legend_right(ax, **options):
    """The legend beside the axes, where it hides no data."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, **options)


def _save(fig, directory, name):
    relative = os.path.join("figures", name)
    fig.savefig(os.path.join(directory, relative), dpi=DPI, bbox_inches="tight")
    plt.close(fig)
    return relative


def _range_error(samples):
    return samples["range_mm"] - samples["true_range_mm"]


def _resolution_mm(ranges):
    """The scanner's range step (1 mm, or 10 mm in cm mode), for histogram bins."""
    steps = np.diff(np.unique(ranges))
    steps = steps[steps > 1e-9]
    return max(1.0, float(np.min(steps))) if steps.size else 1.0


def _bins(values, width):
    low = np.floor(np.nanmin(values) / width) * width - width / 2
    high = np.ceil(np.nanmax(values) / width) * width + width
    return np.arange(low, high, width)


def _modes(context):
    return context.get("calibration", {}).get("modes", [])


def _temperature_span(samples):
    t = samples["junction_c"]
    return f"{np.nanmin(t):.1f}-{np.nanmax(t):.1f} °C"


def histogram(data, directory):
    """Fig. 3: histogram of the ranges; the lasing modes show as separate peaks."""
    s = data.samples
    raw = _range_error(s)
    compensated = raw - s["bias_mm"]
    width = _resolution_mm(s["range_mm"])
    bins = _bins(np.concatenate([raw, compensated]), width)
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.hist(compensated, bins, color="0.7",
            label=r"$y - d - H\hat{\theta}$ (temperature bias removed)")
    ax.hist(raw, bins, histtype="step", color="k", linewidth=1.2, label=r"$y - d$ (raw)")
    modes = _modes(data.context)
    x = np.linspace(bins[0], bins[-1], 600)
    total = np.zeros_like(x)
    for i, m in enumerate(modes):
        density = m["weight"] * np.exp(-0.5 * ((x - m["offset_mm"]) / m["std_mm"]) ** 2) / (
            m["std_mm"] * np.sqrt(2 * np.pi))
        total += density
        ax.plot(x, density * compensated.size * width, color=MODE_COLOURS[i % 4], linestyle="--",
                label=f"mode {i + 1}: μ = {m['offset_mm']:.2f} mm, σ = {m['std_mm']:.2f} mm, "
                      f"π = {m['weight']:.2f}")
    if modes:
        ax.plot(x, total * compensated.size * width, color="k", linewidth=1.5,
                label="trained mixture (Eq. 8)")
    ax.set_xlabel("range error (mm)")
    ax.set_ylabel(f"ranges per {width:g} mm bin")
    ax.set_title("Histogram of the held-out ranges")
    _legend_right(ax)
    return Figure("histogram of consecutive ranges at equilibrium",
                  _save(fig, directory, "fig03_histogram.png"),
                  f"The errors y − d of the {raw.size} held-out ranges (outline) and the same "
                  f"with the trained temperature bias Hθ̂ removed (grey), against the trained "
                  f"mixture of {len(modes)} lasing modes. Junction {_temperature_span(s)}; bins of "
                  f"{width:g} mm, the scanner's range step.")


def bias_against_temperature(data, directory):
    """Fig. 4: the range against the junction temperature; the modes shift with temperature."""
    s = data.samples
    raw = _range_error(s)
    width = _resolution_mm(s["range_mm"])
    fig, ax = plt.subplots(figsize=(6, 4.2))
    _, _, _, image = ax.hist2d(s["junction_c"], raw, bins=[60, _bins(raw, width)],
                               cmap="Greys", cmin=1)
    fig.colorbar(image, ax=ax, label="ranges per cell")
    ax.set_xlabel(r"estimated junction temperature $\hat{t}^j$ (°C)")
    ax.set_ylabel(r"range error $y - d$ (mm)")
    ax.set_title("Range error against the junction temperature")
    return Figure("dependency of the distance measurements on the device temperature",
                  _save(fig, directory, "fig04_bias_temperature.png"),
                  f"The {raw.size} held-out range errors y − d against the smoothed junction "
                  f"temperature t̂ʲ (Eq. 7), as a two-dimensional histogram: the bands are the "
                  f"lasing modes, their drift with temperature is the bias the device's own "
                  f"compensation leaves.")


def thermal_fit(data, directory):
    """Fig. 8: the thermal model driven by the held-out inputs against the measured case."""
    t = data.thermal_fit
    if t is None or t["time_s"].size == 0:
        return None
    hours = t["time_s"] / 3600.0
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(6, 5), sharex=True,
                                      gridspec_kw={"height_ratios": [3, 1]})
    top.plot(hours, t["measured_case_c"], color="0.55", linewidth=1, label=r"measured case $t^s$")
    top.plot(hours, t["predicted_case_c"], color="#1f4e9c", linewidth=1.4,
             label="predicted by the identified model (Eq. 5)")
    top.set_ylabel("case temperature (°C)")
    _legend_right(top)
    top.set_title("Thermal model on the held-out power cycles")
    bottom.plot(hours, t["predicted_case_c"] - t["measured_case_c"], color="k", linewidth=0.8)
    bottom.set_ylabel("error (°C)")
    bottom.set_xlabel("time since the start of the record (h)")
    fit = data.context.get("thermal_fit", {})
    paper = fit.get("held_out_paper_fit_percent")
    nrmse = fit.get("held_out_nrmse_fit_percent")
    numbers = (f" Fit on these cycles: {paper:.5f} % by Eq. 26 (the paper: 92.79 %), "
               f"{nrmse:.2f} % NRMSE." if paper is not None and nrmse is not None else "")
    return Figure("validation of the thermal model Eq. 5",
                  _save(fig, directory, "fig08_thermal_fit.png"),
                  "The model identified on the first half (Algorithm 1, then the prediction-error "
                  "fit) driven by the power inputs of the held-out half, against the measured case "
                  "temperature; below, the prediction error." + numbers)


def _family_name(family):
    return "Fourier" if family == "fourier" else family


def _glr_family(data, family):
    g = data.glr
    chosen = g["family"] == family
    ok = chosen & (g["ok"] == 1)
    return g["order"][ok].astype(int), g["glr"][ok], g["bic"][ok], \
        g["held_out_log_likelihood_per_sample"][ok], g["order"][chosen & (g["ok"] != 1)].astype(int)


def _glr(data, directory, family, name, paper):
    if data.glr is None:
        return None
    orders, glr, bic, held_out, failed = _glr_family(data, family)
    if orders.size == 0:
        return None
    fig, ax = plt.subplots(figsize=(6, 3.8))
    ax.plot(orders, glr, marker="o", color="#1f4e9c", label="GLR 2(ℓᵢ − ℓ₀) (Eq. 27-29)")
    best_glr, best_bic, best_held = (orders[np.argmax(glr)], orders[np.argmin(bic)],
                                     orders[np.argmax(held_out)])
    ax.plot([best_glr], [glr.max()], marker="*", markersize=14, color="#d1495b", linestyle="none",
            label=f"largest GLR (Algorithm 2): order {best_glr}")
    ax.axvline(best_bic, color="#2a9d8f", linestyle="--", label=f"smallest BIC: order {best_bic}")
    ax.axvline(best_held, color="#e9a03b", linestyle=":", linewidth=2,
               label=f"best held-out likelihood: order {best_held}")
    equation = "9" if family == "polynomial" else "11"
    ax.set_xlabel(f"{_family_name(family)} order N of H (Eq. {equation})")
    ax.set_ylabel("generalized likelihood ratio")
    ax.set_xticks(orders)
    f0 = data.context.get("glr", {}).get("fourier_f0_per_c")
    suffix = f", f0 = {f0:.3g} /°C" if family == "fourier" and f0 is not None else ""
    ax.set_title(f"Algorithm 2 over {_family_name(family)} bases{suffix}")
    _legend_right(ax)
    failures = (f" Training failed for order(s) {', '.join(str(o) for o in failed)}."
                if failed.size else "")
    n = data.context.get("glr", {}).get("training_samples", "the")
    return Figure(paper, _save(fig, directory, name),
                  f"The GLR of each {_family_name(family)} basis against the single-Gaussian "
                  f"null (Eq. 28), trained by EM on the {n} training ranges. The GLR grows with "
                  f"every nested order, so the largest is the largest order; BIC and the "
                  f"likelihood of held-out blocks do not, and are the criteria to trust."
                  f"{failures}")


def glr_polynomial(data, directory):
    """Fig. 9: GLR over polynomial orders."""
    return _glr(data, directory, "polynomial", "fig09_glr_polynomial.png",
                "generalized likelihood ratio for the polynomial model")


def glr_fourier(data, directory):
    """Fig. 10: GLR over Fourier orders."""
    return _glr(data, directory, "fourier", "fig10_glr_fourier.png",
                "generalized likelihood ratio for the Fourier model")


def mode_assignment(data, directory):
    """Fig. 11: each range with its most probable mode, and the temperature bias Hθ̂."""
    s = data.samples
    raw = _range_error(s)
    mode = most_probable_mode(s)
    modes = _modes(data.context)
    order = np.argsort(s["junction_c"])
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for i in range(mode_count(s)):
        chosen = mode == i
        ax.scatter(s["junction_c"][chosen], raw[chosen], s=3, alpha=0.35, color=MODE_COLOURS[i % 4],
                   rasterized=True, label=f"ranges assigned to mode {i + 1} ({chosen.sum()})")
    ax.plot(s["junction_c"][order], s["bias_mm"][order], color="k", linewidth=2,
            label=r"temperature bias $H\hat{\theta}$")
    for i, m in enumerate(modes):
        ax.plot(s["junction_c"][order], s["bias_mm"][order] + m["offset_mm"],
                color=MODE_COLOURS[i % 4], linewidth=1.2, linestyle="--",
                label=rf"$H\hat{{\theta}} + \hat{{\mu}}_{i + 1}$")
    ax.set_xlabel(r"estimated junction temperature $\hat{t}^j$ (°C)")
    ax.set_ylabel(r"range error $y - d$ (mm)")
    ax.set_title("Lasing modes assigned by EM testing")
    _legend_right(ax, markerscale=4)
    return Figure("EM testing on real data: modes and temperature bias",
                  _save(fig, directory, "fig11_mode_assignment.png"),
                  "Each held-out range error against t̂ʲ, coloured by its most probable lasing "
                  "mode (the posterior Δ̂ of Eq. 22 at the EM estimate of the whole held-out "
                  "record), with the trained temperature bias Hθ̂ (solid) and each mode's offset "
                  "on it (dashed).")


def _ecdf(values):
    x = np.sort(values)
    return x, np.arange(1, x.size + 1) / x.size


def distribution_before_after(data, directory):
    """Fig. 12: the cumulative distribution before and after the compensation."""
    s = data.samples
    raw = _range_error(s)
    stages = [
        (raw, r"raw $y - d$", "#d1495b"),
        (raw - s["bias_mm"], r"$y - d - H\hat{\theta}$", "#e9a03b"),
        (s["compensated_mm"] - s["true_range_mm"],
         r"$y - d - H\hat{\theta} - \hat{\mu}_{\hat{\imath}}$ (mode removed)", "#1f4e9c"),
    ]
    fig, ax = plt.subplots(figsize=(6, 4))
    for values, label, colour in stages:
        x, p = _ecdf(values)
        ax.step(x, p, where="post", color=colour, label=f"{label}: std {np.std(values):.2f} mm")
    ax.set_xlabel("range error (mm)")
    ax.set_ylabel("cumulative share of ranges")
    ax.set_title("Distribution before and after the compensation")
    _legend_right(ax)
    before, after = np.std(raw), np.std(stages[2][0])
    return Figure("effect of compensating raw data with the biases of each sample's mode",
                  _save(fig, directory, "fig12_distribution.png"),
                  f"The empirical cumulative distribution of the {raw.size} held-out range errors: "
                  f"raw, with the temperature bias removed, and with the bias of each range's most "
                  f"probable mode removed too. The standard deviation falls from {before:.2f} mm "
                  f"to {after:.2f} mm.")


def em_training_convergence(data, directory):
    """Fig. 13: the estimates per EM training iteration."""
    c = data.em_convergence
    if c is None or c["iteration"].size == 0:
        return None
    modes = sum(1 for name in c if name.startswith("mean"))
    fig, axes = plt.subplots(3, 1, figsize=(6, 6.5), sharex=True)
    for i in range(modes):
        colour = MODE_COLOURS[i % 4]
        axes[0].plot(c["iteration"], c[f"mean{i + 1}_mm"], color=colour,
                     label=rf"$\hat{{\mu}}_{i + 1}$")
        axes[1].plot(c["iteration"], c[f"weight{i + 1}"], color=colour,
                     label=rf"$\hat{{\pi}}_{i + 1}$")
    axes[2].plot(c["iteration"], c["log_likelihood"], color="k")
    axes[0].set_ylabel("mode offset (mm)")
    axes[1].set_ylabel("mode weight")
    axes[2].set_ylabel("log-likelihood")
    axes[2].set_xlabel("EM training iteration (§5, Eq. 18-19)")
    _legend_right(axes[0])
    _legend_right(axes[1])
    axes[0].set_title("EM training")
    n = data.context.get("training_samples", "the")
    iterations = data.context.get("em_training_iterations", c["iteration"].size - 1)
    return Figure("convergence of the estimated means during training",
                  _save(fig, directory, "fig13_em_training.png"),
                  f"The mode offsets μ̂ᵢ, weights π̂ᵢ and the log-likelihood at each EM training "
                  f"iteration on the {n} training ranges (iteration 0: the start), {iterations} "
                  f"iterations in all.")


def em_testing_convergence(data, directory):
    """Fig. 14: d̂ per EM testing iteration."""
    t = data.em_test_trace
    if t is None or t["iteration"].size == 0:
        return None
    error = t["distance_mm"] - t["true_range_mm"]
    fig, ax = plt.subplots(figsize=(6, 3.6))
    ax.plot(t["iteration"], error, marker="o", color="#1f4e9c", label=r"$\hat{d} - d$")
    ax.axhline(0.0, color="k", linewidth=1, label="true distance")
    ax.set_xlabel("EM testing iteration (§6, Eq. 22-23; 0: the start, the mean of y)")
    ax.set_ylabel(r"$\hat{d} - d$ (mm)")
    ax.set_title("EM testing")
    _legend_right(ax)
    n = data.context.get("em_test_trace", {}).get("samples", "the")
    return Figure("convergence of the estimated distance during testing",
                  _save(fig, directory, "fig14_em_testing.png"),
                  f"The error of d̂ after each EM testing iteration on the first {n} held-out "
                  f"ranges (the paper's test set had 4000), started as §6 prescribes from the "
                  f"mean of the ranges; it ends {error[-1]:+.3f} mm from the true distance.")


def em_testing_cost(data, directory):
    """Fig. 15: measured time of EM testing against the number of samples."""
    c = data.em_test_cost
    if c is None or c["samples"].size == 0:
        return None
    fig, ax = plt.subplots(figsize=(6, 3.8))
    exponents = []
    for i, order in enumerate(sorted(set(c["fourier_order"].astype(int)))):
        chosen = c["fourier_order"] == order
        k, seconds = c["samples"][chosen], c["seconds"][chosen]
        exponent = np.polyfit(np.log(k), np.log(seconds), 1)[0] if k.size > 1 else float("nan")
        exponents.append(f"order {order}: {exponent:.2f}")
        ax.plot(k, seconds * 1e3, marker="o", color=MODE_COLOURS[i % 4],
                label=f"Fourier order {order} ({2 * order} columns); "
                      f"growth exponent {exponent:.2f}")
    cost = data.context.get("em_test_cost", {})
    steps = cost.get("steps", "")
    left_out = "".join(f" Not timed: {item['basis']}, whose training failed ({item['error']})."
                       for item in cost.get("left_out", []))
    ax.set_xlabel("ranges in the test set K")
    ax.set_ylabel(f"time of {steps} EM test steps (ms)")
    ax.set_title("Cost of EM testing")
    ax.set_ylim(bottom=0)
    _legend_right(ax)
    return Figure("computational cost of EM testing for two Fourier orders",
                  _save(fig, directory, "fig15_cost.png"),
                  f"Measured wall time (the best of {cost.get('repetitions', 'a few')} runs on "
                  f"this machine) of computing Hθ̂ and {steps} EM test steps on the first K "
                  f"held-out ranges, for each trained Fourier model. The paper found quadratic "
                  f"growth; here each step costs O(K), so the fitted exponent of time ∝ Kᵃ is near "
                  f"1 ({'; '.join(exponents)})"
                  f"{', and the order matters little' if len(exponents) > 1 else ''}.{left_out}")


def _window_error(table, column):
    return table[column] - table["true_range_mm"]


def estimates_by_window(data, directory):
    """Fig. 16: cumulative distribution of d̂ for several window lengths."""
    lengths = [w for w in data.context.get("windows", []) if w in data.windows]
    if not lengths:
        return None
    fig, ax = plt.subplots(figsize=(6, 4))
    for i, w in enumerate(lengths):
        x, p = _ecdf(_window_error(data.windows[w], "em_distance_mm"))
        ax.step(x, p, where="post", color=MODE_COLOURS[i % 4],
                label=f"windows of {w} ranges ({x.size})")
    ax.axvline(0.0, color="k", linewidth=1)
    ax.set_xlabel(r"$\hat{d} - d$ (mm)")
    ax.set_ylabel("cumulative share of windows")
    ax.set_title(r"Estimates $\hat{d}$ by window length")
    _legend_right(ax)
    stride = data.context.get("stride", 1)
    which = "every window" if stride == 1 else f"windows {stride} ranges apart"
    steepening = "; longer windows steepen it at the true distance" if len(lengths) > 1 else ""
    return Figure("cumulative distributions of d̂ for different test sample sizes",
                  _save(fig, directory, "fig16_estimates_by_window.png"),
                  f"The error of d̂ on {which} of {', '.join(str(w) for w in lengths)} consecutive "
                  f"held-out ranges{steepening}. Junction {_temperature_span(data.samples)}.")


def errors_over_time(data, directory):
    """Fig. 17: the errors of the three estimators along the record, and the temperature."""
    lengths = sorted(data.windows)
    if not lengths:
        return None
    w = 1000 if 1000 in data.windows else max(lengths)
    table = data.windows[w]
    start = table["start"].astype(int)
    hours = data.samples["time_s"][start] / 3600.0
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(6, 5.5), sharex=True,
                                      gridspec_kw={"height_ratios": [2, 1]})
    for column, label, colour in ESTIMATORS:
        top.plot(hours, _window_error(table, column + "_mm"), color=colour, linewidth=1,
                 label=label)
    top.axhline(0.0, color="k", linewidth=0.8)
    top.set_ylabel("error of the estimate (mm)")
    top.set_title(f"Errors of the three estimators, windows of {w} ranges")
    _legend_right(top)
    bottom.plot(hours, data.samples["junction_c"][start], color="k")
    bottom.set_ylabel(r"$\hat{t}^j$ (°C)")
    bottom.set_xlabel("time of the window's first range since the start of the record (h)")
    return Figure("realizations of the errors of d̂, ȳ and the mean of y − Hθ̂",
                  _save(fig, directory, "fig17_errors.png"),
                  f"The error of each estimator on windows of {w} held-out ranges (the paper: "
                  f"1000) along the record, with the junction temperature t̂ʲ at each window's "
                  f"first range below. Junction "
                  f"{_temperature_span(data.samples)}.")


def _moments(data, directory, name, paper, columns, caption, zero_line):
    m = data.moments
    if m is None or m["window"].size == 0:
        return None
    fig, axes = plt.subplots(2, 1, figsize=(6, 6), sharex=True)
    for ax, (column, label) in zip(axes, columns):
        for estimator, legend, colour in ESTIMATORS:
            chosen = m["estimator"] == estimator
            ax.plot(m["window"][chosen], m[column][chosen], marker="o", color=colour, label=legend)
        ax.set_ylabel(label)
    if zero_line:
        axes[0].axhline(0.0, color="k", linewidth=0.8)
    _legend_right(axes[0])
    axes[1].set_xlabel("window length (ranges in the test set)")
    axes[0].set_title(paper[0].upper() + paper[1:])
    return Figure(paper, _save(fig, directory, name), caption)


def error_moments(data, directory):
    """Fig. 18: mean and variance of the error against the window length."""
    return _moments(data, directory, "fig18_error_moments.png",
                    "moments of the error against the test sample size",
                    [("mean_error_mm", "mean error (mm)"),
                     ("error_variance_mm2", "variance of the error (mm²)")],
                    "Per window length, the mean (above) and variance (below) of each estimator's "
                    f"error over the held-out windows. Junction {_temperature_span(data.samples)}.",
                    zero_line=True)


def absolute_error_moments(data, directory):
    """Fig. 19: mean and variance of the absolute error against the window length."""
    return _moments(data, directory, "fig19_absolute_error_moments.png",
                    "moments of the absolute error against the test sample size",
                    [("mean_absolute_error_mm", "mean absolute error (mm)"),
                     ("absolute_error_variance_mm2", "variance of |error| (mm²)")],
                    "Per window length, the mean (above) and variance (below) of each estimator's "
                    "absolute error over the held-out windows (the paper: MAE 3 → 1 mm, variance "
                    "2.0 → 0.68 mm² on its LMS 200).", zero_line=False)


# In the paper's order: each paper figure number and the function that draws it.
FIGURES = [
    ("3", histogram),
    ("4", bias_against_temperature),
    ("8", thermal_fit),
    ("9", glr_polynomial),
    ("10", glr_fourier),
    ("11", mode_assignment),
    ("12", distribution_before_after),
    ("13", em_training_convergence),
    ("14", em_testing_convergence),
    ("15", em_testing_cost),
    ("16", estimates_by_window),
    ("17", errors_over_time),
    ("18", error_moments),
    ("19", absolute_error_moments),
]


def draw_figures(data, directory, progress):
    """Draws every figure the data allow; returns (figures, paper numbers left out). A figure
    of an earlier report in the same directory that these data do not allow is removed."""
    os.makedirs(os.path.join(directory, "figures"), exist_ok=True)
    figures, skipped = [], []
    for i, (number, draw) in enumerate(FIGURES):
        progress(f"Fig. {number} ({i + 1}/{len(FIGURES)})")
        figure = draw(data, directory)
        if figure is None:
            skipped.append(number)
        else:
            figure.number = number
            figures.append(figure)
    drawn = {os.path.basename(f.file) for f in figures}
    for name in os.listdir(os.path.join(directory, "figures")):
        if re.fullmatch(r"fig\d\d_\w+\.png", name) and name not in drawn:
            os.remove(os.path.join(directory, "figures", name))
    return figures, skipped
