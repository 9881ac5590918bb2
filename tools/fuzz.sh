#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (AddressSanitizer and UBSan on) into build-fuzz/ and
# runs each for a bounded time from a generated seed corpus. Exit status is non-zero when a
# fuzzer finds a crash; its reproducer is left in build-fuzz/findings/.
# Usage: tools/fuzz.sh [SECONDS_PER_TARGET]   (default 60)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds="${1:-60}"
build="${TOFCOMP_FUZZ_BUILD_DIR:-$root/build-fuzz}"
# Only the fuzzers and the libraries they link are built: everything else is off.
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DTOFCOMP_BUILD_FUZZERS=ON -DTOFCOMP_BUILD_TESTS=OFF -DTOFCOMP_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" --target lms2xx_decoder_fuzzer lms2xx_make_seed_corpus
corpus="$build/corpus/lms2xx_decoder"
mkdir -p "$corpus" "$build/findings"
"$build/fuzz/lms2xx_make_seed_corpus" "$corpus"
echo "fuzz: lms2xx_decoder_fuzzer for ${seconds} s"
"$build/fuzz/lms2xx_decoder_fuzzer" "$corpus" -max_total_time="$seconds" -max_len=4096 \
  -artifact_prefix="$build/findings/" -print_final_stats=1 2>&1 | tail -n 12
