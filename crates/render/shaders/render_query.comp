#version 460
// The ray query tracer of the render check (crates/render, `micromap-index
// render --tracer query`): one primary ray per pixel with GL_EXT_ray_query
// against the alpha-masked meshes (geometry not opaque: every candidate the
// traversal does not decide itself reaches the rayQueryProceedEXT loop,
// which decides it by
// render_common.glsl's decide_candidate, the same code as the pipeline
// tracer's any-hit shader).
// Compiled by crates/render/shaders/compile.sh (committed SPIR-V).
#extension GL_EXT_ray_query : require
#extension GL_GOOGLE_include_directive : require
#ifdef MMI_SAMPLER_LOOKUP
#extension GL_EXT_nonuniform_qualifier : require
#endif
layout(local_size_x = 8, local_size_y = 8) in;

#include "render_common.glsl"

void main()
{
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= width || p.y >= height) return;
    uint pixel = p.y * width + p.x;
    rayQueryEXT q;
    rayQueryInitializeEXT(q, scene, gl_RayFlagsNoneEXT, 0xffu, eye.xyz, 0.0, primary_direction(p), 1.0e30);
    Counts n = no_counts();
    while (rayQueryProceedEXT(q)) {
        if (rayQueryGetIntersectionTypeEXT(q, false) != gl_RayQueryCandidateIntersectionTriangleEXT) continue;
        uint prim = uint(rayQueryGetIntersectionInstanceCustomIndexEXT(q, false))
                  + uint(rayQueryGetIntersectionPrimitiveIndexEXT(q, false));
        vec2 b = rayQueryGetIntersectionBarycentricsEXT(q, false);
        if (decide_candidate(pixel, prim, b, n)) rayQueryConfirmIntersectionEXT(q);
    }
    if (rayQueryGetIntersectionTypeEXT(q, true) == gl_RayQueryCommittedIntersectionTriangleEXT) {
        store_hit(pixel, uint(rayQueryGetIntersectionInstanceCustomIndexEXT(q, true))
                             + uint(rayQueryGetIntersectionPrimitiveIndexEXT(q, true)) + 1u,
                  rayQueryGetIntersectionTEXT(q, true));
    } else {
        store_hit(pixel, 0u, 0.0);
    }
    atomicAdd(counters[0], 1u);
    add_counts(n);
}
