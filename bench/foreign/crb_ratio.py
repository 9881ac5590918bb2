#!/usr/bin/env python3
"""MAE of d-hat over the Cramér-Rao bound on the foreign measured data, with tofcomp's defaults.

Usage: bench/foreign/crb_ratio.py TOFCOMP DATA_DIR [--save DIR] [extra tofcomp evaluate options...]

Runs `tofcomp evaluate DATA --json` on every *.csv of DATA_DIR that has a truth file beside it
(foreign-N.csv and foreign-N.truth.json) and prints, per set and window length, the MAE of d-hat,
the truth file's bound (crb_mae_mm) and their ratio: on all the test windows, on those inside the
junction temperatures the calibration was trained on, and on those beyond. Also the structure the
calibration chose. The truth files are read here only, to score: nothing of them reaches tofcomp.
--save DIR keeps each run's JSON as DIR/NAME.json.
"""
import glob
import json
import os
import subprocess
import sys


def ratio(moments, bound):
    if not moments or moments.get("count", 0) == 0:
        return "     -"
    return f"{moments['mean_absolute_error_mm'] / bound:6.2f}"


def main():
    tofcomp, data_dir, extra = sys.argv[1], sys.argv[2], sys.argv[3:]
    save = None
    if "--save" in extra:
        at = extra.index("--save")
        save = extra[at + 1]
        del extra[at:at + 2]
        os.makedirs(save, exist_ok=True)
    print(f"{'set':<12} {'window':>6} {'MAE mm':>8} {'CRB mm':>8} {'ratio':>6} {'inside':>6} "
          f"{'beyond':>6} {'beyond%':>7}  structure")
    worst = worst_inside = 0.0
    for csv in sorted(glob.glob(os.path.join(data_dir, "*.csv"))):
        truth_file = csv[:-4] + ".truth.json"
        if not os.path.exists(truth_file):
            continue
        name = os.path.basename(csv)[:-4]
        truth = json.load(open(truth_file))
        run = subprocess.run([tofcomp, "--json", "-q", "evaluate", csv, *extra],
                             capture_output=True, text=True)
        if run.returncode != 0:
            print(f"{name:<12} refused: {run.stderr.strip()[:150]}")
            worst = float("inf")
            continue
        report = json.loads(run.stdout)
        if save:
            with open(os.path.join(save, name + ".json"), "w") as out:
                out.write(run.stdout)
        structure = (report.get("choices") or {}).get("structure") or {}
        chosen = structure.get("chosen", report["calibration"]["measurement"]["basis"]
                               if "measurement" in report["calibration"] else "")
        for w in report["windows"]:
            bound = truth["crb_mae_mm"].get(str(w["window"]))
            if bound is None or "em" not in w:
                continue
            mae = w["em"]["mean_absolute_error_mm"]
            worst = max(worst, mae / bound)
            inside = w.get("em_inside_trained", {})
            beyond = w.get("em_beyond_trained", {})
            if inside.get("count", 0):
                worst_inside = max(worst_inside, inside["mean_absolute_error_mm"] / bound)
            share = 100.0 * beyond.get("count", 0) / max(1, w["em"]["count"])
            print(f"{name:<12} {w['window']:>6} {mae:8.3f} {bound:8.3f} {mae / bound:6.2f} "
                  f"{ratio(inside, bound)} {ratio(beyond, bound)} {share:6.1f}%  {chosen}")
        sys.stdout.flush()
    print(f"worst ratio {worst:.2f}; inside the trained junction range {worst_inside:.2f}")


if __name__ == "__main__":
    main()
