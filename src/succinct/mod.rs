//! The paper's succinct 4-way tree over an opacity micromap, and a faster
//! layout of the same tree (needs the `alloc` feature; no `std`).
//!
//! "Succinct Opacity Micromaps" (Waldemarson & Doggett, 2024) compresses a
//! micromap in two steps and reads states straight from the result:
//!
//! 1. **Algorithm 1** builds the perfect 4-way tree bottom-up and merges
//!    every node whose four children are leaves with one state into a leaf
//!    (`merge` module). The children of micro-triangle `i` at level `n` are
//!    `4i..4i+3` at level `n + 1` (the curve is hierarchical), so merging is
//!    index arithmetic.
//! 2. **Algorithm 2** writes the merged tree depth-first: one tree bit per
//!    node, 1 internal and 0 leaf, for *every* node including the
//!    micro-triangles at the map's own level, and one state per leaf, in the
//!    same order, into a separate data vector ([`PaperTree`]).
//! 3. **Algorithm 3** looks a state up from the bits: at an internal node it
//!    steps to the first child and scans forward over the subtrees of the
//!    earlier siblings (a counter that gains 4 on each internal bit and loses
//!    1 per node) ([`PaperTree::get`], kept literally as the baseline and the
//!    oracle). Its cost grows about 4x per level.
//!
//! [`LevelOrderTree`] stores the same tree in level order (k²-tree style):
//! the internal/leaf bits of the nodes above the map's level, breadth-first,
//! with a rank directory, and the leaf states in the same order. The child
//! `c` of the node at position `p` is at `1 + 4 rank1(p) + c`, so a lookup
//! costs one rank query per level: O(level) instead of the scan. It drops
//! the bits of the deepest level (those nodes are always leaves) and adds
//! the directory (32 bits per 512 tree bits, none below 513 bits), so its
//! size stays close to the paper's.
//!
//! # Node order, and which reading of Algorithm 2
//!
//! Both layouts order siblings by digit: child `c` of node `i` is
//! micro-triangle `4i + c`, visited in the order `c = 0, 1, 2, 3`.
//! Algorithm 3's bit scan needs exactly this pre-order: to reach child `c` it
//! skips `c` whole subtrees that follow the parent's bit. Algorithm 2 as
//! printed pops a node from a stack and then "adds all child nodes to the
//! stack"; pushed in digit order, the next pop would be child 3 (a pre-order
//! with the children reversed, which Algorithm 3 would misread). We push the
//! children in reverse (3, 2, 1, 0) so that child 0 is popped first: the
//! reading under which Algorithms 2 and 3 agree, and the one the paper's
//! figure 4 shows. (The talk's bitscan slide tests `c > 0` in its loop
//! condition where it means the counter `child`, as the paper's Algorithm 3
//! has it.)
//!
//! # Byte format (version 1, little endian)
//!
//! | offset | size | field |
//! |---|---|---|
//! | 0 | 4 | magic `b"SOMT"` |
//! | 4 | 1 | version, 1 |
//! | 5 | 1 | layout: 0 paper depth-first ([`PaperTree`]), 1 level order ([`LevelOrderTree`]) |
//! | 6 | 1 | level, `0..=16` |
//! | 7 | 1 | format: 1 two-state, 2 four-state (the Vulkan/DXR value) |
//! | 8 | 8 | `tree_bits`: the number of tree bits (`u64`) |
//! | 16 | 8 | `leaves`: the number of leaf states (`u64`) |
//! | 24 | `ceil(tree_bits / 8)` | the tree bits, least-significant bit of each byte first |
//! | ... | `ceil(leaves * b / 8)` | the leaf states, `b` = 1 or 2 bits each, packed like micromap data |
//!
//! Nothing follows; the unused high bits of each section's last byte are
//! zero. The level-order rank directory is not stored: it is rebuilt on
//! load (it is derived data, and a stored copy would need checking too).
//! [`PaperTree::from_bytes`] and [`LevelOrderTree::from_bytes`] accept
//! exactly the bytes that `to_bytes` writes for some micromap: every other
//! input is a [`TreeError`], never a panic. In particular the tree must be
//! *merged* (no internal node with four leaf children of one state), so each
//! micromap has one encoding.
//!
//! ```
//! use micromap_index::micromap::{Format, State};
//! use micromap_index::succinct::{LevelOrderTree, PaperTree};
//! use micromap_index::Level;
//!
//! // Level 1: three opaque micro-triangles and one transparent one.
//! let states = [State::Opaque, State::Opaque, State::Transparent, State::Opaque];
//! let level = Level::new(1).unwrap();
//! let paper = PaperTree::encode(level, Format::TwoState, &states).unwrap();
//! assert_eq!(paper.tree_bit_string(), "10000"); // root internal, four leaves
//! assert_eq!(paper.data_bits(), 4);
//! assert_eq!(paper.get(2), Some(State::Transparent)); // Algorithm 3
//!
//! let fast = LevelOrderTree::from_paper(&paper);
//! assert_eq!(fast.get(2), Some(State::Transparent)); // one rank per level
//! assert_eq!(fast.decode().unwrap(), states);
//! let bytes = fast.to_bytes();
//! assert_eq!(LevelOrderTree::from_bytes(&bytes).unwrap(), fast);
//! ```

mod bits;
mod bytes;
mod level_order;
mod merge;
mod paper;
mod sizes;

pub use level_order::LevelOrderTree;
pub use paper::PaperTree;
pub(crate) use sizes::packed_tree_sizes;
pub use sizes::{tree_sizes, TreeSizes};

use crate::micromap::{Format, Micromap, MicromapError, State};
use crate::Level;
use alloc::vec::Vec;
use core::fmt;

/// The highest level a tree accepts: the level range of the Vulkan
/// reference index ([`crate::spec::index_f32`], [`crate::SpecLevel`]), through which
/// `(u, v)` lookups go.
pub const MAX_TREE_LEVEL: u32 = 16;

/// The two stored layouts of the tree (byte 5 of the byte format).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Layout {
    /// The paper's depth-first bits and data ([`PaperTree`]).
    PaperDfs = 0,
    /// Level order with a rank directory ([`LevelOrderTree`]).
    LevelOrder = 1,
}

/// A part of the byte format, named in errors.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Section {
    /// The tree bits.
    Tree,
    /// The leaf states.
    Data,
}

/// Why states, tree bits or bytes do not make a tree.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum TreeError {
    /// The memory for `bytes` bytes (a flat map's states or the merge
    /// pyramid's codes, one byte each) cannot be had.
    AllocationFailed {
        /// The bytes asked for.
        bytes: u64,
    },
    /// The level is above [`MAX_TREE_LEVEL`].
    LevelTooHigh {
        /// The level given.
        level: u32,
        /// [`MAX_TREE_LEVEL`].
        max: u32,
    },
    /// A flat micromap of `level` needs `4^level` states.
    StateCount {
        /// The level.
        level: u32,
        /// `4^level`.
        expected: u64,
        /// The number given.
        actual: u64,
    },
    /// A 2-state micromap or tree was given an unknown state.
    StateNotInFormat {
        /// The position of the state (micro-triangle index, or leaf number).
        position: u64,
        /// The state.
        state: State,
    },
    /// The tree bits end before the tree is complete.
    TreeEndsEarly {
        /// The number of tree bits.
        tree_bits: u64,
    },
    /// The tree is complete before its bits end.
    TreeBitsLeftOver {
        /// The bits the tree uses.
        used: u64,
        /// The number of tree bits.
        tree_bits: u64,
    },
    /// An internal node at the map's own level: the tree is deeper than the
    /// level.
    DeeperThanLevel {
        /// The position of its tree bit.
        position: u64,
        /// The level.
        level: u32,
    },
    /// An internal node whose four children are leaves with one state:
    /// Algorithm 1 would have merged it, so no micromap encodes to this.
    Unmerged {
        /// The position of its tree bit.
        position: u64,
    },
    /// The number of leaf states is not the number of leaves.
    LeafCount {
        /// Leaves in the tree.
        leaves: u64,
        /// States given.
        data: u64,
    },
    /// The bytes end before the header or a section does.
    Truncated {
        /// Bytes needed.
        needed: u64,
        /// Bytes given.
        available: u64,
    },
    /// Bytes follow the data section.
    TrailingBytes {
        /// Bytes the header declares.
        expected: u64,
        /// Bytes given.
        actual: u64,
    },
    /// The bytes do not start with `b"SOMT"`.
    BadMagic,
    /// A version other than 1.
    UnsupportedVersion {
        /// The version byte.
        version: u8,
    },
    /// The layout byte is not the layout being read.
    WrongLayout {
        /// The layout being read.
        expected: Layout,
        /// The layout byte.
        found: u8,
    },
    /// The format byte is not 1 or 2.
    BadFormat {
        /// The format byte.
        raw: u8,
    },
    /// Bits past the end of a section's last byte are set.
    UnusedBitsSet {
        /// The section.
        section: Section,
    },
}

impl fmt::Display for TreeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TreeError::AllocationFailed { bytes } => {
                write!(f, "the memory for {bytes} bytes of states cannot be had")
            }
            TreeError::LevelTooHigh { level, max } => {
                write!(f, "level {level} is too high: trees take levels 0..={max}")
            }
            TreeError::StateCount {
                level,
                expected,
                actual,
            } => write!(
                f,
                "a level-{level} micromap has {expected} states, got {actual}"
            ),
            TreeError::StateNotInFormat { position, state } => write!(
                f,
                "state {} ({state}) at position {position} is not a 2-state value",
                state.bits()
            ),
            TreeError::TreeEndsEarly { tree_bits } => {
                write!(
                    f,
                    "the {tree_bits} tree bits end before the tree is complete"
                )
            }
            TreeError::TreeBitsLeftOver { used, tree_bits } => write!(
                f,
                "the tree is complete after {used} of its {tree_bits} tree bits"
            ),
            TreeError::DeeperThanLevel { position, level } => write!(
                f,
                "tree bit {position} marks an internal node at the map's level {level}"
            ),
            TreeError::Unmerged { position } => write!(
                f,
                "tree bit {position} marks an internal node whose four children are leaves \
                 with one state (Algorithm 1 merges those)"
            ),
            TreeError::LeafCount { leaves, data } => {
                write!(f, "the tree has {leaves} leaves but {data} leaf states")
            }
            TreeError::Truncated { needed, available } => {
                write!(f, "truncated: {needed} bytes needed, {available} given")
            }
            TreeError::TrailingBytes { expected, actual } => write!(
                f,
                "trailing bytes: the header declares {expected} bytes, {actual} given"
            ),
            TreeError::BadMagic => f.write_str("not a tree: the magic is not \"SOMT\""),
            TreeError::UnsupportedVersion { version } => {
                write!(f, "unsupported version {version} (this reader knows 1)")
            }
            TreeError::WrongLayout { expected, found } => {
                write!(f, "layout byte {found}, expected {}", *expected as u8)
            }
            TreeError::BadFormat { raw } => {
                write!(f, "format {raw} is neither 1 (2-state) nor 2 (4-state)")
            }
            TreeError::UnusedBitsSet { section } => write!(
                f,
                "unused bits set at the end of the {} section",
                match section {
                    Section::Tree => "tree",
                    Section::Data => "data",
                }
            ),
        }
    }
}

impl core::error::Error for TreeError {}

/// The level, if a tree can have it.
fn tree_level(level: Level) -> Result<u32, TreeError> {
    if level.get() > MAX_TREE_LEVEL {
        Err(TreeError::LevelTooHigh {
            level: level.get(),
            max: MAX_TREE_LEVEL,
        })
    } else {
        Ok(level.get())
    }
}

/// Checks a flat micromap: `4^level` states, each one the format holds.
fn check_flat(level: Level, format: Format, states: &[State]) -> Result<u32, TreeError> {
    let level = tree_level(level)?;
    let expected = 1u64 << (2 * level);
    if states.len() as u64 != expected {
        return Err(TreeError::StateCount {
            level,
            expected,
            actual: states.len() as u64,
        });
    }
    check_states(format, states)?;
    Ok(level)
}

/// Every state is one the format holds.
fn check_states(format: Format, states: &[State]) -> Result<(), TreeError> {
    match states.iter().position(|&s| !format.holds(s)) {
        Some(i) => Err(TreeError::StateNotInFormat {
            position: i as u64,
            state: states[i],
        }),
        None => Ok(()),
    }
}

/// The child digit (0..=3) that the path to micro-triangle `index` of a
/// level-`level` map takes below depth `depth`.
#[inline]
fn digit(index: u64, level: u32, depth: u32) -> usize {
    ((index >> (2 * (level - 1 - depth))) & 3) as usize
}

/// An empty vector with room for exactly `4^level` states, allocated
/// fallibly.
fn states_of_level(level: u32) -> Result<Vec<State>, TreeError> {
    room(micro_triangle_count(level))
}

/// An empty vector with room for exactly `len` one-byte items (states or
/// their codes), allocated fallibly: a tree's flat map and its merge
/// pyramid are sized by its level, up to 4 GiB at level 16.
fn room<T>(len: u64) -> Result<Vec<T>, TreeError> {
    let mut list = Vec::new();
    usize::try_from(len)
        .ok()
        .and_then(|len| list.try_reserve_exact(len).ok())
        .ok_or(TreeError::AllocationFailed {
            bytes: len.saturating_mul(core::mem::size_of::<T>() as u64),
        })?;
    Ok(list)
}

/// `4^level` as the number of micro-triangles, for index checks.
#[inline]
fn micro_triangle_count(level: u32) -> u64 {
    1u64 << (2 * level)
}

/// What both layouts share: their level and format, the lookup of a ray hit,
/// and the conversions to and from the packed [`Micromap`], written once.
macro_rules! common_tree_methods {
    ($tree:ident) => {
        impl $tree {
            /// The subdivision level.
            #[must_use]
            pub fn level(&self) -> Level {
                self.level
            }

            /// The format (bits per leaf state).
            #[must_use]
            pub fn format(&self) -> Format {
                self.format
            }

            /// The state a ray hit at `(u, v)` reads: the Vulkan reference
            /// index in binary32 ([`spec::index_f32`](crate::spec::index_f32), the GPU's answer for
            /// every pair of `f32`, NaN and points outside the triangle
            /// included), then `get`. Always `Some` (the index is in range at
            /// every level a tree takes).
            #[must_use]
            #[inline]
            pub fn get_f32(&self, u: f32, v: f32) -> Option<State> {
                // Tree levels are at most MAX_TREE_LEVEL = SpecLevel::MAX.
                let level = crate::SpecLevel(self.level.0);
                self.get(u64::from(crate::spec::index_f32(u, v, level)))
            }

            /// Encodes a packed micromap (its level, format and states).
            ///
            /// ```
            /// use micromap_index::micromap::{Format, Micromap, State};
            #[doc = concat!("use micromap_index::succinct::", stringify!($tree), ";")]
            /// use micromap_index::Level;
            /// let map = Micromap::from_index_fn(Level::new(3).unwrap(), Format::TwoState, |i| {
            ///     if i < 16 { State::Opaque } else { State::Transparent }
            /// }).unwrap();
            #[doc = concat!("let tree = ", stringify!($tree), "::from_micromap(&map).unwrap();")]
            /// assert_eq!(tree.to_micromap().unwrap(), map);
            /// ```
            pub fn from_micromap(map: &Micromap) -> Result<Self, TreeError> {
                let mut states = states_of_level(map.level().get())?;
                states.extend(map.states());
                Self::encode(map.level(), map.format(), &states)
            }

            /// The packed micromap the tree encodes, filled run by run; an
            /// error only if the memory for it cannot be had.
            pub fn to_micromap(&self) -> Result<Micromap, MicromapError> {
                let mut map = Micromap::new(self.level(), self.format())?;
                let mut failed = None;
                self.for_each_run(|first, count, state| {
                    if let Err(e) = map.fill(first, count, state) {
                        failed.get_or_insert(e);
                    }
                });
                failed.map_or(Ok(map), Err)
            }

            /// The flat micromap: `4^level` states in index order, or
            /// [`TreeError::AllocationFailed`] where the memory cannot be
            /// had (a level-16 tree of 24 bytes decodes to 4 GiB).
            pub fn decode(&self) -> Result<Vec<State>, TreeError> {
                let mut out = states_of_level(self.level().get())?;
                // The room was had, so the count fits `usize`.
                let len = micro_triangle_count(self.level().get()) as usize;
                out.resize(len, State::Transparent);
                self.for_each_run(|first, count, state| {
                    // The runs tile 0..4^level, which fits `out`.
                    out[first as usize..(first + count) as usize].fill(state);
                });
                Ok(out)
            }
        }
    };
}

common_tree_methods!(PaperTree);
common_tree_methods!(LevelOrderTree);
