//! The sizes of both tree layouts of a micromap, counted without building
//! either tree (a bake reports them for every distinct micromap).
//!
//! Every node of the merged tree is reachable through mixed nodes, and a
//! mixed node's parent is mixed, so the tree is fixed by how many pyramid
//! nodes are mixed: with `I` mixed nodes in all and `I_last` one level above
//! the map's, it has `1 + 4 I` nodes, `1 + 3 I` leaves, and `4 I_last` nodes
//! at the map's own level (those the level-order layout gives no bit).

use super::level_order::LevelOrderTree;
use super::merge::MIXED;
use super::{tree_level, TreeError};
use crate::micromap::{Format, Micromap};
use crate::Level;
use alloc::vec::Vec;

/// Nodes one level above the map's that [`packed_tree_sizes`] keeps on
/// the stack (a map of level 5 or less).
const SMALL_NODES: usize = 256;

/// The bits of a micromap's [`PaperTree`](super::PaperTree) and
/// [`LevelOrderTree`], as their `total_bits` give them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct TreeSizes {
    /// [`PaperTree::total_bits`](super::PaperTree::total_bits).
    pub paper_bits: u64,
    /// [`LevelOrderTree::total_bits`] (with its default top table).
    pub level_order_bits: u64,
}

/// The sizes of `map`'s two tree layouts, without building them: the same
/// numbers as `PaperTree::from_micromap(map)?.total_bits()` and
/// `LevelOrderTree::from_micromap(map)?.total_bits()`, for a pass over the
/// packed data and `4^(level - 1)` bytes. The errors are theirs: a level
/// above [`MAX_TREE_LEVEL`](super::MAX_TREE_LEVEL), or
/// [`TreeError::AllocationFailed`] where those bytes cannot be had.
///
/// ```
/// use micromap_index::micromap::{Format, Micromap, State};
/// use micromap_index::succinct::{tree_sizes, LevelOrderTree, PaperTree};
/// use micromap_index::Level;
///
/// let states = (0..256).map(|i| if i < 64 { State::Opaque } else { State::Transparent });
/// let map = Micromap::from_states(Level::new(4)?, Format::FourState, states)?;
/// let sizes = tree_sizes(&map)?;
/// assert_eq!(sizes.paper_bits, PaperTree::from_micromap(&map)?.total_bits());
/// assert_eq!(sizes.level_order_bits, LevelOrderTree::from_micromap(&map)?.total_bits());
/// // One internal node (the root) and four uniform quadrants.
/// assert_eq!(sizes.paper_bits, 5 + 4 * 2);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn tree_sizes(map: &Micromap) -> Result<TreeSizes, TreeError> {
    packed_tree_sizes(map.level(), map.format(), map.as_bytes())
}

/// [`tree_sizes`] of the packed data of a map of `level` and `format`
/// (`bytes` holds `4^level` states, as [`Micromap::as_bytes`] gives them;
/// missing bytes read as transparent).
pub(crate) fn packed_tree_sizes(
    level: Level,
    format: Format,
    bytes: &[u8],
) -> Result<TreeSizes, TreeError> {
    let level = tree_level(level)?;
    let (mut mixed, mut mixed_last) = (0u64, 0u64);
    if level > 0 {
        // The nodes one level above the map's straight from the bytes (four
        // states: a 4-state byte, a 2-state nibble), then Algorithm 1's
        // merge in place: node `i` of a depth overwrites slot `i` after its
        // children `4i..4i + 3` (at or after `i`) are read.
        let nodes = 1usize << (2 * (level - 1));
        // (Small maps, most of a bake's, keep their codes on the stack.)
        let mut small = [0u8; SMALL_NODES];
        // The large ones' codes are reserved fallibly (1 GiB at level 16).
        let mut large: Vec<u8>;
        let codes: &mut [u8] = if nodes <= SMALL_NODES {
            &mut small[..nodes]
        } else {
            large = super::room(nodes as u64)?;
            large.resize(nodes, 0);
            &mut large
        };
        match format {
            // A byte of four equal states is `s * 0b01010101`.
            Format::FourState => {
                for (code, &b) in codes.iter_mut().zip(bytes) {
                    *code = if b == (b & 3) * 0x55 { b & 3 } else { MIXED };
                }
            }
            Format::TwoState => {
                let nibbles = bytes.iter().flat_map(|&b| [b & 0xf, b >> 4]);
                for (code, nibble) in codes.iter_mut().zip(nibbles) {
                    *code = match nibble {
                        0x0 => 0,
                        0xf => 1,
                        _ => MIXED,
                    };
                }
            }
        }
        // Missing bytes read as transparent (state 0): the zeros left.
        mixed_last = codes.iter().map(|&c| u64::from(c == MIXED)).sum();
        mixed = mixed_last;
        for depth in (0..level - 1).rev() {
            let mut at_depth = 0u64;
            for i in 0..1usize << (2 * depth) {
                // Four equal codes other than MIXED: the word of `first`.
                let c = [
                    codes[4 * i],
                    codes[4 * i + 1],
                    codes[4 * i + 2],
                    codes[4 * i + 3],
                ];
                let first = c[0];
                codes[i] =
                    if first != MIXED && u32::from_le_bytes(c) == u32::from(first) * 0x0101_0101 {
                        first
                    } else {
                        at_depth += 1;
                        MIXED
                    };
            }
            mixed += at_depth;
        }
    }
    let data_bits = (1 + 3 * mixed) * u64::from(format.bits_per_state());
    let nodes = 1 + 4 * mixed;
    // The level-order layout has a bit for every node above the map's
    // level: all but the map-level ones (at level 0, the root is one).
    let internal_bits = if level == 0 {
        0
    } else {
        nodes - 4 * mixed_last
    };
    Ok(TreeSizes {
        paper_bits: nodes + data_bits,
        level_order_bits: internal_bits
            + LevelOrderTree::directory_bits_for(level, internal_bits)
            + data_bits,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::micromap::State;
    use crate::succinct::PaperTree;
    use micromap_index_test_support::SplitMix64;

    /// The counted sizes equal the built trees' on maps of every shape the
    /// merge meets: uniform, quadrant-structured at a random depth, noisy,
    /// in both formats, at levels 0..=8.
    #[test]
    fn counted_sizes_equal_the_built_trees() {
        let mut rng = SplitMix64::new(0x5123);
        for case in 0..3000u32 {
            let level = case % 9;
            let format = if case % 2 == 0 {
                Format::TwoState
            } else {
                Format::FourState
            };
            let states_of = |k: u64| match format {
                Format::TwoState => [State::Transparent, State::Opaque][(k % 2) as usize],
                Format::FourState => State::from_bits((k % 4) as u8).unwrap(),
            };
            // Runs of 4^g equal states (g random), then some noise: trees
            // from a single node to the full pyramid.
            let grain = (rng.next_u64() % u64::from(level + 1)) as u32;
            let noise = rng.next_u64() % 4;
            let n = 1u64 << (2 * level);
            let mut run_state = 0;
            let states: Vec<State> = (0..n)
                .map(|i| {
                    if i % (1 << (2 * grain)) == 0 {
                        run_state = rng.next_u64();
                    }
                    if rng.next_u64() % 64 < noise {
                        states_of(rng.next_u64())
                    } else {
                        states_of(run_state)
                    }
                })
                .collect();
            let map = Micromap::from_states(Level::new(level).unwrap(), format, states).unwrap();
            let paper = PaperTree::from_micromap(&map).unwrap();
            let level_order = LevelOrderTree::from_micromap(&map).unwrap();
            assert_eq!(
                tree_sizes(&map).unwrap(),
                TreeSizes {
                    paper_bits: paper.total_bits(),
                    level_order_bits: level_order.total_bits(),
                },
                "case {case}: level {level}, {format:?}, grain {grain}, noise {noise}"
            );
            assert_eq!(
                LevelOrderTree::from_paper(&paper).total_bits(),
                level_order.total_bits()
            );
        }
    }
}
