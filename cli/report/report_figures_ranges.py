"""The report's figures of the ranges and the thermal model (Alhashimi et al., Sensors 2015):
Fig. 3 the histogram, Fig. 4 the ranges against temperature, Fig. 8 the thermal fit, Fig. 11 the
mode assignment, Fig. 12 the distribution before and after. Each function draws one PNG into
DIR/figures/ and returns a report_style.Figure, or None when the data do not allow it.
"""

import numpy as np
from matplotlib.colors import LogNorm

from report_data import mode_count, most_probable_mode
from report_style import (MODE_COLOURS, Figure, ecdf, histogram_bins, legend_right, plt,
                          range_error, resolution_mm, save, temperature_span, trained_modes)


def histogram(data, directory):
    """Fig. 3: histogram of the ranges; the lasing modes show as separate peaks."""
    s = data.samples
    raw = range_error(s)
    compensated = raw - s["bias_mm"]
    width = resolution_mm(s["range_mm"])
    bins = histogram_bins(np.concatenate([raw, compensated]), width)
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.hist(compensated, bins, color="0.7",
            label=r"$y - d - H\hat{\theta}$ (temperature bias removed)")
    ax.hist(raw, bins, histtype="step", color="k", linewidth=1.2, label=r"$y - d$ (raw)")
    modes = trained_modes(data.context)
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
    legend_right(ax)
    return Figure("histogram of consecutive ranges at equilibrium",
                  save(fig, directory, "fig03_histogram.png"),
                  f"The errors y − d of the {raw.size} held-out ranges (outline) and the same "
                  f"with the trained temperature bias Hθ̂ removed (grey), against the trained "
                  f"mixture of {len(modes)} lasing modes. Junction {temperature_span(s)}; bins of "
                  f"{width:g} mm, the scanner's range step.")


def bias_against_temperature(data, directory):
    """Fig. 4: the range against the junction temperature; the modes shift with temperature."""
    s = data.samples
    raw = range_error(s)
    width = resolution_mm(s["range_mm"])
    fig, ax = plt.subplots(figsize=(6, 4.2))
    # A logarithmic colour scale: the modes' bands differ in weight by several times, and a few
    # ranges far off either band would vanish on a linear one.
    _, _, _, image = ax.hist2d(s["junction_c"], raw, bins=[60, histogram_bins(raw, width)],
                               cmap="viridis", cmin=1, norm=LogNorm())
    fig.colorbar(image, ax=ax, label="ranges per cell (logarithmic)")
    ax.set_xlabel(r"estimated junction temperature $\hat{t}^j$ (°C)")
    ax.set_ylabel(r"range error $y - d$ (mm)")
    ax.set_title("Range error against the junction temperature")
    return Figure("dependency of the distance measurements on the device temperature",
                  save(fig, directory, "fig04_bias_temperature.png"),
                  f"The {raw.size} held-out range errors y − d against the smoothed junction "
                  f"temperature t̂ʲ (Eq. 7), as a two-dimensional histogram on a logarithmic "
                  f"colour scale (empty cells white): the bands are the lasing modes, their drift "
                  f"with temperature is the bias the device's own compensation leaves.")


ERROR_BIN_S = 60.0  # Fig. 8: the prediction error's mean over each minute


def _minute_means(time_s, error):
    """The mean error over each minute of the record (minutes with readings only)."""
    minute = np.floor((time_s - time_s[0]) / ERROR_BIN_S).astype(int)
    counts = np.bincount(minute)
    sums = np.bincount(minute, weights=error)
    has = counts > 0
    centres = time_s[0] + (np.flatnonzero(has) + 0.5) * ERROR_BIN_S
    return centres, sums[has] / counts[has]


def thermal_fit(data, directory):
    """Fig. 8: the thermal model driven by the held-out inputs against the measured case."""
    t = data.thermal_fit
    if t is None or t["time_s"].size == 0:
        return None
    hours = t["time_s"] / 3600.0
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(6.5, 6), sharex=True,
                                      gridspec_kw={"height_ratios": [2.2, 1.5]})
    top.plot(hours, t["measured_case_c"], color="0.55", linewidth=1, label=r"measured case $t^s$")
    top.plot(hours, t["predicted_case_c"], color="#1f4e9c", linewidth=1.4,
             label="predicted by the identified model (Eq. 5)")
    top.set_ylabel("case temperature (°C)")
    legend_right(top)
    top.set_title("Thermal model on the held-out power cycles")
    # The error on its own axis, in m°C: each reading as a faint dot (the case sensor's rounding
    # makes a band of them), the mean over each minute as a line (what the model misses), and
    # limits that hold 99.8 % of the readings.
    error_mc = 1000.0 * (t["predicted_case_c"] - t["measured_case_c"])
    centres, means = _minute_means(t["time_s"], error_mc)
    bottom.plot(hours, error_mc, linestyle="none", marker=".", markersize=1.5, color="0.7",
                rasterized=True, label="each reading")
    bottom.plot(centres / 3600.0, means, color="#d1495b", linewidth=1.4,
                label=f"mean over each {ERROR_BIN_S:g} s")
    bottom.axhline(0.0, color="k", linewidth=0.8)
    low, high = np.quantile(error_mc, [0.001, 0.999])
    limit = 1.15 * max(abs(low), abs(high), 1.0)
    bottom.set_ylim(-limit, limit)
    bottom.set_ylabel("prediction error,\npredicted − measured (m°C)")
    bottom.set_xlabel("time since the start of the record (h)")
    legend_right(bottom, markerscale=8)
    fit = data.context.get("thermal_fit", {})
    paper = fit.get("held_out_paper_fit_percent")
    nrmse = fit.get("held_out_nrmse_fit_percent")
    numbers = (f" Fit on these cycles: {paper:.5f} % by Eq. 26 (the paper: 92.79 %), "
               f"{nrmse:.2f} % NRMSE." if paper is not None and nrmse is not None else "")
    rms = float(np.sqrt(np.mean(error_mc ** 2)))
    return Figure("validation of the thermal model Eq. 5",
                  save(fig, directory, "fig08_thermal_fit.png"),
                  "The model identified on the first half (Algorithm 1, then the prediction-error "
                  "fit) driven by the power inputs of the held-out half, against the measured case "
                  "temperature; below, on its own axis in thousandths of a degree, the prediction "
                  "error of each reading (grey dots: the case sensor's rounding spreads them into "
                  f"a band) and its mean over each minute (red), what the model misses; RMS "
                  f"{rms:.0f} m°C. The axis holds 99.8 % of the readings." + numbers)


def mode_assignment(data, directory):
    """Fig. 11: each range with its most probable mode, and the temperature bias Hθ̂."""
    s = data.samples
    raw = range_error(s)
    mode = most_probable_mode(s)
    modes = trained_modes(data.context)
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
    legend_right(ax, markerscale=4)
    return Figure("EM testing on real data: modes and temperature bias",
                  save(fig, directory, "fig11_mode_assignment.png"),
                  "Each held-out range error against t̂ʲ, coloured by its most probable lasing "
                  "mode (the posterior Δ̂ of Eq. 22 at the EM estimate of the whole held-out "
                  "record), with the trained temperature bias Hθ̂ (solid) and each mode's offset "
                  "on it (dashed).")


def distribution_before_after(data, directory):
    """Fig. 12: the cumulative distribution before and after the compensation."""
    s = data.samples
    raw = range_error(s)
    stages = [
        (raw, r"raw $y - d$", "#d1495b"),
        (raw - s["bias_mm"], r"$y - d - H\hat{\theta}$", "#e9a03b"),
        (s["compensated_mm"] - s["true_range_mm"],
         r"$y - d - H\hat{\theta} - \hat{\mu}_{\hat{\imath}}$ (mode removed)", "#1f4e9c"),
    ]
    fig, ax = plt.subplots(figsize=(6, 4))
    for values, label, colour in stages:
        x, p = ecdf(values)
        ax.step(x, p, where="post", color=colour, label=f"{label}: std {np.std(values):.2f} mm")
    ax.set_xlabel("range error (mm)")
    ax.set_ylabel("cumulative share of ranges")
    ax.set_title("Distribution before and after the compensation")
    legend_right(ax)
    before, after = np.std(raw), np.std(stages[2][0])
    return Figure("effect of compensating raw data with the biases of each sample's mode",
                  save(fig, directory, "fig12_distribution.png"),
                  f"The empirical cumulative distribution of the {raw.size} held-out range errors: "
                  f"raw, with the temperature bias removed, and with the bias of each range's most "
                  f"probable mode removed too. The standard deviation falls from {before:.2f} mm "
                  f"to {after:.2f} mm.")
