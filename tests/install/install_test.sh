#!/usr/bin/env bash
# `cmake --install` with the prefix the unit expects (/usr) into a staging directory: the
# programs, the configuration, the unit, the sysusers file and the docs land where a Debian
# system looks for them, and the installed daemon accepts its installed configuration.
set -euo pipefail
build=$1
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
DESTDIR="$stage" cmake --install "$build" --prefix /usr > "$stage.log"
for f in usr/bin/tofcompd usr/bin/tofcomp \
         etc/tofcompd/tofcompd.yaml etc/tofcompd/tofcompd-hardware.yaml \
         etc/tofcompd/calibration.yaml etc/tofcompd/scenarios/default.yaml \
         usr/lib/systemd/system/tofcompd.service usr/lib/sysusers.d/tofcompd.conf \
         usr/share/doc/tofcomp/README.md usr/share/doc/tofcomp/protocol.md \
         usr/share/doc/tofcomp/configuration.md; do
  [ -e "$stage/$f" ] || { echo "not installed: /$f"; cat "$stage.log"; exit 1; }
done
rm -f "$stage.log"
# The unit starts the daemon on this file.
grep -q '^ExecStart=/usr/bin/tofcompd --config /etc/tofcompd/tofcompd.yaml' \
  "$stage/usr/lib/systemd/system/tofcompd.service"
"$stage/usr/bin/tofcompd" --config "$stage/etc/tofcompd/tofcompd.yaml" --check-config
echo "install layout holds"
