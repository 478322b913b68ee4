#!/usr/bin/env bash
# Regenerates the FE models of meshes/blade_sector and meshes/damper: gmsh mesh (C3D10) ->
# scripts/fix_gmsh_inp.py (volume elements + node sets only) -> CalculiX stiffness/mass matrices
# (*FREQUENCY, SOLVER=MATRIXSTORAGE). See meshes/README.md.
#
# usage: scripts/make_meshes.sh [coarse|fine|all|disk24] [--out DIR] [--modes N]
#   coarse (default)  meshes/blade_sector/coarse/, meshes/damper/coarse/  (committed)
#                     with --out DIR: DIR/blade_sector/, DIR/damper/
#   fine              build/meshes/blade_sector_fine/, build/meshes/damper_fine/  (not committed)
#                     and the fine FE cascade case build/meshes/cascade3_fine.toml (51 node pairs
#                     per face); with --out DIR: DIR/blade_sector_fine/, DIR/damper_fine/, ...
#   all               both (coarse and fine)
#   disk24            the coarse blade sector and damper bent onto a bladed disk of 24 sectors
#                     (scripts/bend_to_disk.py; cyclic case meshes/disk24/coarse.toml):
#                     meshes/disk24/coarse/ (committed); with --out DIR: DIR/disk24/
#   --modes N         also run a CalculiX eigenvalue analysis (in a temporary folder, nothing kept)
#                     and print the lowest N natural frequencies of each model
#   --set NAME=VALUE  a geometry parameter of both .geo files (gmsh -setnumber), e.g. cham_deg=40
#                     for the wedge angle of the dampers and the platform chamfers (repeatable;
#                     use with --out so the committed meshes stay as they are)
#
# Each output folder gets <job>_mesh.inp (nodes, C3D10 elements, node sets), <job>.inp (the deck
# CalculiX ran; includes the mesh by relative path), <job>.sti, <job>.mas, <job>.dof. Jobs:
# blade_sector, damper. Deterministic: fixed gmsh options, one thread in gmsh and CalculiX; a rerun
# gives bit-identical files with the same gmsh (4.8.4) and CalculiX (2.20) builds.
# Needs the Debian packages gmsh, calculix-ccx and python3.
set -euo pipefail

ROOT_DIR="$(cd "$(dirname "$0")/.." && pwd)"
export LC_ALL=C
export OMP_NUM_THREADS=1 CCX_NPROC_STIFFNESS=1 CCX_NPROC_EQUATION_SOLVER=1 CCX_NPROC_RESULTS=1 NUMBER_OF_CPUS=1

usage() { sed -n '/^# usage:/,/^#$/p' "$0" | sed 's/^# \{0,1\}//'; }
die() { echo "make_meshes.sh: error: $*" >&2; exit 1; }

variant=coarse
out_dir=""
modes=0
geo_set=()
while [ $# -gt 0 ]; do
  case "$1" in
    coarse|fine|all|disk24) variant="$1" ;;
    --out) [ $# -ge 2 ] || die "--out needs a directory"; out_dir="$2"; shift ;;
    --out=*) out_dir="${1#--out=}" ;;
    --modes) [ $# -ge 2 ] || die "--modes needs a number"; modes="$2"; shift ;;
    --set)
      [ $# -ge 2 ] || die "--set needs NAME=VALUE"
      [[ "$2" =~ ^([A-Za-z_][A-Za-z0-9_]*)=([-+0-9.eE]+)$ ]] || die "--set wants NAME=NUMBER, got '$2'"
      geo_set+=(-setnumber "${BASH_REMATCH[1]}" "${BASH_REMATCH[2]}"); shift ;;
    -h|--help) usage; exit 0 ;;
    *) usage >&2; die "unknown argument '$1'" ;;
  esac
  shift
done
[[ "$modes" =~ ^[0-9]+$ ]] || die "--modes wants a non-negative integer, got '$modes'"
[ ${#geo_set[@]} -eq 0 ] || [ -n "$out_dir" ] || die "--set changes the geometry: give --out DIR (the committed meshes are not overwritten)"

GMSH="$(command -v gmsh || true)"
CCX="$(command -v ccx || true)"
if [ -x /usr/bin/python3 ]; then PY=/usr/bin/python3; else PY="$(command -v python3 || true)"; fi
[ -n "$GMSH" ] || die "gmsh not found (Debian package 'gmsh': apt-get install gmsh)"
[ -n "$CCX" ] || die "ccx not found (Debian package 'calculix-ccx': apt-get install calculix-ccx)"
[ -n "$PY" ] || die "python3 not found (Debian package 'python3': apt-get install python3)"
FIX="$ROOT_DIR/scripts/fix_gmsh_inp.py"
BEND="$ROOT_DIR/scripts/bend_to_disk.py"
gmsh_version="$("$GMSH" --version 2>&1 | tail -n 1)"
[ "$gmsh_version" = "4.8.4" ] || echo "make_meshes.sh: warning: gmsh $gmsh_version (the committed meshes were made with 4.8.4; files will differ)" >&2

if [ -n "$out_dir" ]; then
  mkdir -p "$out_dir"
  out_dir="$(cd "$out_dir" && pwd)"
fi

work="$(mktemp -d "${TMPDIR:-/tmp}/make_meshes.XXXXXX")"
trap 'rm -rf "$work"' EXIT

now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", b - a }'; }
size_of() { du -h "$1" | cut -f1; }

# Set by the disk variants: bend_to_disk.py options (--sectors N --pitch P); run_model then bends
# the cleaned mesh onto the disk before CalculiX runs.
bend_args=()

# run_model JOB VARIANT_LABEL GEO DECK OUT ELSET REQUIRE SINGLE GMSH_SETTINGS...
run_model() {
  local job="$1" label="$2" geo="$3" deck="$4" out="$5" elset="$6" require="$7" single="$8"
  shift 8
  local tmp="$work/$job.$label"
  rm -rf "$tmp"
  mkdir -p "$tmp/ccx" "$out"
  echo "== $job ($label) -> $out"

  # 1. gmsh
  local t0 t1 t2 t3
  t0="$(now)"
  if ! "$GMSH" "$geo" -3 -nt 1 "$@" -format inp -o "$tmp/raw.inp" > "$tmp/gmsh.log" 2>&1 \
      || grep -q '^Error' "$tmp/gmsh.log"; then
    grep -E '^(Error|Warning)' "$tmp/gmsh.log" >&2 || tail -n 20 "$tmp/gmsh.log" >&2
    die "gmsh failed on $geo (log above)"
  fi
  t1="$(now)"
  grep -q '^Warning' "$tmp/gmsh.log" && grep '^Warning' "$tmp/gmsh.log" | sed 's/^/  gmsh: /' >&2

  # 2. clean the export: C3D10 + node sets
  local title="$job $label: gmsh $gmsh_version $(basename "$geo") -3 -nt 1 $*"
  "$PY" "$FIX" clean "$tmp/raw.inp" "$tmp/ccx/${job}_mesh.inp" --elset "$elset" \
      --require "$require" ${single:+--single "$single"} --title "$title" \
      --summary "$tmp/summary" | sed 's/^/  /'
  if [ ${#bend_args[@]} -gt 0 ]; then
    mv "$tmp/ccx/${job}_mesh.inp" "$tmp/flat_mesh.inp"
    "$PY" "$BEND" mesh "$tmp/flat_mesh.inp" "$tmp/ccx/${job}_mesh.inp" "${bend_args[@]}"
  fi
  local nodes constrained=0
  nodes="$(sed -n 's/^nodes=//p' "$tmp/summary")"
  if grep -q '^\*BOUNDARY' "$deck"; then
    constrained="$(sed -n 's/^set_ROOT=//p' "$tmp/summary")"
  fi

  # 3. CalculiX: matrices
  cp "$deck" "$tmp/ccx/$job.inp"
  t2="$(now)"
  if ! (cd "$tmp/ccx" && "$CCX" "$job" > ccx.log 2>&1) || grep -q '\*ERROR' "$tmp/ccx/ccx.log"; then
    grep -A3 '\*ERROR' "$tmp/ccx/ccx.log" >&2 || tail -n 20 "$tmp/ccx/ccx.log" >&2
    die "ccx failed on $job ($label)"
  fi
  t3="$(now)"
  local ext
  for ext in sti mas dof; do
    [ -s "$tmp/ccx/$job.$ext" ] || die "ccx wrote no $job.$ext"
  done
  local dofs expected
  dofs="$(wc -l < "$tmp/ccx/$job.dof")"
  expected=$(( 3 * (nodes - constrained) ))
  [ "$dofs" -eq "$expected" ] || die "$job.dof has $dofs lines, expected 3 x ($nodes - $constrained) = $expected"

  # 4. keep mesh, deck, matrices; nothing else (the logs stay in the temporary folder)
  for f in "${job}_mesh.inp" "$job.inp" "$job.sti" "$job.mas" "$job.dof"; do
    mv -f "$tmp/ccx/$f" "$out/$f"
  done
  echo "  nodes $nodes, constrained $constrained, free DOFs $dofs"
  echo "  time: gmsh $(elapsed "$t0" "$t1") s, ccx $(elapsed "$t2" "$t3") s"
  echo "  sizes: mesh $(size_of "$out/${job}_mesh.inp"), .sti $(size_of "$out/$job.sti"), .mas $(size_of "$out/$job.mas"), .dof $(size_of "$out/$job.dof")"
  "$PY" "$FIX" mass "$out/$job"

  # 5. optional eigenvalue check
  if [ "$modes" -gt 0 ]; then
    local eig="$tmp/eig"
    mkdir -p "$eig"
    cp "$out/${job}_mesh.inp" "$eig/"
    sed "s/^\*FREQUENCY, *SOLVER=MATRIXSTORAGE.*/*FREQUENCY, SOLVER=SPOOLES\n$modes/" "$out/$job.inp" > "$eig/$job.inp"
    local t4 t5
    t4="$(now)"
    (cd "$eig" && "$CCX" "$job" > ccx.log 2>&1) || die "ccx eigenvalue run failed on $job"
    t5="$(now)"
    echo "  lowest $modes natural frequencies [Hz] (ccx SPOOLES, $(elapsed "$t4" "$t5") s):"
    awk -v n="$modes" '/E I G E N V A L U E   O U T P U T/ { f = 1; next }
        f && $1 ~ /^[0-9]+$/ && NF >= 5 { printf "    %2d %12.1f\n", $1, $4; if (++k == n) exit }' "$eig/$job.dat"
  fi
}

BLADE_GEO="$ROOT_DIR/meshes/blade_sector/blade_sector.geo"
BLADE_DECK="$ROOT_DIR/meshes/blade_sector/blade_sector_deck.inp"
DAMPER_GEO="$ROOT_DIR/meshes/damper/damper.geo"
DAMPER_DECK="$ROOT_DIR/meshes/damper/damper_deck.inp"
# Pitch of the flat cascade: platform width + gap (blade plat_wy + damper gap, both defaults).
PITCH=0.033

make_variant() {
  local label="$1" blade_out damper_out
  local -a blade_args damper_args
  case "$label" in
    coarse)
      blade_args=(-setnumber lc 0.009 -setnumber lc_blade 0.009 -setnumber n_contact_x 4 -setnumber n_contact_s 1)
      damper_args=(-setnumber lc 0.004 -setnumber n_contact_x 4 -setnumber n_contact_s 1)
      blade_out="${out_dir:-$ROOT_DIR/meshes}/blade_sector"
      damper_out="${out_dir:-$ROOT_DIR/meshes}/damper"
      [ -n "$out_dir" ] || { blade_out="$blade_out/coarse"; damper_out="$damper_out/coarse"; }
      ;;
    disk24)
      # The coarse meshes (same gmsh settings as coarse), bent onto a disk of 24 sectors.
      blade_args=(-setnumber lc 0.009 -setnumber lc_blade 0.009 -setnumber n_contact_x 4 -setnumber n_contact_s 1)
      damper_args=(-setnumber lc 0.004 -setnumber n_contact_x 4 -setnumber n_contact_s 1)
      if [ -n "$out_dir" ]; then blade_out="$out_dir/disk24"; else blade_out="$ROOT_DIR/meshes/disk24/coarse"; fi
      damper_out="$blade_out"
      ;;
    fine)
      blade_args=(-setnumber lc 0.0014 -setnumber lc_blade 0.0014 -setnumber n_contact_x 8 -setnumber n_contact_s 1)
      damper_args=(-setnumber lc 0.0014 -setnumber n_contact_x 8 -setnumber n_contact_s 1)
      blade_out="${out_dir:-$ROOT_DIR/build/meshes}/blade_sector_fine"
      damper_out="${out_dir:-$ROOT_DIR/build/meshes}/damper_fine"
      ;;
  esac
  blade_args+=("${geo_set[@]}")
  damper_args+=("${geo_set[@]}")
  if [ "$label" = disk24 ]; then
    make_disk "$label" 24 "$blade_out"
    return 0
  fi
  run_model blade_sector "$label" "$BLADE_GEO" "$BLADE_DECK" "$blade_out" BLADE \
      ROOT,CONTACT_LEFT,CONTACT_RIGHT EXCITATION,RESPONSE "${blade_args[@]}"
  run_model damper "$label" "$DAMPER_GEO" "$DAMPER_DECK" "$damper_out" DAMPER \
      CONTACT_LEFT,CONTACT_RIGHT "" "${damper_args[@]}"
  echo "== contact node pairs ($label)"
  "$PY" "$FIX" pairs "$blade_out/blade_sector_mesh.inp" CONTACT_RIGHT "$damper_out/damper_mesh.inp" CONTACT_LEFT \
    || die "blade CONTACT_RIGHT and damper CONTACT_LEFT nodes do not coincide"
  "$PY" "$FIX" pairs "$blade_out/blade_sector_mesh.inp" CONTACT_LEFT "$damper_out/damper_mesh.inp" CONTACT_RIGHT \
      --shift "0,-$PITCH,0" \
    || die "blade CONTACT_LEFT (next sector) and damper CONTACT_RIGHT nodes do not coincide"
  [ "$label" = fine ] && write_fine_cascade "$blade_out" "$damper_out"
  return 0
}

# A cyclic sector of a bladed disk of N sectors (make_variant's blade_args / damper_args, one output
# folder): the flat meshes, each bent by bend_to_disk.py before CalculiX (the root stays clamped:
# the disk is rigid), the damper in its flat cascade position (between this blade and the next);
# then the contact nodes are checked (the next sector's blade = this one rotated by +2 pi / N about
# [-1, 0, 0] through the origin) and the damper's centroid (theta_d, radius of the case file) printed.
make_disk() {
  local label="$1" sectors="$2" out="$3"
  bend_args=(--sectors "$sectors" --pitch "$PITCH")
  "$PY" "$BEND" deck "$BLADE_DECK" "$work/blade_sector_deck.$label.inp" "${bend_args[@]}"
  "$PY" "$BEND" deck "$DAMPER_DECK" "$work/damper_deck.$label.inp" "${bend_args[@]}"
  run_model blade_sector "$label" "$BLADE_GEO" "$work/blade_sector_deck.$label.inp" "$out" BLADE \
      ROOT,CONTACT_LEFT,CONTACT_RIGHT EXCITATION,RESPONSE "${blade_args[@]}"
  run_model damper "$label" "$DAMPER_GEO" "$work/damper_deck.$label.inp" "$out" DAMPER \
      CONTACT_LEFT,CONTACT_RIGHT "" "${damper_args[@]}"
  bend_args=()
  echo "== contact node pairs ($label)"
  "$PY" "$BEND" check "$out/blade_sector_mesh.inp" "$out/damper_mesh.inp" --sectors "$sectors" \
      --axis -1,0,0 \
    || die "the bent blade and damper contact nodes do not coincide"
  echo "== damper centroid ($label; the case's theta_d and radius)"
  "$PY" "$BEND" centroid "$out/damper"
}

# The fine FE cascade (51 node pairs per face, 204 in all): meshes/cascade3/coarse.toml with the
# fine models, written next to them (cascade3_fine.toml; the models are too large to commit).
write_fine_cascade() {
  local blade_out="$1" damper_out="$2" dir case_file
  dir="$(dirname "$blade_out")"
  case_file="$dir/cascade3_fine.toml"
  sed -e "s|\.\./blade_sector/coarse/|$(basename "$blade_out")/|g" \
      -e "s|\.\./damper/coarse/|$(basename "$damper_out")/|g" \
      -e 's|^name = "cascade3-coarse"|name = "cascade3-fine"|' \
      -e 's|^description = "3 coarse blade sectors|description = "3 fine blade sectors|' \
      -e 's|4 x 27 node pairs|4 x 51 node pairs|' -e 's|^# Three coarse FE|# Three fine FE|' \
      "$ROOT_DIR/meshes/cascade3/coarse.toml" > "$case_file.tmp"
  grep -q "$(basename "$blade_out")/blade_sector.sti" "$case_file.tmp" \
    || die "could not point $case_file at the fine models"
  mv "$case_file.tmp" "$case_file"
  echo "== fine cascade case: $case_file"
}

t_start="$(now)"
case "$variant" in
  coarse) make_variant coarse ;;
  fine) make_variant fine ;;
  all) make_variant coarse; make_variant fine ;;
  disk24) make_variant disk24 ;;
esac
echo "== done in $(elapsed "$t_start" "$(now)") s"
