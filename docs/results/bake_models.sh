#!/usr/bin/env bash
# Known fraction per level (2..=10) on the committed assets under both
# models (--model gpu-binary32, the default, and --model exact): the thorn
# grid (nearest, repeat, cutoff 0.5: bake's defaults) and the cards glTF
# (its own samplers and cutoffs). Usage: docs/results/bake_models.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release --quiet -p micromap-index-cli
bin=target/release/micromap-index
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
printf '%-6s %-6s %14s %14s\n' asset level gpu-binary32 exact
for level in 2 3 4 5 6 7 8 9 10; do
  for asset in grid cards; do
    row="$asset $level"
    for model in gpu-binary32 exact; do
      if [ "$asset" = grid ]; then
        input=(--texture assets/crytek-sponza/sponza_thorn.png --triangles assets/crytek-sponza/grid.tris.json)
      else
        input=(--gltf assets/crytek-sponza/cards.gltf)
      fi
      "$bin" bake "${input[@]}" --out "$out/b" --force --level "$level" \
        --model "$model" --no-preview --quiet > "$out/s.json"
      row="$row $(python3 -c "import json;print('%.4f' % json.load(open('$out/s.json'))['known_fraction'])")"
    done
    printf '%-6s %-6s %14s %14s\n' $row
  done
done
