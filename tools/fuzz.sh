#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (AddressSanitizer and UBSan on) into build-fuzz/ and
# runs each for a bounded time from a seed corpus. Exit status is non-zero when a fuzzer finds
# a crash; its reproducer is left in build-fuzz/findings/.
# Usage: tools/fuzz.sh [SECONDS_PER_TARGET]   (default 60)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds="${1:-60}"
build="${TOFCOMP_FUZZ_BUILD_DIR:-$root/build-fuzz}"
# Only the fuzzers and the libraries they link are built: everything else is off.
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DTOFCOMP_BUILD_FUZZERS=ON -DTOFCOMP_BUILD_TESTS=OFF -DTOFCOMP_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" --target lms2xx_decoder_fuzzer lms2xx_make_seed_corpus \
  daemon_config_fuzzer socket_request_fuzzer
mkdir -p "$build/findings"

# fuzz NAME CORPUS [libFuzzer options...]
fuzz() {
  local name=$1 corpus=$2
  shift 2
  echo "fuzz: $name for ${seconds} s"
  "$build/fuzz/$name" "$corpus" -max_total_time="$seconds" -artifact_prefix="$build/findings/" \
    -print_final_stats=1 "$@" 2>&1 | tail -n 12
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
# The first byte of an input picks the parser's length limit (below 128: the default).
printf '\001%s' '{"op":"latest","beams":[0,10],"id":1}' > "$corpus/latest"
printf '\001%s' '{"op":"subscribe","every":5}' > "$corpus/subscribe"
printf '\001%s' '{"op":"recalibrate","args":{"recording":"run.csv"}}' > "$corpus/recalibrate"
printf '\377%s' '{"op":"status","id":"a"}' > "$corpus/status-short-limit"
fuzz socket_request_fuzzer "$corpus" -max_len=4096
