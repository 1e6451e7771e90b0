/*
 * Hostile inputs for every entry point of the C API (issue 37): huge
 * dimensions, row pitches and counts, NULL where allowed and where not,
 * misaligned arrays, strides, NaNs, levels and enums out of range, zero
 * sizes, outputs over the limit, millions of contradictions. Each call
 * must return its documented code; none may abort, crash or trip a
 * sanitizer.
 *
 * Run by bindings/c/ci-hostile.sh twice: built with
 * -fsanitize=address,undefined (ASan cannot run under `ulimit -v`, so its
 * allocator caps each allocation instead: max_allocation_size_mb), and
 * built with -fsanitize=undefined under `ulimit -v` (an address-space
 * cap). In both the inputs of up to 4 GiB fit but a second copy of them
 * does not: the cases marked "copy" aborted the process before.
 *
 * Prints one line per call (`name code message`), then "ok N cases"; exits
 * 1 when a code differs from the expected one, 2 when an input could not
 * be mapped (the cap is below the suite's inputs). Arguments name the
 * sections to run (default: all).
 */
#define _DEFAULT_SOURCE /* MAP_ANONYMOUS, MAP_NORESERVE */
#include "micromap_index.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

static int cases = 0;
static int failures = 0;

static void expect(const char *name, mmi_result got, mmi_result want, int line) {
    const char *message = mmi_last_error_message();
    ++cases;
    if (message == NULL) {
        ++failures;
        fprintf(stderr, "hostile.c:%d: %s: mmi_last_error_message() is NULL\n", line, name);
        return;
    }
    printf("%-44s %2d %s\n", name, (int)got, message);
    if (got != want) {
        ++failures;
        fprintf(stderr, "hostile.c:%d: %s returned %d, expected %d (%s)\n", line, name, (int)got,
                (int)want, message);
    }
}

#define EXPECT(name, call, code) expect(name, (call), (code), __LINE__)

/* `size` zero bytes in fresh pages: address space, no memory until
 * written (reads map the shared zero page). */
static void *big(size_t size) {
    void *p = mmap(NULL, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE,
                   -1, 0);
    if (p == MAP_FAILED) {
        fprintf(stderr, "cannot map %zu bytes: raise the address-space cap\n", size);
        exit(2);
    }
    return p;
}

static const float triangle[6] = {0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1.0f};
static const uint8_t checker[4] = {0, 255, 255, 0};

static mmi_mesh small_mesh(void) {
    mmi_mesh m;
    memset(&m, 0, sizeof m);
    m.texture.texels = checker;
    m.texture.width = 2;
    m.texture.height = 2;
    m.texture.format = MMI_TEXEL_U8;
    mmi_material_default(&m.material);
    m.uvs = triangle;
    m.vertex_count = 3;
    return m;
}

static mmi_bake_options default_options(void) {
    mmi_bake_options o;
    mmi_bake_options_default(&o);
    return o;
}

/* mmi_bake on one mesh; the handle, if any, freed; *result must come back
 * NULL on an error. */
static mmi_result bake(const mmi_mesh *mesh, const mmi_bake_options *options) {
    mmi_bake_result *result = (mmi_bake_result *)&result;
    mmi_result code = mmi_bake(mesh, 1, options, &result);
    if (code != MMI_OK && result != NULL) {
        ++failures;
        fprintf(stderr, "mmi_bake returned %d without clearing *result\n", (int)code);
    }
    mmi_bake_result_free(result);
    return code;
}

static void index_functions(void) {
    uint32_t out = 0;
    uint64_t wide = 0;
    float us[4] = {0.25f, NAN, INFINITY, -1e30f};
    float vs[4] = {0.25f, 0.5f, NAN, 1e30f};
    uint32_t outs[4];
    uint64_t wides[4];
    mmi_micro_triangle t;

    EXPECT("index: level 17", mmi_index_f32(0.1f, 0.1f, 17, &out), MMI_ERROR_INVALID_LEVEL);
    EXPECT("index: level UINT32_MAX", mmi_index_f32(0.1f, 0.1f, UINT32_MAX, &out),
           MMI_ERROR_INVALID_LEVEL);
    EXPECT("index: out NULL", mmi_index_f32(0.1f, 0.1f, 3, NULL), MMI_ERROR_NULL_POINTER);
    EXPECT("index: NaN and infinity", mmi_index_f32(NAN, INFINITY, 16, &out), MMI_OK);
    EXPECT("batch: NaN, infinities", mmi_index_f32_batch(us, vs, 4, 16, outs), MMI_OK);
    EXPECT("batch: count 0, all NULL", mmi_index_f32_batch(NULL, NULL, 0, 5, NULL), MMI_OK);
    EXPECT("batch: us NULL", mmi_index_f32_batch(NULL, vs, 4, 5, outs), MMI_ERROR_NULL_POINTER);
    EXPECT("batch: out NULL", mmi_index_f32_batch(us, vs, 4, 5, NULL), MMI_ERROR_NULL_POINTER);
    EXPECT("batch: count SIZE_MAX", mmi_index_f32_batch(us, vs, SIZE_MAX, 5, outs),
           MMI_ERROR_LENGTH);
    EXPECT("batch: count SIZE_MAX / 4", mmi_index_f32_batch(us, vs, SIZE_MAX / 4, 5, outs),
           MMI_ERROR_LENGTH);
    EXPECT("batch: misaligned us",
           mmi_index_f32_batch((const float *)((const char *)us + 1), vs, 2, 5, outs),
           MMI_ERROR_LENGTH);
    EXPECT("batch: level 17", mmi_index_f32_batch(us, vs, 4, 17, outs), MMI_ERROR_INVALID_LEVEL);
    EXPECT("wide: level 33", mmi_wide_index_f32(0.1f, 0.1f, 33, &wide), MMI_ERROR_INVALID_LEVEL);
    EXPECT("wide: level 32, NaN", mmi_wide_index_f32(NAN, 0.1f, 32, &wide), MMI_OK);
    EXPECT("wide batch: count SIZE_MAX / 8",
           mmi_wide_index_f32_batch(us, vs, SIZE_MAX / 8, 5, wides), MMI_ERROR_LENGTH);
    EXPECT("wide batch: NaN, infinities", mmi_wide_index_f32_batch(us, vs, 4, 32, wides), MMI_OK);
    EXPECT("inverse: level 33", mmi_inverse_micro_triangle(33, 0, &t), MMI_ERROR_INVALID_LEVEL);
    EXPECT("inverse: index 4^5", mmi_inverse_micro_triangle(5, 1024, &t),
           MMI_ERROR_INVALID_ARGUMENT);
    EXPECT("inverse: index UINT64_MAX at 32", mmi_inverse_micro_triangle(32, UINT64_MAX, &t),
           MMI_OK);
    EXPECT("inverse: out NULL", mmi_inverse_micro_triangle(3, 0, NULL), MMI_ERROR_NULL_POINTER);
}

static void bake_textures(void) {
    const size_t gib4 = (size_t)1 << 32;
    mmi_mesh m = small_mesh();
    mmi_bake_options o = default_options();
    uint8_t *huge;
    uint16_t u16s[5] = {0, 65535, 65535, 0, 0};

    /* copy: 65535 x 65535 u8 at a pitch of 65536 (4 GiB given, 4 GiB to
     * copy). */
    huge = big(gib4);
    m.texture.texels = huge;
    m.texture.width = 65535;
    m.texture.height = 65535;
    m.texture.row_pitch = 65536;
    EXPECT("texture: u8 65535^2 pitch 65536 (copy)", bake(&m, &o), MMI_ERROR_OUT_OF_MEMORY);
    /* copy: float 32768 x 32768, a pitch 4 bytes wider than the row. */
    m.texture.format = MMI_TEXEL_F32;
    m.texture.width = 32768;
    m.texture.height = 32767;
    m.texture.row_pitch = 4 * 32768 + 4;
    EXPECT("texture: f32 32768x32767 pitch row+4 (copy)", bake(&m, &o), MMI_ERROR_OUT_OF_MEMORY);
    /* 2^32 texels, tight: refused by the library, nothing copied. */
    m.texture.format = MMI_TEXEL_U8;
    m.texture.width = 65536;
    m.texture.height = 65536;
    m.texture.row_pitch = 0;
    EXPECT("texture: u8 65536^2 tight", bake(&m, &o), MMI_ERROR_INVALID_ARGUMENT);
    munmap(huge, gib4);

    m = small_mesh();
    m.texture.row_pitch = SIZE_MAX / 2;
    EXPECT("texture: pitch SIZE_MAX / 2", bake(&m, &o), MMI_ERROR_LENGTH);
    m.texture.row_pitch = 1;
    EXPECT("texture: pitch below the row", bake(&m, &o), MMI_ERROR_LENGTH);
    m = small_mesh();
    m.texture.width = UINT32_MAX;
    m.texture.height = UINT32_MAX;
    m.texture.format = MMI_TEXEL_F32;
    EXPECT("texture: f32 UINT32_MAX^2 (64 EiB)", bake(&m, &o), MMI_ERROR_LENGTH);
    m = small_mesh();
    m.texture.width = 0;
    EXPECT("texture: width 0", bake(&m, &o), MMI_ERROR_INVALID_ARGUMENT);
    m = small_mesh();
    m.texture.height = 0;
    EXPECT("texture: height 0", bake(&m, &o), MMI_ERROR_INVALID_ARGUMENT);
    m = small_mesh();
    m.texture.texels = NULL;
    EXPECT("texture: texels NULL", bake(&m, &o), MMI_ERROR_NULL_POINTER);
    m.texture.format = 3;
    m.texture.texels = checker;
    EXPECT("texture: format 3", bake(&m, &o), MMI_ERROR_INVALID_ENUM);
    /* Misaligned u16 texels are copied, not read misaligned. */
    m = small_mesh();
    m.texture.format = MMI_TEXEL_U16;
    m.texture.texels = (const char *)u16s + 1;
    EXPECT("texture: u16 misaligned (copied)", bake(&m, &o), MMI_OK);
}

static void bake_materials_and_options(void) {
    mmi_mesh m = small_mesh();
    mmi_bake_options o = default_options();
    static float uvs[2048 * 6];
    size_t i;

    m.material.sampler.border_alpha = NAN;
    EXPECT("material: NaN border alpha", bake(&m, &o), MMI_ERROR_INVALID_ARGUMENT);
    m.material.sampler.address_u = MMI_ADDRESS_CLAMP_TO_BORDER;
    EXPECT("material: NaN border, clamp to border", bake(&m, &o), MMI_ERROR_INVALID_ARGUMENT);
    m = small_mesh();
    m.material.cutoff = NAN;
    EXPECT("material: NaN cutoff", bake(&m, &o), MMI_ERROR_INVALID_ARGUMENT);
    m = small_mesh();
    m.material.cutoff = INFINITY;
    EXPECT("material: infinite cutoff", bake(&m, &o), MMI_OK);
    m = small_mesh();
    m.material.alpha_factor = -1.0f;
    EXPECT("material: alpha factor -1", bake(&m, &o), MMI_OK);
    m = small_mesh();
    m.material.sampler.filter = UINT32_MAX;
    EXPECT("material: filter UINT32_MAX", bake(&m, &o), MMI_ERROR_INVALID_ENUM);
    m = small_mesh();
    m.material.sampler.address_v = 5;
    EXPECT("material: address_v 5", bake(&m, &o), MMI_ERROR_INVALID_ENUM);
    m = small_mesh();
    m.material.comparison = 2;
    EXPECT("material: comparison 2", bake(&m, &o), MMI_ERROR_INVALID_ENUM);

    m = small_mesh();
    o.level = 13;
    EXPECT("options: level 13", bake(&m, &o), MMI_ERROR_INVALID_LEVEL);
    o.level = 16;
    EXPECT("options: level 16", bake(&m, &o), MMI_ERROR_INVALID_LEVEL);
    o.level = MMI_LEVEL_AUTO - 1;
    EXPECT("options: level UINT32_MAX - 1", bake(&m, &o), MMI_ERROR_INVALID_LEVEL);
    o = default_options();
    o.max_level = 13;
    EXPECT("options: max_level 13", bake(&m, &o), MMI_ERROR_INVALID_LEVEL);
    o = default_options();
    o.level = MMI_MAX_BAKE_LEVEL;
    EXPECT("options: level 12", bake(&m, &o), MMI_OK);
    o = default_options();
    o.format = 0;
    EXPECT("options: format 0", bake(&m, &o), MMI_ERROR_INVALID_ENUM);
    o = default_options();
    o.unknown = 3;
    EXPECT("options: unknown 3", bake(&m, &o), MMI_ERROR_INVALID_ENUM);
    o = default_options();
    o.model = 2;
    EXPECT("options: model 2", bake(&m, &o), MMI_ERROR_INVALID_ENUM);
    o = default_options();
    o.use_budget = 1;
    o.budget_bytes = 0;
    EXPECT("options: byte budget 0", bake(&m, &o), MMI_OK);
    o = default_options();
    o.level = 5;
    o.max_bytes = 1;
    EXPECT("options: max_bytes 1", bake(&m, &o), MMI_ERROR_LIMIT);
    o.max_bytes = UINT64_MAX;
    EXPECT("options: max_bytes UINT64_MAX", bake(&m, &o), MMI_OK);
    /* 2048 level-12 triangles: 8 GiB of micromaps, over the default
     * limit (this baked on to 5.2 GB before). */
    for (i = 0; i < 2048 * 6; ++i) {
        uvs[i] = triangle[i % 6];
    }
    m.uvs = uvs;
    m.vertex_count = 2048 * 3;
    o = default_options();
    o.level = 12;
    EXPECT("options: 2048 level-12 triangles", bake(&m, &o), MMI_ERROR_LIMIT);
}

static void bake_geometry(void) {
    mmi_mesh m = small_mesh();
    mmi_bake_options o = default_options();
    mmi_bake_result *result = NULL;
    static const float odd[6] = {NAN, 0.0f, 1e30f, -1e30f, INFINITY, 1.0f};
    static const uint32_t far_index[3] = {0, 1, UINT32_MAX};
    static const float alphas[3] = {1.0f, 1.5f, 0.5f};
    static const float nan_alphas[3] = {1.0f, NAN, 0.5f};

    m.uvs = odd;
    EXPECT("uvs: NaN, 1e30, infinity", bake(&m, &o), MMI_OK);
    m = small_mesh();
    m.uvs = NULL;
    EXPECT("uvs: NULL", bake(&m, &o), MMI_ERROR_NULL_POINTER);
    m.vertex_count = 0;
    EXPECT("uvs: NULL, no vertices", bake(&m, &o), MMI_OK);
    m = small_mesh();
    m.vertex_count = SIZE_MAX;
    EXPECT("uvs: vertex_count SIZE_MAX", bake(&m, &o), MMI_ERROR_LENGTH);
    m = small_mesh();
    m.uv_stride = 6;
    EXPECT("uvs: stride 6", bake(&m, &o), MMI_ERROR_INVALID_ARGUMENT);
    m.uv_stride = SIZE_MAX - 3;
    EXPECT("uvs: stride SIZE_MAX - 3", bake(&m, &o), MMI_ERROR_LENGTH);
    m = small_mesh();
    m.uvs = (const float *)((const char *)triangle + 2);
    EXPECT("uvs: misaligned", bake(&m, &o), MMI_ERROR_LENGTH);
    m = small_mesh();
    m.vertex_count = 2;
    EXPECT("uvs: 2 vertices, no indices", bake(&m, &o), MMI_ERROR_LENGTH);
    m = small_mesh();
    m.indices = far_index;
    m.index_count = 3;
    EXPECT("indices: UINT32_MAX names no vertex", bake(&m, &o), MMI_ERROR_BAKE);
    m.index_count = 2;
    EXPECT("indices: count 2", bake(&m, &o), MMI_ERROR_LENGTH);
    m.index_count = SIZE_MAX;
    EXPECT("indices: count SIZE_MAX", bake(&m, &o), MMI_ERROR_LENGTH);
    m = small_mesh();
    m.vertex_alpha = alphas;
    EXPECT("vertex alpha: 1.5", bake(&m, &o), MMI_ERROR_BAKE);
    m.vertex_alpha = nan_alphas;
    EXPECT("vertex alpha: NaN", bake(&m, &o), MMI_ERROR_BAKE);
    m.vertex_alpha_stride = 6;
    EXPECT("vertex alpha: stride 6", bake(&m, &o), MMI_ERROR_INVALID_ARGUMENT);
    m.vertex_alpha_stride = SIZE_MAX - 3;
    EXPECT("vertex alpha: stride SIZE_MAX - 3", bake(&m, &o), MMI_ERROR_LENGTH);
    m.vertex_alpha_stride = 0;
    m.indices = far_index;
    m.index_count = 3;
    EXPECT("vertex alpha: index names no vertex", bake(&m, &o), MMI_ERROR_INVALID_ARGUMENT);

    m = small_mesh();
    EXPECT("bake: meshes NULL", mmi_bake(NULL, 1, &o, &result), MMI_ERROR_NULL_POINTER);
    EXPECT("bake: mesh_count SIZE_MAX", mmi_bake(&m, SIZE_MAX, &o, &result), MMI_ERROR_LENGTH);
    EXPECT("bake: options NULL", mmi_bake(&m, 1, NULL, &result), MMI_ERROR_NULL_POINTER);
    EXPECT("bake: result NULL", mmi_bake(&m, 1, &o, NULL), MMI_ERROR_NULL_POINTER);
    EXPECT("bake: no meshes", mmi_bake(NULL, 0, &o, &result), MMI_OK);
    mmi_bake_result_free(result);
    EXPECT("defaults: options NULL", mmi_bake_options_default(NULL), MMI_ERROR_NULL_POINTER);
    EXPECT("defaults: material NULL", mmi_material_default(NULL), MMI_ERROR_NULL_POINTER);
}

static void bake_results(void) {
    mmi_mesh m = small_mesh();
    mmi_bake_options o = default_options();
    mmi_bake_result *result = NULL;
    const uint8_t *data = NULL;
    size_t len = 0, count = 0;
    uint8_t small[1];
    uint32_t mixed = 0;
    mmi_bake_stats stats;

    o.level = 3;
    EXPECT("result: bake", mmi_bake(&m, 1, &o, &result), MMI_OK);
    EXPECT("result: data NULL handle", mmi_bake_result_data(NULL, &data, &len),
           MMI_ERROR_NULL_POINTER);
    EXPECT("result: data len NULL", mmi_bake_result_data(result, &data, NULL),
           MMI_ERROR_NULL_POINTER);
    EXPECT("result: records out NULL", mmi_bake_result_triangle_records(result, NULL, &len),
           MMI_ERROR_NULL_POINTER);
    EXPECT("result: usage", mmi_bake_result_usage_counts(result, &data, &len), MMI_OK);
    EXPECT("result: geometry count NULL", mmi_bake_result_geometry_count(result, NULL),
           MMI_ERROR_NULL_POINTER);
    EXPECT("result: geometry count", mmi_bake_result_geometry_count(result, &count), MMI_OK);
    EXPECT("result: is_mixed geometry 1", mmi_bake_result_is_mixed(result, 1, &mixed),
           MMI_ERROR_INVALID_ARGUMENT);
    EXPECT("result: is_mixed SIZE_MAX", mmi_bake_result_is_mixed(result, SIZE_MAX, &mixed),
           MMI_ERROR_INVALID_ARGUMENT);
    EXPECT("result: indices width 12", mmi_bake_result_indices(result, 0, 12, NULL, 0, &len),
           MMI_ERROR_INVALID_ENUM);
    EXPECT("result: indices geometry 7", mmi_bake_result_indices(result, 7, 32, NULL, 0, &len),
           MMI_ERROR_INVALID_ARGUMENT);
    EXPECT("result: indices SIZE_MAX - 1",
           mmi_bake_result_indices(result, SIZE_MAX - 1, 32, NULL, 0, &len),
           MMI_ERROR_INVALID_ARGUMENT);
    EXPECT("result: indices short buffer",
           mmi_bake_result_indices(result, 0, 32, small, sizeof small, &len),
           MMI_ERROR_BUFFER_TOO_SMALL);
    EXPECT("result: indices len NULL", mmi_bake_result_indices(result, 0, 32, NULL, 0, NULL),
           MMI_ERROR_NULL_POINTER);
    EXPECT("result: stats NULL", mmi_bake_result_stats(result, NULL), MMI_ERROR_NULL_POINTER);
    EXPECT("result: stats", mmi_bake_result_stats(result, &stats), MMI_OK);
    mmi_bake_result_free(result);
    mmi_bake_result_free(NULL);
}

/* A buffers view over one record at `level` (4-state, offset 0) and one
 * 32-bit index 0. */
static mmi_buffers_view one_record(const uint8_t *data, size_t data_len, uint8_t *records,
                                   const uint8_t *index, uint32_t level) {
    mmi_buffers_view v;
    memset(&v, 0, sizeof v);
    memset(records, 0, 8);
    records[4] = (uint8_t)level;
    records[6] = MMI_FORMAT_4_STATE;
    v.data = data;
    v.data_len = data_len;
    v.records = records;
    v.records_len = 8;
    v.indices = index;
    v.indices_len = 4;
    v.index_width_bits = 32;
    return v;
}

static void validate_and_verify(void) {
    static const uint8_t zero_index[4] = {0, 0, 0, 0};
    /* Two 32-bit special indices -2 (opaque). */
    static const uint8_t opaque_index[8] = {0xfe, 0xff, 0xff, 0xff, 0xfe, 0xff, 0xff, 0xff};
    const size_t level12 = (size_t)1 << 22;
    uint8_t records[8], data[64];
    uint8_t *opaque;
    mmi_buffers_view v;
    mmi_read_options ro;
    mmi_buffers_info info;
    mmi_verify_report report;
    mmi_contradiction witnesses[3];
    mmi_mesh m = small_mesh();
    static const uint8_t transparent[1] = {0};

    memset(data, 0x55, sizeof data);
    v = one_record(data, sizeof data, records, zero_index, 3); /* 16 bytes */
    EXPECT("validate: one record", mmi_validate_buffers(&v, NULL, &info), MMI_OK);
    EXPECT("validate: buffers NULL", mmi_validate_buffers(NULL, NULL, &info),
           MMI_ERROR_NULL_POINTER);
    v.records_len = 7;
    EXPECT("validate: records_len 7", mmi_validate_buffers(&v, NULL, NULL), MMI_ERROR_MALFORMED);
    v.records_len = SIZE_MAX;
    EXPECT("validate: records_len SIZE_MAX", mmi_validate_buffers(&v, NULL, NULL),
           MMI_ERROR_LENGTH);
    v = one_record(data, sizeof data, records, zero_index, 40);
    EXPECT("validate: level 40", mmi_validate_buffers(&v, NULL, NULL), MMI_ERROR_MALFORMED);
    v = one_record(data, sizeof data, records, zero_index, 16);
    EXPECT("validate: level 16, 64 bytes", mmi_validate_buffers(&v, NULL, NULL),
           MMI_ERROR_MALFORMED);
    v = one_record(data, sizeof data, records, zero_index, 3);
    records[0] = 0xff;
    records[1] = 0xff;
    records[2] = 0xff;
    records[3] = 0xff;
    EXPECT("validate: offset UINT32_MAX", mmi_validate_buffers(&v, NULL, NULL),
           MMI_ERROR_MALFORMED);
    v = one_record(data, sizeof data, records, zero_index, 3);
    v.record_stride = 6;
    EXPECT("validate: record stride 6", mmi_validate_buffers(&v, NULL, NULL),
           MMI_ERROR_INVALID_ARGUMENT);
    v.record_stride = SIZE_MAX - 3;
    /* One record ending right after its 8 bytes: any allowed stride. */
    EXPECT("validate: record stride SIZE_MAX - 3", mmi_validate_buffers(&v, NULL, NULL), MMI_OK);
    v = one_record(data, sizeof data, records, zero_index, 3);
    v.index_stride = 6;
    EXPECT("validate: index stride 6", mmi_validate_buffers(&v, NULL, NULL),
           MMI_ERROR_INVALID_ARGUMENT);
    v.index_stride = 0;
    v.index_width_bits = 24;
    EXPECT("validate: index width 24", mmi_validate_buffers(&v, NULL, NULL),
           MMI_ERROR_INVALID_ENUM);
    v = one_record(data, sizeof data, records, zero_index, 3);
    v.data = NULL;
    EXPECT("validate: data NULL", mmi_validate_buffers(&v, NULL, NULL), MMI_ERROR_NULL_POINTER);
    mmi_read_options_default(&ro);
    ro.max_level = UINT32_MAX;
    ro.base_triangle = UINT32_MAX;
    v = one_record(data, sizeof data, records, zero_index, 3);
    EXPECT("validate: base triangle UINT32_MAX", mmi_validate_buffers(&v, &ro, NULL),
           MMI_ERROR_MALFORMED);
    EXPECT("validate: read options NULL", mmi_read_options_default(NULL),
           MMI_ERROR_NULL_POINTER);

    /* mmi_verify: a level-12 record, every state opaque, over a
     * transparent texel: 16.7 million contradictions, three kept (all of
     * them took 1.58 GB before). */
    opaque = big(level12);
    memset(opaque, 0x55, level12);
    m.texture.texels = transparent;
    m.texture.width = 1;
    m.texture.height = 1;
    v = one_record(opaque, level12, records, zero_index, 12);
    EXPECT("verify: 16.7M contradictions, 3 kept", mmi_verify(&m, &v, &report, witnesses, 3),
           MMI_OK);
    if (report.contradictions != (uint64_t)1 << 24 || report.witnesses_written != 3) {
        ++failures;
        fprintf(stderr, "verify: %llu contradictions, %llu written\n",
                (unsigned long long)report.contradictions,
                (unsigned long long)report.witnesses_written);
    }
    munmap(opaque, level12);
    v = one_record(data, sizeof data, records, opaque_index, 3);
    EXPECT("verify: special opaque", mmi_verify(&m, &v, &report, NULL, 0), MMI_OK);
    EXPECT("verify: mesh NULL", mmi_verify(NULL, &v, &report, NULL, 0), MMI_ERROR_NULL_POINTER);
    EXPECT("verify: report NULL", mmi_verify(&m, &v, NULL, NULL, 0), MMI_ERROR_NULL_POINTER);
    EXPECT("verify: witnesses NULL, capacity 3", mmi_verify(&m, &v, &report, NULL, 3),
           MMI_ERROR_NULL_POINTER);
    EXPECT("verify: model 2", mmi_verify_with_model(&m, &v, 2, &report, NULL, 0),
           MMI_ERROR_INVALID_ENUM);
    v.indices = NULL;
    EXPECT("verify: indices NULL", mmi_verify(&m, &v, &report, NULL, 0), MMI_ERROR_NULL_POINTER);
    v = one_record(data, sizeof data, records, opaque_index, 3);
    v.indices_len = 8;
    EXPECT("verify: 2 indices, 1 triangle", mmi_verify(&m, &v, &report, NULL, 0),
           MMI_ERROR_LENGTH);
    v.indices_len = 0;
    EXPECT("verify: no index, 1 triangle", mmi_verify(&m, &v, &report, NULL, 0),
           MMI_ERROR_LENGTH);
    v = one_record(data, sizeof data, records, opaque_index, 3);
    m.material.sampler.border_alpha = NAN;
    EXPECT("verify: NaN border alpha", mmi_verify(&m, &v, &report, NULL, 0),
           MMI_ERROR_INVALID_ARGUMENT);
    m = small_mesh();
    m.material.alpha_factor = 0.25f;
    EXPECT("verify: alpha factor 0.25", mmi_verify(&m, &v, &report, witnesses, 3), MMI_OK);
    m.texture.row_pitch = SIZE_MAX / 2;
    EXPECT("verify: pitch SIZE_MAX / 2", mmi_verify(&m, &v, &report, NULL, 0), MMI_ERROR_LENGTH);
}

static void trees(void) {
    const size_t level16 = (size_t)1 << 32;
    uint8_t states[16], out[16], *huge;
    static const uint8_t junk[12] = {'S', 'O', 'M', 'T', 1, 0, 16, 2, 0xff, 0xff, 0xff, 0xff};
    /* Paper layout, level 16, 4-state; one tree bit (a leaf), one state (3). */
    uint8_t leaf[26] = {'S', 'O', 'M', 'T', 1, 0, 16, 2, 1, 0, 0, 0, 0, 0, 0, 0,
                        1, 0, 0, 0, 0, 0, 0, 0, 0, 3};
    mmi_tree *tree = NULL;
    size_t len = 0;
    uint8_t state = 0;
    mmi_tree_info info;

    memset(states, MMI_STATE_OPAQUE, sizeof states);
    EXPECT("tree: level 17", mmi_tree_encode(MMI_TREE_PAPER, 17, 2, states, 16, &tree),
           MMI_ERROR_INVALID_LEVEL);
    EXPECT("tree: layout 9", mmi_tree_encode(9, 2, 2, states, 16, &tree), MMI_ERROR_INVALID_ENUM);
    EXPECT("tree: format 0", mmi_tree_encode(MMI_TREE_PAPER, 2, 0, states, 16, &tree),
           MMI_ERROR_INVALID_ENUM);
    EXPECT("tree: 15 states at level 2", mmi_tree_encode(MMI_TREE_PAPER, 2, 2, states, 15, &tree),
           MMI_ERROR_LENGTH);
    EXPECT("tree: state_count SIZE_MAX",
           mmi_tree_encode(MMI_TREE_PAPER, 2, 2, states, SIZE_MAX, &tree), MMI_ERROR_LENGTH);
    EXPECT("tree: states NULL", mmi_tree_encode(MMI_TREE_PAPER, 2, 2, NULL, 16, &tree),
           MMI_ERROR_NULL_POINTER);
    EXPECT("tree: tree NULL", mmi_tree_encode(MMI_TREE_PAPER, 2, 2, states, 16, NULL),
           MMI_ERROR_NULL_POINTER);
    states[9] = 200;
    EXPECT("tree: state 200", mmi_tree_encode(MMI_TREE_PAPER, 2, 2, states, 16, &tree),
           MMI_ERROR_INVALID_ENUM);
    states[9] = MMI_STATE_UNKNOWN_OPAQUE;
    EXPECT("tree: unknown in 2-state",
           mmi_tree_encode(MMI_TREE_LEVEL_ORDER, 2, MMI_FORMAT_2_STATE, states, 16, &tree),
           MMI_ERROR_INVALID_ARGUMENT);

    /* copy: 4^16 states (4 GiB) are read in place; the one the format
     * refuses is the last. */
    huge = big(level16);
    huge[level16 - 1] = 4;
    EXPECT("tree: level 16, last state 4 (copy)",
           mmi_tree_encode(MMI_TREE_PAPER, 16, MMI_FORMAT_2_STATE, huge, level16, &tree),
           MMI_ERROR_INVALID_ENUM);
    huge[level16 - 1] = MMI_STATE_UNKNOWN_TRANSPARENT;
    EXPECT("tree: level 16, last unknown (copy)",
           mmi_tree_encode(MMI_TREE_LEVEL_ORDER, 16, MMI_FORMAT_2_STATE, huge, level16, &tree),
           MMI_ERROR_INVALID_ARGUMENT);
    munmap(huge, level16);

    /* A root leaf is 26 bytes at any level: at level 16 it holds 4^16
     * states, which the library used to decode into a 4 GiB copy before
     * writing the caller's buffer. Now it writes the runs into the
     * caller's buffer and allocates nothing. */
    EXPECT("tree: root leaf, level 16", mmi_tree_from_bytes(leaf, sizeof leaf, &tree), MMI_OK);
    len = 0;
    EXPECT("tree: decode size, level 16", mmi_tree_decode(tree, NULL, 0, &len), MMI_OK);
    if (len != level16) {
        ++failures;
        fprintf(stderr, "hostile.c:%d: decode size %zu, expected 4^16\n", __LINE__, len);
    }
    EXPECT("tree: decode short, level 16", mmi_tree_decode(tree, out, sizeof out, &len),
           MMI_ERROR_BUFFER_TOO_SMALL);
    mmi_tree_free(tree);
    leaf[6] = 12;
    EXPECT("tree: root leaf, level 12", mmi_tree_from_bytes(leaf, sizeof leaf, &tree), MMI_OK);
    huge = big((size_t)1 << 24);
    EXPECT("tree: decode, level 12", mmi_tree_decode(tree, huge, (size_t)1 << 24, &len), MMI_OK);
    for (len = 0; len < (size_t)1 << 24 && huge[len] == MMI_STATE_UNKNOWN_OPAQUE; ++len) {
    }
    if (len != (size_t)1 << 24) {
        ++failures;
        fprintf(stderr, "hostile.c:%d: state %zu of the level-12 root leaf is %d\n", __LINE__,
                len, huge[len]);
    }
    munmap(huge, (size_t)1 << 24);
    mmi_tree_free(tree);

    EXPECT("tree: bytes NULL", mmi_tree_from_bytes(NULL, 5, &tree), MMI_ERROR_NULL_POINTER);
    EXPECT("tree: no bytes", mmi_tree_from_bytes(NULL, 0, &tree), MMI_ERROR_MALFORMED);
    EXPECT("tree: junk header, level 16", mmi_tree_from_bytes(junk, sizeof junk, &tree),
           MMI_ERROR_MALFORMED);
    EXPECT("tree: bytes len SIZE_MAX", mmi_tree_from_bytes(junk, SIZE_MAX, &tree),
           MMI_ERROR_LENGTH);

    memset(states, MMI_STATE_OPAQUE, sizeof states);
    states[3] = MMI_STATE_TRANSPARENT;
    EXPECT("tree: encode", mmi_tree_encode(MMI_TREE_LEVEL_ORDER, 2, 2, states, 16, &tree), MMI_OK);
    EXPECT("tree: get 16", mmi_tree_get(tree, 16, &state), MMI_ERROR_INVALID_ARGUMENT);
    EXPECT("tree: get UINT64_MAX", mmi_tree_get(tree, UINT64_MAX, &state),
           MMI_ERROR_INVALID_ARGUMENT);
    EXPECT("tree: get NULL tree", mmi_tree_get(NULL, 0, &state), MMI_ERROR_NULL_POINTER);
    EXPECT("tree: get state NULL", mmi_tree_get(tree, 0, NULL), MMI_ERROR_NULL_POINTER);
    EXPECT("tree: get_f32 NaN", mmi_tree_get_f32(tree, NAN, INFINITY, &state), MMI_OK);
    EXPECT("tree: to_bytes size", mmi_tree_to_bytes(tree, NULL, 0, &len), MMI_OK);
    EXPECT("tree: to_bytes short", mmi_tree_to_bytes(tree, out, 1, &len),
           MMI_ERROR_BUFFER_TOO_SMALL);
    EXPECT("tree: to_bytes len NULL", mmi_tree_to_bytes(tree, out, sizeof out, NULL),
           MMI_ERROR_NULL_POINTER);
    EXPECT("tree: decode short", mmi_tree_decode(tree, out, 15, &len),
           MMI_ERROR_BUFFER_TOO_SMALL);
    EXPECT("tree: decode", mmi_tree_decode(tree, out, sizeof out, &len), MMI_OK);
    EXPECT("tree: info NULL", mmi_tree_info_get(tree, NULL), MMI_ERROR_NULL_POINTER);
    EXPECT("tree: info", mmi_tree_info_get(tree, &info), MMI_OK);
    mmi_tree_free(tree);
    mmi_tree_free(NULL);
}

/* The sections, in order; `hostile NAME...` runs only those named (to
 * look at one repro, e.g. against an older library). */
static const struct {
    const char *name;
    void (*run)(void);
} sections[] = {
    {"index", index_functions},     {"textures", bake_textures},
    {"materials", bake_materials_and_options},
    {"geometry", bake_geometry},    {"results", bake_results},
    {"buffers", validate_and_verify}, {"trees", trees},
};

int main(int argc, char **argv) {
    size_t s;
    int a;
    for (s = 0; s < sizeof sections / sizeof sections[0]; ++s) {
        int chosen = argc == 1;
        for (a = 1; a < argc; ++a) {
            chosen |= strcmp(argv[a], sections[s].name) == 0;
        }
        if (chosen) {
            sections[s].run();
            fflush(stdout);
        }
    }
    if (failures != 0) {
        fprintf(stderr, "%d of %d cases failed\n", failures, cases);
        return 1;
    }
    printf("ok %d cases\n", cases);
    return 0;
}
