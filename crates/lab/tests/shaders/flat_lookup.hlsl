// Check kernel of crates/lab/tests/shaders.rs: the HLSL twin of
// flat_lookup.comp (same bindings, push constants and answers).
[[vk::binding(0, 0)]] StructuredBuffer<uint> data_words;
[[vk::binding(1, 0)]] StructuredBuffer<uint> triangle_words;
[[vk::binding(2, 0)]] StructuredBuffer<uint> index_words;
[[vk::binding(3, 0)]] RWStructuredBuffer<uint> answers;
struct Query { uint start; uint count; uint triangle_id; uint index_width; };
[[vk::push_constant]] ConstantBuffer<Query> q;

static uint data_length;
static uint triangle_length;
static uint index_length;
#define MMI_DATA(i) data_words[i]
#define MMI_DATA_LENGTH data_length
#define MMI_TRIANGLES(i) triangle_words[i]
#define MMI_TRIANGLES_LENGTH triangle_length
#define MMI_INDICES(i) index_words[i]
#define MMI_INDICES_LENGTH index_length
#include "micromap_constants.hlsl"
#include "micromap_state.hlsl"

[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID)
{
    uint stride;
    data_words.GetDimensions(data_length, stride);
    triangle_words.GetDimensions(triangle_length, stride);
    index_words.GetDimensions(index_length, stride);
    // The host dispatches rows of 4,096 workgroups of 64.
    uint i = id.x + id.y * 262144u;
    if (8u * i >= q.count) return;
    uint packed = 0u;
    for (uint k = 0u; k < 8u && 8u * i + k < q.count; k++) {
        packed |= mmi_micromap_state(q.index_width, q.triangle_id, q.start + 8u * i + k) << (4u * k);
    }
    answers[i] = packed;
}
