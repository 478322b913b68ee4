#!/usr/bin/env bash
# Set up (Debian packages), build (Release) and run the whole test suite with ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# Unity build: each library module's files and each test module compile as a few units, so Eigen
# and GoogleTest are instantiated once per unit (Release build 8.5 -> ~5 min on a 2-core Xeon VM).
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=ON
cmake --build build -j"$(nproc)"
source scripts/test_env.sh
ctest --test-dir build --output-on-failure -j"$(nproc)"
# libFuzzer smoke run of the FE readers (clang, ASan + UBSan; a few seconds per target).
bash scripts/fuzz_smoke.sh
