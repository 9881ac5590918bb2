#!/usr/bin/env bash
# libtofcomp-client as a client program's author gets it: the components client, client-dev and python
# installed with the prefix /usr into a staging directory (DESTDIR), then a C program and a C++
# program (client_programs/) compiled against that installation, found once by pkg-config and
# once by CMake's find_package, and run against a live tofcompd (the build's, on its emulated
# LMS 200 with a private socket and ring): each prints the protocol version its hello stated and
# the beams of one scan. Also: the SONAME, the exported symbols, the Python module's place.
# Usage: client_install_test.sh BUILD_DIR TOFCOMPD
set -euo pipefail
build=$1
tofcompd=$2
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
work=$(mktemp -d)
stage=$work/stage
daemon_pid=
cleanup() {
  [ -n "$daemon_pid" ] && kill "$daemon_pid" 2>/dev/null && wait "$daemon_pid" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "client install: $*"; [ -f "$work/tofcompd.log" ] && cat "$work/tofcompd.log"; exit 1; }

for component in client client-dev python; do
  DESTDIR="$stage" cmake --install "$build" --prefix /usr --component "$component" > /dev/null
done

# What each component put where.
pc=$(find "$stage" -name tofcomp-client.pc) || true
[ -n "$pc" ] || fail "no tofcomp-client.pc installed"
export PKG_CONFIG_PATH
PKG_CONFIG_PATH=$(dirname "$pc")
libdir=$(pkg-config --variable=libdir tofcomp-client)
includedir=$(pkg-config --variable=includedir tofcomp-client)
case "$libdir" in "$stage"/usr/*) ;; *) fail "pkg-config's libdir $libdir is not in $stage/usr";; esac
for f in "$includedir/tofcomp/client.hpp" "$includedir/tofcomp/tofcomp_client.h" \
         "$includedir/tofcomp/version.h" "$libdir/libtofcomp-client.a" \
         "$libdir/libtofcomp-client.so" "$libdir/libtofcomp-client.so.0" \
         "$libdir/cmake/tofcomp-client/tofcomp-client-config.cmake" \
         "$stage/usr/lib/python3/dist-packages/tofcomp_client.py"; do
  [ -e "$f" ] || fail "not installed: ${f#"$stage"}"
done
readelf -d "$libdir/libtofcomp-client.so.0" | grep -q 'SONAME.*\[libtofcomp-client\.so\.0\]' ||
  fail "the SONAME is not libtofcomp-client.so.0"
# Only the API is exported: the C functions and tofcomp::client, nothing of the protocol code or
# the JSON library inside.
exported=$(nm -D --defined-only "$libdir/libtofcomp-client.so.0" | c++filt)
echo "$exported" | grep -q ' tofcomp_connect@@TOFCOMP_CLIENT_0' || fail "tofcomp_connect not exported"
if echo "$exported" | grep -q 'nlohmann\|tofcomp::ipc\|tofcomp::core'; then
  fail "internal symbols exported: $(echo "$exported" | grep 'nlohmann\|tofcomp::ipc' | head -3)"
fi

# A live daemon with a private socket and ring.
ring=/tofcomp-install-test-$$
cat > "$work/tofcompd.yaml" <<YAML
emulator:
  enabled: true
  scenario: $root/config/scenarios/default.yaml
case_sensor:
  backend: simulated
calibration:
  file: $root/config/calibration.yaml
outputs:
  socket:
    path: $work/tofcompd.sock
  shm:
    name: $ring
YAML
"$tofcompd" --config "$work/tofcompd.yaml" > "$work/tofcompd.log" 2>&1 &
daemon_pid=$!
for _ in $(seq 1500); do
  [ -S "$work/tofcompd.sock" ] && break
  kill -0 "$daemon_pid" 2>/dev/null || fail "tofcompd exited"
  sleep 0.02
done
[ -S "$work/tofcompd.sock" ] || fail "tofcompd made no socket within 30 s"

# The programs' output: the protocol version from hello, then five beams 178..182.
check_output() {  # LABEL FILE
  grep -q "^$1: libtofcomp-client 0\.1\.0, tofcompd [0-9.]*, protocol 1\.0$" "$2" ||
    fail "$1 program did not print the hello: $(cat "$2")"
  for beam in 178 179 180 181 182; do
    grep -q "^$1: beam $beam " "$2" || fail "$1 program printed no beam $beam: $(cat "$2")"
  done
}

# pkg-config.
cc -Wall -Werror -o "$work/c_pkgconfig" "$here/client_programs/hello_client.c" \
  $(pkg-config --cflags --libs tofcomp-client)
c++ -std=c++17 -Wall -Werror -o "$work/cpp_pkgconfig" "$here/client_programs/hello_client.cpp" \
  $(pkg-config --cflags --libs tofcomp-client)
LD_LIBRARY_PATH=$libdir "$work/c_pkgconfig" "$work/tofcompd.sock" > "$work/c.out"
check_output C "$work/c.out"
LD_LIBRARY_PATH=$libdir "$work/cpp_pkgconfig" "$work/tofcompd.sock" "$ring" > "$work/cpp.out"
check_output C++ "$work/cpp.out"
grep -q "^C++: ring $ring scan [0-9]* of 361 beams$" "$work/cpp.out" || fail "no ring scan: $(cat "$work/cpp.out")"

# CMake's find_package: C on the shared library, C++ on the static one.
cmake -S "$here/client_programs" -B "$work/cmake-build" -G Ninja \
  -DCMAKE_PREFIX_PATH="$stage/usr" > "$work/cmake.log" 2>&1 || { cat "$work/cmake.log"; fail "cmake"; }
cmake --build "$work/cmake-build" > "$work/cmake-build.log" 2>&1 ||
  { cat "$work/cmake-build.log"; fail "building against find_package"; }
LD_LIBRARY_PATH=$libdir "$work/cmake-build/hello_client_c" "$work/tofcompd.sock" > "$work/c2.out"
check_output C "$work/c2.out"
"$work/cmake-build/hello_client_cpp" "$work/tofcompd.sock" "$ring" > "$work/cpp2.out"
check_output C++ "$work/cpp2.out"
if readelf -d "$work/cmake-build/hello_client_cpp" | grep -q 'NEEDED.*libtofcomp-client'; then
  fail "hello_client_cpp was to link the static library"
fi

# The Python module as installed finds the installed library beside it.
PYTHONPATH=$stage/usr/lib/python3/dist-packages python3 -c '
import sys, tofcomp_client
with tofcomp_client.Connection(sys.argv[1], 30.0) as daemon:
    print("Python: protocol %d.%d" % (daemon.hello.protocol_major, daemon.hello.protocol_minor))
' "$work/tofcompd.sock" > "$work/py.out"
grep -q '^Python: protocol 1\.0$' "$work/py.out" || fail "python: $(cat "$work/py.out")"

cat "$work/c.out" "$work/cpp.out" "$work/py.out"
echo "client library installs and links"
