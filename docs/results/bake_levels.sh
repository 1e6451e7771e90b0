#!/usr/bin/env bash
# Bakes the Crytek Sponza thorn texture over the 8x8-quad grid (128 triangles)
# at levels 0..=8, 4-state, linear filtering, clamp-to-edge, cutoff 0.5, and
# prints one row per level: known fraction, bake time per micro-triangle,
# flat / paper-tree / level-order-tree bytes. Usage: docs/results/bake_levels.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release --quiet -p micromap-index-cli
bin=target/release/micromap-index
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
grep -m1 "model name" /proc/cpuinfo
uptime
printf '%-5s %12s %8s %10s %10s %10s %10s %8s %8s\n' level micro-tris known ns/micro flat paper level-ord paper% lo%
for level in 0 1 2 3 4 5 6 7 8; do
  best=""
  for run in 1 2 3; do
    "$bin" bake --texture assets/crytek-sponza/sponza_thorn.png \
      --triangles assets/crytek-sponza/grid.tris.json --out "$out/L$level" --force \
      --level "$level" --format 4 --filter linear --address clamp-to-edge --model exact \
      --no-preview --quiet > "$out/s$run.json"
    best=$(python3 -c "
import json,sys
runs=[json.load(open('$out/s%d.json'%r)) for r in range(1,$run+1)]
print(min(r['bake_seconds'] for r in runs))")
  done
  python3 - "$out/s1.json" "$best" "$level" <<'PY'
import json, sys
s = json.load(open(sys.argv[1])); best = float(sys.argv[2]); level = sys.argv[3]
m = s["micro_triangles"]; total = sum(m.values())
flat = s["bytes_flat"]  # after deduplication and special indices
pct = lambda b: f"{100 * b / flat:7.1f}%" if flat else "    n/a "
print(f"{level:<5} {total:12d} {s['known_fraction']:8.4f} {best / total * 1e9:10.1f} {flat:10d} {s['bytes_paper_tree']:10d} {s['bytes_level_order_tree']:10d} {pct(s['bytes_paper_tree'])} {pct(s['bytes_level_order_tree'])}  maps {s['micromaps_after_dedup']} special {s['special_index_triangles']}")
PY
done
uptime
