#!/usr/bin/env bash
# Configures and builds tofcomp into build/ (Release with debug info, warnings as errors).
# Usage: tools/build.sh [extra cmake -D options]
# TOFCOMP_BUILD_TARGETS: build only these targets (space separated), e.g. "tofcompd tofcomp" for
# tools/run-main.sh; default: every target, tests included.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build="${TOFCOMP_BUILD_DIR:-$root/build}"
jobs="${TOFCOMP_JOBS:-$(nproc)}"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTOFCOMP_WERROR=ON "$@" >/dev/null
targets=()
for target in ${TOFCOMP_BUILD_TARGETS:-}; do targets+=(--target "$target"); done
cmake --build "$build" --parallel "$jobs" "${targets[@]}"
