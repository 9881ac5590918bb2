#!/usr/bin/env bash
# The structure of Eq. 8 re-checked after the model search keeps a term on the bias
# (calibration/structure_recheck.hpp), through the real binary: on the twin's default record
# with a drift of 3 mm/h (tests/cli/strong-time-drift.yaml) training takes more modes than the
# same record without the drift; the search keeps the drift, so the re-check runs, chooses the
# structure again on the ranges less the drift's bias, and, finding the modes of the record
# without it, trains and searches at it. `--json` and the text report it, and the model reported
# is the re-check's. Then the record without the drift (the default scenario): nothing kept, no
# re-check, and the modes the re-check must reach.
set -euo pipefail
tofcomp=$1
root=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$tofcomp" -q simulate "$root/tests/cli/strong-time-drift.yaml" -o "$work/drift.csv"
"$tofcomp" -q diagnose "$work/drift.csv" --json > "$work/drift.json"
"$tofcomp" -q diagnose "$work/drift.csv" > "$work/drift.txt"
"$tofcomp" -q simulate "$root/config/scenarios/default.yaml" -o "$work/clean.csv"
"$tofcomp" -q diagnose "$work/clean.csv" --json > "$work/clean.json"

python3 - "$work" <<'PY'
import json, sys

def expect(ok, message):
    if not ok:
        sys.exit(message)

work = sys.argv[1]
clean = json.load(open(f"{work}/clean.json"))
expect(not clean["search"]["kept"], f"kept on the record without the drift: {clean['search']['kept']}")
expect(clean["structure_recheck"] is None, "a re-check on data where the search kept nothing")
modes = clean["trained_model"]["modes"]

doc = json.load(open(f"{work}/drift.json"))
r = doc["structure_recheck"]
expect(r is not None and r["error"] is None, f"no re-check: {r}")
expect(r["first_modes"] != modes, f"the drift did not move training's modes ({r['first']})")
expect([t for t in r["bias_terms"] if t.startswith("bias x time ")], f"bias terms {r['bias_terms']}")
expect(r["again_modes"] == modes, f"chosen again: {r['again']}, without the drift {modes} modes")
expect(r["searched_again"] and r["chosen"] == "again", f"not chosen: {r}")
expect(doc["trained_model"]["modes"] == modes, f"reported {doc['trained_model']['modes']} modes")
first = doc["search"]["kept"][0]
expect((first["parameter"], first["covariate"]) == ("bias", "time"), f"kept first: {first}")
expect([k["term"] for k in doc["search"]["kept"]] == r["kept_again"],
       f"reported {doc['search']['kept']}, the re-check's search kept {r['kept_again']}")
# The first search paused at its first term on the bias when the junction's re-check, which
# needs whole searches, could not run (training kept the case log's junction).
expect(r["first_search_paused"] == (doc["junction_recheck"] is None),
       f"paused {r['first_search_paused']}, junction re-check {doc['junction_recheck']}")
if r["first_search_paused"]:
    expect(len(r["bias_terms"]) == 1 and r["kept_first"][-1] == r["bias_terms"][0],
           f"paused after {r['kept_first']}, bias {r['bias_terms']}")
text = open(f"{work}/drift.txt").read()
expect("the structure re-checked: training chose " + r["first"] in text, "no re-check in the text")
print(f"re-check: {r['first']} -> {r['again']} ({modes} modes without the drift)")
PY
