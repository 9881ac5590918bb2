#!/usr/bin/env bash
# `tofcomp diagnose` names the model its search starts from, through the real binary: on the
# twin's data drawn with three lasing modes (tests/cli/three-modes.yaml; the default scenario has
# two), the trained model has three modes chosen from the data, with the twin's spreads, weights
# and gaps between offsets (the common offset is θ's, not the modes'), three modes predicting
# held-out ranges better than two, and the held-out log-likelihood per scored range the twin's
# own (minus the entropy of its rounded ranges); the text says the same as the JSON. Then from a calibration
# trained with --modes 2: two modes, as given, and the d̂ windows longer than this short record's
# held-out blocks listed as not compared.
set -euo pipefail
tofcomp=$1
root=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$tofcomp" -q simulate "$root/tests/cli/three-modes.yaml" -o "$work/data.csv"
"$tofcomp" -q diagnose "$work/data.csv" --json > "$work/chosen.json"
"$tofcomp" -q diagnose "$work/data.csv" > "$work/chosen.txt"
"$tofcomp" -q train "$work/data.csv" --modes 2 -o "$work/two.yaml" > /dev/null
"$tofcomp" -q diagnose "$work/data.csv" --calibration "$work/two.yaml" --json > "$work/given.json"
"$tofcomp" -q diagnose "$work/data.csv" --calibration "$work/two.yaml" > "$work/given.txt"

python3 - "$root/tests/cli/three-modes.yaml" "$work" <<'PY'
import json, re, sys

def expect(ok, message):
    if not ok:
        sys.exit(message)

# The twin's modes, from the scenario (one flow mapping a line).
truth = [dict((k, float(v)) for k, v in re.findall(r"(\w+): ([-\d.]+)", line))
         for line in open(sys.argv[1]) if line.strip().startswith("- {offset_mm")]
expect(len(truth) == 3, f"the scenario lists {len(truth)} modes")
work = sys.argv[2]
chosen = json.load(open(f"{work}/chosen.json"))["trained_model"]
expect(chosen["modes"] == 3 and len(chosen["mixture"]) == 3, f"trained model: {chosen}")
expect(chosen["chosen_from_data"] is True, "the structure was not reported as chosen from the data")
by_modes = chosen["best_held_out_log_likelihood_by_modes"]
expect(by_modes["3"] > by_modes["2"], f"three modes do not predict better than two: {by_modes}")
fitted = sorted(chosen["mixture"], key=lambda m: m["offset_mm"])
for i, (f, t) in enumerate(zip(fitted, truth)):
    expect(abs(f["std_mm"] / t["std_mm"] - 1) < 0.15, f"mode {i + 1} spread {f['std_mm']} vs {t['std_mm']}")
    expect(abs(f["weight"] - t["weight"]) < 0.04, f"mode {i + 1} weight {f['weight']} vs {t['weight']}")
for i in range(2):
    gap, true_gap = (fitted[i + 1]["offset_mm"] - fitted[i]["offset_mm"],
                     truth[i + 1]["offset_mm"] - truth[i]["offset_mm"])
    expect(abs(gap - true_gap) < 0.3, f"gap between modes {i + 1} and {i + 2}: {gap} vs {true_gap}")

# The held-out log-likelihood per scored range is the twin's: minus the entropy of its rounded
# ranges (the mixture shifted by a uniform fraction of a mm, as d + Hθ falls between whole mm).
import math
def rounded_probability(k, shift):
    cdf = lambda x, m: sum(m_["weight"] * 0.5 * (1 + math.erf((x - m_["offset_mm"]) / (m_["std_mm"] * math.sqrt(2)))) for m_ in m)
    return cdf(k + 0.5 - shift, truth) - cdf(k - 0.5 - shift, truth)
shifts = [(i + 0.5) / 20 for i in range(20)]
expected = sum(sum(p * math.log(p) for p in (rounded_probability(k, u) for k in range(-30, 31)) if p > 0)
               for u in shifts) / len(shifts)
search = json.load(open(f"{work}/chosen.json"))["search"]
held = search["held_out_log_likelihood"]
ranges = sum(1 for line in open(f"{work}/data.csv") if not line.startswith(("#", "time_s")) and line.split(",")[1])
expect(ranges // 2 < held["scored_ranges"] <= ranges, f"{held['scored_ranges']} scored of {ranges} ranges")
per_range = held["base"] / held["scored_ranges"]
expect(abs(per_range - expected) < 0.03, f"held-out {per_range:.4f} nats a range, the twin's {expected:.4f}")
if not search["kept"]:
    expect(held["final"] == held["base"], "nothing kept, yet the final model scores otherwise")

text = open(f"{work}/chosen.txt").read()
line = next((l for l in text.splitlines() if l.startswith("the trained model")), "")
expect(f"basis {chosen['basis']}, 3 modes (chosen from the data" in line, f"text: {line!r}")
for count, value in by_modes.items():
    expect(f"{count} mode{'s' if count != '1' else ''}: {value:.4f}" in line,
           f"text lacks {count} modes' held-out figure: {line!r}")

given = json.load(open(f"{work}/given.json"))["trained_model"]
expect(given["modes"] == 2 and given["chosen_from_data"] is False, f"from --calibration: {given}")
expect(given["best_held_out_log_likelihood_by_modes"] is None, "held-out figures for a given model")
given_text = open(f"{work}/given.txt").read()
expect(re.search(r"^the trained model \(the search's start\): basis .*, 2 modes \(as given\)$",
                 given_text, re.M), "the text does not say the two modes were given")
# The record is short for the default windows: the search's blocks hold ranges // 20 (two folds
# of ten blocks each) when that is below the longest window, and a window longer than a block is
# not compared: left out of mae_mm, listed, and said in the text.
search = json.load(open(f"{work}/given.json"))["search"]
block = min(800, ranges // 20)
expect(search["block"] == block, f"blocks of {search['block']} ranges, expected {block}")
longer = [w for w in (200, 400, 800) if w > block]
expect(longer, f"blocks of {block} ranges hold every default window: the check below is empty")
expect(search["windows_not_compared"] == longer, f"not compared: {search['windows_not_compared']}")
for part in ("base", "final"):
    expect(sorted(search["mae_mm"][part], key=int) == [str(w) for w in (200, 400, 800) if w <= block],
           f"mae_mm.{part}: {search['mae_mm'][part]}")
for w in longer:
    expect(f"window {w:>4}: not compared: longer than this record's held-out blocks ({block} ranges)"
           in given_text, f"the text does not say window {w} was not compared")
print("diagnose names its trained model: 3 modes chosen from the data, 2 as given; "
      f"windows {longer} not compared on blocks of {block} ranges")
PY
