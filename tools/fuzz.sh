#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (AddressSanitizer and UBSan on) into build-fuzz/ and
# runs each for a bounded time from a seed corpus, as many at once as there are cores
# (TOFCOMP_JOBS), each on one. Exit status is non-zero when a fuzzer finds a crash; its
# reproducer is left in build-fuzz/findings/. The default keeps CI's budget (six targets, 30 s
# each: 90 s on two cores); tools/fuzz-long.sh runs each for 10 minutes.
# Usage: tools/fuzz.sh [SECONDS_PER_TARGET]   (default 30)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds="${1:-30}"
build="${TOFCOMP_FUZZ_BUILD_DIR:-$root/build-fuzz}"
# Only the fuzzers and the libraries they link are built: everything else is off.
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DTOFCOMP_BUILD_FUZZERS=ON -DTOFCOMP_BUILD_TESTS=OFF -DTOFCOMP_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" --parallel "${TOFCOMP_JOBS:-$(nproc)}" --target lms2xx_decoder_fuzzer lms2xx_make_seed_corpus \
  daemon_config_fuzzer socket_request_fuzzer measured_data_csv_fuzzer calibration_file_fuzzer \
  scenario_yaml_fuzzer
mkdir -p "$build/findings"
logs="$build/logs"
rm -rf "$logs"
mkdir -p "$logs"
parallel="${TOFCOMP_JOBS:-$(nproc)}"
started=()

# fuzz NAME CORPUS [libFuzzer options...]: starts the target in the background, once fewer than
# $parallel run; its output goes to logs/NAME.log and its exit status to logs/NAME.status.
fuzz() {
  local name=$1 corpus=$2
  shift 2
  while [ "$(jobs -rp | wc -l)" -ge "$parallel" ]; do wait -n || true; done
  echo "fuzz: $name for ${seconds} s"
  (
    status=0
    "$build/fuzz/$name" "$corpus" -max_total_time="$seconds" -artifact_prefix="$build/findings/" \
      -print_final_stats=1 "$@" > "$logs/$name.log" 2>&1 || status=$?
    echo "$status" > "$logs/$name.status"
  ) &
  started+=("$name")
}

corpus="$build/corpus/lms2xx_decoder"
mkdir -p "$corpus"
"$build/fuzz/lms2xx_make_seed_corpus" "$corpus"
fuzz lms2xx_decoder_fuzzer "$corpus" -max_len=4096

corpus="$build/corpus/daemon_config"
mkdir -p "$corpus"
cp "$root"/config/tofcompd*.yaml "$corpus/"
fuzz daemon_config_fuzzer "$corpus" -max_len=8192 -timeout=10

corpus="$build/corpus/socket_request"
mkdir -p "$corpus"
# The first byte of an input picks the parser's length limit (0-63: the default, 64-127: the
# largest allowed, 1 MiB, 128-255: a small one).
printf '\001%s' '{"op":"latest","beams":[0,10],"id":1}' > "$corpus/latest"
printf '\001%s' '{"op":"subscribe","every":5}' > "$corpus/subscribe"
printf '\001%s' '{"op":"recalibrate","args":{"recording":"run.csv"}}' > "$corpus/recalibrate"
printf '\377%s' '{"op":"status","id":"a"}' > "$corpus/status-short-limit"
printf '\100%s' '{"op":"recalibrate","args":{"a":[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]}}' \
  > "$corpus/deep-largest-limit"
fuzz socket_request_fuzzer "$corpus" -max_len=1048577

corpus="$build/corpus/measured_data_csv"
mkdir -p "$corpus"
printf '# sensor: LMS200\ntime_s,range_mm,case_temp_c,power,ambient_c,true_range_mm\n0,,22,1,22,\n0,2997,,,,3000\n0.25,3001,,,,\n1,,22.0625,,,\n2,,,0,,\n' \
  > "$corpus/format-example"
printf 'time_s,range_mm,beam,operator\n0,3000,180,ann\n0.0133,3001,181,\n' > "$corpus/beams"
fuzz measured_data_csv_fuzzer "$corpus" -max_len=8192 -timeout=10

corpus="$build/corpus/calibration_file"
mkdir -p "$corpus"
cp "$root/config/calibration.yaml" "$corpus/"
fuzz calibration_file_fuzzer "$corpus" -max_len=16384 -timeout=10

corpus="$build/corpus/scenario_yaml"
mkdir -p "$corpus"
cp "$root"/config/scenarios/*.yaml "$corpus/"
fuzz scenario_yaml_fuzzer "$corpus" -max_len=8192 -timeout=10

wait
failed=0
for name in "${started[@]}"; do
  echo "== $name (exit status $(cat "$logs/$name.status"))"
  tail -n 12 "$logs/$name.log"
  [ "$(cat "$logs/$name.status")" = 0 ] || failed=1
done
exit "$failed"
