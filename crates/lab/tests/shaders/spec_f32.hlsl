// Check kernel of crates/lab/tests/shaders.rs: the HLSL twin of
// reference/drivers/glsl/spec_f32.comp (same buffers and push constant).
#include "micromap_index.hlsl"

[[vk::binding(0, 0)]] StructuredBuffer<uint4> cases;
[[vk::binding(1, 0)]] RWStructuredBuffer<uint> indices;
struct Count { uint case_count; };
[[vk::push_constant]] ConstantBuffer<Count> count;

[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID)
{
    uint i = id.x;
    if (i >= count.case_count) return;
    uint4 c = cases[i];
    indices[i] = BarycentricsToSpaceFillingCurveIndex(asfloat(c.x), asfloat(c.y), c.z);
}
