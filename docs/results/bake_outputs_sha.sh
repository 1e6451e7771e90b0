#!/usr/bin/env bash
# Bakes the committed assets with BIN and prints sha256 of every output
# (run it with two binaries and diff the lists: issue 23 checked its
# deduplication, threads and memory changes this way against b5de2e5)
# (summary.json with its timing fields removed). Usage: outputs.sh BIN OUTDIR
set -euo pipefail
bin=$1; out=$2; rm -rf "$out"; mkdir -p "$out"
A=$(cd "$(dirname "$0")/../.." && pwd)/assets
run() { name=$1; shift; "$bin" bake "$@" --out "$out/$name" --quiet >/dev/null; }
for model in exact gpu-binary32; do
  run cards-L6-$model --gltf $A/crytek-sponza/cards.gltf --level 6 --model $model
  run cards-auto-$model --gltf $A/crytek-sponza/cards.gltf --model $model --format 2
  run grid-auto-$model --texture $A/crytek-sponza/sponza_thorn.png --triangles $A/crytek-sponza/grid.tris.json --filter linear --address clamp-to-edge --model $model
  run grid-L4-2-$model --texture $A/crytek-sponza/sponza_thorn.png --triangles $A/crytek-sponza/grid.tris.json --level 4 --format 2 --unknown-as opaque --model $model --index-width 16
  run fern-L4-$model --gltf $A/polyhaven-fern02/fern_02.gltf --level 4 --model $model
  run fern-auto-$model --gltf $A/polyhaven-fern02/fern_02.gltf --max-level 6 --model $model
  run fern-pub-L3-$model --gltf $A/polyhaven-fern02/fern_02_1k.original.gltf --level 3 --model $model 2>/dev/null || echo "fern-pub-L3-$model failed (expected: JPEG missing)"
done
cd "$out"
for d in */; do
  for f in "$d"*; do
    case "$f" in
      *summary.json) python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); [s.pop(k,None) for k in ("bake_seconds","micro_triangles_per_second","preview_seconds")]; print(json.dumps(s,sort_keys=True))' "$f" | sha256sum | sed "s|-|$f|";;
      *) sha256sum "$f";;
    esac
  done
done
