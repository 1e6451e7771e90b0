#!/bin/sh
# The paper's evaluation in software (docs/render.md): for each committed
# asset and level, `micromap-index render --check` on the first Vulkan device
# with ray queries (lavapipe here: a CPU), the ray query tracer, our bake
# (GPU model, 4-state) made on the fly, the five emulated methods, the fitted
# default camera. Then one table (render_table.py: counters, hit fraction,
# times per frame, check status per asset, level and method), its markdown
# form and the plots (render_plot.py, CPU time: lavapipe has no GPU clock
# worth reading).
#   docs/results/render_levels.sh [LEVELS] [SIZE] [FRAMES]
# (defaults 1..9, 256x256, 5). Writes docs/results/render_levels.tsv,
# render_levels.md, render_saved.png and render_cost.png; the device and
# driver are named in each.
set -eu
cd "$(dirname "$0")/../.."
levels=${1:-"1 2 3 4 5 6 7 8 9"}
size=${2:-256x256}
frames=${3:-5}
cargo build --quiet --release -p micromap-index-cli
bin=target/release/micromap-index
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir "$tmp/runs"
for asset in crytek-sponza/cards.gltf polyhaven-fern02/fern_02.gltf; do
    name=$(basename "$asset" .gltf)
    for level in $levels; do
        "$bin" render --gltf "assets/$asset" --tracer query --lookup shader --level "$level" --size "$size" \
            --frames "$frames" --check --force --out "$tmp/$name-$level" >/dev/null
        mkdir "$tmp/runs/$name-$level"
        mv "$tmp/$name-$level/render.json" "$tmp/runs/$name-$level/"
    done
done
python3 docs/results/render_table.py "$tmp/runs" > docs/results/render_levels.tsv
python3 docs/results/render_table.py "$tmp/runs" --markdown --time cpu > docs/results/render_levels.md
python3 docs/results/render_plot.py docs/results/render_levels.tsv --time cpu
echo "wrote docs/results/render_levels.tsv, render_levels.md and render_{saved,cost}.png"
