#!/usr/bin/env python3
"""Self-check of the field bench: generator output, truth, and scorer.

usage: selfcheck.py [--seed N] [--keep]

Generates a small suite (2 cases) in bench/field/.selfcheck/, checks every CSV against
data-format.md, checks truth against the files, then feeds score.py a perfect system (made from
truth), a naive one and malformed files. Exit 0 when every check passes.
"""
import os
import sys

try:
    import numpy as np  # noqa: F401  (needed to import generate for the CRB check)
except ImportError:
    if os.path.exists("/usr/bin/python3") and os.path.realpath(sys.executable) != "/usr/bin/python3":
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    sys.exit("selfcheck.py: numpy is required")

import argparse
import csv
import hashlib
import json
import math
import re
import shutil
import subprocess
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True
import generate  # noqa: E402

NUM_RE = re.compile(r"^[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?$")
META_RE = re.compile(r"^# [A-Za-z0-9_ -]+: .*$")
FIELD_COLS = ["time_s", "beam", "range_mm", "case_temp_c", "power", "ambient_c"]
REF_COLS = FIELD_COLS + ["true_range_mm"]

FAILS = []
NCHECK = [0]


def check(cond, msg):
    NCHECK[0] += 1
    if not cond:
        FAILS.append(msg)
        print("  FAIL:", msg)
    return cond


# ----------------------------------------------------------------------------- format
def read_interchange(path, expect_cols):
    """Validate one file against data-format.md; return range rows and per-file facts."""
    errs = []
    ranges = []        # (line, t, beam, range, ref-or-None)
    temps = 0
    powers = []
    with open(path, newline="") as f:
        lines = f.read().split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    i = 0
    meta = {}
    while i < len(lines) and lines[i].startswith("#"):
        if not META_RE.match(lines[i]):
            errs.append("%s:%d: metadata line not '# key: value'" % (path, i + 1))
        k, _, v = lines[i][2:].partition(": ")
        meta[k] = v
        i += 1
    header = lines[i].split(",")
    if header != expect_cols:
        errs.append("%s:%d: header %s, expected %s" % (path, i + 1, header, expect_cols))
        return errs, ranges, {}
    col = {c: k for k, c in enumerate(header)}
    last_t = -1.0
    power = 1
    ref_now = {}
    for ln in range(i + 1, len(lines)):
        row = lines[ln].split(",")
        where = "%s:%d" % (path, ln + 1)
        if len(row) != len(header):
            errs.append("%s: %d fields" % (where, len(row)))
            continue
        if all(c == "" for c in row):
            continue
        vals = {}
        for c, k in col.items():
            s = row[k]
            if s == "":
                continue
            if not NUM_RE.match(s):
                errs.append("%s: column %s: %r not a finite number" % (where, c, s))
                continue
            vals[c] = float(s)
        if "time_s" not in vals:
            errs.append("%s: missing time_s" % where)
            continue
        t = vals["time_s"]
        if t < last_t:
            errs.append("%s: time goes backwards" % where)
        last_t = t
        if "power" in vals:
            if vals["power"] not in (0.0, 1.0):
                errs.append("%s: power %r" % (where, row[col["power"]]))
            power = int(vals["power"])
            powers.append((t, power))
        if "case_temp_c" in vals:
            temps += 1
        if "true_range_mm" in vals:
            if "range_mm" not in vals:
                errs.append("%s: true_range_mm without range" % where)
        if "range_mm" in vals:
            if power == 0:
                errs.append("%s: range_mm while power is 0" % where)
            b = vals.get("beam", 0.0)
            if b != int(b) or b < 0:
                errs.append("%s: beam %r" % (where, b))
            r = vals["range_mm"]
            if r != int(r) or not (0 <= r <= 8183):
                errs.append("%s: range %r" % (where, r))
            if "true_range_mm" in vals:
                ref_now[int(b)] = vals["true_range_mm"]
            ranges.append((ln + 1, t, int(b), int(r), vals.get("true_range_mm")))
        elif "beam" in vals:
            errs.append("%s: beam without range" % where)
    facts = {"meta": meta, "temps": temps, "powers": powers, "end_t": last_t}
    return errs, ranges, facts


def sha(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


# ----------------------------------------------------------------------------- files
def check_case(suite, name, size="small"):
    print("case", name)
    cdir = os.path.join(suite, "cases", name)
    tj = json.load(open(os.path.join(suite, "truth", name + ".json")))
    band = tj["bench_band_c"]
    cfg = generate.SIZES[size]
    # bench
    errs, br, bf = read_interchange(os.path.join(cdir, "bench.csv"), REF_COLS)
    check(not errs, "bench.csv format: %s" % errs[:3])
    beams = sorted(set(b for _, _, b, _, _ in br))
    check(1 <= len(beams) <= 3, "bench beams %s" % beams)
    check(all(ref is not None for _, _, _, _, ref in br), "bench: every range has its reference")
    dtrue = {x["beam"]: x["d_mm"] for x in tj["bench"]["beams"]}
    check(all(abs(ref - dtrue[b]) < 0.051 for _, _, b, _, ref in br), "bench references equal truth d")
    hrs = bf["end_t"] / 3600
    check(cfg["bench_hours"][0] * 0.95 <= hrs <= cfg["bench_hours"][1] * 1.05, "bench duration %.2f h" % hrs)
    check(any(p == 0 for _, p in bf["powers"]), "bench has power cycles")
    check(bf["temps"] > 100, "bench has case temperature rows")
    check(band[1] - band[0] > 1.0, "bench band has width (%.2f K)" % (band[1] - band[0]))
    # field days
    nd = len(tj["field_days"])
    check(1 <= nd <= 3, "field days %d" % nd)
    B = tj["scene"]["beams"]
    check(cfg["beams"][0] <= B <= cfg["beams"][1], "beams %d" % B)
    for k in range(1, 4):
        p = os.path.join(cdir, "field-%d.csv" % k)
        check(os.path.exists(p) == (k <= nd), "field-%d.csv exists iff drawn" % k)
        if k > nd:
            continue
        errs, fr, ff = read_interchange(p, FIELD_COLS)
        check(not errs, "field-%d format: %s" % (k, errs[:3]))
        per_t = {}
        for _, t, b, _, _ in fr:
            per_t.setdefault(t, []).append(b)
        check(all(v == list(range(B)) for v in per_t.values()), "field-%d: one range per beam per scan" % k)
        h = ff["end_t"] / 3600
        check(cfg["day_hours"][0] * 0.95 <= h <= cfg["day_hours"][1] * 1.01, "field-%d duration %.2f h" % (k, h))
        d = tj["field_days"][k - 1]
        check(0.003 <= d["occluded_share"] <= 0.10, "field-%d occluded share %.3f" % (k, d["occluded_share"]))
        check(d["gross_share"] <= 0.006, "field-%d gross share %.4f" % (k, d["gross_share"]))
        check(d["clipped"] == 0, "field-%d no clipped ranges" % k)
    ex = tj["field_junction_c"][1] - band[1]
    check(4.0 <= ex <= 21.0, "field junction exceeds the bench band by %.1f K (5-20 drawn)" % ex)
    # test day
    errs, tr, tf = read_interchange(os.path.join(cdir, "test.csv"), FIELD_COLS)
    check(not errs, "test.csv format: %s" % errs[:3])
    errs, rr, rf = read_interchange(os.path.join(cdir, "test-with-reference.csv"), REF_COLS)
    check(not errs, "test-with-reference.csv format: %s" % errs[:3])
    a = [l.split(",") for l in open(os.path.join(cdir, "test.csv")).read().splitlines() if not l.startswith("#")]
    b = [l.split(",") for l in open(os.path.join(cdir, "test-with-reference.csv")).read().splitlines()
         if not l.startswith("#")]
    check(len(a) == len(b) and all(x == y[:-1] for x, y in zip(a[1:], b[1:])),
          "test-with-reference.csv = test.csv + a true_range_mm column")
    ex = tj["test_junction_c"][1] - band[1]
    check(4.6 <= ex <= 20.5, "test junction exceeds the bench band by %.1f K" % ex)
    # (a power break on the test day may cool the junction a little below what was seen)
    lo = min(band[0], tj["field_junction_c"][0]) - 2.5
    hi = tj["field_junction_c"][1] + 0.5
    check(lo <= tj["test_junction_c"][0] and tj["test_junction_c"][1] <= hi,
          "test junction %.1f-%.1f C within what bench and field saw (%.1f-%.1f C)"
          % (tj["test_junction_c"][0], tj["test_junction_c"][1], lo + 2.5, hi - 0.5))
    # per-row truth
    rows = list(csv.DictReader(open(os.path.join(suite, "truth", name + "-test.csv"))))
    check(len(rows) == len(tr), "truth rows %d = test ranges %d" % (len(rows), len(tr)))
    ok_align = all(abs(float(r["time_s"]) - t) < 1e-6 and int(r["beam"]) == bb and int(r["range_mm"]) == y
                   for r, (_, t, bb, y, _) in zip(rows, tr))
    check(ok_align, "truth rows aligned with test.csv (time, beam, range)")
    mu = tj["modes"]["offset_mm"]
    sd = tj["modes"]["std_mm"]
    bias = tj["bias"]
    maxdb = 0.0
    res = {m: [] for m in range(len(mu))}
    inside = beyond = 0
    bad_occ = bad_gross = bad_ref = 0
    n_occ = n_gross = 0
    for r, (_, _, _, _, ref) in zip(rows, rr):
        tjn = float(r["junction_c"])
        x = tjn - bias["tref_c"]
        bz = (bias["b0_mm"] + bias["lin_mm_per_k"] * x + bias["quad_mm_per_k2"] * x * x
              + bias["amp_mm"] * math.sin(2 * math.pi * x / bias["period_k"] + bias["phase_rad"]))
        maxdb = max(maxdb, abs(bz - float(r["true_bias_mm"])))
        if band[0] <= tjn <= band[1]:
            inside += 1
        else:
            beyond += 1
        d = float(r["true_distance_mm"])
        y = int(r["range_mm"])
        occ, gro, m = int(r["occluded"]), int(r["gross"]), int(r["mode"])
        still = not occ and not gro
        if still:
            res[m].append(y - d - float(r["true_bias_mm"]) - mu[m])
            if ref is None or abs(ref - d) > 0.051:
                bad_ref += 1
        elif ref is not None:
            bad_ref += 1
        if gro:
            n_gross += 1
            if not (y in (0, 8183) or abs(y - d - bz) >= 299):
                bad_gross += 1
        elif occ:
            n_occ += 1
            if not (y < d - 250 + bz + mu[m] + 6 * sd[m] + 1):
                bad_occ += 1
    check(maxdb < 2e-3, "true_bias_mm = bias(junction_c) from the truth parameters (max diff %.2g)" % maxdb)
    check(bad_ref == 0, "references set exactly on still rows (%d bad)" % bad_ref)
    check(bad_occ == 0 and n_occ > 0, "occluded ranges in front of the surface (%d of %d bad)" % (bad_occ, n_occ))
    check(bad_gross == 0 and n_gross > 0, "gross ranges are gross (%d of %d bad)" % (bad_gross, n_gross))
    for m, v in res.items():
        if len(v) < 200:
            continue
        mean = sum(v) / len(v)
        sdv = math.sqrt(sum((x - mean) ** 2 for x in v) / (len(v) - 1))
        exp = math.sqrt(sd[m] ** 2 + 1 / 12)
        check(abs(mean) < 5 * exp / math.sqrt(len(v)) + 0.05, "mode %d residual mean %.3f" % (m, mean))
        check(abs(sdv / exp - 1) < 0.06, "mode %d residual std %.3f vs %.3f" % (m, sdv, exp))
    check(inside > 0.05 * len(rows) and beyond > 0.05 * len(rows),
          "test day covers inside (%d) and beyond (%d) the bench band" % (inside, beyond))
    w = tj["modes"]["weight"]
    check(abs(sum(wi * mi for wi, mi in zip(w, mu))) < 1e-9 and abs(sum(w) - 1) < 1e-9, "mode weights/offsets")
    c = tj["crb"]
    check(c["fisher_iid_mixture_per_range"] <= c["fisher_mode_known_per_range"], "iid Fisher <= mode-known")
    for N in ("200", "400", "800"):
        check(c["crb_mae_mm"][N] <= c["oracle_mean_mae_mm_expected"][N] * 1.0001 or tj["modes"]["switching"] != "iid",
              "CRB MAE <= plain-mean MAE (N=%s)" % N)
    return rows, tj


# ----------------------------------------------------------------------------- systems
def write_system(path, rows, kind):
    """kind: perfect (from truth) or naive (compensated = range, nothing set apart)."""
    hist = {}
    with open(path, "w") as f:
        f.write("# system: %s\n" % kind)
        f.write("time_s,beam,range_mm,compensated_mm,window_mm,window_std_mm,still,flags\n")
        for r in rows:
            y = int(r["range_mm"])
            out = r["occluded"] == "1" or r["gross"] == "1"
            if kind == "perfect":
                comp = y - float(r["true_bias_mm"])
                key = (r["beam"], r["episode"])
                still = 0 if out else 1
            else:
                comp = float(y)
                key = (r["beam"],)
                still = 1
            h = hist.setdefault(key, [])
            if still:
                h.append(comp)
                if len(h) > 400:
                    h.pop(0)
            if h:
                m = sum(h) / len(h)
                s = math.sqrt(sum((x - m) ** 2 for x in h) / max(1, len(h) - 1) / len(h)) if len(h) > 1 else 10.0
                wm, ws = "%.4f" % m, "%.4f" % s
            else:
                wm = ws = ""
            f.write("%s,%s,%d,%.4f,%s,%s,%d,%s\n" % (r["time_s"], r["beam"], y, comp, wm, ws, still,
                                                     "" if still else "outlier"))


def run_score(suite, name, comp, js=None):
    cmd = [sys.executable, os.path.join(HERE, "score.py"), "--suite", suite, "--case", name, "--compensated", comp]
    if js:
        cmd += ["--json", js]
    p = subprocess.run(cmd, capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def mutate(src, dst, fn):
    lines = open(src).read().splitlines()
    lines = fn(lines)
    open(dst, "w").write("\n".join(lines) + "\n")


def check_scorer(suite, name, rows, tj, work):
    print("scorer on", name)
    perf = os.path.join(work, name + "-perfect.csv")
    write_system(perf, rows, "perfect")
    rc, out, err = run_score(suite, name, perf, os.path.join(work, name + "-perfect.json"))
    check(rc == 0, "perfect system passes every goal (rc %d, %s)" % (rc, err.strip()[:200]))
    js = json.load(open(os.path.join(work, name + "-perfect.json")))
    nwin = 0
    for c in ("inside", "beyond", "all"):
        for N, e in js["results"][c]["windows"].items():
            if e["windows"]:
                nwin += e["windows"]
                check(e["ratio_system_oracle"] is not None and abs(e["ratio_system_oracle"] - 1.0) < 1e-9,
                      "perfect ratio %s N=%s = %r" % (c, N, e["ratio_system_oracle"]))
        sa = js["results"][c]["set_apart"]
        check(sa["outlier_set_apart_share"] in (None, 1.0) and sa["still_set_apart_share"] in (None, 0.0),
              "perfect set-apart shares %s" % c)
    check(js["results"]["inside"]["windows"]["800"]["windows"] >= 5
          and js["results"]["beyond"]["windows"]["800"]["windows"] >= 5,
          "at least 5 windows of 800 inside and beyond the band")
    check(js["counts"]["nan_inf"] == 0 and nwin > 0, "perfect: no NaN, windows scored")
    e = js["results"]["all"]["windows"]["200"]
    expo = tj["crb"]["oracle_mean_mae_mm_expected"]["200"]
    # windows of different beams share the lasing-mode chain: count them as beams-fold dependent when sticky
    n_eff = e["windows"] / (1 if tj["modes"]["switching"] == "iid" else tj["scene"]["beams"])
    tol = max(0.1, 3.5 * math.sqrt(math.pi / 2 - 1) / math.sqrt(max(n_eff, 1)))
    check(abs(e["mae_oracle_mm"] / expo - 1) <= tol,
          "oracle MAE N=200 %.3f vs expected %.3f (%d windows, tolerance %.0f%%)"
          % (e["mae_oracle_mm"], expo, e["windows"], 100 * tol))
    check(e["mae_oracle_mm"] >= 0.9 * e["crb_mae_mm"], "oracle MAE not below the CRB")
    naive = os.path.join(work, name + "-naive.csv")
    write_system(naive, rows, "naive")
    rc, out, err = run_score(suite, name, naive, os.path.join(work, name + "-naive.json"))
    js = json.load(open(os.path.join(work, name + "-naive.json")))
    rat = [e["ratio_system_oracle"] for c in ("inside", "beyond")
           for e in js["results"][c]["windows"].values() if e["ratio_system_oracle"] is not None]
    check(rc == 1 and rat and max(rat) > 3.0 and min(rat) > 1.0,
          "naive system fails (rc %d, ratios %s)" % (rc, ["%.1f" % r for r in rat]))
    check(js["results"]["all"]["set_apart"]["outlier_set_apart_share"] == 0.0, "naive sets nothing apart")
    # malformed
    cases = {
        "bad-number": (lambda L: L[:12] + [",".join(L[12].split(",")[:3] + ["12.3x"] + L[12].split(",")[4:])] + L[13:],
                       "compensated_mm"),
        "truncated": (lambda L: L[:-5], "file ends after"),
        "no-still-col": (lambda L: [l.rsplit(",", 2)[0] + "," + l.rsplit(",", 1)[1] if not l.startswith("#") else l
                                    for l in L], "still"),
        "still-2": (lambda L: L[:20] + [",".join(L[20].split(",")[:6] + ["2"] + L[20].split(",")[7:])] + L[21:], "still"),
        "swapped": (lambda L: L[:5] + [L[6], L[5]] + L[7:], "beam"),
        "short-row": (lambda L: L[:30] + [L[30].rsplit(",", 1)[0]] + L[31:], "fields"),
        "bad-time": (lambda L: L[:40] + ["abc" + L[40]] + L[41:], "time_s"),
    }
    for tag, (fn, word) in cases.items():
        p = os.path.join(work, name + "-" + tag + ".csv")
        mutate(perf, p, fn)
        rc, out, err = run_score(suite, name, p)
        check(rc == 2 and "Traceback" not in err and word in err and re.search(r":\d+", err),
              "malformed %s -> exit 2 naming line and %s (rc %d: %s)" % (tag, word, rc, err.strip()[:160]))
    p = os.path.join(work, name + "-nan.csv")
    mutate(perf, p, lambda L: L[:50] + [",".join(L[50].split(",")[:3] + ["nan"] + L[50].split(",")[4:])] + L[51:])
    rc, out, err = run_score(suite, name, p, p + ".json")
    js = json.load(open(p + ".json"))
    check(rc == 1 and js["counts"]["nan_inf"] == 1, "a NaN cell is counted, not a crash (rc %d)" % rc)


def check_crb():
    print("CRB computation")
    rng = generate.np.random.default_rng(5)
    modes = {"offset_mm": [-3.0, 4.0], "std_mm": [2.0, 2.5], "weight": [4 / 7, 3 / 7],
             "switching": "markov", "fresh_prob_per_scan": 1.0}
    c = generate.crb_figures(modes, rng, reps=3000)
    f = c["fisher_window"]["400"] / 400
    check(abs(f / c["fisher_iid_mixture_per_range"] - 1) < 0.08,
          "HMM Monte Carlo with s=1 equals the iid Fisher (%.4f vs %.4f)" % (f, c["fisher_iid_mixture_per_range"]))
    modes["fresh_prob_per_scan"] = 0.1
    c = generate.crb_figures(modes, rng, reps=1500)
    f = c["fisher_per_range_asymptotic"]
    check(c["fisher_iid_mixture_per_range"] * 0.95 < f < c["fisher_mode_known_per_range"] * 1.02,
          "sticky modes: iid %.4f <= HMM %.4f <= mode known %.4f" % (
              c["fisher_iid_mixture_per_range"], f, c["fisher_mode_known_per_range"]))


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--seed", type=int, default=20150)
    ap.add_argument("--keep", action="store_true")
    a = ap.parse_args()
    work = os.path.join(HERE, ".selfcheck")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    suite = os.path.join(work, "suite")
    t0 = time.time()
    p = subprocess.run([sys.executable, os.path.join(HERE, "generate.py"), "--out", suite, "--seed", str(a.seed),
                        "--size", "small", "--count", "2"], capture_output=True, text=True)
    dt = time.time() - t0
    print(p.stdout.strip())
    check(p.returncode == 0, "generate.py ran (%s)" % p.stderr.strip()[-300:])
    size = sum(os.path.getsize(os.path.join(dp, f)) for dp, _, fs in os.walk(suite) for f in fs)
    print("small draw of 2 cases: %.1f s, %.1f MB" % (dt, size / 1e6))
    check(dt < 30, "small --count 2 in < 30 s (%.1f s)" % dt)
    check(size < 30e6, "small --count 2 < 30 MB (%.1f MB)" % (size / 1e6))
    p2 = subprocess.run([sys.executable, os.path.join(HERE, "generate.py"), "--out", suite + "-again", "--seed",
                         str(a.seed), "--size", "small", "--count", "1"], capture_output=True, text=True)
    same = all(sha(os.path.join(suite, "cases", "case-01", f)) == sha(os.path.join(suite + "-again", "cases", "case-01", f))
               for f in ("bench.csv", "test.csv"))
    check(p2.returncode == 0 and same, "same seed -> same files")
    for name in json.load(open(os.path.join(suite, "suite.json")))["cases"]:
        rows, tj = check_case(suite, name)
        check_scorer(suite, name, rows, tj, work)
    check_crb()
    print("\n%d checks, %d failed" % (NCHECK[0], len(FAILS)))
    if not a.keep and not FAILS:
        shutil.rmtree(work, ignore_errors=True)
    sys.exit(1 if FAILS else 0)


if __name__ == "__main__":
    main()
