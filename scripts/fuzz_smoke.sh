#!/usr/bin/env bash
# Builds the libFuzzer targets of the FE readers and of the lumped case-file reader with clang
# (ASan + UBSan) and runs each for a short time on its fixtures: the smoke run of CI. Longer runs: FUZZ_SECONDS=600 bash scripts/fuzz_smoke.sh
# Needs clang and libclang-rt-14-dev (scripts/setup.sh installs them).
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_EACH=${FUZZ_SECONDS:-10}
if ! command -v clang++ > /dev/null; then
  echo "fuzz_smoke: clang++ not found (Debian packages clang, libclang-rt-14-dev)" >&2
  exit 2
fi
out=build-fuzz
mkdir -p "$out"
common=(-std=c++20 -g1 -O1 -fno-sanitize-recover=all -Iinclude -Isrc -isystem /usr/include/eigen3)
# The FE readers only: the HDF5 writer/reader is not fed untrusted text and would need libhdf5.
readers=()
for f in src/io/*.cpp; do [[ $f == src/io/hdf5_file.cpp ]] || readers+=("$f"); done
# The case-file reader: its own sources, toml++ as the shared library the project links.
case_sources=(src/model/case_file.cpp src/model/case_reader.cpp src/model/model.cpp src/model/formulation.cpp)
# The assembly reader on top: its bodies, interfaces and checks (the FE readers above; the
# reductions stubbed in the harness), LAPACK from Debian's reference libraries.
assembly_sources=(src/model/assembly_bodies.cpp src/model/assembly_file.cpp
                  src/model/assembly_interfaces.cpp src/contact/interface_geometry.cpp
                  src/linear/linear.cpp src/linear/dense_lapack.cpp)
toml=(-DTOML_HEADER_ONLY=0 -DTOML_SHARED_LIB=1)
declare -A corpus=([op4]="tests/data/op4 tests/fuzz/regressions/op4" [punch]="tests/data/dmig tests/data/extseout"
                   [abaqus]=tests/data/abaqus [calculix]=tests/data/calculix [mtx]=tests/data/mtx
                   [inp_deck]="tests/data/calculix meshes/damper/coarse" [case]=meshes/lumped3
                   [assembly]="meshes/lumped3/as_fe examples/exporters")
targets=(op4 punch abaqus calculix mtx inp_deck)
# The readers are compiled once (instrumented for the fuzzer, not linked with its main), on every
# core; each target then only compiles its harness and links: ~1 min instead of ~5.
echo "fuzz_smoke: compiling ${#readers[@]} readers and ${#targets[@]} harnesses"
jobs=()
for f in "${readers[@]}"; do jobs+=("$f:$out/$(basename "${f%.cpp}").o"); done
for t in "${targets[@]}"; do jobs+=("tests/fuzz/${t}_fuzz.cpp:$out/${t}_fuzz.o"); done
for f in tests/fuzz/case_fuzz.cpp "${case_sources[@]}"; do jobs+=("$f:$out/case_$(basename "${f%.cpp}").o"); done
for f in tests/fuzz/assembly_fuzz.cpp "${assembly_sources[@]}"; do jobs+=("$f:$out/asm_$(basename "${f%.cpp}").o"); done
printf '%s\n' "${jobs[@]}" | xargs -P "$(nproc)" -I{} bash -c \
  'src=${1%%:*}; obj=${1#*:}; shift; clang++ "$@" -c "$src" -o "$obj"' _ {} \
  "${common[@]}" "${toml[@]}" -fsanitize=fuzzer-no-link,address,undefined
objects=()
for f in "${readers[@]}"; do objects+=("$out/$(basename "${f%.cpp}").o"); done
for t in "${targets[@]}"; do
  clang++ -fsanitize=fuzzer,address,undefined "$out/${t}_fuzz.o" "${objects[@]}" -o "$out/${t}_fuzz"
done
case_objects=()
for f in tests/fuzz/case_fuzz.cpp "${case_sources[@]}"; do case_objects+=("$out/case_$(basename "${f%.cpp}").o"); done
clang++ -fsanitize=fuzzer,address,undefined "${case_objects[@]}" -lmuparser -ltomlplusplus -o "$out/case_fuzz"
asm_objects=("${objects[@]}")
for f in "${case_sources[@]}"; do asm_objects+=("$out/case_$(basename "${f%.cpp}").o"); done
for f in tests/fuzz/assembly_fuzz.cpp "${assembly_sources[@]}"; do asm_objects+=("$out/asm_$(basename "${f%.cpp}").o"); done
clang++ -fsanitize=fuzzer,address,undefined "${asm_objects[@]}" -lmuparser -ltomlplusplus -llapack -lblas \
  -o "$out/assembly_fuzz"
targets+=(case assembly)
# fuzz_one TARGET: runs one target on its corpus; its verdict (ok / found) in $out/TARGET.verdict.
fuzz_one() {
  local t=$1 work="$out/corpus_$1"
  mkdir -p "$work"
  # shellcheck disable=SC2086
  if "$out/${t}_fuzz" -max_total_time="$SECONDS_EACH" -rss_limit_mb=2048 -malloc_limit_mb=1024 \
    -print_final_stats=0 "$work" ${corpus[$t]} > "$out/${t}.log" 2>&1; then
    echo ok > "$out/$t.verdict"
  else
    echo found > "$out/$t.verdict"
  fi
}
# The targets one per core at a time: seven 10-second runs in ~40 s on 2 cores instead of 70.
echo "fuzz_smoke: running ${#targets[@]} targets for ${SECONDS_EACH} s each, $(nproc) at a time"
rm -f "$out"/*.verdict
for t in "${targets[@]}"; do
  fuzz_one "$t" &
  while [ "$(jobs -rp | wc -l)" -ge "$(nproc)" ]; do wait -n || true; done
done
wait
found=0
for t in "${targets[@]}"; do
  if [ "$(cat "$out/$t.verdict" 2> /dev/null)" = ok ]; then
    echo "fuzz_smoke: $t ok ($(grep -c '^#' "$out/${t}.log" || true) status lines)"
  else
    echo "fuzz_smoke: $t found a problem:" >&2
    tail -40 "$out/${t}.log" >&2
    found=1
  fi
done
[ "$found" = 0 ] || exit 1
echo "fuzz_smoke: all targets ran without findings"
