#!/usr/bin/env bash
# ctest: a bound curve is the same on 1 thread, 2 threads and 2 MPI ranks (bounds.h5 to 1e-12,
# bounds.csv byte for byte); killed with SIGKILL at a random moment and rerun with --resume it
# writes the uninterrupted run's files, computes no point pass twice and leaves no temporary
# file. verify and noa on 2 MPI ranks report what they report serially.
set -euo pipefail
fricrom="${1:?usage: curve_units_test.sh FRICROM REPO_ROOT}"
root="${2:?usage: curve_units_test.sh FRICROM REPO_ROOT}"
py=/usr/bin/python3
tmp="$(mktemp -d)"
trap 'kill -9 $(jobs -p) 2>/dev/null || true; rm -rf "$tmp"' EXIT
fail() { echo "curve_units_test: $*" >&2; exit 1; }
# 40 frequencies over the lumped case's range, 1000 check samples each: 80 point passes, about 4 s on
# one thread here
# FRICROM_TEST_CURVE_POINTS: fewer points where every run is slower (the sanitizer build: 8).
points="${FRICROM_TEST_CURVE_POINTS:-40}"
curve=(bounds "$root/meshes/lumped3/baseline.toml" --method reduced --points "$points" --check-samples 1000
       --random-seeds 8 --json --quiet)

source "$(dirname "$0")/kill_mid_run.sh"
t0=$(date +%s.%N)
"$fricrom" "${curve[@]}" --threads 1 --out "$tmp/ref" > "$tmp/ref.json"
t_ref=$(seconds_since "$t0")
"$fricrom" "${curve[@]}" --threads 2 --out "$tmp/two" > "$tmp/two.json"

compare() {  # compare DIR_A DIR_B: every dataset of bounds.h5 to 1e-12, bounds.csv byte for byte
  "$py" - "$1/bounds.h5" "$2/bounds.h5" <<'PY' || fail "$1/bounds.h5 and $2/bounds.h5 differ"
import sys, h5py, numpy as np
a, b = h5py.File(sys.argv[1], "r"), h5py.File(sys.argv[2], "r")
names = []
a.visit(lambda n: names.append(n) if isinstance(a[n], h5py.Dataset) else None)
assert names, "no datasets"
for k in names:
    if "wall" in k:
        continue  # timings differ between runs
    x, y = a[k][()], b[k][()]
    if getattr(x, "dtype", None) is not None and x.dtype.kind == "f":
        assert np.array_equal(np.isnan(x), np.isnan(y)), k
        assert np.allclose(x, y, rtol=1e-12, atol=1e-300, equal_nan=True), (k, np.nanmax(np.abs(x - y)))
    else:
        assert np.array_equal(x, y), k
PY
  cmp -s "$1/bounds.csv" "$2/bounds.csv" || fail "$1/bounds.csv and $2/bounds.csv differ"
}
compare "$tmp/ref" "$tmp/two"
"$py" - "$tmp/ref.json" "$points" <<'PY' || fail "the serial curve's unit counts are wrong"
import json, sys
j = json.load(open(sys.argv[1]))
u = j["units"]
n = int(sys.argv[2])
# Pass 1 at every point, pass 2 as two sweeps (one unit each).
assert u["total"] == n + 2 and u["computed"] == n + 2 and u["resumed"] == 0, u
assert len(j["points"]) == n and j["status_min"] == "converged", j.keys()
# The stages in the order run, each with its units and this run's wall time.
st = j["stages"]
assert [(s["stage"], s["units"], s["computed"]) for s in st] == \
    [("frequencies", n, n), ("sweeps", 2, 2)], st
assert all(0.0 <= s["wall_s"] <= j["wall_s"] for s in st), st
PY

# Pass 2 from each point's neighbours instead of the sweeps: one unit per point, on 2 ranks as
# serially.
"$fricrom" "${curve[@]}" --neighbour-pass neighbours --threads 1 --out "$tmp/nb1" > "$tmp/nb1.json"
mpirun --allow-run-as-root --oversubscribe -np 2 "$fricrom" "${curve[@]}" --neighbour-pass neighbours \
  --out "$tmp/nb2" > "$tmp/nb2.json" || fail "mpirun -np 2 bounds --neighbour-pass neighbours failed"
compare "$tmp/nb1" "$tmp/nb2"
"$py" - "$tmp/nb1.json" "$points" <<'PY' || fail "the neighbour pass's unit counts are wrong"
import json, sys
j = json.load(open(sys.argv[1]))
n = int(sys.argv[2])
assert j["units"]["total"] == j["units"]["computed"] == 2 * n, j["units"]
assert [(s["stage"], s["units"]) for s in j["stages"]] == \
    [("frequencies", n), ("neighbour starts", n)], j["stages"]
PY
"$fricrom" "${curve[@]}" --neighbour-pass sideways --out "$tmp/bad" > /dev/null 2>&1 \
  && fail "--neighbour-pass accepted an unknown name"

# Two MPI ranks: pass 1 handed out, its records broadcast, pass 2 handed out; rank 0 writes.
export OMPI_MCA_btl_vader_single_copy_mechanism=none
mpirun --allow-run-as-root --oversubscribe -np 2 "$fricrom" "${curve[@]}" --out "$tmp/mpi" \
  > "$tmp/mpi.json" || fail "mpirun -np 2 bounds failed"
"$py" -c 'import json, sys; u = json.load(open(sys.argv[1]))["units"]; assert u["ranks"] == 2 and u["computed"] == int(sys.argv[2]) + 2, u' \
  "$tmp/mpi.json" "$points" || fail "the MPI run did not use 2 ranks"
compare "$tmp/ref" "$tmp/mpi"

# Anchors every 4th point, continuation between them: the same files on 2 ranks as serially, and
# the unit counts say so (anchors + two chains per stretch + pass 2).
"$fricrom" "${curve[@]}" --anchor-every 4 --threads 1 --out "$tmp/a1" > "$tmp/a1.json"
mpirun --allow-run-as-root --oversubscribe -np 2 "$fricrom" "${curve[@]}" --anchor-every 4 \
  --out "$tmp/a2" > "$tmp/a2.json" || fail "mpirun -np 2 bounds --anchor-every 4 failed"
compare "$tmp/a1" "$tmp/a2"
"$py" - "$tmp/a1.json" "$points" <<'PY' || fail "the anchored curve's unit counts are wrong"
import json, sys
n = int(sys.argv[2])
anchors = len(set(list(range(0, n, 4)) + [n - 1]))
chains = 2 * sum(1 for a in range(0, n - 1, 4) if min(a + 4, n - 1) - a >= 2)
u = json.load(open(sys.argv[1]))["units"]
assert u["total"] == u["computed"] == anchors + chains + 2, (u, anchors, chains)
st = json.load(open(sys.argv[1]))["stages"]
assert [(s["stage"], s["units"]) for s in st] == \
    [("frequencies", anchors), ("continuations", chains), ("sweeps", 2)], st
PY

# The harmonic ladder (H = 3 searched at H = 1): a refinement stage after pass 2, the same files
# on 2 threads and 2 ranks as serially, every point refined (search_harmonics 1) and counted.
lad=(bounds "$root/meshes/lumped3/baseline.toml" --range 262 270 --points 9 --check-samples 16
     --harmonics 3 --search-harmonics 1 --json --quiet)
"$fricrom" "${lad[@]}" --threads 1 --out "$tmp/l1" > "$tmp/l1.json"
"$fricrom" "${lad[@]}" --threads 2 --out "$tmp/l2" > "$tmp/l2.json"
mpirun --allow-run-as-root --oversubscribe -np 2 "$fricrom" "${lad[@]}" --out "$tmp/lm" \
  > "$tmp/lm.json" || fail "mpirun -np 2 bounds --search-harmonics 1 failed"
compare "$tmp/l1" "$tmp/l2"
compare "$tmp/l1" "$tmp/lm"
"$py" - "$tmp/l1.json" "$tmp/lm.json" <<'PY' || fail "the ladder curve's counts are wrong"
import json, sys
for name in sys.argv[1:]:
    j = json.load(open(name))
    u = j["units"]
    assert u["total"] == u["computed"] == 9 + 2 + 9, u
    assert all(p["search_harmonics"] == 1 and p["refinement_fallbacks"] == 0 for p in j["points"])
    assert j["status"] == "converged", j["status"]
    assert [s["stage"] for s in j["stages"]] == \
        ["frequencies", "sweeps", "harmonic refinement"], j["stages"]
PY

# Kill at a random moment within 70 % of the serial run's time after the journal appears, then
# resume on 2 threads; a kill that comes after the run ended is retried with half the window.
window=$("$py" -c 'import sys; print(0.7 * float(sys.argv[1]))' "$t_ref")
killed=0
for _ in 1 2 3 4 5 6; do
  rm -rf "$tmp/k"
  if kill_mid_run "$tmp/k/bounds.journal" "$window" "$fricrom" "${curve[@]}" --threads 1 --out "$tmp/k"; then
    killed=1
    break
  fi
  window=$("$py" -c 'import sys; print(0.5 * float(sys.argv[1]))' "$window")
done
[ "$killed" = 1 ] || fail "every run ended before its kill (window down to $window s)"
recorded=$("$py" - "$tmp/k/bounds.journal" <<'PY'
import json, os, sys
n = 0
if os.path.exists(sys.argv[1]):
    for line in open(sys.argv[1]).read().split("\n")[1:]:
        try:
            n += "unit" in json.loads(line)
        except ValueError:
            pass
print(n)
PY
)
"$fricrom" "${curve[@]}" --threads 2 --out "$tmp/k" --resume > "$tmp/k.json" \
  || fail "the resumed run failed"
"$py" - "$tmp/k.json" "$recorded" "$points" <<'PY' || fail "unit counts of the resumed run are wrong"
import json, sys
u = json.load(open(sys.argv[1]))["units"]
recorded = int(sys.argv[2])
print(f"curve_units_test: killed after {recorded} of {u['total']} point passes; resumed {u['resumed']}, computed {u['computed']}")
assert u["resumed"] == recorded and u["computed"] + u["resumed"] == u["total"] == int(sys.argv[3]) + 2, u
# Stages count this run's work only: a resumed unit is in no stage's `computed`.
st = json.load(open(sys.argv[1]))["stages"]
assert sum(s["computed"] for s in st) == u["computed"], st
assert sum(s["units"] for s in st) == u["total"], st
PY
compare "$tmp/ref" "$tmp/k"
ls -a "$tmp/k" | grep -q "tmp-" && fail "temporary files left in the output folder"
[ -f "$tmp/k/bounds.journal" ] && fail "the journal of a finished run is still there"
"$py" - "$tmp/k" <<'PY' || fail "bounds.manifest.json does not describe the files"
import json, os, sys
m = json.load(open(os.path.join(sys.argv[1], "bounds.manifest.json")))
names = sorted(f["file"] for f in m["files"])
assert names == ["bounds.csv", "bounds.h5"], names
PY

# verify: bounds, alpha samples and time integrations as units; 2 ranks = serial.
v=(verify "$root/meshes/lumped3/baseline.toml" --freq 266 --alpha-samples 24 --time-runs 2 --json --quiet)
"$fricrom" "${v[@]}" --threads 1 --out "$tmp/v1" > "$tmp/v1.json" || fail "verify failed"
mpirun --allow-run-as-root --oversubscribe -np 2 "$fricrom" "${v[@]}" --out "$tmp/v2" \
  > "$tmp/v2.json" || fail "mpirun -np 2 verify failed"
"$py" - "$tmp/v1.json" "$tmp/v2.json" <<'PY' || fail "verify: serial and 2 ranks differ"
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
for run in a["time_integration"] + b["time_integration"]:
    assert run.pop("wall_s") >= 0.0  # a timing, not a result
for k in ("y_min", "y_max", "sampling", "time_integration", "certified"):
    assert a[k] == b[k], k
assert a["sampling"]["converged"] == 24 and len(a["time_integration"]) == 2, a
PY
# noa: the scan's values (and the comparison sweep's) on 2 ranks, the refinement on rank 0 = serial.
n=(noa "$root/meshes/lumped3/baseline.toml" --method reduced --param beta --from 0 --to 0.2 --freq 266
   --sweep-steps 6 --json --quiet)
"$fricrom" "${n[@]}" --threads 1 --out "$tmp/n1" > "$tmp/n1.json" || fail "noa failed"
mpirun --allow-run-as-root --oversubscribe -np 2 "$fricrom" "${n[@]}" --out "$tmp/n2" \
  > "$tmp/n2.json" || fail "mpirun -np 2 noa failed"
"$py" - "$tmp/n1.json" "$tmp/n2.json" <<'PY' || fail "noa: serial and 2 ranks differ"
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
for k in ("p_opt", "R_opt", "history", "outer_iterations", "inner_solves"):
    assert a[k] == b[k], k
for k in ("p_best", "R_best", "inner_solves"):
    assert a["manual_sweep"][k] == b["manual_sweep"][k], k
assert b["units"]["ranks"] == 2 and a["converged"], (a["units"], b["units"])
PY
echo "curve_units_test: passed"
