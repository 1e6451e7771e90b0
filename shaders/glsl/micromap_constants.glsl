// micromap_constants.glsl: the numbers every lookup in shaders/glsl shares.
// They equal the library's (micromap_index::micromap::State, Format, the
// special indices, the succinct byte format); crates/lab/tests/shaders.rs
// parses these #define lines and compares them with the Rust constants.
//
// Contract: definitions only; reads no memory.
#ifndef MICROMAP_CONSTANTS_GLSL
#define MICROMAP_CONSTANTS_GLSL

// States (State::bits()): what every lookup returns.
#define MMI_STATE_TRANSPARENT 0u
#define MMI_STATE_OPAQUE 1u
#define MMI_STATE_UNKNOWN_TRANSPARENT 2u
#define MMI_STATE_UNKNOWN_OPAQUE 3u
// Returned for a malformed buffer or an index out of range. A caller that
// treats `state >= 2u` as "unknown: run the alpha test" treats it as unknown.
#define MMI_STATE_INVALID 4u

// Formats (Format::raw(), VkOpacityMicromapFormatEXT, D3D12 and glTF).
#define MMI_FORMAT_2_STATE 1u
#define MMI_FORMAT_4_STATE 2u

// Special indices (State::special_index()): -(state + 1).
#define MMI_SPECIAL_INDEX_TRANSPARENT (-1)
#define MMI_SPECIAL_INDEX_OPAQUE (-2)
#define MMI_SPECIAL_INDEX_UNKNOWN_TRANSPARENT (-3)
#define MMI_SPECIAL_INDEX_UNKNOWN_OPAQUE (-4)
// -5: reserved (cluster geometry: disable the micromap); a lookup through it
// returns MMI_STATE_INVALID.
#define MMI_SPECIAL_INDEX_RESERVED (-5)

// The highest subdivision level the lookups accept (DXR, the OMM SDK, the
// baker: 0..=12).
#define MMI_MAX_LEVEL 12u

// The succinct trees' byte format (micromap_index::succinct, version 1).
#define MMI_TREE_MAGIC 0x544d4f53u
#define MMI_TREE_VERSION 1u
#define MMI_TREE_LAYOUT_PAPER 0u
#define MMI_TREE_LAYOUT_LEVEL_ORDER 1u
#define MMI_TREE_HEADER_WORDS 6u
// The level-order rank directory: one entry (two words) per this many bits.
#define MMI_RANK_BLOCK_BITS 512u
// A level-order top-table entry with this bit is a leaf's state (low 2 bits).
#define MMI_TOP_LEAF 0x8000u
#define MMI_TOP_MAX_DEPTH 7u

#endif // MICROMAP_CONSTANTS_GLSL
