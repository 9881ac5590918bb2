#!/usr/bin/env bash
# Fleet recalibration offline through the real binary: `tofcomp calibrate-dir` on a directory of
# two twin recordings (a time drift the paper's model lacks, and a clean one), a recording that
# is not the interchange CSV, and files that are not recordings. Checks: every recording has its
# row in name order, the broken one failed with its file named and the others went on (exit
# status 1); the drift's calibration carries the time drift and the clean one's nothing (the
# twin's truth); each calibration is the one `tofcomp diagnose --calibration-output` (or
# `tofcomp train`) writes for that recording alone (diagnose writes train's where nothing is
# kept), and -j 1 writes what -j 2 writes; progress
# on stderr names every recording; then the errors met before any work.
set -euo pipefail
tofcomp=$1
root=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

mkdir -p "$work/fleet/sub.csv"
"$tofcomp" -q simulate "$root/tests/cli/report-time-drift.yaml" -o "$work/fleet/scanner-a.csv"
"$tofcomp" -q simulate "$root/tests/cli/clean-short.yaml" -o "$work/fleet/scanner-b.csv"
printf 'this is not a recording\n1,2,3\n' > "$work/fleet/scanner-0-broken.csv"
echo "notes" > "$work/fleet/README.txt"

status=0
"$tofcomp" calibrate-dir "$work/fleet" -o "$work/out2" -j 2 --json \
  > "$work/batch.json" 2> "$work/progress.txt" || status=$?
[ "$status" -eq 1 ] || fail "exit status $status with a broken recording (want 1)"
for name in scanner-0-broken.csv scanner-a.csv scanner-b.csv; do
  grep -q "$name" "$work/progress.txt" || fail "progress does not name $name: $(cat "$work/progress.txt")"
done
grep -q "README.txt\|sub.csv" "$work/progress.txt" && fail "progress names a file that is no recording"

python3 - "$work/batch.json" "$work/out2" <<'PY'
import json, os, sys
batch, out = json.load(open(sys.argv[1])), sys.argv[2]
rows = batch["recordings"]
assert [r["recording"] for r in rows] == ["scanner-0-broken.csv", "scanner-a.csv", "scanner-b.csv"], rows
assert batch["calibrated"] == 2 and batch["failed"] == 1, batch
broken, drift, clean = rows
assert broken["status"] == "failed" and "scanner-0-broken.csv" in broken["error"], broken
assert not os.path.exists(os.path.join(out, "scanner-0-broken.yaml"))
assert json.load(open(os.path.join(out, "scanner-0-broken.json")))["error"] == broken["error"]
for r in (drift, clean):
    assert r["status"] == "calibrated", r
    assert os.path.exists(r["calibration_file"]), r
    assert r["ranges"] > 10000, r
    assert r["junction_c"][0] < r["junction_c"][1], r
    assert all(0.5 < v < 3.0 for v in r["mae_over_cramer_rao"].values()), r
# The time drift the scenario carries is kept first (a later step may keep more).
assert drift["named"].split(", ")[0] == "time drift", drift
assert clean["named"] == "none", clean
detail = json.load(open(os.path.join(out, "scanner-a.json")))
assert detail["training"]["em_converged"] in (True, False) and detail["search"]["kept"], detail.keys()
PY

# Each recording alone, through the commands that do one: the same calibration (but its time).
without_time() { grep -v '^ *created_utc:' "$1"; }
"$tofcomp" -q diagnose "$work/fleet/scanner-a.csv" --calibration-output "$work/alone-a.yaml" > /dev/null
"$tofcomp" -q train "$work/fleet/scanner-b.csv" -o "$work/alone-b.yaml" > /dev/null
diff <(without_time "$work/alone-a.yaml") <(without_time "$work/out2/scanner-a.yaml") > /dev/null ||
  fail "scanner-a's calibration differs from diagnose --calibration-output's"
diff <(without_time "$work/alone-b.yaml") <(without_time "$work/out2/scanner-b.yaml") > /dev/null ||
  fail "scanner-b's calibration differs from train's"
# The clean recording's search keeps nothing: diagnose still writes the calibration asked for,
# the trained one (train's), and says so.
"$tofcomp" -q diagnose "$work/fleet/scanner-b.csv" --calibration-output "$work/diagnosed-b.yaml" \
  > "$work/diagnosed-b.txt"
grep -q "the search kept nothing: the trained calibration (the paper's model) written to $work/diagnosed-b.yaml" \
  "$work/diagnosed-b.txt" || fail "diagnose does not say it wrote the trained calibration"
diff <(without_time "$work/diagnosed-b.yaml") <(without_time "$work/alone-b.yaml") > /dev/null ||
  fail "diagnose --calibration-output on a record where nothing is kept differs from train's"

# One at a time: the same files.
"$tofcomp" -q calibrate-dir "$work/fleet" -o "$work/out1" -j 1 > "$work/table.txt" || true
for name in scanner-a scanner-b; do
  diff <(without_time "$work/out1/$name.yaml") <(without_time "$work/out2/$name.yaml") > /dev/null ||
    fail "$name: -j 1 and -j 2 wrote different calibrations"
done
grep -q "^scanner-0-broken.csv  *failed: " "$work/table.txt" || fail "table: $(cat "$work/table.txt")"
grep -q "^3 recordings: 2 calibrated, 1 failed$" "$work/table.txt" || fail "table: $(cat "$work/table.txt")"

# Errors before any work.
mkdir "$work/empty"
if "$tofcomp" -q calibrate-dir "$work/empty" -o "$work/out3" 2> "$work/err"; then fail "empty dir accepted"; fi
grep -q "no recording (\*.csv) in it" "$work/err" || fail "empty dir: $(cat "$work/err")"
touch "$work/a-file"
if "$tofcomp" -q calibrate-dir "$work/fleet" -o "$work/a-file/out" 2> "$work/err"; then
  fail "an output dir under a file accepted"
fi
grep -q "cannot create it" "$work/err" || fail "output dir: $(cat "$work/err")"
echo "calibrate-dir: all checks hold"
