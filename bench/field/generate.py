#!/usr/bin/env python3
"""Blind test data for field calibration of a pulsed ToF scanner (LMS 200-like).

Written apart from the system under test, from the paper (Alhashimi, Varagnolo, Gustafsson,
Sensors 2015: thermal RC network, Eq. 3-6; measurement model Eq. 8) and the interchange CSV
format only. See README.md in this folder.

usage: generate.py --out DIR --seed N [--size small|large] [--count K]
"""
import os
import sys

try:
    import numpy as np
except ImportError:  # pragma: no cover - re-exec with Debian's python, which has numpy
    if os.path.exists("/usr/bin/python3") and os.path.realpath(sys.executable) != "/usr/bin/python3":
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    sys.exit("generate.py: numpy is required")

import argparse
import json
import math
import time

TREF_C = 25.0          # reference temperature of the bias shape
DT_S = 0.5             # thermal integration step (exact zero-order-hold discretisation)
MAX_RANGE_MM = 8183    # "no echo" value reported as a gross error
OCC_GAP_MM = 250.0     # an occluding object is at least this much in front of the surface
WINDOWS = (200, 400, 800)

SIZES = {
    "small": dict(bench_hours=(1.0, 2.0), bench_rates=[1.0, 2.0], bench_on_min=(15, 35),
                  bench_off_min=(5, 15), day_hours=(2.0, 4.0), beams=(8, 16),
                  field_rates=[0.5, 1.0], max_ranges_per_s=8.0, budget_mb=12.0, breaks=(0, 1),
                  break_min=(3, 12), steps_per_day=(0.5, 2.5), occ_median_s=(10, 45),
                  occ_max_s=240),
    "large": dict(bench_hours=(4.0, 8.0), bench_rates=[1.0, 2.0, 5.0], bench_on_min=(40, 120),
                  bench_off_min=(10, 60), day_hours=(24.0, 24.0), beams=(30, 90),
                  field_rates=[0.5, 1.0, 2.0], max_ranges_per_s=100.0, breaks=(0, 2),
                  break_min=(10, 90), steps_per_day=(1.0, 6.0), occ_median_s=(15, 90),
                  occ_max_s=600),
}


# ----------------------------------------------------------------------------- physics
def bias_mm(tj, b):
    """H(t^j) theta: a smooth drawn shape of the junction temperature (mm)."""
    x = np.asarray(tj, dtype=float) - b["tref_c"]
    return (b["b0_mm"] + b["lin_mm_per_k"] * x + b["quad_mm_per_k2"] * x * x
            + b["amp_mm"] * np.sin(2.0 * np.pi * x / b["period_k"] + b["phase_rad"]))


def expm2(a):
    """Matrix exponential of a small matrix (scaling and squaring, Taylor)."""
    n = max(0, int(math.ceil(math.log2(max(np.abs(a).sum(axis=1).max(), 1e-12) / 0.25))) + 1)
    m = a / (2.0 ** n)
    e = np.eye(a.shape[0])
    term = np.eye(a.shape[0])
    for k in range(1, 20):
        term = term @ m / k
        e = e + term
    for _ in range(n):
        e = e @ e
    return e


def thermal_matrices(th, dt):
    r1, c1, r2, c2 = th["R1"], th["C1"], th["R2"], th["C2"]
    a = np.array([[-(1.0 / (r2 * c2) + 1.0 / (r1 * c2)), 1.0 / (r1 * c2)],
                  [1.0 / (r1 * c1), -1.0 / (r1 * c1)]])
    ad = expm2(a * dt)
    ainv = np.linalg.inv(a)
    g = ainv @ (ad - np.eye(2))
    bu = g @ np.array([0.0, th["P"] / c1])           # per unit of power state (0/1)
    ba = g @ np.array([1.0 / (r2 * c2), 0.0])        # per degree of ambient
    return ad, bu, ba


def simulate_thermal(th, amb, u, x0):
    """State [t^c, t^j] on the DT_S grid; amb, u on the grid (piecewise constant)."""
    ad, bu, ba = thermal_matrices(th, DT_S)
    a11, a12, a21, a22 = ad[0, 0], ad[0, 1], ad[1, 0], ad[1, 1]
    bu1, bu2, ba1, ba2 = bu[0], bu[1], ba[0], ba[1]
    n = len(amb)
    tc = [0.0] * n
    tj = [0.0] * n
    c, j = float(x0[0]), float(x0[1])
    al = amb.tolist()
    ul = u.tolist()
    for k in range(n):
        tc[k] = c
        tj[k] = j
        uk, ak = ul[k], al[k]
        c, j = (a11 * c + a12 * j + bu1 * uk + ba1 * ak,
                a21 * c + a22 * j + bu2 * uk + ba2 * ak)
    return np.array(tc), np.array(tj)


def power_at(changes, t_ms):
    """changes: list of (t_ms, state) sorted; state holds until the next change."""
    ct = np.array([c[0] for c in changes], dtype=np.int64)
    cs = np.array([c[1] for c in changes], dtype=np.int64)
    idx = np.searchsorted(ct, t_ms, side="right") - 1
    out = np.where(idx >= 0, cs[np.clip(idx, 0, None)], 1)
    return out


def mode_sequence(rng, n, modes, beams_per_scan):
    """Lasing modes of n consecutive ranges (scan-major order): iid or a 'fresh draw' Markov chain."""
    w = np.array(modes["weight"])
    m = len(w)
    if modes["switching"] == "iid":
        return rng.choice(m, size=n, p=w)
    s_scan = modes["fresh_prob_per_scan"]
    s_step = 1.0 - (1.0 - s_scan) ** (1.0 / beams_per_scan)
    fresh = rng.random(n) < s_step
    fresh[0] = True
    idx = np.where(fresh, np.arange(n), 0)
    idx = np.maximum.accumulate(idx)
    draws = rng.choice(m, size=n, p=w)
    return draws[idx]


# ----------------------------------------------------------------------------- CRB
def _phi(x):
    return np.exp(-0.5 * x * x) / math.sqrt(2.0 * math.pi)


def _cdf_diff(hi, lo):
    """Phi(hi) - Phi(lo) computed without cancellation in either tail."""
    erfc = np.vectorize(math.erfc)
    up = 0.5 * (erfc(-hi / math.sqrt(2)) - erfc(-lo / math.sqrt(2)))      # good for lo < 0
    dn = 0.5 * (erfc(lo / math.sqrt(2)) - erfc(hi / math.sqrt(2)))        # good for lo >= 0
    return np.where(lo >= 0, dn, up)


def emission_tables(modes, nphase=16):
    mu = np.array(modes["offset_mm"])
    sd = np.array(modes["std_mm"])
    kmax = int(math.ceil(np.abs(mu).max() + 10 * sd.max())) + 2
    ks = np.arange(-kmax, kmax + 1)
    ph = (np.arange(nphase) + 0.5) / nphase
    # [phase, mode, k]
    c = ph[:, None, None] + mu[None, :, None]
    hi = (ks[None, None, :] + 0.5 - c) / sd[None, :, None]
    lo = (ks[None, None, :] - 0.5 - c) / sd[None, :, None]
    pmf = np.maximum(_cdf_diff(hi, lo), 1e-300)
    dpmf = -(_phi(hi) - _phi(lo)) / sd[None, :, None]      # d/dd of the pmf
    return ks, ph, pmf, dpmf, kmax


def _hmm_scores(rng, reps, n, s, w, mu, sd, ph, pmf, dpmf, kmax):
    """Exact score d/dd log p(y_1..n) of simulated windows (forward-backward, Fisher identity)."""
    m = len(w)
    ph_idx = rng.integers(0, len(ph), size=reps)
    fresh = rng.random((reps, n)) < s
    fresh[:, 0] = True
    idx = np.where(fresh, np.arange(n)[None, :], 0)
    idx = np.maximum.accumulate(idx, axis=1)
    draws = rng.choice(m, size=(reps, n), p=w)
    mode = np.take_along_axis(draws, idx, axis=1)
    y = np.rint(ph[ph_idx][:, None] + mu[mode] + sd[mode] * rng.standard_normal((reps, n)))
    yi = np.clip(y.astype(int) + kmax, 0, pmf.shape[2] - 1)
    e = pmf[ph_idx[:, None, None], np.arange(m)[None, None, :], yi[:, :, None]]     # [r, k, m]
    g = dpmf[ph_idx[:, None, None], np.arange(m)[None, None, :], yi[:, :, None]] / e
    alpha = np.empty((reps, n, m))
    a = w[None, :] * e[:, 0, :]
    a /= a.sum(axis=1, keepdims=True)
    alpha[:, 0, :] = a
    for k in range(1, n):
        a = ((1 - s) * a + s * w[None, :]) * e[:, k, :]
        a /= a.sum(axis=1, keepdims=True)
        alpha[:, k, :] = a
    beta = np.ones((reps, m))
    score = (alpha[:, n - 1, :] * g[:, n - 1, :]).sum(axis=1)
    for k in range(n - 2, -1, -1):
        eb = e[:, k + 1, :] * beta
        beta = (1 - s) * eb + s * (w[None, :] * eb).sum(axis=1, keepdims=True)
        beta /= beta.sum(axis=1, keepdims=True)
        gam = alpha[:, k, :] * beta
        gam /= gam.sum(axis=1, keepdims=True)
        score += (gam * g[:, k, :]).sum(axis=1)
    return score


def crb_figures(modes, rng, reps=4000):
    """Fisher information of d per range (ranges rounded to 1 mm, all else known)."""
    w = np.array(modes["weight"])
    mu = np.array(modes["offset_mm"])
    sd = np.array(modes["std_mm"])
    ks, ph, pmf, dpmf, kmax = emission_tables(modes)
    mix = (w[None, :, None] * pmf).sum(axis=1)
    dmix = (w[None, :, None] * dpmf).sum(axis=1)
    i_iid = float(((dmix ** 2 / mix).sum(axis=1)).mean())
    i_known = float((w[None, :, None] * dpmf ** 2 / pmf).sum(axis=(1, 2)).mean())
    out = {"fisher_iid_mixture_per_range": i_iid, "fisher_mode_known_per_range": i_known}
    fisher_n = {}
    if modes["switching"] == "iid":
        for n in WINDOWS:
            fisher_n[n] = n * i_iid
        out["method"] = "exact: iid Gaussian mixture, pmf of the 1 mm rounding, averaged over the fractional part of d+bias"
    else:
        s = modes["fresh_prob_per_scan"]
        m = len(w)
        for n in WINDOWS:
            sq = 0.0
            done = 0
            while done < reps:
                r = min(1000, reps - done)
                sq += float(np.sum(_hmm_scores(rng, r, n, s, w, mu, sd, ph, pmf, dpmf, kmax) ** 2))
                done += r
            fisher_n[n] = sq / reps
        out["method"] = ("Monte Carlo (%d windows each): variance of the exact HMM score (Fisher identity, "
                         "forward-backward with the pmf of the 1 mm rounding), 'fresh draw' Markov modes" % reps)
    out["fisher_window"] = {str(n): fisher_n[n] for n in WINDOWS}
    out["fisher_per_range_asymptotic"] = fisher_n[WINDOWS[-1]] / WINDOWS[-1]
    out["crb_mae_mm"] = {str(n): math.sqrt(2.0 / math.pi) / math.sqrt(fisher_n[n]) for n in WINDOWS}
    # modes known (e.g. inferred from the other beams of the same scan when switching is sticky)
    out["crb_mode_known_mae_mm"] = {str(n): math.sqrt(2.0 / math.pi) / math.sqrt(n * i_known) for n in WINDOWS}
    # the MAE of the plain window mean (the scorer's oracle), for reference
    var_w = float((w * (sd ** 2 + 1.0 / 12.0)).sum())
    var_mu = float((w * mu ** 2).sum())
    rho = 0.0 if modes["switching"] == "iid" else 1.0 - modes["fresh_prob_per_scan"]
    exp_oracle = {}
    for n in WINDOWS:
        k = np.arange(1, n)
        corr = 1.0 + 2.0 * float(((1.0 - k / n) * rho ** k).sum())
        exp_oracle[str(n)] = math.sqrt(2.0 / math.pi) * math.sqrt((var_w + var_mu * corr) / n)
    out["oracle_mean_mae_mm_expected"] = exp_oracle
    return out


# ----------------------------------------------------------------------------- draws
def draw_physics(rng, size):
    while True:
        r1 = rng.uniform(0.10, 0.40)
        r2 = rng.uniform(0.20, 0.70)
        p = rng.uniform(5.0, 12.0)
        if 3.0 <= p * (r1 + r2) <= 11.0:
            break
    tau1 = rng.uniform(5.0, 45.0)
    tau2 = rng.uniform(15.0, 60.0) * 60.0
    thermal = {"R1": r1, "C1": tau1 / r1, "R2": r2, "C2": tau2 / r2, "P": p,
               "tau_junction_s": tau1, "tau_case_s": tau2, "rise_k": p * (r1 + r2)}
    sensor = {"period_s": float(rng.choice([0.5, 1.0, 2.0, 2.5, 5.0])),
              "resolution_c": float(rng.choice([0.0625, 0.125, 0.25])),
              "noise_c": float(rng.uniform(0.01, 0.10)),
              "ambient_log_noise_c": 0.02, "ambient_log_resolution_c": 0.01}
    bias = {"form": "b0 + lin*x + quad*x^2 + amp*sin(2*pi*x/period + phase), x = t_j - tref",
            "tref_c": TREF_C, "b0_mm": rng.uniform(-20, 20),
            "lin_mm_per_k": float(rng.choice([-1, 1]) * rng.uniform(0.2, 1.0)),
            "quad_mm_per_k2": rng.uniform(-0.03, 0.03), "amp_mm": rng.uniform(0.0, 3.0),
            "period_k": rng.uniform(10.0, 40.0), "phase_rad": rng.uniform(0, 2 * math.pi)}
    m = int(rng.choice([2, 3]))
    off = np.concatenate([[0.0], np.cumsum(rng.uniform(3.0, 12.0, size=m - 1))])
    wt = rng.dirichlet(2.0 * np.ones(m))
    wt = np.maximum(wt, 0.08)
    wt /= wt.sum()
    off = off - float((wt * off).sum())
    modes = {"offset_mm": off.tolist(), "std_mm": rng.uniform(1.0, 4.0, size=m).tolist(),
             "weight": wt.tolist(),
             "note": "offsets have zero weighted mean: E[y - d - bias] = 0"}
    if rng.random() < 0.4:
        modes["switching"] = "iid"
        modes["fresh_prob_per_scan"] = 1.0
    else:
        modes["switching"] = "markov"
        modes["fresh_prob_per_scan"] = float(math.exp(rng.uniform(math.log(0.05), math.log(0.7))))
    modes["switching_note"] = ("one chain over the ranges in time order (scan-major); between two "
                               "consecutive ranges the mode is redrawn from the weights with probability "
                               "1-(1-s)^(1/beams), i.e. with probability s between consecutive scans of one beam")
    return thermal, sensor, bias, modes


def schedule_changes(on_off):
    """[(state, seconds), ...] -> [(t_ms, state)] change points."""
    out, t = [], 0
    for st, dur in on_off:
        out.append((int(t * 1000), int(st)))
        t += int(dur)
    return out, t


def thermal_run(th, amb_fn, changes, total_s, x0):
    n = int(round(total_s / DT_S)) + 2
    tg = np.arange(n) * DT_S
    amb = amb_fn(tg)
    u = power_at(changes, np.rint(tg * 1000).astype(np.int64)).astype(float)
    tc, tj = simulate_thermal(th, amb, u, x0)
    return tg, amb, tc, tj


def sensor_rows(rng, sensor, tg, amb, tc, total_s):
    per_ms = int(round(sensor["period_s"] * 1000))
    t_ms = np.arange(0, int(total_s * 1000) + 1, per_ms, dtype=np.int64)
    t = t_ms / 1000.0
    c = np.interp(t, tg, tc) + rng.normal(0, sensor["noise_c"], size=len(t))
    c = np.round(c / sensor["resolution_c"]) * sensor["resolution_c"]
    a = np.round(np.interp(t, tg, amb) + rng.normal(0, sensor["ambient_log_noise_c"], size=len(t)), 2)
    return t_ms, c, a


def scan_times(rate, total_s, changes):
    per_ms = int(round(1000.0 / rate))
    t_ms = np.arange(0, int(total_s * 1000), per_ms, dtype=np.int64)
    on = power_at(changes, t_ms) == 1
    return t_ms[on]


# ----------------------------------------------------------------------------- writing
def fmt_t(ms):
    return "%d.%03d" % (ms // 1000, ms % 1000)


def write_csv(path, meta, ref, p_rows, s_rows, r_rows):
    """p_rows=(t_ms, state); s_rows=(t_ms, case, amb); r_rows=(t_ms, beam, y, refmm or None)."""
    cols = ["time_s", "beam", "range_mm", "case_temp_c", "power", "ambient_c"]
    if ref:
        cols.append("true_range_mm")
    tail = "," if ref else ""
    tp, sp = p_rows
    ts, cs, as_ = s_rows
    tr, br, yr, dr = r_rows
    np_, ns = len(tp), len(ts)
    t_all = np.concatenate([tp, ts, tr])
    kind = np.concatenate([np.zeros(np_, np.int8), np.ones(ns, np.int8), np.full(len(tr), 2, np.int8)])
    sub = np.concatenate([np.zeros(np_ + ns, np.int64), br.astype(np.int64)])
    order = np.lexsort((sub, kind, t_all))
    tp_l, sp_l = tp.tolist(), sp.tolist()
    ts_l, cs_l, as_l = ts.tolist(), cs.tolist(), as_.tolist()
    with open(path, "w", newline="\n") as f:
        for k, v in meta:
            f.write("# %s: %s\n" % (k, v))
        f.write(",".join(cols) + "\n")
        chunk = 200000
        for c0 in range(0, len(order), chunk):
            o = order[c0:c0 + chunk]
            lines = []
            rsel = o[o >= np_ + ns] - (np_ + ns)
            rt = tr[rsel].tolist()
            rb = br[rsel].tolist()
            ry = yr[rsel].tolist()
            rd = dr[rsel].tolist() if (ref and dr is not None) else None
            ri = 0
            for i in o.tolist():
                if i < np_:
                    lines.append("%s,,,,%d,%s" % (fmt_t(tp_l[i]), sp_l[i], tail))
                elif i < np_ + ns:
                    j = i - np_
                    lines.append("%s,,,%.4f,,%.2f%s" % (fmt_t(ts_l[j]), cs_l[j], as_l[j], tail))
                else:
                    if ref:
                        d = rd[ri]
                        lines.append("%s,%d,%d,,,,%s" % (fmt_t(rt[ri]), rb[ri], ry[ri],
                                                         "" if d != d else "%.1f" % d))
                    else:
                        lines.append("%s,%d,%d,,," % (fmt_t(rt[ri]), rb[ri], ry[ri]))
                    ri += 1
            f.write("\n".join(lines) + "\n")


# ----------------------------------------------------------------------------- records
def bench_record(rng, cfg, th, sensor, bias, modes):
    nb = int(rng.choice([1, 2, 3]))
    while True:
        ds = np.sort(rng.uniform(1000.0, 7500.0, size=nb))
        if nb == 1 or np.diff(ds).min() >= 500:
            break
    ds = np.round(ds, 1)
    total_target = rng.uniform(*cfg["bench_hours"]) * 3600
    on_off, t = [], 0
    while True:
        on = int(min(rng.uniform(*cfg["bench_on_min"]) * 60, total_target - t))
        on_off.append((1, on))
        t += on
        rem = int(total_target - t)
        if rem < (cfg["bench_off_min"][0] + 5) * 60:
            on_off[-1] = (1, on + rem)                      # end on, at the drawn duration
            break
        off = int(min(rng.uniform(*cfg["bench_off_min"]) * 60, total_target - t - 300))
        on_off.append((0, off))
        t += off
    changes, total_s = schedule_changes(on_off)
    amb = {"base_c": rng.uniform(18.0, 24.0), "drift_c_per_h": rng.uniform(-0.3, 0.3),
           "wave_c": rng.uniform(0.05, 0.4), "wave_period_h": rng.uniform(0.7, 3.0),
           "wave_phase": rng.uniform(0, 2 * math.pi)}

    def amb_fn(t):
        return (amb["base_c"] + amb["drift_c_per_h"] * t / 3600.0
                + amb["wave_c"] * np.sin(2 * np.pi * t / (amb["wave_period_h"] * 3600) + amb["wave_phase"]))

    a0 = amb_fn(np.array([0.0]))[0]
    tg, ambg, tc, tj = thermal_run(th, amb_fn, changes, total_s, (a0, a0))
    rate = float(rng.choice(cfg["bench_rates"]))
    st = scan_times(rate, total_s, changes)
    n = len(st)
    tjs = np.interp(st / 1000.0, tg, tj)
    b = bias_mm(tjs, bias)
    t_ms = np.repeat(st, nb)
    beam = np.tile(np.arange(nb), n)
    dd = np.tile(ds, n)
    mode = mode_sequence(rng, n * nb, modes, nb)
    mu, sd = np.array(modes["offset_mm"]), np.array(modes["std_mm"])
    y = np.rint(dd + np.repeat(b, nb) + mu[mode] + sd[mode] * rng.standard_normal(n * nb)).astype(np.int64)
    y = np.clip(y, 1, MAX_RANGE_MM - 1)
    srow = sensor_rows(rng, sensor, tg, ambg, tc, total_s)
    info = {"beams": [{"beam": i, "d_mm": float(ds[i])} for i in range(nb)], "rate_hz": rate,
            "duration_s": total_s, "schedule": [[s, d] for s, d in on_off], "ambient": amb,
            "band_c": [float(tjs.min()), float(tjs.max())], "ranges": int(n * nb)}
    rows = ((np.array([c[0] for c in changes], np.int64), np.array([c[1] for c in changes], np.int64)),
            srow, (t_ms, beam, y, dd))
    return info, rows


def reflect(x, lo, hi):
    L = np.maximum(hi - lo, 1.0)
    z = np.mod(x - lo, 2 * L)
    return lo + L - np.abs(z - L)


def field_day(rng, cfg, case, scene, kind, e_day, band, cold, L):
    th, sensor, bias, modes = case["thermal"], case["sensor"], case["bias"], case["modes"]
    B = scene["beams"]
    rate = scene["rate_hz"]
    # power: on all day, a few breaks
    nbreak = int(rng.integers(cfg["breaks"][0], cfg["breaks"][1] + 1))
    breaks = []
    for _ in range(nbreak):
        dur = int(rng.uniform(*cfg["break_min"]) * 60)
        st = int(rng.uniform(0.15, 0.85) * L)
        if all(st + dur + 600 < b0 or st > b0 + d0 + 600 for b0, d0 in breaks) and st + dur < L - 600:
            breaks.append((st, dur))
    breaks.sort()
    on_off, t = [], 0
    for st, dur in breaks:
        on_off.append((1, st - t))
        on_off.append((0, dur))
        t = st + dur
    on_off.append((1, L - t))
    changes, total_s = schedule_changes(on_off)
    # ambient of the hall: cool morning, warm afternoon, partial cooling
    width = band[1] - band[0]
    rise = th["rise_k"]
    u_m = rng.uniform(0.3, 0.8) if kind == "test" else rng.uniform(0.2, 1.2)
    plateau = rng.uniform(0.25, 0.4) if kind == "test" else rng.uniform(0.0, 0.3)
    amb = {"min_c": band[0] + u_m * width - rise, "plateau_frac": plateau,
           "peak_at": plateau + (1.0 - plateau) * rng.uniform(0.45, 0.7),
           "end_frac": rng.uniform(0.2, 0.6), "wobble_c": rng.uniform(0.1, 0.6),
           "wobble_period_frac": rng.uniform(0.2, 0.6), "wobble_phase": rng.uniform(0, 2 * math.pi),
           "target_excess_k": e_day}
    if rng.random() < 0.5:
        amb["dip_c"] = rng.uniform(0.5, 2.5)
        amb["dip_at_frac"] = rng.uniform(0.2, 0.9)
        amb["dip_len_s"] = rng.uniform(10, 40) * 60
    else:
        amb["dip_c"] = 0.0
        amb["dip_at_frac"] = 0.5
        amb["dip_len_s"] = 600.0
    amb["swing_c"] = band[1] + e_day - rise - amb["min_c"]

    def amb_fn(tt):
        uu = tt / L
        pk = amb["peak_at"]
        pl = amb["plateau_frac"]
        up = np.sin(0.5 * np.pi * np.clip((uu - pl) / (pk - pl), 0, 1)) ** 2
        dn = 1.0 - (1.0 - amb["end_frac"]) * np.sin(0.5 * np.pi * np.clip((uu - pk) / (1 - pk), 0, 1)) ** 2
        shape = np.where(uu <= pk, up, dn)
        dip_c = amb["dip_at_frac"] * L
        z = np.clip((tt - dip_c) / amb["dip_len_s"], -0.5, 0.5)
        dip = amb["dip_c"] * np.cos(np.pi * z) ** 2 * (np.abs(z) < 0.5)
        wob = amb["wobble_c"] * np.sin(2 * np.pi * tt / (amb["wobble_period_frac"] * L) + amb["wobble_phase"])
        return amb["min_c"] + amb["swing_c"] * shape + wob - dip

    st_ms = scan_times(rate, total_s, changes)
    for _ in range(4):
        a0 = float(amb_fn(np.array([0.0]))[0])
        x0 = (a0, a0) if cold else (a0 + th["P"] * th["R2"], a0 + th["rise_k"])
        tg, ambg, tc, tj = thermal_run(th, amb_fn, changes, total_s, x0)
        tjs = np.interp(st_ms / 1000.0, tg, tj)
        excess = float(tjs.max() - band[1])
        if abs(excess - e_day) < 0.3:
            break
        amb["swing_c"] += (e_day - excess) * 1.05
    amb["excess_k"] = excess
    n = len(st_ms)
    bz = bias_mm(tjs, bias)
    # scene: still surfaces, permanent steps, occlusions, gross errors
    d_now = scene["d_mm"].copy()
    steps = []
    nsteps = int(rng.poisson(rng.uniform(*cfg["steps_per_day"])))
    for _ in range(nsteps):
        b = int(rng.integers(0, B))
        ts_ = int(rng.uniform(0.1, 0.9) * L * 1000)
        ts_ = ts_ - ts_ % 1000
        steps.append([ts_, b])
    steps.sort()
    d_mat = np.repeat(d_now[None, :], n, axis=0)
    ep = np.zeros((n, B), dtype=np.int64)
    step_info = []
    occ = np.zeros((n, B), dtype=bool)
    obj = np.full((n, B), np.nan)
    occ_events = []

    def add_occlusion(beams, t0_ms, dur_ms, hi_cap=None, why="person/forklift"):
        i0 = np.searchsorted(st_ms, t0_ms)
        i1 = np.searchsorted(st_ms, t0_ms + dur_ms)
        if i1 <= i0:
            return
        tt = (st_ms[i0:i1] - t0_ms) / 1000.0
        dref = min(d_mat[i0, b] for b in beams)
        hi = dref - OCC_GAP_MM if hi_cap is None else min(hi_cap, dref - OCC_GAP_MM)
        lo = OCC_GAP_MM
        o0 = rng.uniform(lo, hi)
        v = rng.uniform(-1500, 1500) if rng.random() < 0.7 else 0.0
        jit = rng.uniform(5, 40)
        path = reflect(o0 + v * tt, lo, hi)
        for b in beams:
            o = path + rng.normal(0, jit, size=len(tt))
            o = np.clip(o, lo, d_mat[i0:i1, b] - OCC_GAP_MM)
            occ[i0:i1, b] = True
            obj[i0:i1, b] = o
        occ_events.append({"beams": list(beams), "t0_s": t0_ms / 1000.0, "dur_s": dur_ms / 1000.0,
                           "speed_mm_s": float(v), "what": why})

    for ts_, b in steps:
        wall = scene["wall_mm"][b]
        cur = d_now[b]
        if abs(cur - wall) > 1.0:
            new = wall                                        # pallet removed
            what = "removed"
        else:
            if wall < 1100:
                continue
            new = round(float(wall - rng.uniform(300.0, min(2500.0, wall - 800.0))), 1)
            what = "placed"
        i = np.searchsorted(st_ms, ts_)
        d_mat[i:, b] = new
        ep[i:, b] += 1
        d_now[b] = new
        step_info.append({"beam": b, "time_s": ts_ / 1000.0, "from_mm": float(cur), "to_mm": float(new),
                          "what": "pallet " + what})
        # the forklift that moved it occludes the beam just before
        fd = int(rng.uniform(10, 60) * 1000)
        add_occlusion([b], ts_ - fd, fd, hi_cap=min(cur, new) - OCC_GAP_MM, why="forklift moving a pallet")
    occ_median = rng.uniform(*cfg["occ_median_s"])
    share = scene["occ_share"]
    target_s = share * L                                     # per beam, mean over beams
    mean_w = 2.0
    mean_dur = occ_median * math.exp(0.5 * 0.8 ** 2)
    nev = int(rng.poisson(target_s * B / (mean_dur * mean_w)))
    for _ in range(nev):
        w = int(rng.choice([1, 1, 2, 2, 3, 4]))
        c = int(rng.choice(B, p=scene["occ_weight"]))
        beams = list(range(max(0, c - w // 2), min(B, c - w // 2 + w)))
        dur = float(np.clip(occ_median * math.exp(rng.normal(0, 0.8)), 3.0, cfg["occ_max_s"]))
        t0 = int(rng.uniform(0, L - dur) * 1000)
        add_occlusion(beams, t0, int(dur * 1000))
    gross = rng.random((n, B)) < scene["gross_prob"]
    mode = mode_sequence(rng, n * B, modes, B).reshape(n, B)
    mu, sd = np.array(modes["offset_mm"]), np.array(modes["std_mm"])
    base = np.where(occ, obj, d_mat)
    expct = base + bz[:, None]
    y = np.rint(expct + mu[mode] + sd[mode] * rng.standard_normal((n, B))).astype(np.int64)
    gi = np.flatnonzero(gross)
    gk = rng.random(len(gi))
    gr = rng.integers(1, MAX_RANGE_MM, size=len(gi))
    ex_g = expct.reshape(-1)[gi]
    wall_g = (d_mat + bz[:, None]).reshape(-1)[gi]
    near = (np.abs(gr - ex_g) < 300) | (np.abs(gr - wall_g) < 300)
    gr = np.where(near, MAX_RANGE_MM, gr)
    yf = y.reshape(-1)
    yf[gi] = np.where(gk < 0.6, MAX_RANGE_MM, np.where(gk < 0.85, 0, gr))
    y = yf.reshape(n, B)
    del base, expct
    clipped = int(((y > MAX_RANGE_MM) | (y < 0)).sum())
    y = np.clip(y, 0, MAX_RANGE_MM)
    scene["d_mm"] = d_now
    srow = sensor_rows(rng, sensor, tg, ambg, tc, total_s)
    info = {"duration_s": total_s, "rate_hz": rate, "beams": B, "cold_start": bool(cold),
            "schedule": [[s, d] for s, d in on_off], "ambient": amb,
            "junction_c": [float(tjs.min()), float(tjs.max())],
            "ambient_c": [float(ambg.min()), float(ambg.max())],
            "steps": step_info, "occlusion_events": len(occ_events),
            "occluded_share": float(occ.mean()) if n else 0.0,
            "gross_share": float(gross.mean()) if n else 0.0, "gross_count": int(gross.sum()),
            "ranges": int(n * B), "clipped": clipped,
            "bias_mm_range": [float(bz.min()), float(bz.max())]}
    rows = ((np.array([c[0] for c in changes], np.int64), np.array([c[1] for c in changes], np.int64)),
            srow, (np.repeat(st_ms, B), np.tile(np.arange(B), n), y.reshape(-1), None))
    per_row = {"t_ms": np.repeat(st_ms, B), "beam": np.tile(np.arange(B), n), "y": y.reshape(-1),
               "d": d_mat.reshape(-1), "ep": ep.reshape(-1), "occ": occ.reshape(-1),
               "gross": gross.reshape(-1), "mode": mode.reshape(-1), "bias": np.repeat(bz, B),
               "tj": np.repeat(tjs, B)}
    return info, rows, per_row


def make_case(out, name, seed, size):
    cfg = SIZES[size]
    rng = np.random.default_rng(seed)
    th, sensor, bias, modes = draw_physics(rng, size)
    case = {"thermal": th, "sensor": sensor, "bias": bias, "modes": modes}
    cdir = os.path.join(out, "cases", name)
    tdir = os.path.join(out, "truth")
    os.makedirs(cdir, exist_ok=True)
    os.makedirs(tdir, exist_ok=True)
    meta0 = [("sensor", "pulsed ToF scanner, LMS200-like (blind field bench)"), ("case", name)]
    # bench
    binfo, brows = bench_record(rng, cfg, th, sensor, bias, modes)
    band = binfo["band_c"]
    write_csv(os.path.join(cdir, "bench.csv"),
              meta0 + [("record", "bench calibration, fixed targets"), ("beams", len(binfo["beams"]))],
              True, *brows)
    # scene
    while True:
        B = int(rng.integers(cfg["beams"][0], cfg["beams"][1] + 1))
        rate = float(rng.choice(cfg["field_rates"]))
        if B * rate <= cfg["max_ranges_per_s"]:
            break
    wall = np.round(rng.uniform(800.0, 8000.0, size=B), 1)
    occ_share = rng.uniform(0.01, 0.05)
    ow = rng.uniform(0.3, 1.7, size=B)
    scene = {"beams": B, "rate_hz": rate, "wall_mm": wall.copy(), "d_mm": wall.copy(),
             "occ_share": occ_share, "occ_weight": ow / ow.sum(), "gross_prob": rng.uniform(0.0005, 0.004)}
    e_case = rng.uniform(5.5, 20.0)
    D = int(rng.integers(1, 4))
    Ls = [int(rng.uniform(*cfg["day_hours"]) * 3600) for _ in range(D + 1)]      # field days, then test
    if cfg.get("budget_mb"):
        # keep a small case within its byte budget: field rows ~21 B, test rows ~21+26+53 B per range
        est = lambda: B * rate * (21.0 * sum(Ls[:-1]) + 100.0 * Ls[-1]) / 1e6
        while est() > cfg["budget_mb"]:
            if D > 1 and min(Ls) <= cfg["day_hours"][0] * 3600 * 1.01:
                D -= 1
                Ls = Ls[1:]
            else:
                Ls = [max(int(cfg["day_hours"][0] * 3600), int(x * 0.95)) for x in Ls]
    days = []
    jmin, jmax = [], []
    hot = int(rng.integers(1, D + 1))                  # the field day that reaches the full excess
    for k in range(1, D + 1):
        e_day = e_case if k == hot else e_case * rng.uniform(0.6, 1.0)
        info, rows, _ = field_day(rng, cfg, case, scene, "field", e_day, band, cold=rng.random() < 0.5,
                                  L=Ls[k - 1])
        info["file"] = "field-%d.csv" % k
        info["d_mm_end"] = scene["d_mm"].tolist()
        days.append(info)
        jmin.append(info["junction_c"][0])
        jmax.append(info["junction_c"][1])
        write_csv(os.path.join(cdir, info["file"]),
                  meta0 + [("record", "field day %d, no reference" % k), ("beams", B)], False, *rows)
    d_start_test = scene["d_mm"].copy()
    e_test = max(5.0, e_case * rng.uniform(0.8, 0.97))
    # the scanner ran overnight before the test day: it starts warm, inside the bench band
    tinfo, trows, pr = field_day(rng, cfg, case, scene, "test", e_test, band, cold=False, L=Ls[-1])
    tinfo["file"] = "test.csv"
    tinfo["d_mm_start"] = d_start_test.tolist()
    write_csv(os.path.join(cdir, "test.csv"),
              meta0 + [("record", "test day, no reference"), ("beams", B)], False, *trows)
    still = ~(pr["occ"] | pr["gross"])
    refd = np.where(still, pr["d"], np.nan)
    p_, s_, r_ = trows
    write_csv(os.path.join(cdir, "test-with-reference.csv"),
              meta0 + [("record", "test day with references on the still surfaces"), ("beams", B)],
              True, p_, s_, (r_[0], r_[1], r_[2], refd))
    # per-row truth of the test day
    mu = np.array(modes["offset_mm"])
    with open(os.path.join(tdir, name + "-test.csv"), "w", newline="\n") as f:
        f.write("row_index,time_s,beam,range_mm,true_distance_mm,episode,occluded,gross,mode,"
                "true_bias_mm,junction_c\n")
        ntot = len(pr["t_ms"])
        for c0 in range(0, ntot, 200000):
            sl = slice(c0, c0 + 200000)
            lines = []
            for i, (t, b, y, d, e, o, g, m, bz, tj) in enumerate(zip(
                    pr["t_ms"][sl].tolist(), pr["beam"][sl].tolist(), pr["y"][sl].tolist(),
                    pr["d"][sl].tolist(), pr["ep"][sl].tolist(), pr["occ"][sl].tolist(),
                    pr["gross"][sl].tolist(), pr["mode"][sl].tolist(), pr["bias"][sl].tolist(),
                    pr["tj"][sl].tolist()), start=c0):
                lines.append("%d,%s,%d,%d,%.1f,%d,%d,%d,%d,%.4f,%.3f" % (i, fmt_t(t), b, y, d, e, int(o),
                                                                       int(g), m, bz, tj))
            f.write("\n".join(lines) + "\n")
    crb = crb_figures(modes, np.random.default_rng([seed, 7]))
    tj_test = pr["tj"]
    inside = (tj_test >= band[0]) & (tj_test <= band[1])
    grid = np.linspace(min(band[0], min(jmin + [tinfo["junction_c"][0]])) - 2,
                       max(jmax + [tinfo["junction_c"][1]]) + 2, 9)
    truth = {
        "case": name, "seed": seed, "size": size, "generator": "bench/field/generate.py",
        "thermal": th, "sensor": sensor, "bias": bias, "modes": modes,
        "bias_table": {"junction_c": grid.tolist(), "bias_mm": bias_mm(grid, bias).tolist()},
        "bench": binfo, "bench_band_c": band,
        "scene": {"beams": B, "rate_hz": rate, "wall_mm": wall.tolist(), "occ_share_target": occ_share,
                  "gross_prob": scene["gross_prob"], "occlusion_gap_min_mm": OCC_GAP_MM},
        "excess_target_k": e_case,
        "field_days": days,
        "field_junction_c": [float(min(jmin)), float(max(jmax))],
        "test": tinfo,
        "test_junction_c": tinfo["junction_c"],
        "test_rows_inside_band": int(inside.sum()), "test_rows_beyond_band": int((~inside).sum()),
        "test_per_row": "truth/%s-test.csv" % name,
        "crb": crb,
        "crb_mae_mm": crb["crb_mae_mm"],
        "definitions": {
            "true_bias_mm": "H(t_j)theta at the row's true junction temperature; mode offsets have zero "
                            "weighted mean, so E[range - true_distance - true_bias] = 0 on still rows",
            "inside_band": "bench_band_c[0] <= junction <= bench_band_c[1]; beyond = outside",
            "crb_mae_mm": "sqrt(2/pi)*sqrt(1/Fisher_N): MAE of an efficient unbiased estimator of d from N "
                          "still ranges, bias and mode statistics known, ranges rounded to 1 mm"},
    }
    with open(os.path.join(tdir, name + ".json"), "w") as f:
        json.dump(truth, f, indent=1, default=float)
    return truth


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--size", choices=sorted(SIZES), default="small")
    ap.add_argument("--count", type=int, default=1)
    a = ap.parse_args(argv)
    if a.count < 1:
        ap.error("--count must be >= 1")
    t0 = time.time()
    seeds = np.random.SeedSequence(a.seed).spawn(a.count)
    names = []
    for k in range(a.count):
        name = "case-%02d" % (k + 1)
        s = int(seeds[k].generate_state(1)[0])
        tr = make_case(a.out, name, s, a.size)
        names.append(name)
        print("%s: bench band %.1f-%.1f C, field junction %.1f-%.1f C, test %.1f-%.1f C, %d beams, %d field day(s)"
              % (name, tr["bench_band_c"][0], tr["bench_band_c"][1], tr["field_junction_c"][0],
                 tr["field_junction_c"][1], tr["test_junction_c"][0], tr["test_junction_c"][1],
                 tr["scene"]["beams"], len(tr["field_days"])))
    with open(os.path.join(a.out, "suite.json"), "w") as f:
        json.dump({"seed": a.seed, "size": a.size, "cases": names}, f, indent=1)
    print("wrote %d case(s) to %s in %.1f s" % (a.count, a.out, time.time() - t0))


if __name__ == "__main__":
    main()
