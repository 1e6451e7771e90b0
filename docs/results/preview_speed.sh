#!/usr/bin/env bash
# Bakes each committed asset at level 8 and prints, per asset, the bake's
# and the preview's seconds from summary.json (issue 38: the preview, drawn
# at its own resolution by the library's index function, takes at most as
# long as the bake). The best of three runs of each; the CPU and the load
# are printed with them. Usage: docs/results/preview_speed.sh [BIN]
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=${1:-target/release/micromap-index}
if [ $# -eq 0 ]; then cargo build --release --quiet -p micromap-index-cli; fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
grep -m1 "model name" /proc/cpuinfo
echo "cores: $(nproc)"
uptime
printf '%-8s %10s %10s %8s %10s %10s\n' asset triangles distinct bake_s preview_s preview/bake
run() { # run NAME ARGS...
  local name=$1; shift
  for r in 1 2 3; do
    "$bin" bake "$@" --level 8 --out "$out/$name" --force --quiet > "$out/$name.$r.json"
  done
  python3 - "$name" "$out/$name".{1,2,3}.json <<'PY'
import json, sys
name, files = sys.argv[1], sys.argv[2:]
runs = [json.load(open(f)) for f in files]
bake = min(r["bake_seconds"] for r in runs)
preview = min(r["preview_seconds"] for r in runs)
s = runs[0]
print(f"{name:<8} {s['triangles']:10d} {s['distinct_triangles']:10d} {bake:8.3f} {preview:10.3f} {preview / bake:10.2f}")
PY
}
run fern --gltf assets/polyhaven-fern02/fern_02.gltf
run cards --gltf assets/crytek-sponza/cards.gltf
run grid --texture assets/crytek-sponza/sponza_thorn.png \
  --triangles assets/crytek-sponza/grid.tris.json --filter linear --address clamp-to-edge
uptime
