#!/usr/bin/env bash
# --help in GNU style (issue 54, item 2; io/help_format.hpp), for tofcomp and every subcommand,
# tofcompd and the bridges: no line over 80 columns; no CLI11 type marks (TEXT:FILE, FLOAT:,
# REQUIRED, =default glued to a type); each option as "-c, --config=FILE" or "    --socket=PATH";
# one spelling per concept (--beams=FIRST:LAST wherever it is taken). Then the options are
# checked before any work: a bad --windows is a usage error (status 2) at once, not after a
# training.
# Usage: help_format_test.sh TOFCOMP TOFCOMPD [BRIDGE...]
set -euo pipefail
tofcomp=$1
tofcompd=$2
shift 2
fail() { echo "FAIL: $*" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
max_columns=80

# check_help NAME: the help in $work/help.txt, checked.
check_help() {
  local name=$1 help="$work/help.txt"
  [ -s "$help" ] || fail "$name --help printed nothing"
  local long
  # Columns on a terminal: characters, a combining mark (the hat of d̂) taking none.
  long=$(python3 - "$help" "$max_columns" <<'PY'
import sys, unicodedata
for number, line in enumerate(open(sys.argv[1], encoding="utf-8"), 1):
    line = line.rstrip("\n")
    width = sum(1 for c in line if not unicodedata.combining(c))
    if width > int(sys.argv[2]):
        print(f"{number}: {width} columns: {line}")
PY
)
  [ -z "$long" ] || fail "$name --help has lines over $max_columns columns:"$'\n'"$long"
  if grep -nE 'TEXT:|FLOAT:|INT:|UINT:|REQUIRED|Excludes:|Needs:' "$help"; then
    fail "$name --help shows CLI11's marks"
  fi
  # Every option line: two spaces, then "-x, --long", "-x" or four spaces and "--long".
  if grep -nE '^ {2,6}-' "$help" | grep -vE '^[0-9]+:  (-[A-Za-z0-9](, --[a-z0-9-]+)?|    --[a-z0-9-]+)([= ]|$)'; then
    fail "$name --help has option lines not in GNU form"
  fi
}

subcommands() {  # the names in the Subcommands: section of a help
  awk '/^Subcommands:/ { on = 1; next } on && /^  [a-z]/ { print $1 } on && /^$/ { on = 0 }' "$1"
}

"$tofcomp" --help > "$work/help.txt"
check_help tofcomp
cp "$work/help.txt" "$work/top.txt"
count=1
for sub in $(subcommands "$work/top.txt"); do
  "$tofcomp" "$sub" --help > "$work/help.txt"
  check_help "tofcomp $sub"
  count=$((count + 1))
  cp "$work/help.txt" "$work/sub.txt"
  for nested in $(subcommands "$work/sub.txt"); do
    "$tofcomp" "$sub" "$nested" --help > "$work/help.txt"
    check_help "tofcomp $sub $nested"
    count=$((count + 1))
  done
done
[ "$count" -ge 15 ] || fail "only $count helps found: the Subcommands section was not read"
for program in "$tofcompd" "$@"; do
  "$program" --help > "$work/help.txt"
  check_help "$(basename "$program")"
done

# One spelling: --beams takes FIRST:LAST in every command that has it.
for command in "query latest" "query subscribe" "shm-dump"; do
  # shellcheck disable=SC2086
  "$tofcomp" $command --help | grep -q -- '--beams=FIRST:LAST' ||
    fail "tofcomp $command --help does not spell --beams=FIRST:LAST"
done

# Checked before any work: a usage error, status 2, the item named; no training started (the
# data file need not even be read: a missing one would be status 2 as well, so it exists here).
printf 'time_s,range_mm,true_range_mm\n0,3000,3000\n' > "$work/d.csv"
for command in evaluate diagnose; do
  set +e
  "$tofcomp" "$command" "$work/d.csv" --windows 200,800x > "$work/out.txt" 2> "$work/err.txt"
  status=$?
  set -e
  [ "$status" = 2 ] || { cat "$work/err.txt" >&2; fail "$command --windows 200,800x: status $status, not 2"; }
  grep -q "'800x' is not a window length" "$work/err.txt" || { cat "$work/err.txt" >&2; fail "$command: the item is not named"; }
  grep -q "training" "$work/err.txt" && fail "$command trained before refusing --windows"
done
set +e
"$tofcomp" query subscribe --beams 9:2 > /dev/null 2> "$work/err.txt"
status=$?
set -e
[ "$status" = 2 ] || fail "query subscribe --beams 9:2: status $status, not 2"
echo "help: $count helps of tofcomp and the daemon's and bridges' in GNU form; options checked first"
