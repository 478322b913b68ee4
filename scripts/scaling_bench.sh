#!/usr/bin/env bash
# Speed-up of threads and MPI ranks on the lumped 40-value gamma sweeps (issue 12): the sweep at a
# fixed 266 Hz (0.9 s of work, where OpenMPI's ~0.1 s start-up shows) and the same values each
# at its own resonance (--track-peak, ~14 s of work). Runs the variants in turn (serial, 2
# threads, 1 and 2 MPI ranks) RUNS times each, prints the median wall times and the ratios, and
# checks that every variant wrote the serial run's sweep.csv byte for byte (exit 1 otherwise).
# Usage: scripts/scaling_bench.sh [RUNS]   (default 5; needs a Release build in build/)
set -euo pipefail
cd "$(dirname "$0")/.."
runs="${1:-5}"
fr="$PWD/build/fricrom"
[[ -x "$fr" ]] || { echo "scaling_bench.sh: no $fr (build first)" >&2; exit 2; }
mpi=(mpirun --oversubscribe)
[[ "$(id -u)" == 0 ]] && mpi+=(--allow-run-as-root)
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
case_file=meshes/lumped3/baseline.toml
common=(sweep "$case_file" --method reduced --param gamma --from 0 --to 0.43 --steps 40 --quiet)

# wall seconds of one run of "$@" writing into $tmp/$name (a fresh folder: no resume)
one_run() {
  local name="$1"
  shift
  rm -rf "${tmp:?}/$name"
  local t0 t1
  t0=$(date +%s.%N)
  "$@" --out "$tmp/$name" > /dev/null
  t1=$(date +%s.%N)
  awk -v a="$t0" -v b="$t1" 'BEGIN {print b - a}'
}

median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }

for sweep in fixed peak; do
  extra=(--freq 266)
  [[ $sweep == peak ]] && extra=(--track-peak)
  declare -A times=()
  for ((k = 0; k < runs; ++k)); do
    times[serial]+="$(one_run serial "$fr" "${common[@]}" "${extra[@]}" --threads 1) "
    times[threads2]+="$(one_run threads2 "$fr" "${common[@]}" "${extra[@]}" --threads 2) "
    times[ranks1]+="$(one_run ranks1 "${mpi[@]}" -np 1 "$fr" "${common[@]}" "${extra[@]}") "
    times[ranks2]+="$(one_run ranks2 "${mpi[@]}" -np 2 "$fr" "${common[@]}" "${extra[@]}") "
  done
  for v in threads2 ranks1 ranks2; do
    cmp -s "$tmp/serial/sweep.csv" "$tmp/$v/sweep.csv" ||
      { echo "scaling_bench.sh: $sweep sweep: $v wrote another sweep.csv" >&2; exit 1; }
  done
  declare -A med=()
  for v in serial threads2 ranks1 ranks2; do
    med[$v]=$(tr ' ' '\n' <<< "${times[$v]}" | grep . | median)
  done
  printf '%s sweep (%s runs, median wall): 1 thread %.3f s, 2 threads %.3f s (%.2fx); ' \
    "$sweep" "$runs" "${med[serial]}" "${med[threads2]}" "$(awk -v a="${med[serial]}" -v b="${med[threads2]}" 'BEGIN {print a / b}')"
  printf 'mpirun -np 1 %.3f s, -np 2 %.3f s (%.2fx); files identical\n' \
    "${med[ranks1]}" "${med[ranks2]}" "$(awk -v a="${med[ranks1]}" -v b="${med[ranks2]}" 'BEGIN {print a / b}')"
  unset times med
done
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores, $(free -g | awk '/Mem/{print $2}') GiB"
