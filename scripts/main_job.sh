#!/usr/bin/env bash
# The main job: set up, build (Release) and run the lumped validation benchmark of the paper
# (Zara et al. 2024, §4): Table 3, the FRF at α = 0, the response bounds (Fig. 9, 10), the
# robustness sweeps over γ and β (Fig. 11, 14) with the contact states (Fig. 12, 13, 15, 16), both
# NOA runs, and a markdown report beside the paper's numbers. Results go to results/lumped3/.
# Then the coarse FE cascade at one frequency beside its lumped calibration (results/cascade3/).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=ON > /dev/null
cmake --build build -j"$(nproc)" --target fricrom_cli

CASE=meshes/lumped3/baseline.toml
OUT=results/lumped3
FR=./build/fricrom
PY=/usr/bin/python3
mkdir -p "$OUT"
declare -A T
# Runs a step, records its wall time; a step whose solves did not all converge (exit 1) is
# reported and the job goes on; bad input (exit 2) stops it.
step() {
  local name=$1; shift
  local t0 rc=0
  t0=$(date +%s.%N)
  "$@" || rc=$?
  T[$name]=$(printf "%.3f" "$(echo "$(date +%s.%N) - $t0" | bc -l)")
  if [ "$rc" -eq 1 ]; then echo "main job: step '$name' reported non-converged points (see above)"; fi
  if [ "$rc" -gt 1 ]; then echo "main job: step '$name' failed (exit $rc)"; exit "$rc"; fi
}
# The step wall times recorded so far (T) as a JSON object.
write_timings() {
  local first=1
  {
    echo "{"
    for k in "${!T[@]}"; do
      [ $first -eq 1 ] || echo ","
      first=0
      printf '  "%s": %s' "$k" "${T[$k]}"
    done
    echo; echo "}"
  } > "$1"
}
json() { local f=$1; shift; "$@" --json > "$f.tmp" || { local rc=$?; mv "$f.tmp" "$f"; return $rc; }; mv "$f.tmp" "$f"; }

echo; echo "== Table 3: natural frequencies of the free and full-stick systems =="
step modes json "$OUT/modes.json" $FR modes "$CASE"
$PY scripts/compare_table3.py "$OUT/modes.json"

echo; echo "== FRF of y2 at alpha = 0 (H = 1, 128 samples/period) =="
step frf $FR frf "$CASE" --alpha 0,0,0,0 --plot --normalise --out "$OUT/frf"

echo; echo "== Response bounds over 240-290 Hz (Fig. 9) and contact states at the peak (Fig. 10) =="
step bounds_curve json "$OUT/bounds.json" $FR bounds "$CASE" --method reduced --points 101 --plot --out "$OUT/bounds"
FREF=$($PY -c "import json;print(json.load(open('$OUT/bounds.json'))['peak_freq_hz'])")
$PY -c "import json;j=json.load(open('$OUT/bounds.json'));print(f\"peak of y_max at {j['peak_freq_hz']:.2f} Hz: y_min = {j['y_min']:.4e} m, y_max = {j['y_max']:.4e} m, R = {j['R']:.4f}; states at min {j['states_at_min']}, at max {j['states_at_max']}\")"

echo; echo "== Robustness sweeps at $FREF Hz (Fig. 11, 14) =="
step sweep_gamma json "$OUT/sweep_gamma.json" $FR sweep "$CASE" --method reduced --param gamma --from 0 --to 0.43 --steps 44 --freq "$FREF" --plot --out "$OUT/sweep_gamma"
step sweep_beta json "$OUT/sweep_beta.json" $FR sweep "$CASE" --method reduced --param beta --from 0 --to 0.2 --steps 41 --freq "$FREF" --plot --out "$OUT/sweep_beta"

echo; echo "== Contact states at gamma = 0.3, 0.43 and beta = 0.1, 0.175 (Fig. 12, 13, 15, 16) =="
for pv in gamma=0.3 gamma=0.43 beta=0.1 beta=0.175; do
  step "states_$pv" $FR bounds "$CASE" --method reduced --set "$pv" --freq "$FREF" --plot --quiet --out "$OUT/states_${pv/=/_}"
done

echo; echo "== NOA (paper: gamma 0.354 with R = 0.974; beta 0.0794 with R = 1) =="
step noa_gamma json "$OUT/noa_gamma.json" $FR noa "$CASE" --method reduced --param gamma --from 0 --to 0.43 --freq "$FREF" --no-sweep --out "$OUT/noa_gamma"
step noa_beta json "$OUT/noa_beta.json" $FR noa "$CASE" --method reduced --param beta --from 0 --to 0.2 --freq "$FREF" --no-sweep --out "$OUT/noa_beta"
for p in gamma beta; do
  $PY -c "import json;j=json.load(open('$OUT/noa_$p.json'));s=json.load(open('$OUT/sweep_$p.json'));print(f\"NOA $p: p_opt = {j['p_opt']:.4f}, R = {j['R_opt']:.4f}, {j['outer_iterations']} outer iterations, {j['inner_solves']} inner solves, {j['wall_s']:.2f} s; manual sweep: {len(s['values'])} values, {s['inner_solves']} inner solves, {s['wall_s']:.2f} s\")"
done

# Figures of the per-parameter runs under one roof, and the report.
mkdir -p "$OUT/figures"
cp "$OUT/frf/frf.png" "$OUT/figures/frf.png" 2>/dev/null || true
cp "$OUT/bounds/bounds.png" "$OUT/figures/bounds.png" 2>/dev/null || true
cp "$OUT/bounds/contacts.png" "$OUT/figures/contacts_baseline.png" 2>/dev/null || true
for p in gamma beta; do
  $PY scripts/plot_sweep.py "$OUT/sweep_$p/sweep.h5" "$OUT/figures/sweep_$p.png" --noa "$OUT/noa_$p.json" \
    $( [ $p = gamma ] && echo --paper-noa 0.354,0.974 || echo --paper-noa 0.0794,1.0 ) || true
done
for pv in gamma_0.3 gamma_0.43 beta_0.1 beta_0.175; do
  cp "$OUT/states_$pv/contacts.png" "$OUT/figures/contacts_$pv.png" 2>/dev/null || true
done
write_timings "$OUT/timings.json"
$PY scripts/make_report.py --out "$OUT/report.md" --modes "$OUT/modes.json" --bounds "$OUT/bounds.json" \
  --sweep-gamma "$OUT/sweep_gamma.json" --sweep-beta "$OUT/sweep_beta.json" \
  --noa-gamma "$OUT/noa_gamma.json" --noa-beta "$OUT/noa_beta.json" \
  --figures-dir "$OUT/figures" --timings "$OUT/timings.json"

# The FE cascade study beside its lumped calibration (about 75 s here on 2 cores): modes, the
# bound curve below the resonance with the contact-state map at its peak, the certification of
# the bounds at 1040 Hz by 200 random-alpha solutions, R over gamma (a sweep of both models) and
# the NOA over gamma on the FE model at 1040 Hz. The curve through the family's peaks
# (1090-1105 Hz) costs minutes: docs/lumped-vs-fe.md has it (50 points, ~8 min).
FE_CASE=meshes/cascade3/coarse.toml
FE_OUT=results/cascade3
FE_RANGE=(--range 960 1040 --points 5)
FE_REF=1040
mkdir -p "$FE_OUT/figures"
unset T
declare -A T
echo; echo "== FE cascade: modes, bound curve ${FE_RANGE[*]} Hz, R(gamma) and NOA at $FE_REF Hz, lumped calibration =="
step fe_modes json "$FE_OUT/fe_modes.json" $FR modes "$FE_CASE"
step fe_bounds json "$FE_OUT/fe_bounds.json" $FR bounds "$FE_CASE" "${FE_RANGE[@]}" --plot --out "$FE_OUT/fe_bounds"
# The bounds at the family's resonance, level by level (interface, face shapes, pair).
step fe_peak json "$FE_OUT/fe_peak.json" $FR bounds "$FE_CASE" --freq 1100 --search quick --threads 1 \
  --out "$FE_OUT/fe_peak"
step fe_verify json "$FE_OUT/fe_verify.json" $FR verify "$FE_CASE" --freq "$FE_REF" --alpha-samples 200 \
  --check-samples 200 --time-runs 3 --out "$FE_OUT/fe_verify"
step fe_noa json "$FE_OUT/fe_noa.json" $FR noa "$FE_CASE" --param gamma --from 0 --to 0.3 --freq "$FE_REF" \
  --noa-objective one-minus-r --no-sweep --search quick --out "$FE_OUT/fe_noa"
step lump json "$FE_OUT/lump.json" $FR lump "$FE_CASE" --to "$FE_OUT/lumped.toml"
step lumped_modes json "$FE_OUT/lumped_modes.json" $FR modes "$FE_OUT/lumped.toml"
step lumped_bounds json "$FE_OUT/lumped_bounds.json" $FR bounds "$FE_OUT/lumped.toml" "${FE_RANGE[@]}" --out "$FE_OUT/lumped_bounds"
step gamma_study $PY scripts/gamma_study.py --case "$FE_CASE" --freqs "$FE_REF" --from 0 --to 0.3 --steps 5 --search quick \
  --out "$FE_OUT/gamma_study" --figure "$FE_OUT/figures/r_gamma.png" --fricrom "$FR"
$PY scripts/plot_lumped_vs_fe.py "$FE_OUT/fe_bounds/bounds.h5" "$FE_OUT/lumped_bounds/bounds.h5" \
  "$FE_OUT/figures/bounds_fe_vs_lumped.png" || true
$PY scripts/plot_verify.py "$FE_OUT/figures/verify.png" "$FE_OUT/fe_verify.json" || true
cp "$FE_OUT/fe_bounds/contact_map.png" "$FE_OUT/figures/contact_map.png" 2>/dev/null || true
cp "$FE_OUT/fe_bounds/bounds.png" "$FE_OUT/figures/bounds_fe.png" 2>/dev/null || true
write_timings "$FE_OUT/timings.json"
$PY scripts/make_cascade_report.py --dir "$FE_OUT" --out "$FE_OUT/report.md"

echo
echo "Results in $OUT: report.md, figures/, modes.json, frf/, bounds/, sweep_*/, states_*/, noa_*/"
echo "FE cascade results in $FE_OUT: report.md, figures/, fe_bounds/, fe_noa/, gamma_study/, lumped.toml"
