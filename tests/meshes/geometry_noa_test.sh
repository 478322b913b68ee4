#!/usr/bin/env bash
# ctest: the geometry route of scripts/geometry_noa.py without the long part. (1) make_meshes.sh
# --set refuses to overwrite the committed meshes; (2) a wedge angle of 40 deg regenerates both
# models with coinciding contact nodes and the written case carries 40 deg faces (fricrom lump reads
# the wedge angle back from the face normals); (3) a range whose geometry gmsh rejects ends with
# exit 1, every value listed as rejected with gmsh's message, and R_opt null (never a number).
set -euo pipefail
root="${1:?usage: geometry_noa_test.sh REPO_ROOT FRICROM}"
fricrom="${2:?usage: geometry_noa_test.sh REPO_ROOT FRICROM}"
py=/usr/bin/python3
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail() { echo "geometry_noa_test: $*" >&2; exit 1; }

# (1)
if bash "$root/scripts/make_meshes.sh" coarse --set cham_deg=40 > "$tmp/log1" 2>&1; then
  fail "make_meshes.sh --set without --out succeeded"
fi
grep -q -- "--out" "$tmp/log1" || fail "make_meshes.sh --set without --out: message does not name --out"
bash "$root/scripts/make_meshes.sh" coarse --out "$tmp/x" --set cham_deg=abc > "$tmp/log1b" 2>&1 \
  && fail "make_meshes.sh accepted --set cham_deg=abc"
grep -q "NAME=NUMBER" "$tmp/log1b" || fail "--set cham_deg=abc: unclear message"

# (2) one design evaluated by hand the way geometry_noa.py does it
bash "$root/scripts/make_meshes.sh" coarse --out "$tmp/d40/meshes" --set cham_deg=40 > "$tmp/log2" 2>&1 \
  || { cat "$tmp/log2" >&2; fail "make_meshes.sh --set cham_deg=40 failed"; }
grep -q "27 coincide" "$tmp/log2" || fail "cham_deg=40: contact nodes do not coincide"
cmp -s "$tmp/d40/meshes/damper/damper_mesh.inp" "$root/meshes/damper/coarse/damper_mesh.inp" \
  && fail "cham_deg=40 left the damper mesh unchanged"
sed -e 's|\.\./blade_sector/coarse/|meshes/blade_sector/|g' -e 's|\.\./damper/coarse/|meshes/damper/|g' \
  "$root/meshes/cascade3/coarse.toml" > "$tmp/d40/cascade3.toml"
"$fricrom" lump "$tmp/d40/cascade3.toml" --to "$tmp/d40/lumped.toml" --json > "$tmp/lump.json" 2> "$tmp/log3" \
  || { cat "$tmp/log3" >&2; fail "fricrom lump on the 40 deg cascade failed"; }
"$py" - "$tmp/lump.json" <<'PY' || fail "the 40 deg cascade's faces are not at 40 deg"
import json, sys
j = json.load(open(sys.argv[1]))
import math
angles = [math.degrees(c["theta_rad"]) for c in j["contacts"]]
assert len(angles) == 4 and all(abs(abs(a) - 40.0) < 1e-6 for a in angles), angles
PY

# (3)
set +e
"$py" "$root/scripts/geometry_noa.py" --from 2 --to 6 --freq 1000 --max-evals 4 --out "$tmp/bad" \
  --fricrom "$fricrom" --quiet > "$tmp/out3" 2> "$tmp/err3"
code=$?
set -e
[ "$code" = 1 ] || { cat "$tmp/err3" >&2; fail "invalid range: exit $code, expected 1"; }
grep -q "no valid design" "$tmp/err3" || fail "invalid range: no 'no valid design' message"
"$py" - "$tmp/bad/geometry_noa.json" <<'PY' || fail "invalid range: wrong geometry_noa.json"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["status"] == "failed" and j["R_opt"] is None and j["p_opt"] is None, j
assert j["evaluations"] == 4 and j["rejected"] == 4, j
assert all("invalid geometry" in d["message"] and "inconsistent" in d["message"] for d in j["designs"])
assert all(d["R"] is None for d in j["designs"])
PY

# (4) a rerun into the same OUT reuses a design only if it was computed for the same inputs
# (frequency, harmonics, case): the same command reuses all four, another --freq none.
reuse() {  # FREQ EXPECTED_REUSED
  "$py" "$root/scripts/geometry_noa.py" --from 2 --to 6 --freq "$1" --max-evals 4 --out "$tmp/bad" \
    --fricrom "$fricrom" --quiet > /dev/null 2>&1 && fail "rerun at $1 Hz: exit 0 on invalid designs"
  "$py" - "$tmp/bad/geometry_noa.json" "$2" <<'PY' || fail "rerun at $1 Hz: wrong reuse"
import json, sys
j = json.load(open(sys.argv[1]))
reused = sum(1 for d in j["designs"] if d["reused"])
assert reused == int(sys.argv[2]), (reused, j["designs"])
PY
}
reuse 1000 4
reuse 1040 0
echo "geometry_noa_test: passed"
