#!/usr/bin/env bash
# The blind suite's small draw (bench/blind/README.md): one set of each of the 12 kinds of
# effect the generator draws and two clean sets, drawn with a fixed seed by a generator written
# apart from the detector; `tofcomp diagnose` runs on each set and on each effect set's clean
# counterpart, and only the scorer reads the truth. The floor asserted here guards against a
# regression; the figures themselves (a larger draw, its confusion table) are in
# docs/closing-the-loop.md.
#   at least 4 of the 12 effects named right first (kept first: the effect's parameter and
#     covariate). The floor is set from a draw other than this one, not from this one's result:
#     on the 24 single-effect sets of bench/blind's small draw the search named 15 right first
#     (docs/closing-the-loop.md, "Blind evaluation"); at that rate, 12 sets name 3 or fewer right
#     with probability under 1 % (binomial), and a guess among the grammar's ~60 candidates names
#     one right with probability under 2 % per set. So a fall below 4 is a regression, not a
#     bad draw; the accuracy itself is a figure of the docs, not of this test;
#   nothing kept on both clean sets, and on at least 11 of the 12 clean counterparts;
#   no run failed.
set -euo pipefail
tofcomp=$1
root=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

python3 "$root/bench/blind/generate.py" --out "$work/suite" --seed 20261125 --count 12 --clean 2 \
  --size small --jobs 2 > "$work/generate.log"
python3 "$root/bench/blind/score.py" --tofcomp "$tofcomp" --suite "$work/suite" --jobs 2 \
  --json "$work/score.json" > "$work/score.txt"
cat "$work/score.txt"

python3 - "$work/score.json" <<'PY'
import json, sys

score = json.load(open(sys.argv[1]))
right = sum(k["named_right_first"] for k in score["per_kind"].values())
singles = score["totals"]["singles"]
clean, counterparts = score["clean"], score["counterparts"]
failures = score["failures"]
problems = []
if singles != 12:
    problems.append(f"the draw has {singles} single-effect sets, not 12")
if right < 4:
    problems.append(f"{right} of {singles} effects named right first (at least 4)")
if clean["nothing_kept"] != clean["n"]:
    problems.append(f"something kept on {clean['n'] - clean['nothing_kept']} of {clean['n']} clean sets")
if counterparts["nothing_kept"] < counterparts["n"] - 1:
    problems.append(f"something kept on {counterparts['n'] - counterparts['nothing_kept']} of "
                    f"{counterparts['n']} clean counterparts (at most 1)")
if failures:
    problems.append(f"{len(failures)} runs failed: {failures}")
if problems:
    sys.exit("blind suite: " + "; ".join(problems))
print(f"blind suite: {right}/{singles} named right first; clean {clean['nothing_kept']}/{clean['n']}, "
      f"counterparts {counterparts['nothing_kept']}/{counterparts['n']} nothing kept")
PY
