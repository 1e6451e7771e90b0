#version 450
// Check kernel of crates/lab/tests/shaders.rs: mmi_level_order_get for the
// indices start .. start + count, 4 bits per answer, eight per output word.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Tree { uint tree_words[]; };
layout(std430, set = 0, binding = 1) readonly buffer Rank { uint rank_words[]; };
layout(std430, set = 0, binding = 2) readonly buffer Top { uint top_words[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Out { uint answers[]; };
layout(push_constant) uniform Query { uint start; uint count; uint top_depth; uint top_start; };

#define MMI_LOT(i) tree_words[i]
#define MMI_LOT_LENGTH uint(tree_words.length())
#define MMI_LOT_RANK(i) rank_words[i]
#define MMI_LOT_RANK_LENGTH uint(rank_words.length())
#define MMI_LOT_TOP(i) top_words[i]
#define MMI_LOT_TOP_LENGTH uint(top_words.length())
#include "level_order_tree.glsl"

void main()
{
    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (8u * i >= count) return;
    uint packed = 0u;
    for (uint k = 0u; k < 8u && 8u * i + k < count; k++) {
        packed |= mmi_level_order_get(start + 8u * i + k, top_depth, top_start) << (4u * k);
    }
    answers[i] = packed;
}
