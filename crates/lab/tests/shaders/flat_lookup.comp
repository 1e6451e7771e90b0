#version 450
// Check kernel of crates/lab/tests/shaders.rs: mmi_micromap_state for the
// micro-triangles start .. start + count of one triangle, 4 bits per answer,
// eight answers per output word (answer k of invocation i in bits 4k..4k+3).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Data { uint data_words[]; };
layout(std430, set = 0, binding = 1) readonly buffer Triangles { uint triangle_words[]; };
layout(std430, set = 0, binding = 2) readonly buffer Indices { uint index_words[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Out { uint answers[]; };
layout(push_constant) uniform Query { uint start; uint count; uint triangle_id; uint index_width; };

#define MMI_DATA(i) data_words[i]
#define MMI_DATA_LENGTH uint(data_words.length())
#define MMI_TRIANGLES(i) triangle_words[i]
#define MMI_TRIANGLES_LENGTH uint(triangle_words.length())
#define MMI_INDICES(i) index_words[i]
#define MMI_INDICES_LENGTH uint(index_words.length())
#include "micromap_state.glsl"

void main()
{
    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (8u * i >= count) return;
    uint packed = 0u;
    for (uint k = 0u; k < 8u && 8u * i + k < count; k++) {
        packed |= mmi_micromap_state(index_width, triangle_id, start + 8u * i + k) << (4u * k);
    }
    answers[i] = packed;
}
