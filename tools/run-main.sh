#!/usr/bin/env bash
# The main job on its embedded default, no hardware: set up, build, start tofcompd on the
# emulated LMS 200 and its simulated case sensor, show live compensated ranges through the
# client (socket) and the shared-memory ring, stop it; then the paper's §8 offline: simulate
# the default scenario with the digital twin, train a calibration, evaluate the compensation.
# Outputs go to out/ (the daemon's log and recording, data, calibration, the paper's figures).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/tools/setup.sh"
# Only what the job runs, not the tests (tools/run-tests.sh builds those): the two programs and
# the client library the Python client binds.
TOFCOMP_BUILD_TARGETS="tofcompd tofcomp tofcomp_client" bash "$root/tools/build.sh"
build="${TOFCOMP_BUILD_DIR:-$root/build}"
tofcomp="$build/cli/tofcomp"
out="$root/out"
mkdir -p "$out"

# The daemon as installed runs on /etc/tofcompd/tofcompd.yaml; here on the built-in default
# (`tofcompd --print-default-config`). It says where it publishes: as root the system's places
# (/run/tofcompd/tofcompd.sock, the ring /tofcompd), as another user that user's own
# ($XDG_RUNTIME_DIR/tofcompd/tofcompd.sock, the ring /tofcompd.UID).
"$build/daemon/tofcompd" 2> "$out/tofcompd.log" &
daemon=$!
trap 'kill "$daemon" 2>/dev/null || true' EXIT
where=""
for _ in $(seq 100); do
  where=$(grep -m1 -o 'publishing to shm .* and socket .*' "$out/tofcompd.log" || true)
  [ -n "$where" ] && break
  kill -0 "$daemon" 2>/dev/null || { cat "$out/tofcompd.log" >&2; exit 1; }
  sleep 0.1
done
[ -n "$where" ] || { echo "run-main: tofcompd did not start; its log:" >&2; cat "$out/tofcompd.log" >&2; exit 1; }
ring=${where#publishing to shm }
ring=${ring%% and socket *}
socket=${where##* and socket }
for _ in $(seq 100); do [ -S "$socket" ] && break; sleep 0.1; done
"$tofcomp" query --socket "$socket" subscribe -n 3 --every 25 --beams 178:182
"$tofcomp" query --socket "$socket" status
"$tofcomp" shm-dump "$ring" --beams 180:180
# A program of one's own: the Python client of the build tree (client/python, docs/client-library.md).
PYTHONPATH="$build/client/python" python3 - "$socket" <<'PYTHON'
import sys
import tofcomp_client

with tofcomp_client.Connection(sys.argv[1]) as daemon:
    daemon.subscribe(beams=(180, 180), format="json")
    scan = daemon.next_scan(timeout=5.0)
    beam = scan.beams[0]
    print("python: scan %d, beam %d: raw %.0f mm, compensated %.2f mm, window %.2f +- %.2f mm"
          % (scan.sequence, beam.index, beam.raw_mm, beam.compensated_mm, beam.window_mm,
             beam.window_std_mm))
PYTHON
kill -TERM "$daemon"
wait "$daemon"
trap - EXIT
echo "tofcompd stopped; its log: out/tofcompd.log"

"$tofcomp" simulate "$root/config/scenarios/default.yaml" -o "$out/default.csv"
"$tofcomp" train "$out/default.csv" -o "$out/calibration.yaml"
"$tofcomp" evaluate "$out/default.csv" --figures "$out/figures" \
  --calibration-output "$out/calibration-first-half.yaml"
