/*
 * bake_grid: bakes an alpha texture and a UV triangle list with the C API
 * and writes the buffers `micromap-index bake` writes:
 *
 *   bake_grid TEXTURE.raw UVS.bin LEVEL|auto OUTDIR
 *
 * C has no PNG decoder, so the inputs are raw files (native endian):
 *   TEXTURE.raw  uint32 width, height, format (MMI_TEXEL_*), row pitch in
 *                bytes; then pitch * height bytes of texels
 *   UVS.bin      uint32 vertex count, floats per vertex (>= 2); then the
 *                vertices, (u, v) first; vertices 3t..3t+2 are triangle t
 * make_inputs.py, next to this file, writes them from a PNG and a
 * TRIS.json (Python's standard library only). Writes
 * OUTDIR/micromap-data.bin, micromap-triangles.bin, micromap-indices.bin
 * (32-bit) and micromap-usage.bin, and prints the statistics: the bytes
 * `micromap-index bake --texture TEXTURE.png --triangles TRIS.json --level
 * LEVEL` writes (bindings/c/tests/c_api.rs checks it on the committed
 * assets).
 *
 * From the repository's root:
 *   cargo build --release -p micromap-index-capi
 *   cc -std=c99 -Ibindings/c/include bindings/c/examples/bake_grid.c \
 *      target/release/libmicromap_index_capi.a -lpthread -ldl -lm -o bake_grid
 *   python3 bindings/c/examples/make_inputs.py \
 *      assets/crytek-sponza/sponza_thorn.png assets/crytek-sponza/grid.tris.json in
 *   mkdir -p out && ./bake_grid in/texture.raw in/uvs.bin 4 out
 */
#include "micromap_index.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void *read_file(const char *path, size_t *len) {
    FILE *f = fopen(path, "rb");
    void *data = NULL;
    long size;
    if (!f) {
        return NULL;
    }
    if (fseek(f, 0, SEEK_END) == 0 && (size = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0) {
        data = malloc((size_t)size + 1);
        if (data && fread(data, 1, (size_t)size, f) != (size_t)size) {
            free(data);
            data = NULL;
        }
        *len = (size_t)size;
    }
    fclose(f);
    return data;
}

static int write_file(const char *dir, const char *name, const uint8_t *data, size_t len) {
    char path[4096];
    FILE *f;
    int ok;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    f = fopen(path, "wb");
    if (!f) {
        fprintf(stderr, "cannot write %s\n", path);
        return 0;
    }
    ok = (len == 0 || fwrite(data, 1, len, f) == len);
    ok = (fclose(f) == 0) && ok;
    return ok;
}

static uint32_t word(const uint8_t *p) {
    uint32_t w;
    memcpy(&w, p, sizeof w);
    return w;
}

/* Reports a failed call and returns 1. */
static int fail(const char *what, mmi_result r) {
    fprintf(stderr, "%s: error %d: %s\n", what, (int)r, mmi_last_error_message());
    return 1;
}

int main(int argc, char **argv) {
    size_t texture_len = 0, uvs_len = 0, len = 0;
    uint8_t *texture_file, *uvs_file, *indices = NULL;
    const uint8_t *data;
    mmi_mesh mesh;
    mmi_bake_options options;
    mmi_bake_result *result = NULL;
    mmi_bake_stats stats;
    mmi_result r;
    uint32_t vertex_count, stride;
    float *uvs;
    int status = 1;

    if (argc != 5) {
        fprintf(stderr, "usage: %s TEXTURE.raw UVS.bin LEVEL|auto OUTDIR\n", argv[0]);
        return 2;
    }
    if (mmi_version() != MICROMAP_INDEX_VERSION) {
        fprintf(stderr, "header %s, library %s\n", MICROMAP_INDEX_VERSION_STRING,
                mmi_version_string());
        return 1;
    }
    texture_file = (uint8_t *)read_file(argv[1], &texture_len);
    uvs_file = (uint8_t *)read_file(argv[2], &uvs_len);
    if (!texture_file || !uvs_file || texture_len < 16 || uvs_len < 8) {
        fprintf(stderr, "cannot read the inputs\n");
        return 1;
    }
    vertex_count = word(uvs_file);
    stride = word(uvs_file + 4);
    /* The floats, copied to aligned memory. */
    uvs = (float *)malloc(uvs_len - 8 + sizeof(float));
    if (!uvs) {
        return 1;
    }
    memcpy(uvs, uvs_file + 8, uvs_len - 8);

    memset(&mesh, 0, sizeof mesh);
    mesh.texture.width = word(texture_file);
    mesh.texture.height = word(texture_file + 4);
    mesh.texture.format = word(texture_file + 8);
    mesh.texture.row_pitch = word(texture_file + 12);
    mesh.texture.texels = texture_file + 16;
    if ((r = mmi_material_default(&mesh.material)) != MMI_OK) {
        return fail("mmi_material_default", r);
    }
    mesh.uvs = uvs;
    mesh.vertex_count = vertex_count;
    mesh.uv_stride = (size_t)stride * sizeof(float);
    mesh.indices = NULL;

    if ((r = mmi_bake_options_default(&options)) != MMI_OK) {
        return fail("mmi_bake_options_default", r);
    }
    if (strcmp(argv[3], "auto") != 0) {
        options.level = (uint32_t)strtoul(argv[3], NULL, 10);
    }
    if ((r = mmi_bake(&mesh, 1, &options, &result)) != MMI_OK) {
        return fail("mmi_bake", r);
    }

    if ((r = mmi_bake_result_data(result, &data, &len)) != MMI_OK) {
        fail("mmi_bake_result_data", r);
        goto done;
    }
    if (!write_file(argv[4], "micromap-data.bin", data, len)) {
        goto done;
    }
    if ((r = mmi_bake_result_triangle_records(result, &data, &len)) != MMI_OK) {
        fail("mmi_bake_result_triangle_records", r);
        goto done;
    }
    if (!write_file(argv[4], "micromap-triangles.bin", data, len)) {
        goto done;
    }
    if ((r = mmi_bake_result_usage_counts(result, &data, &len)) != MMI_OK) {
        fail("mmi_bake_result_usage_counts", r);
        goto done;
    }
    if (!write_file(argv[4], "micromap-usage.bin", data, len)) {
        goto done;
    }
    /* The index buffer: its size first, then the bytes. */
    r = mmi_bake_result_indices(result, MMI_ALL_GEOMETRIES, 32, NULL, 0, &len);
    if (r != MMI_OK) {
        fail("mmi_bake_result_indices (size)", r);
        goto done;
    }
    indices = (uint8_t *)malloc(len + 1);
    if (!indices) {
        goto done;
    }
    r = mmi_bake_result_indices(result, MMI_ALL_GEOMETRIES, 32, indices, len, &len);
    if (r != MMI_OK) {
        fail("mmi_bake_result_indices", r);
        goto done;
    }
    if (!write_file(argv[4], "micromap-indices.bin", indices, len)) {
        goto done;
    }
    if ((r = mmi_bake_result_stats(result, &stats)) != MMI_OK) {
        fail("mmi_bake_result_stats", r);
        goto done;
    }
    printf("triangles %llu micromaps %llu special %llu bytes %llu known %.6f\n",
           (unsigned long long)stats.triangles, (unsigned long long)stats.micromaps,
           (unsigned long long)stats.special_index_triangles,
           (unsigned long long)stats.bytes_flat, stats.known_fraction);
    status = 0;
done:
    free(indices);
    mmi_bake_result_free(result);
    free(uvs);
    free(uvs_file);
    free(texture_file);
    return status;
}
