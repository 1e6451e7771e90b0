#!/bin/sh
# The paper's evaluation in software (docs/render.md): for each committed
# asset and level, `micromap-index render` on the first Vulkan device with
# ray queries (lavapipe here: a CPU), our bake (GPU model, 4-state) made on
# the fly, every method; one TSV line per asset, level and method with the
# counters and the least process CPU time per frame. Then the plots.
#   docs/results/render_levels.sh [LEVELS] [SIZE] [FRAMES]
# (defaults 1..9, 256x256, 3). Writes docs/results/render_levels.tsv and
# docs/results/render_*.png; the device is named in the TSV's first line.
set -eu
cd "$(dirname "$0")/../.."
levels=${1:-"1 2 3 4 5 6 7 8 9"}
size=${2:-256x256}
frames=${3:-3}
cargo build --quiet --release -p micromap-index-cli
bin=target/release/micromap-index
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
tsv=docs/results/render_levels.tsv
first=1
for asset in crytek-sponza/cards.gltf polyhaven-fern02/fern_02.gltf; do
    name=$(basename "$asset" .gltf)
    for level in $levels; do
        "$bin" render --gltf "assets/$asset" --tracer query --level "$level" --size "$size" --frames "$frames" \
            --check --force --out "$tmp/$name-$level" >/dev/null
        python3 - "$tmp/$name-$level/render.json" "$name" "$level" "$first" >>"$tmp/tsv" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
if sys.argv[4] == "1":
    print("# device: " + j["device"])
    print("# size: %dx%d, %s" % (j["size"][0], j["size"][1], j["time"]))
    print("asset\tlevel\tmethod\tcandidates\ttexture_fetches\tknown\tunknown\tcontradicted\tdiffering_pixels\tfetches_saved\tdecided_without_texture\tcpu_ms_per_frame")
for m in j["methods"]:
    print("%s\t%s\t%s\t%d\t%d\t%d\t%d\t%d\t%d\t%.4f\t%.4f\t%.2f" % (
        sys.argv[2], sys.argv[3], m["method"], m["candidates"], m["texture_fetches"], m["known"],
        m["unknown"], m["contradicted"], m["pixels_differing_from_alpha_test"],
        m["texture_fetches_saved_fraction"], m["decided_without_texture_fraction"],
        1e3 * m["cpu_seconds_per_frame"]))
PY
        first=0
    done
done
mv "$tmp/tsv" "$tsv"
python3 docs/results/render_plot.py "$tsv"
echo "wrote $tsv and docs/results/render_*.png"
