#!/bin/bash
# scripts/plot_disk_design.py: two sweeps of one parameter in one figure (a PNG is written), and
# the clear errors (exit 2, the file named): a missing sweep file, sweeps of different parameters.
# Usage: plot_disk_design_test.sh FRICROM SOURCE_DIR
set -u
fr=$1
src=$2
d=$(mktemp -d)
trap 'rm -rf "$d"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
case_file=$src/meshes/lumped3/baseline.toml
"$fr" sweep "$case_file" --param gamma --from 0 --to 0.2 --steps 3 --freq 266 --quiet --out "$d/g" ||
  fail "gamma sweep"
"$fr" sweep "$case_file" --param beta --from 0 --to 0.1 --steps 2 --freq 266 --quiet --out "$d/b" ||
  fail "beta sweep"
plot=$src/scripts/plot_disk_design.py
/usr/bin/python3 "$plot" "$d/two.png" --curve A "$d/g/sweep.h5" --curve B "$d/g/sweep.h5" ||
  fail "two curves"
[ -s "$d/two.png" ] || fail "no figure written"
out=$(/usr/bin/python3 "$plot" "$d/x.png" --curve A "$d/none.h5" 2>&1)
[ $? -eq 2 ] || fail "missing file: exit status"
grep -q "none.h5" <<<"$out" || fail "missing file not named: $out"
out=$(/usr/bin/python3 "$plot" "$d/x.png" --curve A "$d/g/sweep.h5" --curve B "$d/b/sweep.h5" 2>&1)
[ $? -eq 2 ] || fail "different parameters: exit status"
grep -q "different parameters" <<<"$out" || fail "different parameters not said: $out"
[ ! -e "$d/x.png" ] || fail "a figure was written on an error"
echo "ok"
