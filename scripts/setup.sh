#!/usr/bin/env bash
# Installs the Debian 12 packages jam needs (only those missing; apt-get update first), then
# configures and builds jam in Release into build/. Safe to run again: it only rebuilds.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  cmake g++ make git pkg-config
  libcli11-dev libfmt-dev libhdf5-dev hdf5-tools libboost-test-dev
  libeigen3-dev libgsl-dev libtomlplusplus-dev
  lammps python3-h5py python3-matplotlib libopenmpi-dev openmpi-bin nlohmann-json3-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "setup: installing ${missing[*]}" >&2
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)"
