#!/usr/bin/env bash
# What bench/peers/run.sh needs beyond tools/setup.sh (benchmark-only: the tests do not use it):
# numpy with threadpoolctl, Debian's OpenBLAS, and R with flexmix. Installing OpenBLAS makes it the
# system's BLAS where the libblas.so.3 alternative is in auto mode; run.sh loads it through
# LD_LIBRARY_PATH either way.
set -euo pipefail
PACKAGES=(python3-numpy python3-threadpoolctl libopenblas0-pthread r-base-core r-cran-flexmix)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then echo "peers setup: all present"; exit 0; fi
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
