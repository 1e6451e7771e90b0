//! The paper's layout: depth-first tree bits and leaf data (Algorithms 2
//! and 3).

use super::bits::{BitVec, PackedStates};
use super::merge::Pyramid;
use super::{check_flat, check_states, digit, micro_triangle_count, tree_level, Layout, TreeError};
use crate::micromap::{Format, State};
use crate::Level;
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

/// A micromap as the paper stores it: one tree bit per node of the merged
/// tree in pre-order (1 internal, 0 leaf; children in digit order 0..=3),
/// and one state per leaf in the same order. Lookups run Algorithm 3.
///
/// Every value of this type is a valid, merged tree of its level (the
/// constructors check), so lookups never leave the bits.
///
/// ```
/// use micromap_index::micromap::{Format, State};
/// use micromap_index::succinct::PaperTree;
/// use micromap_index::Level;
///
/// // A level-2 map: quadrant 1 is mixed, the rest is uniform.
/// let mut states = [State::Opaque; 16];
/// states[5] = State::UnknownOpaque;
/// let tree = PaperTree::encode(Level::new(2).unwrap(), Format::FourState, &states).unwrap();
/// assert_eq!(tree.tree_bit_string(), "101000000");
/// assert_eq!(tree.leaf_states(), [1, 1, 3, 1, 1, 1, 1].map(|b| State::from_bits(b).unwrap()));
/// for (i, &state) in states.iter().enumerate() {
///     assert_eq!(tree.get(i as u64), Some(state));
/// }
/// assert_eq!(tree.get(16), None);
/// ```
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct PaperTree {
    pub(super) level: Level,
    pub(super) format: Format,
    pub(super) tree: BitVec,
    pub(super) data: PackedStates,
}

impl PaperTree {
    /// Encodes a flat micromap (`4^level` states in index order):
    /// Algorithm 1 (merge uniform quadrants), then Algorithm 2 (depth-first
    /// bits, children pushed in reverse so child 0 is popped first; see the
    /// [module docs](super)).
    ///
    /// Errors: [`TreeError::LevelTooHigh`] above level 16,
    /// [`TreeError::StateCount`] unless there are `4^level` states,
    /// [`TreeError::StateNotInFormat`] for an unknown state in a 2-state map,
    /// [`TreeError::AllocationFailed`] where the merge pyramid (`4^level *
    /// 4/3` bytes) cannot be had.
    pub fn encode(level: Level, format: Format, states: &[State]) -> Result<Self, TreeError> {
        let level = check_flat(level, format, states)?;
        let pyramid = Pyramid::merge_uniform_quadrants(level, states)?;
        let mut tree = BitVec::new();
        let mut data = PackedStates::new(format);
        // Algorithm 2 with an explicit stack of (depth, index).
        let mut stack = vec![(0usize, 0usize)];
        while let Some((depth, index)) = stack.pop() {
            if let Some(state) = pyramid.uniform(depth, index) {
                tree.push(false);
                data.push(state);
            } else {
                tree.push(true);
                // Reversed, so that child 0 is popped (written) first.
                for c in (0..4).rev() {
                    stack.push((depth + 1, 4 * index + c));
                }
            }
        }
        Ok(PaperTree {
            level: Level(level as u8),
            format,
            tree,
            data,
        })
    }

    /// A tree from its bits and leaf states, checked: the bits must be one
    /// complete pre-order tree no deeper than `level`, merged (no internal
    /// node with four leaf children of one state), with one state per leaf,
    /// each one the format holds.
    pub fn from_parts(
        level: Level,
        format: Format,
        tree_bits: impl IntoIterator<Item = bool>,
        leaf_states: &[State],
    ) -> Result<Self, TreeError> {
        let level = tree_level(level)?;
        check_states(format, leaf_states)?;
        let mut tree = BitVec::new();
        for bit in tree_bits {
            tree.push(bit);
        }
        let mut data = PackedStates::new(format);
        for &state in leaf_states {
            data.push(state);
        }
        Self::checked(level, format, tree, data)
    }

    /// Checks the structure (see [`from_parts`](Self::from_parts)).
    pub(super) fn checked(
        level: u32,
        format: Format,
        tree: BitVec,
        data: PackedStates,
    ) -> Result<Self, TreeError> {
        /// An internal node whose children are being read.
        struct Frame {
            position: usize,
            seen: u8,
            /// The state shared by every child so far if all were leaves.
            leaves_alike: Option<State>,
        }
        let mut stack: Vec<Frame> = Vec::with_capacity(level as usize + 1);
        let mut t = 0usize;
        let mut leaves = 0usize;
        loop {
            if t >= tree.len() {
                return Err(TreeError::TreeEndsEarly {
                    tree_bits: tree.len() as u64,
                });
            }
            // The node's outcome as its parent sees it: Some(state) for a
            // leaf whose state is known, None otherwise.
            let mut outcome = if tree.get(t) {
                if stack.len() == level as usize {
                    return Err(TreeError::DeeperThanLevel {
                        position: t as u64,
                        level,
                    });
                }
                stack.push(Frame {
                    position: t,
                    seen: 0,
                    leaves_alike: None,
                });
                t += 1;
                continue;
            } else {
                t += 1;
                leaves += 1;
                data.get(leaves - 1)
            };
            // Close every parent this node completes.
            loop {
                let Some(frame) = stack.last_mut() else {
                    // The root is complete.
                    if t != tree.len() {
                        return Err(TreeError::TreeBitsLeftOver {
                            used: t as u64,
                            tree_bits: tree.len() as u64,
                        });
                    }
                    if leaves != data.len() {
                        return Err(TreeError::LeafCount {
                            leaves: leaves as u64,
                            data: data.len() as u64,
                        });
                    }
                    return Ok(PaperTree {
                        level: Level(level as u8),
                        format,
                        tree,
                        data,
                    });
                };
                frame.leaves_alike = match (frame.seen, outcome) {
                    (0, first) => first,
                    (_, next) if next == frame.leaves_alike => next,
                    _ => None,
                };
                frame.seen += 1;
                if frame.seen < 4 {
                    break;
                }
                if frame.leaves_alike.is_some() {
                    return Err(TreeError::Unmerged {
                        position: frame.position as u64,
                    });
                }
                stack.pop();
                outcome = None;
            }
        }
    }

    /// Every leaf as a run `(first, count, state)` of equal states: the
    /// micro-triangles `first..first + count` (a whole subtree, so `count`
    /// is a power of four) all hold `state`. The runs tile `0..4^level`
    /// and come in index order. Nothing is allocated beyond a stack of
    /// `3 level + 1` entries, so a caller fills memory of its own.
    pub fn for_each_run(&self, mut run: impl FnMut(u64, u64, State)) {
        // The same walk as Algorithm 2, reading instead of writing.
        let mut stack = vec![(0u32, 0u64)];
        let (mut t, mut d) = (0usize, 0usize);
        while let Some((depth, index)) = stack.pop() {
            let internal = self.tree.get(t);
            t += 1;
            if internal {
                for c in (0..4).rev() {
                    stack.push((depth + 1, 4 * index + c));
                }
            } else {
                let state = self.data.get(d).unwrap_or(State::Transparent);
                d += 1;
                let shift = 2 * (self.level.get() - depth);
                run(index << shift, 1 << shift, state);
            }
        }
    }

    /// The state of micro-triangle `index` by Algorithm 3, kept literally:
    /// at an internal node, step past its bit and let `bitscan` skip the
    /// subtrees of the `child` earlier siblings. `None` if `index` is not
    /// below `4^level`.
    #[must_use]
    pub fn get(&self, index: u64) -> Option<State> {
        if index >= micro_triangle_count(self.level.get()) {
            return None;
        }
        let (mut t, mut d) = (0usize, 0usize);
        let mut depth = 0;
        loop {
            if self.tree.get(t) {
                t += 1;
                // `step(u, v)` of the paper: the next base-4 digit of the index.
                let child = digit(index, self.level.get(), depth);
                depth += 1;
                (t, d) = self.bitscan(child, t, d);
            } else {
                return self.data.get(d);
            }
        }
    }

    /// Algorithm 3's `bitscan`: from the first child's bit `t` (and leaf
    /// count `d`), skip `child` whole subtrees. The counter `child` gains 4
    /// at each internal node (its children are still to skip) and loses 1
    /// per node.
    #[inline]
    fn bitscan(&self, child: usize, mut t: usize, mut d: usize) -> (usize, usize) {
        let mut child = child;
        while t < self.tree.len() && child > 0 {
            if self.tree.get(t) {
                child += 4;
            } else {
                d += 1;
            }
            child -= 1;
            t += 1;
        }
        (t, d)
    }

    /// The number of tree bits (nodes).
    #[must_use]
    pub fn tree_bits(&self) -> u64 {
        self.tree.len() as u64
    }

    /// The number of data bits: leaves times the format's bits per state.
    #[must_use]
    pub fn data_bits(&self) -> u64 {
        self.data.bit_len() as u64
    }

    /// Tree bits plus data bits: the paper's size.
    #[must_use]
    pub fn total_bits(&self) -> u64 {
        self.tree_bits() + self.data_bits()
    }

    /// The number of leaves.
    #[must_use]
    pub fn leaf_count(&self) -> u64 {
        self.data.len() as u64
    }

    /// The tree bits, in order.
    pub fn tree_bit_iter(&self) -> impl Iterator<Item = bool> + '_ {
        (0..self.tree.len()).map(|t| self.tree.get(t))
    }

    /// The tree bits as a string of `0` and `1`.
    #[must_use]
    pub fn tree_bit_string(&self) -> String {
        self.tree_bit_iter()
            .map(|bit| if bit { '1' } else { '0' })
            .collect()
    }

    /// The leaf states, in order.
    #[must_use]
    pub fn leaf_states(&self) -> Vec<State> {
        (0..self.data.len())
            .filter_map(|d| self.data.get(d))
            .collect()
    }

    /// The byte format of the [module docs](super), layout 0.
    #[must_use]
    pub fn to_bytes(&self) -> Vec<u8> {
        super::bytes::write(
            Layout::PaperDfs,
            self.level.get(),
            self.format,
            &self.tree,
            &self.data,
        )
    }

    /// Reads [`to_bytes`](Self::to_bytes)'s output back, checking
    /// everything: any other input is a [`TreeError`].
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, TreeError> {
        let (level, format, tree, data) = super::bytes::read(Layout::PaperDfs, bytes)?;
        Self::checked(level, format, tree, data)
    }
}
