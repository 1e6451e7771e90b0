//! The exhaustive proof: the walk equals the reference on every face of the
//! level-`n` lattice, hence at every real point of the closed triangle.
//!
//! Both [`uv2index`] and the reference ([`spec`]) only
//! compare the point against lines of the level-`n` lattice, so each is
//! constant on every face of it (vertex, open edge, open micro-triangle;
//! see [`crate::lattice`]). One point per face therefore decides all real
//! points. `docs/verification.md` spells the argument out and records the
//! results; `micromap-lab prove` runs it.
//!
//! # How every face is reached in a few nanoseconds
//!
//! A direct walk costs `level` steps per face. Instead the faces are
//! enumerated down the subdivision tree, and the walk's steps are
//! tabulated once:
//!
//! * One [`Walk::step`] compares the local `(u, v, w)` only with `1/2`, so
//!   its outcome (digit, new flags, the affine map into the child) is the
//!   same on each face of the *local* level-1 lattice (19 faces: 6
//!   vertices, 9 open edges, 4 open children).
//! * So the set of points whose walk reaches a node is a union of the
//!   node's own faces: always its interior, some of its 3 open edges, some
//!   of its 3 vertices (its *owned mask*). Which faces each child owns, and
//!   the child's digit and flags, depend only on the node's flags and mask.
//! * [`Table::build`] runs the real step (on exact [`Fixed64`] points) once
//!   on a representative of every owned local face of every reachable
//!   state, and reads off each child's digit, flags, owned mask and where
//!   its corners are among the parent's corners and edge midpoints.
//! * A depth-first descent then carries the index prefix and the three
//!   global corners of each micro-triangle down to the nodes one level
//!   above the leaves; the faces their four leaves own come from a list per
//!   state, so the hot loop has no branch per leaf. Every face is compared
//!   with the reference: its cell by [`spec::cell_dyadic`], the reference's
//!   integer half once per leaf (a function of the cell, shared by the
//!   faces whose cell is the leaf interior's). Each face is owned by
//!   exactly one leaf (the walk is a function), which the face count
//!   checks.
//!
//! ```
//! use micromap_index_lab::prove::{prove_level, Progress, Settings, WalkVersion};
//! use micromap_index_lab::lattice;
//! use micromap_index::{Level};
//!
//! let level = Level::new(6).unwrap();
//! let report = prove_level(level, &Settings::default(), &Progress::new()).unwrap();
//! assert_eq!(report.faces_checked, lattice::face_count(level));
//! assert_eq!(report.mismatches(), 0);
//!
//! // The talk's version 1 fails the same check on some lattice edges and vertices.
//! let settings = Settings { walk: WalkVersion::Version1, ..Settings::default() };
//! let report = prove_level(level, &settings, &Progress::new()).unwrap();
//! assert!(report.mismatches() > 0);
//! ```

mod descent;
mod exhaustive;
mod sample;
mod table;
#[cfg(test)]
mod tests;

pub use descent::for_each_face;
#[allow(clippy::wildcard_imports)]
use descent::*;
pub use exhaustive::prove_level;
#[allow(clippy::wildcard_imports)]
use exhaustive::*;
pub use sample::sample_level;
pub use table::Table;
#[allow(clippy::wildcard_imports)]
use table::*;

use crate::lattice::{self, Face, FaceKind};
use crate::rng::SplitMix64;
use micromap_index::num::Fixed64;
use micromap_index::uv2index::{self, Walk};
use micromap_index::{spec, Error, Level};
use std::fmt;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::Instant;

/// Which walk is checked.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum WalkVersion {
    /// The paper's walk with flip flags ([`Walk::step`]).
    #[default]
    Version2,
    /// The talk's version 1 with rotations ([`Walk::step_version1`]); it is
    /// expected to fail, which shows that the check can fail.
    Version1,
}

impl WalkVersion {
    /// A short name: `version2` or `version1`.
    ///
    /// ```
    /// use micromap_index_lab::prove::WalkVersion;
    /// assert_eq!(WalkVersion::Version1.name(), "version1");
    /// ```
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            WalkVersion::Version2 => "version2",
            WalkVersion::Version1 => "version1",
        }
    }

    pub(super) fn step(self, walk: &mut Walk<Fixed64>) -> u8 {
        match self {
            WalkVersion::Version2 => walk.step(),
            WalkVersion::Version1 => micromap_index::internals::step_version1(walk),
        }
    }

    /// The whole walk on one point, step by step (used by the sampler).
    pub(super) fn index(self, u: Fixed64, v: Fixed64, level: Level) -> u64 {
        match self {
            WalkVersion::Version2 => uv2index::index_unchecked(u, v, level),
            WalkVersion::Version1 => {
                micromap_index::internals::index_version1_unchecked(u, v, level)
            }
        }
    }
}

/// Which form of the Vulkan reference the walk is compared with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Reference {
    /// The reference's steps over the reals with its 32-bit integer half
    /// ([`spec::index_from_cell`]): levels `0..=16`.
    #[default]
    Spec,
    /// The same with the integer half widened to 64 bits
    /// ([`spec::wide_index_from_cell`]): levels `0..=32`.
    SpecWide,
}

impl Reference {
    /// A short name: `spec` or `spec-wide`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Reference::Spec => "spec",
            Reference::SpecWide => "spec-wide",
        }
    }

    /// The highest level this form of the reference computes valid indices
    /// for.
    ///
    /// ```
    /// use micromap_index_lab::prove::Reference;
    /// assert_eq!(Reference::Spec.max_level(), 16);
    /// assert_eq!(Reference::SpecWide.max_level(), 32);
    /// ```
    #[must_use]
    pub fn max_level(self) -> u32 {
        match self {
            Reference::Spec => spec::MAX_LEVEL,
            Reference::SpecWide => Level::MAX,
        }
    }
}

/// What to check and with how many threads.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Settings {
    /// The walk under test.
    pub walk: WalkVersion,
    /// The reference it must equal.
    pub reference: Reference,
    /// Worker threads; `0` means one per available core.
    pub threads: usize,
    /// How many mismatches to keep as examples (the ones with the smallest
    /// walk index, then in face order; the count of all is always kept).
    pub examples: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            walk: WalkVersion::Version2,
            reference: Reference::Spec,
            threads: 0,
            examples: 5,
        }
    }
}

/// Shared between a running check and whoever watches it: how much is done
/// and a flag that asks it to stop. A stopped check returns what it
/// finished, marked incomplete.
///
/// ```
/// use micromap_index_lab::prove::{prove_level, Progress, Settings};
/// use micromap_index::Level;
/// let progress = Progress::new();
/// progress.cancel();
/// let report = prove_level(Level::new(12).unwrap(), &Settings::default(), &progress).unwrap();
/// assert!(!report.complete);
/// ```
#[derive(Debug, Default)]
pub struct Progress {
    done: AtomicU64,
    total: AtomicU64,
    cancelled: AtomicBool,
}

impl Progress {
    /// Nothing done, not cancelled.
    #[must_use]
    pub fn new() -> Self {
        Progress::default()
    }

    /// Asks the running check to stop after the work units in flight.
    pub fn cancel(&self) {
        self.cancelled.store(true, Ordering::Relaxed);
    }

    /// Whether [`Progress::cancel`] was called.
    pub fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }

    /// `(done, total)` work units of the level being checked (all units are
    /// about the same size).
    pub fn units(&self) -> (u64, u64) {
        (
            self.done.load(Ordering::Relaxed),
            self.total.load(Ordering::Relaxed),
        )
    }

    pub(super) fn start(&self, total: u64) {
        self.done.store(0, Ordering::Relaxed);
        self.total.store(total, Ordering::Relaxed);
    }

    pub(super) fn finish_unit(&self) {
        self.done.fetch_add(1, Ordering::Relaxed);
    }
}

/// How a level was checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// Every face of the lattice (a proof for the level).
    Exhaustive,
    /// Uniformly random faces, each walked step by step.
    Sampled {
        /// The random seed (the same seed draws the same faces).
        seed: u64,
    },
}

/// One face where the walk and the reference disagree.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Mismatch {
    /// The face (its representative point is exact: `x, y / 2^(level+2)`).
    pub face: Face,
    /// The walk's index.
    pub walk: u64,
    /// The reference's index.
    pub reference: u64,
}

/// The outcome of checking one level.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelReport {
    /// The level.
    pub level: Level,
    /// The walk checked.
    pub walk: WalkVersion,
    /// The reference compared with.
    pub reference: Reference,
    /// Every face, or a sample.
    pub method: Method,
    /// Faces compared.
    pub faces_checked: u128,
    /// Faces that had to be compared: the level's face count
    /// ([`lattice::face_count`]) for a proof, the sample size for a sample.
    /// Equal to `faces_checked` when the run completed.
    pub faces_expected: u128,
    /// Mismatches per face kind, in the order of [`FACE_KINDS`].
    pub mismatches_by_kind: [u128; 6],
    /// The first few mismatches (see [`Settings::examples`]).
    pub examples: Vec<Mismatch>,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// `false` if the run was cancelled before every face was compared.
    pub complete: bool,
}

impl LevelReport {
    /// All mismatches found.
    #[must_use]
    pub fn mismatches(&self) -> u128 {
        self.mismatches_by_kind.iter().sum()
    }

    /// Whether this report proves the walk equal to the reference at the
    /// level: every face was compared, the count is the face count, and
    /// none differed.
    #[must_use]
    pub fn is_proof(&self) -> bool {
        self.method == Method::Exhaustive
            && self.complete
            && self.faces_checked == self.faces_expected
            && self.mismatches() == 0
    }
}

/// The face kinds in the order [`LevelReport::mismatches_by_kind`] uses:
/// [`FaceKind::ALL`] (the lattice owns the order).
pub const FACE_KINDS: [FaceKind; 6] = FaceKind::ALL;

/// Why a check could not run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ProveError {
    /// The level is above what the reference supports (or above 32).
    Level(Error),
    /// Building the transition table found a step that does not behave as
    /// the method assumes (a bug in the walk or in this module).
    Table(String),
}

impl fmt::Display for ProveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ProveError::Level(e) => e.fmt(f),
            ProveError::Table(why) => write!(f, "transition table: {why}"),
        }
    }
}

impl std::error::Error for ProveError {}
