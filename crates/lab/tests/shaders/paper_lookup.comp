#version 450
// Check kernel of crates/lab/tests/shaders.rs: mmi_paper_tree_get for the
// indices start .. start + count (or, with `listed` 1, for the indices in
// binding 1), 4 bits per answer, eight per output word.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Tree { uint tree_words[]; };
layout(std430, set = 0, binding = 1) readonly buffer List { uint list[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Out { uint answers[]; };
layout(push_constant) uniform Query { uint start; uint count; uint listed; uint unused; };

#define MMI_PAPER(i) tree_words[i]
#define MMI_PAPER_LENGTH uint(tree_words.length())
#include "paper_tree.glsl"

void main()
{
    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (8u * i >= count) return;
    uint packed = 0u;
    for (uint k = 0u; k < 8u && 8u * i + k < count; k++) {
        uint index = listed != 0u ? list[8u * i + k] : start + 8u * i + k;
        packed |= mmi_paper_tree_get(index) << (4u * k);
    }
    answers[i] = packed;
}
