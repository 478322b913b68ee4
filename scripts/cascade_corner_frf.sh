#!/bin/bash
# The fixed-alpha FRF of the coarse cascade at an interface corner (every t1 direction of the first
# damper's faces at -1, of the second damper's at +1, t2 = 0), traced over the case's range with
# the Hill stability of every point: docs/figures/cascade_frf_corner_h1_stability.png.
# Usage: scripts/cascade_corner_frf.sh [OUT_DIR] [extra frf options, e.g. --harmonics 1]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
fricrom="${FRICROM:-$here/build/fricrom}"
case_file="$here/meshes/cascade3/coarse.toml"
out="${1:-results/cascade_corner_frf}"
shift || true
mkdir -p "$out"
alpha=$("$fricrom" frf "$case_file" --freq 1050 --json --out "$out/probe" |
  /usr/bin/python3 -c '
import json, sys
names = json.load(sys.stdin)["contacts"]
print(",".join(("-1" if n.startswith("d1") else "1") if n.endswith("t1") else "0" for n in names))')
"$fricrom" frf "$case_file" --alpha "$alpha" --stability --plot --out "$out" "$@"
