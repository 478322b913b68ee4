#!/usr/bin/env bash
# Builds the whole library, CLI and test suite with AddressSanitizer + UndefinedBehaviorSanitizer
# (gcc, -O1, -g1: functions and lines in reports, no variables; every UB check fatal) in
# build-asan/ and runs every test under them: the CI step that keeps "no crash, no undefined
# behaviour on any input" a checked property, not a hope.
# Benchmarks are not built. Third-party libraries (OpenBLAS, ARPACK, Ipopt, FFTW, HDF5) are not
# instrumented; leaks inside them at exit are not ours and are not reported (detect_leaks=0).
set -euo pipefail
cd "$(dirname "$0")/.."
flags="-O1 -g1 -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=all"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFRICROM_BUILD_BENCHMARKS=OFF \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$flags" -DCMAKE_C_FLAGS_RELWITHDEBINFO="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" > /dev/null
cmake --build build-asan -j"$(nproc)"
export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# The kill/resume scripts run every CLI several times; ~10x slower under the sanitizers, they
# take a smaller sweep and curve here (the same paths: journal, kill -9, --resume, MPI, lock).
export FRICROM_TEST_SWEEP_STEPS=16 FRICROM_TEST_CURVE_POINTS=8
ctest --test-dir build-asan --output-on-failure -j"$(nproc)"
echo "sanitize_tests: the whole suite passed under ASan + UBSan"
