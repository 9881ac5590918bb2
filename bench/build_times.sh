#!/usr/bin/env bash
# Times what a newcomer waits for (docs/performance.md, "Building and testing"): a fresh clone
# of this checkout's HEAD in a temporary directory, then the README's commands in it, each timed.
#   bench/build_times.sh warm main    bash tools/run-main.sh, ccache's own cache as it is
#   bench/build_times.sh cold main    the same with an empty cache (a temporary CCACHE_DIR)
#   bench/build_times.sh warm tests   bash tools/run-tests.sh (CI), then ctest -L fast again
#   bench/build_times.sh cold tests   the same with an empty cache
# Packages are expected installed (tools/setup.sh). Prints one line per step: its seconds.
# BUILD_TIMES_KEEP=DIR keeps what says where the time went: ninja's log of each build
# (build.ninja_log, fuzz.ninja_log) and ctest's cost of each test (ctest_costs.txt).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cache=${1:?cold or warm}
job=${2:?main or tests}
work=$(mktemp -d /tmp/tofcomp-build-times.XXXXXX)
keep=${BUILD_TIMES_KEEP:-}
# keep_logs: copies the clone's build and test logs into $keep (when set) before the clone goes.
keep_logs() {
  [ -n "$keep" ] || return 0
  mkdir -p "$keep"
  cp "$work/tofcomp/build/.ninja_log" "$keep/build.ninja_log" 2>/dev/null || true
  cp "$work/tofcomp/build-fuzz/.ninja_log" "$keep/fuzz.ninja_log" 2>/dev/null || true
  cp "$work/tofcomp/build/Testing/Temporary/CTestCostData.txt" "$keep/ctest_costs.txt" 2>/dev/null || true
  cp "$work"/*.log "$keep/" 2>/dev/null || true
}
trap 'keep_logs; rm -rf "$work"' EXIT
git clone -q "$root" "$work/tofcomp"
clone="$work/tofcomp"
# The tests read ../shared (the paper's foreign data sets) beside the checkout, as in CI's.
if [ -d "$root/../shared" ]; then ln -s "$(cd "$root/../shared" && pwd)" "$work/shared"; fi
case "$cache" in
  cold) export CCACHE_DIR="$work/ccache" ;;
  warm) ;;
  *) echo "build_times: the first argument is cold or warm" >&2; exit 2 ;;
esac

# step NAME COMMAND...: runs it in the clone, its output to $work/NAME.log, prints its seconds.
step() {
  local name=$1
  shift
  local start end
  start=$(date +%s.%N)
  if ! (cd "$clone" && "$@") > "$work/$name.log" 2>&1; then
    echo "build_times: $name failed; its log:" >&2
    tail -n 40 "$work/$name.log" >&2
    exit 1
  fi
  end=$(date +%s.%N)
  awk -v name="$name" -v a="$start" -v b="$end" 'BEGIN { printf "%-28s %8.1f s\n", name, b - a }'
}

echo "$cache cache, $(nproc) cores, $(git -C "$root" rev-parse --short HEAD)"
case "$job" in
  main) step run-main.sh bash tools/run-main.sh ;;
  tests)
    step run-tests.sh bash tools/run-tests.sh
    step "ctest -L fast" bash -c 'cd build && ctest -L fast --parallel "$(nproc)"'
    ;;
  *) echo "build_times: the second argument is main or tests" >&2; exit 2 ;;
esac
ccache --show-stats 2>/dev/null | grep -E '^ *(Hits|Misses):' || true
