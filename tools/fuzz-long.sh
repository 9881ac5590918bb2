#!/usr/bin/env bash
# The long fuzzing run (not CI): every libFuzzer target of tools/fuzz.sh for 10 minutes (or
# SECONDS_PER_TARGET), as many at once as there are cores, its summary kept in
# build-fuzz/fuzz-long.log. The figures of the last run are in docs/performance.md ("Fuzzing").
# Usage: tools/fuzz-long.sh [SECONDS_PER_TARGET]   (default 600)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds="${1:-600}"
build="${TOFCOMP_FUZZ_BUILD_DIR:-$root/build-fuzz}"
mkdir -p "$build"
{
  echo "tools/fuzz-long.sh $seconds on $(uname -srm), $(nproc) cores, $(date -u +%Y-%m-%dT%H:%MZ)"
  bash "$root/tools/fuzz.sh" "$seconds"
} 2>&1 | tee "$build/fuzz-long.log"
