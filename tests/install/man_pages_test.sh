#!/usr/bin/env bash
# The manual pages say what the programs do: every option of `tofcompd --help` is in tofcompd(8),
# every option of `tofcomp-ros2-bridge --help` in tofcomp-ros2-bridge(8),
# every option of `tofcomp-mqtt-bridge --help` in tofcomp-mqtt-bridge(8),
# every subcommand and top-level option of `tofcomp --help` (and --instance of query and
# shm-dump) in tofcomp(1), every key of docs/configuration.md's tables in tofcompd.yaml(5); and
# each page renders (build/man/*.gz, by scdoc) to a man page with its NAME section.
set -euo pipefail
build=$1
root=$(cd "$(dirname "$0")/../.." && pwd)
man="$root/man"
fail=0
# Long options in --help (GNU style, io/help_format.hpp): "  -c, --config=FILE" and
# "      --check-config".
long_options() { sed -n 's/^  \(-[a-zA-Z], \|    \)\(--[a-z-]*\).*/\2/p' | grep -v -e '^--help$'; }

for option in $("$build/daemon/tofcompd" --help | long_options); do
  grep -qF -- "*$option*" "$man/tofcompd.8.scd" ||
    grep -qF -- "$option*" "$man/tofcompd.8.scd" ||
    { echo "tofcompd(8) lacks $option"; fail=1; }
done
for option in $("$build/bridges/ros2/tofcomp-ros2-bridge" --help | long_options); do
  grep -qF -- "$option*" "$man/tofcomp-ros2-bridge.8.scd" ||
    { echo "tofcomp-ros2-bridge(8) lacks $option"; fail=1; }
done
for option in $("$build/bridges/mqtt/tofcomp-mqtt-bridge" --help | long_options); do
  grep -qF -- "$option*" "$man/tofcomp-mqtt-bridge.8.scd" ||
    { echo "tofcomp-mqtt-bridge(8) lacks $option"; fail=1; }
done
for option in $("$build/cli/tofcomp" --help | long_options); do
  grep -qF -- "$option*" "$man/tofcomp.1.scd" || { echo "tofcomp(1) lacks $option"; fail=1; }
done
subcommands=$("$build/cli/tofcomp" --help | sed -n '/^Subcommands:/,$s/^  \([a-z-]*\) .*/\1/p')
[ -n "$subcommands" ] || { echo "no subcommands in tofcomp --help"; exit 1; }
for sub in $subcommands; do
  grep -q "^\*$sub\*" "$man/tofcomp.1.scd" || { echo "tofcomp(1) lacks $sub"; fail=1; }
done
for sub in query shm-dump; do
  "$build/cli/tofcomp" "$sub" --help | grep -q -- '-i, --instance' ||
    { echo "tofcomp $sub has no --instance"; fail=1; }
done
grep -qF -- '*-i* _INSTANCE_' "$man/tofcomp.1.scd" || { echo "tofcomp(1) lacks --instance"; fail=1; }

# Keys: the section of each "## `section`" heading joined with each `key` of its table rows.
keys=$(awk '/^## `[a-z_]+`/ { split($0, h, "`"); section = h[2] }
            /^## / && !/^## `/ { section = "" }
            section != "" && /^\| `/ { split($0, c, "|"); n = split(c[2], k, "`");
              for (i = 2; i <= n; i += 2) print section "." k[i] }' "$root/docs/configuration.md")
[ "$(echo "$keys" | wc -l)" -gt 60 ] || { echo "too few keys read from configuration.md"; exit 1; }
for key in $keys; do
  # As scdoc source: "_" escaped, the key between "*" or ", " and "*" or ",".
  pattern="[*, ]$(echo "$key" | sed 's/_/\\\\_/g; s/\./\\./g')[*,]"
  grep -qE -- "$pattern" "$man/tofcompd.yaml.5.scd" ||
    { echo "tofcompd.yaml(5) lacks $key"; fail=1; }
done

for page in tofcompd.8 tofcompd.yaml.5 tofcomp.1 tofcomp-ros2-bridge.8 tofcomp-mqtt-bridge.8; do
  zcat "$build/man/$page.gz" | grep -q '^\.SH NAME' || { echo "build/man/$page.gz is no man page"; fail=1; }
done
[ "$fail" = 0 ] && echo "man pages hold"
