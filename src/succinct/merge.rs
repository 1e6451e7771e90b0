//! Algorithm 1 of the paper: the perfect 4-way tree over a flat micromap,
//! built bottom-up by merging uniform quadrants.
//!
//! The curve is hierarchical: the children of micro-triangle `i` at level
//! `n` are `4i..4i+3` at level `n + 1`, so "the four children of a node" is
//! index arithmetic and no geometry is needed.

use super::{room, TreeError};
use crate::micromap::State;
use alloc::vec;
use alloc::vec::Vec;

/// The code of a node whose subtree is not uniform (an internal node of the
/// merged tree); codes `0..=3` are a uniform subtree's state.
pub(crate) const MIXED: u8 = 4;

/// Every node of the perfect tree, level by level: `depths[d][i]` is the
/// state of node `i` at depth `d` if its whole subtree has that one state,
/// else [`MIXED`]. `depths[level]` is the flat micromap.
///
/// The merged tree (what the encodings store) is the part of this pyramid
/// reachable from the root through mixed nodes: a uniform node is a leaf and
/// its descendants are dropped.
pub(crate) struct Pyramid {
    pub(crate) depths: Vec<Vec<u8>>,
}

impl Pyramid {
    /// Algorithm 1: for each level from the map's own up to the root, a node
    /// is a leaf with state `s` when its four children are leaves with state
    /// `s`, else internal. `states.len()` is `4^level` (checked by the
    /// callers). The pyramid's `4^level * 4/3` bytes are allocated
    /// fallibly ([`TreeError::AllocationFailed`]).
    pub(crate) fn merge_uniform_quadrants(
        level: u32,
        states: &[State],
    ) -> Result<Pyramid, TreeError> {
        let mut depths = vec![Vec::new(); level as usize + 1];
        let mut flat = room(states.len() as u64)?;
        flat.extend(states.iter().map(|s| s.bits()));
        depths[level as usize] = flat;
        for depth in (0..level as usize).rev() {
            let children = &depths[depth + 1];
            let mut merged = room(children.len() as u64 / 4)?;
            merged.extend(children.chunks_exact(4).map(|children| {
                let first = children[0];
                if first != MIXED && children.iter().all(|&c| c == first) {
                    first
                } else {
                    MIXED
                }
            }));
            depths[depth] = merged;
        }
        Ok(Pyramid { depths })
    }

    /// The node's state if it is a leaf of the merged tree's pyramid
    /// (uniform), else `None`.
    #[inline]
    pub(crate) fn uniform(&self, depth: usize, index: usize) -> Option<State> {
        State::from_bits(self.depths[depth][index])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_equal_children_merge_and_unequal_ones_do_not() {
        use State::*;
        let states = [
            [Opaque; 4],
            [Transparent; 4],
            [Opaque, Opaque, Opaque, UnknownOpaque],
            [Opaque; 4],
        ]
        .concat();
        let pyramid = Pyramid::merge_uniform_quadrants(2, &states).unwrap();
        assert_eq!(pyramid.depths[1], [1, 0, MIXED, 1]);
        assert_eq!(pyramid.depths[0], [MIXED]);
        let uniform = Pyramid::merge_uniform_quadrants(2, &[UnknownTransparent; 16]).unwrap();
        assert_eq!(uniform.depths[0], [2]);
        assert_eq!(uniform.uniform(0, 0), Some(UnknownTransparent));
    }
}
