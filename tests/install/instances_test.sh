#!/usr/bin/env bash
# Several scanners on one host: two tofcompd on the built-in default (each its own emulated
# LMS 200) at once, started as an ordinary user would, with --socket and --shm in a directory of
# their own; each answers `tofcomp query status` on its own socket, publishes to its own ring,
# and names both in its stats. Then, where /run is writable (root, as in CI), two daemons with
# --instance NAME, found by `tofcomp query --instance NAME` and `tofcomp shm-dump --instance NAME`.
set -euo pipefail
build=$1
tofcompd="$build/daemon/tofcompd"
tofcomp="$build/cli/tofcomp"
work=$(mktemp -d)
tag="ctest-$$"
pids=()
instances=()
cleanup() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  for name in "${instances[@]}"; do rm -rf "/run/tofcompd/$name"; done
  rm -f "/dev/shm/$tag-"* "/dev/shm/tofcompd-$tag-"*
  rm -rf "$work"
}
trap cleanup EXIT
deadline_s=60

# Waits until `tofcomp query ARGS status` says the daemon publishes scans, or fails after the
# deadline.
wait_for_answer() {
  local log=$1; shift
  for _ in $(seq $((deadline_s * 10))); do
    if "$tofcomp" query "$@" --timeout 1 status 2> /dev/null |
        grep '^status.state: publishing' > /dev/null; then
      return 0
    fi
    sleep 0.1
  done
  echo "no answer from tofcompd ($*) within ${deadline_s} s; its log:"; cat "$log"; exit 1
}

# The value of a "key: value" line of `tofcomp query ... stats` (text).
stat() { "$tofcomp" query "${@:2}" stats | sed -n "s|^$1: ||p"; }

for side in left right; do
  "$tofcompd" --socket "$work/$side.sock" --shm "/$tag-$side" > "$work/$side.log" 2>&1 &
  pids+=($!)
done
for side in left right; do
  wait_for_answer "$work/$side.log" --socket "$work/$side.sock"
done
for side in left right; do
  [ "$(stat stats.shm.name --socket "$work/$side.sock")" = "/$tag-$side" ] ||
    { echo "$side: stats name another ring"; "$tofcomp" query --socket "$work/$side.sock" stats; exit 1; }
  # Each ring is written by its own daemon: the writer pid shm-dump reads is that daemon's.
  pid=$("$tofcomp" shm-dump "/$tag-$side" --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["ring"]["writer_pid"])')
  [ "$side" = left ] && want=${pids[0]} || want=${pids[1]}
  [ "$pid" = "$want" ] || { echo "$side: ring written by pid $pid, not $want"; exit 1; }
done
# Their lock files are their own: each holds the one beside its socket.
test -e "$work/left.lock" && test -e "$work/right.lock"
echo "two daemons with --socket and --shm each answer on their own socket and ring"

if [ -w /run ]; then
  for side in a b; do
    name="$tag-$side"
    instances+=("$name")
    "$tofcompd" --instance "$name" > "$work/$name.log" 2>&1 &
    pids+=($!)
  done
  for name in "${instances[@]}"; do
    wait_for_answer "$work/$name.log" --instance "$name"
    test -S "/run/tofcompd/$name/tofcompd.sock"
    [ "$(stat stats.shm.name --instance "$name")" = "/tofcompd-$name" ]
    "$tofcomp" shm-dump --instance "$name" > "$work/$name.dump"
    grep -q "^ring /tofcompd-$name: writer pid" "$work/$name.dump"
    # The log names the instance on every line.
    grep -q " tofcompd@$name info socket: listening on /run/tofcompd/$name/tofcompd.sock" "$work/$name.log" ||
      { cat "$work/$name.log"; exit 1; }
  done
  echo "two instances answer on /run/tofcompd/NAME/tofcompd.sock and /tofcompd-NAME"
else
  echo "/run is not writable by this user: --instance not run (the unit's RuntimeDirectory makes it)"
fi
# A name that is no instance name is refused before anything starts.
if "$tofcomp" query --instance ../etc status 2> "$work/err"; then echo "bad name accepted"; exit 1; fi
grep -q "instance name '../etc'" "$work/err"
echo "instances hold"
