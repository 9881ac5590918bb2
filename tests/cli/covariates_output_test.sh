#!/usr/bin/env bash
# `tofcomp diagnose --covariates-output` through the real binary: one row per range of the data,
# at the data's own range times; the time since power-on and the time recomputed here from the
# CSV's power log; the ambient column where the data log one and absent where they do not; the
# residual centred (the trained model's y − d − Hθ̂ − Σ π μ averages near zero); the junction's
# lag at each time constant of the grid. Then the error a user meets: a file that cannot be
# written is named, and nothing is left behind.
set -euo pipefail
tofcomp=$1
root=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$tofcomp" -q simulate "$root/tests/cli/report-time-drift.yaml" -o "$work/data.csv"
"$tofcomp" -q diagnose "$work/data.csv" --covariates-output "$work/covariates.csv" > /dev/null
# The same data without the ambient column.
python3 - "$work/data.csv" "$work/no-ambient.csv" <<'PY'
import csv, sys
rows = [r for r in open(sys.argv[1]) if not r.startswith("#")]
reader = list(csv.DictReader(rows))
fields = [f for f in reader[0].keys() if f != "ambient_c"]
with open(sys.argv[2], "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=fields)
    w.writeheader()
    for r in reader:
        if any(r[k] for k in fields if k != "time_s"):
            w.writerow({k: r[k] for k in fields})
PY
"$tofcomp" -q diagnose "$work/no-ambient.csv" --covariates-output "$work/covariates-no-ambient.csv" > /dev/null

python3 - "$work/data.csv" "$work/covariates.csv" "$work/covariates-no-ambient.csv" <<'PY'
import bisect, csv, math, sys
data = list(csv.DictReader(r for r in open(sys.argv[1]) if not r.startswith("#")))
out = list(csv.DictReader(open(sys.argv[2])))
bare = list(csv.DictReader(open(sys.argv[3])))

def expect(ok, message):
    if not ok:
        sys.exit(message)

range_times = [float(r["time_s"]) for r in data if r["range_mm"]]
expect(len(out) == len(range_times), f"{len(out)} rows for {len(range_times)} ranges")
expect(all(abs(float(o["time_s"]) - t) < 1e-9 for o, t in zip(out, range_times)),
       "the rows are not at the data's range times")
# The power log: each switch's time and state; the time since the last switch on.
switches = [(float(r["time_s"]), float(r["power"])) for r in data if r["power"]]
on_times = [t for i, (t, p) in enumerate(switches) if p > 0.5 and (i == 0 or switches[i - 1][1] < 0.5)]
for o, t in zip(out, range_times):
    last_on = on_times[bisect.bisect_right(on_times, t) - 1]
    expect(abs(float(o["time_since_power_on_s"]) - (t - last_on)) < 1e-6,
           f"time since power-on at {t}: {o['time_since_power_on_s']} != {t - last_on}")
    expect(abs(float(o["time_h"]) - (t - range_times[0]) / 3600.0) < 1e-9, f"time at {t}")
expect("ambient_c" in out[0] and "ambient_c" not in bare[0],
       "the ambient column follows the data's ambient log")
lags = [k for k in out[0] if k.startswith("junction_lag_")]
expect(lags == [f"junction_lag_{tau}s_c" for tau in (30, 60, 120, 240, 480, 960, 1920)],
       f"the lag columns: {lags}")
residual = [float(o["residual_mm"]) for o in out]
mean = sum(residual) / len(residual)
spread = math.sqrt(sum((r - mean) ** 2 for r in residual) / len(residual))
expect(abs(mean) < 0.1 * spread, f"the residual is not centred: mean {mean}, sd {spread}")
expect(all(math.isfinite(float(v)) for o in out for v in o.values()), "a value is not finite")
PY

# A file that cannot be written: named, non-zero status, nothing written.
if "$tofcomp" -q diagnose "$work/data.csv" --covariates-output "$work/missing/dir/c.csv" \
    > /dev/null 2> "$work/error.txt"; then
  echo "an unwritable --covariates-output was accepted"; exit 1
fi
grep -q "missing/dir/c.csv" "$work/error.txt" || { cat "$work/error.txt"; exit 1; }
test ! -e "$work/missing" || { echo "a directory was made"; exit 1; }
echo ok
