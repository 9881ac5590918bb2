#!/usr/bin/python3
"""Self-check of the blind generator (not of the detector).

For every set of a suite made by generate.py it
  * parses each CSV by the rules of shared/docs/data-format.md,
  * re-simulates the thermal network from the truth with an independent integrator (RK4),
    checks the case sensor against it, and checks that the clean data follow the paper's model
    (residual y - d - H(tj)theta is the drawn mixture of the modes, rounded to 1 mm, with no
    trend in time, time since power-on, ambient or heating rate and no serial dependence),
  * for a set with an effect: checks that it differs from its counterpart only through the
    effect, and prints a statistic of the effect measured on the effect set and on the counterpart.

Usage: selfcheck.py --suite DIR [--ids set-0001,...]
It reads DIR/truth: it is a tool for the generator's author, never for the detector under test.
"""
import os
import sys

try:
    import numpy as np
except ImportError:
    if os.path.exists("/usr/bin/python3") and not os.environ.get("BLIND_REEXEC"):
        os.environ["BLIND_REEXEC"] = "1"
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    raise

import argparse
import glob
import json
import math


# ------------------------------------------------------------------------------ CSV per the spec
def read_csv(path):
    cols = {}
    header = None
    rows = {"time": [], "range": [], "range_t": [], "case": [], "case_t": [], "amb": [], "amb_t": [],
            "power": [], "power_t": [], "true": []}
    power = 1
    last_t = -math.inf
    with open(path) as f:
        for ln, line in enumerate(f, 1):
            line = line.rstrip("\r\n")
            if header is None:
                if line.startswith("#"):
                    continue
                header = line.split(",")
                cols = {c: i for i, c in enumerate(header)}
                assert "time_s" in cols, "no time_s"
                continue
            cells = line.split(",")
            assert len(cells) == len(header), "line %d: %d cells" % (ln, len(cells))
            if all(c == "" for c in cells):
                continue
            vals = {}
            for c, i in cols.items():
                if cells[i] != "":
                    v = float(cells[i])
                    assert math.isfinite(v), "line %d: non-finite %s" % (ln, c)
                    vals[c] = v
            assert "time_s" in vals, "line %d: missing time_s" % ln
            t = vals["time_s"]
            assert t >= last_t, "line %d: time goes backwards" % ln
            last_t = t
            if "power" in vals:
                assert vals["power"] in (0.0, 1.0), "line %d: power %r" % (ln, vals["power"])
                power = int(vals["power"])
                rows["power"].append(power)
                rows["power_t"].append(t)
            if "range_mm" in vals:
                assert power == 1, "line %d: range while the power is 0" % ln
                assert vals["range_mm"] == round(vals["range_mm"]), "line %d: range not whole mm" % ln
                rows["range"].append(vals["range_mm"])
                rows["range_t"].append(t)
                rows["true"].append(vals.get("true_range_mm", np.nan))
            if "case_temp_c" in vals:
                rows["case"].append(vals["case_temp_c"])
                rows["case_t"].append(t)
            if "ambient_c" in vals:
                rows["amb"].append(vals["ambient_c"])
                rows["amb_t"].append(t)
    return {k: np.asarray(v, float) for k, v in rows.items()}


# ------------------------------------------------------------------------------ independent physics
def ambient(amb, t, t_end):
    t = np.asarray(t, float)
    x = amb["base_c"] + amb["drift_c_per_h"] * t / 3600 + amb["wave_c"] * np.sin(
        2 * np.pi * t / (amb["wave_period_h"] * 3600) + amb["wave_phase"])
    ramp = np.clip((t - amb["step_at"] * t_end) / amb["step_ramp_s"] + 0.5, 0, 1)
    return x + amb["step_c"] * ramp


def rk4_network(ph, dt=0.25):
    th = ph["thermal"]
    R1, C1, R2, C2, P = th["R1"], th["C1"], th["R2"], th["C2"], th["P"]
    sched = ph["schedule"]
    t_end = sum(d for _, d in sched)
    n = int(round(t_end / dt))
    tg = np.arange(n + 1) * dt
    edges = np.cumsum([0] + [d for _, d in sched])
    states = [s for s, _ in sched]

    def u_at(t):
        i = np.searchsorted(edges, t, side="right") - 1
        i = min(max(i, 0), len(states) - 1)
        return P if states[i] else 0.0

    ta = ambient(ph["ambient"], tg, t_end)
    tam = ambient(ph["ambient"], tg + dt / 2, t_end)
    tc = np.empty(n + 1)
    tj = np.empty(n + 1)
    c = j = float(ambient(ph["ambient"], 0.0, t_end))

    def f(c, j, u, a):
        dc = j / (R1 * C2) - c * (1 / (R2 * C2) + 1 / (R1 * C2)) + a / (C2 * R2)
        dj = u / C1 + c / (R1 * C1) - j / (R1 * C1)
        return dc, dj
    for k in range(n + 1):
        tc[k], tj[k] = c, j
        if k == n:
            break
        u = u_at(tg[k] + dt / 2)
        a0, am, a1 = ta[k], tam[k], ta[k + 1] if k + 1 <= n else ta[k]
        k1 = f(c, j, u, a0)
        k2 = f(c + dt / 2 * k1[0], j + dt / 2 * k1[1], u, am)
        k3 = f(c + dt / 2 * k2[0], j + dt / 2 * k2[1], u, am)
        k4 = f(c + dt * k3[0], j + dt * k3[1], u, a1)
        c += dt / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        j += dt / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
    return tg, tc, tj


def bias_of(ph, tj):
    b = ph["bias"]
    x = tj - b["t0_c"]
    return b["scale"] * (b["lin"] * x + b["quad"] * x * x
                         + b["amp"] * np.sin(2 * np.pi * x / b["period_c"] + b["phase"]))


def norm_cdf(z):
    """Standard normal cdf, vectorised (Abramowitz & Stegun 7.1.26, |error| < 1.5e-7)."""
    z = np.asarray(z, float)
    x = np.abs(z) / math.sqrt(2)
    t = 1 / (1 + 0.3275911 * x)
    y = 1 - (((((1.061405429 * t - 1.453152027) * t) + 1.421413741) * t - 0.284496736) * t
             + 0.254829592) * t * np.exp(-x * x)
    return 0.5 * (1 + np.sign(z) * y)


def nearest_mode(r, offs):
    offs = np.asarray(offs)
    return np.abs(r[:, None] - offs[None, :]).argmin(axis=1)


# ------------------------------------------------------------------------------ per set
def check_set(suite, truth):
    ph = truth["physics"]
    d = truth["d_mm"]
    data = os.path.join(suite, "data")
    eff_path = os.path.join(data, truth["id"] + ".csv")
    clean_path = os.path.join(data, truth["counterpart"]) if truth["counterpart"] else eff_path
    E = read_csv(eff_path)
    C = read_csv(clean_path) if truth["counterpart"] else E
    out = {"id": truth["id"], "kind": truth["kind"],
           "labels": ["%s:%s" % (e["parameter"], e["covariate"]) for e in truth["effects"]]}
    assert np.all(E["true"] == d) and np.all(C["true"] == d)
    assert np.array_equal(E["range_t"], C["range_t"])
    assert np.array_equal(E["case"], C["case"]) and np.array_equal(E["amb"], C["amb"])
    assert len(E["range"]) == ph["samples"]

    tg, tcg, tjg = rk4_network(ph)
    t = C["range_t"]
    tj = np.interp(t, tg, tjg)
    dtj = np.gradient(tjg, tg)
    rate = np.interp(t, tg, dtj) * 60  # degC/min
    # case sensor vs the re-simulated case node
    tcs = np.interp(C["case_t"], tg, tcg)
    sres = C["case"] - tcs
    sens = ph["sensor"]
    out["sensor_err_mean"] = float(sres.mean())
    out["sensor_err_std"] = float(sres.std())
    out["sensor_err_std_expected"] = math.sqrt(sens["noise_c"] ** 2 + sens["resolution_c"] ** 2 / 12)
    out["junction_range"] = [float(tj.min()), float(tj.max())]
    out["junction_rise_over_ambient_max"] = float(np.max(tjg - ambient(ph["ambient"], tg, tg[-1])))

    # clean residual vs the paper's model
    r = C["range"] - d - bias_of(ph, tj)
    modes = ph["modes"]
    w = np.asarray(modes["weight"])
    mu = np.asarray(modes["offset_mm"])
    sd = np.asarray(modes["std_mm"])
    m_exp = float(w @ mu)
    v_exp = float(w @ (sd ** 2 + mu ** 2) - m_exp ** 2 + 1 / 12)
    out["clean_resid_mean"] = float(r.mean())
    out["clean_resid_mean_expected"] = m_exp
    out["clean_resid_mean_z"] = float((r.mean() - m_exp) / math.sqrt(v_exp / len(r)))
    out["clean_resid_var_ratio"] = float(r.var() / v_exp)
    # exact test of the discrete model: randomised probability integral transform of each range
    # given its bias, P(Y <= y) for Y = round(d + b + w); uniform iid under the model
    x = C["range"] - d - bias_of(ph, tj)
    F_hi = np.zeros_like(x)
    F_lo = np.zeros_like(x)
    for wi, mi, si in zip(w, mu, sd):
        F_hi += wi * norm_cdf((x + 0.5 - mi) / si)
        F_lo += wi * norm_cdf((x - 0.5 - mi) / si)
    v = np.random.default_rng(0).uniform(size=len(x))
    pit = F_lo + v * (F_hi - F_lo)
    h, _ = np.histogram(pit, np.linspace(0, 1, 21))
    pe = len(pit) / 20
    out["clean_pit_chi2_per_dof"] = float(((h - pe) ** 2 / pe).sum() / 19)
    out["clean_pit_lag1_corr"] = float(np.corrcoef(pit[1:], pit[:-1])[0, 1])

    # no trend: residual regressed on covariates, standardised slopes
    t_on = np.zeros_like(t)
    pt, ps = C["power_t"], C["power"]
    on_starts = pt[ps == 1]
    t_on = t - on_starts[np.searchsorted(on_starts, t, side="right") - 1]
    ta = np.interp(t, C["amb_t"], C["amb"])
    covs = {"time": t, "t_on_exp": np.exp(-t_on / 300), "ambient": ta, "rate": np.tanh(rate / 0.1)}
    zs = {}
    for name, x in covs.items():
        X = np.column_stack([np.ones_like(x), (tj - tj.mean()) / tj.std(),
                             ((tj - tj.mean()) / tj.std()) ** 2, (x - x.mean()) / (x.std() + 1e-12)])
        coef, res, *_ = np.linalg.lstsq(X, r, rcond=None)
        s2 = np.sum((r - X @ coef) ** 2) / (len(r) - 4)
        cov = s2 * np.linalg.inv(X.T @ X)
        zs[name] = float(coef[3] / math.sqrt(cov[3, 3]))
    out["clean_trend_z"] = zs
    nm = nearest_mode(r, mu)
    a = (nm[1:] == nm[:-1]).mean()
    pexp = float(np.sum(np.bincount(nm, minlength=len(mu)) ** 2) / len(nm) ** 2)
    out["clean_same_mode_next"] = float(a)
    out["clean_same_mode_next_iid"] = pexp

    if truth["counterpart"]:
        re_ = E["range"] - d - bias_of(ph, tj)
        diff = E["range"] - C["range"]
        out["changed_fraction"] = float(np.mean(diff != 0))
        stats = []
        for eff in truth["effects"]:
            stats.append(effect_stat(eff, t, t_on, tj, rate, ta, r, re_, diff, ph))
        out["effect_stats"] = stats
        if MAE:
            out["paper_mae_clean"] = paper_mae(C["range"], d, tj, ph["modes"])
            out["paper_mae_effect"] = paper_mae(E["range"], d, tj, ph["modes"])
    elif MAE:
        out["paper_mae_clean"] = paper_mae(C["range"], d, tj, ph["modes"])
    return out


def paper_mae(y, d, tj, modes, windows=(200, 400, 800), iters=60):
    """The paper's model trained on these data (Sec. 5: EM, H = a polynomial of the true
    junction temperature of degree 6, as many modes as the clean model), then the window test of Sec. 6 (EM
    for d per window of consecutive ranges).  Returns {window: MAE of d-hat}.  A yardstick of how
    much an effect matters to a user of the paper's model, not an imitation of the detector."""
    y = np.asarray(y, float)
    yt = y - d
    z = (tj - tj.mean()) / (tj.std() + 1e-12)
    H = np.column_stack([z ** n for n in range(1, 7)])
    mu = np.array(modes["offset_mm"], float)
    sd = np.array(modes["std_mm"], float)
    pi = np.array(modes["weight"], float)
    theta = np.zeros(H.shape[1])
    for _ in range(iters):
        e = (yt - H @ theta)[:, None] - mu[None, :]
        lg = np.log(pi) - np.log(sd) - 0.5 * (e / sd) ** 2
        lg -= lg.max(axis=1, keepdims=True)
        g = np.exp(lg)
        g /= g.sum(axis=1, keepdims=True)
        wk = (g / sd ** 2).sum(axis=1)
        tgt = yt - (g * mu / sd ** 2).sum(axis=1) / wk
        theta = np.linalg.solve(H.T @ (H * wk[:, None]), H.T @ (wk * tgt))
        r = yt - H @ theta
        nk = g.sum(axis=0) + 1e-9
        mu = (g * r[:, None]).sum(axis=0) / nk
        sd = np.sqrt((g * (r[:, None] - mu) ** 2).sum(axis=0) / nk + 1.0 / 12)
        pi = nk / nk.sum()
    out = {}
    x = y - H @ theta
    for W in windows:
        n = len(x) // W
        if n < 1:
            continue
        X = x[:n * W].reshape(n, W)
        dh = np.median(X, axis=1) - float(pi @ mu)
        for _ in range(40):
            e = (X - dh[:, None])[:, :, None] - mu
            lg = np.log(pi) - np.log(sd) - 0.5 * (e / sd) ** 2
            lg -= lg.max(axis=2, keepdims=True)
            g = np.exp(lg)
            g /= g.sum(axis=2, keepdims=True)
            wgt = g / sd ** 2
            dh = ((wgt * (X[:, :, None] - mu)).sum(axis=(1, 2))) / wgt.sum(axis=(1, 2))
        out[str(W)] = float(np.mean(np.abs(dh - d)))
    return out


def tertiles(x):
    q1, q2 = np.percentile(x, [33.3, 66.7])
    return x <= q1, x >= q2


def effect_stat(eff, t, t_on, tj, rate, ta, rc, re_, diff, ph):
    """A statistic of the effect measured on the counterpart (clean) and on the effect set."""
    p, c, v = eff["parameter"], eff["covariate"], eff["values"]
    mu = np.asarray(ph["modes"]["offset_mm"])
    res = {"label": p + ":" + c, "strength": round(eff["strength"], 3)}

    def med_mode(r, sel):
        # median of the residual over the ranges nearest the modes, minus the mixture (robust level)
        return float(np.median(r[sel]))
    if p == "bias":
        # exact: effect minus clean is the effect's bias, up to rounding
        if c == "time":
            T = v["record_s"]
            x = t / T
            early, late = x < 0.15, x > 0.85
            f = lambda r: float(np.median(r[late]) - np.median(r[early]))
            res["stat"] = "median resid, last 15% minus first 15% of the record (mm)"
            res["expected"] = v["total_mm"]
        elif c == "time_since_power_on":
            early = t_on < min(v["tau_s"], 300)
            late = t_on > 3 * v["tau_s"] + 600
            f = lambda r: float(np.mean(r[early]) - np.mean(r[late]))
            res["stat"] = "mean resid, t_on < min(tau,5min) minus t_on > 3tau+10min"
            res["expected_order"] = v["amplitude_mm"]
        elif c == "heating_rate":
            hot = rate > 2 * v["rate_scale_c_per_min"]
            flat = np.abs(rate) < 0.2 * v["rate_scale_c_per_min"]
            f = lambda r: float(np.mean(r[hot]) - np.mean(r[flat])) if hot.any() and flat.any() else float("nan")
            res["stat"] = "mean resid, rate>2*scale minus |rate|<0.2*scale"
            res["expected_order"] = v["amplitude_mm"]
        elif c == "ambient":
            def f(r):
                X = np.column_stack([np.ones_like(ta), tj, tj ** 2, ta])
                return float(np.linalg.lstsq(X, r, rcond=None)[0][3])
            res["stat"] = "slope of resid on ambient given tj (mm/degC)"
            res["expected"] = v["mm_per_c"]
        else:
            raise ValueError(c)
        res["clean"], res["effect"] = f(rc), f(re_)
    elif p == "thermal_state":
        def f(r):
            # resid regressed on the lagged-node deviation re-computed from the truth's tau
            tau = v["tau_s"]
            dt = np.diff(t, prepend=t[0])
            th = np.empty_like(tj)
            h = tj[0]
            for i in range(len(tj)):
                a = math.exp(-dt[i] / tau) if dt[i] < 50 * tau else 0.0
                h = a * h + (1 - a) * tj[i]
                th[i] = h
            # note: gaps (power off) are not integrated here: only a rough regressor
            X = np.column_stack([np.ones_like(tj), tj, tj ** 2, th - tj])
            return float(np.linalg.lstsq(X, r, rcond=None)[0][3])
        res["stat"] = "slope of resid on (lag(tj) - tj) given tj, rough (gaps not integrated)"
        res["expected_order"] = v["mm_per_c"]
        res["clean"], res["effect"] = f(rc), f(re_)
    elif p == "mode_offset":
        j = v["mode"]
        cold, hot = tertiles(tj)

        def f(r):
            nm = nearest_mode(r, mu)
            sel = nm == j
            return med_mode(r, sel & hot) - med_mode(r, sel & cold)
        res["stat"] = "median resid of ranges nearest mode j, hot minus cold tertile"
        res["expected_order"] = v["mm_per_c"] * (np.median(tj[tertiles(tj)[1]]) - np.median(tj[tertiles(tj)[0]]))
        res["clean"], res["effect"] = f(rc), f(re_)
    elif p == "spread":
        cold, hot = tertiles(tj)

        def f(r):
            nm = nearest_mode(r, mu)
            # MAD around the mode offset, pooled over modes, hot/cold
            dev = np.abs(r - mu[nm])
            return float(np.median(dev[hot]) / np.median(dev[cold]))
        res["stat"] = "median |resid - nearest mode|, hot / cold tertile"
        res["expected_order"] = v["ratio_hot_over_cold"] ** (2 / 3)
        res["clean"], res["effect"] = f(rc), f(re_)
    elif p == "weights":
        j = v["mode"]
        if c == "junction_temperature":
            a, b = tertiles(tj)
            res["stat"] = "share of ranges nearest mode j, hot minus cold tertile"
            res["expected_order"] = v["weight_hot"] - v["weight_cold"]
            a, b = b, a
        else:
            a = t_on < v["tau_s"] / 2
            b = t_on > 3 * v["tau_s"] + 600
            res["stat"] = "share of ranges nearest mode j, t_on<tau/2 minus t_on>3tau+10min"
            res["expected_order"] = v["weight_at_power_on"] - v["weight_late"]

        def f(r):
            nm = nearest_mode(r, mu)
            return float(np.mean(nm[a] == j) - np.mean(nm[b] == j))
        res["clean"], res["effect"] = f(rc), f(re_)
    elif p == "markov":
        def f(r):
            nm = nearest_mode(r, mu)
            return float(np.mean(nm[1:] == nm[:-1]))
        res["stat"] = "P(same nearest mode next)"
        res["expected_order"] = v["p_same_mode_next"]
        res["clean"], res["effect"] = f(rc), f(re_)
    elif p == "extra_mode":
        off = v["offset_mm"]
        f = lambda r: float(np.mean(np.abs(r - off) < min(2 * v["std_mm"], v["gap_mm"] / 2)))
        res["stat"] = "share of resid within min(2sd, gap/2) of the extra offset"
        res["expected_order"] = v["weight"]
        res["clean"], res["effect"] = f(rc), f(re_)
    elif p == "outliers":
        f = lambda r: float(np.mean(np.abs(r) > 60))
        res["stat"] = "share |resid| > 60 mm"
        res["expected_order"] = v["fraction"]
        res["clean"], res["effect"] = f(rc), f(re_)
    return res


MAE = False


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--suite", required=True)
    ap.add_argument("--ids", default=None)
    ap.add_argument("--json", default=None)
    ap.add_argument("--mae", action="store_true",
                    help="also train the paper's model on each set and its counterpart and "
                         "compare the window MAE of d (a yardstick of an effect's impact)")
    a = ap.parse_args()
    global MAE
    MAE = a.mae
    paths = sorted(glob.glob(os.path.join(a.suite, "truth", "*.json")))
    if a.ids:
        want = set(a.ids.split(","))
        paths = [p for p in paths if os.path.basename(p)[:-5] in want]
    allout = []
    for p in paths:
        with open(p) as f:
            truth = json.load(f)
        try:
            o = check_set(a.suite, truth)
        except AssertionError as ex:
            print("%s: FORMAT/CONSISTENCY FAILURE: %s" % (truth["id"], ex))
            allout.append({"id": truth["id"], "error": str(ex)})
            continue
        allout.append(o)
        print("%s %-6s %-40s sens %+.3f/%.3f(exp %.3f) tj %.1f-%.1f rise %.1f | clean: mean z %+.1f "
              "var %.3f pit chi2/dof %.2f lag1 %+.3f trend z %s same-next %.3f/%.3f" % (
                  o["id"], o["kind"], ",".join(o["labels"]) or "-", o["sensor_err_mean"],
                  o["sensor_err_std"], o["sensor_err_std_expected"], *o["junction_range"],
                  o["junction_rise_over_ambient_max"],
                  o["clean_resid_mean_z"], o["clean_resid_var_ratio"], o["clean_pit_chi2_per_dof"], o["clean_pit_lag1_corr"],
                  " ".join("%s=%+.1f" % kv for kv in o["clean_trend_z"].items()),
                  o["clean_same_mode_next"], o["clean_same_mode_next_iid"]))
        for s in o.get("effect_stats", []):
            exp = s.get("expected", s.get("expected_order"))
            print("    %-34s s=%.2f  %s: clean %+.4f  effect %+.4f  (truth %s %+.4f)" % (
                s["label"], s["strength"], s["stat"], s["clean"], s["effect"],
                "=" if "expected" in s else "~", exp))
        if "paper_mae_effect" in o:
            print("    paper-model window MAE (mm) clean %s | effect %s" % (
                " ".join("%s:%.3f" % kv for kv in o["paper_mae_clean"].items()),
                " ".join("%s:%.3f" % kv for kv in o["paper_mae_effect"].items())))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(allout, f, indent=1)


if __name__ == "__main__":
    main()
