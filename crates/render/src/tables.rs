//! The host-side tables `shaders/glsl/level_order_tree.glsl` reads next to
//! a level-order tree's bytes (the byte format does not store them): the
//! rank directory and the top table. The renderer and the shader test
//! (`crates/lab/tests/shaders.rs`) both build them here.
//!
//! ```
//! use micromap_index::micromap::{Format, State};
//! use micromap_index::succinct::LevelOrderTree;
//! use micromap_index::Level;
//! use micromap_index_render::tables::{rank_directory, top_table};
//! let mut states = vec![State::Opaque; 64];
//! states[5] = State::Transparent;
//! let tree = LevelOrderTree::encode(Level::new(3).unwrap(), Format::FourState, &states).unwrap();
//! let bytes = tree.to_bytes();
//! assert!(rank_directory(&bytes).is_empty()); // at most 128 tree bits
//! let (top, start) = top_table(&bytes, 1);
//! assert_eq!(top.len(), 2); // 4 entries, two per word
//! assert_eq!(start, 1);
//! ```

/// The tree bits of a tree's bytes (header fields and the section as u64
/// words, least-significant bit first). Bytes shorter than their header
/// says give the words that are there (the shader refuses such bytes).
fn tree_section(bytes: &[u8]) -> (u64, Vec<u64>) {
    let Some(header) = bytes.get(8..16) else {
        return (0, Vec::new());
    };
    let tree_bits = u64::from_le_bytes(header.try_into().unwrap_or([0; 8]));
    let end = 24usize.saturating_add(tree_bits.div_ceil(8) as usize);
    let section = bytes.get(24..end.min(bytes.len())).unwrap_or(&[]);
    let words = section
        .chunks(8)
        .map(|c| {
            let mut w = [0u8; 8];
            w[..c.len()].copy_from_slice(c);
            u64::from_le_bytes(w)
        })
        .collect();
    (tree_bits, words)
}

/// The rank directory `level_order_tree.glsl` reads (`MMI_LOT_RANK`): per
/// 512 tree bits one `u64`, the ones before the block in the high half and
/// the ones in the block's words `0..2`, `0..4`, `0..6` in 9-bit fields, as
/// two little-endian words; empty up to 128 bits. The library builds the
/// same entries in memory (`succinct::bits::RankBits`, not public).
#[must_use]
pub fn rank_directory(bytes: &[u8]) -> Vec<u32> {
    let (tree_bits, words) = tree_section(bytes);
    if tree_bits <= 128 {
        return Vec::new();
    }
    let mut out = Vec::new();
    let mut ones = 0u64;
    for block in words.chunks(8) {
        let mut relative = 0u64;
        let mut in_block = 0u64;
        for (i, w) in block.iter().enumerate() {
            if i % 2 == 0 && i > 0 {
                relative |= in_block << (9 * (i as u32 / 2 - 1));
            }
            in_block += u64::from(w.count_ones());
        }
        out.extend([relative as u32, ones as u32]);
        ones += in_block;
    }
    out
}

/// The top table of depth `depth` and the position of its depth's first
/// node (`MMI_LOT_TOP`, `top_start`), as `LevelOrderTree::with_top_depth`
/// builds it: for each `depth`-digit prefix, the node at that depth as an
/// offset from `top_start`, or `0x8000 | state` where the path ends in a
/// leaf above. `depth` 0 gives an empty table; `depth` must be below the
/// tree's level and at most 7 (the shader's limits) for the entries to fit
/// 16 bits. Bytes that are not a well-formed tree give some table (the
/// shader checks every entry it reads).
#[must_use]
pub fn top_table(bytes: &[u8], depth: u32) -> (Vec<u32>, u32) {
    if depth == 0 || depth > 7 || bytes.len() < 24 {
        return (Vec::new(), 0);
    }
    let (tree_bits, words) = tree_section(bytes);
    let format = u32::from(bytes[7]).min(2);
    let data_bit = 8 * (24 + tree_bits.div_ceil(8));
    let before: Vec<u64> = words
        .iter()
        .scan(0u64, |acc, w| {
            let b = *acc;
            *acc += u64::from(w.count_ones());
            Some(b)
        })
        .collect();
    let total =
        before.last().copied().unwrap_or(0) + words.last().map_or(0, |w| u64::from(w.count_ones()));
    let rank = |p: u64| {
        let w = (p / 64) as usize;
        if p >= tree_bits || w >= words.len() {
            return total;
        }
        before[w] + u64::from((words[w] & ((1u64 << (p % 64)) - 1)).count_ones())
    };
    let bit = |p: u64| {
        p < tree_bits
            && words
                .get((p / 64) as usize)
                .is_some_and(|w| (w >> (p % 64)) & 1 == 1)
    };
    let state = |leaf: u64| {
        let at = data_bit + leaf * u64::from(format);
        let byte = bytes.get((at / 8) as usize).copied().unwrap_or(0);
        u32::from(byte >> (at % 8)) & ((1 << format) - 1)
    };
    let (mut start, mut count) = (0u64, 1u64);
    for _ in 0..depth {
        let end = start + count;
        (start, count) = (end, 4 * (rank(end).saturating_sub(rank(start))));
    }
    let entries: Vec<u32> = (0..1u64 << (2 * depth))
        .map(|prefix| {
            let mut p = 0u64;
            for d in 0..depth {
                if !bit(p) {
                    return 0x8000 | state(p.saturating_sub(rank(p)));
                }
                p = 1 + 4 * rank(p) + ((prefix >> (2 * (depth - 1 - d))) & 3);
            }
            (p.saturating_sub(start)) as u32
        })
        .collect();
    let packed = entries
        .chunks(2)
        .map(|c| c[0] | c.get(1).map_or(0, |&e| e << 16))
        .collect();
    (packed, start as u32)
}
