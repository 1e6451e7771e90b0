#!/bin/sh
# The two tracers of `micromap-index render` side by side (docs/render.md):
# for each committed asset at levels 4 and 8, our bake (GPU model, 4-state)
# made on the fly, every method under --tracer both; one TSV line per asset,
# level and method with each tracer's candidates, fetches and least process
# CPU time per frame, and whether the tracers' counters are equal.
#   docs/results/render_tracers.sh [LEVELS] [SIZE] [FRAMES]
# (defaults "4 8", 256x256, 3). Writes docs/results/render_tracers.tsv; the
# device is named in its first line. Built with the test profile (opt-level
# 2, as the tests run it).
set -eu
cd "$(dirname "$0")/../.."
levels=${1:-"4 8"}
size=${2:-256x256}
frames=${3:-3}
cargo build --quiet --profile test -p micromap-index-cli
bin=target/debug/micromap-index
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
first=1
for asset in crytek-sponza/cards.gltf polyhaven-fern02/fern_02.gltf; do
    name=$(basename "$asset" .gltf)
    for level in $levels; do
        "$bin" render --gltf "assets/$asset" --level "$level" --size "$size" --frames "$frames" \
            --tracer both --lookup shader --check --force --out "$tmp/$name-$level" >/dev/null
        python3 - "$tmp/$name-$level/render.json" "$name" "$level" "$first" >>"$tmp/tsv" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
if sys.argv[4] == "1":
    print("# device: " + j["device"])
    print("# size: %dx%d, %s" % (j["size"][0], j["size"][1], j["time"]))
    print("asset\tlevel\tmethod\tquery_candidates\tpipeline_candidates\tquery_fetches\tpipeline_fetches\tcounters_equal\tquery_cpu_ms\tpipeline_cpu_ms\tpipeline_over_query")
by = {(m["tracer"], m["method"]): m for m in j["methods"]}
for method in [m["method"] for m in j["methods"] if m["tracer"] == "query"]:
    q, p = by[("query", method)], by[("pipeline", method)]
    keys = ["candidates", "texture_fetches", "known", "unknown", "contradicted", "invalid"]
    qt, pt = 1e3 * q["cpu_seconds_per_frame"], 1e3 * p["cpu_seconds_per_frame"]
    print("%s\t%s\t%s\t%d\t%d\t%d\t%d\t%s\t%.2f\t%.2f\t%.2f" % (
        sys.argv[2], sys.argv[3], method, q["candidates"], p["candidates"],
        q["texture_fetches"], p["texture_fetches"],
        "yes" if all(q[k] == p[k] for k in keys) else "no", qt, pt, pt / qt))
PY
        first=0
    done
done
mv "$tmp/tsv" docs/results/render_tracers.tsv
echo "wrote docs/results/render_tracers.tsv"
