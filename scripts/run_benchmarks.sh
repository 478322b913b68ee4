#!/usr/bin/env bash
# Builds (Release) and runs the Google Benchmark programs; writes the results with the machine's
# description to benchmarks/results/<date>.json and prints them. Not part of the test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=ON > /dev/null
cmake --build build -j"$(nproc)" --target fricrom_bench
mkdir -p benchmarks/results
out="benchmarks/results/$(date -u +%Y%m%dT%H%M%SZ).json"
./build/benchmarks/fricrom_bench --benchmark_out="$out.tmp" --benchmark_out_format=json "$@"
mv "$out.tmp" "$out"
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores, $(free -g | awk '/Mem/{print $2}') GiB"
echo "results: $out"
