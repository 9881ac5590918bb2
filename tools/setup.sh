#!/usr/bin/env bash
# Installs every package tofcomp needs to build, test and run, from Debian 12's archive.
# Idempotent: packages already present are left alone. Needs root (or sudo) when something is missing.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config git ccache
  clang libclang-rt-14-dev clang-format clang-tidy
  libeigen3-dev
  libboost-dev libboost-system-dev
  libspdlog-dev libfmt-dev
  libyaml-cpp-dev
  libgpiod-dev
  libgtest-dev libgmock-dev
  libbenchmark-dev
  libcli11-dev
  libmosquitto-dev mosquitto mosquitto-clients openssl
  nlohmann-json3-dev
  libsystemd-dev systemd
  python3 python3-matplotlib python3-numpy
  scdoc
  dpkg-dev lintian fakeroot
  cyclonedds-dev cyclonedds-tools
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} packages present"
  exit 0
fi

echo "setup: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "setup: these packages are missing and this user is not root: ${missing[*]}" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "setup: done"
