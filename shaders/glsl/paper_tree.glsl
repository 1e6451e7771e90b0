// paper_tree.glsl: the state of one micro-triangle from a
// micromap_index::succinct::PaperTree by the paper's Algorithm 3, literally
// (Waldemarson & Doggett, "Succinct Opacity Micromaps", 2024): at an
// internal bit step to the first child and scan forward over the earlier
// siblings' subtrees, bit by bit (a counter that gains 4 at each internal bit
// and loses 1 per node). Its cost grows about 4x per level; it is the
// baseline the level-order tree (level_order_tree.glsl) is measured against.
//
// Buffer, a uint array declared by the including shader and named through
// macros defined before the #include:
//   MMI_PAPER(i), MMI_PAPER_LENGTH   the tree's bytes as PaperTree::to_bytes
//       writes them (header "SOMT", version 1, layout 0, level, format,
//       u64 tree_bits, u64 leaves, tree bits in pre-order, leaf states),
//       zero-padded to a multiple of 4 bytes.
//
// Function
//   uint mmi_paper_tree_get(uint index)   index below 4^level
// Return: the state (0..3, State numbering), or MMI_STATE_INVALID (4).
// Levels 0..=12 (MMI_MAX_LEVEL), both formats.
//
// Malformed input is total: every read is bounds-checked, and
// MMI_STATE_INVALID is returned for a wrong magic, version, layout, format, a
// level above 12, a high word of tree_bits or leaves that is not 0, sections
// that do not fit in MMI_PAPER_LENGTH words, an index not below 4^level, a
// walk that runs past the tree bits or below the map's level, or a leaf past
// the states. The loops are bounded by tree_bits and the level. The tree's
// shape is not checked: check bytes once on the host with
// PaperTree::from_bytes.
#ifndef PAPER_TREE_GLSL
#define PAPER_TREE_GLSL

#include "micromap_constants.glsl"

uint mmi_paper_bit(uint t)
{
    return (MMI_PAPER(MMI_TREE_HEADER_WORDS + (t >> 5u)) >> (t & 31u)) & 1u;
}

uint mmi_paper_tree_get(uint index)
{
    if (MMI_PAPER_LENGTH < MMI_TREE_HEADER_WORDS) return MMI_STATE_INVALID;
    if (MMI_PAPER(0u) != MMI_TREE_MAGIC) return MMI_STATE_INVALID;
    uint h = MMI_PAPER(1u);
    uint level = (h >> 16u) & 0xffu;
    uint format = h >> 24u;
    if ((h & 0xffu) != MMI_TREE_VERSION || ((h >> 8u) & 0xffu) != MMI_TREE_LAYOUT_PAPER
        || level > MMI_MAX_LEVEL || (format != MMI_FORMAT_2_STATE && format != MMI_FORMAT_4_STATE)
        || MMI_PAPER(3u) != 0u || MMI_PAPER(5u) != 0u)
        return MMI_STATE_INVALID;
    uint tree_bits = MMI_PAPER(2u);
    uint leaves = MMI_PAPER(4u);
    if (tree_bits >= 0x10000000u || leaves >= 0x10000000u) return MMI_STATE_INVALID;
    uint tree_bytes = (tree_bits + 7u) >> 3u;
    uint data_bytes = (leaves * format + 7u) >> 3u;
    if (4u * MMI_TREE_HEADER_WORDS + tree_bytes + data_bytes > 4u * MMI_PAPER_LENGTH)
        return MMI_STATE_INVALID;
    if (index >= (1u << (2u * level))) return MMI_STATE_INVALID;

    uint t = 0u; // tree bit
    uint d = 0u; // leaves passed
    for (uint depth = 0u; depth <= level; depth++) {
        if (t >= tree_bits) return MMI_STATE_INVALID;
        if (mmi_paper_bit(t) == 0u) {
            if (d >= leaves) return MMI_STATE_INVALID;
            uint at = 8u * (4u * MMI_TREE_HEADER_WORDS + tree_bytes) + d * format;
            return (MMI_PAPER(at >> 5u) >> (at & 31u)) & ((1u << format) - 1u);
        }
        if (depth == level) return MMI_STATE_INVALID; // internal below the map's level
        t++;
        // step(u, v): the next base-4 digit of the index.
        uint child = (index >> (2u * (level - 1u - depth))) & 3u;
        // bitscan: skip `child` whole subtrees.
        while (t < tree_bits && child > 0u) {
            if (mmi_paper_bit(t) != 0u) child += 4u;
            else d++;
            child--;
            t++;
        }
    }
    return MMI_STATE_INVALID;
}

#endif // PAPER_TREE_GLSL
