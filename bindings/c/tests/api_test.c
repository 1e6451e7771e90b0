/*
 * The C API from C: answers against known values, misuse returning its
 * documented codes (NULL, short buffers, bad enums, bad levels, malformed
 * bytes), and handle lifetimes; run by tests/c_api.rs, under
 * AddressSanitizer and UndefinedBehaviorSanitizer where the runtime is
 * installed. Prints the layout of every struct for the Rust side to check
 * (`sizeof NAME N` lines), then "ok N checks".
 */
#include "micromap_index.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int checks = 0;
static int failures = 0;

#define CHECK(cond)                                                                     \
    do {                                                                                \
        ++checks;                                                                       \
        if (!(cond)) {                                                                  \
            ++failures;                                                                 \
            fprintf(stderr, "%s:%d: CHECK(%s) failed; last error: %s\n", __FILE__,      \
                    __LINE__, #cond, mmi_last_error_message());                         \
        }                                                                               \
    } while (0)

#define EXPECT(call, code) CHECK((call) == (code))

/* The message of the last failure mentions `word`. */
static int says(const char *word) { return strstr(mmi_last_error_message(), word) != NULL; }

static void layout(void) {
#define SIZE(T) printf("sizeof %s %u\n", #T, (unsigned)sizeof(T))
    SIZE(mmi_micro_triangle);
    SIZE(mmi_texture);
    SIZE(mmi_sampler);
    SIZE(mmi_material);
    SIZE(mmi_uv_transform);
    SIZE(mmi_mesh);
    SIZE(mmi_bake_options);
    SIZE(mmi_bake_stats);
    SIZE(mmi_buffers_view);
    SIZE(mmi_read_options);
    SIZE(mmi_buffers_info);
    SIZE(mmi_verify_report);
    SIZE(mmi_contradiction);
    SIZE(mmi_tree_info);
#undef SIZE
}

static void index_and_inverse(void) {
    uint32_t out = 0;
    uint64_t wide = 0;
    float us[5] = {0.3f, 0.3f, 1.0f, -1.0f, 0.0f};
    float vs[5] = {0.3f, 0.6f, 0.0f, 2.0f, 0.0f};
    uint32_t batch[5];
    uint64_t wide_batch[5];
    mmi_micro_triangle t;
    int i;

    EXPECT(mmi_index_f32(0.3f, 0.3f, 2, &out), MMI_OK);
    CHECK(out == 5);
    CHECK(mmi_last_error_message()[0] == '\0');
    EXPECT(mmi_index_f32(0.3f, 0.3f, 17, &out), MMI_ERROR_INVALID_LEVEL);
    CHECK(says("17"));
    EXPECT(mmi_index_f32(0.3f, 0.3f, 2, NULL), MMI_ERROR_NULL_POINTER);
    CHECK(says("out"));
    EXPECT(mmi_index_f32(NAN, 2.0f, 3, &out), MMI_OK);

    EXPECT(mmi_index_f32_batch(us, vs, 5, 2, batch), MMI_OK);
    CHECK(batch[0] == 5 && batch[1] == 12);
    for (i = 0; i < 5; ++i) {
        EXPECT(mmi_index_f32(us[i], vs[i], 2, &out), MMI_OK);
        CHECK(batch[i] == out);
    }
    EXPECT(mmi_index_f32_batch(NULL, NULL, 0, 2, NULL), MMI_OK);
    EXPECT(mmi_index_f32_batch(us, NULL, 5, 2, batch), MMI_ERROR_NULL_POINTER);
    EXPECT(mmi_index_f32_batch(us, vs, 5, 99, batch), MMI_ERROR_INVALID_LEVEL);
    /* A misaligned array. */
    EXPECT(mmi_index_f32_batch((const float *)((const char *)us + 1), vs, 2, 2, batch),
           MMI_ERROR_LENGTH);

    EXPECT(mmi_wide_index_f32(1.0f, 0.0f, 32, &wide), MMI_OK);
    CHECK(wide == 2 * UINT64_C(0x5555555555555555));
    EXPECT(mmi_wide_index_f32(0.0f, 0.0f, 33, &wide), MMI_ERROR_INVALID_LEVEL);
    EXPECT(mmi_wide_index_f32_batch(us, vs, 5, 2, wide_batch), MMI_OK);
    for (i = 0; i < 5; ++i) {
        CHECK(wide_batch[i] == batch[i]);
    }

    EXPECT(mmi_inverse_micro_triangle(1, 1, &t), MMI_OK);
    CHECK(t.level == 1 && t.index == 1 && t.upright == 0);
    CHECK(t.vertices[0] == 0 && t.vertices[1] == 1 && t.vertices[2] == 1 &&
          t.vertices[3] == 1 && t.vertices[4] == 1 && t.vertices[5] == 0);
    EXPECT(mmi_inverse_micro_triangle(1, 4, &t), MMI_ERROR_INVALID_ARGUMENT);
    EXPECT(mmi_inverse_micro_triangle(33, 0, &t), MMI_ERROR_INVALID_LEVEL);
    EXPECT(mmi_inverse_micro_triangle(1, 0, NULL), MMI_ERROR_NULL_POINTER);
    /* The inverse and the index agree on every micro-triangle's centroid. */
    for (i = 0; i < 64; ++i) {
        float cu, cv;
        EXPECT(mmi_inverse_micro_triangle(3, (uint64_t)i, &t), MMI_OK);
        cu = (float)(t.vertices[0] + t.vertices[2] + t.vertices[4]) / 24.0f;
        cv = (float)(t.vertices[1] + t.vertices[3] + t.vertices[5]) / 24.0f;
        EXPECT(mmi_index_f32(cu, cv, 3, &out), MMI_OK);
        CHECK(out == (uint32_t)i);
    }
}

/* An 8 x 8 texture, opaque in its left three columns, with a row pitch of
 * 11 bytes; one quad over it as two indexed triangles. */
static uint8_t texels[8 * 11];
static const float quad_uvs[] = {0.0f, 0.0f, 9.0f, 1.0f, 0.0f, 9.0f, 1.0f, 1.0f, 9.0f, 0.0f, 1.0f, 9.0f};
static const uint32_t quad_indices[] = {0, 1, 2, 0, 2, 3};

static void quad_mesh(mmi_mesh *mesh) {
    int x, y;
    for (y = 0; y < 8; ++y) {
        for (x = 0; x < 11; ++x) {
            texels[y * 11 + x] = (x < 3) ? 255 : (x < 8 ? 0 : 77);
        }
    }
    memset(mesh, 0, sizeof *mesh);
    mesh->texture.texels = texels;
    mesh->texture.width = 8;
    mesh->texture.height = 8;
    mesh->texture.row_pitch = 11;
    mesh->texture.format = MMI_TEXEL_U8;
    EXPECT(mmi_material_default(&mesh->material), MMI_OK);
    mesh->uvs = quad_uvs;
    mesh->vertex_count = 4;
    mesh->uv_stride = 3 * sizeof(float);
    mesh->indices = quad_indices;
    mesh->index_count = 6;
}

static void bake_and_verify(void) {
    mmi_mesh mesh, bad;
    mmi_bake_options options, bad_options;
    mmi_bake_result *result = NULL;
    mmi_bake_stats stats;
    mmi_verify_report report;
    mmi_contradiction witnesses[4];
    mmi_buffers_view view;
    mmi_buffers_info info;
    mmi_read_options read_options;
    const uint8_t *data = NULL, *records = NULL, *usage = NULL;
    size_t data_len = 0, records_len = 0, usage_len = 0, len = 0, count = 0;
    uint8_t indices[64], small[2], flipped[64];
    size_t i;
    float wide_texels[64];
    static const float zero_alpha[4] = {0.0f, 0.0f, 0.0f, 0.0f};

    quad_mesh(&mesh);
    EXPECT(mmi_bake_options_default(&options), MMI_OK);
    CHECK(options.level == MMI_LEVEL_AUTO && options.max_level == 12 &&
          options.format == MMI_FORMAT_4_STATE && options.model == MMI_MODEL_GPU_BINARY32 &&
          options.max_bytes == MMI_DEFAULT_MAX_BYTES);

    /* Misuse first: each returns its code and leaves *result NULL. */
    result = (mmi_bake_result *)&mesh; /* must be overwritten with NULL */
    EXPECT(mmi_bake(NULL, 1, &options, &result), MMI_ERROR_NULL_POINTER);
    CHECK(result == NULL);
    EXPECT(mmi_bake(&mesh, 1, NULL, &result), MMI_ERROR_NULL_POINTER);
    EXPECT(mmi_bake(&mesh, 1, &options, NULL), MMI_ERROR_NULL_POINTER);
    bad_options = options;
    bad_options.level = 17;
    EXPECT(mmi_bake(&mesh, 1, &bad_options, &result), MMI_ERROR_INVALID_LEVEL);
    bad_options = options;
    bad_options.level = MMI_MAX_BAKE_LEVEL + 1; /* 13: the range is the CLI's */
    EXPECT(mmi_bake(&mesh, 1, &bad_options, &result), MMI_ERROR_INVALID_LEVEL);
    CHECK(says("level 13: expected a level 0..=12"));
    bad_options = options;
    bad_options.max_level = 40;
    EXPECT(mmi_bake(&mesh, 1, &bad_options, &result), MMI_ERROR_INVALID_LEVEL);
    bad_options = options;
    bad_options.max_level = 16;
    EXPECT(mmi_bake(&mesh, 1, &bad_options, &result), MMI_ERROR_INVALID_LEVEL);
    CHECK(says("max_level 16"));
    bad_options = options;
    bad_options.level = 4;
    bad_options.max_bytes = 100; /* two level-4 maps alone are 128 bytes */
    EXPECT(mmi_bake(&mesh, 1, &bad_options, &result), MMI_ERROR_LIMIT);
    CHECK(says("over the limit of 100 bytes") && result == NULL);
    bad_options = options;
    bad_options.format = 3;
    EXPECT(mmi_bake(&mesh, 1, &bad_options, &result), MMI_ERROR_INVALID_ENUM);
    bad_options = options;
    bad_options.unknown = 7;
    EXPECT(mmi_bake(&mesh, 1, &bad_options, &result), MMI_ERROR_INVALID_ENUM);
    bad = mesh;
    bad.texture.format = 9;
    EXPECT(mmi_bake(&bad, 1, &options, &result), MMI_ERROR_INVALID_ENUM);
    bad = mesh;
    bad.material.sampler.filter = 2;
    EXPECT(mmi_bake(&bad, 1, &options, &result), MMI_ERROR_INVALID_ENUM);
    bad = mesh;
    bad.material.sampler.address_v = 5;
    EXPECT(mmi_bake(&bad, 1, &options, &result), MMI_ERROR_INVALID_ENUM);
    bad = mesh;
    bad.material.comparison = 2;
    EXPECT(mmi_bake(&bad, 1, &options, &result), MMI_ERROR_INVALID_ENUM);
    bad = mesh;
    bad.material.cutoff = NAN;
    EXPECT(mmi_bake(&bad, 1, &options, &result), MMI_ERROR_INVALID_ARGUMENT);
    bad = mesh;
    bad.material.sampler.border_alpha = NAN;
    EXPECT(mmi_bake(&bad, 1, &options, &result), MMI_ERROR_INVALID_ARGUMENT);
    CHECK(says("border alpha is NaN"));
    bad = mesh;
    bad.texture.row_pitch = 7; /* below the 8-byte row */
    EXPECT(mmi_bake(&bad, 1, &options, &result), MMI_ERROR_LENGTH);
    bad = mesh;
    bad.texture.width = 0;
    EXPECT(mmi_bake(&bad, 1, &options, &result), MMI_ERROR_INVALID_ARGUMENT);
    bad = mesh;
    bad.texture.texels = NULL;
    EXPECT(mmi_bake(&bad, 1, &options, &result), MMI_ERROR_NULL_POINTER);
    bad = mesh;
    bad.uv_stride = 6;
    EXPECT(mmi_bake(&bad, 1, &options, &result), MMI_ERROR_INVALID_ARGUMENT);
    bad = mesh;
    bad.index_count = 5;
    EXPECT(mmi_bake(&bad, 1, &options, &result), MMI_ERROR_LENGTH);
    bad = mesh;
    bad.vertex_count = 3; /* index 3 names no vertex */
    EXPECT(mmi_bake(&bad, 1, &options, &result), MMI_ERROR_BAKE);
    CHECK(says("index 3"));
    bad = mesh;
    bad.indices = NULL; /* four vertices, not a multiple of 3 */
    EXPECT(mmi_bake(&bad, 1, &options, &result), MMI_ERROR_LENGTH);
    CHECK(result == NULL);

    /* The bake: level 4 (edges of 8 and 11.3 texels, eq. 1). */
    EXPECT(mmi_bake(&mesh, 1, &options, &result), MMI_OK);
    CHECK(result != NULL);
    EXPECT(mmi_bake_result_stats(result, &stats), MMI_OK);
    CHECK(stats.triangles == 2);
    CHECK(stats.level_count == 5 && stats.levels[4] == 2);
    CHECK(stats.counts[MMI_STATE_OPAQUE] > 0 && stats.counts[MMI_STATE_TRANSPARENT] > 0);
    CHECK(stats.known_fraction > 0.5 && stats.known_fraction < 1.0);
    EXPECT(mmi_bake_result_stats(NULL, &stats), MMI_ERROR_NULL_POINTER);
    EXPECT(mmi_bake_result_stats(result, NULL), MMI_ERROR_NULL_POINTER);
    EXPECT(mmi_bake_result_geometry_count(result, &count), MMI_OK);
    CHECK(count == 1);

    EXPECT(mmi_bake_result_data(result, &data, &data_len), MMI_OK);
    CHECK(data != NULL && data_len == stats.bytes_flat);
    EXPECT(mmi_bake_result_data(result, NULL, &data_len), MMI_ERROR_NULL_POINTER);
    EXPECT(mmi_bake_result_data(result, &data, NULL), MMI_ERROR_NULL_POINTER);
    EXPECT(mmi_bake_result_triangle_records(result, &records, &records_len), MMI_OK);
    CHECK(records_len == 8 * stats.micromaps);
    EXPECT(mmi_bake_result_usage_counts(result, &usage, &usage_len), MMI_OK);
    CHECK(usage_len % 12 == 0 && usage_len > 0);

    /* Sizes first; short buffers refused with the size written. */
    EXPECT(mmi_bake_result_indices(result, 0, 32, NULL, 0, &len), MMI_OK);
    CHECK(len == 8);
    len = 0;
    EXPECT(mmi_bake_result_indices(result, 0, 32, small, sizeof small, &len),
           MMI_ERROR_BUFFER_TOO_SMALL);
    CHECK(len == 8);
    EXPECT(mmi_bake_result_indices(result, 0, 32, indices, sizeof indices, NULL),
           MMI_ERROR_NULL_POINTER);
    EXPECT(mmi_bake_result_indices(result, 0, 12, NULL, 0, &len), MMI_ERROR_INVALID_ENUM);
    EXPECT(mmi_bake_result_indices(result, 1, 32, NULL, 0, &len), MMI_ERROR_INVALID_ARGUMENT);
    EXPECT(mmi_bake_result_indices(result, 0, 8, indices, sizeof indices, &len), MMI_OK);
    CHECK(len == 2);
    EXPECT(mmi_bake_result_indices(result, 0, 16, indices, sizeof indices, &len), MMI_OK);
    CHECK(len == 4);
    EXPECT(mmi_bake_result_indices(result, MMI_ALL_GEOMETRIES, 32, indices, sizeof indices, &len),
           MMI_OK);
    CHECK(len == 8);

    /* The validator accepts the bake's buffers... */
    memset(&view, 0, sizeof view);
    view.data = data;
    view.data_len = data_len;
    view.records = records;
    view.records_len = records_len;
    view.usage_counts = usage;
    view.usage_counts_len = usage_len;
    view.indices = indices;
    view.indices_len = len;
    view.index_width_bits = 32;
    EXPECT(mmi_validate_buffers(&view, NULL, &info), MMI_OK);
    CHECK(info.records == stats.micromaps && info.indices == 2);
    EXPECT(mmi_read_options_default(&read_options), MMI_OK);
    CHECK(read_options.max_level == 16 && read_options.allow_overlap == 0);
    EXPECT(mmi_validate_buffers(&view, &read_options, NULL), MMI_OK);
    EXPECT(mmi_validate_buffers(NULL, NULL, NULL), MMI_ERROR_NULL_POINTER);
    /* ... and refuses broken ones. */
    {
        mmi_buffers_view broken = view;
        broken.records_len = records_len - 1;
        EXPECT(mmi_validate_buffers(&broken, NULL, NULL), MMI_ERROR_MALFORMED);
        broken = view;
        broken.data_len = data_len - 1;
        EXPECT(mmi_validate_buffers(&broken, NULL, NULL), MMI_ERROR_MALFORMED);
        broken = view;
        broken.index_width_bits = 24;
        EXPECT(mmi_validate_buffers(&broken, NULL, NULL), MMI_ERROR_INVALID_ENUM);
        broken = view;
        broken.data = NULL;
        EXPECT(mmi_validate_buffers(&broken, NULL, NULL), MMI_ERROR_NULL_POINTER);
    }

    /* The verifier finds the bake sound... */
    view.usage_counts = NULL;
    EXPECT(mmi_verify(&mesh, &view, &report, witnesses, 4), MMI_OK);
    CHECK(report.triangles == 2 && report.triangles_checked == 2);
    CHECK(report.contradictions == 0 && report.known > 0 && report.witnesses_written == 0);
    EXPECT(mmi_verify(&mesh, &view, NULL, NULL, 0), MMI_ERROR_NULL_POINTER);
    EXPECT(mmi_verify(&mesh, &view, &report, NULL, 4), MMI_ERROR_NULL_POINTER);
    /* The alpha factor is verified as it is baked: a quarter of any texel
     * is below the cutoff, so every opaque micro-triangle is contradicted. */
    bad = mesh;
    bad.material.alpha_factor = 0.25f;
    EXPECT(mmi_verify(&bad, &view, &report, NULL, 0), MMI_OK);
    CHECK(report.contradictions == stats.counts[MMI_STATE_OPAQUE]);
    {
        mmi_buffers_view short_indices = view;
        short_indices.indices_len = 4;
        EXPECT(mmi_verify(&mesh, &short_indices, &report, NULL, 0), MMI_ERROR_LENGTH);
    }
    /* ... and a wrong one unsound, with witnesses: every index says
     * "opaque" (special index -2), which the transparent columns deny. */
    for (i = 0; i < 8; i += 4) {
        flipped[i] = 0xfe;
        flipped[i + 1] = 0xff;
        flipped[i + 2] = 0xff;
        flipped[i + 3] = 0xff;
    }
    view.indices = flipped;
    view.indices_len = 8;
    EXPECT(mmi_verify(&mesh, &view, &report, witnesses, 1), MMI_OK);
    CHECK(report.contradictions >= 1 && report.witnesses_written == 1);
    CHECK(witnesses[0].state == MMI_STATE_OPAQUE && witnesses[0].has_texel == 1);
    /* The named texel is one of the transparent columns (x >= 3), also
     * under the default GPU model, whose witness may lie just left of it. */
    CHECK(witnesses[0].texel_x >= 3 && witnesses[0].texel_alpha == 0.0);
    EXPECT(mmi_verify(&mesh, &view, &report, NULL, 0), MMI_OK);
    CHECK(report.witnesses_written == 0 && report.contradictions >= 1);
    /* The same under the exact model, named explicitly; an unknown model
     * is refused. */
    EXPECT(mmi_verify_with_model(&mesh, &view, MMI_MODEL_EXACT, &report, witnesses, 1), MMI_OK);
    CHECK(report.contradictions >= 1 && witnesses[0].texel_x >= 3 &&
          witnesses[0].texel_alpha == 0.0);
    EXPECT(mmi_verify_with_model(&mesh, &view, 2, &report, NULL, 0), MMI_ERROR_INVALID_ENUM);
    /* And by bake options: the defaults name the texture unit; a field out
     * of range is refused, NULL options too. */
    {
        mmi_bake_options judge;
        EXPECT(mmi_bake_options_default(&judge), MMI_OK);
        CHECK(judge.subtexel_bits == 8 && judge.interpolation == MMI_INTERPOLATION_F32 &&
              judge.linear_rule == MMI_LINEAR_VALUE && judge.filter_error == 1.0f / 128.0f);
        EXPECT(mmi_verify_with_options(&mesh, &view, &judge, &report, witnesses, 1), MMI_OK);
        CHECK(report.contradictions >= 1 && witnesses[0].texel_x >= 3);
        judge.subtexel_bits = 3;
        EXPECT(mmi_verify_with_options(&mesh, &view, &judge, &report, NULL, 0),
               MMI_ERROR_INVALID_ARGUMENT);
        EXPECT(mmi_verify_with_options(&mesh, &view, NULL, &report, NULL, 0),
               MMI_ERROR_NULL_POINTER);
    }
    /* Vertex alpha too: with alpha 0 everywhere nothing is opaque, and
     * both "opaque" triangles are contradicted. */
    bad = mesh;
    bad.vertex_alpha = zero_alpha;
    EXPECT(mmi_verify(&bad, &view, &report, NULL, 0), MMI_OK);
    CHECK(report.contradictions == 2);

    mmi_bake_result_free(result);
    mmi_bake_result_free(NULL);

    /* Vertex alpha 0 at every vertex: 0 times any texel is below the
     * cutoff, so every micro-triangle is transparent. */
    bad = mesh;
    bad.vertex_alpha = zero_alpha;
    options.level = 2;
    EXPECT(mmi_bake(&bad, 1, &options, &result), MMI_OK);
    EXPECT(mmi_bake_result_stats(result, &stats), MMI_OK);
    CHECK(stats.counts[MMI_STATE_TRANSPARENT] == 2 * 16 && stats.counts[MMI_STATE_OPAQUE] == 0);
    mmi_bake_result_free(result);
    /* A texture transform: u' = u / 4 + 1/16 stays in the opaque columns
     * 0..2 (u' < 3/8), so every micro-triangle is opaque; a rotation
     * beyond 65536 radians is refused. */
    {
        mmi_uv_transform transform = {{0.0625f, 0.0f}, 0.0f, {0.25f, 1.0f}};
        bad = mesh;
        bad.uv_transform = &transform;
        EXPECT(mmi_bake(&bad, 1, &options, &result), MMI_OK);
        EXPECT(mmi_bake_result_stats(result, &stats), MMI_OK);
        CHECK(stats.counts[MMI_STATE_OPAQUE] == 2 * 16);
        mmi_bake_result_free(result);
        transform.rotation = 1e6f;
        EXPECT(mmi_bake(&bad, 1, &options, &result), MMI_ERROR_INVALID_ARGUMENT);
        CHECK(result == NULL);
    }
    /* The exact model, and a model out of range. */
    options.model = MMI_MODEL_EXACT;
    EXPECT(mmi_bake(&mesh, 1, &options, &result), MMI_OK);
    mmi_bake_result_free(result);
    bad_options = options;
    bad_options.model = 2;
    EXPECT(mmi_bake(&mesh, 1, &bad_options, &result), MMI_ERROR_INVALID_ENUM);
    CHECK(result == NULL);
    options.model = MMI_MODEL_GPU_BINARY32;

    /* A float texture, tightly packed, 2-state at a fixed level. */
    for (i = 0; i < 64; ++i) {
        wide_texels[i] = (i % 8) < 3 ? 1.0f : 0.0f;
    }
    mesh.texture.texels = wide_texels;
    mesh.texture.row_pitch = 0;
    mesh.texture.format = MMI_TEXEL_F32;
    options.level = 3;
    options.format = MMI_FORMAT_2_STATE;
    EXPECT(mmi_bake(&mesh, 1, &options, &result), MMI_OK);
    EXPECT(mmi_bake_result_stats(result, &stats), MMI_OK);
    CHECK(stats.level_count == 4 && stats.levels[3] == 2);
    mmi_bake_result_free(result);
}

/* `element`-byte elements of `in` laid `stride` bytes apart into `out`,
 * the gaps filled with junk, ending right after the last element; the
 * length written. */
static size_t spread(const uint8_t *in, size_t len, size_t element, size_t stride, uint8_t *out) {
    size_t n = 0, i, k;
    for (i = 0; i < len; i += element) {
        if (i > 0) {
            for (k = element; k < stride; ++k) {
                out[n++] = (uint8_t)(0xa5 ^ k);
            }
        }
        memcpy(out + n, in + i, element);
        n += element;
    }
    return n;
}

/* No mixed special indices, and strided buffers: the quad's texture with
 * three triangles, the third inside the transparent columns (a special
 * index unless the option is on). */
static void no_mixed_and_strides(void) {
    static const float uvs[] = {0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1.0f, 1.0f, 1.0f, 0.0f,
                                1.0f, 1.0f, 0.0f, 0.5f, 0.2f, 0.9f, 0.2f, 0.5f, 0.6f};
    mmi_mesh mesh;
    mmi_bake_options options;
    mmi_bake_result *result = NULL;
    mmi_buffers_view tight, strided;
    mmi_buffers_info tight_info, strided_info;
    mmi_verify_report tight_report, strided_report;
    const uint8_t *data = NULL, *records = NULL;
    size_t data_len = 0, records_len = 0, len = 0, plain_records = 0;
    uint8_t indices[12], spread_records[16 * 8], spread_indices[12 * 3];
    uint32_t mixed = 9;
    int16_t narrow[3];
    int i;

    quad_mesh(&mesh);
    mesh.uvs = uvs;
    mesh.uv_stride = 0;
    mesh.vertex_count = 9;
    mesh.indices = NULL;
    mesh.index_count = 0;
    EXPECT(mmi_bake_options_default(&options), MMI_OK);
    CHECK(options.no_mixed_special_indices == 0);
    options.level = 3;

    /* Default: the third triangle is special index -1, beside records. */
    EXPECT(mmi_bake(&mesh, 1, &options, &result), MMI_OK);
    EXPECT(mmi_bake_result_is_mixed(result, 0, &mixed), MMI_OK);
    CHECK(mixed == 1);
    EXPECT(mmi_bake_result_indices(result, 0, 16, (uint8_t *)narrow, sizeof narrow, &len), MMI_OK);
    CHECK(len == 6 && narrow[2] == -1);
    EXPECT(mmi_bake_result_triangle_records(result, &records, &plain_records), MMI_OK);
    EXPECT(mmi_bake_result_is_mixed(result, 1, &mixed), MMI_ERROR_INVALID_ARGUMENT);
    EXPECT(mmi_bake_result_is_mixed(result, 0, NULL), MMI_ERROR_NULL_POINTER);
    EXPECT(mmi_bake_result_is_mixed(NULL, 0, &mixed), MMI_ERROR_NULL_POINTER);
    mmi_bake_result_free(result);

    /* On: a shared level-0 record instead, and not mixed. */
    options.no_mixed_special_indices = 1;
    EXPECT(mmi_bake(&mesh, 1, &options, &result), MMI_OK);
    EXPECT(mmi_bake_result_is_mixed(result, 0, &mixed), MMI_OK);
    CHECK(mixed == 0);
    EXPECT(mmi_bake_result_data(result, &data, &data_len), MMI_OK);
    EXPECT(mmi_bake_result_triangle_records(result, &records, &records_len), MMI_OK);
    CHECK(records_len == plain_records + 8 && records_len <= 16 * 8 / 2);
    EXPECT(mmi_bake_result_indices(result, 0, 32, indices, sizeof indices, &len), MMI_OK);
    CHECK(len == 12);
    for (i = 0; i < 3; ++i) {
        CHECK(indices[4 * i + 3] < 0x80); /* no special index */
    }

    /* The tight view verifies sound... */
    memset(&tight, 0, sizeof tight);
    tight.data = data;
    tight.data_len = data_len;
    tight.records = records;
    tight.records_len = records_len;
    tight.indices = indices;
    tight.indices_len = len;
    tight.index_width_bits = 32;
    EXPECT(mmi_validate_buffers(&tight, NULL, &tight_info), MMI_OK);
    CHECK(tight_info.indices == 3 && tight_info.special_indices == 0);
    EXPECT(mmi_verify(&mesh, &tight, &tight_report, NULL, 0), MMI_OK);
    CHECK(tight_report.triangles_checked == 3 && tight_report.contradictions == 0);

    /* ... and the same buffers at record stride 16 and index stride 12,
     * junk in the gaps, read and verify the same. */
    strided = tight;
    strided.records = spread_records;
    strided.records_len = spread(records, records_len, 8, 16, spread_records);
    strided.record_stride = 16;
    strided.indices = spread_indices;
    strided.indices_len = spread(indices, len, 4, 12, spread_indices);
    strided.index_stride = 12;
    CHECK(strided.records_len == 16 * (records_len / 8) - 8 && strided.indices_len == 28);
    memset(&strided_info, 0xff, sizeof strided_info);
    EXPECT(mmi_validate_buffers(&strided, NULL, &strided_info), MMI_OK);
    CHECK(memcmp(&strided_info, &tight_info, sizeof tight_info) == 0);
    memset(&strided_report, 0xff, sizeof strided_report);
    EXPECT(mmi_verify(&mesh, &strided, &strided_report, NULL, 0), MMI_OK);
    CHECK(memcmp(&strided_report, &tight_report, sizeof tight_report) == 0);
    /* Read tightly, the junk is refused. */
    {
        mmi_buffers_view as_tight = strided;
        as_tight.record_stride = 0;
        as_tight.index_stride = 0;
        EXPECT(mmi_validate_buffers(&as_tight, NULL, NULL), MMI_ERROR_MALFORMED);
    }

    /* Strides the APIs do not allow: refused before any byte is read. */
    {
        mmi_buffers_view bad = strided;
        bad.record_stride = 4;
        EXPECT(mmi_validate_buffers(&bad, NULL, NULL), MMI_ERROR_INVALID_ARGUMENT);
        CHECK(says("record stride 4"));
        EXPECT(mmi_verify(&mesh, &bad, &strided_report, NULL, 0), MMI_ERROR_INVALID_ARGUMENT);
        bad.record_stride = 18;
        EXPECT(mmi_validate_buffers(&bad, NULL, NULL), MMI_ERROR_INVALID_ARGUMENT);
        bad = strided;
        bad.index_stride = 6;
        EXPECT(mmi_validate_buffers(&bad, NULL, NULL), MMI_ERROR_INVALID_ARGUMENT);
        CHECK(says("index stride 6"));
        EXPECT(mmi_verify(&mesh, &bad, &strided_report, NULL, 0), MMI_ERROR_INVALID_ARGUMENT);
        /* Without indices the index stride is not looked at. */
        bad.indices = NULL;
        EXPECT(mmi_validate_buffers(&bad, NULL, NULL), MMI_OK);
        /* A strided length that is neither whole strides nor ends after
         * an element is malformed. */
        bad = strided;
        bad.records_len -= 1;
        EXPECT(mmi_validate_buffers(&bad, NULL, NULL), MMI_ERROR_MALFORMED);
    }
    mmi_bake_result_free(result);
}

static void tree(void) {
    uint8_t states[16], decoded[16], state = 9, bytes[256], small[4];
    size_t len = 0, i;
    uint32_t index = 0;
    mmi_tree *t = NULL, *back = NULL;
    mmi_tree_info info;

    for (i = 0; i < 16; ++i) {
        states[i] = (i < 4) ? MMI_STATE_OPAQUE : (i % 2 ? MMI_STATE_TRANSPARENT : MMI_STATE_UNKNOWN_OPAQUE);
    }
    EXPECT(mmi_tree_encode(MMI_TREE_LEVEL_ORDER, 2, MMI_FORMAT_4_STATE, states, 16, &t), MMI_OK);
    for (i = 0; i < 16; ++i) {
        EXPECT(mmi_tree_get(t, i, &state), MMI_OK);
        CHECK(state == states[i]);
    }
    EXPECT(mmi_tree_get(t, 16, &state), MMI_ERROR_INVALID_ARGUMENT);
    EXPECT(mmi_tree_get(NULL, 0, &state), MMI_ERROR_NULL_POINTER);
    EXPECT(mmi_tree_get(t, 0, NULL), MMI_ERROR_NULL_POINTER);
    EXPECT(mmi_index_f32(0.1f, 0.7f, 2, &index), MMI_OK);
    EXPECT(mmi_tree_get_f32(t, 0.1f, 0.7f, &state), MMI_OK);
    CHECK(state == states[index]);
    EXPECT(mmi_tree_info_get(t, &info), MMI_OK);
    CHECK(info.layout == MMI_TREE_LEVEL_ORDER && info.level == 2 && info.format == MMI_FORMAT_4_STATE);
    CHECK(info.leaf_count == 13); /* the opaque first quarter merged */

    EXPECT(mmi_tree_to_bytes(t, NULL, 0, &len), MMI_OK);
    CHECK(len > 24 && len < sizeof bytes);
    EXPECT(mmi_tree_to_bytes(t, small, sizeof small, &len), MMI_ERROR_BUFFER_TOO_SMALL);
    EXPECT(mmi_tree_to_bytes(t, bytes, sizeof bytes, &len), MMI_OK);
    EXPECT(mmi_tree_from_bytes(bytes, len, &back), MMI_OK);
    EXPECT(mmi_tree_decode(back, NULL, 0, &len), MMI_OK);
    CHECK(len == 16);
    EXPECT(mmi_tree_decode(back, decoded, 15, &len), MMI_ERROR_BUFFER_TOO_SMALL);
    EXPECT(mmi_tree_decode(back, decoded, sizeof decoded, &len), MMI_OK);
    CHECK(memcmp(decoded, states, 16) == 0);
    mmi_tree_free(back);
    back = NULL;
    /* Malformed bytes: truncated, a changed magic, nothing. */
    EXPECT(mmi_tree_to_bytes(t, bytes, sizeof bytes, &len), MMI_OK);
    EXPECT(mmi_tree_from_bytes(bytes, len - 1, &back), MMI_ERROR_MALFORMED);
    CHECK(back == NULL);
    bytes[0] ^= 1;
    EXPECT(mmi_tree_from_bytes(bytes, len, &back), MMI_ERROR_MALFORMED);
    EXPECT(mmi_tree_from_bytes(NULL, 0, &back), MMI_ERROR_MALFORMED);
    EXPECT(mmi_tree_from_bytes(NULL, 5, &back), MMI_ERROR_NULL_POINTER);
    mmi_tree_free(t);
    mmi_tree_free(NULL);

    /* The paper's layout agrees; misuse. */
    EXPECT(mmi_tree_encode(MMI_TREE_PAPER, 2, MMI_FORMAT_4_STATE, states, 16, &t), MMI_OK);
    for (i = 0; i < 16; ++i) {
        EXPECT(mmi_tree_get(t, i, &state), MMI_OK);
        CHECK(state == states[i]);
    }
    EXPECT(mmi_tree_to_bytes(t, bytes, sizeof bytes, &len), MMI_OK);
    EXPECT(mmi_tree_from_bytes(bytes, len, &back), MMI_OK);
    EXPECT(mmi_tree_info_get(back, &info), MMI_OK);
    CHECK(info.layout == MMI_TREE_PAPER);
    mmi_tree_free(back);
    mmi_tree_free(t);
    t = NULL;
    EXPECT(mmi_tree_encode(MMI_TREE_PAPER, 2, MMI_FORMAT_2_STATE, states, 16, &t),
           MMI_ERROR_INVALID_ARGUMENT);
    CHECK(t == NULL);
    EXPECT(mmi_tree_encode(MMI_TREE_PAPER, 2, MMI_FORMAT_4_STATE, states, 15, &t), MMI_ERROR_LENGTH);
    EXPECT(mmi_tree_encode(7, 2, MMI_FORMAT_4_STATE, states, 16, &t), MMI_ERROR_INVALID_ENUM);
    EXPECT(mmi_tree_encode(MMI_TREE_PAPER, 2, 0, states, 16, &t), MMI_ERROR_INVALID_ENUM);
    EXPECT(mmi_tree_encode(MMI_TREE_PAPER, 17, MMI_FORMAT_4_STATE, states, 16, &t),
           MMI_ERROR_INVALID_LEVEL);
    EXPECT(mmi_tree_encode(MMI_TREE_PAPER, 2, MMI_FORMAT_4_STATE, NULL, 16, &t),
           MMI_ERROR_NULL_POINTER);
    states[3] = 4;
    EXPECT(mmi_tree_encode(MMI_TREE_PAPER, 2, MMI_FORMAT_4_STATE, states, 16, &t),
           MMI_ERROR_INVALID_ENUM);
    EXPECT(mmi_tree_encode(MMI_TREE_PAPER, 2, MMI_FORMAT_4_STATE, states, 16, NULL),
           MMI_ERROR_NULL_POINTER);
}

int main(void) {
    CHECK(mmi_version() == MICROMAP_INDEX_VERSION);
    CHECK(strcmp(mmi_version_string(), MICROMAP_INDEX_VERSION_STRING) == 0);
    layout();
    index_and_inverse();
    bake_and_verify();
    no_mixed_and_strides();
    tree();
    if (failures) {
        fprintf(stderr, "%d of %d checks failed\n", failures, checks);
        return 1;
    }
    printf("ok %d checks\n", checks);
    return 0;
}
