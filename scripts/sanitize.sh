#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer build (clang, build-asan/) of the executable,
# the test suites labelled "sanitize" and the libFuzzer targets; runs those suites and a
# bounded fuzz run of each target (label "fuzz", JAM_FUZZ_SECONDS each, default 20, from
# libFuzzer seed JAM_FUZZ_SEED, default 1; 0 draws one: JAM_FUZZ_SECONDS=600 JAM_FUZZ_SEED=0
# is a longer hunt).
# Called by .ci/run after the main (g++) test suite. Usage: scripts/sanitize.sh [ctest args]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${JAM_FUZZ_SECONDS:-20}"
seed="${JAM_FUZZ_SEED:-1}"
# MPI is left out: OpenMPI's own allocations would drown the leak checker.
# -O1 with line tables: the usual sanitizer setting, and the quickest build that keeps the
# suites fast. NDEBUG as in Release: the libraries' own debug assertions are not what ships
# (toml++ 3.3.0 asserts on some malformed table headers that the Release build rejects with
# a parse error).
flags="-O1 -gline-tables-only -DNDEBUG"
CC=clang-14 CXX=clang++-14 cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=None \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_C_FLAGS="$flags" \
  -DJAM_FUZZ=ON -DJAM_WERROR=ON -DCMAKE_DISABLE_FIND_PACKAGE_MPI=ON \
  -DJAM_FUZZ_SECONDS="$seconds" -DJAM_FUZZ_SEED="$seed" >/dev/null
targets=(jam fuzz_campaign_file fuzz_lammps_data fuzz_checkpoint fuzz_run_file_shapes
  fuzz_stats_file_shapes fuzz_checkpoint_shapes fuzz_chain_start_shapes fuzz_lammps_log
  fuzz_open_run_shapes fuzz_external_toml fuzz_import)
while read -r t; do targets+=("$t"); done < <(
  ctest --test-dir build-asan -N -L sanitize | sed -n 's/^ *Test *#[0-9]*: //p')
cmake --build build-asan -j "$(nproc)" --target "${targets[@]}"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:halt_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --test-dir build-asan --output-on-failure -j 2 -L 'sanitize|fuzz' "$@"
