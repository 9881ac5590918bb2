#!/usr/bin/env bash
# Every command of the README runs as written (issue 54, item 6). The README's shell blocks are
# fenced ```sh; each is run, in order, by bash in a scratch folder that holds the checkout's
# config/ and the build tree as build/, so that the README's relative paths mean what they mean
# in the repository root, and nothing is written into the checkout. A block fenced ```sh daemon
# is a program the README starts in a shell of its own: it runs in the background until the
# end, and the next block waits until it says where it publishes. Blocks fenced ```sh setup
# (the two commands, installing) are what CI itself runs or need a package manager: they are
# only checked to name files that exist. The README's shape is checked too: at most 150 lines,
# none over 100 characters.
# Usage: readme_commands_test.sh SOURCE_ROOT BUILD_DIR
set -euo pipefail
root=$1
build=$2
readme="$root/README.md"
fail() { echo "FAIL: $*" >&2; exit 1; }

max_lines=150
max_columns=100
lines=$(wc -l < "$readme")
[ "$lines" -le "$max_lines" ] || fail "README.md has $lines lines, more than $max_lines"
long=$(python3 - "$readme" "$max_columns" <<'PY'
import sys
for number, line in enumerate(open(sys.argv[1], encoding="utf-8"), 1):
    if len(line.rstrip("\n")) > int(sys.argv[2]):
        print(f"README.md:{number}: {len(line.rstrip())} characters")
PY
)
[ -z "$long" ] || fail "README.md lines over $max_columns characters:"$'\n'"$long"

work=$(mktemp -d /tmp/tofcomp-readme.XXXXXX)
daemon=""
cleanup() {
  if [ -n "$daemon" ]; then kill -TERM "$daemon" 2>/dev/null || true; wait "$daemon" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT
mkdir "$work/run"
ln -s "$root/config" "$work/run/config"
ln -s "$build" "$work/run/build"

# The blocks, one file each: blocks/N.KIND.sh (KIND: run, daemon or setup).
mkdir "$work/blocks"
awk -v dir="$work/blocks" '
  /^```sh( (daemon|setup))?$/ { n++; kind = ($2 == "" ? "run" : $2); file = sprintf("%s/%02d.%s.sh", dir, n, kind); inside = 1; next }
  /^```/ && inside { inside = 0; close(file); next }
  inside { print > file }
' "$readme"
count=$(find "$work/blocks" -name '*.sh' | wc -l)
[ "$count" -gt 0 ] || fail "no \`\`\`sh blocks in README.md"

# wait_for_daemon LOG: until the daemon says where it publishes; fails with its log when it
# stops first.
wait_for_daemon() {
  for _ in $(seq 300); do
    grep -q "publishing to shm .* and socket " "$1" && return 0
    kill -0 "$daemon" 2>/dev/null || { cat "$1" >&2; fail "the README's daemon stopped"; }
    sleep 0.1
  done
  cat "$1" >&2
  fail "the README's daemon did not start within 30 s"
}

for block in "$work"/blocks/*.sh; do
  name=$(basename "$block")
  case "$name" in
    *.setup.sh)
      # Each file a setup command names (a script, a build file) is where it says.
      for file in $(grep -o '[A-Za-z0-9_./-]*\.\(sh\|cmake\)' "$block"); do
        case "$file" in
          build/*) [ -e "$build/${file#build/}" ] || fail "$name names $file, which the build has not" ;;
          *) [ -e "$root/$file" ] || fail "$name names $file, which the checkout has not" ;;
        esac
      done
      ;;
    *.daemon.sh)
      # One command, exec'd, so that $! is the program and the end stops it.
      [ "$(grep -c . "$block")" = 1 ] || fail "$name: a daemon block holds one command"
      (cd "$work/run" && exec bash -c "exec $(cat "$block")") 2> "$work/daemon.log" &
      daemon=$!
      wait_for_daemon "$work/daemon.log"
      ;;
    *.run.sh)
      echo "== README block $name"
      (cd "$work/run" && bash -euo pipefail "$block") > "$work/$name.out" 2>&1 ||
        { cat "$work/$name.out" >&2; fail "README block $name failed: $(cat "$block")"; }
      tail -n 5 "$work/$name.out"
      ;;
  esac
done
echo "README: $count blocks, every command ran"
