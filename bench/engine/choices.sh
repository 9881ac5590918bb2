#!/usr/bin/env bash
# What training and diagnose choose on the twin's scenarios and the foreign sets, and the CPU
# time each took: to show that a change to the engine's speed leaves the choices alone (run it
# on the builds before and after, and compare the tables; docs/performance.md).
#
# Usage: bench/engine/choices.sh BUILD_DIR [DATA_DIR]
#   BUILD_DIR: a build with cli/tofcomp. DATA_DIR: where the scenarios' records are simulated
#   (kept between runs, so both builds judge the same files); default /tmp/tofcomp-choices.
# Prints one line per data set: name, ranges, the structure chosen, the terms diagnose keeps
# (or "-"), and the user CPU seconds of train and of diagnose (from the trained calibration).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "$1" && pwd)
data=${2:-/tmp/tofcomp-choices}
tofcomp="$build/cli/tofcomp"
datasheet="$root/config/lms200-datasheet.yaml"
mkdir -p "$data"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

sets=()
for scenario in "$root"/config/scenarios/*.yaml; do
  name=$(basename "$scenario" .yaml)
  [ -s "$data/$name.csv" ] || "$tofcomp" simulate "$scenario" -o "$data/$name.csv" -q
  sets+=("$data/$name.csv")
done
for f in /work/shared/data/foreign/*.csv; do [ -e "$f" ] && sets+=("$f"); done

# User CPU seconds of a command (GNU time), its stdout to $2.
cpu_of() {
  local out=$1
  shift
  /usr/bin/time -f '%U' -o "$work/time" "$@" >"$out"
  cat "$work/time"
}

printf '%-28s %8s  %-40s %-40s %7s %7s\n' "data" "ranges" "structure" "kept" "train s" "diag s"
for csv in "${sets[@]}"; do
  name=$(basename "$csv" .csv)
  train_s=$(cpu_of "$work/train.json" "$tofcomp" --json -q train "$csv" --datasheet "$datasheet" \
    -o "$work/c.yaml")
  diagnose_s=$(cpu_of "$work/diagnose.json" "$tofcomp" --json -q diagnose "$csv" \
    --datasheet "$datasheet" --calibration "$work/c.yaml" --threads 1)
  python3 - "$name" "$work/train.json" "$work/diagnose.json" "$train_s" "$diagnose_s" <<'PY'
import json, sys
name, train, diagnose, train_s, diagnose_s = sys.argv[1:]
t = json.load(open(train))
d = json.load(open(diagnose))
structure = t["choices"].get("structure", {}).get("chosen", "given")
ranges = t["calibration"]["provenance"]["samples"]
kept = d["named"] or "-"
print(f"{name:28s} {ranges:8d}  {structure:40s} {kept:40s} {float(train_s):7.1f} {float(diagnose_s):7.1f}")
PY
done
