// The render check's shared part (crates/render): the bindings, the push
// constants, the binary32 alpha test, the micromap lookups and the decision
// of one candidate by `method`. Included by both tracers, the ray query
// compute shader (render_query.comp) and the ray tracing pipeline's any-hit
// and ray generation shaders (render_pipeline.rahit, .rgen), so the two
// tracers decide by the same code. The includer enables GL_EXT_ray_query or
// GL_EXT_ray_tracing (for accelerationStructureEXT) and
// GL_GOOGLE_include_directive first.
// Methods (push constant `method`):
//   0 alpha test only                  every candidate fetches the texture
//   1 flat micromap, 4-state           known states decide, unknown -> alpha test
//   2 flat micromap, forced 2-state    the state's low bit decides
//                                      (VK_GEOMETRY_INSTANCE_FORCE_OPACITY_MICROMAP_2_STATE_EXT)
//   3 level-order tree, 4-state        as 1, the state from level_order_tree.glsl
//   4 paper tree (Algorithm 3), 4-state as 1, from paper_tree.glsl
//   5 hardware micromap                the driver's VK_EXT_opacity_micromap
//   6 hardware micromap, forced 2-state  decides known states before any-hit;
//                                      what it hands the shader runs the
//                                      alpha test, as method 0
// Every known decision is also checked against the alpha test (not counted
// as a fetch): a disagreement is a contradicted candidate, counted in its
// pixel's third word and, for pixels below `record_limit`, recorded with its
// pixel, primitive, micro-triangle, binary32 barycentrics and the alpha the
// test compared (its bits) for the host's exact classification (the host orders the records by pixel, so both
// tracers list the same first ones).
// A primitive's number is its instance's custom index (the mesh's first
// triangle) plus its index in the mesh's BLAS: the scene's triangle order. The lookups come from shaders/glsl (included, never
// copied); the texture is sampled by the code below (nearest or bilinear,
// Vulkan's address modes, binary32), so the host can recompute any fetch,
// or, compiled with MMI_SAMPLER_LOOKUP (the includer enables
// GL_EXT_nonuniform_qualifier), by the device's texture unit: a combined
// image sampler per mesh (binding 12: the texture's alpha as UNORM, the
// mesh's filter, address modes and border), textureLod at level 0 of the
// same binary32 texture coordinate, then the same binary32 alpha test.
#ifndef RENDER_COMMON_GLSL
#define RENDER_COMMON_GLSL

layout(set = 0, binding = 0) uniform accelerationStructureEXT scene;
// Per triangle (the BLAS's primitive order), TRI_WORDS floats: uv0, uv1,
// uv2, then the vertex alphas a0, a1, a2 (1 for a mesh without).
#define TRI_WORDS 9u
layout(std430, set = 0, binding = 1) readonly buffer TriangleUvs { float tri_uv[]; };
// Per triangle: its material (mesh) number.
layout(std430, set = 0, binding = 2) readonly buffer TriangleMesh { uint tri_mesh[]; };
// Per mesh, MESH_WORDS words: texel base, width, height, filter (0 nearest,
// 1 linear), address u, address v (0 repeat, 1 mirrored repeat, 2 clamp to
// edge, 3 clamp to border, 4 mirror clamp to edge), cutoff (float bits),
// comparison (0 >=, 1 >), alpha factor (float bits), border alpha (float
// bits), vertex alpha (1: multiplied in).
#define MESH_WORDS 11u
layout(std430, set = 0, binding = 3) readonly buffer Meshes { uint mesh_info[]; };
layout(std430, set = 0, binding = 4) readonly buffer Texels { float texels[]; };
layout(std430, set = 0, binding = 5) readonly buffer Data { uint data_words[]; };
layout(std430, set = 0, binding = 6) readonly buffer Records { uint record_words[]; };
layout(std430, set = 0, binding = 7) readonly buffer Indices { uint index_words[]; };
layout(std430, set = 0, binding = 8) readonly buffer Trees { uint tree_words[]; };
// Per record, TREE_WORDS words: level-order tree base, length, rank
// directory base, length, top table base, length, top depth, top start,
// paper tree base, length (bases and lengths in words of tree_words).
#define TREE_WORDS 10u
layout(std430, set = 0, binding = 9) readonly buffer TreeDirectory { uint tree_dir[]; };
// Per pixel, PIXEL_WORDS words: committed primitive + 1 (0: miss), t
// (float bits), contradicted candidates.
#define PIXEL_WORDS 3u
layout(std430, set = 0, binding = 10) buffer Pixels { uint pixels[]; };
// COUNTERS words of counters, then contradiction records of RECORD_WORDS.
#define COUNTERS 8u
#define RECORD_WORDS 8u
layout(std430, set = 0, binding = 11) buffer Counters { uint counters[]; };
#ifdef MMI_SAMPLER_LOOKUP
// Per mesh: its texture's alpha through its sampler (the sampler lookup).
layout(set = 0, binding = 12) uniform sampler2D textures[];
#endif

layout(push_constant) uniform Frame {
    uint width;
    uint height;
    uint method;
    uint index_width;
    uint max_records;
    uint fault; // bit 0: look up at (b2, b1); bit 1: flip known states
    uint record_limit; // pixels at or past it record no contradiction
    uint pad1;
    vec4 eye;
    vec4 forward;
    vec4 right; // scaled: half the image's width at distance 1
    vec4 up;    // scaled: half its height
};

#define MMI_DATA(i) data_words[i]
#define MMI_DATA_LENGTH uint(data_words.length())
#define MMI_TRIANGLES(i) record_words[i]
#define MMI_TRIANGLES_LENGTH uint(record_words.length())
#define MMI_INDICES(i) index_words[i]
#define MMI_INDICES_LENGTH uint(index_words.length())
#include "micromap_state.glsl"

// The trees of one record: the includes read through these (set per lookup).
uint g_lot_base = 0u, g_lot_len = 0u, g_rank_base = 0u, g_rank_len = 0u;
uint g_top_base = 0u, g_top_len = 0u, g_paper_base = 0u, g_paper_len = 0u;
#define MMI_LOT(i) tree_words[g_lot_base + (i)]
#define MMI_LOT_LENGTH g_lot_len
#define MMI_LOT_RANK(i) tree_words[g_rank_base + (i)]
#define MMI_LOT_RANK_LENGTH g_rank_len
#define MMI_LOT_TOP(i) tree_words[g_top_base + (i)]
#define MMI_LOT_TOP_LENGTH g_top_len
#define MMI_PAPER(i) tree_words[g_paper_base + (i)]
#define MMI_PAPER_LENGTH g_paper_len
#include "level_order_tree.glsl"
#include "paper_tree.glsl"

// Vulkan's address modes on an integer texel coordinate; 0xffffffff: border.
uint wrap_texel(int i, uint size, uint mode)
{
    int n = int(size);
    if (mode == 0u) return uint(((i % n) + n) % n);
    if (mode == 1u) {
        int t = ((i % (2 * n)) + 2 * n) % (2 * n);
        return uint(t < n ? t : 2 * n - 1 - t);
    }
    if (mode == 2u) return uint(clamp(i, 0, n - 1));
    if (mode == 3u) return (i >= 0 && i < n) ? uint(i) : 0xffffffffu;
    return uint(clamp(i >= 0 ? i : -1 - i, 0, n - 1));
}

float texel_alpha(uint m, int x, int y)
{
    uint base = m * MESH_WORDS;
    uint tx = wrap_texel(x, mesh_info[base + 1u], mesh_info[base + 4u]);
    uint ty = wrap_texel(y, mesh_info[base + 2u], mesh_info[base + 5u]);
    if (tx == 0xffffffffu || ty == 0xffffffffu) return uintBitsToFloat(mesh_info[base + 9u]);
    return texels[mesh_info[base] + ty * mesh_info[base + 1u] + tx];
}

// The alpha the alpha test compares at barycentrics b of triangle prim:
// the filtered alpha times the mesh's alpha factor (times its vertex
// alpha), in binary32.
float alpha_value(uint prim, vec2 b)
{
    uint m = tri_mesh[prim];
    uint base = m * MESH_WORDS;
    precise float w0 = 1.0 - b.x - b.y;
    uint t = TRI_WORDS * prim;
    precise float u = w0 * tri_uv[t] + b.x * tri_uv[t + 2u] + b.y * tri_uv[t + 4u];
    precise float v = w0 * tri_uv[t + 1u] + b.x * tri_uv[t + 3u] + b.y * tri_uv[t + 5u];
#ifdef MMI_SAMPLER_LOOKUP
    // The texture unit filters (nearest or linear, the mesh's sampler).
    float alpha = textureLod(textures[nonuniformEXT(m)], vec2(u, v), 0.0).r;
#else
    precise float x = u * float(mesh_info[base + 1u]);
    precise float y = v * float(mesh_info[base + 2u]);
    float alpha;
    if (mesh_info[base + 3u] == 0u) {
        alpha = texel_alpha(m, int(floor(x)), int(floor(y)));
    } else {
        precise float xs = x - 0.5;
        precise float ys = y - 0.5;
        float x0 = floor(xs);
        float y0 = floor(ys);
        precise float a = xs - x0;
        precise float c = ys - y0;
        int i = int(x0);
        int j = int(y0);
        precise float top = (1.0 - a) * texel_alpha(m, i, j) + a * texel_alpha(m, i + 1, j);
        precise float bottom = (1.0 - a) * texel_alpha(m, i, j + 1) + a * texel_alpha(m, i + 1, j + 1);
        alpha = (1.0 - c) * top + c * bottom;
    }
#endif
    precise float value = alpha * uintBitsToFloat(mesh_info[base + 8u]);
    if (mesh_info[base + 10u] != 0u) {
        // glTF's COLOR_0 alpha, interpolated in binary32, multiplied in
        // after the factor.
        precise float va = w0 * tri_uv[t + 6u] + b.x * tri_uv[t + 7u] + b.y * tri_uv[t + 8u];
        value = value * va;
    }
    return value;
}

// Whether `value` (alpha_value's) passes triangle prim's cutoff.
bool alpha_passes(uint prim, float value)
{
    uint base = tri_mesh[prim] * MESH_WORDS;
    float cutoff = uintBitsToFloat(mesh_info[base + 6u]);
    return mesh_info[base + 7u] == 0u ? value >= cutoff : value > cutoff;
}

// The alpha test at barycentrics b of triangle prim, in binary32.
bool alpha_test(uint prim, vec2 b)
{
    return alpha_passes(prim, alpha_value(prim, b));
}

// The state method `method` looks up at (u, v); the micro-triangle in `mt`
// (0 for a special index).
uint lookup(uint prim, float u, float v, out uint mt)
{
    mt = 0u;
    uint record = mmi_triangle_record(index_width, prim);
    if (record == MMI_TRIANGLE_INVALID) return MMI_STATE_INVALID;
    if (record >= MMI_TRIANGLE_SPECIAL) return record & 3u;
    uint level = mmi_record_level(record);
    if (level == MMI_LEVEL_INVALID) return MMI_STATE_INVALID;
    mt = BarycentricsToSpaceFillingCurveIndex(u, v, level);
    if (method == 1u || method == 2u) return mmi_record_state(record, mt);
    if (TREE_WORDS * record + TREE_WORDS > uint(tree_dir.length())) return MMI_STATE_INVALID;
    uint d = TREE_WORDS * record;
    if (method == 3u) {
        g_lot_base = tree_dir[d];
        g_lot_len = tree_dir[d + 1u];
        g_rank_base = tree_dir[d + 2u];
        g_rank_len = tree_dir[d + 3u];
        g_top_base = tree_dir[d + 4u];
        g_top_len = tree_dir[d + 5u];
        return mmi_level_order_get(mt, tree_dir[d + 6u], tree_dir[d + 7u]);
    }
    g_paper_base = tree_dir[d + 8u];
    g_paper_len = tree_dir[d + 9u];
    return mmi_paper_tree_get(mt);
}

// One candidate's counts (summed per ray by the query tracer, added per
// candidate by the any-hit shader).
struct Counts {
    uint candidates;
    uint fetches;
    uint known;
    uint unknown;
    uint contradicted;
    uint invalid;
};

Counts no_counts()
{
    return Counts(0u, 0u, 0u, 0u, 0u, 0u);
}

// Whether the candidate hit of triangle `prim` at barycentrics `b`, seen by
// pixel `pixel`, is opaque by `method`; counts it in `n` and records a
// contradicted known state.
bool decide_candidate(uint pixel, uint prim, vec2 b, inout Counts n)
{
    n.candidates++;
    if (method == 0u || method >= 5u) {
        n.fetches++;
        return alpha_test(prim, b);
    }
    uint mt;
    bool swap = (fault & 1u) != 0u;
    uint state = lookup(prim, swap ? b.y : b.x, swap ? b.x : b.y, mt);
    if (state == MMI_STATE_INVALID) n.invalid++;
    else if (method == 2u) state &= 1u;
    if ((fault & 2u) != 0u && state < 2u) state ^= 1u;
    if (state >= 2u) {
        n.unknown++;
        n.fetches++;
        return alpha_test(prim, b);
    }
    n.known++;
    bool opaque = state == 1u;
    float value = alpha_value(prim, b);
    if (alpha_passes(prim, value) != opaque) {
        n.contradicted++;
        atomicAdd(pixels[PIXEL_WORDS * pixel + 2u], 1u);
        uint r = pixel < record_limit ? atomicAdd(counters[7], 1u) : max_records;
        if (r < max_records) {
            uint at = COUNTERS + RECORD_WORDS * r;
            counters[at] = pixel;
            counters[at + 1u] = prim;
            counters[at + 2u] = mt;
            counters[at + 3u] = floatBitsToUint(b.x);
            counters[at + 4u] = floatBitsToUint(b.y);
            counters[at + 5u] = state;
            counters[at + 6u] = method;
            counters[at + 7u] = floatBitsToUint(value);
        }
    }
    return opaque;
}

// Adds `n` to the frame's counters (words 1..=6; word 0 counts rays).
void add_counts(Counts n)
{
    if (n.candidates != 0u) atomicAdd(counters[1], n.candidates);
    if (n.fetches != 0u) atomicAdd(counters[2], n.fetches);
    if (n.known != 0u) atomicAdd(counters[3], n.known);
    if (n.unknown != 0u) atomicAdd(counters[4], n.unknown);
    if (n.contradicted != 0u) atomicAdd(counters[5], n.contradicted);
    if (n.invalid != 0u) atomicAdd(counters[6], n.invalid);
}

// The primary ray of pixel p: its direction from `eye`.
vec3 primary_direction(uvec2 p)
{
    vec2 ndc = vec2((2.0 * float(p.x) + 1.0) / float(width) - 1.0,
                    1.0 - (2.0 * float(p.y) + 1.0) / float(height));
    return normalize(forward.xyz + ndc.x * right.xyz + ndc.y * up.xyz);
}

// Stores pixel's committed hit: primitive + 1 (0: miss) and t's bits.
void store_hit(uint pixel, uint prim_plus_one, float t)
{
    pixels[PIXEL_WORDS * pixel] = prim_plus_one;
    pixels[PIXEL_WORDS * pixel + 1u] = prim_plus_one == 0u ? 0u : floatBitsToUint(t);
}

#endif
