#!/usr/bin/env bash
# Installs codesign's build and run dependencies (Debian 12 packages only, see
# third_party_notes.md) and builds the Release binary into build/release.
# Safe to run again: packages already present are not reinstalled; the build is incremental.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libsuitesparse-dev libnlopt-cxx-dev
  liblcm-dev liblcm-bin liblcm-java default-jre-headless default-jdk-headless libjchart2d-java
  libosmesa6-dev libpng-dev
  libgmsh-dev libtomlplusplus-dev libcli11-dev
  libgtest-dev libbenchmark-dev
  gnuplot-nox
  libopenmpi-dev openmpi-bin
  clang libclang-rt-14-dev
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  echo "setup: installing ${missing[*]}"
  $SUDO apt-get update
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
fi

cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build/release -j "$(nproc)"
echo "setup: built build/release/codesign"
