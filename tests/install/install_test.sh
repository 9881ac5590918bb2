#!/usr/bin/env bash
# `cmake --install` with the prefix the unit expects (/usr) into a staging directory: the
# programs, the configuration, the unit, the sysusers file, the docs and the report renderer
# land where a Debian system looks for them, the installed daemon accepts its installed
# configuration, and the installed tofcomp finds its renderer and needs no datasheet file.
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
         usr/share/doc/tofcomp/configuration.md \
         usr/share/tofcomp/report/diagnosis_report.py usr/share/tofcomp/report/report_data.py \
         usr/share/tofcomp/report/report_figures.py usr/share/tofcomp/report/report_html.py \
         usr/share/tofcomp/report/report_figures_em.py \
         usr/share/tofcomp/report/report_figures_ranges.py \
         usr/share/tofcomp/report/report_figures_windows.py \
         usr/share/tofcomp/report/report_style.py; do
  [ -e "$stage/$f" ] || { echo "not installed: /$f"; cat "$stage.log"; exit 1; }
done
rm -f "$stage.log"
# The unit starts the daemon on this file.
grep -q '^ExecStart=/usr/bin/tofcompd --config /etc/tofcompd/tofcompd.yaml' \
  "$stage/usr/lib/systemd/system/tofcompd.service"
"$stage/usr/bin/tofcompd" --config "$stage/etc/tofcompd/tofcompd.yaml" --check-config
# The installed tofcomp finds its report renderer beside it (../share/tofcomp/report) and
# writes a report with its figures.
root=$(cd "$(dirname "$0")/../.." && pwd)
"$stage/usr/bin/tofcomp" -q simulate "$root/tests/install/short-scenario.yaml" -o "$stage/short.csv"
"$stage/usr/bin/tofcomp" -q diagnose "$stage/short.csv" \
  --datasheet "$stage/etc/tofcompd/lms200-datasheet.yaml" --report "$stage/report" > /dev/null
grep -q 'src="figures/fig19_absolute_error_moments.png"' "$stage/report/index.html"
# The installed tofcomp needs no datasheet file: without --datasheet it fits as from the
# installed copy of config/lms200-datasheet.yaml.
"$stage/usr/bin/tofcomp" -q thermal-fit "$stage/short.csv" --json > "$stage/fit-default.json"
"$stage/usr/bin/tofcomp" -q thermal-fit "$stage/short.csv" --json \
  --datasheet "$stage/etc/tofcompd/lms200-datasheet.yaml" > "$stage/fit-named.json"
cmp -s "$stage/fit-default.json" "$stage/fit-named.json" ||
  { echo "installed tofcomp's default datasheet is not lms200-datasheet.yaml"; exit 1; }
test -s "$stage/report/figures/fig03_histogram.png"
echo "install layout holds"
