#!/usr/bin/env bash
# Known fraction per level (2..=10) on the committed assets under both
# models (--model gpu-binary32, the default, and --model exact): the thorn
# grid (nearest, repeat, cutoff 0.5: bake's defaults) and the cards glTF
# (its own samplers and cutoffs). Also the widening's cost as the GPU
# bake's summary.json reports it ("widening": micro-triangles made unknown,
# and the known fraction the exact model would have), which must equal the
# exact bake's (the script fails otherwise).
# Usage: docs/results/bake_models.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release --quiet -p micromap-index-cli
bin=target/release/micromap-index
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
printf '%-6s %-6s %14s %14s %16s %14s\n' asset level gpu-binary32 exact exact-as-reported made-unknown
for level in 2 3 4 5 6 7 8 9 10; do
  for asset in grid cards; do
    if [ "$asset" = grid ]; then
      input=(--texture assets/crytek-sponza/sponza_thorn.png --triangles assets/crytek-sponza/grid.tris.json)
    else
      input=(--gltf assets/crytek-sponza/cards.gltf)
    fi
    for model in gpu-binary32 exact; do
      "$bin" bake "${input[@]}" --out "$out/b" --force --level "$level" \
        --model "$model" --no-preview --quiet > "$out/$model.json"
    done
    python3 - "$asset" "$level" "$out/gpu-binary32.json" "$out/exact.json" <<'PY'
import json, sys
asset, level, gpu, exact = sys.argv[1], sys.argv[2], json.load(open(sys.argv[3])), json.load(open(sys.argv[4]))
w = gpu["widening"]
known = lambda s: s["micro_triangles"]["opaque"] + s["micro_triangles"]["transparent"]
if w["micro_triangles_made_unknown"] != known(exact) - known(gpu) or w["known_fraction_exact_model"] != exact["known_fraction"]:
    sys.exit(f"{asset} level {level}: summary.json's widening {w} disagrees with the exact bake")
print('%-6s %-6s %14.4f %14.4f %16.4f %14d' % (asset, level, gpu["known_fraction"], exact["known_fraction"],
      w["known_fraction_exact_model"], w["micro_triangles_made_unknown"]))
PY
  done
done
