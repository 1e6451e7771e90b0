#!/usr/bin/env bash
# What the glTF tools people run before a bake do to EXT_mesh_opacity_micromap
# (issue 38): installs gltf-transform 4.5 and gltfpack 1.3 from npm into a
# scratch folder, runs them on a baked asset (the committed cards at level
# 4, written back with --gltf-out) and on the unbaked asset, and prints per
# output the extensions used, the meshes and primitives, how many carry the
# extension, and what `verify-bake --gltf` and a bake say. Needs node/npm and
# the npm registry. Usage: docs/results/gltf_tools.sh [BIN]
set -uo pipefail
cd "$(dirname "$0")/../.."
bin=${1:-target/release/micromap-index}
if [ $# -eq 0 ]; then cargo build --release --quiet -p micromap-index-cli; fi
bin=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")
assets=$(pwd)/assets/crytek-sponza
w=$(mktemp -d)
trap 'rm -rf "$w"' EXIT
cd "$w"
npm init -y >/dev/null 2>&1
npm install --no-audit --no-fund --silent @gltf-transform/cli@4.5 gltfpack@1.3 >/dev/null 2>&1 \
  || { echo "npm install failed"; exit 1; }
echo "gltf-transform $(npx gltf-transform --version 2>&1 | tail -1), $(npx gltfpack -h 2>&1 | head -1)"
inspect() { python3 - "$@" <<'PY'
import json, struct, sys
for path in sys.argv[1:]:
    d = open(path, 'rb').read()
    n = struct.unpack('<I', d[12:16])[0]
    j = json.loads(d[20:20 + n])
    prims = [pr for mesh in j.get('meshes', []) for pr in mesh['primitives']]
    ext = sum(1 for pr in prims if 'EXT_mesh_opacity_micromap' in (pr.get('extensions') or {}))
    print(f"  {path}: extensionsUsed {j.get('extensionsUsed')}, {len(j.get('meshes', []))} meshes, "
          f"{len(prims)} primitives, {ext} with EXT_mesh_opacity_micromap")
PY
}
run() { # run LABEL COMMAND...: the command's stderr/stdout lines that warn, and its exit code
  local label=$1; shift
  echo "\$ $label"
  "$@" >out.log 2>&1; local rc=$?
  grep -iE "warn|micromap|error" out.log | sed 's/^/  | /' | sort -u
  echo "  exit $rc"
}
echo "== a baked asset through the tools"
"$bin" bake --gltf "$assets/cards.gltf" --out baked --gltf-out cards-omm.glb --level 4 --quiet --no-preview >/dev/null
inspect baked/cards-omm.glb
run "gltf-transform copy cards-omm.glb copy.glb" npx gltf-transform copy baked/cards-omm.glb copy.glb
run "gltf-transform optimize cards-omm.glb optimize.glb" npx gltf-transform optimize baked/cards-omm.glb optimize.glb
run "gltfpack -i cards-omm.glb -o pack.glb" npx gltfpack -i baked/cards-omm.glb -o pack.glb
inspect copy.glb optimize.glb pack.glb
for f in copy.glb optimize.glb pack.glb; do
  echo "\$ micromap-index verify-bake --gltf $f"
  "$bin" verify-bake --gltf "$f" 2>&1 | sed 's/^/  | /'
done
echo "== the tools first, the bake last"
run "gltfpack -i cards.glb -o pack-noq.glb -noq" npx gltfpack -i "$assets/cards.glb" -o pack-noq.glb -noq
run "gltf-transform optimize cards.glb optimize-nc.glb --compress false --texture-compress false" \
  npx gltf-transform optimize "$assets/cards.glb" optimize-nc.glb --compress false --texture-compress false
for f in pack-noq.glb optimize-nc.glb; do
  echo "\$ micromap-index bake --gltf $f --gltf-out out.glb --level 4; verify-bake --gltf out.glb"
  "$bin" bake --gltf "$f" --out "last-$f" --gltf-out out.glb --level 4 --quiet --no-preview >/dev/null 2>&1
  echo "  bake exit $?"
  "$bin" verify-bake --gltf "last-$f/out.glb" 2>&1 | head -1 | sed 's/^/  | /'
  inspect "last-$f/out.glb"
done
echo "== default gltfpack (quantized UVs) and gltf-transform optimize (meshopt) before a bake"
run "gltfpack -i cards.glb -o pack-q.glb" npx gltfpack -i "$assets/cards.glb" -o pack-q.glb
run "gltf-transform optimize cards.glb optimize-c.glb" npx gltf-transform optimize "$assets/cards.glb" optimize-c.glb
for f in pack-q.glb optimize-c.glb; do
  echo "\$ micromap-index bake --gltf $f"
  "$bin" bake --gltf "$f" --out "q-$f" --level 4 --quiet --no-preview 2>&1 >/dev/null | sed 's/^/  | /'
done
