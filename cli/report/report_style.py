"""What every figure of the diagnosis report shares: matplotlib on the Agg backend (no display),
one style, the colours of the lasing modes and of the three estimators of §8.4, the Figure a
drawing function returns, and small helpers on the report's tables (histogram bins, equal-count
bins and binned means with their 95 % intervals: summaries of the data, not of a model).
"""

import math
import os
from dataclasses import dataclass

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
import numpy as np  # noqa: E402

DPI = 110
MODE_COLOURS = ["#1f4e9c", "#d1495b", "#2a9d8f", "#e9a03b"]
ESTIMATORS = [  # the three estimators of §8.4, Fig. 17-19
    ("raw_mean", r"$\bar{y}$ (window mean of raw ranges)", "#d1495b"),
    ("bias_corrected_mean",
     r"$\overline{y - H\hat{\theta}} - \sum_i \hat{\pi}_i \hat{\mu}_i$ (bias removed, centred)",
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


def legend_right(ax, **options):
    """The legend beside the axes, where it hides no data."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, **options)


def save(fig, directory, name):
    relative = os.path.join("figures", name)
    fig.savefig(os.path.join(directory, relative), dpi=DPI, bbox_inches="tight")
    plt.close(fig)
    return relative


def range_error(samples):
    return samples["range_mm"] - samples["true_range_mm"]


def resolution_mm(ranges):
    """The scanner's range step (1 mm, or 10 mm in cm mode), for histogram bins."""
    steps = np.diff(np.unique(ranges))
    steps = steps[steps > 1e-9]
    return max(1.0, float(np.min(steps))) if steps.size else 1.0


def histogram_bins(values, width):
    low = np.floor(np.nanmin(values) / width) * width - width / 2
    high = np.ceil(np.nanmax(values) / width) * width + width
    return np.arange(low, high, width)


def trained_modes(context):
    return context.get("calibration", {}).get("modes", [])


def temperature_span(samples):
    t = samples["junction_c"]
    return f"{np.nanmin(t):.1f}-{np.nanmax(t):.1f} °C"


def ecdf(values):
    x = np.sort(values)
    return x, np.arange(1, x.size + 1) / x.size


def equal_count_edges(x, bins):
    return np.unique(np.quantile(x, np.linspace(0.0, 1.0, bins + 1)))


def binned_means(x, y, edges, least=2):
    """Bins of x between edges: the mean x, the mean y and its 95 % half-width per bin of at
    least `least` values (values outside the edges are left out)."""
    index = np.searchsorted(edges, x, side="right") - 1
    index[x == edges[-1]] = edges.size - 2
    centre, mean, half_width = [], [], []
    for b in range(edges.size - 1):
        chosen = index == b
        if chosen.sum() < max(least, 2):
            continue
        centre.append(np.mean(x[chosen]))
        mean.append(np.mean(y[chosen]))
        half_width.append(1.96 * np.std(y[chosen], ddof=1) / math.sqrt(chosen.sum()))
    return np.array(centre), np.array(mean), np.array(half_width)
