// level_order_tree.glsl: the state of one micro-triangle from a
// micromap_index::succinct::LevelOrderTree, as LevelOrderTree::get computes
// it: the top table resolves the first levels in one read, then one rank
// query per level (child c of the internal node at p is at 1 + 4 rank1(p) + c,
// the leaf at x holds state x - rank1(x)).
//
// Buffers, uint arrays declared by the including shader and named through
// macros defined before the #include:
//   MMI_LOT(i), MMI_LOT_LENGTH    the tree's bytes as LevelOrderTree::to_bytes
//       writes them (header "SOMT", version 1, layout 1, level, format,
//       u64 tree_bits, u64 leaves, tree bits, leaf states), zero-padded to a
//       multiple of 4 bytes.
//   MMI_LOT_RANK(i), MMI_LOT_RANK_LENGTH   the rank directory, derived from the
//       tree bits (the byte format does not store it): for each 512-bit block
//       b, word 2b = the ones in the block's 64-bit words 0..2, 0..4 and 0..6,
//       9 bits each (bits 0..9, 9..18, 18..27), word 2b + 1 = the ones before
//       the block: the library's u64 entries, little endian. Empty (length 0
//       is fine, declare one word) when tree_bits <= 128.
//   MMI_LOT_TOP(i), MMI_LOT_TOP_LENGTH     the top table, two u16 entries per
//       word (entry e in bits 16 (e & 1) of word e >> 1): for each
//       top_depth-digit prefix of an index, the node at depth top_depth on its
//       path as an offset from top_start, or MMI_TOP_LEAF | state when the
//       path ends in a leaf above. Not read when top_depth is 0.
// micromap_index_render::tables builds both on the host (Rust).
//
// Function
//   uint mmi_level_order_get(uint index, uint top_depth, uint top_start)
//     index: micro-triangle, below 4^level; top_depth 0..=min(7, level - 1)
//     (0: no table); top_start: the position of the first node at depth
//     top_depth (0 when top_depth is 0).
// Return: the state (0..3, State numbering), or MMI_STATE_INVALID (4).
// Levels 0..=12 (MMI_MAX_LEVEL), both formats.
//
// Malformed input is total: every read is bounds-checked against the
// *_LENGTH macros, and MMI_STATE_INVALID is returned for a wrong magic,
// version, layout, format, a level above 12, a high word of tree_bits or
// leaves that is not 0, sections that do not fit in MMI_LOT_LENGTH words,
// an index not below 4^level, a top_depth above 7 or not below the level, a
// missing directory or table entry, and a walk that leaves the tree bits or
// the leaf states. The tree's shape (four children per internal bit, merged)
// is not checked here: a wrong shape that stays in bounds gives some state;
// check bytes once on the host with LevelOrderTree::from_bytes.
#ifndef LEVEL_ORDER_TREE_GLSL
#define LEVEL_ORDER_TREE_GLSL

#include "micromap_constants.glsl"

// Bit p of the tree section and rank1(p); `ok` false when the directory entry
// is missing. p must be below tree_bits.
uint mmi_lot_rank(uint p, uint tree_bits, out uint bit, out bool ok)
{
    uint w = p >> 5u;
    uint word = MMI_LOT(MMI_TREE_HEADER_WORDS + w);
    bit = (word >> (p & 31u)) & 1u;
    uint relative = 0u;
    uint before = 0u;
    ok = true;
    if (tree_bits > 128u) {
        uint block = p >> 9u;
        if (2u * block + 1u >= MMI_LOT_RANK_LENGTH) {
            ok = false;
            return 0u;
        }
        relative = MMI_LOT_RANK(2u * block);
        before = MMI_LOT_RANK(2u * block + 1u);
    }
    uint pair = (p >> 7u) & 3u;
    // The ones in the block's words before the pair (none before pair 0).
    uint rank = before + (pair == 0u ? 0u : (relative >> (9u * (pair - 1u))) & 511u);
    // The pair's (128 bits, four words) words below w, then w below p.
    for (uint x = (p >> 7u) << 2u; x < w; x++) {
        rank += uint(bitCount(MMI_LOT(MMI_TREE_HEADER_WORDS + x)));
    }
    return rank + uint(bitCount(word & ((1u << (p & 31u)) - 1u)));
}

uint mmi_level_order_get(uint index, uint top_depth, uint top_start)
{
    if (MMI_LOT_LENGTH < MMI_TREE_HEADER_WORDS) return MMI_STATE_INVALID;
    if (MMI_LOT(0u) != MMI_TREE_MAGIC) return MMI_STATE_INVALID;
    uint h = MMI_LOT(1u);
    uint level = (h >> 16u) & 0xffu;
    uint format = h >> 24u;
    if ((h & 0xffu) != MMI_TREE_VERSION || ((h >> 8u) & 0xffu) != MMI_TREE_LAYOUT_LEVEL_ORDER
        || level > MMI_MAX_LEVEL || (format != MMI_FORMAT_2_STATE && format != MMI_FORMAT_4_STATE)
        || MMI_LOT(3u) != 0u || MMI_LOT(5u) != 0u)
        return MMI_STATE_INVALID;
    uint tree_bits = MMI_LOT(2u);
    uint leaves = MMI_LOT(4u);
    // Both below 2^28 for any tree of level 12; larger ones cannot fit.
    if (tree_bits >= 0x10000000u || leaves >= 0x10000000u) return MMI_STATE_INVALID;
    uint tree_bytes = (tree_bits + 7u) >> 3u;
    uint data_bytes = (leaves * format + 7u) >> 3u; // format = bits per state
    if (4u * MMI_TREE_HEADER_WORDS + tree_bytes + data_bytes > 4u * MMI_LOT_LENGTH)
        return MMI_STATE_INVALID;
    if (index >= (1u << (2u * level))) return MMI_STATE_INVALID;
    uint data_bit = 8u * (4u * MMI_TREE_HEADER_WORDS + tree_bytes);

    uint p = 0u;
    uint depth = 0u;
    if (top_depth > 0u) {
        if (top_depth > MMI_TOP_MAX_DEPTH || top_depth >= level) return MMI_STATE_INVALID;
        uint prefix = index >> (2u * (level - top_depth));
        if ((prefix >> 1u) >= MMI_LOT_TOP_LENGTH) return MMI_STATE_INVALID;
        uint entry = (MMI_LOT_TOP(prefix >> 1u) >> (16u * (prefix & 1u))) & 0xffffu;
        if ((entry & MMI_TOP_LEAF) != 0u) return entry & 3u;
        p = top_start + entry;
        depth = top_depth;
    }
    uint leaf = 0xffffffffu;
    for (; depth < level; depth++) {
        if (p >= tree_bits) return MMI_STATE_INVALID;
        uint bit;
        bool ok;
        uint rank = mmi_lot_rank(p, tree_bits, bit, ok);
        if (!ok) return MMI_STATE_INVALID;
        if (bit == 0u) {
            leaf = p - rank;
            break;
        }
        p = 1u + 4u * rank + ((index >> (2u * (level - 1u - depth))) & 3u);
    }
    if (leaf == 0xffffffffu) {
        // A node at the map's level (no bit): state p - (all ones).
        uint ones = 0u;
        if (tree_bits > 0u) {
            uint bit;
            bool ok;
            ones = mmi_lot_rank(tree_bits - 1u, tree_bits, bit, ok) + bit;
            if (!ok) return MMI_STATE_INVALID;
        }
        if (p < ones) return MMI_STATE_INVALID;
        leaf = p - ones;
    }
    if (leaf >= leaves) return MMI_STATE_INVALID;
    uint at = data_bit + leaf * format;
    return (MMI_LOT(at >> 5u) >> (at & 31u)) & ((1u << format) - 1u);
}

#endif // LEVEL_ORDER_TREE_GLSL
