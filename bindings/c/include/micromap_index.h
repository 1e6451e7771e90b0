/*
 * micromap_index.h: the C API of micromap-index (opacity micromaps: the
 * Vulkan micro-triangle index, its inverse, an exact alpha-texture baker
 * into API buffers, a verifier of any baker's buffers, the buffer
 * validator and the succinct tree).
 *
 * C99 and C++ compatible. Every function is a thin wrapper over the Rust
 * library (bindings/c, crate micromap-index-capi); no algorithm is written
 * twice. Hand-written; bindings/c/tests/header.rs fails when a Rust
 * signature, struct or constant differs from this file.
 *
 * Conventions (docs/c.md):
 * - Every function returns an mmi_result: MMI_OK or an MMI_ERROR_* code;
 *   mmi_last_error_message() then says why (per thread).
 * - Every entry point is total: NULL pointers, wrong lengths, enum values
 *   naming no case and levels out of range return their codes. A Rust
 *   panic never crosses the boundary (MMI_ERROR_PANIC). Memory sized by
 *   the input that cannot be had is MMI_ERROR_OUT_OF_MEMORY, and a bake
 *   whose output may pass mmi_bake_options.max_bytes MMI_ERROR_LIMIT;
 *   docs/c.md ("Limits") lists every limit and how to raise it.
 * - Enums are uint32_t fields checked on entry (the MMI_* constants).
 * - Handles (mmi_bake_result, mmi_tree) belong to the caller and are freed
 *   with their *_free function; memory lent by a handle's accessors stays
 *   valid until then. Caller buffers are filled "size first": pass
 *   out == NULL to learn the length, then call again.
 * - A handle may be read from several threads at once; inputs must not
 *   change during a call; outputs must not overlap inputs.
 *
 * SPDX-License-Identifier: MIT OR Apache-2.0
 */
#ifndef MICROMAP_INDEX_H
#define MICROMAP_INDEX_H

#include <stddef.h>
#include <stdint.h>

/* The version of the library this header describes; mmi_version() returns
 * MICROMAP_INDEX_VERSION of the linked library. */
#define MICROMAP_INDEX_VERSION_MAJOR 0
#define MICROMAP_INDEX_VERSION_MINOR 1
#define MICROMAP_INDEX_VERSION_PATCH 0
#define MICROMAP_INDEX_VERSION                                                  \
    (MICROMAP_INDEX_VERSION_MAJOR * 10000 + MICROMAP_INDEX_VERSION_MINOR * 100 \
     + MICROMAP_INDEX_VERSION_PATCH)
#define MICROMAP_INDEX_VERSION_STRING "0.1.0"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ */
/* Results and errors                                                  */
/* ------------------------------------------------------------------ */

/** A status code: MMI_OK or one of the MMI_ERROR_* codes. */
typedef int32_t mmi_result;

/** Success. */
#define MMI_OK 0
/** A pointer that must not be NULL was NULL. */
#define MMI_ERROR_NULL_POINTER 1
/** A subdivision level outside the range the function takes. */
#define MMI_ERROR_INVALID_LEVEL 2
/** A uint32_t enum value that names no case. */
#define MMI_ERROR_INVALID_ENUM 3
/** Lengths that disagree or are not a whole number of items, or a pointer
 * not aligned for its type. */
#define MMI_ERROR_LENGTH 4
/** The caller's output buffer is too short; the required length was
 * written to *len. */
#define MMI_ERROR_BUFFER_TOO_SMALL 5
/** A value out of range: an index past the end, a NaN cutoff or border
 * alpha, an empty texture, a stride the function does not allow (UV,
 * vertex alpha, record, index), an index width the buffers cannot use. */
#define MMI_ERROR_INVALID_ARGUMENT 6
/** Bytes refused by the buffer validator or the tree reader. */
#define MMI_ERROR_MALFORMED 7
/** The library refused the mesh or its bake (an index naming no vertex,
 * a vertex alpha outside [0, 1], buffers past the APIs' limits; the
 * message says why). */
#define MMI_ERROR_BAKE 8
/** A combination this version does not support. */
#define MMI_ERROR_UNSUPPORTED 9
/** A Rust panic was caught at the boundary (a bug: please report it). */
#define MMI_ERROR_PANIC 10
/** Memory sized by the input (a copy of the texture's rows, the baker's
 * tables, a decoded micromap, gathered triangles) could not be had: the
 * allocator refused or the size does not fit the address space. Nothing
 * was kept; the process goes on. */
#define MMI_ERROR_OUT_OF_MEMORY 11
/** The bake's output may exceed mmi_bake_options.max_bytes; nothing was
 * baked (raise max_bytes, or shrink the output with a byte budget or a
 * lower level). */
#define MMI_ERROR_LIMIT 12

/** The message of the last failed call on this thread ("" after a call
 * that succeeded). Valid until the next mmi_ call on this thread; never
 * NULL. */
const char *mmi_last_error_message(void);

/** The linked library's version, major * 10000 + minor * 100 + patch. */
uint32_t mmi_version(void);

/** The linked library's version as a static string, e.g. "0.1.0". */
const char *mmi_version_string(void);

/* ------------------------------------------------------------------ */
/* Constants                                                           */
/* ------------------------------------------------------------------ */

/** mmi_texture.format: 8-bit unorm texels (alpha = c / 255). */
#define MMI_TEXEL_U8 0
/** 16-bit unorm texels (alpha = c / 65535), native endian. */
#define MMI_TEXEL_U16 1
/** float texels, as they are (NaN is transparent). */
#define MMI_TEXEL_F32 2

/** mmi_sampler.filter: nearest. */
#define MMI_FILTER_NEAREST 0
/** Bilinear. */
#define MMI_FILTER_LINEAR 1

/** mmi_sampler.address_u / address_v (Vulkan's sampler address modes). */
#define MMI_ADDRESS_REPEAT 0
/** Mirrored repeat. */
#define MMI_ADDRESS_MIRRORED_REPEAT 1
/** Clamp to edge. */
#define MMI_ADDRESS_CLAMP_TO_EDGE 2
/** Clamp to border (mmi_sampler.border_alpha). */
#define MMI_ADDRESS_CLAMP_TO_BORDER 3
/** Mirror clamp to edge. */
#define MMI_ADDRESS_MIRROR_CLAMP_TO_EDGE 4

/** mmi_material.comparison: opaque when alpha >= cutoff (glTF MASK). */
#define MMI_OPAQUE_AT_LEAST 0
/** Opaque when alpha > cutoff (the OMM SDK's rule). */
#define MMI_OPAQUE_ABOVE 1

/** Micromap formats (the Vulkan/DXR values): 2-state. */
#define MMI_FORMAT_2_STATE 1
/** 4-state. */
#define MMI_FORMAT_4_STATE 2

/** mmi_bake_options.unknown, 2-state only: unknowns become the state they
 * fall back to (what "force 2-state" does). */
#define MMI_UNKNOWN_FALLBACK 0
/** Unknowns become opaque. */
#define MMI_UNKNOWN_OPAQUE 1
/** Unknowns become transparent. */
#define MMI_UNKNOWN_TRANSPARENT 2

/** mmi_bake_options.level: each triangle's useful level (edges of at most
 * one texel, the paper's eq. 1), capped at max_level. */
#define MMI_LEVEL_AUTO 0xFFFFFFFFu
/** The highest mmi_bake_options.level and max_level: 12, the highest DXR
 * allows and Vulkan devices report (the CLI's and Python's range too). */
#define MMI_MAX_BAKE_LEVEL 12
/** mmi_bake_options.max_bytes == 0 means this limit on a bake's estimated
 * output: 1 GiB (micromap-index bake --max-bytes's default). */
#define MMI_DEFAULT_MAX_BYTES 1073741824

/** mmi_bake_options.model, mmi_verify_with_model: known states hold for
 * what a GPU computes in binary32 (the default; docs/bake.md). */
#define MMI_MODEL_GPU_BINARY32 0
/** Known states hold for the exact real texture coordinates only. */
#define MMI_MODEL_EXACT 1

/** mmi_bake_options.interpolation: the shader interpolates texture
 * coordinates in binary32 (the default). */
#define MMI_INTERPOLATION_F32 0
/** The shader interpolates in 16-bit floats (mediump). */
#define MMI_INTERPOLATION_F16 1
/** mmi_bake_options.linear_rule: linear filtering judged by the filtered
 * value (the default; docs/bake.md, "The texture unit"). */
#define MMI_LINEAR_VALUE 0
/** Linear filtering judged by footprint (every texel of the 2x2 footprint
 * read, whatever its weight). */
#define MMI_LINEAR_FOOTPRINT 1

/** mmi_bake_result_indices: every geometry, concatenated. */
#define MMI_ALL_GEOMETRIES SIZE_MAX

/** Tree layouts: the paper's depth-first tree. */
#define MMI_TREE_PAPER 0
/** The level-order tree with a rank directory (O(level) lookups). */
#define MMI_TREE_LEVEL_ORDER 1

/** Micro-triangle states (the API values). */
#define MMI_STATE_TRANSPARENT 0
/** Opaque. */
#define MMI_STATE_OPAQUE 1
/** Unknown, transparent when any-hit is skipped. */
#define MMI_STATE_UNKNOWN_TRANSPARENT 2
/** Unknown, opaque when any-hit is skipped. */
#define MMI_STATE_UNKNOWN_OPAQUE 3

/* ------------------------------------------------------------------ */
/* The index function and its inverse                                  */
/* ------------------------------------------------------------------ */

/** The micro-triangle index of the point (u, v) at level 0..=16, as the
 * Vulkan reference computes it in binary32, for every float pair (NaN and
 * points outside the triangle included). MMI_ERROR_INVALID_LEVEL above 16,
 * MMI_ERROR_NULL_POINTER for a NULL out. */
mmi_result mmi_index_f32(float u, float v, uint32_t level, uint32_t *out);

/** out[i] = mmi_index_f32(us[i], vs[i], level) for i < count, by the
 * library's SIMD batch kernels. With count == 0 the pointers may be NULL.
 * Misaligned arrays are MMI_ERROR_LENGTH. On an error nothing is written. */
mmi_result mmi_index_f32_batch(const float *us, const float *vs, size_t count, uint32_t level,
                               uint32_t *out);

/** The reference widened to 64-bit words: levels 0..=32; equal to
 * mmi_index_f32 for levels 0..=16. */
mmi_result mmi_wide_index_f32(float u, float v, uint32_t level, uint64_t *out);

/** out[i] = mmi_wide_index_f32(us[i], vs[i], level), by the batch kernels. */
mmi_result mmi_wide_index_f32_batch(const float *us, const float *vs, size_t count,
                                    uint32_t level, uint64_t *out);

/** One micro-triangle, exactly. */
typedef struct mmi_micro_triangle {
    /** The subdivision level. */
    uint32_t level;
    /** 1 if it has the base triangle's orientation, 0 if upside down. */
    uint32_t upright;
    /** Its index on the space-filling curve. */
    uint64_t index;
    /** u0, v0, u1, v1, u2, v2 as numerators over 2^level, in the walk's
     * local vertex order. */
    uint64_t vertices[6];
} mmi_micro_triangle;

/** The micro-triangle with `index` at `level` (0..=32): its exact
 * vertices. MMI_ERROR_INVALID_LEVEL above 32, MMI_ERROR_INVALID_ARGUMENT
 * for an index >= 4^level. */
mmi_result mmi_inverse_micro_triangle(uint32_t level, uint64_t index, mmi_micro_triangle *out);

/* ------------------------------------------------------------------ */
/* Baking                                                              */
/* ------------------------------------------------------------------ */

/** An alpha texture in the caller's memory. */
typedef struct mmi_texture {
    /** Row 0 (the image's top row, v = 0) first. */
    const void *texels;
    /** Texels per row, at least 1. */
    uint32_t width;
    /** Rows, at least 1. */
    uint32_t height;
    /** Bytes from one row to the next (at least a row); 0: tightly packed.
     * Rows are copied only when the pitch is not the row's size or the
     * texels are misaligned. */
    size_t row_pitch;
    /** MMI_TEXEL_U8, MMI_TEXEL_U16 or MMI_TEXEL_F32. */
    uint32_t format;
} mmi_texture;

/** How the runtime samples the texture. */
typedef struct mmi_sampler {
    /** MMI_FILTER_NEAREST or MMI_FILTER_LINEAR. */
    uint32_t filter;
    /** MMI_ADDRESS_* along u. */
    uint32_t address_u;
    /** MMI_ADDRESS_* along v. */
    uint32_t address_v;
    /** The alpha read outside the texture under clamp-to-border. */
    float border_alpha;
} mmi_sampler;

/** How a texture is alpha-tested. */
typedef struct mmi_material {
    /** The sampler. */
    mmi_sampler sampler;
    /** The alpha cutoff (not NaN). */
    float cutoff;
    /** MMI_OPAQUE_AT_LEAST or MMI_OPAQUE_ABOVE. */
    uint32_t comparison;
    /** Multiplies every texel's alpha before the cutoff (glTF's
     * baseColorFactor[3]); 1 for none. */
    float alpha_factor;
} mmi_material;

/** glTF's KHR_texture_transform: uv' = offset + R(rotation) (scale * uv),
 * R counter-clockwise by rotation radians (the extension's translation *
 * rotation * scale). The baker models it as the shader computes it, in
 * binary32 on the interpolated coordinate (docs/bake.md, "Texture
 * transforms"). */
typedef struct mmi_uv_transform {
    /** Added after the rotation (the extension's offset). */
    float offset[2];
    /** Radians, counter-clockwise; at most 65536 in magnitude. */
    float rotation;
    /** Multiplies the coordinate first (the extension's scale). */
    float scale[2];
} mmi_uv_transform;

/** One mesh: a texture, its material and triangles in UV space. */
typedef struct mmi_mesh {
    /** The alpha texture. */
    mmi_texture texture;
    /** Sampler, cutoff and alpha factor. */
    mmi_material material;
    /** Vertex i's (u, v) are the two floats at byte i * uv_stride
     * (4-byte aligned). */
    const float *uvs;
    /** The number of vertices at uvs. */
    size_t vertex_count;
    /** Bytes from one vertex to the next: a multiple of 4, at least 8;
     * 0 means 8 (tight pairs). */
    size_t uv_stride;
    /** Three vertex indices per triangle, or NULL: vertices 3t, 3t+1, 3t+2
     * form triangle t (vertex_count a multiple of 3). */
    const uint32_t *indices;
    /** The number of indices, a multiple of 3 (ignored without indices). */
    size_t index_count;
    /** Vertex i's alpha (glTF's COLOR_0 alpha, in [0, 1]) is the float at
     * byte i * vertex_alpha_stride (4-byte aligned), multiplied into the
     * sampled alpha as glTF renderers do; NULL: alpha 1. */
    const float *vertex_alpha;
    /** Bytes from one vertex alpha to the next: a multiple of 4; 0 means 4. */
    size_t vertex_alpha_stride;
    /** The texture-coordinate transform the runtime's shader applies to the
     * interpolated coordinate before sampling (glTF's KHR_texture_transform),
     * or NULL: none. Non-finite values and rotations beyond 65536 radians are
     * MMI_ERROR_INVALID_ARGUMENT. */
    const mmi_uv_transform *uv_transform;
} mmi_mesh;

/** How mmi_bake bakes; start from mmi_bake_options_default. */
typedef struct mmi_bake_options {
    /** A fixed level 0..=MMI_MAX_BAKE_LEVEL (12) for every triangle, or
     * MMI_LEVEL_AUTO; above 12 is MMI_ERROR_INVALID_LEVEL (earlier builds
     * took 0..=16: the range is now the CLI's and Python's). */
    uint32_t level;
    /** With MMI_LEVEL_AUTO: the highest level chosen, 0..=12. */
    uint32_t max_level;
    /** MMI_FORMAT_2_STATE or MMI_FORMAT_4_STATE. */
    uint32_t format;
    /** 2-state: what unknowns become (MMI_UNKNOWN_*). */
    uint32_t unknown;
    /** Non-zero: at most budget_bytes of micromap data for all meshes
     * together (the highest levels are lowered first). */
    uint32_t use_budget;
    /** Block tests a micro-triangle may use (0: the library's default). */
    uint32_t block_budget;
    /** The byte budget, with use_budget. */
    uint64_t budget_bytes;
    /** Which hits known states hold for: MMI_MODEL_GPU_BINARY32 (the
     * default, 0) or MMI_MODEL_EXACT. */
    uint32_t model;
    /** Padding, 0. */
    uint32_t reserved;
    /** Non-zero: no geometry mixes special indices with records (Vulkan
     * KHR's "no mixed special indices", `micromap-index bake
     * --no-mixed-special`): in a geometry that references any record, each
     * special index becomes a shared level-0 record of its state. 0 (the
     * default): special indices wherever a triangle is uniform. */
    uint32_t no_mixed_special_indices;
    /** Padding, 0. */
    uint32_t reserved2;
    /** Refuse the bake with MMI_ERROR_LIMIT, before any micro-triangle is
     * baked, when its output may exceed this many bytes (an upper bound:
     * every triangle's micromap at its chosen level before deduplication,
     * the records, 32-bit indices and usage counts). 0 means
     * MMI_DEFAULT_MAX_BYTES (1 GiB), as micromap-index bake --max-bytes. */
    uint64_t max_bytes;
    /** The texture unit's sub-texel bits: texel coordinates snap to
     * multiples of 2^-k texels, 4..=16; 0 means 8 (the default;
     * docs/bake.md, "The texture unit"). */
    uint32_t subtexel_bits;
    /** MMI_INTERPOLATION_F32 (the default, 0) or MMI_INTERPOLATION_F16. */
    uint32_t interpolation;
    /** MMI_LINEAR_VALUE (the default, 0) or MMI_LINEAR_FOOTPRINT. */
    uint32_t linear_rule;
    /** The largest error of a linear filter's result, in alpha units,
     * (0, 1]; 0 means 2^-7 (the default). */
    float filter_error;
} mmi_bake_options;

/** What mmi_bake found over all meshes. */
typedef struct mmi_bake_stats {
    /** Triangles baked. */
    uint64_t triangles;
    /** Entries of levels used (the highest level used plus one). */
    uint32_t level_count;
    /** Padding, 0. */
    uint32_t reserved;
    /** Triangles per chosen level. */
    uint64_t levels[17];
    /** Micro-triangles per state (MMI_STATE_*), before a 2-state format
     * resolves the unknowns. */
    uint64_t counts[4];
    /** Triangles baked exactly. */
    uint64_t status_exact;
    /** Triangles with a coordinate that is not finite. */
    uint64_t status_not_finite;
    /** Triangles off the exact grid. */
    uint64_t status_out_of_exact_range;
    /** Triangles where the block budget ran out. */
    uint64_t status_budget_exceeded;
    /** Triangles where the work budget ran out (the rest unknown). */
    uint64_t status_work_budget_exceeded;
    /** Known micro-triangles over all micro-triangles. */
    double known_fraction;
    /** The known fraction weighted by texel area. */
    double known_area_fraction;
    /** Distinct micromaps after deduplication. */
    uint64_t micromaps;
    /** Triangles given a special index. */
    uint64_t special_index_triangles;
    /** Bytes of packed micromap data. */
    uint64_t bytes_flat;
    /** Bytes as the paper's succinct trees. */
    uint64_t bytes_paper_tree;
    /** Bytes as level-order trees. */
    uint64_t bytes_level_order_tree;
    /** Unknown micro-triangles that MMI_MODEL_EXACT would know: the GPU
     * model's widening cost (0 under MMI_MODEL_EXACT). */
    uint64_t widened;
} mmi_bake_stats;

/** A finished bake (opaque): free with mmi_bake_result_free. */
typedef struct mmi_bake_result mmi_bake_result;

/** The defaults: MMI_LEVEL_AUTO up to 12, 4-state, fallback for unknowns,
 * no byte budget, the library's block budget, the GPU binary32 model,
 * special indices mixed with records, max_bytes MMI_DEFAULT_MAX_BYTES,
 * the default texture unit written out (subtexel_bits 8, binary32
 * interpolation, linear filtering by value, filter_error 2^-7)
 * (micromap-index bake's defaults). */
mmi_result mmi_bake_options_default(mmi_bake_options *options);

/** The default material: nearest, repeat on both axes, border alpha 0,
 * opaque when alpha >= 0.5 (glTF's default), alpha factor 1. */
mmi_result mmi_material_default(mmi_material *material);

/** Bakes mesh_count meshes exactly (one geometry per mesh, micromaps
 * deduplicated across all) into a new handle written to *result (NULL on
 * an error). The same inputs give the same bytes as `micromap-index bake`.
 * Errors: MMI_ERROR_NULL_POINTER; _INVALID_LEVEL (level or max_level above
 * MMI_MAX_BAKE_LEVEL); _INVALID_ENUM; _LENGTH (a pitch below a row, a
 * vertex or index count not a multiple of 3, a misaligned array);
 * _INVALID_ARGUMENT (empty texture, a texture of 2^32 texels or more, NaN
 * cutoff or border alpha, bad stride, an index naming no vertex when
 * vertex_alpha is given); _LIMIT (the output may exceed max_bytes);
 * _OUT_OF_MEMORY (a copy of the input or the baker's tables could not be
 * allocated); _BAKE (an index naming no vertex, a vertex alpha outside
 * [0, 1], the library's other refusals). */
mmi_result mmi_bake(const mmi_mesh *meshes, size_t mesh_count, const mmi_bake_options *options,
                    mmi_bake_result **result);

/** The packed micromap data (micromap-data.bin): *data and *len receive
 * memory owned by the handle, valid until mmi_bake_result_free. */
mmi_result mmi_bake_result_data(const mmi_bake_result *result, const uint8_t **data,
                                size_t *len);

/** The 8-byte triangle records {u32 data offset, u16 level, u16 format},
 * little endian (micromap-triangles.bin), owned by the handle. */
mmi_result mmi_bake_result_triangle_records(const mmi_bake_result *result, const uint8_t **data,
                                            size_t *len);

/** The 12-byte usage counts {u32 count, u32 level, u32 format}, little
 * endian (micromap-usage.bin), owned by the handle. */
mmi_result mmi_bake_result_usage_counts(const mmi_bake_result *result, const uint8_t **data,
                                        size_t *len);

/** The number of geometries (one per baked mesh). */
mmi_result mmi_bake_result_geometry_count(const mmi_bake_result *result, size_t *count);

/** Whether geometry's index buffer holds both special indices and records:
 * *mixed receives 1 if so, else 0. A Vulkan KHR pipeline created with
 * VK_PIPELINE_CREATE_2_OPACITY_MICROMAP_DISALLOW_MIXED_SPECIAL_INDEX_BIT_KHR
 * must not trace a mixed geometry; never 1 after a bake with
 * no_mixed_special_indices. A geometry past the last is
 * MMI_ERROR_INVALID_ARGUMENT. */
mmi_result mmi_bake_result_is_mixed(const mmi_bake_result *result, size_t geometry,
                                    uint32_t *mixed);

/** The per-triangle index buffer of `geometry` (or of all, concatenated,
 * with MMI_ALL_GEOMETRIES: micromap-indices.bin) at width_bits 8, 16 or
 * 32, little endian, special indices -1..-4 as two's complement. *len
 * receives the size in bytes; with out == NULL that is all; a capacity
 * below it is MMI_ERROR_BUFFER_TOO_SMALL. An index too large for the
 * width, or a geometry past the last, is MMI_ERROR_INVALID_ARGUMENT; a
 * width other than 8, 16, 32 is MMI_ERROR_INVALID_ENUM. */
mmi_result mmi_bake_result_indices(const mmi_bake_result *result, size_t geometry,
                                   uint32_t width_bits, uint8_t *out, size_t capacity,
                                   size_t *len);

/** The bake's statistics. */
mmi_result mmi_bake_result_stats(const mmi_bake_result *result, mmi_bake_stats *stats);

/** Frees a handle from mmi_bake and everything its accessors lent; NULL
 * is ignored. */
void mmi_bake_result_free(mmi_bake_result *result);

/* ------------------------------------------------------------------ */
/* Validating and verifying buffers                                    */
/* ------------------------------------------------------------------ */

/** Micromap buffers in the caller's memory (API layouts, little endian;
 * records and indices tight or at the strides given). Zero-initialise it:
 * strides 0 are tight. */
typedef struct mmi_buffers_view {
    /** The packed micromap data. */
    const uint8_t *data;
    /** Its length in bytes. */
    size_t data_len;
    /** The 8-byte triangle records. */
    const uint8_t *records;
    /** Their length in bytes (a multiple of 8 when tight; see
     * record_stride). */
    size_t records_len;
    /** The 12-byte usage counts, or NULL: not checked. */
    const uint8_t *usage_counts;
    /** Their length in bytes. */
    size_t usage_counts_len;
    /** One geometry's per-triangle index buffer, or NULL: none. */
    const uint8_t *indices;
    /** Its length in bytes. */
    size_t indices_len;
    /** The index width in bits: 8, 16 or 32 (ignored without indices). */
    uint32_t index_width_bits;
    /** Bytes from one triangle record to the next (Vulkan's
     * triangleArrayStride): 0 means 8 (tight); otherwise at least 8 and a
     * multiple of 4 (MMI_ERROR_INVALID_ARGUMENT if not). The bytes between
     * records are ignored; records_len covers whole strides or ends right
     * after the last record (MMI_ERROR_MALFORMED if not). */
    size_t record_stride;
    /** Bytes from one index to the next (Vulkan's indexStride): 0 means the
     * index width (tight); otherwise a multiple of the width
     * (MMI_ERROR_INVALID_ARGUMENT if not). The bytes between indices are
     * ignored; indices_len covers whole strides or ends right after the
     * last index (MMI_ERROR_MALFORMED if not). Ignored without indices. */
    size_t index_stride;
} mmi_buffers_view;

/** Options of mmi_validate_buffers; start from mmi_read_options_default. */
typedef struct mmi_read_options {
    /** Non-zero: records may share or overlap data while their blocks total
     * at most max_decoded_bytes; zero: blocks must be disjoint (glTF). */
    uint32_t allow_overlap;
    /** The highest level accepted (at most 16; 12 for DXR). */
    uint32_t max_level;
    /** Added to every regular index (Vulkan's baseTriangle). */
    uint32_t base_triangle;
    /** Padding, 0. */
    uint32_t reserved;
    /** With allow_overlap: the limit on the records' block sizes. */
    uint64_t max_decoded_bytes;
} mmi_read_options;

/** What mmi_validate_buffers read. */
typedef struct mmi_buffers_info {
    /** Triangle records. */
    uint64_t records;
    /** Indices in the index buffer (0 without one). */
    uint64_t indices;
    /** Indices that are special (-1..-4). */
    uint64_t special_indices;
} mmi_buffers_info;

/** What mmi_verify found over all triangles. */
typedef struct mmi_verify_report {
    /** Triangles in the mesh. */
    uint64_t triangles;
    /** Triangles checked (finite coordinates on the exact grid). */
    uint64_t triangles_checked;
    /** Known micro-triangles checked. */
    uint64_t known;
    /** Unknown micro-triangles (never wrong). */
    uint64_t unknown;
    /** Known micro-triangles the block budget could not decide. */
    uint64_t undecided;
    /** Micro-triangles whose known state the texture contradicts (0: sound). */
    uint64_t contradictions;
    /** Contradictions written to the caller's array. */
    uint64_t witnesses_written;
} mmi_verify_report;

/** A micro-triangle whose known state the texture contradicts, with an
 * exact witness point. */
typedef struct mmi_contradiction {
    /** The triangle. */
    uint64_t triangle;
    /** The micro-triangle (0 for a special index). */
    uint64_t micro_triangle;
    /** The state the buffers give it (MMI_STATE_*). */
    uint32_t state;
    /** 1 if the witness fields hold a point, 0 if the exact point search
     * gave up (the block search alone proved the contradiction). */
    uint32_t has_witness;
    /** The witness's horizontal texel coordinate x / 2^witness_shift_x, x
     * a 128-bit two's complement number: its high 64 bits. */
    int64_t witness_x_hi;
    /** The low 64 bits of x. */
    uint64_t witness_x_lo;
    /** The vertical texel coordinate y / 2^witness_shift_y: high 64 bits. */
    int64_t witness_y_hi;
    /** The low 64 bits of y. */
    uint64_t witness_y_lo;
    /** The exponent of x's denominator. */
    uint32_t witness_shift_x;
    /** The exponent of y's denominator. */
    uint32_t witness_shift_y;
    /** The witness in texture coordinates, rounded to double. */
    double witness_u;
    /** The witness's v. */
    double witness_v;
    /** 1 if texel_x, texel_y name the texel of the other class, 0 if it is
     * the border colour. */
    uint32_t has_texel;
    /** The texel's column (after wrapping). */
    uint32_t texel_x;
    /** The texel's row. */
    uint32_t texel_y;
    /** Padding, 0. */
    uint32_t reserved;
    /** The texel's alpha (or the border alpha). */
    double texel_alpha;
} mmi_contradiction;

/** The validator's defaults: disjoint blocks, levels up to 16, base
 * triangle 0. */
mmi_result mmi_read_options_default(mmi_read_options *options);

/** Checks untrusted micromap buffers as the APIs require (record layout,
 * formats and levels, blocks in bounds and disjoint unless allowed, usage
 * counts matching the records, indices naming records or special, at the
 * view's strides): MMI_OK, or MMI_ERROR_MALFORMED with the first problem
 * as the message; MMI_ERROR_INVALID_ARGUMENT for a stride the APIs do not
 * allow (checked first); MMI_ERROR_INVALID_ENUM for an index width other
 * than 8, 16, 32; MMI_ERROR_OUT_OF_MEMORY when a decoded micromap cannot
 * be allocated. options may be NULL (the defaults); info may be NULL. */
mmi_result mmi_validate_buffers(const mmi_buffers_view *buffers, const mmi_read_options *options,
                                mmi_buffers_info *info);

/** mmi_verify_with_model under the default model, MMI_MODEL_GPU_BINARY32. */
mmi_result mmi_verify(const mmi_mesh *mesh, const mmi_buffers_view *buffers,
                      mmi_verify_report *report, mmi_contradiction *witnesses,
                      size_t witness_capacity);

/** Checks any baker's buffers (data, records and one index per triangle of
 * mesh) against mesh under model (MMI_MODEL_*), as `micromap-index
 * verify-bake --model` does: texture, sampler, cutoff, alpha factor and
 * vertex alpha as mmi_bake models them. Every known micro-triangle whose
 * closed area can read a texel of the other class is a contradiction.
 * Records may share data. The first witness_capacity contradictions are
 * written to witnesses (NULL allowed with capacity 0); report counts them
 * all, in memory that does not grow with their number (a witness's
 * texel_alpha is the texel's as the texture holds it, before the alpha
 * factor and vertex alpha). MMI_OK whether or not contradictions were
 * found; MMI_ERROR_NULL_POINTER (mesh, buffers, buffers->indices, report,
 * or witnesses with a capacity); MMI_ERROR_MALFORMED for buffers the
 * validator refuses; MMI_ERROR_INVALID_ARGUMENT for a stride the APIs do
 * not allow (mmi_buffers_view); MMI_ERROR_LENGTH when the index count is
 * not the triangle count; MMI_ERROR_INVALID_ENUM for an unknown model; a
 * mesh mmi_bake refuses gets mmi_bake's code; MMI_ERROR_OUT_OF_MEMORY when
 * memory sized by the input (a decoded micromap, a copy of the texture)
 * could not be had. */
mmi_result mmi_verify_with_model(const mmi_mesh *mesh, const mmi_buffers_view *buffers,
                                 uint32_t model, mmi_verify_report *report,
                                 mmi_contradiction *witnesses, size_t witness_capacity);

/** mmi_verify_with_model judged by options as mmi_bake would bake with
 * them: the model, the texture unit (subtexel_bits, interpolation,
 * linear_rule, filter_error) and the block budget; the other fields are
 * not read. Under linear filtering by value a contradiction's witness is
 * where the filtered value is lowest (highest). Codes as
 * mmi_verify_with_model, and MMI_ERROR_NULL_POINTER for options,
 * MMI_ERROR_INVALID_ARGUMENT for a texture unit outside its ranges. */
mmi_result mmi_verify_with_options(const mmi_mesh *mesh, const mmi_buffers_view *buffers,
                                   const mmi_bake_options *options, mmi_verify_report *report,
                                   mmi_contradiction *witnesses, size_t witness_capacity);

/* ------------------------------------------------------------------ */
/* The succinct tree                                                   */
/* ------------------------------------------------------------------ */

/** A succinct tree over one micromap (opaque): free with mmi_tree_free. */
typedef struct mmi_tree mmi_tree;

/** What mmi_tree_info_get reports. */
typedef struct mmi_tree_info {
    /** MMI_TREE_PAPER or MMI_TREE_LEVEL_ORDER. */
    uint32_t layout;
    /** The subdivision level. */
    uint32_t level;
    /** MMI_FORMAT_2_STATE or MMI_FORMAT_4_STATE. */
    uint32_t format;
    /** Padding, 0. */
    uint32_t reserved;
    /** The size in bits (tree bits, leaf states, rank directory). */
    uint64_t total_bits;
    /** Leaf states stored. */
    uint64_t leaf_count;
} mmi_tree_info;

/** Encodes a flat micromap of `level` (0..=16), given as state_count ==
 * 4^level states (MMI_STATE_*, one byte each), into a tree of `layout` and
 * `format`. A 2-state format refuses unknown states
 * (MMI_ERROR_INVALID_ARGUMENT); a wrong count is MMI_ERROR_LENGTH; a state
 * above 3 is MMI_ERROR_INVALID_ENUM. *tree receives the handle (NULL on an
 * error). */
mmi_result mmi_tree_encode(uint32_t layout, uint32_t level, uint32_t format,
                           const uint8_t *states, size_t state_count, mmi_tree **tree);

/** Reads a tree from the bytes mmi_tree_to_bytes writes (either layout):
 * any other input is MMI_ERROR_MALFORMED, never a crash. */
mmi_result mmi_tree_from_bytes(const uint8_t *bytes, size_t len, mmi_tree **tree);

/** The state of micro-triangle `index`; MMI_ERROR_INVALID_ARGUMENT for an
 * index >= 4^level. */
mmi_result mmi_tree_get(const mmi_tree *tree, uint64_t index, uint8_t *state);

/** The state a ray hit at barycentrics (u, v) reads: the Vulkan reference
 * index in binary32, then the lookup (every float pair). */
mmi_result mmi_tree_get_f32(const mmi_tree *tree, float u, float v, uint8_t *state);

/** The tree's bytes (format version 1): *len receives the size; with
 * out == NULL that is all; a smaller capacity is
 * MMI_ERROR_BUFFER_TOO_SMALL. */
mmi_result mmi_tree_to_bytes(const mmi_tree *tree, uint8_t *out, size_t capacity, size_t *len);

/** Every micro-triangle's state (4^level bytes, MMI_STATE_*), size first
 * as mmi_tree_to_bytes. */
mmi_result mmi_tree_decode(const mmi_tree *tree, uint8_t *states, size_t capacity, size_t *len);

/** The tree's layout, level, format and sizes. */
mmi_result mmi_tree_info_get(const mmi_tree *tree, mmi_tree_info *info);

/** Frees a tree; NULL is ignored. */
void mmi_tree_free(mmi_tree *tree);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* MICROMAP_INDEX_H */
