#!/usr/bin/env bash
# ctest: the committed coarse FE models (meshes/*/coarse/) regenerate from their gmsh + CalculiX
# sources with scripts/make_meshes.sh, file for file and byte for byte.
set -euo pipefail
root="${1:?usage: regenerate_coarse.sh REPO_ROOT}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
bash "$root/scripts/make_meshes.sh" coarse --out "$tmp" > "$tmp/log" 2>&1 || {
  echo "regenerate_coarse: scripts/make_meshes.sh failed:" >&2
  cat "$tmp/log" >&2
  exit 1
}
status=0
for model in blade_sector damper; do
  for f in "$root/meshes/$model/coarse/"*; do
    name="$(basename "$f")"
    if ! cmp -s "$f" "$tmp/$model/$name"; then
      echo "regenerate_coarse: meshes/$model/coarse/$name differs from the regenerated file" >&2
      status=1
    fi
  done
  count_committed=$(ls "$root/meshes/$model/coarse" | wc -l)
  count_new=$(ls "$tmp/$model" | wc -l)
  if [[ "$count_committed" != "$count_new" ]]; then
    echo "regenerate_coarse: $model: $count_new files regenerated, $count_committed committed" >&2
    status=1
  fi
done
[[ $status == 0 ]] && echo "regenerate_coarse: meshes/blade_sector/coarse and meshes/damper/coarse regenerate identically"
exit $status
