#!/usr/bin/env bash
# ctest: a sweep killed with SIGKILL at a random moment and rerun with --resume writes the same
# files as an uninterrupted run; no value is computed twice (the journal's count plus the
# resumed run's computed count is the total); no temporary file is left; a second run on a folder
# another run is writing is refused with exit 2. Also: 1 and 2 threads, and 2 MPI ranks, give the
# same files as the serial run, and so do 4 ranks.
set -euo pipefail
fricrom="${1:?usage: sweep_resume_test.sh FRICROM REPO_ROOT}"
root="${2:?usage: sweep_resume_test.sh FRICROM REPO_ROOT}"
py=/usr/bin/python3
tmp="$(mktemp -d)"
trap 'kill -9 $(jobs -p) 2>/dev/null || true; rm -rf "$tmp"' EXIT
fail() { echo "sweep_resume_test: $*" >&2; exit 1; }
# gamma in [0, 0.43] at the lumped case's peak: values cost 10-150 ms each (about 4 s in all)
# FRICROM_TEST_SWEEP_STEPS: fewer values where every run is slower (the sanitizer build: 16).
steps="${FRICROM_TEST_SWEEP_STEPS:-80}"
sweep=(sweep "$root/meshes/lumped3/baseline.toml" --method reduced --param gamma --from 0 --to 0.43
       --freq 266 --json --quiet)

source "$(dirname "$0")/kill_mid_run.sh"
t0=$(date +%s.%N)
"$fricrom" "${sweep[@]}" --steps "$steps" --threads 1 --out "$tmp/ref" > "$tmp/ref.json"
t_ref=$(seconds_since "$t0")
"$fricrom" "${sweep[@]}" --steps "$steps" --threads 2 --out "$tmp/two" > "$tmp/two.json"

compare() {  # compare DIR_A DIR_B: the datasets of sweep.h5 to 1e-12, sweep.csv byte for byte
  "$py" - "$1/sweep.h5" "$2/sweep.h5" <<'PY' || fail "$1/sweep.h5 and $2/sweep.h5 differ"
import sys, h5py, numpy as np
a, b = h5py.File(sys.argv[1], "r"), h5py.File(sys.argv[2], "r")
for k in a["sweep"]:
    x, y = a["sweep"][k][()], b["sweep"][k][()]
    if x.dtype.kind == "f":
        assert np.array_equal(np.isnan(x), np.isnan(y)), k
        assert np.allclose(x, y, rtol=1e-12, atol=0, equal_nan=True), (k, np.max(np.abs(x - y)))
    else:
        assert (x == y).all(), k
PY
  cmp -s "$1/sweep.csv" "$2/sweep.csv" || fail "$1/sweep.csv and $2/sweep.csv differ"
}
compare "$tmp/ref" "$tmp/two"

# Two MPI ranks (values handed out by rank 0, which computes too): the same files. Containers often
# forbid the cross-process memory attach of OpenMPI's shared-memory transport: plain copies.
export OMPI_MCA_btl_vader_single_copy_mechanism=none
mpirun --allow-run-as-root --oversubscribe -np 2 "$fricrom" "${sweep[@]}" --steps "$steps" \
  --out "$tmp/mpi" > "$tmp/mpi.json" || fail "mpirun -np 2 sweep failed"
"$py" -c 'import json, sys; u = json.load(open(sys.argv[1]))["units"]; assert u["ranks"] == 2 and u["computed"] == int(sys.argv[2]), u' \
  "$tmp/mpi.json" "$steps" || fail "the MPI run did not use 2 ranks"
compare "$tmp/ref" "$tmp/mpi"
# Four ranks (three workers, each holding one unit ahead while many remain, and none near the end):
# every value computed once, the same files.
mpirun --allow-run-as-root --oversubscribe -np 4 "$fricrom" "${sweep[@]}" --steps "$steps" \
  --out "$tmp/mpi4" > "$tmp/mpi4.json" || fail "mpirun -np 4 sweep failed"
"$py" -c 'import json, sys; u = json.load(open(sys.argv[1]))["units"]; assert u["ranks"] == 4 and u["computed"] == int(sys.argv[2]), u' \
  "$tmp/mpi4.json" "$steps" || fail "the 4-rank run did not use 4 ranks or computed a value twice"
compare "$tmp/ref" "$tmp/mpi4"
# Commands that do not distribute their work refuse to run on several ranks (exit 2).
set +e
mpirun --allow-run-as-root --oversubscribe -np 2 "$fricrom" modes "$root/meshes/lumped3/baseline.toml" \
  > /dev/null 2> "$tmp/mpi_modes.err"
code=$?
set -e
[ "$code" != 0 ] || fail "mpirun -np 2 fricrom modes succeeded"
grep -q "distribute their work over MPI" "$tmp/mpi_modes.err" || fail "mpirun modes: unclear message"

# Kill at a random moment within 70 % of the serial run's time after the journal appears, then
# resume; a kill that comes after the run ended is retried with half the window.
window=$("$py" -c 'import sys; print(0.7 * float(sys.argv[1]))' "$t_ref")
killed=0
for _ in 1 2 3 4 5 6; do
  rm -rf "$tmp/k"
  if kill_mid_run "$tmp/k/sweep.journal" "$window" \
      "$fricrom" "${sweep[@]}" --steps "$steps" --threads 1 --out "$tmp/k"; then
    killed=1
    break
  fi
  window=$("$py" -c 'import sys; print(0.5 * float(sys.argv[1]))' "$window")
done
[ "$killed" = 1 ] || fail "every run ended before its kill (window down to $window s)"
# Units the killed run made durable: the journal's complete lines after its header.
recorded=$("$py" - "$tmp/k/sweep.journal" <<'PY'
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
"$fricrom" "${sweep[@]}" --steps "$steps" --threads 2 --out "$tmp/k" --resume > "$tmp/k.json" \
  || fail "the resumed run failed"
"$py" - "$tmp/k.json" "$recorded" "$steps" <<'PY' || fail "unit counts of the resumed run are wrong"
import json, sys
u = json.load(open(sys.argv[1]))["units"]
recorded = int(sys.argv[2])
print(f"sweep_resume_test: killed after {recorded} of {u['total']} values; resumed {u['resumed']}, computed {u['computed']}")
assert u["resumed"] == recorded and u["computed"] + u["resumed"] == u["total"] == int(sys.argv[3]), u
PY
compare "$tmp/ref" "$tmp/k"
ls -a "$tmp/k" | grep -q "tmp-" && fail "temporary files left in the output folder"
[ -f "$tmp/k/sweep.journal" ] && fail "the journal of a finished run is still there"
"$py" - "$tmp/k" <<'PY' || fail "sweep.manifest.json does not describe the files"
import json, os, sys
m = json.load(open(os.path.join(sys.argv[1], "sweep.manifest.json")))
names = sorted(f["file"] for f in m["files"])
assert names == ["sweep.csv", "sweep.h5"], names
for f in m["files"]:
    assert os.path.getsize(os.path.join(sys.argv[1], f["file"])) == f["bytes"], f
PY

# A stale temporary file of a killed run is removed by the next run on the folder.
touch "$tmp/k/sweep.csv.tmp-999999"
"$fricrom" "${sweep[@]}" --steps 2 --out "$tmp/k" > /dev/null
[ -e "$tmp/k/sweep.csv.tmp-999999" ] && fail "stale temporary file not removed"

# --resume without anything to resume is an error (exit 2), not a silent fresh run.
set +e
"$fricrom" "${sweep[@]}" --steps "$steps" --out "$tmp/none" --resume > /dev/null 2> "$tmp/none.err"
code=$?
set -e
[ "$code" = 2 ] || fail "--resume with no journal: exit $code, expected 2"
grep -q "no journal" "$tmp/none.err" || fail "--resume with no journal: unclear message"

# A second run on a folder that another run is writing: refused with exit 2.
"$fricrom" "${sweep[@]}" --steps 800 --threads 1 --out "$tmp/busy" > /dev/null 2>&1 &
pid=$!
for _ in $(seq 50); do [ -f "$tmp/busy/sweep.journal" ] && break; sleep 0.1; done
set +e
"$fricrom" "${sweep[@]}" --steps "$steps" --out "$tmp/busy" > /dev/null 2> "$tmp/busy.err"
code=$?
set -e
kill -9 "$pid" 2>/dev/null || true
wait "$pid" 2>/dev/null || true
[ "$code" = 2 ] || fail "concurrent run on one --out: exit $code, expected 2"
grep -q "another fricrom run is writing" "$tmp/busy.err" || fail "concurrent run: unclear message"
# verify: the alpha samples on 1 and 2 threads give the same sampling report.
for t in 1 2; do
  "$fricrom" verify "$root/meshes/lumped3/baseline.toml" --freq 266 --alpha-samples 40 --time-runs 0 \
    --threads "$t" --json --quiet --out "$tmp/verify$t" > "$tmp/verify$t.json" || fail "verify --threads $t failed"
done
"$py" - "$tmp/verify1.json" "$tmp/verify2.json" <<'PY' || fail "verify: 1 and 2 threads differ"
import json, sys
a, b = (json.load(open(f))["sampling"] for f in sys.argv[1:3])
assert a == b and a["converged"] == 40, (a, b)
PY
echo "sweep_resume_test: passed"
