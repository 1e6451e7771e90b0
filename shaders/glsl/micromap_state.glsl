// micromap_state.glsl: the flat opacity-micromap lookup over the buffers the
// baker writes (`micromap-index bake`; the layout Vulkan EXT/KHR, DXR 1.2 and
// the glTF draft read): the state of one micro-triangle of one triangle.
//
// Buffers, declared by the including shader as uint arrays (little endian,
// each file's bytes zero-padded to a multiple of 4), named through macros
// defined before the #include:
//   MMI_DATA(i), MMI_DATA_LENGTH            micromap-data.bin: packed states,
//       least-significant bit first, 1 bit (2-state) or 2 bits (4-state).
//   MMI_TRIANGLES(i), MMI_TRIANGLES_LENGTH  micromap-triangles.bin: 8-byte
//       records; word 2r = dataOffset (bytes), word 2r + 1 =
//       subdivisionLevel | format << 16.
//   MMI_INDICES(i), MMI_INDICES_LENGTH      micromap-indices.bin: one index
//       per triangle at `index_width` bytes (1, 2 or 4); the top four
//       patterns are the special indices -1..-4, -5 is reserved.
// e.g.  layout(std430, binding = 0) readonly buffer Data { uint data[]; };
//       #define MMI_DATA(i) data[i]
//       #define MMI_DATA_LENGTH uint(data.length())
//
// Functions
//   uint mmi_record_state(uint record, uint micro_triangle)
//   uint mmi_micromap_state(uint index_width, uint triangle_id, uint micro_triangle)
//   uint mmi_micromap_state_at(uint index_width, uint triangle_id, float u, float v)
//       (the micro-triangle the Vulkan reference index picks for (u, v))
//   uint mmi_record_level(uint record)   (MMI_LEVEL_INVALID if malformed)
//   uint mmi_triangle_record(uint index_width, uint triangle_id)
//       (a record number, MMI_TRIANGLE_SPECIAL | state, MMI_TRIANGLE_INVALID)
// Return: the state, numbered as micromap_index::micromap::State (0
// transparent, 1 opaque, 2 unknown-transparent, 3 unknown-opaque); a 2-state
// map gives 0 or 1. A special index gives its state for every micro-triangle.
// Levels 0..=12 (MMI_MAX_LEVEL). (`triangle` is a keyword in HLSL, hence
// `triangle_id`.)
//
// Malformed input is total: every read is bounds-checked against the
// *_LENGTH macros, nothing out of bounds is read, and MMI_STATE_INVALID (4)
// is returned for: an index width other than 1, 2, 4; a triangle whose index
// lies past the index buffer; the reserved index -5; a record number past the
// records; a record with a format other than 1, 2 or a level above 12; a
// micro_triangle not below 4^level; a map whose bytes (max(1, 4^level *
// bits / 8) from dataOffset) do not lie within the data buffer. What is not
// checked: triangle ids covered by the index buffer's zero padding (they
// read record 0), overlapping maps, nonzero unused bits (never read).
#ifndef MICROMAP_STATE_GLSL
#define MICROMAP_STATE_GLSL

#include "micromap_constants.glsl"
#include "micromap_index.glsl"

// The level of a record, or MMI_LEVEL_INVALID when the record is missing or
// malformed (format or level out of range).
#define MMI_LEVEL_INVALID 0xffffffffu
uint mmi_record_level(uint record)
{
    if (record >= MMI_TRIANGLES_LENGTH / 2u) return MMI_LEVEL_INVALID;
    uint shape = MMI_TRIANGLES(2u * record + 1u);
    uint level = shape & 0xffffu;
    uint format = shape >> 16u;
    if (level > MMI_MAX_LEVEL) return MMI_LEVEL_INVALID;
    if (format != MMI_FORMAT_2_STATE && format != MMI_FORMAT_4_STATE) return MMI_LEVEL_INVALID;
    return level;
}

uint mmi_record_state(uint record, uint micro_triangle)
{
    uint level = mmi_record_level(record);
    if (level == MMI_LEVEL_INVALID) return MMI_STATE_INVALID;
    if (micro_triangle >= (1u << (2u * level))) return MMI_STATE_INVALID;
    uint offset = MMI_TRIANGLES(2u * record);
    uint bits = MMI_TRIANGLES(2u * record + 1u) >> 16u; // format 1 or 2 = bits per state
    // The map's bits counted from the word holding its first byte: at most
    // 3 * 8 + 2 * 4^12 < 2^26, no overflow.
    uint first = (offset & 3u) * 8u;
    uint last_bit = first + max(8u, bits << (2u * level)) - 1u;
    uint base = offset >> 2u;
    if (base + (last_bit >> 5u) >= MMI_DATA_LENGTH) return MMI_STATE_INVALID;
    uint bit = first + micro_triangle * bits;
    // A state never straddles a word (bit is a multiple of its width).
    uint word = MMI_DATA(base + (bit >> 5u));
    return (word >> (bit & 31u)) & ((1u << bits) - 1u);
}

// What a triangle's entry in the index buffer says: a record number (below
// 2^30), MMI_TRIANGLE_SPECIAL | state for a special index, or
// MMI_TRIANGLE_INVALID.
#define MMI_TRIANGLE_SPECIAL 0xfffffff0u
#define MMI_TRIANGLE_INVALID 0xffffffffu
uint mmi_triangle_record(uint index_width, uint triangle_id)
{
    if (index_width != 1u && index_width != 2u && index_width != 4u) return MMI_TRIANGLE_INVALID;
    // The byte offset cannot wrap for any triangle a buffer can hold; larger
    // ids fail the length check.
    if (triangle_id >= 0x40000000u) return MMI_TRIANGLE_INVALID;
    uint at = triangle_id * index_width;
    if ((at >> 2u) >= MMI_INDICES_LENGTH) return MMI_TRIANGLE_INVALID;
    uint all_ones = index_width == 4u ? 0xffffffffu : (1u << (8u * index_width)) - 1u;
    uint raw = (MMI_INDICES(at >> 2u) >> (8u * (at & 3u))) & all_ones;
    uint from_top = all_ones - raw; // 0 for -1, ..., 3 for -4, 4 for -5
    if (from_top <= 3u) return MMI_TRIANGLE_SPECIAL | from_top;
    // -5 (reserved), or a record no buffer of 2^32 bytes can hold.
    if (from_top == 4u || raw >= 0x40000000u) return MMI_TRIANGLE_INVALID;
    return raw;
}

uint mmi_micromap_state(uint index_width, uint triangle_id, uint micro_triangle)
{
    uint record = mmi_triangle_record(index_width, triangle_id);
    if (record == MMI_TRIANGLE_INVALID) return MMI_STATE_INVALID;
    if (record >= MMI_TRIANGLE_SPECIAL) return record & 3u;
    return mmi_record_state(record, micro_triangle);
}

uint mmi_micromap_state_at(uint index_width, uint triangle_id, float u, float v)
{
    uint record = mmi_triangle_record(index_width, triangle_id);
    if (record == MMI_TRIANGLE_INVALID) return MMI_STATE_INVALID;
    if (record >= MMI_TRIANGLE_SPECIAL) return record & 3u;
    uint level = mmi_record_level(record);
    if (level == MMI_LEVEL_INVALID) return MMI_STATE_INVALID;
    return mmi_record_state(record, BarycentricsToSpaceFillingCurveIndex(u, v, level));
}

#endif // MICROMAP_STATE_GLSL
