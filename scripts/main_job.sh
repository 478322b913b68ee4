#!/usr/bin/env bash
# The main job: set up, build (Release) and run the lumped validation benchmark of the paper
# (Zara et al. 2024, §4.1): Table 3, the FRF at α = 0 with its figure, results files in results/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build -j"$(nproc)" --target fricrom_cli

CASE=meshes/lumped3/baseline.toml
OUT=results/lumped3
mkdir -p "$OUT"

echo
echo "== Table 3: natural frequencies of the free and full-stick systems =="
./build/fricrom modes "$CASE" --json > "$OUT/modes.json.tmp" && mv "$OUT/modes.json.tmp" "$OUT/modes.json"
/usr/bin/python3 scripts/compare_table3.py "$OUT/modes.json"

echo
echo "== Nonlinear FRF of y2 at alpha = 0 (H = 1, 128 samples/period) =="
./build/fricrom frf "$CASE" --alpha 0,0,0,0 --plot --normalise --out "$OUT"
echo
echo "Results: $OUT/modes.json, $OUT/frf.h5, $OUT/frf.csv, $OUT/frf.png"
