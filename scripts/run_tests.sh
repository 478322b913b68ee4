#!/usr/bin/env bash
# Set up (Debian packages), build (Release) and run the whole test suite with ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
source scripts/test_env.sh
ctest --test-dir build --output-on-failure -j"$(nproc)"
# libFuzzer smoke run of the FE readers (clang, ASan + UBSan; a few seconds per target).
bash scripts/fuzz_smoke.sh
