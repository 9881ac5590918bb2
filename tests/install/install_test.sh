#!/usr/bin/env bash
# `cmake --install --strip` with the prefix a Debian system uses (/usr) into a staging directory:
# the programs, the configuration, the units, the sysusers file, the man pages, the docs and the
# data directory land where a Debian system looks for them; the installed /etc/tofcompd/tofcompd.yaml
# names a real scanner (no emulator) and passes the daemon's check once its state files exist; the
# emulator runs from the installed data directory only when asked; the installed tofcomp finds its
# renderer and needs no datasheet file; the ROS 2 bridge's units (the single daemon's and the
# per-instance template, both passing systemd-analyze verify) and configuration (off) are in
# place, and --instance gives the instance's socket and refuses a file naming another; no path
# of the build tree is in a binary. Then the prefix /usr/local: the units name that prefix's
# daemon, bridge and configuration.
set -euo pipefail
build=$1
root=$(cd "$(dirname "$0")/../.." && pwd)
stage=$(mktemp -d)
trap 'rm -rf "$stage" "$stage.log"' EXIT
DESTDIR="$stage" cmake --install "$build" --prefix /usr --strip > "$stage.log"
for f in usr/bin/tofcompd usr/bin/tofcomp etc/tofcompd/tofcompd.yaml \
         usr/bin/tofcomp-ros2-bridge etc/tofcompd/ros2-bridge.yaml \
         usr/lib/systemd/system/tofcomp-ros2-bridge.service \
         usr/lib/systemd/system/tofcomp-ros2-bridge@.service usr/share/man/man8/tofcomp-ros2-bridge.8.gz \
         usr/lib/systemd/system/tofcompd.service usr/lib/systemd/system/tofcompd@.service \
         usr/lib/systemd/system/tofcompd.socket \
         usr/lib/sysusers.d/tofcompd.conf \
         usr/share/man/man8/tofcompd.8.gz usr/share/man/man5/tofcompd.yaml.5.gz \
         usr/share/man/man1/tofcomp.1.gz \
         usr/share/tofcomp/tofcompd-emulator.yaml usr/share/tofcomp/calibration.yaml \
         usr/share/tofcomp/lms200-datasheet.yaml usr/share/tofcomp/scenarios/default.yaml \
         usr/share/tofcomp/scenarios/effect-warm-up.yaml \
         usr/share/doc/tofcomp/README.md usr/share/doc/tofcomp/protocol.md \
         usr/share/doc/tofcomp/configuration.md usr/share/doc/tofcomp/copyright \
         usr/share/doc/tofcompd/copyright usr/share/doc/tofcompd/changelog.gz \
         usr/share/tofcomp/report/diagnosis_report.py usr/share/tofcomp/report/report_data.py \
         usr/share/tofcomp/report/report_figures.py usr/share/tofcomp/report/report_html.py \
         usr/share/tofcomp/report/report_figures_em.py \
         usr/share/tofcomp/report/report_figures_ranges.py \
         usr/share/tofcomp/report/report_figures_windows.py \
         usr/share/tofcomp/report/report_style.py \
         usr/bin/tofcomp-mqtt-bridge usr/lib/systemd/system/tofcomp-mqtt-bridge@.service \
         usr/share/man/man8/tofcomp-mqtt-bridge.8.gz \
         usr/share/doc/tofcomp-mqtt-bridge/examples/mqtt-bridge.yaml; do
  [ -e "$stage/$f" ] || { echo "not installed: /$f"; cat "$stage.log"; exit 1; }
done
# The units start the installed daemon on the installed configuration.
grep -qx 'ExecStart=/usr/bin/tofcompd --config /etc/tofcompd/tofcompd.yaml' \
  "$stage/usr/lib/systemd/system/tofcompd.service"
grep -qx 'ExecStart=/usr/bin/tofcompd --config /etc/tofcompd/%i.yaml --instance %i' \
  "$stage/usr/lib/systemd/system/tofcompd@.service"
# The ROS 2 bridge: its unit on its configuration, which publishes nothing until enabled.
grep -qx 'ExecStart=/usr/bin/tofcomp-ros2-bridge --config /etc/tofcompd/ros2-bridge.yaml' \
  "$stage/usr/lib/systemd/system/tofcomp-ros2-bridge.service"
grep -qx '  enabled: false' "$stage/etc/tofcompd/ros2-bridge.yaml"
"$stage/usr/bin/tofcomp-ros2-bridge" --config "$stage/etc/tofcompd/ros2-bridge.yaml" --check-config |
  grep -q ': ok; '
# Its template: instance %i's configuration in a directory of its own beside that file.
grep -qx 'ExecStart=/usr/bin/tofcomp-ros2-bridge --config /etc/tofcompd/ros2-bridge/%i.yaml --instance %i' \
  "$stage/usr/lib/systemd/system/tofcomp-ros2-bridge@.service"
grep -qx 'Wants=tofcompd@%i.service network-online.target' \
  "$stage/usr/lib/systemd/system/tofcomp-ros2-bridge@.service"
grep -qx 'After=tofcompd@%i.service network-online.target' \
  "$stage/usr/lib/systemd/system/tofcomp-ros2-bridge@.service"
# Both units confined alike: the template's [Service] after ExecStart= is the single unit's.
service_tail() { sed -n '/^ExecStart=/,$p' "$stage/usr/lib/systemd/system/$1" | tail -n +2; }
cmp -s <(service_tail tofcomp-ros2-bridge.service) <(service_tail tofcomp-ros2-bridge@.service) ||
  { echo "the ROS 2 bridge's units differ after ExecStart="; exit 1; }
grep -qx 'MemoryDenyWriteExecute=yes' "$stage/usr/lib/systemd/system/tofcomp-ros2-bridge@.service"
# systemd-analyze verify: both load without a word (an unknown or misspelt key is only a warning,
# exit status 0, so any output fails), the template as instance front. Their ExecStart= names
# /usr/bin, here the stage's.
units="$stage/verify-units"
mkdir "$units"
for u in tofcomp-ros2-bridge.service tofcomp-ros2-bridge@.service; do
  sed "s|=/usr/bin/|=$stage/usr/bin/|" "$stage/usr/lib/systemd/system/$u" > "$units/$u"
done
(cd "$units" && systemd-analyze verify --man=no ./tofcomp-ros2-bridge.service \
   ./tofcomp-ros2-bridge@front.service) > "$stage/verify.log" 2>&1 || { cat "$stage/verify.log"; exit 1; }
if [ -s "$stage/verify.log" ]; then cat "$stage/verify.log"; exit 1; fi
# --instance, as the template passes it: the instance's socket unless the file names one, and a
# file naming another instance refused with the file and the key; a bad NAME is a bad command
# line (status 2), by the daemon's rule.
ros2_conf="$stage/ros2-front.yaml"
printf 'ros2:\n  enabled: true\n  scan_topic: front/scan\n  frame_id: laser_front\n' > "$ros2_conf"
"$stage/usr/bin/tofcomp-ros2-bridge" --config "$ros2_conf" --instance front --check-config |
  grep -qx "$ros2_conf: ok; DDS domain 0, publishing rt/front/scan and rt/diagnostics from /run/tofcompd/front/tofcompd.sock"
printf '  instance: back\n' >> "$ros2_conf"
if "$stage/usr/bin/tofcomp-ros2-bridge" --config "$ros2_conf" --instance front --check-config \
     > "$stage/ros2.out" 2>&1; then
  echo "tofcomp-ros2-bridge --instance front took a file naming instance back"; exit 1
fi
grep -qF "$ros2_conf: ros2.instance is 'back', but --instance names 'front'" "$stage/ros2.out" ||
  { cat "$stage/ros2.out"; exit 1; }
status=0
"$stage/usr/bin/tofcomp-ros2-bridge" --config "$ros2_conf" --instance ../front --check-config \
  > "$stage/ros2.out" 2>&1 || status=$?
[ "$status" = 2 ] && grep -qF "instance name '../front'" "$stage/ros2.out" ||
  { echo "--instance ../front: status $status"; cat "$stage/ros2.out"; exit 1; }
# The MQTT bridge: one unit per instance, on its own configuration.
grep -qx 'ExecStart=/usr/bin/tofcomp-mqtt-bridge --config /etc/tofcomp-mqtt-bridge/%i.yaml --instance %i' \
  "$stage/usr/lib/systemd/system/tofcomp-mqtt-bridge@.service"
# No path of the source or build tree in a binary (the data directory is found from the binary).
for b in tofcompd tofcomp tofcomp-ros2-bridge tofcomp-mqtt-bridge; do
  if strings "$stage/usr/bin/$b" | grep -F -e "$root" -e "$(cd "$build" && pwd)"; then
    echo "/usr/bin/$b holds a path of the build tree"; exit 1
  fi
done

# The installed configuration drives a real scanner: an LMS 200 on a serial port, no emulator.
conf="$stage/etc/tofcompd/tofcompd.yaml"
grep -q '^  device: /dev/ttyUSB0' "$conf"
if grep -q '^emulator:' "$conf"; then echo "the installed configuration runs the emulator"; exit 1; fi
# Its state files (a calibration, a bench recording) do not exist on a new host: the check says
# which is missing. With them in place (here under the stage's var/) it passes, with no scenario.
if "$stage/usr/bin/tofcompd" --config "$conf" --check-config > "$stage/check" 2>&1; then
  echo "the installed configuration passed without its calibration"; exit 1
fi
grep -q 'calibration.file /var/lib/tofcompd/calibration.yaml' "$stage/check"
mkdir -p "$stage/var/bench"
sed "s|/var/lib/tofcompd|$stage/var|g" "$conf" > "$stage/real.yaml"
cp "$stage/usr/share/tofcomp/calibration.yaml" "$stage/var/calibration.yaml"
"$stage/usr/bin/tofcomp" -q simulate "$root/tests/install/short-scenario.yaml" -o "$stage/var/bench.csv" > /dev/null
"$stage/usr/bin/tofcompd" --config "$stage/real.yaml" --check-config > "$stage/check"
grep -q ': valid; calibration '"$stage"'/var/calibration.yaml; datasheet: the bundled LMS 200 datasheet' "$stage/check"
if grep -q scenario "$stage/check"; then cat "$stage/check"; exit 1; fi
# The emulator only when asked: the installed example and the built-in default read their
# scenario and calibration from the installed data directory.
data="$stage/usr/share/tofcomp"
"$stage/usr/bin/tofcompd" --config "$data/tofcompd-emulator.yaml" --check-config |
  grep -qF "valid; calibration $data/calibration.yaml; scenario $data/scenarios/default.yaml"
"$stage/usr/bin/tofcompd" --check-config |
  grep -qF "built-in default (config/tofcompd.yaml): valid; calibration $data/calibration.yaml; scenario $data/scenarios/default.yaml"

# The installed tofcomp finds its report renderer in the data directory and writes a report.
"$stage/usr/bin/tofcomp" -q simulate "$root/tests/install/short-scenario.yaml" -o "$stage/short.csv" > /dev/null
"$stage/usr/bin/tofcomp" -q diagnose "$stage/short.csv" \
  --datasheet "$data/lms200-datasheet.yaml" --report "$stage/report" > /dev/null
grep -q 'src="figures/fig19_absolute_error_moments.png"' "$stage/report/index.html"
test -s "$stage/report/figures/fig03_histogram.png"
# The installed tofcomp needs no datasheet file: without --datasheet it fits as from the
# installed copy of config/lms200-datasheet.yaml.
"$stage/usr/bin/tofcomp" -q thermal-fit "$stage/short.csv" --json > "$stage/fit-default.json"
"$stage/usr/bin/tofcomp" -q thermal-fit "$stage/short.csv" --json \
  --datasheet "$data/lms200-datasheet.yaml" > "$stage/fit-named.json"
cmp -s "$stage/fit-default.json" "$stage/fit-named.json" ||
  { echo "installed tofcomp's default datasheet is not lms200-datasheet.yaml"; exit 1; }

# Another prefix: the units follow it.
local_stage="$stage/local"
DESTDIR="$local_stage" cmake --install "$build" --prefix /usr/local --component daemon > "$stage.log"
grep -qx 'ExecStart=/usr/local/bin/tofcompd --config /usr/local/etc/tofcompd/tofcompd.yaml' \
  "$local_stage/usr/local/lib/systemd/system/tofcompd.service"
grep -qx 'ExecStart=/usr/local/bin/tofcompd --config /usr/local/etc/tofcompd/%i.yaml --instance %i' \
  "$local_stage/usr/local/lib/systemd/system/tofcompd@.service"
test -f "$local_stage/usr/local/etc/tofcompd/tofcompd.yaml"
DESTDIR="$local_stage" cmake --install "$build" --prefix /usr/local --component ros2-bridge > "$stage.log"
grep -qx 'ExecStart=/usr/local/bin/tofcomp-ros2-bridge --config /usr/local/etc/tofcompd/ros2-bridge.yaml' \
  "$local_stage/usr/local/lib/systemd/system/tofcomp-ros2-bridge.service"
grep -qx 'ExecStart=/usr/local/bin/tofcomp-ros2-bridge --config /usr/local/etc/tofcompd/ros2-bridge/%i.yaml --instance %i' \
  "$local_stage/usr/local/lib/systemd/system/tofcomp-ros2-bridge@.service"
test -x "$local_stage/usr/local/bin/tofcompd"
echo "install layout holds"
