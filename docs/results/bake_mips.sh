#!/usr/bin/env bash
# Known fraction at level 8 on the committed assets for each --mips rule
# (0: level 0 only, the default; N: levels 0..=N; all: down to 1x1),
# under the default GPU model, with the bake time (summary.json's
# bake_seconds) on this machine. Usage: docs/results/bake_mips.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release --quiet -p micromap-index-cli
bin=target/release/micromap-index
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
printf '%-6s %-6s %14s %12s\n' asset mips known_fraction seconds
for asset in grid cards; do
  if [ "$asset" = grid ]; then
    input=(--texture assets/crytek-sponza/sponza_thorn.png --triangles assets/crytek-sponza/grid.tris.json)
  else
    input=(--gltf assets/crytek-sponza/cards.gltf)
  fi
  for mips in 0 1 2 3 4 all; do
    "$bin" bake "${input[@]}" --out "$out/b" --force --level 8 --mips "$mips" \
      --no-preview --quiet > "$out/s.json"
    python3 -c "import json;s=json.load(open('$out/s.json'));assert s['mips']=='$mips';print('%-6s %-6s %14.4f %12.2f' % ('$asset','$mips',s['known_fraction'],s['bake_seconds']))"
  done
done
