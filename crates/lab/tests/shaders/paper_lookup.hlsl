// Check kernel of crates/lab/tests/shaders.rs: the HLSL twin of
// paper_lookup.comp (same bindings, push constants and answers).
[[vk::binding(0, 0)]] StructuredBuffer<uint> tree_words;
[[vk::binding(1, 0)]] StructuredBuffer<uint> list;
[[vk::binding(2, 0)]] RWStructuredBuffer<uint> answers;
struct Query { uint start; uint count; uint listed; uint unused; };
[[vk::push_constant]] ConstantBuffer<Query> q;

static uint tree_length;
#define MMI_PAPER(i) tree_words[i]
#define MMI_PAPER_LENGTH tree_length
#include "paper_tree.hlsl"

[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID)
{
    uint stride;
    tree_words.GetDimensions(tree_length, stride);
    uint i = id.x + id.y * 262144u;
    if (8u * i >= q.count) return;
    uint packed = 0u;
    for (uint k = 0u; k < 8u && 8u * i + k < q.count; k++) {
        uint index = q.listed != 0u ? list[8u * i + k] : q.start + 8u * i + k;
        packed |= mmi_paper_tree_get(index) << (4u * k);
    }
    answers[i] = packed;
}
