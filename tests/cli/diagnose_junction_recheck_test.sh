#!/usr/bin/env bash
# The junction re-checked after the model search keeps a term (calibration/junction_recheck.hpp),
# through the real binary, on the twin's warm-up (3 mm decaying in 300 s after each power-on)
# with a junction far from the datasheet's (tests/cli/warm-up-slow-junction.yaml): training takes
# the junction from the ranges, the search keeps a term, so the re-check runs; it reports both
# starts (their junctions and what each search kept) and keeps the one whose final model has the
# larger held-out log-likelihood per range over the ranges both scored; the search reported, the
# trained model and the calibration written are that start's (its junction's P·R1 and R1·C1 in
# the file), or the structure re-check's that follows when it chose a structure again; the warm-up is kept first, near the twin's amplitude and time constant. Then data
# without an effect (tests/cli/clean-short.yaml): nothing kept, so no re-check.
set -euo pipefail
tofcomp=$1
root=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$tofcomp" -q simulate "$root/tests/cli/warm-up-slow-junction.yaml" -o "$work/warm.csv"
"$tofcomp" -q diagnose "$work/warm.csv" --json --calibration-output "$work/warm.yaml" > "$work/warm.json"
"$tofcomp" -q simulate "$root/tests/cli/clean-short.yaml" -o "$work/clean.csv"
"$tofcomp" -q diagnose "$work/clean.csv" --json > "$work/clean.json"

python3 - "$work" <<'PY'
import json, re, sys

def expect(ok, message):
    if not ok:
        sys.exit(message)

work = sys.argv[1]
doc = json.load(open(f"{work}/warm.json"))
r = doc["junction_recheck"]
expect(r is not None and r["error"] is None, f"no re-check: {r}")
ranges, case_log = r["from_ranges"], r["from_case_log"]
expect(ranges["kept"], "the re-check ran though the search from the ranges' junction kept nothing")
scored = doc["search"]["held_out_log_likelihood"]["scored_ranges"]
expect(0 < r["common_ranges"] <= scored, f"{r['common_ranges']} common ranges, {scored} scored")
chosen = "case_log" if r["from_case_log_per_range"] > r["from_ranges_per_range"] else "ranges"
expect(r["chosen"] == chosen, f"chose {r['chosen']} on {r['from_ranges_per_range']} against "
       f"{r['from_case_log_per_range']}")
start = case_log if chosen == "case_log" else ranges
# The search reported is the chosen start's, or, when the structure re-check that follows
# (calibration/structure_recheck.hpp) chose a structure again from it, that re-check's.
s = doc["structure_recheck"]
restructured = s is not None and s["chosen"] == "again"
if s is not None:
    expect(s["kept_first"] == start["kept"], f"the structure re-check started from {s['kept_first']}")
reported = s["kept_again"] if restructured else start["kept"]
expect([k["term"] for k in doc["search"]["kept"]] == reported,
       f"reported {doc['search']['kept']}, the chosen start (and re-check) kept {reported}")
# The calibration written carries the chosen start's junction (trained again at a re-checked
# structure from the case log's, the same; from the ranges', judged again at that structure).
text = open(f"{work}/warm.yaml").read()
value = lambda key: float(re.search(rf"^  {key}: ([-\d.e+]+)$", text, re.M).group(1))
rise, tau = value("power_w") * value("r1_k_per_w"), value("r1_k_per_w") * value("c1_j_per_k")
if chosen == "case_log" or not restructured:
    expect(abs(rise / start["rise_k"] - 1) < 1e-6 and abs(tau / start["time_constant_s"] - 1) < 1e-6,
           f"the calibration's junction {rise} K, {tau} s is not the {chosen} start's {start}")
# The warm-up first, near the twin's 3 mm and 300 s.
first = doc["search"]["kept"][0]
expect((first["parameter"], first["covariate"]) == ("bias", "time_since_power_on"),
       f"kept first: {first}")
terms = text[text.index("  terms:"):]
if first["form"] == "decay":
    amplitude = float(re.search(r"coefficients_mm: \[([-\d.e+]+)\]", terms).group(1))
    time_constant = float(re.search(r"time_constant_s: ([-\d.e+]+)", terms).group(1))
    expect(2.25 < amplitude < 3.75, f"warm-up amplitude {amplitude} mm (the twin's 3)")
    expect(150 < time_constant < 450, f"warm-up time constant {time_constant} s (the twin's 300)")

clean = json.load(open(f"{work}/clean.json"))
expect(not clean["search"]["kept"], f"kept on clean data: {clean['search']['kept']}")
expect(clean["junction_recheck"] is None, "a re-check on data where the search kept nothing")
print(f"re-check: {chosen} chosen ({r['from_ranges_per_range']:.4f} against "
      f"{r['from_case_log_per_range']:.4f} nats a range over {r['common_ranges']} ranges)")
PY
