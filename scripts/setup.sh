#!/usr/bin/env bash
# Installs the Debian 12 packages jam needs (only those missing; apt-get update first), then
# configures and builds jam in Release into build/. Safe to run again: it only rebuilds.
#
#   scripts/setup.sh           what the main job needs: the compiler, the libraries, and Python
#                              with matplotlib and h5py for the report
#   scripts/setup.sh --tests   also what the test suite needs: Boost.Test, LAMMPS (lmp, for the
#                              cross-checks run live), OpenMPI, clang with its sanitizer and
#                              fuzzer runtimes, Chromium (the report test), Python venv and pip
#                              (the jamio test), pandas and xarray (jamio's frames), gsd (the
#                              HOOMD-blue GSD import), hdf5-tools, pytest (the Python tests),
#                              Slurm and munge (the test starts a private single-node Slurm; no
#                              service is configured)
# Why each package is there: docs/development.md#dependencies.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  cmake g++ make git pkg-config
  libcli11-dev libfmt-dev libhdf5-dev libeigen3-dev libgsl-dev libtomlplusplus-dev
  nlohmann-json3-dev python3-h5py python3-matplotlib python3-numpy
)
tests=false
case "${1:-}" in
  "") ;;
  --tests) tests=true ;;
  *) echo "setup: unknown option '$1' (usage: scripts/setup.sh [--tests])" >&2; exit 2 ;;
esac
if $tests; then
  packages+=(
    libboost-test-dev hdf5-tools lammps libopenmpi-dev openmpi-bin
    clang-14 libclang-rt-14-dev llvm-14 chromium
    python3-venv python3-pip python3-setuptools python3-pandas python3-xarray python3-gsd
    python3-pytest slurmctld slurmd slurm-client munge
  )
fi

installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
missing=()
for p in "${packages[@]}"; do installed "$p" || missing+=("$p"); done
if ((${#missing[@]})); then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "setup: installing ${missing[*]}" >&2
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# The test suites are built whenever Boost.Test is there (so a main-job set-up after a test
# set-up keeps them).
with_tests=OFF
installed libboost-test-dev && with_tests=ON
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DJAM_TESTS="$with_tests" >/dev/null
cmake --build build -j "$(nproc)"
