#!/usr/bin/env bash
# Bakes the two Crytek Sponza alpha textures with every baker of the default
# build, over assets/crytek-sponza/grid.tris.json (8 x 8 quads, 128
# triangles; checked to be `other-bake --grid 8`), at levels 4, 6, 8
# in 4-state and level 6 in 2-state; writes out/<baker>/<texture>-L<level>-f<format>/.
# Usage: crates/other-bakers/run-sponza.sh   (from anywhere)
set -euo pipefail
cd "$(dirname "$0")"
export CARGO_TARGET_DIR="$PWD/target"
cargo build --release --quiet
bin="$CARGO_TARGET_DIR/release/other-bake"
assets=../../assets/crytek-sponza
# The committed grid has the triangles --grid 8 prints (its text differs:
# it also names its source).
"$bin" --grid 8 | python3 -c 'import json, sys
sys.exit(json.load(open(sys.argv[1]))["triangles"] != json.load(sys.stdin)["triangles"])' "$assets/grid.tris.json"
grep -m1 "model name" /proc/cpuinfo
uptime
for baker in meshopt-cpp meshopt-rs; do
  for texture in sponza_thorn chain; do
    for lf in 4:4:200 6:4:50 8:4:10 6:2:50; do
      IFS=: read -r level format repeat <<<"$lf"
      "$bin" --baker "$baker" --texture "$assets/$texture.png" --triangles "$assets/grid.tris.json" \
        --level "$level" --format "$format" --repeat "$repeat" \
        --out "out/$baker/$texture-L$level-f$format"
    done
  done
done
uptime
# The level-8 data is too large to commit (2 MiB a run): keep its hashes.
(cd out && find . -name '*.bin' | sort | xargs sha256sum) > out/SHA256SUMS
