#!/usr/bin/env bash
# tofcompd started by socket activation (systemd/tofcompd.socket; docs/deployment.md): with
# systemd-socket-activate listening at a path, the first client's connection starts tofcompd,
# which serves that socket (sd_listen_fds) instead of binding its own, answers the client that
# waited in the socket's queue, and leaves the socket file to the manager when it stops. Passed
# two sockets, or a datagram socket, it stops at start naming what it was given.
# Usage: socket_activation_test.sh TOFCOMPD TOFCOMP
set -euo pipefail
tofcompd=$1
tofcomp=$2
fail() { echo "FAIL: $*" >&2; exit 1; }

work=$(mktemp -d /tmp/tofcomp-activation.XXXXXX)
shm="/tofcomp-activation-$$"
activator=""
cleanup() {
  [ -n "$activator" ] && kill "$activator" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

# wait_for_socket PATH: until the manager has bound PATH.
wait_for_socket() {
  for _ in $(seq 200); do
    [ -S "$1" ] && return 0
    kill -0 "$activator" 2>/dev/null || fail "systemd-socket-activate stopped before binding $1"
    sleep 0.1
  done
  fail "no socket at $1 after 20 s"
}

# 1. One stream socket. systemd-socket-activate binds it, waits for a connection, then becomes
# tofcompd (it execs the daemon in its own process: $! is the daemon from then on).
socket="$work/tofcompd.sock"
systemd-socket-activate -l "$socket" "$tofcompd" -d --socket "$socket" --shm "$shm" \
  2> "$work/daemon.log" &
activator=$!
wait_for_socket "$socket"
inode=$(stat -c %i "$socket")
# (The log holds the activator's own "Listening on ..." line so far.)
if grep -q "starting" "$work/daemon.log"; then
  cat "$work/daemon.log" >&2
  fail "tofcompd ran before a client came"
fi
# This connection starts the daemon and waits in the queue until it serves; --timeout covers the
# daemon's start on a loaded machine.
status=$("$tofcomp" query --socket "$socket" --timeout 60 status) ||
  { cat "$work/daemon.log" >&2; fail "query status through the activated socket failed"; }
echo "$status" | grep -q '^status.state: ' || fail "no state in the answer: $status"
grep -q "listening on $socket, the socket the service manager passed" "$work/daemon.log" ||
  { cat "$work/daemon.log" >&2; fail "the log does not say it serves the passed socket"; }
grep -q "publishing to shm $shm and socket $socket" "$work/daemon.log" ||
  { cat "$work/daemon.log" >&2; fail "the log does not say where it publishes"; }
[ "$(stat -c %i "$socket")" = "$inode" ] || fail "the daemon replaced the manager's socket file"
kill -TERM "$activator"
wait "$activator" || fail "tofcompd did not stop cleanly (status $?)"
activator=""
[ -S "$socket" ] || fail "tofcompd removed the socket file the manager made"

# 2. A socket at another path than the configuration's: served, and the log names both.
other="$work/other.sock"
systemd-socket-activate -l "$other" "$tofcompd" -d --socket "$socket.configured" --shm "$shm" \
  2> "$work/other.log" &
activator=$!
wait_for_socket "$other"
"$tofcomp" query --socket "$other" --timeout 60 status > /dev/null ||
  { cat "$work/other.log" >&2; fail "query status through a socket at another path failed"; }
grep -q "the service manager passed a socket at $other: served there, not at outputs.socket.path $socket.configured" \
  "$work/other.log" || { cat "$work/other.log" >&2; fail "no warning naming both paths"; }
kill -TERM "$activator"
wait "$activator" || fail "tofcompd did not stop cleanly (status $?)"
activator=""

# refused WHAT LOG EXPECTED: tofcompd, started by the manager with WHAT, exits non-zero and its
# log says EXPECTED.
refused() {
  local log=$2 expected=$3
  if wait "$activator"; then fail "tofcompd started on $1"; fi
  activator=""
  grep -qF "$expected" "$log" || { cat "$log" >&2; fail "no '$expected' for $1"; }
}

# 3. Two sockets: tofcompd serves one.
systemd-socket-activate -l "$work/a.sock" -l "$work/b.sock" "$tofcompd" -d --shm "$shm" \
  2> "$work/two.log" &
activator=$!
wait_for_socket "$work/a.sock"
"$tofcomp" query --socket "$work/a.sock" --timeout 60 status > /dev/null 2>&1 &&
  fail "a daemon given two sockets answered"
refused "two sockets" "$work/two.log" "the service manager passed 2 sockets (LISTEN_FDS)"

# 4. A datagram socket: not what its clients speak.
systemd-socket-activate --datagram -l "$work/datagram.sock" "$tofcompd" -d --shm "$shm" \
  2> "$work/datagram.log" &
activator=$!
wait_for_socket "$work/datagram.sock"
python3 -c 'import socket, sys
s = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
s.sendto(b"{}", sys.argv[1])' "$work/datagram.sock"
refused "a datagram socket" "$work/datagram.log" "is not a listening Unix stream socket"

echo "socket activation: ok"
