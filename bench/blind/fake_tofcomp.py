#!/usr/bin/env python3
"""A stand-in for `tofcomp diagnose FILE --json -q`, to test score.py's parsing and failure
handling.  It never reads the truth: what it does with a file is drawn from a hash of the file's
name, so a run is reproducible.

    score.py --tofcomp bench/blind/fake_tofcomp.py --suite DIR --timeout 5

Most files get a well-formed answer with arbitrary labels; some get each kind of failure the
scorer must survive: a non-zero exit, a hang (killed by --timeout), output that is not JSON,
a missing field, a malformed label, a missing window.  FAKE_TOFCOMP_ALL_OK=1 makes every answer
well-formed (and instant).
"""
import hashlib
import json
import os
import sys
import time

VOCAB = [("bias", "time"), ("bias", "time_since_power_on"), ("bias", "heating_rate"),
         ("bias", "ambient"), ("mode_offset", "junction_temperature"),
         ("spread", "junction_temperature"), ("weights", "junction_temperature"),
         ("weights", "time_since_power_on"), ("markov", "none"), ("extra_mode", "none"),
         ("outliers", "none"), ("thermal_state", "none")]


def main():
    a = sys.argv[1:]
    if len(a) < 2 or a[0] != "diagnose" or "--json" not in a:
        print("usage: fake_tofcomp.py diagnose FILE --json [-q]", file=sys.stderr)
        return 2
    path = a[1]
    if not os.path.isfile(path):
        print("error: %s: no such file" % path, file=sys.stderr)
        return 1
    h = hashlib.sha256(os.path.basename(path).encode()).digest()
    r = h[0] % 20
    if os.environ.get("FAKE_TOFCOMP_ALL_OK"):
        r = 19
    print("fake: reading %s" % path, file=sys.stderr)
    if r == 0:
        print("fake: error: simulated crash in the EM", file=sys.stderr)
        return 3
    if r == 1:
        time.sleep(3600)
        return 0
    if r == 2:
        print("this is not json {")
        return 0
    n_kept = h[1] % 3
    kept = []
    for i in range(n_kept):
        p, c = VOCAB[h[2 + i] % len(VOCAB)]
        kept.append({"parameter": p, "covariate": c, "form": "fake", "effect": "fake %s" % p})
    p, c = VOCAB[h[5] % len(VOCAB)]
    best = {"parameter": p, "covariate": c, "form": "fake"} if h[6] % 4 else None
    base = {w: 0.1 + h[7 + i] / 255.0 for i, w in enumerate(("200", "400", "800"))}
    final = {w: v * (0.6 + 0.6 * h[10] / 255.0) for w, v in base.items()}
    doc = {"tool": "fake", "search": {"kept": kept, "best": best,
                                      "mae_mm": {"final": final, "base": base}}}
    if r == 3:
        del doc["search"]["mae_mm"]["final"]
    elif r == 4:
        doc["search"]["kept"] = [{"parameter": "bias"}]
    elif r == 5:
        del doc["search"]["mae_mm"]["base"]["800"]
    elif r == 6:
        del doc["search"]["best"]
    print(json.dumps(doc, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
