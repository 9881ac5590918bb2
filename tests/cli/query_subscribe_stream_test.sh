#!/usr/bin/env bash
# `tofcomp query subscribe` without -n streams like `gpspipe -w`, against a real tofcompd on its
# emulated LMS 200: with --json one scan object per line as each arrives (a reader that stops
# after three lines gets them, so none is held to the end), ended with status 0 by the reader
# going away (SIGPIPE) or by SIGINT (Ctrl-C), every line printed whole; `shm-dump --follow`
# streams the ring alike.
set -euo pipefail
tofcomp=$1
tofcompd=$2
root=$3
work=$(mktemp -d)
daemon=""
client=""
cleanup() {
  for pid in $client $daemon; do kill "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; [ -f "$work/tofcompd.log" ] && tail -n 20 "$work/tofcompd.log"; exit 1; }

socket="$work/tofcompd.sock"
ring=/tofcomp-stream-test-$$
cat > "$work/tofcompd.yaml" <<YAML
emulator:
  enabled: true
  scenario: $root/config/scenarios/default.yaml
  time_scale: 1.0
case_sensor:
  backend: simulated
  poll_interval_ms: 200
calibration:
  file: $root/config/calibration.yaml
outputs:
  socket:
    path: $socket
  shm:
    name: $ring
log:
  level: info
  target: stderr
YAML
"$tofcompd" --config "$work/tofcompd.yaml" 2> "$work/tofcompd.log" &
daemon=$!
for _ in $(seq 300); do [ -S "$socket" ] && break; sleep 0.1; done
[ -S "$socket" ] || fail "tofcompd made no socket"

# check_lines FILE: every line a whole scan object, sequences increasing.
check_lines() {
  python3 - "$1" <<'PY'
import json, sys
lines = open(sys.argv[1]).read().splitlines()
assert len(lines) >= 3, lines
scans = [json.loads(line) for line in lines]
sequences = [s["sequence"] for s in scans]
assert sequences == sorted(sequences) and len(set(sequences)) == len(sequences), sequences
assert all([b["index"] for b in s["beams"]] == [180, 181] for s in scans), scans[0]["beams"]
PY
}

# The reader goes away after three lines: the client ends with status 0.
set +e
"$tofcomp" query --socket "$socket" subscribe --json --beams 180:181 | head -n 3 > "$work/piped.jsonl"
statuses=("${PIPESTATUS[@]}")
set -e
[ "${statuses[0]}" = 0 ] || fail "subscribe | head -n 3: tofcomp's status ${statuses[0]}, not 0"
[ "$(wc -l < "$work/piped.jsonl")" = 3 ] || fail "head got $(wc -l < "$work/piped.jsonl") lines"
check_lines "$work/piped.jsonl" || fail "piped lines: $(cat "$work/piped.jsonl")"

# interrupted OUT CMD...: runs CMD into OUT and sends it SIGINT once three lines are out; its
# exit status must be 0.
interrupted() {
  local out=$1
  shift
  "$@" > "$out" &
  client=$!
  for _ in $(seq 300); do [ "$(wc -l < "$out")" -ge 3 ] && break; sleep 0.1; done
  kill -INT "$client"
  set +e
  wait "$client"
  local status=$?
  set -e
  client=""
  [ "$status" = 0 ] || fail "$* after SIGINT: status $status, not 0"
}

# SIGINT once three lines are out: status 0, the lines whole.
interrupted "$work/interrupted.jsonl" "$tofcomp" query --socket "$socket" subscribe --json --beams 180:181
check_lines "$work/interrupted.jsonl" || fail "lines before SIGINT: $(tail -c 300 "$work/interrupted.jsonl")"

# `tofcomp shm-dump --follow --json` streams the ring the same way: {"scan": ...} per line as
# each is read, the summary as the last line when interrupted, status 0 either way.
check_ring_lines() {
  python3 - "$1" "$2" <<'PY'
import json, sys
lines = [json.loads(line) for line in open(sys.argv[1]).read().splitlines()]
scans = [line["scan"] for line in lines if "scan" in line]
assert len(scans) >= 3, lines
sequences = [s["sequence"] for s in scans]
assert sequences == sorted(sequences) and len(set(sequences)) == len(sequences), sequences
assert all([b["index"] for b in s["beams"]] == [180, 181] for s in scans), scans[0]["beams"]
if sys.argv[2] == "summary":
    assert "scan" not in lines[-1] and lines[-1]["scans_read"] == len(scans), lines[-1]
PY
}
set +e
"$tofcomp" shm-dump "$ring" --follow --json --beams 180:181 | head -n 3 > "$work/ring-piped.jsonl"
statuses=("${PIPESTATUS[@]}")
set -e
[ "${statuses[0]}" = 0 ] || fail "shm-dump --follow | head -n 3: tofcomp's status ${statuses[0]}, not 0"
[ "$(wc -l < "$work/ring-piped.jsonl")" = 3 ] || fail "head got $(wc -l < "$work/ring-piped.jsonl") lines"
check_ring_lines "$work/ring-piped.jsonl" none || fail "ring lines: $(cat "$work/ring-piped.jsonl")"
interrupted "$work/ring-interrupted.jsonl" "$tofcomp" shm-dump "$ring" --follow --json --beams 180:181
check_ring_lines "$work/ring-interrupted.jsonl" summary ||
  fail "shm-dump lines before SIGINT: $(tail -c 300 "$work/ring-interrupted.jsonl")"
echo "query subscribe and shm-dump --follow stream: all checks hold"
