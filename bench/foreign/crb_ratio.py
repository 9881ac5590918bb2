#!/usr/bin/env python3
"""MAE of d-hat over the Cramér-Rao bound on the foreign measured data, with tofcomp's defaults.

Usage: bench/foreign/crb_ratio.py TOFCOMP DATA_DIR [extra tofcomp evaluate options...]

Runs `tofcomp evaluate DATA --json` on every foreign-N.csv of DATA_DIR and prints, per set and
window length, the MAE of d-hat, the truth file's bound (crb_mae_mm) and their ratio. The truth
files are read here only, to score: nothing of them reaches tofcomp.
"""
import glob
import json
import os
import subprocess
import sys


def main():
    tofcomp, data_dir, extra = sys.argv[1], sys.argv[2], sys.argv[3:]
    print(f"{'set':<12} {'window':>6} {'MAE mm':>8} {'CRB mm':>8} {'ratio':>6}  thermal fit")
    worst = 0.0
    for csv in sorted(glob.glob(os.path.join(data_dir, "foreign-*.csv"))):
        name = os.path.basename(csv)[:-4]
        truth = json.load(open(csv[:-4] + ".truth.json"))
        run = subprocess.run([tofcomp, "--json", "-q", "evaluate", csv, *extra],
                             capture_output=True, text=True)
        if run.returncode != 0:
            print(f"{name:<12} refused: {run.stderr.strip()[:150]}")
            worst = float("inf")
            continue
        report = json.loads(run.stdout)
        fit = report["thermal_fit"]
        for w in report["windows"]:
            bound = truth["crb_mae_mm"].get(str(w["window"]))
            if bound is None or "em" not in w:
                continue
            mae = w["em"]["mean_absolute_error_mm"]
            worst = max(worst, mae / bound)
            print(f"{name:<12} {w['window']:>6} {mae:8.3f} {bound:8.3f} {mae / bound:6.2f}  "
                  f"held-out NRMSE {fit.get('held_out_nrmse_fit_percent', float('nan')):.1f} %")
    print(f"worst ratio {worst:.2f}")


if __name__ == "__main__":
    main()
