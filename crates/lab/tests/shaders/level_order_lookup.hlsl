// Check kernel of crates/lab/tests/shaders.rs: the HLSL twin of
// level_order_lookup.comp (same bindings, push constants and answers).
[[vk::binding(0, 0)]] StructuredBuffer<uint> tree_words;
[[vk::binding(1, 0)]] StructuredBuffer<uint> rank_words;
[[vk::binding(2, 0)]] StructuredBuffer<uint> top_words;
[[vk::binding(3, 0)]] RWStructuredBuffer<uint> answers;
struct Query { uint start; uint count; uint top_depth; uint top_start; };
[[vk::push_constant]] ConstantBuffer<Query> q;

static uint tree_length;
static uint rank_length;
static uint top_length;
#define MMI_LOT(i) tree_words[i]
#define MMI_LOT_LENGTH tree_length
#define MMI_LOT_RANK(i) rank_words[i]
#define MMI_LOT_RANK_LENGTH rank_length
#define MMI_LOT_TOP(i) top_words[i]
#define MMI_LOT_TOP_LENGTH top_length
#include "level_order_tree.hlsl"

[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID)
{
    uint stride;
    tree_words.GetDimensions(tree_length, stride);
    rank_words.GetDimensions(rank_length, stride);
    top_words.GetDimensions(top_length, stride);
    uint i = id.x + id.y * 262144u;
    if (8u * i >= q.count) return;
    uint packed = 0u;
    for (uint k = 0u; k < 8u && 8u * i + k < q.count; k++) {
        packed |= mmi_level_order_get(q.start + 8u * i + k, q.top_depth, q.top_start) << (4u * k);
    }
    answers[i] = packed;
}
