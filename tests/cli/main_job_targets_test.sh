#!/usr/bin/env bash
# tools/run-main.sh builds only what the main job runs: the targets it gives tools/build.sh are
# tofcompd, tofcomp and the client library, and building them builds no test (ninja's commands for them link no
# *_test), while building everything, as tools/run-tests.sh does, does.
set -euo pipefail
root=$1
build=$2
fail() { echo "FAIL: $*"; exit 1; }

targets=$(sed -n 's/^TOFCOMP_BUILD_TARGETS="\([^"]*\)" bash .*tools\/build.sh.*/\1/p' "$root/tools/run-main.sh")
[ "$targets" = "tofcompd tofcomp tofcomp_client" ] || fail "run-main.sh builds '$targets'"
grep -q 'TOFCOMP_BUILD_TARGETS' "$root/tools/run-tests.sh" && fail "run-tests.sh builds only some targets"
# shellcheck disable=SC2086
ninja -C "$build" -t commands $targets > "$build/main-job-commands.txt"
grep -q -- "-o cli/tofcomp " "$build/main-job-commands.txt" || fail "no link of tofcomp"
grep -q -- "-o daemon/tofcompd " "$build/main-job-commands.txt" || fail "no link of tofcompd"
if grep -q -- "-o tests/[^ ]*_test " "$build/main-job-commands.txt"; then
  fail "the main job's build links a test: $(grep -o -- "-o tests/[^ ]*_test " "$build/main-job-commands.txt" | head -3)"
fi
ninja -C "$build" -t commands all > "$build/main-job-commands.txt"
grep -q -- "-o tests/[^ ]*_test " "$build/main-job-commands.txt" || fail "the full build links no test"
rm -f "$build/main-job-commands.txt"
echo "main job's targets: all checks hold"
