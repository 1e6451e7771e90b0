#!/usr/bin/env bash
# The Khronos glTF-Validator on bake --gltf-out's outputs (issue 34): installs
# gltf-validator 2.0.0-dev.3.10 from npm into a scratch folder, bakes the
# committed cards (cards.gltf and cards.glb) at level 4 into NAME.gltf and
# NAME.glb, moves every output folder elsewhere (an output must stand
# alone), and validates each there. Prints each file's counts and messages;
# exit 1 on any error or warning (infos and hints are printed, not failed:
# the validator does not know EXT_mesh_opacity_micromap, and says so as an
# info). Needs node/npm and the npm registry. Run by .ci/run.
# Usage: docs/results/gltf_validator.sh [BIN]
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=${1:-target/release/micromap-index}
if [ $# -eq 0 ]; then cargo build --release --quiet -p micromap-index-cli; fi
bin=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")
assets=$(pwd)/assets/crytek-sponza
w=$(mktemp -d)
trap 'rm -rf "$w"' EXIT
(cd "$w" && npm init -y >/dev/null 2>&1 \
  && npm install --no-audit --no-fund --silent gltf-validator@2.0.0-dev.3.10 >/dev/null 2>&1) \
  || { echo "npm install gltf-validator failed" >&2; exit 1; }
for input in cards.gltf cards.glb; do
  for name in "with omm.gltf" out.glb; do
    "$bin" bake --gltf "$assets/$input" --out "$w/baked/$input $name" --level 4 --quiet \
      --gltf-out "$name" >/dev/null
  done
done
mv "$w/baked" "$w/moved"
cat > "$w/validate.js" <<'JS'
// Each file given, its external resources read beside it.
const validator = require('gltf-validator');
const fs = require('fs');
const path = require('path');
(async () => {
  let bad = 0;
  for (const file of process.argv.slice(2)) {
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
      uri: path.basename(file),
      externalResourceFunction: (uri) => new Promise((resolve, reject) => {
        const at = path.join(path.dirname(file), decodeURIComponent(uri));
        fs.readFile(at, (err, data) => (err ? reject(err.toString()) : resolve(new Uint8Array(data))));
      }),
    });
    const i = report.issues;
    console.log(`${path.basename(path.dirname(file))}/${path.basename(file)}: ${i.numErrors} errors, ` +
      `${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints`);
    for (const m of i.messages) {
      console.log(`  ${['error', 'warning', 'info', 'hint'][m.severity]} ${m.code} ${m.pointer || ''}`);
    }
    if (i.numErrors + i.numWarnings > 0) bad++;
  }
  process.exit(bad ? 1 : 0);
})();
JS
echo "gltf-validator $(node -p "require('$w/node_modules/gltf-validator/package.json').version"), outputs moved after the bake"
cd "$w" && node validate.js moved/*/*.gltf moved/*/*.glb
