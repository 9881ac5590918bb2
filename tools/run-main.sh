#!/usr/bin/env bash
# The main job on its embedded default, no hardware: set up, build, start tofcompd on the
# emulated LMS 200 and its simulated case sensor, show live compensated ranges through the
# client (socket) and the shared-memory ring, stop it; then the paper's §8 offline: simulate
# the default scenario with the digital twin, train a calibration, evaluate the compensation.
# Outputs go to out/ (the daemon's log and recording, data, calibration, figure data).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/tools/setup.sh"
# Only the two programs the job runs, not the tests (tools/run-tests.sh builds those).
TOFCOMP_BUILD_TARGETS="tofcompd tofcomp" bash "$root/tools/build.sh"
build="${TOFCOMP_BUILD_DIR:-$root/build}"
tofcomp="$build/cli/tofcomp"
out="$root/out"
mkdir -p "$out"

# The daemon as installed runs on /etc/tofcompd/tofcompd.yaml; here on the built-in default
# (`tofcompd --print-default-config`), its socket at /run/tofcompd/tofcompd.sock.
"$build/daemon/tofcompd" 2> "$out/tofcompd.log" &
daemon=$!
trap 'kill "$daemon" 2>/dev/null || true' EXIT
socket=/run/tofcompd/tofcompd.sock
for _ in $(seq 100); do [ -S "$socket" ] && break; sleep 0.1; done
"$tofcomp" query subscribe -n 3 --every 25 --beams 178:182
"$tofcomp" query status
"$tofcomp" shm-dump --beams 180:180
kill -TERM "$daemon"
wait "$daemon"
trap - EXIT
echo "tofcompd stopped; its log: out/tofcompd.log"

"$tofcomp" simulate "$root/config/scenarios/default.yaml" -o "$out/default.csv"
"$tofcomp" train "$out/default.csv" -o "$out/calibration.yaml"
"$tofcomp" evaluate "$out/default.csv" --figures "$out/figures" \
  --calibration-output "$out/calibration-first-half.yaml"
