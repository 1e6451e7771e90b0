#!/bin/sh
# The paper's Table 3 on a GPU (docs/render.md, issue 35): alpha test, flat
# emulation, level-order tree, paper tree and the driver's own opacity
# micromaps (VK_EXT_opacity_micromap, as baked and forced to 2 states) on the
# committed assets at every level, one `micromap-index render --check` per
# asset and level, each under both lookups (--lookup both: the shader's
# binary32 alpha test and the device's texture unit through a combined image
# sampler); render.json per run, a table (TSV and markdown) and plots.
#
#   docs/results/gpu_render.sh [--bin PATH] [--out DIR] [--levels "1 .. 12"]
#       [--size 1920x1080] [--frames 5] [--tracer auto|query|pipeline|both]
#       [--device N|NAME]
#
# On a fresh NVIDIA machine (no Vulkan loader, no network) it needs the
# loader's Debian packages in .gl/ (fetched beforehand on a machine with
# apt, as /work/.library/device/README.md describes: `apt-get download
# libvulkan1` for amd64) and a built CLI (--bin, or target/release/
# micromap-index, or cargo). It unpacks .gl/*.deb into / and runs ldconfig
# when no libvulkan.so.1 is installed, and points VK_DRIVER_FILES at the
# NVIDIA ICD under /usr/local/nvidia when the loader's own search finds no
# driver. --tracer auto (the default) traces both tracers where the device
# has both extensions, else the one it has (NVIDIA's headless machines have
# run ray tracing pipelines, not ray queries). Where the device has no
# VK_EXT_opacity_micromap (lavapipe, every CPU device) the hardware methods
# are listed as unsupported and the rest still run; a bake refused by
# --max-bytes (the fern at the highest levels) is listed as refused. Exit 1
# if any run's check failed (the table says which), else 0.
#
# Defaults: levels 1..12, 1920x1080, 5 frames, DIR docs/results/gpu. On
# lavapipe, try it small: --levels "1 2" --size 160x90 --frames 1 --out /tmp/g
set -eu
cd "$(dirname "$0")/../.."
bin= out=docs/results/gpu levels="1 2 3 4 5 6 7 8 9 10 11 12" size=1920x1080 frames=5
tracer=auto device=
while [ $# -gt 0 ]; do
    case $1 in
    --bin) bin=$2 ;;
    --out) out=$2 ;;
    --levels) levels=$2 ;;
    --size) size=$2 ;;
    --frames) frames=$2 ;;
    --tracer) tracer=$2 ;;
    --device) device=$2 ;;
    *) sed -n '2,30p' "$0" >&2; exit 2 ;;
    esac
    shift 2
done

echo "== Vulkan loader and driver"
if ! ldconfig -p 2>/dev/null | grep -q 'libvulkan\.so\.1'; then
    if ls .gl/*.deb >/dev/null 2>&1; then
        for f in .gl/*.deb; do dpkg -x "$f" /; done
        ldconfig
    else
        echo "no libvulkan.so.1 and no .gl/*.deb to unpack (see the header of $0)" >&2
        exit 4
    fi
fi
nvidia_icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
if [ -f "$nvidia_icd" ] && ! ls /usr/share/vulkan/icd.d/*nvidia* /etc/vulkan/icd.d/*nvidia* >/dev/null 2>&1; then
    export VK_DRIVER_FILES="${VK_DRIVER_FILES:-$nvidia_icd}"
    export VK_ICD_FILENAMES="${VK_ICD_FILENAMES:-$nvidia_icd}"
fi

echo "== the CLI"
if [ -z "$bin" ]; then
    if [ -x target/release/micromap-index ]; then
        bin=target/release/micromap-index
    elif command -v cargo >/dev/null 2>&1; then
        cargo build --quiet --release -p micromap-index-cli
        bin=target/release/micromap-index
    else
        echo "no micromap-index: build it (cargo build --release -p micromap-index-cli) or pass --bin" >&2
        exit 2
    fi
fi
"$bin" help render >/dev/null && echo "$bin"

mkdir -p "$out"
rm -rf "$out"/*-[0-9]* "$out/unsupported.tsv"
probe=$(mktemp -d)
trap 'rm -rf "$probe"' EXIT
cards=assets/crytek-sponza/cards.gltf
# A tiny render: exit 0 or 4 (no such device); its stderr says why.
try() {
    "$bin" render --gltf "$cards" --level 1 --size 2x2 --force --out "$probe/p" \
        ${device:+--device "$device"} "$@" >/dev/null 2>"$probe/why"
}
if [ "$tracer" = auto ]; then
    for t in both pipeline query; do
        if try --tracer "$t" --methods alpha-test; then tracer=$t; break; fi
    done
    [ "$tracer" != auto ] || { cat "$probe/why" >&2; exit 4; }
fi
echo "tracer: $tracer"
methods=flat-4-state,flat-2-state,level-order-tree,paper-tree
if try --tracer "$tracer" --methods hardware,hardware-2-state; then
    methods=$methods,hardware,hardware-2-state
else
    if grep -q 'without VK_EXT_opacity_micromap' "$probe/why"; then
        why="the device has no VK_EXT_opacity_micromap"
    else
        why=$(sed 's/^micromap-index: render: //' "$probe/why")
    fi
    printf 'hardware\t%s\nhardware-2-state\t%s\n' "$why" "$why" > "$out/unsupported.tsv"
    echo "hardware micromaps unsupported: $why"
fi

echo "== runs ($size, $frames frames, levels $levels)"
failed=0
for asset in crytek-sponza/cards.gltf polyhaven-fern02/fern_02.gltf; do
    name=$(basename "$asset" .gltf)
    for level in $levels; do
        run="$out/$name-$level"
        set +e
        "$bin" render --gltf "assets/$asset" --tracer "$tracer" --lookup both --methods "$methods" \
            --level "$level" --size "$size" --frames "$frames" --check --force \
            ${device:+--device "$device"} --out "$run" >"$probe/stdout" 2>"$probe/stderr"
        status=$?
        set -e
        case $status in
        0) echo "$name level $level: passed" ;;
        1) echo "$name level $level: check FAILED"; failed=1 ;;
        2) mv "$probe/stderr" "$run.refused"; rm -rf "$run"
           echo "$name level $level: refused: $(tail -1 "$run.refused")"; continue ;;
        *) cat "$probe/stderr" >&2; exit "$status" ;;
        esac
        # Keep render.json; the pictures of every run would be hundreds of MB.
        find "$run" -name '*.png' ! -name 'alpha-test.png' ! -name 'pipeline-alpha-test.png' \
            ! -name 'sampler-alpha-test.png' ! -name 'sampler-alpha-test-diff.png' -delete
    done
done

echo "== table and plots"
python3 docs/results/render_table.py "$out" > "$out/table.tsv"
python3 docs/results/render_table.py "$out" --markdown > "$out/table.md"
python3 docs/results/render_plot.py "$out/table.tsv" --out "$out/"
echo "wrote $out/table.tsv, table.md, saved.png, cost.png and one render.json per run"
exit "$failed"
