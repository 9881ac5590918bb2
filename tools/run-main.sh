#!/usr/bin/env bash
# The main job on its embedded default: set up, build, then simulate the default scenario with
# the digital twin, train a calibration on it and evaluate the compensation (paper §8),
# printing the error before and after. Outputs go to out/ (data, calibration, figure data).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/tools/setup.sh"
bash "$root/tools/build.sh"
tofcomp="${TOFCOMP_BUILD_DIR:-$root/build}/cli/tofcomp"
out="$root/out"
mkdir -p "$out"
"$tofcomp" simulate "$root/config/scenarios/default.yaml" -o "$out/default.csv"
"$tofcomp" train "$out/default.csv" --datasheet "$root/config/lms200-datasheet.yaml" \
  -o "$out/calibration.yaml"
"$tofcomp" evaluate "$out/default.csv" --datasheet "$root/config/lms200-datasheet.yaml" \
  --figures "$out/figures" --calibration-output "$out/calibration-first-half.yaml"
