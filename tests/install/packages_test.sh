#!/usr/bin/env bash
# The Debian packages (packaging/cpack.cmake): CPack makes them from this build's binaries,
# stripped; each holds what its component installs; they install with dpkg into a clean root
# (an empty directory with its own dpkg database, so the host's is never touched; the maintainer
# scripts run outside a chroot with DPKG_ROOT set, as dpkg's --force-script-chrootless does, and
# dependencies are not installed there), where dpkg -L lists their files, the daemon's user
# exists, and the daemon runs its emulator example; lintian reports no error (E:).
set -euo pipefail
build=$1
root=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
version=$(sed -n 's/^CMAKE_PROJECT_VERSION:STATIC=//p' "$build/CMakeCache.txt")

cpack --config "$build/CPackConfig.cmake" -B "$work/debs" > "$work/cpack.log" 2>&1 ||
  { cat "$work/cpack.log"; exit 1; }
debs=("$work"/debs/*.deb)
daemon_deb="$work/debs/tofcompd_${version}_amd64.deb"
cli_deb="$work/debs/tofcomp_${version}_amd64.deb"
test -f "$daemon_deb" && test -f "$cli_deb" || { ls "$work/debs"; exit 1; }
echo "packages: $(cd "$work/debs" && ls -- *.deb | tr '\n' ' ')"

# What each holds.
contents() { dpkg-deb -c "$1" | awk '{print $6}' | sed 's|^\./|/|'; }
contents "$daemon_deb" > "$work/daemon.list"
contents "$cli_deb" > "$work/cli.list"
for f in /usr/bin/tofcompd /etc/tofcompd/tofcompd.yaml \
         /usr/lib/systemd/system/tofcompd.service /usr/lib/systemd/system/tofcompd@.service \
         /usr/lib/systemd/system/tofcompd.socket \
         /usr/lib/sysusers.d/tofcompd.conf /usr/share/man/man8/tofcompd.8.gz \
         /usr/share/man/man5/tofcompd.yaml.5.gz /usr/share/tofcomp/tofcompd-emulator.yaml \
         /usr/share/doc/tofcompd/copyright; do
  grep -qx "$f" "$work/daemon.list" || { echo "tofcompd lacks $f"; exit 1; }
done
for f in /usr/bin/tofcomp /usr/share/man/man1/tofcomp.1.gz /usr/share/tofcomp/scenarios/default.yaml \
         /usr/share/tofcomp/lms200-datasheet.yaml /usr/share/tofcomp/calibration.yaml \
         /usr/share/tofcomp/report/diagnosis_report.py /usr/share/doc/tofcomp/copyright \
         /usr/share/doc/tofcomp/deployment.md; do
  grep -qx "$f" "$work/cli.list" || { echo "tofcomp lacks $f"; exit 1; }
done
mqtt_deb="$work/debs/tofcomp-mqtt-bridge_${version}_amd64.deb"
contents "$mqtt_deb" > "$work/bridge.list"
for f in /usr/bin/tofcomp-mqtt-bridge /usr/lib/systemd/system/tofcomp-mqtt-bridge@.service \
         /usr/share/man/man8/tofcomp-mqtt-bridge.8.gz \
         /usr/share/doc/tofcomp-mqtt-bridge/examples/mqtt-bridge.yaml \
         /usr/share/doc/tofcomp-mqtt-bridge/copyright; do
  grep -qx "$f" "$work/bridge.list" || { echo "tofcomp-mqtt-bridge lacks $f"; exit 1; }
done
# It runs as tofcompd's user, which the daemon's package makes; libmosquitto from Debian.
dpkg-deb -f "$mqtt_deb" Depends | grep -q "tofcompd (= $version)"
dpkg-deb -f "$mqtt_deb" Depends | grep -q "libmosquitto1"
if grep -x /usr/bin/tofcomp "$work/daemon.list" || grep -x /usr/bin/tofcompd "$work/cli.list"; then
  echo "a program in the other package"; exit 1
fi
dpkg-deb -f "$daemon_deb" Depends | grep -q "tofcomp (= $version)"
dpkg-deb -I "$daemon_deb" conffiles | grep -qx /etc/tofcompd/tofcompd.yaml

# Into a clean root.
target="$work/root"
mkdir -p "$target/var/lib/dpkg/info" "$target/var/lib/dpkg/updates"
touch "$target/var/lib/dpkg/status"
dpkg --root="$target" --force-script-chrootless --force-depends -i "${debs[@]}" > "$work/dpkg.log" 2>&1 ||
  { cat "$work/dpkg.log"; exit 1; }
dpkg --root="$target" -s tofcompd | grep -qx 'Status: install ok installed'
dpkg --root="$target" -s tofcomp | grep -qx 'Status: install ok installed'
dpkg --root="$target" -L tofcompd | grep -qx /usr/bin/tofcompd
dpkg --root="$target" -L tofcomp | grep -qx /usr/share/tofcomp/scenarios/default.yaml
# The client library's packages, when the tree builds it: the shared library with its shlibs
# and ldconfig trigger, the development files, the Python module.
if [ -f "$work/debs/libtofcomp-client0_${version}_amd64.deb" ]; then
  dpkg --root="$target" -L libtofcomp-client0 | grep -qx /usr/lib/libtofcomp-client.so.0.1.0
  dpkg-deb -I "$work/debs/libtofcomp-client0_${version}_amd64.deb" shlibs |
    grep -q '^libtofcomp-client 0 libtofcomp-client0'
  dpkg-deb -I "$work/debs/libtofcomp-client0_${version}_amd64.deb" triggers | grep -qx 'activate-noawait ldconfig'
  dpkg --root="$target" -L libtofcomp-client-dev | grep -qx /usr/include/tofcomp/tofcomp_client.h
  dpkg --root="$target" -L python3-tofcomp-client | grep -qx /usr/lib/python3/dist-packages/tofcomp_client.py
fi
# The ROS 2 bridge's package: the program, its units (not enabled: the single daemon's and the
# per-instance template) and its configuration, a conffile.
ros2_deb="$work/debs/tofcomp-ros2-bridge_${version}_amd64.deb"
dpkg --root="$target" -L tofcomp-ros2-bridge | grep -qx /usr/bin/tofcomp-ros2-bridge
dpkg --root="$target" -L tofcomp-ros2-bridge | grep -qx /usr/share/man/man8/tofcomp-ros2-bridge.8.gz
dpkg --root="$target" -L tofcomp-ros2-bridge | grep -qx /usr/lib/systemd/system/tofcomp-ros2-bridge.service
dpkg --root="$target" -L tofcomp-ros2-bridge | grep -qx /usr/lib/systemd/system/tofcomp-ros2-bridge@.service
dpkg-deb -I "$ros2_deb" conffiles | grep -qx /etc/tofcompd/ros2-bridge.yaml
dpkg-deb -f "$ros2_deb" Depends | grep -q "tofcompd (= $version)"
dpkg-deb -f "$ros2_deb" Depends | grep -q "libddsc0debian"
grep -q '^tofcompd:x:[0-9]*:[0-9]*:.*:/var/lib/tofcompd:' "$target/etc/passwd"

# Stripped, with no path of the build or source tree inside; sizes for docs/deployment.md.
for b in tofcompd tofcomp tofcomp-ros2-bridge tofcomp-mqtt-bridge; do
  if readelf -S "$target/usr/bin/$b" | grep -E '\.(symtab|debug_info)'; then
    echo "/usr/bin/$b is not stripped"; exit 1
  fi
  if strings "$target/usr/bin/$b" | grep -F -e "$root" -e "$(cd "$build" && pwd)"; then
    echo "/usr/bin/$b holds a path of the build tree"; exit 1
  fi
  echo "/usr/bin/$b: $(stat -c %s "$target/usr/bin/$b") bytes, stripped"
done
# The installed daemon runs its emulator example from the installed data directory.
data="$target/usr/share/tofcomp"
"$target/usr/bin/tofcompd" --config "$data/tofcompd-emulator.yaml" --check-config |
  grep -qF "valid; calibration $data/calibration.yaml; scenario $data/scenarios/default.yaml"
# The man pages render.
for page in usr/share/man/man8/tofcompd.8.gz usr/share/man/man5/tofcompd.yaml.5.gz \
            usr/share/man/man1/tofcomp.1.gz usr/share/man/man8/tofcomp-ros2-bridge.8.gz \
            usr/share/man/man8/tofcomp-mqtt-bridge.8.gz; do
  zcat "$target/$page" | grep -q '^\.SH NAME' || { echo "$page is no man page"; exit 1; }
done

# lintian: no errors.
lintian --tag-display-limit 0 "${debs[@]}" > "$work/lintian.log" 2>&1 || true
if grep '^E:' "$work/lintian.log"; then echo "lintian reports errors"; exit 1; fi
grep -v '^running with root' "$work/lintian.log" || true
echo "packages hold"
