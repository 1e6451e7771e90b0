#version 460
// The ray tracing pipeline tracer's miss shader: no committed hit.
// Compiled by crates/render/shaders/compile.sh (committed SPIR-V).
#extension GL_EXT_ray_tracing : require

layout(location = 0) rayPayloadInEXT uvec2 hit;

void main()
{
    hit = uvec2(0u);
}
