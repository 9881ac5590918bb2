#!/usr/bin/env bash
# tofcompd run by a normal user on its defaults (issue 54, docs/deployment.md "Running as a normal
# user"): it starts, publishes its socket under $XDG_RUNTIME_DIR/tofcompd and its ring as
# /tofcompd.UID, says so, and that user's `tofcomp query` and `tofcomp shm-dump` find it without
# being told where. Without $XDG_RUNTIME_DIR it uses /tmp/tofcompd-UID, and refuses that folder
# when someone else put a symlink there. Run as root, the daemon runs as nobody (setpriv); run as
# another user, as that user.
# With CLIENT_DIR (the build's client library folder), the Python client, run by that user
# without a path, reads that user's daemon too.
# Usage: normal_user_test.sh TOFCOMPD TOFCOMP [CLIENT_DIR]
set -euo pipefail
fail() { echo "FAIL: $*" >&2; exit 1; }

work=$(mktemp -d /tmp/tofcomp-normal-user.XXXXXX)
chmod 755 "$work"
# The programs are run from a copy the user can reach, laid out as the build tree is (their data
# in ../share/tofcomp): the build tree may lie where only its owner may go (a home folder, a
# 0700 temporary folder).
mkdir -m 755 "$work/bin"
install -m 755 "$1" "$2" "$work/bin/"
cp -r "$(dirname "$1")/../share" "$work/"
chmod -R a+rX "$work/share"
client_dir=${3:-}
if [ -n "$client_dir" ]; then
  # The build tree's layout: the module in client/python/, its library in client/.
  mkdir -p "$work/client/python"
  cp "$client_dir/python/tofcomp_client.py" "$work/client/python/"
  cp -P "$client_dir"/libtofcomp-client.so* "$work/client/"
  chmod -R a+rX "$work/client"
fi
tofcompd="$work/bin/$(basename "$1")"
tofcomp="$work/bin/$(basename "$2")"
daemon=""
cleanup() {
  [ -n "$daemon" ] && kill "$daemon" 2>/dev/null || true
  rm -rf "$work" "${fallback:-}"
}
trap cleanup EXIT

# The command prefix that runs a program as the user: a simple command, so that a daemon started
# in the background with it is $! itself (setpriv and env exec it).
if [ "$(id -u)" -eq 0 ]; then
  uid=65534
  as_user=(setpriv --reuid="$uid" --regid="$uid" --clear-groups --)
else
  uid=$(id -u)
  as_user=()
fi
as_user() { "${as_user[@]}" "$@"; }
runtime="$work/run"
mkdir -m 700 "$runtime" "$work/home"
chown "$uid" "$runtime" "$work/home" 2>/dev/null || true
fallback=/tmp/tofcompd-$uid
rm -rf "$fallback"

# start_daemon LOG [ENV...] [-- OPTIONS...]: tofcompd on its built-in default as the user, in the
# background.
start_daemon() {
  local log=$1
  shift
  local environment=()
  while [ $# -gt 0 ] && [ "$1" != "--" ]; do environment+=("$1"); shift; done
  [ $# -gt 0 ] && shift
  "${as_user[@]}" env -i PATH=/usr/bin:/bin HOME="$work/home" "${environment[@]}" "$tofcompd" "$@" \
    2> "$log" &
  daemon=$!
}

# wait_for_socket PATH LOG: until PATH is a socket; fails with the log when the daemon stops.
wait_for_socket() {
  for _ in $(seq 200); do
    [ -S "$1" ] && return 0
    kill -0 "$daemon" 2>/dev/null || { cat "$2" >&2; fail "tofcompd stopped before serving $1"; }
    sleep 0.1
  done
  cat "$2" >&2
  fail "no socket at $1 after 20 s"
}

stop_daemon() {
  kill -TERM "$daemon"
  wait "$daemon" || fail "tofcompd did not stop cleanly (status $?)"
  daemon=""
}

# 1. With $XDG_RUNTIME_DIR.
socket="$runtime/tofcompd/tofcompd.sock"
start_daemon "$work/daemon.log" XDG_RUNTIME_DIR="$runtime"
wait_for_socket "$socket" "$work/daemon.log"
grep -q "publishing to shm /tofcompd.$uid and socket $socket" "$work/daemon.log" ||
  { cat "$work/daemon.log" >&2; fail "the log does not say where it publishes"; }
[ "$(stat -c %a "$runtime/tofcompd")" = 700 ] || fail "$runtime/tofcompd is not 0700"
status=$(as_user env -i PATH=/usr/bin:/bin XDG_RUNTIME_DIR="$runtime" "$tofcomp" query status)
echo "$status" | grep -q '^status.state: publishing' || fail "query status without --socket: $status"
for _ in $(seq 100); do
  as_user env -i PATH=/usr/bin:/bin XDG_RUNTIME_DIR="$runtime" "$tofcomp" shm-dump --beams 180:180 \
    > "$work/dump.txt" 2>&1 && break
  sleep 0.1
done
grep -q "/tofcompd.$uid" "$work/dump.txt" || { cat "$work/dump.txt" >&2; fail "shm-dump did not read /tofcompd.$uid"; }
if [ -n "$client_dir" ]; then
  as_user env -i PATH=/usr/bin:/bin XDG_RUNTIME_DIR="$runtime" PYTHONPATH="$work/client/python" \
    python3 -c '
import tofcomp_client
with tofcomp_client.Connection() as daemon:
    daemon.subscribe(beams=(180, 180), format="json")
    print("python: beam", daemon.next_scan(timeout=30.0).beams[0].index)
' > "$work/python.txt" 2>&1 || { cat "$work/python.txt" >&2; fail "the Python client without a path did not read the user's daemon"; }
  grep -q "python: beam 180" "$work/python.txt" || { cat "$work/python.txt" >&2; fail "no scan in Python"; }
fi
stop_daemon

# 2. Without it: /tmp/tofcompd-UID, made for the user alone.
start_daemon "$work/fallback.log"
wait_for_socket "$fallback/tofcompd.sock" "$work/fallback.log"
[ "$(stat -c '%a %u' "$fallback")" = "700 $uid" ] || fail "$fallback is not the user's 0700 folder"
stop_daemon
rm -rf "$fallback"

# 3. A symlink planted there is refused, named, and nothing is published through it.
mkdir -p "$work/planted"
ln -s "$work/planted" "$fallback"
start_daemon "$work/planted.log"
if wait "$daemon"; then fail "tofcompd started in a planted symlink"; fi
daemon=""
grep -q "$fallback is not a directory" "$work/planted.log" ||
  { cat "$work/planted.log" >&2; fail "the refusal does not name $fallback"; }
[ -z "$(ls -A "$work/planted")" ] || fail "something was made through the symlink"
rm -f "$fallback"

# 4. --log-level: a bad level is a bad command line (status 2, named); error leaves out the
# start's info lines, which the default level writes (step 1's log).
set +e
as_user "$tofcompd" --log-level loud 2> "$work/loud.log"
status=$?
set -e
[ "$status" -eq 2 ] || fail "--log-level loud: status $status, not 2"
grep -q -- "--log-level" "$work/loud.log" || { cat "$work/loud.log" >&2; fail "the refusal does not name --log-level"; }
start_daemon "$work/quiet.log" XDG_RUNTIME_DIR="$runtime" -- -d --log-level error
wait_for_socket "$socket" "$work/quiet.log"
stop_daemon
grep -q "starting with" "$work/daemon.log" || fail "the default level does not log the start"
if grep -q "starting with" "$work/quiet.log"; then fail "--log-level error logged the start"; fi
echo "normal user: ok (uid $uid)"
