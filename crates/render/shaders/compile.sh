#!/bin/sh
# Regenerates the committed SPIR-V of the render check from its GLSL and the
# shader library (shaders/glsl, included, never copied): the ray query
# tracer (render_query.comp) and the ray tracing pipeline tracer
# (render_pipeline.rgen, .rahit, .rchit, .rmiss), both including
# render_common.glsl; and the sampler lookup's variants of the two that
# decide candidates (render_query_sampler.spv, render_pipeline_rahit_sampler.spv:
# -DMMI_SAMPLER_LOOKUP, the alpha test through a combined image sampler).
# Run from anywhere; tests/spirv.rs checks that the committed files equal
# this script's output.
#   crates/render/shaders/compile.sh [OUT_DIR]   (default: next to the source)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
out=${1:-$here}
for shader in render_query.comp render_pipeline.rgen render_pipeline.rahit \
    render_pipeline.rchit render_pipeline.rmiss; do
    spv=$(echo "$shader" | tr . _).spv
    [ "$shader" = render_query.comp ] && spv=render_query.spv
    glslangValidator -V --target-env vulkan1.2 -I"$here/../../../shaders/glsl" \
        "$here/$shader" -o "$out/$spv" >/dev/null
    spirv-val --target-env vulkan1.2 "$out/$spv"
done
for shader in render_query.comp render_pipeline.rahit; do
    spv=$(echo "$shader" | tr . _)_sampler.spv
    [ "$shader" = render_query.comp ] && spv=render_query_sampler.spv
    glslangValidator -V --target-env vulkan1.2 -DMMI_SAMPLER_LOOKUP \
        -I"$here/../../../shaders/glsl" "$here/$shader" -o "$out/$spv" >/dev/null
    spirv-val --target-env vulkan1.2 "$out/$spv"
done
