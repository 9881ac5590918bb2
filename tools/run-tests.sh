#!/usr/bin/env bash
# The one command that sets up, builds and runs every test (it is what CI runs).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/tools/setup.sh"
bash "$root/tools/build.sh"
cd "${TOFCOMP_BUILD_DIR:-$root/build}"
ctest --output-on-failure --parallel "${TOFCOMP_JOBS:-$(nproc)}"
# The fuzzers, for a bounded time each (TOFCOMP_FUZZ_SECONDS, default 30: six targets, 3 minutes).
bash "$root/tools/fuzz.sh" "${TOFCOMP_FUZZ_SECONDS:-30}"
