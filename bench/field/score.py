#!/usr/bin/env python3
"""Score a system's compensated output for the test day of one field case.

usage: score.py --suite DIR --case NAME --compensated OUT.csv [--json S.json]

The only program that reads DIR/truth/. Standard library only.
Exit status: 0 scored and every goal met, 1 scored and some goal missed, 2 malformed input.
"""
import argparse
import csv
import json
import math
import os
import re
import sys
from array import array

WINDOWS = (200, 400, 800)
REQUIRED = ("time_s", "beam", "range_mm", "compensated_mm", "window_mm", "window_std_mm", "still", "flags")
GOAL_RATIO = 1.25          # MAE(system window mean) / MAE(oracle window mean)
GOAL_OUTLIER_APART = 0.99  # share of occluded/gross ranges with still = 0
GOAL_STILL_APART = 0.02    # share of truly still ranges with still = 0
GOAL_MISSING_WINDOWS = 0.05
MIN_WINDOWS_FOR_GOAL = 5
MIN_PRESENT = 0.5          # a window's mean needs at least this share of present cells
AFTER_STEP_S = 300.0
NUM_RE = re.compile(r"^[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?$")
NONFINITE = {"nan", "+nan", "-nan", "inf", "+inf", "-inf", "infinity", "+infinity", "-infinity"}
NAN = float("nan")


class Malformed(Exception):
    pass


def fail(msg):
    sys.stderr.write("score.py: malformed input: %s\n" % msg)
    sys.exit(2)


def num(cell, where, counts=None):
    """'' -> None; finite number -> float; nan/inf -> counted, None; else Malformed."""
    s = cell.strip()
    if s == "":
        return None
    if NUM_RE.match(s):
        return float(s)
    if s.lower() in NONFINITE:
        if counts is not None:
            counts["nan_inf"] += 1
            return None
        raise Malformed("%s: %r is not a finite number" % (where, cell))
    raise Malformed("%s: %r is not a number" % (where, cell))


def read_truth(suite, case):
    jpath = os.path.join(suite, "truth", case + ".json")
    cpath = os.path.join(suite, "truth", case + "-test.csv")
    for p in (jpath, cpath):
        if not os.path.isfile(p):
            raise Malformed("%s: no such file (is --suite/--case right?)" % p)
    try:
        with open(jpath) as f:
            tj = json.load(f)
    except ValueError as e:
        raise Malformed("%s: not valid JSON (%s)" % (jpath, e))
    cols = ("time_s", "beam", "range_mm", "true_distance_mm", "episode", "occluded", "gross",
            "true_bias_mm", "junction_c")
    t = {c: array("d") for c in cols}
    with open(cpath, newline="") as f:
        rd = csv.reader(f)
        head = next(rd, None)
        if head is None:
            raise Malformed("%s: empty" % cpath)
        idx = {}
        for c in cols:
            if c not in head:
                raise Malformed("%s:1: column %s missing" % (cpath, c))
            idx[c] = head.index(c)
        for ln, row in enumerate(rd, start=2):
            if len(row) != len(head):
                raise Malformed("%s:%d: %d fields, header has %d" % (cpath, ln, len(row), len(head)))
            for c in cols:
                v = num(row[idx[c]], "%s:%d: column %s" % (cpath, ln, c))
                if v is None:
                    raise Malformed("%s:%d: column %s empty" % (cpath, ln, c))
                t[c].append(v)
    return tj, t, cpath


def read_output(path, truth, tpath):
    if not os.path.isfile(path):
        raise Malformed("%s: no such file" % path)
    n = len(truth["time_s"])
    out = {"comp": array("d"), "win": array("d"), "wstd": array("d"), "still": array("b")}
    counts = {"nan_inf": 0, "missing_compensated_mm": 0, "missing_window_mm": 0,
              "missing_window_std_mm": 0, "missing_still": 0}
    with open(path, newline="") as f:
        ln = 0
        line = f.readline()
        while line and (line.startswith("#") or line.strip() == ""):
            ln += 1
            line = f.readline()
        if not line:
            raise Malformed("%s: no header row" % path)
        ln += 1
        try:
            head = next(csv.reader([line]))
        except (csv.Error, StopIteration) as e:
            raise Malformed("%s:%d: %s" % (path, ln, e))
        head = [h.strip().lstrip("\ufeff") for h in head]
        for c in REQUIRED:
            if c not in head:
                raise Malformed("%s:%d: required column %s missing from the header" % (path, ln, c))
        ix = {c: head.index(c) for c in REQUIRED}
        k = 0
        rdr = csv.reader(f)
        lineno = ln
        while True:
            try:
                row = next(rdr)
            except StopIteration:
                break
            except csv.Error as e:
                raise Malformed("%s:%d: %s" % (path, ln + rdr.line_num, e))
            lineno = ln + rdr.line_num
            if len(row) == 0 or all(c.strip() == "" for c in row):
                continue                               # a row with no value at all is ignored
            if len(row) != len(head):
                raise Malformed("%s:%d: %d fields, header has %d" % (path, lineno, len(row), len(head)))
            if k >= n:
                raise Malformed("%s:%d: more rows than ranges in the test day (%d)" % (path, lineno, n))
            w = lambda c: "%s:%d: column %s" % (path, lineno, c)
            ts = num(row[ix["time_s"]], w("time_s"))
            if ts is None:
                raise Malformed("%s empty (required)" % w("time_s"))
            if abs(ts - truth["time_s"][k]) > 0.0015:
                raise Malformed("%s: %s but range %d of test.csv is at %.3f s (one row per range, same order)"
                                % (w("time_s"), row[ix["time_s"]], k + 1, truth["time_s"][k]))
            b = num(row[ix["beam"]], w("beam"))
            if b is None or b != truth["beam"][k]:
                raise Malformed("%s: %r but range %d of test.csv is beam %d"
                                % (w("beam"), row[ix["beam"]], k + 1, truth["beam"][k]))
            r = num(row[ix["range_mm"]], w("range_mm"))
            if r is None or abs(r - truth["range_mm"][k]) > 0.5:
                raise Malformed("%s: %r but range %d of test.csv is %d"
                                % (w("range_mm"), row[ix["range_mm"]], k + 1, truth["range_mm"][k]))
            for c, key in (("compensated_mm", "comp"), ("window_mm", "win"), ("window_std_mm", "wstd")):
                v = num(row[ix[c]], w(c), counts)
                if v is None:
                    counts["missing_" + c] += 1
                    v = NAN
                out[key].append(v)
            s = num(row[ix["still"]], w("still"), counts)
            if s is None:
                counts["missing_still"] += 1
                out["still"].append(-1)
            elif s in (0.0, 1.0):
                out["still"].append(int(s))
            else:
                raise Malformed("%s: %r (0, 1 or empty)" % (w("still"), row[ix["still"]]))
            k += 1
    if k != n:
        raise Malformed("%s:%d: file ends after %d ranges; test.csv has %d ranges (one row per range)"
                        % (path, lineno, k, n))
    return out, counts, head


def mean(xs):
    return sum(xs) / len(xs) if xs else None


def score(tj, t, out, counts):
    band = tj["bench_band_c"]
    crb = tj["crb"]["crb_mae_mm"]
    i_asym = tj["crb"]["fisher_per_range_asymptotic"]
    n = len(t["time_s"])
    inside = [band[0] <= x <= band[1] for x in t["junction_c"]]
    outlier = [t["occluded"][i] > 0.5 or t["gross"][i] > 0.5 for i in range(n)]
    # still sequences per (beam, episode), in row order
    seqs = {}
    for i in range(n):
        if not outlier[i]:
            seqs.setdefault((int(t["beam"][i]), int(t["episode"][i])), []).append(i)
    classes = ("inside", "beyond", "all")
    win = {c: {N: [] for N in WINDOWS} for c in classes}
    for key, seq in seqs.items():
        for N in WINDOWS:
            for w0 in range(0, len(seq) - N + 1, N):
                rows = seq[w0:w0 + N]
                d = t["true_distance_mm"][rows[0]]
                orc = abs(mean([t["range_mm"][i] - t["true_bias_mm"][i] for i in rows]) - d)
                comp = [out["comp"][i] for i in rows if out["comp"][i] == out["comp"][i]]
                sys_err = abs(mean(comp) - d) if len(comp) >= MIN_PRESENT * N else None
                last = rows[-1]
                wv = out["win"][last]
                wsd = out["wstd"][last]
                w_err = abs(wv - d) if wv == wv else None
                cover = None
                if w_err is not None and wsd == wsd and wsd >= 0:
                    cover = w_err <= 1.96 * wsd
                n_ep = w0 + N
                rec = {"sys": sys_err, "oracle": orc, "win": w_err, "cover": cover,
                       "bound_ep": math.sqrt(2.0 / math.pi) / math.sqrt(n_ep * i_asym)}
                tmean = mean([t["junction_c"][i] for i in rows])
                cl = "inside" if band[0] <= tmean <= band[1] else "beyond"
                win[cl][N].append(rec)
                win["all"][N].append(rec)
    res = {}
    for c in classes:
        res[c] = {"windows": {}, "set_apart": {}}
        for N in WINDOWS:
            ws = win[c][N]
            have = [r for r in ws if r["sys"] is not None]
            mw = [r for r in ws if r["win"] is not None]
            e = {"windows": len(ws), "windows_missing": len(ws) - len(have),
                 "mae_system_mm": mean([r["sys"] for r in have]),
                 "mae_oracle_mm": mean([r["oracle"] for r in have]),
                 "mae_oracle_all_windows_mm": mean([r["oracle"] for r in ws]),
                 "window_mm_windows": len(mw), "window_mm_missing": len(ws) - len(mw),
                 "mae_window_mm": mean([r["win"] for r in mw]),
                 "crb_mae_mm": crb[str(N)],
                 "crb_mode_known_mae_mm": tj["crb"].get("crb_mode_known_mae_mm", {}).get(str(N)),
                 "crb_episode_mae_mm": mean([r["bound_ep"] for r in mw]),
                 "window_std_coverage_95": None}
            cov = [r["cover"] for r in mw if r["cover"] is not None]
            if cov:
                e["window_std_coverage_95"] = sum(cov) / len(cov)
            e["ratio_system_oracle"] = (e["mae_system_mm"] / e["mae_oracle_mm"]
                                        if have and e["mae_oracle_mm"] > 0 else None)
            e["ratio_window_crb"] = e["mae_window_mm"] / crb[str(N)] if mw else None
            e["ratio_window_crb_episode"] = (e["mae_window_mm"] / e["crb_episode_mae_mm"] if mw else None)
            res[c]["windows"][str(N)] = e
        sel = [i for i in range(n) if c == "all" or (inside[i] == (c == "inside"))]
        o = [i for i in sel if outlier[i]]
        s = [i for i in sel if not outlier[i]]
        sa = {"outlier_ranges": len(o),
              "outlier_set_apart": sum(1 for i in o if out["still"][i] == 0),
              "outlier_still_empty": sum(1 for i in o if out["still"][i] < 0),
              "still_ranges": len(s),
              "still_set_apart": sum(1 for i in s if out["still"][i] == 0),
              "still_still_empty": sum(1 for i in s if out["still"][i] < 0)}
        sa["outlier_set_apart_share"] = sa["outlier_set_apart"] / len(o) if o else None
        sa["still_set_apart_share"] = sa["still_set_apart"] / len(s) if s else None
        res[c]["set_apart"] = sa
    # still ranges soon after a permanent change of a surface (information only)
    first = {}
    after = []
    for i in range(n):
        key = (int(t["beam"][i]), int(t["episode"][i]))
        if key not in first:
            first[key] = t["time_s"][i]
        if key[1] > 0 and not outlier[i] and t["time_s"][i] - first[key] <= AFTER_STEP_S:
            after.append(i)
    res["after_step"] = {"seconds": AFTER_STEP_S, "still_ranges": len(after),
                         "still_set_apart": sum(1 for i in after if out["still"][i] == 0)}
    # goals
    goals = []
    for c in ("inside", "beyond"):
        for N in WINDOWS:
            e = res[c]["windows"][str(N)]
            name = "%s N=%d: MAE ratio system/oracle <= %.2f, missing windows <= %d%%" % (
                c, N, GOAL_RATIO, round(100 * GOAL_MISSING_WINDOWS))
            if e["windows"] < MIN_WINDOWS_FOR_GOAL:
                goals.append({"goal": name, "status": "n/a", "why": "%d windows" % e["windows"]})
                continue
            ok = (e["ratio_system_oracle"] is not None and e["ratio_system_oracle"] <= GOAL_RATIO
                  and e["windows_missing"] <= GOAL_MISSING_WINDOWS * e["windows"])
            goals.append({"goal": name, "status": "pass" if ok else "fail",
                          "value": e["ratio_system_oracle"], "missing": e["windows_missing"]})
        sa = res[c]["set_apart"]
        if sa["outlier_ranges"]:
            v = sa["outlier_set_apart_share"]
            goals.append({"goal": "%s: occluded/gross set apart >= %.0f%%" % (c, 100 * GOAL_OUTLIER_APART),
                          "status": "pass" if v >= GOAL_OUTLIER_APART else "fail", "value": v})
        if sa["still_ranges"]:
            v = sa["still_set_apart_share"]
            goals.append({"goal": "%s: truly still set apart <= %.0f%%" % (c, 100 * GOAL_STILL_APART),
                          "status": "pass" if v <= GOAL_STILL_APART else "fail", "value": v})
    goals.append({"goal": "no NaN/inf cells", "status": "pass" if counts["nan_inf"] == 0 else "fail",
                  "value": counts["nan_inf"]})
    return res, goals


def fmt(v, f="%.3f"):
    return "-" if v is None else f % v


def report(case, tj, t, counts, res, goals):
    band = tj["bench_band_c"]
    n = len(t["time_s"])
    occ = sum(1 for x in t["occluded"] if x > 0.5)
    gro = sum(1 for x in t["gross"] if x > 0.5)
    p = print
    p("case %s: %d ranges (occluded %d, gross %d); bench band %.2f-%.2f C; test junction %.2f-%.2f C"
      % (case, n, occ, gro, band[0], band[1], tj["test_junction_c"][0], tj["test_junction_c"][1]))
    p("missing cells: compensated %d, window %d, window_std %d, still %d; NaN/inf cells %d"
      % (counts["missing_compensated_mm"], counts["missing_window_mm"], counts["missing_window_std_mm"],
         counts["missing_still"], counts["nan_inf"]))
    p("")
    p("%-7s %4s %5s %4s | %8s %8s %6s | %8s %8s %6s %8s %6s %5s" % (
        "band", "N", "win", "miss", "MAE sys", "MAE orc", "ratio", "MAE wmm", "CRB", "ratio",
        "CRB ep", "ratio", "cov95"))
    for c in ("inside", "beyond", "all"):
        for N in WINDOWS:
            e = res[c]["windows"][str(N)]
            p("%-7s %4d %5d %4d | %8s %8s %6s | %8s %8s %6s %8s %6s %5s" % (
                c, N, e["windows"], e["windows_missing"], fmt(e["mae_system_mm"]), fmt(e["mae_oracle_mm"]),
                fmt(e["ratio_system_oracle"], "%.2f"), fmt(e["mae_window_mm"]), fmt(e["crb_mae_mm"]),
                fmt(e["ratio_window_crb"], "%.2f"), fmt(e["crb_episode_mae_mm"]),
                fmt(e["ratio_window_crb_episode"], "%.2f"), fmt(e["window_std_coverage_95"], "%.2f")))
    p("")
    p("%-7s %9s %10s %7s | %9s %10s %7s" % ("band", "outliers", "set apart", "share", "still", "set apart",
                                             "share"))
    for c in ("inside", "beyond", "all"):
        sa = res[c]["set_apart"]
        p("%-7s %9d %10d %7s | %9d %10d %7s" % (
            c, sa["outlier_ranges"], sa["outlier_set_apart"], fmt(sa["outlier_set_apart_share"], "%.4f"),
            sa["still_ranges"], sa["still_set_apart"], fmt(sa["still_set_apart_share"], "%.4f")))
    a = res["after_step"]
    p("still ranges within %.0f s after a surface moved: %d, set apart %d"
      % (a["seconds"], a["still_ranges"], a["still_set_apart"]))
    p("")
    for g in goals:
        p("[%s] %s%s" % (g["status"].upper(), g["goal"],
                         "" if g.get("value") is None else "  (%s)" % fmt(g["value"], "%.4g")))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--suite", required=True)
    ap.add_argument("--case", required=True)
    ap.add_argument("--compensated", required=True)
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    try:
        tj, t, tpath = read_truth(a.suite, a.case)
        out, counts, head = read_output(a.compensated, t, tpath)
    except Malformed as e:
        fail(str(e))
    except (OSError, UnicodeDecodeError) as e:
        fail("%s: %s" % (a.compensated, e))
    res, goals = score(tj, t, out, counts)
    report(a.case, tj, t, counts, res, goals)
    extra = sorted(set(head) - set(REQUIRED))
    doc = {"case": a.case, "suite": os.path.abspath(a.suite), "compensated": os.path.abspath(a.compensated),
           "rows": len(t["time_s"]),
           "occluded_rows": sum(1 for x in t["occluded"] if x > 0.5),
           "gross_rows": sum(1 for x in t["gross"] if x > 0.5),
           "bench_band_c": tj["bench_band_c"], "test_junction_c": tj["test_junction_c"],
           "counts": counts, "extra_columns": extra, "results": res, "goals": goals,
           "pass": all(g["status"] != "fail" for g in goals),
           "thresholds": {"ratio_system_oracle": GOAL_RATIO, "outlier_set_apart": GOAL_OUTLIER_APART,
                          "still_set_apart": GOAL_STILL_APART, "missing_windows": GOAL_MISSING_WINDOWS,
                          "min_windows_for_goal": MIN_WINDOWS_FOR_GOAL, "min_present_cells": MIN_PRESENT}}
    if a.json:
        with open(a.json, "w") as f:
            json.dump(doc, f, indent=1)
    sys.exit(0 if doc["pass"] else 1)


if __name__ == "__main__":
    main()
