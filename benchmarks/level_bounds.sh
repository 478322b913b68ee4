#!/usr/bin/env bash
# The coarse FE cascade's bounds next to its resonance, one frequency at a time (one thread each),
# with the α levels (default and thorough presets) and with the single-level per-pair search
# (--alpha-levels pair); then the table of docs/bounds-and-design.md ("Bounds over α levels").
#   bash benchmarks/level_bounds.sh OUT_DIR [FREQS...]      (default 1090 1094 1098 1100 1102 1106 1110)
#   LEVEL_BOUNDS_SET=gamma=0.15 bash benchmarks/level_bounds.sh OUT_DIR 1100   (a case parameter)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: level_bounds.sh OUT_DIR [FREQS...]}
shift
freqs=("$@")
[ ${#freqs[@]} -gt 0 ] || freqs=(1090 1094 1098 1100 1102 1106 1110)
mkdir -p "$out"
case=meshes/cascade3/coarse.toml
for f in "${freqs[@]}"; do
  for v in levels pair thorough; do
    extra=()
    [ -n "${LEVEL_BOUNDS_SET:-}" ] && extra+=(--set "$LEVEL_BOUNDS_SET")
    [ "$v" = pair ] && extra+=(--alpha-levels pair)
    [ "$v" = thorough ] && extra+=(--search thorough)
    ./build/fricrom bounds "$case" --freq "$f" --threads 1 --json --quiet "${extra[@]}" \
      --out "$out/$v$f" > "$out/$v$f.json" || true
  done
done
/usr/bin/python3 - "$out" "${freqs[@]}" <<'PY'
import json, sys
out, freqs = sys.argv[1], sys.argv[2:]
def load(p):
    try:
        return json.load(open(p))
    except Exception:
        return None
def cell(j):
    if not j:
        return "— | — | — | —"
    f = lambda v, p: "null" if v is None else format(v, p)
    return f"{f(j['y_min'], '.4e')} | {f(j['y_max'], '.4e')} | {f(j['R'], '.3f')} | {j['wall_s']:.1f}"
print("| f [Hz] | pair only: y_min | y_max | R | s | levels: y_min | y_max | R | s | thorough: y_min | y_max | R | s |")
print("|---|" + "---|" * 12)
for f in freqs:
    print(f"| {f} | {cell(load(f'{out}/pair{f}.json'))} | {cell(load(f'{out}/levels{f}.json'))} | {cell(load(f'{out}/thorough{f}.json'))} |")
print()
print("| f [Hz] | interface [y_min, y_max] | face | pair |")
print("|---|---|---|---|")
for f in freqs:
    j = load(f"{out}/levels{f}.json")
    if j and j.get("levels"):
        print(f"| {f} | " + " | ".join(f"[{l['y_min']:.4e}, {l['y_max']:.4e}]" for l in j["levels"]) + " |")
PY
