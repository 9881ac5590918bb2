#!/usr/bin/env python3
"""Field calibration on a blind field suite (generate.py): for every case, the bench calibration
(`tofcomp train BENCH`) and the field calibration (`tofcomp train BENCH FIELD... --calibration
BENCH.yaml`) compensate the test day through the daemon's path (`tofcomp replay`); score.py alone
reads the truth. Each is also tested with EM windows on the test day's file with references
(`tofcomp test`: the windows holding a range that is not still left out). Prints one table row per
case and calibration, and the medians.

    python3 bench/field/evaluate.py --tofcomp build/cli/tofcomp --suite DIR [--json OUT.json]

Standard library only; the commands it runs are printed with --verbose.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
WINDOWS = ("200", "400", "800")
TEST_STRIDE = 10  # ranges between the starts of `tofcomp test`'s windows


def run(command, verbose):
    if verbose:
        print("+ " + " ".join(command), file=sys.stderr)
    done = subprocess.run(command, capture_output=True, text=True)
    return done


def evaluate_case(a, case, work):
    directory = os.path.join(a.suite, "cases", case)
    fields = sorted(f for f in os.listdir(directory) if f.startswith("field-"))
    bench_yaml = os.path.join(work, case + "-bench.yaml")
    field_yaml = os.path.join(work, case + "-field.yaml")
    steps = [
        [a.tofcomp, "-q", "train", os.path.join(directory, "bench.csv"), "-o", bench_yaml],
        [a.tofcomp, "-q", "train", os.path.join(directory, "bench.csv")]
        + [os.path.join(directory, f) for f in fields]
        + ["--calibration", bench_yaml, "-o", field_yaml],
    ]
    for step in steps:
        done = run(step, a.verbose)
        if done.returncode != 0:
            return {"case": case, "error": done.stderr.strip()[-300:]}
    out = {"case": case}
    for name, calibration in (("bench", bench_yaml), ("field", field_yaml)):
        replayed = os.path.join(work, f"{case}-{name}-replayed.csv")
        score = os.path.join(work, f"{case}-{name}-score.json")
        done = run([a.tofcomp, "-q", "replay", os.path.join(directory, "test.csv"),
                    "--calibration", calibration, "-o", replayed], a.verbose)
        if done.returncode != 0:
            return {"case": case, "error": done.stderr.strip()[-300:]}
        done = run([sys.executable, os.path.join(HERE, "score.py"), "--suite", a.suite, "--case",
                    case, "--compensated", replayed, "--json", score], a.verbose)
        if done.returncode not in (0, 1):
            return {"case": case, "error": done.stderr.strip()[-300:]}
        out[name] = json.load(open(score))["results"]
        # EM windows of the test day's still ranges against its references (`tofcomp test`):
        # d-hat's MAE over the Cramér–Rao bound, inside the bench calibration's band and beyond.
        done = run([a.tofcomp, "-q", "--json", "test",
                    os.path.join(directory, "test-with-reference.csv"), "--calibration",
                    calibration, "--band-of", bench_yaml, "--windows", ",".join(WINDOWS),
                    "--stride", str(TEST_STRIDE)],
                   a.verbose)
        if done.returncode != 0:
            return {"case": case, "error": done.stderr.strip()[-300:]}
        tested = json.loads(done.stdout)
        out[name + "_test"] = {
            str(w["window"]): {band: (w[f"em_{band}_trained"]["mean_absolute_error_mm"]
                                      / w["cramer_rao_mae_mm"]
                                      if w[f"em_{band}_trained"]["count"] else None)
                               for band in ("inside", "beyond")}
            for w in tested["windows"]}
    return out


def cell(results, band, n, key):
    w = results[band]["windows"].get(n, {})
    value = w.get(key)
    return value if isinstance(value, (int, float)) else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tofcomp", required=True)
    ap.add_argument("--suite", required=True)
    ap.add_argument("--json")
    ap.add_argument("--verbose", action="store_true")
    a = ap.parse_args()
    cases = sorted(os.listdir(os.path.join(a.suite, "cases")))
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for case in cases:
            rows.append(evaluate_case(a, case, work))
            print(f"{case}: done", file=sys.stderr)
    header = ("case   calib  | ratio to oracle, inside (200/400/800) | beyond (200/400/800) "
              "| window d-hat / CRB beyond (200/400/800) | occluded set apart | still set apart")
    print(header)
    medians = {}
    for r in rows:
        if "error" in r:
            print(f"{r['case']}  failed: {r['error']}")
            continue
        for name in ("bench", "field"):
            res = r[name]
            ratio = {b: [cell(res, b, n, "ratio_system_oracle") for n in WINDOWS]
                     for b in ("inside", "beyond")}
            crb = [cell(res, "beyond", n, "ratio_window_crb") for n in WINDOWS]
            # A band without occluded (or still) ranges has no share: null in the scorer's JSON.
            shares = lambda key: [res[b]["set_apart"][key] for b in ("inside", "beyond")
                                  if res[b]["set_apart"][key] is not None]
            occluded = min(shares("outlier_set_apart_share"), default=float("nan"))
            still = max(shares("still_set_apart_share"), default=float("nan"))
            fmt = lambda xs: "/".join("-" if x is None else f"{x:.2f}" for x in xs)
            print(f"{r['case']} {name:6} | {fmt(ratio['inside']):>37} | {fmt(ratio['beyond']):>20} | "
                  f"{fmt(crb):>40} | {occluded:18.4f} | {still:15.4f}")
            for key, values in (("inside", ratio["inside"]), ("beyond", ratio["beyond"])):
                for n, v in zip(WINDOWS, values):
                    if v is not None:
                        medians.setdefault((name, key, n), []).append(v)
    print("EM windows of the test day (tofcomp test), MAE of d-hat over the Cramer-Rao bound:")
    for r in rows:
        if "error" in r:
            continue
        for name in ("bench", "field"):
            t = r[name + "_test"]
            fmt = lambda band: "/".join("-" if t[n][band] is None else f"{t[n][band]:.2f}"
                                        for n in WINDOWS)
            print(f"{r['case']} {name:6} | inside {fmt('inside'):>17} | beyond {fmt('beyond'):>17}")
            for band in ("inside", "beyond"):
                for n in WINDOWS:
                    if t[n][band] is not None:
                        medians.setdefault((name + " d-hat/CRB", band, n), []).append(t[n][band])
    print("medians of the ratio to the oracle (and of d-hat over the bound):")
    for (name, band, n), values in sorted(medians.items()):
        print(f"  {name:6} {band:7} N={n}: {statistics.median(values):.2f} over {len(values)} cases")
    if a.json:
        json.dump(rows, open(a.json, "w"))
    return 0 if all("error" not in r for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
