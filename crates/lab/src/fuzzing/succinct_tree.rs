//! The body of the fuzz target `succinct_tree` replayed on stable by
//! `crates/lab/tests/fuzz_corpus.rs`.

use micromap_index::micromap::{Format, State};
use micromap_index::succinct::{LevelOrderTree, PaperTree};
use micromap_index::Level;

/// Checks the tree readers and encoders on arbitrary bytes; panics only when
/// a property fails.
///
/// 1. The whole input goes to [`PaperTree::from_bytes`] and
///    [`LevelOrderTree::from_bytes`] (and, if it is at least 6 bytes long,
///    again with byte 5, the layout, set to the other layout). Neither
///    panics; what one accepts writes back to the same bytes, converts to
///    the other layout and back unchanged, holds the same runs of states in
///    both (the paper's tiling `0..4^level` in index order), and answers
///    the lookups at both ends of every run (up to 4096) with its state.
/// 2. The input also describes a micromap: byte 0 the level (`% 7`, so
///    `0..=6`), byte 1 bit 0 the format (0 two-state, 1 four-state), then
///    four states per byte from byte 2 on (2 bits each, lowest first; the
///    low bit only in a 2-state map; missing bytes read as zero). Both
///    layouts encode it, decode it back, answer every index like it, and
///    read their bytes back. Then the byte `bytes[2..4]` (LE `u16`, modulo
///    the length) of each encoding is `XORed` with byte 4 (or `0x01` if that
///    is zero): the reader must reject the result or accept one that writes
///    back to it.
pub fn succinct_tree(data: &[u8]) {
    check_readers(data);
    if data.len() > 5 {
        let mut other = data.to_vec();
        other[5] ^= 1;
        check_readers(&other);
    }
    check_encoders(data);
}

fn byte(data: &[u8], i: usize) -> u8 {
    data.get(i).copied().unwrap_or(0)
}

fn check_readers(bytes: &[u8]) {
    if let Ok(paper) = PaperTree::from_bytes(bytes) {
        assert_eq!(
            paper.to_bytes(),
            bytes,
            "paper tree bytes do not round-trip"
        );
        let fast = LevelOrderTree::from_paper(&paper);
        assert_eq!(PaperTree::from_level_order(&fast), paper);
        check_same_map(&paper, &fast, None);
    }
    if let Ok(fast) = LevelOrderTree::from_bytes(bytes) {
        assert_eq!(
            fast.to_bytes(),
            bytes,
            "level-order bytes do not round-trip"
        );
        let paper = PaperTree::from_level_order(&fast);
        assert_eq!(LevelOrderTree::from_paper(&paper), fast);
        check_same_map(&paper, &fast, None);
    }
}

/// Both trees hold `flat` (or, if `None`, the same map), lookups included.
/// The maps are compared by their runs, as many as the trees have leaves
/// (bounded by the input's bytes): a 26-byte tree of level 16 decodes to
/// 4 GiB, which a fuzz run must not allocate.
fn check_same_map(paper: &PaperTree, fast: &LevelOrderTree, flat: Option<&[State]>) {
    let (mut paper_runs, mut fast_runs) = (Vec::new(), Vec::new());
    paper.for_each_run(|first, count, state| paper_runs.push((first, count, state)));
    fast.for_each_run(|first, count, state| fast_runs.push((first, count, state)));
    // The paper's walk is in index order and its runs tile 0..4^level.
    let len = 1u64 << (2 * paper.level().get());
    let mut next = 0;
    for &(first, count, _) in &paper_runs {
        assert_eq!(first, next, "the paper tree's runs leave a gap or overlap");
        next = first + count;
    }
    assert_eq!(next, len, "the paper tree's runs do not end at 4^level");
    fast_runs.sort_unstable_by_key(|&(first, _, _)| first);
    assert_eq!(fast_runs, paper_runs, "the layouts hold different maps");
    if let Some(flat) = flat {
        assert_eq!(
            paper.decode().as_deref(),
            Ok(flat),
            "decode is not the encoded micromap"
        );
        assert_eq!(fast.decode().as_deref(), Ok(flat), "level-order decode");
    }
    // The first indices of every run, up to 4096 lookups.
    let probes = paper_runs
        .iter()
        .flat_map(|&(first, count, state)| [(first, state), (first + count - 1, state)])
        .take(4096);
    for (index, state) in probes {
        assert_eq!(paper.get(index), Some(state), "Algorithm 3, index {index}");
        assert_eq!(fast.get(index), Some(state), "level order, index {index}");
    }
    assert_eq!(paper.get(len), None);
    assert_eq!(fast.get(len), None);
}

fn check_encoders(data: &[u8]) {
    let level = u32::from(byte(data, 0) % 7);
    let format = if byte(data, 1) & 1 == 0 {
        Format::TwoState
    } else {
        Format::FourState
    };
    let count = 1usize << (2 * level);
    let states: Vec<State> = (0..count)
        .map(|i| {
            let bits = (byte(data, 2 + i / 4) >> (2 * (i % 4))) & 3;
            let state = State::ALL[bits as usize];
            match format {
                Format::TwoState => State::ALL[(bits & 1) as usize],
                Format::FourState => state,
            }
        })
        .collect();
    let Ok(level) = Level::new(level) else {
        return; // never: levels 0..=6 are valid
    };
    let paper = PaperTree::encode(level, format, &states)
        .unwrap_or_else(|e| panic!("encode failed on a valid map: {e}"));
    let fast = LevelOrderTree::encode(level, format, &states)
        .unwrap_or_else(|e| panic!("encode failed on a valid map: {e}"));
    assert_eq!(LevelOrderTree::from_paper(&paper), fast);
    assert_eq!(PaperTree::from_level_order(&fast), paper);
    check_same_map(&paper, &fast, Some(&states));
    let parts = PaperTree::from_parts(level, format, paper.tree_bit_iter(), &paper.leaf_states());
    assert_eq!(
        parts.as_ref(),
        Ok(&paper),
        "from_parts rejects encode's bits"
    );
    let at = usize::from(u16::from_le_bytes([byte(data, 2), byte(data, 3)]));
    let flip = match byte(data, 4) {
        0 => 1,
        b => b,
    };
    let paper_bytes = paper.to_bytes();
    assert_eq!(PaperTree::from_bytes(&paper_bytes).as_ref(), Ok(&paper));
    let mut damaged = paper_bytes.clone();
    damaged[at % paper_bytes.len()] ^= flip;
    if let Ok(tree) = PaperTree::from_bytes(&damaged) {
        assert_eq!(tree.to_bytes(), damaged);
    }
    let fast_bytes = fast.to_bytes();
    assert_eq!(LevelOrderTree::from_bytes(&fast_bytes).as_ref(), Ok(&fast));
    let mut damaged = fast_bytes.clone();
    damaged[at % fast_bytes.len()] ^= flip;
    if let Ok(tree) = LevelOrderTree::from_bytes(&damaged) {
        assert_eq!(tree.to_bytes(), damaged);
    }
}
