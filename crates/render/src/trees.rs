//! The succinct trees of every micromap record as the shaders read them
//! (binding 8 and its directory, binding 9): one word buffer with each
//! record's level-order tree, its rank directory and top table
//! ([`crate::tables`]) and its paper tree, and [`TREE_WORDS`] words per
//! record saying where each part starts and how long it is.

use crate::error::RenderError;
use crate::scene::Micromaps;
use crate::tables;
use micromap_index::succinct::{LevelOrderTree, PaperTree};

/// Words per tree directory entry (shader `TREE_WORDS`).
pub(crate) const TREE_WORDS: usize = 10;

/// `bytes` zero-padded to whole words.
pub(crate) fn padded(bytes: &[u8]) -> Vec<u32> {
    bytes
        .chunks(4)
        .map(|c| {
            let mut w = [0u8; 4];
            w[..c.len()].copy_from_slice(c);
            u32::from_le_bytes(w)
        })
        .collect()
}

/// The trees of every record: one word buffer and a directory of
/// [`TREE_WORDS`] words per record. The level-order trees get a top table
/// of depth `min(level - 1, 4)`.
pub(crate) fn tree_buffers(micromaps: &Micromaps) -> Result<(Vec<u32>, Vec<u32>), RenderError> {
    let mut words = Vec::new();
    let mut dir = Vec::new();
    let mut push = |part: &[u32]| {
        let base = words.len() as u32;
        words.extend_from_slice(part);
        [base, part.len() as u32]
    };
    for (record, map) in micromaps.read().micromaps.iter().enumerate() {
        let states: Vec<_> = map.states().collect();
        let tree_error = |error| RenderError::Tree { record, error };
        let lot = LevelOrderTree::encode(map.level(), map.format(), &states)
            .map_err(tree_error)?
            .to_bytes();
        let paper = PaperTree::encode(map.level(), map.format(), &states)
            .map_err(tree_error)?
            .to_bytes();
        let depth = map.level().get().saturating_sub(1).min(4);
        let rank = tables::rank_directory(&lot);
        let (top, top_start) = tables::top_table(&lot, depth);
        let [lot_base, lot_len] = push(&padded(&lot));
        let [rank_base, rank_len] = push(&rank);
        let [top_base, top_len] = push(&top);
        let [paper_base, paper_len] = push(&padded(&paper));
        dir.extend([
            lot_base, lot_len, rank_base, rank_len, top_base, top_len, depth, top_start,
            paper_base, paper_len,
        ]);
    }
    debug_assert_eq!(dir.len(), TREE_WORDS * micromaps.read().micromaps.len());
    Ok((words, dir))
}
