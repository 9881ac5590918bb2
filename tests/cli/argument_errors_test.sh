#!/usr/bin/env bash
# What a user who mistypes meets, through the real binary: a number out of bounds is refused with
# its bound in a few words (not CLI11's "not in range 0.000000 to 1797693…"), and a mistyped
# subcommand or option gets a "did you mean" naming the right one, and that message alone (exit
# status 2 for both); field
# training names the options it would ignore (exit status 1).
set -euo pipefail
tofcomp=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# exits STATUS ARGS... EXPECTED: tofcomp ARGS must exit STATUS with EXPECTED on stderr, and
# never with CLI11's own range message.
exits() {
  local wanted=$1
  shift
  local expected=${*: -1}
  set +e
  "$tofcomp" "${@:1:$#-1}" > /dev/null 2> "$work/err"
  local status=$?
  set -e
  [ "$status" = "$wanted" ] || fail "tofcomp ${*:1:$#-1}: status $status, not $wanted"
  grep -qF -- "$expected" "$work/err" || fail "tofcomp ${*:1:$#-1}: no '$expected' in: $(cat "$work/err")"
  if grep -q "not in range\|179769" "$work/err"; then fail "CLI11's range message: $(cat "$work/err")"; fi
}
# Refused by the parser (status 2), or by the command once parsed (status 1).
refused() { exits 2 "$@"; }
failed() { exits 1 "$@"; }

refused query subscribe -n 0 "--count: must be at least 1, not 0"
refused query subscribe --every 0 "--every: must be between 1 and 1000000, not 0"
refused query --timeout 0 status "--timeout: must be greater than 0, not 0"
refused query --timeout soon status "--timeout: 'soon' is not a number"
refused shm-dump -n 0 "--count: must be at least 1, not 0"
touch "$work/scenario.yaml"
refused emulate "$work/scenario.yaml" --time-scale -1 "--time-scale: must be at least 0, not -1"

refused evalute "tofcomp: 'evalute' is not a subcommand; did you mean 'evaluate'?"
refused query subscibe "tofcomp query: 'subscibe' is not a subcommand; did you mean 'subscribe'?"
refused query subscribe --evry 5 \
  "tofcomp query subscribe: '--evry' is not an option; did you mean '--every'?"
refused query subscribe --jsn "tofcomp query subscribe: '--jsn' is not an option; did you mean '--json'?"
# Field training uses every beam and chooses the basis itself: options it would ignore are named.
printf 'time_s,range_mm\n0,1000\n' > "$work/field.csv"
failed train "$work/field.csv" --calibration "$work/scenario.yaml" --beam 3 -o "$work/c.yaml" \
  "--beam: field training"
failed train "$work/field.csv" "$work/field.csv" --basis polynomial:2 --modes 2 -o "$work/c.yaml" \
  "--basis, --modes: field training"
failed train "$work/field.csv" --beam 1 -o "$work/c.yaml" "--beam: field training"
# --threads and --jobs take 0, their default, "one per core", as their help says.
refused train "$work/field.csv" --threads -1 -o "$work/c.yaml" "--threads: must be between 0 and 256, not -1"
refused calibrate-dir "$work" --jobs 300 "--jobs: must be between 0 and 256, not 300"

# A typo gets one message, the suggestion, not CLI11's own before it.
alone() {
  refused "$@"
  if grep -q "subcommand is required\|not expected" "$work/err"; then
    fail "tofcomp ${*:1:$#-1}: CLI11's message besides the suggestion: $(cat "$work/err")"
  fi
}
alone evalute "tofcomp: 'evalute' is not a subcommand; did you mean 'evaluate'?"
alone train "$work/field.csv" --bem 3 -o "$work/c.yaml" \
  "tofcomp train: '--bem' is not an option; did you mean '--beam'?"

echo "argument errors: all checks hold"
