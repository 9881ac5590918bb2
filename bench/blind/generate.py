#!/usr/bin/python3
"""Blind test-data generator for `tofcomp diagnose`.

Draws data sets in the interchange CSV (shared/docs/data-format.md) from the paper's model
(thermal network of section 3, measurement model Eq. 8 with 2 or 3 lasing modes) plus, in most
sets, one or two effects the model lacks.  The truth of every set goes to DIR/truth/<id>.json,
which only score.py reads.  See README.md beside this file.

Written from the paper and the data format alone, without reading the detector.
"""
import os
import sys

try:
    import numpy as np
except ImportError:  # e.g. a pyenv python3 without numpy: fall back to Debian's
    if os.path.exists("/usr/bin/python3") and not os.environ.get("BLIND_REEXEC"):
        os.environ["BLIND_REEXEC"] = "1"
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    raise

import argparse
import glob
import json
import math
import time
from concurrent.futures import ProcessPoolExecutor

# --------------------------------------------------------------------------------------------
# The effects' vocabulary (fixed, shared with score.py)
# --------------------------------------------------------------------------------------------
from kinds import KINDS  # noqa: E402  (the vocabulary both scripts share)
KIND_NAMES = ["%s:%s" % k for k in KINDS]

# a bias effect is redrawn (up to this many tries) while the part of it that no smooth function of
# the junction temperature explains moves no 200-range window mean by BIAS_GUARD_MM
BIAS_GUARD_MM = 0.15
BIAS_GUARD_TRIES = 30

SIZES = {"small": (15000, 25000), "full": (60000, 120000)}

# Fixed roles of the random streams of one set: the clean counterpart of a set re-uses every one
# of them, so that it is the very same draw with the effect switched off.
S_PHYS, S_SENSOR, S_AMBLOG, S_MODE, S_STAY, S_EXTRA, S_OUTL, S_NOISE = range(8)
N_STREAMS = 8


def parse_kind(text):
    t = text.strip().replace("\u00d7", ":").replace("*", ":")
    if ":" not in t:
        # allow the bare parameter when it is unambiguous (markov, extra_mode, ...)
        hits = [k for k in KINDS if k[0] == t]
        if len(hits) == 1:
            return hits[0]
        raise ValueError("unknown kind %r" % text)
    p, c = t.split(":", 1)
    if (p, c) not in KINDS:
        raise ValueError("unknown kind %r (known: %s)" % (text, ", ".join(KIND_NAMES)))
    return (p, c)


# --------------------------------------------------------------------------------------------
# small helpers
# --------------------------------------------------------------------------------------------
def lin(lo, hi, s):
    return lo + (hi - lo) * s


def loguni(lo, hi, s):
    return math.exp(math.log(lo) + (math.log(hi) - math.log(lo)) * s)


def sigmoid(x):
    return 1.0 / (1.0 + np.exp(-x))


def logit(p):
    return math.log(p / (1.0 - p))


def py(o):
    """numpy scalars/arrays -> plain JSON types."""
    if isinstance(o, dict):
        return {str(k): py(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [py(v) for v in o]
    if isinstance(o, np.ndarray):
        return [py(v) for v in o.tolist()]
    if isinstance(o, (np.integer,)):
        return int(o)
    if isinstance(o, (np.floating,)):
        return float(o)
    return o


# --------------------------------------------------------------------------------------------
# physics
# --------------------------------------------------------------------------------------------
def draw_physics(rng, size):
    n_lo, n_hi = SIZES[size]
    # schedule and range rate: reject until the number of ranges falls in the size's band with a
    # rate of 1-5 Hz (so 'small' sets tend to have fewer/shorter cycles)
    for _ in range(100000):
        ncyc = int(rng.integers(4, 8))
        on = np.round(rng.uniform(40, 120, ncyc) * 60).astype(int)
        off = np.round(rng.uniform(10, 60, ncyc) * 60).astype(int)
        n_target = rng.uniform(n_lo, n_hi)
        rate = n_target / on.sum()
        if 1.0 <= rate <= 5.0:
            break
    else:  # pragma: no cover
        raise RuntimeError("could not draw a schedule")
    rate = round(float(rate), 4)
    schedule = []
    for a, b in zip(on, off):
        schedule += [[1, int(a)], [0, int(b)]]

    tau1 = rng.uniform(5, 45)                 # R1*C1, s
    tau2 = rng.uniform(20, 120) * 60          # R2*C2, s
    rise = rng.uniform(3.5, 11.0)             # P*(R1+R2): junction's steady rise over ambient
    frac1 = rng.uniform(0.25, 0.6)            # share of R1 in it
    P = rng.uniform(3.0, 12.0)
    R1 = rise * frac1 / P
    R2 = rise * (1 - frac1) / P
    thermal = {"R1": R1, "C1": tau1 / R1, "R2": R2, "C2": tau2 / R2, "P": P,
               "tau1_s": tau1, "tau2_s": tau2, "steady_rise_c": rise}

    step = rng.uniform(-0.6, 0.6) if rng.uniform() < 0.7 else 0.0
    ambient = {"base_c": rng.uniform(15, 28), "drift_c_per_h": rng.uniform(-0.4, 0.4),
               "wave_c": rng.uniform(0.2, 1.5), "wave_period_h": rng.uniform(3, 14),
               "wave_phase": rng.uniform(0, 2 * math.pi), "step_c": step,
               "step_at": rng.uniform(0.2, 0.9), "step_ramp_s": 120.0,
               "log_noise_c": 0.02}

    sensor = {"period_s": round(float(rng.uniform(0.5, 5.0)), 1),
              "resolution_c": float(rng.choice([0.0625, 0.1, 0.125, 0.25])),
              "noise_c": rng.uniform(0.01, 0.06)}

    d_mm = int(rng.integers(1500, 7501))

    M = int(rng.integers(2, 4))
    gaps = rng.uniform(2.5, 8.0, M - 1)
    offs = np.concatenate([[0.0], np.cumsum(gaps)])
    while True:
        w = rng.dirichlet(np.full(M, 3.0))
        if w.min() >= 0.15:
            break
    offs = offs - float(np.dot(w, offs)) + rng.uniform(-2.5, 2.5)
    modes = {"offset_mm": offs, "std_mm": rng.uniform(0.5, 3.0, M), "weight": w}

    bias = {"lin": rng.uniform(0.1, 0.8) * rng.choice([-1, 1]),
            "quad": rng.uniform(-0.08, 0.08),
            "amp": rng.uniform(0.0, 2.0),
            "period_c": rng.uniform(5.0, 20.0),
            "phase": rng.uniform(0, 2 * math.pi),
            "span_target_mm": rng.uniform(2.0, 8.0)}
    return {"thermal": thermal, "schedule": schedule, "rate_hz": rate, "ambient": ambient,
            "sensor": sensor, "d_mm": d_mm, "modes": modes, "bias": bias}


def ambient_fn(amb, t_end):
    t_step = amb["step_at"] * t_end

    def f(t):
        t = np.asarray(t, dtype=float)
        x = (amb["base_c"] + amb["drift_c_per_h"] * t / 3600.0
             + amb["wave_c"] * np.sin(2 * math.pi * t / (amb["wave_period_h"] * 3600.0)
                                      + amb["wave_phase"]))
        x = x + amb["step_c"] * np.clip((t - t_step) / amb["step_ramp_s"] + 0.5, 0.0, 1.0)
        return x
    return f


class Thermal:
    """Exact solution of Eq. 3 on a 1 s grid (power switches at whole seconds; the ambient is
    held at its mid-step value over each second), and exact in-between values at any time."""

    def __init__(self, th, schedule, amb_f):
        R1, C1, R2, C2, P = th["R1"], th["C1"], th["R2"], th["C2"], th["P"]
        self.R1, self.R2, self.C1, self.P = R1, R2, C1, P
        A = np.array([[-(1 / (R2 * C2) + 1 / (R1 * C2)), 1 / (R1 * C2)],
                      [1 / (R1 * C1), -1 / (R1 * C1)]])
        self.A = A
        lam, V = np.linalg.eig(A)
        self.lam, self.V, self.Vi = lam.real, V.real, np.linalg.inv(V.real)
        t_end = int(sum(d for _, d in schedule))
        self.t_end = t_end
        u = np.zeros(t_end + 1)
        t0 = 0
        self.on_intervals = []
        for state, dur in schedule:
            if state:
                u[t0:t0 + dur] = P
                self.on_intervals.append((t0, t0 + dur))
            t0 += dur
        self.u = u
        self.ta = amb_f(np.arange(t_end + 1) + 0.5)
        # steady state of each step: tc = ta + u R2, tj = ta + u (R1 + R2)
        ss_c = self.ta + u * R2
        ss_j = self.ta + u * (R1 + R2)
        Phi = self.V @ np.diag(np.exp(self.lam)) @ self.Vi
        p00, p01, p10, p11 = Phi[0, 0], Phi[0, 1], Phi[1, 0], Phi[1, 1]
        xc = np.empty(t_end + 1)
        xj = np.empty(t_end + 1)
        c = j = float(amb_f(0.0))          # starts in equilibrium with the ambient, power off
        ssc = ss_c.tolist()
        ssj = ss_j.tolist()
        for k in range(t_end + 1):
            xc[k] = c
            xj[k] = j
            dc = c - ssc[k]
            dj = j - ssj[k]
            c = ssc[k] + p00 * dc + p01 * dj
            j = ssj[k] + p10 * dc + p11 * dj
        self.xc, self.xj, self.ss_c, self.ss_j = xc, xj, ss_c, ss_j

    def at(self, t):
        """case temp, junction temp and dtj/dt (degC/s) at times t (s)."""
        t = np.asarray(t, dtype=float)
        k = np.clip(np.floor(t).astype(int), 0, self.t_end)
        s = t - k
        dc = self.xc[k] - self.ss_c[k]
        dj = self.xj[k] - self.ss_j[k]
        e0 = np.exp(self.lam[0] * s)
        e1 = np.exp(self.lam[1] * s)
        V, Vi = self.V, self.Vi
        # Phi(s) = V diag(e) Vi
        z0 = Vi[0, 0] * dc + Vi[0, 1] * dj
        z1 = Vi[1, 0] * dc + Vi[1, 1] * dj
        yc = V[0, 0] * e0 * z0 + V[0, 1] * e1 * z1
        yj = V[1, 0] * e0 * z0 + V[1, 1] * e1 * z1
        tc = self.ss_c[k] + yc
        tj = self.ss_j[k] + yj
        rate_j = self.A[1, 0] * yc + self.A[1, 1] * yj
        return tc, tj, rate_j

    def lag_of_junction(self, tau):
        """A third node driven by the junction: dth/dt = (tj - th)/tau, exact for a junction
        temperature linear within each 1 s step.  Returns th on the grid."""
        e = math.exp(-1.0 / tau)
        g = 1.0 - tau * (1.0 - e)
        xj = self.xj.tolist()
        th = np.empty(len(xj))
        h = xj[0]
        for k in range(len(xj)):
            th[k] = h
            if k + 1 < len(xj):
                a, b = xj[k], xj[k + 1]
                h = e * h + (1 - e) * a + (b - a) * g
        return th


def bias_fn(b, t0, scale):
    def f(tj):
        x = np.asarray(tj) - t0
        return scale * (b["lin"] * x + b["quad"] * x * x
                        + b["amp"] * np.sin(2 * math.pi * x / b["period_c"] + b["phase"]))
    return f


# --------------------------------------------------------------------------------------------
# effects
# --------------------------------------------------------------------------------------------
def draw_effect(kind, rng, ctx):
    """Draws one effect.  Returns the truth record; its private key '_apply' is a function that
    modifies the per-range model arrays."""
    p, c = kind
    sign = float(rng.choice([-1.0, 1.0]))
    M = len(ctx["modes"]["weight"])
    rec = {"parameter": p, "covariate": c}

    if kind == ("bias", "time"):
        s = rng.uniform()
        A = sign * lin(0.5, 4.0, s)
        form = str(rng.choice(["linear", "saturating", "sigmoid"]))
        T = float(ctx["t"][-1])
        vals = {"total_mm": A, "record_s": T, "range": "|total| 0.5-4 mm over the record"}
        if form == "linear":
            def shape(t):
                return t / T
        elif form == "saturating":
            tf = rng.uniform(0.15, 0.5)
            vals["tau_fraction_of_record"] = tf

            def shape(t):
                return (1 - np.exp(-t / (tf * T))) / (1 - math.exp(-1 / tf))
        else:
            cen, wid = rng.uniform(0.3, 0.7), rng.uniform(0.05, 0.15)
            vals.update({"center_fraction": cen, "width_fraction": wid})
            lo, hi = 1 / (1 + math.exp(cen / wid)), 1 / (1 + math.exp(-(1 - cen) / wid))

            def shape(t):
                return (sigmoid((t / T - cen) / wid) - lo) / (hi - lo)
        vals["formula"] = "total_mm * shape(t / record_s), shape 0 at t=0 and 1 at the end"

        def apply(m):
            m["bias_add"] += A * shape(m["t"])
        strength = s

    elif kind == ("bias", "time_since_power_on"):
        s1, s2 = rng.uniform(), rng.uniform()
        A = sign * loguni(1.0, 5.0, s1)
        tau = loguni(1.0, 20.0, s2) * 60
        form = "exp"
        vals = {"amplitude_mm": A, "tau_s": tau, "formula": "amplitude_mm * exp(-t_on / tau_s)",
                "range": "|amplitude| 1-5 mm (log), tau 1-20 min (log); strength = mean of both"}

        def apply(m):
            m["bias_add"] += A * np.exp(-m["t_on"] / tau)
        strength = (s1 + s2) / 2

    elif kind == ("bias", "heating_rate"):
        s1, s2 = rng.uniform(), rng.uniform()
        h = sign * loguni(1.0, 4.0, s1)
        r0 = loguni(0.3, 0.03, s2)  # degC/min; smaller saturates earlier = stronger
        form = "tanh"
        vals = {"amplitude_mm": h, "rate_scale_c_per_min": r0,
                "formula": "amplitude_mm * tanh((dtj/dt in degC/min) / rate_scale_c_per_min)",
                "range": "|amplitude| 1-4 mm (log), rate scale 0.3-0.03 degC/min (log); "
                         "strength = mean of both"}

        def apply(m):
            m["bias_add"] += h * np.tanh(m["rate_j"] * 60.0 / r0)
        strength = (s1 + s2) / 2

    elif kind == ("bias", "ambient"):
        # drawn as the bias it makes over the ambient's range while ranging (0.5-3 mm), so that a
        # weak draw is not lost in a flat ambient; the slope is kept within 0.15-1.5 mm/degC
        s = rng.uniform()
        amb_span = float(np.percentile(ctx["ta"], 99) - np.percentile(ctx["ta"], 1))
        k = min(max(lin(0.5, 3.0, s) / max(amb_span, 1e-6), 0.15), 1.5)
        s = min(max((k * amb_span - 0.5) / 2.5, 0.0), 1.0)
        k *= sign
        ref = float(np.median(ctx["ta"]))
        form = "linear"
        vals = {"mm_per_c": k, "ref_c": ref, "ambient_span_c": amb_span,
                "bias_span_mm": abs(k) * amb_span,
                "formula": "mm_per_c * (ambient - ref_c)",
                "range": "|k| * ambient span (p1-p99) 0.5-3 mm, |k| kept in 0.15-1.5 mm/degC; "
                         "strength = position of the realised span"}

        def apply(m):
            m["bias_add"] += k * (m["ta"] - ref)
        strength = s

    elif kind == ("mode_offset", "junction_temperature"):
        # drawn as the shift of the mode across the junction range (p1-p99), 1-5 mm; the slope
        # is kept within 0.15-1.5 mm/degC
        s = rng.uniform()
        span = 2 * ctx["tj_half"]
        k = min(max(lin(1.0, 5.0, s) / span, 0.15), 1.5)
        s = min(max((k * span - 1.0) / 4.0, 0.0), 1.0)
        k *= sign
        j = int(rng.integers(0, M))
        mid = ctx["tj_mid"]
        form = "linear"
        vals = {"mode": j, "mm_per_c": k, "ref_c": mid, "junction_span_c": span,
                "shift_across_range_mm": k * span,
                "formula": "offset[mode] += mm_per_c * (tj - ref_c)",
                "range": "|shift across the junction range| 1-5 mm, |k| kept in 0.15-1.5 mm/degC; "
                         "strength = position of the realised shift"}

        def apply(m):
            m["MU"][:, j] += k * (m["tj"] - mid)
        strength = s

    elif kind == ("spread", "junction_temperature"):
        s = rng.uniform()
        f = lin(0.2, 0.6, s)
        ratio = (1 + f) if sign > 0 else 1 / (1 + f)
        form = "exponential"
        vals = {"ratio_hot_over_cold": ratio, "ref_c": ctx["tj_mid"], "half_span_c": ctx["tj_half"],
                "formula": "std[every mode] *= ratio ** (z / 2), z = (tj - ref_c) / half_span_c",
                "range": "1 + 20-60 % (grow) or its inverse (shrink) across the range"}

        def apply(m):
            m["SD"] *= (ratio ** (m["z"] / 2.0))[:, None]
        strength = s

    elif kind == ("weights", "junction_temperature"):
        s = rng.uniform()
        delta = lin(0.15, 0.5, s)
        j = int(rng.integers(0, M))
        w0 = float(ctx["modes"]["weight"][j])
        L0 = logit(w0)
        lo, hi = 0.0, 50.0
        for _ in range(100):
            b = (lo + hi) / 2
            if 1 / (1 + math.exp(-(L0 + b))) - 1 / (1 + math.exp(-(L0 - b))) < delta:
                lo = b
            else:
                hi = b
        b = sign * (lo + hi) / 2
        form = "logistic"
        vals = {"mode": j, "weight_mid": w0, "logit_slope": b, "ref_c": ctx["tj_mid"],
                "half_span_c": ctx["tj_half"],
                "weight_cold": 1 / (1 + math.exp(-(L0 - b))),
                "weight_hot": 1 / (1 + math.exp(-(L0 + b))),
                "formula": "logit(w[mode]) = logit(weight_mid) + logit_slope * z, "
                           "z = (tj - ref_c) / half_span_c; other modes rescaled",
                "range": "|w_hot - w_cold| 0.15-0.5"}

        def apply(m):
            m["logit_add"][:, j] += b * m["z"]
        strength = s

    elif kind == ("weights", "time_since_power_on"):
        s1, s2 = rng.uniform(), rng.uniform()
        delta = lin(0.15, 0.5, s1)
        tau = loguni(2.0, 20.0, s2) * 60
        j = int(rng.integers(0, M))
        w0 = float(ctx["modes"]["weight"][j])
        if not (0.03 <= w0 + sign * delta <= 0.97):
            sign = -sign
        w_on = min(max(w0 + sign * delta, 0.03), 0.97)
        b = logit(w_on) - logit(w0)
        form = "exp"
        vals = {"mode": j, "weight_late": w0, "weight_at_power_on": w_on, "tau_s": tau,
                "formula": "logit(w[mode]) = logit(weight_late) + b * exp(-t_on / tau_s), "
                           "other modes rescaled", "b": b,
                "range": "|w_on - w_late| 0.15-0.5, tau 2-20 min (log); strength = mean of both"}

        def apply(m):
            m["logit_add"][:, j] += b * np.exp(-m["t_on"] / tau)
        strength = (s1 + s2) / 2

    elif kind == ("markov", "none"):
        s = rng.uniform()
        p_stay = 1 - loguni(0.2, 0.01, s)
        w = np.asarray(ctx["modes"]["weight"])
        form = "sticky"
        vals = {"p_stay": p_stay,
                "p_same_mode_next": p_stay + (1 - p_stay) * float(np.sum(w * w)),
                "formula": "with p_stay keep the mode, else draw it anew from the weights "
                           "(stationary law = the weights); chain restarts at each power-on",
                "range": "p_stay 0.8-0.99 (log of 1-p)"}

        def apply(m):
            m["p_stay"] = p_stay
        strength = s

    elif kind == ("extra_mode", "none"):
        s = rng.uniform()
        we = lin(0.05, 0.3, s)
        offs = np.asarray(ctx["modes"]["offset_mm"])
        gap = rng.uniform(5.0, 12.0)
        off = float(offs.max() + gap) if sign > 0 else float(offs.min() - gap)
        sd = rng.uniform(0.5, 3.0)
        form = "gaussian"
        vals = {"weight": we, "offset_mm": off, "std_mm": sd, "gap_mm": gap,
                "formula": "with probability weight the range comes from N(offset_mm, std_mm) "
                           "instead of the drawn mode", "range": "weight 0.05-0.3"}

        def apply(m):
            m["extra"] = (we, off, sd)
        strength = s

    elif kind == ("outliers", "none"):
        s = rng.uniform()
        frac = loguni(0.002, 0.03, s)
        form = str(rng.choice(["uniform", "spurious"]))
        vals = {"fraction": frac, "range": "fraction 0.2-3 % (log)"}
        if form == "uniform":
            vals.update({"half_width_mm": 500.0,
                         "formula": "replaced by d + U(-500, 500) mm"})
            spec = ("uniform", 500.0)
        else:
            dd = sign * rng.uniform(150.0, 1500.0)
            dd = max(dd, 300.0 - ctx["d"])
            sd = rng.uniform(3.0, 20.0)
            vals.update({"offset_mm": dd, "std_mm": sd,
                         "formula": "replaced by a spurious return d + N(offset_mm, std_mm)"})
            spec = ("spurious", dd, sd)

        def apply(m):
            m["outliers"] = (frac, spec)
        strength = s

    elif kind == ("thermal_state", "none"):
        s1, s2 = rng.uniform(), rng.uniform()
        k = sign * loguni(0.4, 2.5, s1)
        tau = loguni(2.0, 20.0, s2) * 60
        form = "lagged_node"
        th_grid = ctx["thermal"].lag_of_junction(tau)
        t = ctx["t"]
        kk = np.clip(np.floor(t).astype(int), 0, len(th_grid) - 2)
        s_ = t - kk
        th = th_grid[kk] * (1 - s_) + th_grid[kk + 1] * s_
        dev = th - ctx["tj"]
        vals = {"mm_per_c": k, "tau_s": tau,
                "deviation_range_c": [float(dev.min()), float(dev.max())],
                "formula": "bias += mm_per_c * (th - tj), dth/dt = (tj - th) / tau_s "
                           "(a heat-sink node driven by the junction)",
                "range": "|k| 0.4-2.5 mm/degC (log), tau 2-20 min (log); strength = mean of both"}

        def apply(m):
            m["bias_add"] += k * dev
        strength = (s1 + s2) / 2
    else:
        raise ValueError(kind)

    rec.update({"form": form, "values": vals, "strength": float(strength), "_apply": apply})
    return rec


# --------------------------------------------------------------------------------------------
# one set
# --------------------------------------------------------------------------------------------
def simulate(set_seed, size, kinds):
    """Returns (clean_csv_text, effect_csv_text or None, truth dict without id)."""
    ss = np.random.SeedSequence(set_seed)
    streams = [np.random.default_rng(s) for s in ss.spawn(N_STREAMS)]
    phys = draw_physics(streams[S_PHYS], size)

    sched = phys["schedule"]
    t_end = int(sum(d for _, d in sched))
    amb_f = ambient_fn(phys["ambient"], t_end)
    th = Thermal(phys["thermal"], sched, amb_f)

    # range times: while the power is on, from the power-on instant, at the range rate
    rate = phys["rate_hz"]
    t_list, ton_list, seg_start = [], [], []
    for a, b in th.on_intervals:
        n = int(math.floor((b - a) * rate - 1e-9)) + 1
        k = np.arange(n)
        tt = a + k / rate
        # must fall strictly before the power-off row once printed to the millisecond
        keep = np.rint(tt * 1000).astype(np.int64) < b * 1000
        tt = tt[keep]
        t_list.append(tt)
        ton_list.append(tt - a)
        st = np.zeros(len(tt), bool)
        st[0] = True
        seg_start.append(st)
    t = np.concatenate(t_list)
    t_on = np.concatenate(ton_list)
    seg_start = np.concatenate(seg_start)
    N = len(t)
    tc, tj, rate_j = th.at(t)
    ta = amb_f(t)

    # bias H(tj) theta, scaled to the drawn span over the realised junction range
    tj_lo, tj_hi = float(np.percentile(tj, 1)), float(np.percentile(tj, 99))
    t0 = float(tj.min())
    b = phys["bias"]
    raw = bias_fn(b, t0, 1.0)(np.linspace(tj.min(), tj.max(), 400))
    span = float(raw.max() - raw.min())
    scale = b["span_target_mm"] / span if span > 1e-9 else 1.0
    b["t0_c"] = t0
    b["scale"] = scale
    b["formula"] = ("scale * (lin*x + quad*x^2 + amp*sin(2*pi*x/period_c + phase)), x = tj - t0_c")
    bias = bias_fn(b, t0, scale)(tj)

    tj_mid = (tj_lo + tj_hi) / 2
    tj_half = max((tj_hi - tj_lo) / 2, 0.25)
    ctx = {"t": t, "t_on": t_on, "tj": tj, "ta": ta, "rate_j": rate_j, "modes": phys["modes"],
           "tj_mid": tj_mid, "tj_half": tj_half, "thermal": th, "d": phys["d_mm"]}

    # per-range random numbers, the same for a set and its counterpart
    u_mode = streams[S_MODE].uniform(size=N)
    u_stay = streams[S_STAY].uniform(size=N)
    u_extra = streams[S_EXTRA].uniform(size=N)
    ro = streams[S_OUTL]
    u_out = ro.uniform(size=N)
    u_outv = ro.uniform(size=N)
    e_out = ro.standard_normal(size=N)
    e = streams[S_NOISE].standard_normal(size=N)

    effects = []
    zq = np.vander((tj - tj_mid) / tj_half, 5)
    for i, kind in enumerate(kinds):
        for attempt in range(BIAS_GUARD_TRIES):
            erng = np.random.default_rng(
                np.random.SeedSequence([set_seed, 1000 + KINDS.index(kind), i, attempt]))
            eff = draw_effect(kind, erng, ctx)
            if kind[0] not in ("bias", "thermal_state"):
                break
            # guard: a bias effect that a smooth function of the junction temperature would
            # absorb (a slow drift collinear with the heating, say) is not missing from the model;
            # redraw it until what tj cannot explain moves some 200-range window by >= 0.15 mm
            m = {"t": t, "t_on": t_on, "tj": tj, "ta": ta, "rate_j": rate_j, "bias_add": np.zeros(N)}
            eff["_apply"](m)
            coef, *_ = np.linalg.lstsq(zq, m["bias_add"], rcond=None)
            r = m["bias_add"] - zq @ coef
            nw = N // 200
            wmax = float(np.abs(r[:nw * 200].reshape(nw, 200).mean(axis=1)).max())
            if wmax >= BIAS_GUARD_MM:
                break
        eff["values"]["redraws"] = attempt
        effects.append(eff)

    modes = phys["modes"]
    M = len(modes["weight"])
    d = phys["d_mm"]

    def ranges(with_effects):
        m = {"t": t, "t_on": t_on, "tj": tj, "ta": ta, "rate_j": rate_j,
             "z": (tj - tj_mid) / tj_half,
             "bias_add": np.zeros(N),
             "MU": np.tile(np.asarray(modes["offset_mm"], float), (N, 1)),
             "SD": np.tile(np.asarray(modes["std_mm"], float), (N, 1)),
             "logit_add": np.zeros((N, M)),
             "p_stay": 0.0, "extra": None, "outliers": None}
        if with_effects:
            for eff in effects:
                eff["_apply"](m)
        # weights: one mode's logit moved, the others rescaled (log-weights shifted alike)
        W = np.tile(np.asarray(modes["weight"], float), (N, 1))
        if np.any(m["logit_add"] != 0):
            # per mode j with a logit shift: w_j' = sigmoid(logit(w_j) + a), others scaled
            for j in range(M):
                a = m["logit_add"][:, j]
                if not np.any(a != 0):
                    continue
                wj = W[:, j]
                wj_new = sigmoid(np.log(wj / (1 - wj)) + a)
                others = [i for i in range(M) if i != j]
                W[:, others] *= ((1 - wj_new) / (1 - wj))[:, None]
                W[:, j] = wj_new
        cdf = np.cumsum(W, axis=1)
        cdf /= cdf[:, -1:]
        mode = (u_mode[:, None] > cdf[:, :-1]).sum(axis=1)
        if m["p_stay"] > 0:
            refresh = (u_stay >= m["p_stay"]) | seg_start
            idx = np.maximum.accumulate(np.where(refresh, np.arange(N), 0))
            mode = mode[idx]
        rows = np.arange(N)
        mu = m["MU"][rows, mode]
        sd = m["SD"][rows, mode]
        if m["extra"] is not None:
            we, off, sde = m["extra"]
            ex = u_extra < we
            mu = np.where(ex, off, mu)
            sd = np.where(ex, sde, sd)
            mode = np.where(ex, M, mode)
        y = d + bias + m["bias_add"] + mu + sd * e
        if m["outliers"] is not None:
            frac, spec = m["outliers"]
            ox = u_out < frac
            if spec[0] == "uniform":
                val = d + (2 * u_outv - 1) * spec[1]
            else:
                val = d + spec[1] + spec[2] * e_out
            y = np.where(ox, val, y)
            mode = np.where(ox, -1, mode)
        return np.rint(y).astype(np.int64), m["bias_add"], mode

    y_clean, _, mode_clean = ranges(False)
    if effects:
        y_eff, badd, _ = ranges(True)
    else:
        y_eff, badd = None, None

    # case sensor and ambient log
    per = phys["sensor"]["period_s"]
    ts = np.arange(0, int(math.floor(t_end / per + 1e-9)) + 1) * per
    tcs, _, _ = th.at(ts)
    res = phys["sensor"]["resolution_c"]
    s_read = np.round((tcs + phys["sensor"]["noise_c"] * streams[S_SENSOR].standard_normal(len(ts))) / res) * res
    amb_rng = streams[S_AMBLOG]
    a_sens = amb_f(ts) + phys["ambient"]["log_noise_c"] * amb_rng.standard_normal(len(ts))
    p_times = []
    p_states = []
    t0_ = 0
    for state, dur in sched:
        p_times.append(t0_)
        p_states.append(state)
        t0_ += dur
    p_times = np.asarray(p_times, float)
    a_pow = amb_f(p_times) + phys["ambient"]["log_noise_c"] * amb_rng.standard_normal(len(p_times))

    def csv_text(y):
        # rows: (time in ms, priority, text); priority: power 0, sensor 1, range 2
        def fmt_t(ms):
            return "%d.%03d" % divmod(ms, 1000)
        ms_p = np.rint(p_times * 1000).astype(np.int64)
        ms_s = np.rint(ts * 1000).astype(np.int64)
        ms_r = np.rint(t * 1000).astype(np.int64)
        rp = ["%s,,,%d,%.2f," % (fmt_t(a), s, b) for a, s, b in
              zip(ms_p.tolist(), p_states, a_pow.tolist())]
        rs = ["%s,,%.4f,,%.2f," % (fmt_t(a), v, b) for a, v, b in
              zip(ms_s.tolist(), s_read.tolist(), a_sens.tolist())]
        dstr = str(d)
        rr = ["%d.%03d,%d,,,,%s" % (a // 1000, a % 1000, v, dstr) for a, v in
              zip(ms_r.tolist(), y.tolist())]
        ms = np.concatenate([ms_p, ms_s, ms_r])
        pr = np.concatenate([np.zeros(len(ms_p), int), np.ones(len(ms_s), int),
                             np.full(len(ms_r), 2)])
        allrows = rp + rs + rr
        order = np.lexsort((np.arange(len(ms)), pr, ms))
        out = ["# sensor: LMS200", "# target: fixed",
               "time_s,range_mm,case_temp_c,power,ambient_c,true_range_mm"]
        out += [allrows[i] for i in order.tolist()]
        return "\n".join(out) + "\n"

    clean_csv = csv_text(y_clean)
    eff_csv = csv_text(y_eff) if effects else None

    # realised impact of the effects (informative; see README)
    truth_effects = []
    for eff in effects:
        truth_effects.append({k: v for k, v in eff.items() if not k.startswith("_")})
    impact = None
    if effects:
        diff = (y_eff - y_clean).astype(float)
        nw = N // 200
        wdiff = diff[:nw * 200].reshape(nw, 200).mean(axis=1)
        resid_c = (y_clean - d - bias)
        resid_e = (y_eff - d - bias)
        impact = {"window200_mean_shift_mae_mm": float(np.abs(wdiff).mean()),
                  "window200_mean_shift_max_mm": float(np.abs(wdiff).max()),
                  "ranges_changed_fraction": float(np.mean(diff != 0)),
                  "residual_std_ratio": float(np.std(resid_e) / np.std(resid_c))}
        if np.any(badd != 0):
            z = (tj - tj_mid) / tj_half
            X = np.vander(z, 5)
            coef, *_ = np.linalg.lstsq(X, badd, rcond=None)
            r = badd - X @ coef
            wr = r[:nw * 200].reshape(nw, 200).mean(axis=1)
            impact.update({"bias_span_mm": float(badd.max() - badd.min()),
                           "bias_not_explained_by_tj_mae_mm": float(np.abs(r).mean()),
                           "bias_not_explained_by_tj_window200_mae_mm": float(np.abs(wr).mean())})

    physics = dict(phys)
    physics["junction_c"] = [float(tj.min()), float(tj.max())]
    physics["junction_c_p01_p99"] = [tj_lo, tj_hi]
    physics["case_c"] = [float(tc.min()), float(tc.max())]
    physics["ambient_c_while_ranging"] = [float(ta.min()), float(ta.max())]
    physics["samples"] = int(N)
    physics["duration_s"] = int(t_end)
    physics["mode_counts_clean"] = np.bincount(mode_clean, minlength=M).tolist()
    truth = {"seed": int(set_seed), "size": size,
             "kind": "clean" if not effects else ("single" if len(effects) == 1 else "pair"),
             "effects": truth_effects, "impact": impact,
             "physics": py(physics), "d_mm": d}
    return clean_csv, eff_csv, py(truth)


def build_one(job):
    idx, set_id, set_seed, size, kinds, out = job
    t0 = time.time()
    clean_csv, eff_csv, truth = simulate(set_seed, size, kinds)
    truth = {"id": set_id, **truth}
    data = os.path.join(out, "data")
    if eff_csv is None:
        with open(os.path.join(data, set_id + ".csv"), "w") as f:
            f.write(clean_csv)
        truth["counterpart"] = None
    else:
        with open(os.path.join(data, set_id + ".csv"), "w") as f:
            f.write(eff_csv)
        with open(os.path.join(data, set_id + "-clean.csv"), "w") as f:
            f.write(clean_csv)
        truth["counterpart"] = set_id + "-clean.csv"
    truth["suite_index"] = idx
    with open(os.path.join(out, "truth", set_id + ".json"), "w") as f:
        json.dump(truth, f, indent=1)
    return set_id, truth["kind"], [e["parameter"] + ":" + e["covariate"] for e in truth["effects"]], \
        truth["physics"]["samples"], time.time() - t0


def plan(seed, count, pairs, clean, kinds):
    rng = np.random.default_rng(np.random.SeedSequence([seed, 7]))
    sets = []
    for i in range(count):
        sets.append([kinds[i % len(kinds)]])
    # pairs: walk through shuffled copies of the kinds, two distinct at a time
    pool = []
    while len(sets) < count + pairs:
        if len(pool) < 2:
            perm = [kinds[i] for i in rng.permutation(len(kinds))]
            pool = pool + perm
        a = pool.pop(0)
        j = next((i for i, k in enumerate(pool) if k != a), None)
        if j is None:
            if len(kinds) < 2:
                raise SystemExit("--pairs needs at least two kinds")
            pool += [kinds[i] for i in rng.permutation(len(kinds))]
            continue
        b = pool.pop(j)
        sets.append([a, b])
    for _ in range(clean):
        sets.append([])
    order = rng.permutation(len(sets))
    seeds = rng.integers(0, 2 ** 62, size=len(sets))
    jobs = []
    for n, i in enumerate(order.tolist()):
        jobs.append((n + 1, "set-%04d" % (n + 1), int(seeds[n]), sets[i]))
    return jobs


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="output directory (data/ and truth/ go there)")
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--count", type=int, required=True, help="single-effect sets")
    ap.add_argument("--size", choices=sorted(SIZES), default="full")
    ap.add_argument("--kinds", default=None,
                    help="comma list of parameter:covariate (default: all %d kinds)" % len(KINDS))
    ap.add_argument("--pairs", type=int, default=0, help="sets with two effects")
    ap.add_argument("--clean", type=int, default=0, help="independent clean sets")
    ap.add_argument("--jobs", type=int, default=max(1, os.cpu_count() or 1),
                    help="parallel processes (does not change the output)")
    ap.add_argument("--force", action="store_true", help="write into a non-empty directory")
    a = ap.parse_args(argv)
    if a.count < 0 or a.pairs < 0 or a.clean < 0 or a.jobs < 1:
        ap.error("counts must be >= 0 and --jobs >= 1")
    try:
        kinds = [parse_kind(k) for k in a.kinds.split(",") if k.strip()] if a.kinds else list(KINDS)
    except ValueError as ex:
        ap.error(str(ex))
    if not kinds and (a.count or a.pairs):
        ap.error("--kinds is empty")
    for sub in ("data", "truth"):
        p = os.path.join(a.out, sub)
        if os.path.isdir(p) and os.listdir(p):
            if not a.force:
                ap.error("%s is not empty (use --force to replace a suite there)" % p)
            # --force: remove an earlier suite's sets (only the generator's own file names)
            for old in glob.glob(os.path.join(p, "set-*.csv" if sub == "data" else "set-*.json")):
                os.remove(old)
        os.makedirs(p, exist_ok=True)
    jobs = plan(a.seed, a.count, a.pairs, a.clean, kinds)
    with open(os.path.join(a.out, "suite.json"), "w") as f:
        json.dump({"generator": "bench/blind/generate.py", "seed": a.seed, "count": a.count,
                   "pairs": a.pairs, "clean": a.clean, "size": a.size,
                   "kinds": ["%s:%s" % k for k in kinds],
                   "sets": [j[1] for j in jobs]}, f, indent=1)
    work = [(n, sid, s, a.size, ks, a.out) for n, sid, s, ks in jobs]
    t0 = time.time()
    def report(results):
        for sid, kind, labels, n, dt in results:
            print("%s  %6d ranges  %.1fs" % (sid, n, dt), file=sys.stderr)
    if a.jobs == 1 or len(work) <= 1:
        report(map(build_one, work))
    else:
        with ProcessPoolExecutor(max_workers=a.jobs) as ex:
            report(ex.map(build_one, work))
    print("%d sets in %s (%.0f s); truth in %s/truth is for score.py only" %
          (len(work), a.out, time.time() - t0, a.out), file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
