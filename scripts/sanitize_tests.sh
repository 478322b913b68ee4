#!/usr/bin/env bash
# Builds the whole library, CLI and test suite with AddressSanitizer + UndefinedBehaviorSanitizer
# (clang, -O1, -g1: functions and lines in reports, no variables; every check it runs fatal) in
# build-asan/ and runs every test under them: the CI step that keeps "no crash, no undefined
# behaviour on any input" a checked property, not a hope.
# Benchmarks are not built. Third-party libraries (OpenBLAS, ARPACK, Ipopt, FFTW, HDF5) are not
# instrumented; leaks inside them at exit are not ours and are not reported (detect_leaks=0).
set -euo pipefail
cd "$(dirname "$0")/.."
# Four UBSan checks are left to others here: object-size (ASan checks every access against its
# redzones), null (a null dereference is a SEGV that ASan reports with its stack), alignment and
# pointer-overflow. They are costly in Eigen's inner loops (the profile shows its coefficient
# accessors as calls there): Bounds.NonmonotoneRunsEndOnTheirBestIterate 30.6 s with them,
# 7.1 s without (ASan alone 5.9 s, Release 1.5 s; 2-core Xeon VM, 2026-11-28). The fuzz smoke
# run (scripts/fuzz_smoke.sh) keeps the whole -fsanitize=undefined set on every FE reader and
# the case parser.
flags="-O1 -g1 -fno-omit-frame-pointer -fsanitize=address,undefined \
  -fno-sanitize=object-size,null,alignment,pointer-overflow -fno-sanitize-recover=all"
# clang (installed for the fuzz targets): faster than gcc here (10 against 14 min per file on 2
# cores); as a unity build 7:18 on a 2-core Xeon VM (benchmarks/README.md).
CC=clang CXX=clang++ cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_UNITY_BUILD=ON \
  -DFRICROM_BUILD_BENCHMARKS=OFF -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$flags" -DCMAKE_C_FLAGS_RELWITHDEBINFO="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" > /dev/null
cmake --build build-asan -j"$(nproc)"
source scripts/test_env.sh
export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:strict_string_checks=1
# One BLAS thread, as the CLI runs its harmonic-balance commands (fricrom/blas_threads.h):
# OpenBLAS 0.3.21's threaded zgemv (zgemv_thread_n -> zgemv_n_HASWELL) reads past the end of the
# FE cascade's complex receptance blocks on a 2-core AMD EPYC VM, where ASan's heap leaves an
# unmapped page (SEGV in Cascade.* tests; the same tests pass with one thread, and the code
# before 2026-12-02's session crashed alike). The environment wins if it says otherwise.
export OPENBLAS_NUM_THREADS="${OPENBLAS_NUM_THREADS:-1}"
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# ~5x slower under the sanitizers (20x with all of UBSan's checks), the longest tests take
# smaller sizes here (the same code paths; the Release suite runs the full sizes): the kill/resume
# scripts a 16-value sweep and an 8-point curve (journal, kill -9, --resume, MPI, lock), the
# alpha-grid test every 7th point, the FE cascade's verify one time integration.
export FRICROM_TEST_SWEEP_STEPS=16 FRICROM_TEST_CURVE_POINTS=8 FRICROM_TEST_GRID_STRIDE=7
export FRICROM_TEST_TIME_RUNS=1
# The FE alpha-level tests at one point at H = 1 (tests/bounds/level_search_test.cpp).
export FRICROM_TEST_FE_LADDER=0
# The Release run's test times, where there are some, order this run too (longest first): without
# them ctest starts the tests in their order and a few 10-25 s ones ran alone at its end.
if [ -f build/Testing/Temporary/CTestCostData.txt ]; then
  mkdir -p build-asan/Testing/Temporary
  cp build/Testing/Temporary/CTestCostData.txt build-asan/Testing/Temporary/
fi
ctest --test-dir build-asan --output-on-failure -j"$(nproc)"
echo "sanitize_tests: the whole suite passed under ASan + UBSan"
