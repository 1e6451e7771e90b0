#!/usr/bin/env bash
# Vertex alpha's cost (issue 34): the committed Poly Haven fern baked from
# its glTF as it is, and with a smooth COLOR_0 alpha added (0.7 at each
# mesh's lowest vertex to 1.0 at its highest, linear in height: every
# triangle a range of its own), at levels 4, 6 and 8 (LEVELS), on 1 thread
# and on every core, with the vertex-alpha bake's time over the plain one's
# (vs_plain). Reports the best wall time of ROUNDS bakes (`bake_seconds` from
# summary.json), peak memory (/usr/bin/time), the known fraction and the
# distinct triangles, and checks the one-thread vertex-alpha bakes at levels
# 4 and 6 (written back with --gltf-out) with verify-bake --gltf.
# Usage: docs/results/bake_vertex_alpha.sh [ROUNDS] > docs/results/bake_vertex_alpha.txt
set -euo pipefail
rounds=${1:-3}
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
cargo build --release --quiet -p micromap-index-cli
mi="$root/target/release/micromap-index"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fern=assets/polyhaven-fern02
python3 - "$fern" "$work" <<'PY'
import json, os, shutil, struct, sys
src, out = sys.argv[1], sys.argv[2]
d = json.load(open(f"{src}/fern_02.gltf"))
buf = open(f"{src}/fern_02.bin", "rb").read()
colors = bytearray()
for mesh in d["meshes"]:
    for prim in mesh["primitives"]:
        pos = d["accessors"][prim["attributes"]["POSITION"]]
        view = d["bufferViews"][pos["bufferView"]]
        at = view.get("byteOffset", 0) + pos.get("byteOffset", 0)
        stride = view.get("byteStride", 12)
        ys = [struct.unpack_from("<3f", buf, at + stride * i)[1] for i in range(pos["count"])]
        lo, hi = min(ys), max(ys)
        start = len(colors)
        for y in ys:
            colors += struct.pack("<4f", 1, 1, 1, 0.7 + 0.3 * (y - lo) / ((hi - lo) or 1))
        d["bufferViews"].append({"buffer": 1, "byteOffset": start, "byteLength": len(colors) - start})
        d["accessors"].append({"bufferView": len(d["bufferViews"]) - 1, "componentType": 5126,
                               "count": pos["count"], "type": "VEC4"})
        prim["attributes"]["COLOR_0"] = len(d["accessors"]) - 1
d["buffers"].append({"byteLength": len(colors), "uri": "colors.bin"})
open(f"{out}/colors.bin", "wb").write(colors)
shutil.copy(f"{src}/fern_02.bin", out)
for image in d["images"]:
    os.makedirs(os.path.dirname(f"{out}/{image['uri']}"), exist_ok=True)
    shutil.copy(f"{src}/{image['uri']}", f"{out}/{image['uri']}")
json.dump(d, open(f"{out}/fern_vertex_alpha.gltf", "w"))
PY
echo "# docs/results/bake_vertex_alpha.sh $rounds, commit $(git rev-parse --short HEAD)$(git diff --quiet || echo -dirty) ($(date -u +%F\ %H:%M) UTC)"
echo "# $(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //'), $(nproc) cores, load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-17s %5s %7s %10s %8s %8s %9s %8s %s\n' asset level threads best_s vs_plain peak_MB known distinct verify
for level in ${LEVELS:-4 6 8}; do
  for threads in 1 "$(nproc)"; do
    for asset in "$fern/fern_02.gltf" "$work/fern_vertex_alpha.gltf"; do
      best=
      for _ in $(seq "$rounds"); do
        rm -rf "$work/o"
        /usr/bin/time -f '%M' -o "$work/mem" "$mi" bake --gltf "$asset" --out "$work/o" --level "$level" \
          --threads "$threads" --quiet --no-preview --gltf-out out.glb >/dev/null
        s=$(python3 -c "import json; print(json.load(open('$work/o/summary.json'))['bake_seconds'])")
        best=$(python3 -c "print(min(float('$s'), float('${best:-inf}')))")
      done
      read -r known distinct < <(python3 -c "import json; s = json.load(open('$work/o/summary.json')); print(round(s['known_fraction'], 5), s['distinct_triangles'])")
      verdict=-
      case $asset:$level:$threads in
        *vertex_alpha*:[46]:1)
          "$mi" verify-bake --gltf "$work/o/out.glb" --json >"$work/v.json" || true
          verdict=$(python3 -c "import json; v = json.load(open('$work/v.json')); print('sound' if v['sound'] else 'UNSOUND')")
          ;;
      esac
      case $asset in
        *vertex_alpha*) ratio=$(python3 -c "print(f'{$best / $plain:.2f}x')") ;;
        *) plain=$best ratio=- ;;
      esac
      printf '%-17s %5s %7s %10.4f %8s %8.1f %8s %9s %s\n' "$(basename "$asset" .gltf)" "$level" "$threads" "$best" \
        "$ratio" "$(($(cat "$work/mem") / 1024)).0" "$known" "$distinct" "$verdict"
    done
  done
done
