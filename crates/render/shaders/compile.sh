#!/bin/sh
# Regenerates the committed SPIR-V of the render check from its GLSL and the
# shader library (shaders/glsl, included, never copied). Run from anywhere;
# tests/spirv.rs checks that the committed file equals this script's output.
#   crates/render/shaders/compile.sh [OUT_DIR]   (default: next to the source)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
out=${1:-$here}
glslangValidator -V --target-env vulkan1.2 -I"$here/../../../shaders/glsl" \
    "$here/render_query.comp" -o "$out/render_query.spv" >/dev/null
spirv-val --target-env vulkan1.2 "$out/render_query.spv"
