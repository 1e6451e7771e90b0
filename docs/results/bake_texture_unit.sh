#!/usr/bin/env bash
# Known fraction on the committed Poly Haven fern (linear, clamp to edge,
# cutoff 0.5, opaque above, 4-state, every triangle at the level) at levels
# 4..=8: ours with the default texture unit (8 sub-texel bits), with
# Vulkan's minimum of 4, and with the footprint rule of earlier versions;
# and, given your build of the OMM SDK (crates/other-bakers/README.md), the
# OMM SDK's, with verify-bake's contradictions in its output under our
# model (default unit; 16 sub-texel bits; the exact model; the exact model
# with no filter error). Deterministic counts, no times.
# Usage: docs/results/bake_texture_unit.sh [/path/to/libomm-lib.so] > docs/results/bake_texture_unit.txt
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
lib=${1:-${OMM_SDK_LIB:-}}
cd "$root"
cargo build --release --quiet -p micromap-index-cli
mi="$root/target/release/micromap-index"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The fern's triangles as TRIS.json (the same extraction as bake_compare_omm.sh).
sed -n '/^python3 - assets\/polyhaven-fern02/,/^PY$/p' docs/results/bake_compare_omm.sh \
  | sed "1s|>\"\$work/fern.tris.json\"|>$work/fern.tris.json|" >"$work/extract.sh"
bash "$work/extract.sh"
tex=assets/polyhaven-fern02/textures/fern_02_diff_1k.png
sampler=(--filter linear --address clamp-to-edge --opaque-above)
known() { python3 -c "import json,sys; print(round(json.load(open(sys.argv[1]))['known_fraction'], 4))" "$1/summary.json"; }
echo "# docs/results/bake_texture_unit.sh, commit $(git rev-parse --short HEAD)$(git diff --quiet || echo -dirty) ($(date -u +%F))"
if [ -n "$lib" ]; then
  ob="$root/crates/other-bakers/target/release/other-bake"
  (cd crates/other-bakers && CARGO_TARGET_DIR="$PWD/target" cargo build --release --quiet)
  echo "# omm-sdk: $(OMM_SDK_LIB="$lib" "$ob" --list | sed -n 's/^omm-sdk loads: //p')"
fi
printf '%-5s %8s %8s %10s %8s %8s %10s %10s %10s %12s\n' level k=8 k=4 footprint omm ours/omm \
  omm-wrong omm-wrong16 omm-exact omm-exact-e0
for level in 4 5 6 7 8; do
  row=("$level")
  for args in "--subtexel-bits 8" "--subtexel-bits 4" "--linear footprint"; do
    rm -rf "$work/o"
    # shellcheck disable=SC2086
    "$mi" bake --texture "$tex" --triangles "$work/fern.tris.json" --level "$level" "${sampler[@]}" \
      $args --no-preview --quiet --out "$work/o" >/dev/null
    row+=("$(known "$work/o")")
  done
  if [ -n "$lib" ]; then
    rm -rf "$work/omm"
    OMM_SDK_LIB="$lib" "$ob" --baker omm-sdk --texture "$tex" --triangles "$work/fern.tris.json" \
      --level "$level" --format 4 --filter linear --address clamp-to-edge --out "$work/omm" >/dev/null 2>&1
    omm=$(python3 -c "import json,sys; m=json.load(open(sys.argv[1]))['micro_triangle_states']; print(round((m['transparent']+m['opaque'])/sum(m.values()), 4))" "$work/omm/summary.json")
    row+=("$omm" "$(python3 -c "print(round(${row[1]} / $omm, 4))")")
    for args in "" "--subtexel-bits 16" "--model exact" "--model exact --filter-error 0"; do
      # shellcheck disable=SC2086
      n=$("$mi" verify-bake --texture "$tex" --triangles "$work/fern.tris.json" --micromaps "$work/omm" \
        --no-usage "${sampler[@]}" $args --json 2>/dev/null \
        | python3 -c "import json,sys; print(json.load(sys.stdin)['contradictions'])" || true)
      row+=("$n")
    done
  fi
  printf '%-5s %8s %8s %10s %8s %8s %10s %10s %10s %12s\n' "${row[@]}"
done
