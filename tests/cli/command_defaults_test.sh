#!/usr/bin/env bash
# The defaults a user need not type, through the real binary: without --datasheet the thermal
# fit starts from config/lms200-datasheet.yaml (the same result as naming that file; a different
# datasheet gives a different start), and `simulate` without -o writes the CSV to stdout, the
# same bytes as with -o FILE; --figures' help says it draws PNG and writes CSV; train's --threads (0: the
# default, one per core) changes nothing in its calibration. Then one version: `tofcomp
# --version` and `tofcompd --version` print the project(VERSION) of CMakeLists.txt.
set -euo pipefail
tofcomp=$1
tofcompd=$2
root=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# simulate: stdout without -o, the file's bytes with it; the summary on stderr.
"$tofcomp" simulate "$root/config/scenarios/default.yaml" > "$work/stdout.csv" 2> "$work/err"
"$tofcomp" -q simulate "$root/config/scenarios/default.yaml" -o "$work/file.csv"
cmp -s "$work/stdout.csv" "$work/file.csv" || fail "simulate to stdout differs from -o FILE"
grep -q "^# scenario: default$" "$work/stdout.csv" || fail "stdout holds no CSV"
grep -q "wrote stdout: " "$work/err" || fail "no summary on stderr: $(cat "$work/err")"
if "$tofcomp" simulate "$root/config/scenarios/default.yaml" --json > /dev/null 2> "$work/err"; then
  fail "simulate --json without -o mixed JSON into the CSV"
fi
grep -q -- "--json needs -o FILE" "$work/err" || fail "unclear refusal: $(cat "$work/err")"

# train --threads: the structure search's folds on one thread or two give the same calibration
# (its creation time aside); the default (one per core) too, and 0, which names the default.
for threads in 1 2 0 default; do
  option=(--threads "$threads"); [ "$threads" = default ] && option=()
  "$tofcomp" -q train "$work/file.csv" "${option[@]}" -o "$work/train-$threads.yaml" > /dev/null
  grep -v "created_utc" "$work/train-$threads.yaml" > "$work/train-$threads.body"
done
cmp -s "$work/train-1.body" "$work/train-2.body" || fail "train --threads 1 and 2 differ"
cmp -s "$work/train-1.body" "$work/train-default.body" || fail "train's default threads differ"
cmp -s "$work/train-0.body" "$work/train-default.body" || fail "train --threads 0 is not the default"

# --datasheet: its default is the bundled LMS 200 file.
"$tofcomp" -q thermal-fit "$work/file.csv" --json > "$work/default.json"
"$tofcomp" -q thermal-fit "$work/file.csv" --json \
  --datasheet "$root/config/lms200-datasheet.yaml" > "$work/named.json"
cmp -s "$work/default.json" "$work/named.json" ||
  fail "thermal-fit without --datasheet differs from --datasheet config/lms200-datasheet.yaml"
sed 's/electrical_power_w: 20.0/electrical_power_w: 30.0/' "$root/config/lms200-datasheet.yaml" \
  > "$work/other-datasheet.yaml"
"$tofcomp" -q thermal-fit "$work/file.csv" --json --datasheet "$work/other-datasheet.yaml" \
  > "$work/other.json"
python3 - "$work/default.json" "$work/other.json" <<'PY'
import json, sys
default, other = (json.load(open(p))["algorithm1"] for p in sys.argv[1:])
# Algorithm 1's heat power is electrical power × efficiency (0.5): 10 W from the bundled file.
assert abs(default["power_w"] - 10.0) < 1e-12, default
assert abs(other["power_w"] - 15.0) < 1e-12, other
PY
"$tofcomp" thermal-fit --help | grep -q "config/lms200-datasheet.yaml" ||
  fail "--help does not name the default datasheet"

# --figures says what it writes: the figures as PNG, their data as CSV.
for command in evaluate test; do
  "$tofcomp" "$command" --help | tr -s ' \n' ' ' | grep -q -- "--figures=DIR Draw .*PNG.*CSV" ||
    fail "$command --help does not say --figures draws PNG and writes CSV"
done

# One version, from project(VERSION).
version=$(sed -n 's/^project(tofcomp VERSION \([0-9.]*\) .*/\1/p' "$root/CMakeLists.txt")
[ -n "$version" ] || fail "no project VERSION in CMakeLists.txt"
[ "$("$tofcomp" --version)" = "tofcomp $version" ] || fail "tofcomp --version: $("$tofcomp" --version)"
[ "$("$tofcompd" --version)" = "tofcompd $version" ] || fail "tofcompd --version: $("$tofcompd" --version)"
echo "command defaults and version: all checks hold"
