"""The report's figures of the window estimators of §8.4 (Alhashimi et al., Sensors 2015):
Fig. 16 d̂ by window length, Fig. 17 the errors along the record, Fig. 18-19 the moments of the
error against the window length. Each function draws one PNG into DIR/figures/ and returns a
report_style.Figure, or None when the data do not allow it.
"""

from report_style import (ESTIMATORS, MODE_COLOURS, Figure, ecdf, legend_right, plt, save,
                          temperature_span)


def _window_error(table, column):
    return table[column] - table["true_range_mm"]


def estimates_by_window(data, directory):
    """Fig. 16: cumulative distribution of d̂ for several window lengths."""
    lengths = [w for w in data.context.get("windows", []) if w in data.windows]
    if not lengths:
        return None
    fig, ax = plt.subplots(figsize=(6, 4))
    for i, w in enumerate(lengths):
        x, p = ecdf(_window_error(data.windows[w], "em_distance_mm"))
        ax.step(x, p, where="post", color=MODE_COLOURS[i % 4],
                label=f"windows of {w} ranges ({x.size})")
    ax.axvline(0.0, color="k", linewidth=1)
    ax.set_xlabel(r"$\hat{d} - d$ (mm)")
    ax.set_ylabel("cumulative share of windows")
    ax.set_title(r"Estimates $\hat{d}$ by window length")
    legend_right(ax)
    stride = data.context.get("stride", 1)
    which = "every window" if stride == 1 else f"windows {stride} ranges apart"
    steepening = "; longer windows steepen it at the true distance" if len(lengths) > 1 else ""
    return Figure("cumulative distributions of d̂ for different test sample sizes",
                  save(fig, directory, "fig16_estimates_by_window.png"),
                  f"The error of d̂ on {which} of {', '.join(str(w) for w in lengths)} consecutive "
                  f"held-out ranges{steepening}. Junction {temperature_span(data.samples)}.")


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
    legend_right(top)
    bottom.plot(hours, data.samples["junction_c"][start], color="k")
    bottom.set_ylabel(r"$\hat{t}^j$ (°C)")
    bottom.set_xlabel("time of the window's first range since the start of the record (h)")
    return Figure("realizations of the errors of d̂, ȳ and the mean of y − Hθ̂",
                  save(fig, directory, "fig17_errors.png"),
                  f"The error of each estimator on windows of {w} held-out ranges (the paper: "
                  f"1000) along the record, with the junction temperature t̂ʲ at each window's "
                  f"first range below. Junction "
                  f"{temperature_span(data.samples)}.")


def _moments(data, directory, name, paper, columns, caption, zero_line, bound=False):
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
    if bound and "cramer_rao_mae_mm" in m:
        # The Cramér-Rao bound of d as a mean absolute error, computed by tofcomp per window.
        chosen = m["estimator"] == "em_distance"
        axes[0].plot(m["window"][chosen], m["cramer_rao_mae_mm"][chosen], linestyle="--",
                     color="k", label="Cramér–Rao bound")
    legend_right(axes[0])
    axes[1].set_xlabel("window length (ranges in the test set)")
    axes[0].set_title(paper[0].upper() + paper[1:])
    return Figure(paper, save(fig, directory, name), caption)


def error_moments(data, directory):
    """Fig. 18: mean and variance of the error against the window length."""
    return _moments(data, directory, "fig18_error_moments.png",
                    "moments of the error against the test sample size",
                    [("mean_error_mm", "mean error (mm)"),
                     ("error_variance_mm2", "variance of the error (mm²)")],
                    "Per window length, the mean (above) and variance (below) of each estimator's "
                    f"error over the held-out windows. Junction {temperature_span(data.samples)}.",
                    zero_line=True)


def absolute_error_moments(data, directory):
    """Fig. 19: mean and variance of the absolute error against the window length."""
    return _moments(data, directory, "fig19_absolute_error_moments.png",
                    "moments of the absolute error against the test sample size",
                    [("mean_absolute_error_mm", "mean absolute error (mm)"),
                     ("absolute_error_variance_mm2", "variance of |error| (mm²)")],
                    "Per window length, the mean (above) and variance (below) of each estimator's "
                    "absolute error over the held-out windows (the paper: MAE 3 → 1 mm, variance "
                    "2.0 → 0.68 mm² on its LMS 200); dashed, the Cramér–Rao bound of d as a mean "
                    "absolute error: no unbiased estimator does better on average.",
                    zero_line=False, bound=True)
