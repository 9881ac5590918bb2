#!/usr/bin/env bash
# End to end through the real binary: `tofcomp emulate` serves the default scenario on a pty and
# `tofcomp scan` brings it up and reads scans. The scenario's wall is 3 m away, so the centre
# beam reads 3000 mm within the twin's bias and noise (a few mm); then the errors a user meets.
set -euo pipefail
tofcomp=$1
root=$2
work=$(mktemp -d)
emulator=""
cleanup() {
  if [ -n "$emulator" ]; then kill "$emulator" 2>/dev/null || true; wait "$emulator" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT

"$tofcomp" -q emulate "$root/config/scenarios/default.yaml" --link "$work/lms200" \
  --time-scale 0 --duration 120 > "$work/emulate.out" &
emulator=$!
for _ in $(seq 100); do [ -s "$work/emulate.out" ] && break; sleep 0.1; done
device=$(head -n 1 "$work/emulate.out")
[ -e "$device" ] || { echo "emulate printed no device path: '$device'"; exit 1; }

"$tofcomp" -q scan "$work/lms200" -n 20 --baud 38400 --json > "$work/scan.json"
python3 - "$work/scan.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
scans = r["scans"]
assert len(scans) == 20, len(scans)
assert [s["sequence"] for s in scans] == list(range(20)), [s["sequence"] for s in scans]
for s in scans:
    assert s["values"] == 361 and len(s["codes"]) == 361, s["values"]
    assert s["units"] == "mm", s["units"]
    centre = s["codes"][180]
    assert 2980 <= centre <= 3020, centre
print("scan through the emulated device holds")
PY

# A port that does not exist: exit status 1 and a message naming it.
if "$tofcomp" -q scan "$work/absent" -n 1 --timeout 0.5 2> "$work/err"; then
  echo "scan of a missing port succeeded"; exit 1
fi
grep -q "absent: No such file or directory" "$work/err"
# A bad variant: exit status 1 with the allowed values.
if "$tofcomp" -q scan "$work/lms200" --variant 90:1 2> "$work/err"; then exit 1; fi
grep -q "180:1, 180:0.5" "$work/err"
echo "emulate and scan: all checks hold"
