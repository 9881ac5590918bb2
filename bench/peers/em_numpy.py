"""The exact EM of §5 (core/em_train.hpp, MStep::Exact) in numpy, written as a competent numpy
user would: vectorized over the ranges, the (theta, mu) block by weighted least squares with
weights r_ki / sigma_i^2 (one (p + M) x (p + M) normal system), then sigma_i^2 and pi_i in closed
form. The same start and stopping rule as tofcomp's (max |d pi| < 1e-5 and |d loglik| <= 1e-10 K).

Usage: em_numpy.py DIR CASE ITERATIONS REPEATS
  prints one JSON line: per-iteration time (ITERATIONS plain iterations, best of REPEATS) and
  the converged fit (iterations, log-likelihood, time)."""
import json
import sys
import time

import numpy as np

WEIGHT_TOLERANCE = 1e-5
LOG_LIKELIHOOD_TOLERANCE = 1e-10
MAX_ITERATIONS = 100000


def e_step(h, y, theta, mean, var, weight):
    e = y - h @ theta
    log_joint = np.log(weight) - 0.5 * np.log(2 * np.pi * var) - 0.5 * (e[:, None] - mean) ** 2 / var
    top = log_joint.max(axis=1, keepdims=True)
    p = np.exp(log_joint - top)
    s = p.sum(axis=1, keepdims=True)
    return p / s, float(np.sum(top[:, 0] + np.log(s[:, 0])))


def m_step(h, y, r, var):
    k, p = h.shape
    w = r / var                         # K x M
    total = w.sum(axis=1)               # K
    hw = h * total[:, None]
    a = np.empty((p + len(var), p + len(var)))
    a[:p, :p] = h.T @ hw
    a[:p, p:] = h.T @ w
    a[p:, :p] = a[:p, p:].T
    a[p:, p:] = np.diag(w.sum(axis=0))
    b = np.concatenate([hw.T @ y, w.T @ y])
    sol = np.linalg.solve(a, b)
    theta, mean = sol[:p], sol[p:]
    e = y - h @ theta
    mass = r.sum(axis=0)
    var = (r * (e[:, None] - mean) ** 2).sum(axis=0) / mass
    return theta, mean, var, mass / k


def fit(h, y, start, iterations=None):
    theta, mean, var, weight = (np.array(start[n]) for n in ("theta", "mean", "variance", "weight"))
    k = len(y)
    previous, change, n = -np.inf, np.inf, 0
    while True:
        r, loglik = e_step(h, y, theta, mean, var, weight)
        if iterations is None:
            if change < WEIGHT_TOLERANCE and abs(loglik - previous) <= LOG_LIKELIHOOD_TOLERANCE * k:
                return n, loglik, True
            if n == MAX_ITERATIONS:
                return n, loglik, False
        elif n == iterations:
            return n, loglik, True
        theta, mean, var, new_weight = m_step(h, y, r, var)
        change = np.abs(new_weight - weight).max()
        weight, previous, n = new_weight, loglik, n + 1


def main(directory, name, iterations, repeats):
    meta = json.load(open(f"{directory}/{name}.json"))
    k, p = meta["K"], meta["p"]
    h = np.fromfile(f"{directory}/{name}.h.f64", dtype="<f8").reshape(k, p)
    y = np.fromfile(f"{directory}/{name}.y.f64", dtype="<f8")
    best = np.inf
    for _ in range(repeats):
        t0 = time.process_time()
        fit(h, y, meta["start"], iterations)
        best = min(best, time.process_time() - t0)
    t0 = time.process_time()
    n, loglik, converged = fit(h, y, meta["start"])
    seconds = time.process_time() - t0
    print(json.dumps({"peer": "numpy", "case": name, "s_per_iteration": best / iterations,
                      "iterations": n, "log_likelihood": loglik, "converged": converged,
                      "fit_s": seconds}))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))
