#!/usr/bin/env python3
"""d-hat through the daemon's path on a blind suite: each set's calibration replayed.

Usage: replay_score.py --tofcomp PATH --tofcompd PATH --suite DIR --calibrations CDIR
                       [--window W] [--jobs J] [--score-json S.json] [--json OUT.json]

score.py's figure of d-hat is offline: the model search's held-out windows, each term read on
its own covariate at the RTS-smoothed junction.  tofcompd applies a calibration causally: its
junction filter, Eq. 3's heating rate at the filter's state, an ambient term as the constant
of the calibration's ambient, the incremental window.  The two can rank calibrations apart
(docs/closing-the-loop.md, section 5.5).  This script takes the calibrations score.py wrote
(`score.py --calibrations CDIR`: CDIR/<data file>.yaml for every set and counterpart), runs
    PATH replay <the set, as measured data> --config <the daemon's default, at CDIR's
                calibration and window W> -o <replayed>
and scores the window's d-hat (column 6) against the data's own true_range_mm, every range the
window published an estimate for.
Per kind it prints the ratio of an effect set's MAE to its clean counterpart's (the issue's
1.25 x goal, on the daemon's path), beside score.py's offline ratio at the same window when
--score-json is given.  A run that fails is listed with its reason; exit status 0 once
everything that could be scored was, 2 on bad arguments.

Only the truth's kind and effect labels are read, for the grouping.  Pure standard library.
"""
import argparse
import csv
import glob
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

SEP = "\u00d7"  # ×, as score.py labels effects
RATIO_OK = 1.25
WINDOW_COLUMN = 4  # time_s, beam, range_mm, compensated_mm, window_mm, ... (tofcomp replay -o)
REPLAY_TIMEOUT_S = 600.0


def true_ranges(path):
    """The true range of every range row of an interchange CSV, in order."""
    out = []
    with open(path, newline="") as f:
        rows = csv.reader(line for line in f if not line.startswith("#"))
        header = next(rows)
        r, t = header.index("range_mm"), header.index("true_range_mm")
        for row in rows:
            if row[r].strip():
                out.append(float(row[t]))
    return out


def daemon_config(tofcompd, calibration, window):
    """The daemon's default configuration at `calibration` and window `window`."""
    text = subprocess.run([tofcompd, "--print-default-config"], check=True,
                          capture_output=True, text=True).stdout
    text, n = re.subn(r"(?m)^(  file: ).*calibration\.yaml.*$",
                      lambda m: m.group(1) + calibration, text)
    if n != 1:
        raise RuntimeError("the default configuration has no calibration file line")
    text, n = re.subn(r"(?m)^(  window: )\d+", lambda m: m.group(1) + str(window), text)
    if n != 1:
        raise RuntimeError("the default configuration has no window line")
    # A relative scenario path is read beside the configuration file: make it absolute.
    # In a build tree (build/daemon/tofcompd) the scenarios are the source tree's config/.
    build = os.path.dirname(os.path.dirname(os.path.abspath(tofcompd)))
    scenarios = os.path.abspath(os.path.join(build, "..", "config", "scenarios"))
    if not os.path.isdir(scenarios):
        return text
    return re.sub(r"(?m)^(  scenario: )scenarios/", lambda m: m.group(1) + scenarios + "/", text)


def replay_mae(a, data_csv, calibration):
    """The mean absolute error of the daemon's window d-hat over every range of `data_csv`."""
    truth = true_ranges(data_csv)
    with tempfile.TemporaryDirectory() as tmp:
        config = os.path.join(tmp, "tofcompd.yaml")
        with open(config, "w") as f:
            f.write(daemon_config(a.tofcompd, os.path.abspath(calibration), a.window))
        replayed = os.path.join(tmp, "replayed.csv")
        proc = subprocess.run([a.tofcomp, "replay", data_csv, "--config", config, "-o",
                               replayed], capture_output=True, text=True,
                              timeout=REPLAY_TIMEOUT_S)
        if proc.returncode != 0:
            raise RuntimeError("replay exit %d: %s" % (proc.returncode,
                                                       proc.stderr.strip()[-300:]))
        with open(replayed, newline="") as f:
            rows = [row for row in csv.reader(f) if row and row[0][:1].isdigit()]
    if len(rows) != len(truth):
        raise RuntimeError("replay gave %d ranges, the data hold %d" % (len(rows), len(truth)))
    # A window publishes no d-hat until it holds enough ranges (the first few of a record, and
    # after a restart); those ranges are left out.
    errors = [abs(float(row[WINDOW_COLUMN]) - t) for row, t in zip(rows, truth)
              if row[WINDOW_COLUMN].strip()]
    if not errors:
        raise RuntimeError("replay published no window estimate")
    return statistics.fmean(errors)


def label(truth):
    effects = truth.get("effects") or []
    if not effects:
        return "clean"
    return " + ".join(e["parameter"] + SEP + e["covariate"] for e in effects)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tofcomp", required=True)
    ap.add_argument("--tofcompd", required=True)
    ap.add_argument("--suite", required=True, help="a directory made by generate.py")
    ap.add_argument("--calibrations", required=True, help="score.py's --calibrations directory")
    ap.add_argument("--window", type=int, default=200)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--score-json", default=None, help="score.py's --json, for its offline ratio")
    ap.add_argument("--json", default=None, help="write the results here")
    a = ap.parse_args(argv)
    for exe in (a.tofcomp, a.tofcompd):
        if not (os.path.isfile(exe) and os.access(exe, os.X_OK)):
            ap.error("%s is not an executable file" % exe)
    if a.window < 1 or a.jobs < 1:
        ap.error("--window and --jobs must be >= 1")
    a.tofcomp, a.tofcompd = os.path.abspath(a.tofcomp), os.path.abspath(a.tofcompd)

    truths = []
    for p in sorted(glob.glob(os.path.join(a.suite, "truth", "*.json"))):
        with open(p) as f:
            truths.append(json.load(f))
    if not truths:
        ap.error("no truth in %s/truth" % a.suite)
    names = []
    for t in truths:
        names.append(t["id"])
        if t.get("counterpart"):
            names.append(t["counterpart"][:-len(".csv")])

    def work(name):
        data = os.path.join(a.suite, "data", name + ".csv")
        calibration = os.path.join(a.calibrations, name + ".yaml")
        try:
            if not os.path.isfile(calibration):
                raise RuntimeError("no calibration %s (score.py --calibrations)" % calibration)
            return name, replay_mae(a, data, calibration), None
        except (RuntimeError, OSError, ValueError, subprocess.SubprocessError) as ex:
            return name, None, str(ex)

    with ThreadPoolExecutor(max_workers=a.jobs) as ex:
        results = {n: (m, e) for n, m, e in ex.map(work, names)}
    offline = {}
    if a.score_json:
        with open(a.score_json) as f:
            for row in json.load(f)["mae_ratio"]["rows"]:
                offline[row["id"]] = row["ratio"].get(str(a.window))

    rows, failures = [], [(n, e) for n, (m, e) in results.items() if e]
    for t in truths:
        if not t.get("counterpart") or len(t.get("effects") or []) != 1:
            continue
        mine, clean = results[t["id"]][0], results[t["counterpart"][:-len(".csv")]][0]
        if mine is None or clean is None:
            continue
        rows.append({"id": t["id"], "true": label(t), "mae_mm": mine, "counterpart_mae_mm": clean,
                     "ratio": mine / clean, "offline_ratio": offline.get(t["id"])})
    by_kind = {}
    for r in rows:
        by_kind.setdefault(r["true"], []).append(r)
    print("d-hat through the daemon's path (tofcomp replay, window %d, every range): an effect "
          "set's MAE over its clean counterpart's" % a.window)
    print("%-40s %5s %12s %12s %14s" % ("true effect", "sets", "within 1.25x", "median ratio",
                                        "offline median"))
    for kind in sorted(by_kind):
        rs = by_kind[kind]
        off = [r["offline_ratio"] for r in rs if r["offline_ratio"] is not None]
        print("%-40s %5d %12s %12.2f %14s" % (
            kind, len(rs), "%d/%d" % (sum(r["ratio"] <= RATIO_OK for r in rs), len(rs)),
            statistics.median(r["ratio"] for r in rs),
            "%.2f" % statistics.median(off) if off else "-"))
    if rows:
        off_ok = [r for r in rows if r["offline_ratio"] is not None]
        print("%-40s %5d %12s %12.2f %14s" % (
            "all", len(rows), "%d/%d" % (sum(r["ratio"] <= RATIO_OK for r in rows), len(rows)),
            statistics.median(r["ratio"] for r in rows),
            "%d/%d within" % (sum(r["offline_ratio"] <= RATIO_OK for r in off_ok), len(off_ok))
            if off_ok else "-"))
    cleans = [(t["id"], results[t["id"]][0]) for t in truths if not t.get("effects")]
    for name, mae in cleans:
        if mae is not None:
            print("clean set %s: MAE %.3f mm" % (name, mae))
    for name, err in failures:
        print("FAILED %s: %s" % (name, err))
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"window": a.window, "rows": rows,
                       "mae_mm": {n: m for n, (m, e) in results.items()},
                       "failures": dict(failures)}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
