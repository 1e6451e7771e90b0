/* Conformance driver: runs an implementation of
       uint32_t BarycentricsToSpaceFillingCurveIndex(float u, float v, uint32_t level);
   (linked from another file, e.g. implementation.c) on the cases of a
   binary32 vector file and prints one answer line per case for
   `micromap-index check`:
       {"id": N, "index": I}        or, above --max-level,
       {"id": N, "unsupported": true}

   Input (a file argument or stdin), either form, line by line:
     * a vector file as the generator writes it (reference/vectors/spec-f32.json:
       one case per line, fields in schema order); header lines are skipped;
     * or simple lines "ID U_BITS V_BITS LEVEL" (decimal id, hex bits, decimal level).

   Build and run (see build.sh):
       cc -O2 -std=c99 -ffp-contract=off -fno-fast-math \
          driver.c implementation.c -o driver
       ./driver [--max-level N] reference/vectors/spec-f32.json > answers.jsonl
       micromap-index check --vectors reference/vectors/spec-f32.json --answers answers.jsonl

   Exit status: 0, or 2 for a usage error, an unreadable file or a line it
   cannot read (named on stderr). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

uint32_t BarycentricsToSpaceFillingCurveIndex(float u, float v, uint32_t level);

static float from_bits(uint32_t bits)
{
    float x;
    memcpy(&x, &bits, sizeof x); /* reinterpret, never convert */
    return x;
}

int main(int argc, char **argv)
{
    unsigned long max_level = 32;
    const char *path = NULL;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--max-level") == 0 && i + 1 < argc) {
            char *end;
            max_level = strtoul(argv[++i], &end, 10);
            if (*end != '\0') {
                fprintf(stderr, "driver: --max-level needs a number\n");
                return 2;
            }
        } else if (!path && argv[i][0] != '-') {
            path = argv[i];
        } else {
            fprintf(stderr, "usage: %s [--max-level N] [FILE]\n", argv[0]);
            return 2;
        }
    }
    FILE *in = path ? fopen(path, "r") : stdin;
    if (!in) {
        perror(path);
        return 2;
    }
    char line[4096];
    unsigned long line_number = 0, answered = 0;
    while (fgets(line, sizeof line, in)) {
        line_number++;
        unsigned long long id;
        unsigned u_bits, v_bits, level;
        const char *p = line + strspn(line, " \t");
        int fields;
        if (p[0] == '{' && strstr(p, "\"id\"")) {
            fields = sscanf(p, "{\"id\":%llu,\"u\":\"0x%8x\",\"v\":\"0x%8x\",\"level\":%u",
                            &id, &u_bits, &v_bits, &level);
        } else if (p[0] >= '0' && p[0] <= '9') {
            fields = sscanf(p, "%llu %x %x %u", &id, &u_bits, &v_bits, &level);
        } else {
            continue; /* a header or closing line of a vector file, or blank */
        }
        if (fields != 4) {
            fprintf(stderr, "driver: %s: line %lu: cannot read a case\n",
                    path ? path : "stdin", line_number);
            return 2;
        }
        if (level > max_level || level > 31) {
            printf("{\"id\": %llu, \"unsupported\": true}\n", id);
        } else {
            uint32_t index = BarycentricsToSpaceFillingCurveIndex(
                from_bits(u_bits), from_bits(v_bits), level);
            printf("{\"id\": %llu, \"index\": %lu}\n", id, (unsigned long)index);
        }
        answered++;
    }
    if (path) fclose(in);
    if (answered == 0) {
        fprintf(stderr, "driver: no case read\n");
        return 2;
    }
    return 0;
}
