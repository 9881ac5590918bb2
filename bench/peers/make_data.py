"""Writes the peers' common data: ranges minus the distance y (K) and the basis H (K x p) of a
mixture of overlapping lasing modes on a smooth temperature bias (Eq. 8), with the starting
point every peer begins from. One case per (K, p): files CASE.h.f64 (K x p, row-major,
little-endian float64), CASE.y.f64 and CASE.json (K, p, M, the start, the truth).

The start is tofcomp's default (core/em_train.cpp, EmInitialization::Quantiles): theta and a
constant by least squares, the residual split at its M quantiles into mu_i and sigma_i^2,
pi_i = 1/M; and r0, the responsibilities at it (K x M, CASE.r0.f64), for flexmix, which starts
from posteriors."""
import json
import sys

import numpy as np

MODES_MEAN = np.array([-1.4, 0.0, 1.5])      # mm: about two spreads apart, overlapping
MODES_SIGMA = np.array([0.6, 0.55, 0.7])
MODES_WEIGHT = np.array([0.3, 0.4, 0.3])
LOW_C, HIGH_C = 24.8, 28.8
SEED = 20150813


def legendre_columns(x, p):
    """P_1..P_p of x in [-1, 1] by the three-term recurrence (no constant: the mu_i carry it)."""
    cols = [np.ones_like(x), x]
    for n in range(1, p):
        cols.append(((2 * n + 1) * x * cols[n] - n * cols[n - 1]) / (n + 1))
    return np.column_stack(cols[1:p + 1])


def make_case(k, p, rng):
    # Six power cycles of the junction temperature, as the twin's bench record.
    phase = np.linspace(0.0, 6.0, k, endpoint=False) % 1.0
    t = LOW_C + (HIGH_C - LOW_C) * np.where(phase < 0.5, 1 - np.exp(-6 * phase),
                                            np.exp(-6 * (phase - 0.5)) * (1 - np.exp(-3)))
    x = 2 * (t - LOW_C) / (HIGH_C - LOW_C) - 1
    bias = -2.0 * x + 0.6 * np.sin(2.5 * x)
    mode = rng.choice(len(MODES_MEAN), size=k, p=MODES_WEIGHT)
    y = bias + MODES_MEAN[mode] + MODES_SIGMA[mode] * rng.standard_normal(k)
    return legendre_columns(x, p), y


def quantile_start(h, y, m):
    design = np.column_stack([h, np.ones(len(y))])
    coef = np.linalg.lstsq(design, y, rcond=None)[0]
    theta = coef[:-1]
    residual = np.sort(y - h @ theta)
    k = len(y)
    mean, var = [], []
    for i in range(m):
        group = residual[k * i // m:k * (i + 1) // m]
        mean.append(group.mean())
        var.append(((group - group.mean()) ** 2).mean())
    return theta, np.array(mean), np.array(var), np.full(m, 1.0 / m)


def responsibilities(h, y, theta, mean, var, weight):
    e = y - h @ theta
    log_joint = np.log(weight) - 0.5 * np.log(2 * np.pi * var) - 0.5 * (e[:, None] - mean) ** 2 / var
    top = log_joint.max(axis=1, keepdims=True)
    p = np.exp(log_joint - top)
    return p / p.sum(axis=1, keepdims=True)


def main(out_dir, sizes, columns):
    rng = np.random.default_rng(SEED)
    m = len(MODES_MEAN)
    for k in sizes:
        for p in columns:
            name = f"k{k}_p{p}"
            h, y = make_case(k, p, rng)
            theta, mean, var, weight = quantile_start(h, y, m)
            np.ascontiguousarray(h, dtype="<f8").tofile(f"{out_dir}/{name}.h.f64")
            y.astype("<f8").tofile(f"{out_dir}/{name}.y.f64")
            responsibilities(h, y, theta, mean, var, weight).astype("<f8").tofile(
                f"{out_dir}/{name}.r0.f64")
            with open(f"{out_dir}/{name}.json", "w") as f:
                json.dump({"name": name, "K": k, "p": p, "M": m,
                           "start": {"theta": theta.tolist(), "mean": mean.tolist(),
                                     "variance": var.tolist(), "weight": weight.tolist()},
                           "truth": {"mean": MODES_MEAN.tolist(),
                                     "variance": (MODES_SIGMA ** 2).tolist(),
                                     "weight": MODES_WEIGHT.tolist()}}, f)
            print(name)


if __name__ == "__main__":
    main(sys.argv[1], [int(v) for v in sys.argv[2].split(",")],
         [int(v) for v in sys.argv[3].split(",")])
