#!/usr/bin/env bash
# MPI stays optional at configure time (cmake/OptionalMPI.cmake): a wrapper whose headers are
# not installed (openmpi-bin without libopenmpi-dev) gives a configured build without MPI, not
# a failed configure; configured again once MPI is usable, the same build directory finds it
# (the failed detection does not stick in CMakeCache.txt).
# Usage: configure_mpi.sh SOURCE_DIR
set -euo pipefail
source_dir="$1"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir "$work/bin"
cat > "$work/bin/mpicxx" <<'WRAPPER'
#!/bin/sh
# Names include directories that do not exist, as OpenMPI's wrapper does without its headers.
case "$*" in
  *-showme:incdirs*) echo "/nonexistent/openmpi/include" ;;
  *-showme:compile*) echo "-I/nonexistent/openmpi/include -pthread" ;;
  *-showme*) echo "g++ -I/nonexistent/openmpi/include -pthread -lmpi_cxx -lmpi" ;;
  *) exec g++ -I/nonexistent/openmpi/include "$@" ;;
esac
WRAPPER
chmod +x "$work/bin/mpicxx"

fail() { echo "FAIL: $*"; exit 1; }
cache() { sed -n "s/^$1:INTERNAL=//p" "$work/build/CMakeCache.txt"; }

if ! cmake -S "$source_dir" -B "$work/build" -DJAM_TESTS=OFF \
    -DMPI_CXX_COMPILER="$work/bin/mpicxx" > "$work/first.log" 2>&1; then
  cat "$work/first.log"
  fail "configure failed with a wrapper whose headers are missing"
fi
grep -q "jam: building without MPI: .*names no directory holding mpi.h" "$work/first.log" ||
  fail "no one-line reason for building without MPI: $(cat "$work/first.log")"
[ "$(cache JAM_MPI_USABLE)" = FALSE ] || fail "JAM_MPI_USABLE is not FALSE"
echo "broken wrapper: configured without MPI"

real="$(command -v mpicxx || true)"
if [ -z "$real" ] || [ -z "$("$real" -showme:incdirs 2>/dev/null)" ]; then
  echo "no usable mpicxx here: the second half (MPI found again) is skipped"
  exit 0
fi
cmake -S "$source_dir" -B "$work/build" -DMPI_CXX_COMPILER="$real" > "$work/second.log" 2>&1 ||
  { cat "$work/second.log"; fail "reconfigure with $real failed"; }
[ "$(cache JAM_MPI_USABLE)" = TRUE ] || fail "MPI not found again after it became usable: $(cat "$work/second.log")"
echo "usable wrapper, same build directory: MPI found"
