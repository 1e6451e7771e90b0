//! The level-order layout (k²-tree style): O(level) lookups with one rank
//! query per level.

use super::bits::{BitVec, PackedStates, RankBits};
use super::merge::Pyramid;
use super::{check_flat, digit, micro_triangle_count, Layout, PaperTree, TreeError};
use crate::micromap::{Format, State};
use crate::Level;
use alloc::vec;
use alloc::vec::Vec;

/// The paper's merged tree in level order: nodes are numbered breadth-first
/// (depth by depth, and within a depth by micro-triangle index, which is the
/// order of their parents and then of the digit), the bit of every node
/// above the map's level says internal (1) or leaf (0), and the leaf states
/// follow in node order. The nodes at the map's own level are always leaves,
/// so they have no bit.
///
/// The children of the internal node at position `p` are at
/// `1 + 4 rank1(p) + c`, `c = 0..=3` (`rank1(p)`: the ones before `p`), and
/// the leaf at position `x` holds state number `x - rank1(x)`. A rank
/// directory (one `u64` per 512 bits: the ones before the block and before
/// each of its word pairs; 12.5% of the bits, none up to 128 bits) makes
/// each rank a directory read plus two popcounts, without a loop.
///
/// Every value of this type is a valid, merged tree of its level.
///
/// ```
/// use micromap_index::micromap::{Format, State};
/// use micromap_index::succinct::{LevelOrderTree, PaperTree};
/// use micromap_index::Level;
///
/// let mut states = [State::Opaque; 16];
/// states[5] = State::UnknownOpaque;
/// let level = Level::new(2).unwrap();
/// let tree = LevelOrderTree::encode(level, Format::FourState, &states).unwrap();
/// // Depth 0: the root (internal); depth 1: leaf, internal, leaf, leaf;
/// // depth 2 (no bits): the four children of node 2.
/// assert_eq!(tree.internal_bits(), 5);
/// assert_eq!(tree.directory_bits(), 0);
/// assert_eq!(tree.get(5), Some(State::UnknownOpaque));
/// assert_eq!(tree.get(4), Some(State::Opaque));
/// let paper = PaperTree::encode(level, Format::FourState, &states).unwrap();
/// assert_eq!(LevelOrderTree::from_paper(&paper), tree);
/// ```
///
/// Two trees are equal when they encode the same map the same way, whatever
/// their top tables (lookup acceleration derived from the bits).
#[derive(Clone, Debug)]
pub struct LevelOrderTree {
    pub(super) level: Level,
    pub(super) format: Format,
    internal: RankBits,
    data: PackedStates,
    /// Depth the top table resolves (0: no table).
    top_depth: u32,
    /// Position of the first node at depth `top_depth`.
    top_start: usize,
    /// For every `top_depth`-digit prefix of an index: the node at depth
    /// `top_depth` on its path as its offset from `top_start`, or
    /// [`TOP_LEAF`] | the state's bits when the path ends in a leaf above.
    top: Vec<u16>,
}

impl PartialEq for LevelOrderTree {
    fn eq(&self, other: &Self) -> bool {
        (self.level, self.format, &self.internal, &self.data)
            == (other.level, other.format, &other.internal, &other.data)
    }
}

impl Eq for LevelOrderTree {}

impl core::hash::Hash for LevelOrderTree {
    fn hash<H: core::hash::Hasher>(&self, state: &mut H) {
        (self.level, self.format, &self.internal, &self.data).hash(state);
    }
}

/// Marks a top-table entry that is a leaf's state, not an offset (offsets
/// are below `4^TOP_MAX_DEPTH = 2^14`).
const TOP_LEAF: u16 = 1 << 15;
/// The top table's deepest depth: 16,384 entries, 32 KiB.
const TOP_MAX_DEPTH: u32 = 7;

/// The top table's depth for a tree of `internal_bits` internal/leaf bits
/// (before [`clamped_top_depth`]): the deepest table (16 bits per entry)
/// within 1/32 of the internal bits, which keeps the layout within 1.1x of
/// the paper's bits.
fn default_top_depth(internal_bits: u64) -> u32 {
    let mut depth = 0;
    while (16u64 << (2 * (depth + 1))) * 32 <= internal_bits {
        depth += 1;
    }
    depth
}

/// A top table's depth as a tree of `level` can have it: at most
/// `TOP_MAX_DEPTH`, and one below the map's level (the table covers only
/// nodes that have a bit).
fn clamped_top_depth(depth: u32, level: u32) -> u32 {
    depth.min(TOP_MAX_DEPTH).min(level.saturating_sub(1))
}

/// The nodes of the depth below the `count` nodes from position `start`:
/// they begin where those end, four per internal node among them (the
/// positions must lie within the bits).
fn next_depth(internal: &RankBits, start: usize, count: usize) -> (usize, usize) {
    let end = start + count;
    (end, 4 * (internal.rank1(end) - internal.rank1(start)))
}

impl LevelOrderTree {
    /// Encodes a flat micromap (`4^level` states in index order): Algorithm
    /// 1, then the merged tree breadth-first.
    ///
    /// Errors: as [`PaperTree::encode`].
    pub fn encode(level: Level, format: Format, states: &[State]) -> Result<Self, TreeError> {
        let deepest = check_flat(level, format, states)? as usize;
        let pyramid = Pyramid::merge_uniform_quadrants(deepest as u32, states)?;
        let mut internal = BitVec::new();
        let mut data = PackedStates::new(format);
        let mut nodes = vec![0usize];
        for depth in 0..=deepest {
            let mut next = Vec::new();
            for &index in &nodes {
                if let Some(state) = pyramid.uniform(depth, index) {
                    if depth < deepest {
                        internal.push(false);
                    }
                    data.push(state);
                } else {
                    internal.push(true);
                    next.extend(4 * index..4 * index + 4);
                }
            }
            nodes = next;
        }
        Ok(LevelOrderTree::assemble(
            level,
            format,
            RankBits::new(internal),
            data,
        ))
    }

    /// The tree from its parts, with the default top table: the bits are
    /// a tree of `level` (checked by every caller).
    fn assemble(level: Level, format: Format, internal: RankBits, data: PackedStates) -> Self {
        let depth = default_top_depth(internal.len() as u64);
        LevelOrderTree {
            level,
            format,
            internal,
            data,
            top_depth: 0,
            top_start: 0,
            top: Vec::new(),
        }
        .with_top_depth(depth)
    }

    /// The bits of a tree's lookup directory (rank directory and default
    /// top table) for a map of `level` with `internal_bits` internal/leaf
    /// bits: [`directory_bits`](Self::directory_bits) without the tree.
    pub(crate) fn directory_bits_for(level: u32, internal_bits: u64) -> u64 {
        let top = clamped_top_depth(default_top_depth(internal_bits), level);
        let entries = if top == 0 { 0 } else { 1u64 << (2 * top) };
        RankBits::directory_bits_for(internal_bits) + 16 * entries
    }

    /// The same tree with a top table of depth `depth`: one read resolves
    /// the first `depth` levels of every lookup, for `2 * 4^depth` bytes.
    /// The depth is clamped to `TOP_MAX_DEPTH` (7) and to one below the
    /// map's level (the table covers only nodes that have a bit); 0 drops
    /// the table.
    ///
    /// Trees come with the deepest table within 1/32 of their internal bits
    /// (what [`LevelOrderTree::directory_bits`] counts); a deeper one trades
    /// memory for lookup time (`docs/succinct.md` measures both).
    ///
    /// ```
    /// use micromap_index::micromap::{Format, State};
    /// use micromap_index::succinct::LevelOrderTree;
    /// use micromap_index::Level;
    ///
    /// let states: Vec<State> = (0..4096)
    ///     .map(|i| if i % 7 < 3 { State::Opaque } else { State::Transparent })
    ///     .collect();
    /// let tree = LevelOrderTree::encode(Level::new(6).unwrap(), Format::TwoState, &states).unwrap();
    /// let fast = tree.clone().with_top_depth(4);
    /// assert_eq!(fast.top_depth(), 4);
    /// assert!(fast.directory_bits() >= tree.directory_bits() + 16 * 256);
    /// assert!((0..4096).all(|i| fast.get(i) == tree.get(i)));
    /// assert_eq!(tree.with_top_depth(99).top_depth(), 5);
    /// ```
    #[must_use]
    pub fn with_top_depth(mut self, depth: u32) -> Self {
        let depth = clamped_top_depth(depth, self.level.get());
        let (mut start, mut count) = (0usize, 1usize);
        for _ in 0..depth {
            (start, count) = next_depth(&self.internal, start, count);
        }
        let top = if depth == 0 {
            Vec::new()
        } else {
            (0..1u64 << (2 * depth))
                .map(|prefix| {
                    let mut p = 0usize;
                    for d in 0..depth {
                        match self.node(p) {
                            Ok(first_child) => p = first_child + digit(prefix, depth, d),
                            Err(state) => return TOP_LEAF | u16::from(state.bits()),
                        }
                    }
                    // At most 4^depth nodes at this depth: below 2^14.
                    (p - start) as u16
                })
                .collect()
        };
        self.top_depth = depth;
        self.top_start = start;
        self.top = top;
        self
    }

    /// The depth of the top table (0: none).
    #[must_use]
    pub fn top_depth(&self) -> u32 {
        self.top_depth
    }

    /// The same tree in level order, from the paper's layout: the pre-order
    /// visits the nodes of each depth in index order, so sorting its nodes by
    /// depth (stably) is the level order.
    #[must_use]
    pub fn from_paper(paper: &PaperTree) -> Self {
        let deepest = paper.level().get() as usize;
        let format = paper.format();
        let mut bits_by_depth = vec![BitVec::new(); deepest];
        let mut leaves_by_depth = vec![PackedStates::new(format); deepest + 1];
        // Children still to come of each open internal node.
        let mut open: Vec<u8> = Vec::with_capacity(deepest + 1);
        let mut d = 0;
        for bit in paper.tree_bit_iter() {
            let depth = open.len();
            if depth < deepest {
                bits_by_depth[depth].push(bit);
            }
            if bit {
                open.push(4);
                continue;
            }
            // A valid tree has a state for every leaf.
            leaves_by_depth[depth].push(paper.data.get(d).unwrap_or(State::Transparent));
            d += 1;
            while let Some(left) = open.last_mut() {
                *left -= 1;
                if *left > 0 {
                    break;
                }
                open.pop();
            }
        }
        let mut internal = BitVec::new();
        for bits in &bits_by_depth {
            for t in 0..bits.len() {
                internal.push(bits.get(t));
            }
        }
        let mut data = PackedStates::new(format);
        for leaves in &leaves_by_depth {
            for i in 0..leaves.len() {
                data.push(leaves.get(i).unwrap_or(State::Transparent));
            }
        }
        LevelOrderTree::assemble(paper.level(), format, RankBits::new(internal), data)
    }

    /// Checks the structure: the bits of depth `d + 1` are four per one-bit
    /// of depth `d`, nothing is left over, one state per leaf, merged.
    pub(super) fn checked(
        level: u32,
        format: Format,
        bits: BitVec,
        data: PackedStates,
    ) -> Result<Self, TreeError> {
        let internal = RankBits::new(bits);
        let tree_bits = internal.len();
        let (mut start, mut count) = (0usize, 1usize);
        for _ in 0..level {
            if count == 0 {
                break;
            }
            if start + count > tree_bits {
                return Err(TreeError::TreeEndsEarly {
                    tree_bits: tree_bits as u64,
                });
            }
            (start, count) = next_depth(&internal, start, count);
        }
        if start != tree_bits {
            return Err(TreeError::TreeBitsLeftOver {
                used: start as u64,
                tree_bits: tree_bits as u64,
            });
        }
        // `count`: the nodes at the map's level (0 if the tree stops above).
        let leaves = tree_bits - internal.count_ones() + count;
        if leaves != data.len() {
            return Err(TreeError::LeafCount {
                leaves: leaves as u64,
                data: data.len() as u64,
            });
        }
        let tree = LevelOrderTree::assemble(Level(level as u8), format, internal, data);
        for p in 0..tree_bits {
            if let Ok(first_child) = tree.node(p) {
                let mut children = (first_child..first_child + 4).map(|x| tree.node(x));
                let first = children.next();
                if matches!(first, Some(Err(_))) && children.all(|child| Some(child) == first) {
                    return Err(TreeError::Unmerged { position: p as u64 });
                }
            }
        }
        Ok(tree)
    }

    /// The node at position `p`: `Ok(first child's position)` if internal,
    /// `Err(state)` if a leaf.
    #[inline]
    pub(super) fn node(&self, p: usize) -> Result<usize, State> {
        let (internal, rank) = self.internal.bit_and_rank(p);
        if internal {
            Ok(1 + 4 * rank)
        } else {
            // A valid tree has a state for every leaf position.
            Err(self.data.get(p - rank).unwrap_or(State::Transparent))
        }
    }

    /// Every leaf as a run `(first, count, state)` of equal states: the
    /// micro-triangles `first..first + count` (a whole subtree, so `count`
    /// is a power of four) all hold `state`. The runs tile `0..4^level`,
    /// one depth after another (not in index order). The walk holds the
    /// nodes of one depth, at most the tree's own leaf count, so a caller
    /// fills memory of its own.
    pub fn for_each_run(&self, mut run: impl FnMut(u64, u64, State)) {
        let deepest = self.level.get();
        // Breadth-first: (position, index) of the nodes of one depth.
        let mut nodes = vec![(0usize, 0u64)];
        for depth in 0..=deepest {
            let mut next = Vec::new();
            for &(p, index) in &nodes {
                match self.node(p) {
                    Ok(first_child) => {
                        next.extend((0..4).map(|c| (first_child + c as usize, 4 * index + c)));
                    }
                    Err(state) => {
                        let shift = 2 * (deepest - depth);
                        run(index << shift, 1 << shift, state);
                    }
                }
            }
            nodes = next;
        }
    }

    /// The state of micro-triangle `index`: from the root, one rank query
    /// per level to the child on the index's path. `None` if `index` is not
    /// below `4^level`.
    ///
    /// On x86-64 with `std` and without `popcnt` among the compile-time
    /// target features (the default target), it runs a copy compiled with
    /// hardware `popcnt` where the CPU has one (detected at run time).
    #[must_use]
    #[inline]
    pub fn get(&self, index: u64) -> Option<State> {
        crate::arch::with_popcnt(Lookup { tree: self, index })
    }

    /// [`LevelOrderTree::get`] without run-time dispatch: inlined into the
    /// dispatcher's `popcnt` copy.
    #[inline(always)]
    pub(crate) fn get_portable(&self, index: u64) -> Option<State> {
        let deepest = self.level.get();
        if index >= micro_triangle_count(deepest) {
            return None;
        }
        // The top table resolves the first `top_depth` levels in one read.
        let mut p = 0usize;
        if self.top_depth > 0 {
            let prefix = (index >> (2 * (deepest - self.top_depth))) as usize;
            // `index < 4^level`, so the prefix is below `4^top_depth`.
            let &entry = self.top.get(prefix)?;
            if entry & TOP_LEAF != 0 {
                return State::from_bits((entry & 3) as u8);
            }
            p = self.top_start + usize::from(entry);
        }
        for depth in self.top_depth..deepest {
            let (internal, rank) = self.internal.bit_and_rank(p);
            if !internal {
                return self.data.get(p - rank);
            }
            p = 1 + 4 * rank + digit(index, deepest, depth);
        }
        self.data.get(p - self.internal.count_ones())
    }

    /// The internal/leaf bits (one per node above the map's level).
    #[must_use]
    pub fn internal_bits(&self) -> u64 {
        self.internal.len() as u64
    }

    /// The lookup directory's bits: the rank directory (64 per 512
    /// internal bits, none up to 128) and the top table (16 per entry,
    /// `4^top_depth` entries; see [`LevelOrderTree::with_top_depth`]).
    #[must_use]
    pub fn directory_bits(&self) -> u64 {
        self.internal.directory_bits() + 16 * self.top.len() as u64
    }

    /// The data bits: leaves times the format's bits per state.
    #[must_use]
    pub fn data_bits(&self) -> u64 {
        self.data.bit_len() as u64
    }

    /// Internal bits, directory and data: the size in memory, in bits
    /// (before rounding each part up to whole words).
    #[must_use]
    pub fn total_bits(&self) -> u64 {
        self.internal_bits() + self.directory_bits() + self.data_bits()
    }

    /// The number of leaves.
    #[must_use]
    pub fn leaf_count(&self) -> u64 {
        self.data.len() as u64
    }

    /// The byte format of the [module docs](super), layout 1 (without the
    /// rank directory).
    #[must_use]
    pub fn to_bytes(&self) -> Vec<u8> {
        super::bytes::write(
            Layout::LevelOrder,
            self.level.get(),
            self.format,
            self.internal.bits(),
            &self.data,
        )
    }

    /// Reads [`to_bytes`](Self::to_bytes)'s output back, checking
    /// everything and rebuilding the directory: any other input is a
    /// [`TreeError`].
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, TreeError> {
        let (level, format, bits, data) = super::bytes::read(Layout::LevelOrder, bytes)?;
        Self::checked(level, format, bits, data)
    }
}

/// One [`LevelOrderTree::get`] as the body that [`crate::arch::with_popcnt`]
/// compiles with hardware `popcnt`.
struct Lookup<'a> {
    tree: &'a LevelOrderTree,
    index: u64,
}

impl crate::arch::PopcntBody for Lookup<'_> {
    type Output = Option<State>;
    #[inline(always)]
    fn run(self) -> Option<State> {
        self.tree.get_portable(self.index)
    }
}

/// The conversion from this layout to the paper's lives here, beside the
/// one from it: `paper.rs` knows nothing of the level-order layout.
impl PaperTree {
    /// The same tree in the paper's layout, from the level-order one.
    #[must_use]
    pub fn from_level_order(fast: &LevelOrderTree) -> Self {
        let mut tree = BitVec::new();
        let mut data = PackedStates::new(fast.format());
        // Pre-order over level-order positions, children pushed in reverse.
        let mut stack = vec![0usize];
        while let Some(p) = stack.pop() {
            match fast.node(p) {
                Ok(first_child) => {
                    tree.push(true);
                    for c in (0..4).rev() {
                        stack.push(first_child + c);
                    }
                }
                Err(state) => {
                    tree.push(false);
                    data.push(state);
                }
            }
        }
        PaperTree {
            level: fast.level(),
            format: fast.format(),
            tree,
            data,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use micromap_index_test_support::SplitMix64;

    /// The dispatched lookup (hardware `popcnt` where the CPU has it) and
    /// the portable one answer alike on every index of random maps with
    /// runs of equal states, levels 0..=7, both formats: the tests of the
    /// public `get` elsewhere cover only the path this CPU takes.
    #[test]
    fn dispatched_and_portable_lookups_agree() {
        let mut rng = SplitMix64::new(0x2545_f491_4f6c_dd1d);
        let mut next = move || rng.next_u64();
        for level in 0..=7u32 {
            for format in [Format::TwoState, Format::FourState] {
                let count = 1usize << (2 * level);
                let mut states = Vec::with_capacity(count);
                while states.len() < count {
                    let bits = (next() % 4) as u8;
                    let state = State::from_bits(match format {
                        Format::TwoState => bits & 1,
                        Format::FourState => bits,
                    })
                    .unwrap();
                    let run = 1usize << (2 * (next() % 4));
                    states.extend(core::iter::repeat(state).take(run.min(count - states.len())));
                }
                let level_n = Level::new(level).unwrap();
                let tree = LevelOrderTree::encode(level_n, format, &states).unwrap();
                for (i, &state) in states.iter().enumerate() {
                    assert_eq!(tree.get(i as u64), Some(state), "level {level} index {i}");
                    assert_eq!(tree.get_portable(i as u64), Some(state));
                }
                assert_eq!(tree.get(count as u64), None);
                assert_eq!(tree.get_portable(count as u64), None);
            }
        }
    }

    /// A level-9 map whose first sixteenth is one state (a leaf at depth 2)
    /// and whose rest is noise: the top table reaches depth 3, holds
    /// leaf entries and positions, and every index reads its state.
    #[test]
    fn top_table_answers_like_the_flat_map() {
        let mut rng = SplitMix64::new(0x9e37_79b9_7f4a_7c15);
        let count = 1usize << 18;
        let states: Vec<State> = (0..count)
            .map(|i| {
                let r = rng.next_u64();
                if i < count / 16 || r % 3 == 0 {
                    State::Opaque
                } else {
                    State::Transparent
                }
            })
            .collect();
        let tree =
            LevelOrderTree::encode(Level::new(9).unwrap(), Format::TwoState, &states).unwrap();
        assert_eq!(tree.top_depth, 3);
        assert!(tree.top[..4].iter().all(|&e| e & TOP_LEAF != 0));
        assert!(tree.top[4..].iter().all(|&e| e & TOP_LEAF == 0));
        assert_eq!(
            tree.directory_bits(),
            tree.internal.directory_bits() + 16 * 64
        );
        for top_depth in [0, 1, 3, 5, 7, 8] {
            let tree = tree.clone().with_top_depth(top_depth);
            let depth = top_depth.min(7);
            assert_eq!(tree.top_depth(), depth);
            assert_eq!(
                tree.top.len(),
                if depth == 0 { 0 } else { 1 << (2 * depth) }
            );
            for (i, &state) in states.iter().enumerate() {
                assert_eq!(tree.get_portable(i as u64), Some(state), "index {i}");
                assert_eq!(tree.get(i as u64), Some(state), "index {i}");
            }
        }
        let back = LevelOrderTree::from_bytes(&tree.to_bytes()).unwrap();
        assert_eq!(back, tree);
        assert_eq!(back.clone().with_top_depth(0), tree.with_top_depth(7));
    }
}
