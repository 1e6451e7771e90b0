#version 460
// The ray tracing pipeline tracer's closest-hit shader: returns the
// committed hit (the scene's primitive + 1, t's bits) to the ray generation
// shader.
// Compiled by crates/render/shaders/compile.sh (committed SPIR-V).
#extension GL_EXT_ray_tracing : require

layout(location = 0) rayPayloadInEXT uvec2 hit;

void main()
{
    hit = uvec2(uint(gl_InstanceCustomIndexEXT) + uint(gl_PrimitiveID) + 1u,
                floatBitsToUint(gl_HitTEXT));
}
