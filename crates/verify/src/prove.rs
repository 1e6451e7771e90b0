//! The exhaustive proof: the walk equals the reference on every face of the
//! level-`n` lattice, hence at every real point of the closed triangle.
//!
//! Both [`uv2index`] and the reference ([`spec`]) only
//! compare the point against lines of the level-`n` lattice, so each is
//! constant on every face of it (vertex, open edge, open micro-triangle;
//! see [`crate::lattice`]). One point per face therefore decides all real
//! points. `docs/verification.md` spells the argument out and records the
//! results; `micromap-index prove` runs it.
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
//! use micromap_index_verify::prove::{prove_level, Progress, Settings, WalkVersion};
//! use micromap_index_verify::lattice;
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
    /// use micromap_index_verify::prove::WalkVersion;
    /// assert_eq!(WalkVersion::Version1.name(), "version1");
    /// ```
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            WalkVersion::Version2 => "version2",
            WalkVersion::Version1 => "version1",
        }
    }

    fn step(self, walk: &mut Walk<Fixed64>) -> u8 {
        match self {
            WalkVersion::Version2 => walk.step(),
            WalkVersion::Version1 => micromap_index::internals::step_version1(walk),
        }
    }

    /// The whole walk on one point, step by step (used by the sampler).
    fn index(self, u: Fixed64, v: Fixed64, level: Level) -> u64 {
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
    /// use micromap_index_verify::prove::Reference;
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
/// use micromap_index_verify::prove::{prove_level, Progress, Settings};
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

    fn start(&self, total: u64) {
        self.done.store(0, Ordering::Relaxed);
        self.total.store(total, Ordering::Relaxed);
    }

    fn finish_unit(&self) {
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

/// The face kinds in the order [`LevelReport::mismatches_by_kind`] uses.
pub const FACE_KINDS: [FaceKind; 6] = [
    FaceKind::Vertex,
    FaceKind::HorizontalEdge,
    FaceKind::VerticalEdge,
    FaceKind::DiagonalEdge,
    FaceKind::Upright,
    FaceKind::UpsideDown,
];

fn kind_slot(kind: FaceKind) -> usize {
    match kind {
        FaceKind::Vertex => 0,
        FaceKind::HorizontalEdge => 1,
        FaceKind::VerticalEdge => 2,
        FaceKind::DiagonalEdge => 3,
        FaceKind::Upright => 4,
        FaceKind::UpsideDown => 5,
    }
}

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

// ---------------------------------------------------------------------------
// The transition table.

/// Owned-mask bits: vertex `j` is bit `j`, the open edge opposite vertex
/// `j` is bit `3 + j`. The interior is always owned.
const ALL_OWNED: u8 = 0b11_1111;

/// A node's local vertices in the order [`Walk`] weighs them: vertex 0 by
/// `w`, vertex 1 by `u`, vertex 2 by `v`. The parent's level-1 vertices, at
/// scale 8 (`u = x / 8`, `v = y / 8`): V0, V1, V2, M01, M12, M20.
const LEVEL1_VERTICES: [(i64, i64); 6] = [(0, 0), (8, 0), (0, 8), (4, 0), (4, 4), (0, 4)];

/// Which of a triangle's closed faces a point with these barycentrics is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum LocalFace {
    Vertex(usize),
    EdgeOpposite(usize),
    Interior,
}

impl LocalFace {
    /// From which barycentrics are zero, in vertex order `[w, u, v]`.
    fn from_zeros(zero: [bool; 3]) -> Option<LocalFace> {
        match zero {
            [false, false, false] => Some(LocalFace::Interior),
            [true, false, false] => Some(LocalFace::EdgeOpposite(0)),
            [false, true, false] => Some(LocalFace::EdgeOpposite(1)),
            [false, false, true] => Some(LocalFace::EdgeOpposite(2)),
            [false, true, true] => Some(LocalFace::Vertex(0)),
            [true, false, true] => Some(LocalFace::Vertex(1)),
            [true, true, false] => Some(LocalFace::Vertex(2)),
            [true, true, true] => None,
        }
    }

    /// The owned-mask bit, `None` for the (always owned) interior.
    fn mask_bit(self) -> Option<u8> {
        match self {
            LocalFace::Vertex(j) => Some(1 << j),
            LocalFace::EdgeOpposite(j) => Some(1 << (3 + j)),
            LocalFace::Interior => None,
        }
    }
}

/// The walk's state at a node, as far as the rest of the walk cares.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct NodeState {
    mid_flip: bool,
    top_flip: bool,
    owned: u8,
}

/// One child of a node, as the step makes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Child {
    digit: u8,
    /// Index of the child's state in [`Table::states`].
    state: u16,
    /// The child's owned mask (also in its state; here to save a lookup).
    owned: u8,
    /// For each of the child's local vertices 0, 1, 2: which of the
    /// parent's [`LEVEL1_VERTICES`] it is.
    corners: [u8; 3],
}

/// The walk's step tabulated per node state: for each reachable (flags,
/// owned mask), the four children in digit order.
///
/// ```
/// use micromap_index_verify::prove::{Table, WalkVersion};
/// let table = Table::build(WalkVersion::Version2).unwrap();
/// assert_eq!(table.state_count(), 8); // flags x owned masks actually reached
/// ```
#[derive(Clone, Debug)]
pub struct Table {
    states: Vec<NodeState>,
    children: Vec<[Child; 4]>,
    /// Per state, the open edges and vertices its four children own, as
    /// one list (`boundary[boundary_start[s]..boundary_start[s + 1]]`).
    boundary: Vec<BoundaryFace>,
    boundary_start: Vec<usize>,
}

/// An open edge or a vertex that one child of a node owns: its
/// representative is `2 (P + Q)` at scale `4 * 2^level`, `P`, `Q` two of the
/// node's [`LEVEL1_VERTICES`] (equal for a vertex).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct BoundaryFace {
    child: u8,
    ends: [u8; 2],
}

/// A walk at `(x, y) / 2^scale_log2` with the given flags.
fn walk_at(x: i64, y: i64, scale_log2: u32, state: NodeState) -> Option<Walk<Fixed64>> {
    let mut walk = Walk::new(
        Fixed64::from_scaled(x, scale_log2)?,
        Fixed64::from_scaled(y, scale_log2)?,
    );
    walk.mid_flip = state.mid_flip;
    walk.top_flip = state.top_flip;
    Some(walk)
}

/// The walk's local barycentrics in vertex order `[w, u, v]`, raw.
fn barycentrics(walk: &Walk<Fixed64>) -> [i64; 3] {
    [walk.w.raw(), walk.u.raw(), walk.v.raw()]
}

/// Which local face of the child a point with these raw barycentrics is
/// in, if it is in the closed child at all.
fn child_face(raw: [i64; 3]) -> Option<LocalFace> {
    let one = Fixed64::ONE.raw();
    if raw.iter().any(|&c| !(0..=one).contains(&c)) {
        return None;
    }
    LocalFace::from_zeros(raw.map(|c| c == 0))
}

/// What one step does to one face of the parent's level-1 lattice.
struct StepOutcome {
    digit: u8,
    flags: (bool, bool),
    barycentrics: [i64; 3],
}

fn step_once(
    version: WalkVersion,
    x: i64,
    y: i64,
    scale_log2: u32,
    state: NodeState,
) -> Option<StepOutcome> {
    let mut walk = walk_at(x, y, scale_log2, state)?;
    let digit = version.step(&mut walk);
    Some(StepOutcome {
        digit,
        flags: (walk.mid_flip, walk.top_flip),
        barycentrics: barycentrics(&walk),
    })
}

/// What is known about one child while a state is being tabulated.
#[derive(Clone, Copy)]
struct ChildDraft {
    flags: (bool, bool),
    owned: u8,
    /// A point of the open child, at scale 8.
    interior: Option<(i64, i64)>,
}

impl Table {
    /// Tabulates `version`'s step over all node states reachable from the
    /// root (no flags, every face owned).
    pub fn build(version: WalkVersion) -> Result<Table, ProveError> {
        let fail = |why: String| ProveError::Table(why);
        let root = NodeState {
            mid_flip: false,
            top_flip: false,
            owned: ALL_OWNED,
        };
        let mut states = vec![root];
        let mut children = Vec::new();
        let level1 = Level::new(1).map_err(ProveError::Level)?;
        // The 19 faces of the local level-1 lattice, one point each, scale 8.
        let faces: Vec<(i64, i64)> = lattice::faces(level1)
            .map(|face| (face.x as i64, face.y as i64))
            .collect();
        let mut next = 0;
        while next < states.len() {
            let state = states[next];
            next += 1;
            let mut drafts: [Option<ChildDraft>; 4] = [None; 4];
            for &(x, y) in &faces {
                let parent_face = LocalFace::from_zeros([x + y == 8, x == 0, y == 0])
                    .ok_or_else(|| fail(format!("face ({x}, {y})/8 is not in the triangle")))?;
                if let Some(bit) = parent_face.mask_bit() {
                    if state.owned & bit == 0 {
                        continue;
                    }
                }
                let outcome = step_once(version, x, y, 3, state)
                    .ok_or_else(|| fail(format!("({x}, {y})/8 does not fit Fixed64")))?;
                let face = child_face(outcome.barycentrics)
                    .ok_or_else(|| fail(format!("step sends ({x}, {y})/8 outside its child")))?;
                let draft = drafts
                    .get_mut(usize::from(outcome.digit))
                    .ok_or_else(|| fail(format!("digit {} out of range", outcome.digit)))?;
                let draft = draft.get_or_insert(ChildDraft {
                    flags: outcome.flags,
                    owned: 0,
                    interior: None,
                });
                if draft.flags != outcome.flags {
                    return Err(fail(format!(
                        "digit {} reached with two flag sets",
                        outcome.digit
                    )));
                }
                match face.mask_bit() {
                    Some(bit) if draft.owned & bit != 0 => {
                        return Err(fail(format!(
                            "two faces land on one face of child {}",
                            outcome.digit
                        )));
                    }
                    Some(bit) => draft.owned |= bit,
                    None if draft.interior.is_some() => {
                        return Err(fail(format!(
                            "two interiors land in child {}",
                            outcome.digit
                        )));
                    }
                    None => draft.interior = Some((x, y)),
                }
            }
            let mut row = [Child {
                digit: 0,
                state: 0,
                owned: 0,
                corners: [0; 3],
            }; 4];
            for (digit, draft) in drafts.iter().enumerate() {
                let draft = draft.ok_or_else(|| fail(format!("no face reaches child {digit}")))?;
                let interior = draft
                    .interior
                    .ok_or_else(|| fail(format!("child {digit} does not own its interior")))?;
                let child_state = NodeState {
                    mid_flip: draft.flags.0,
                    top_flip: draft.flags.1,
                    owned: draft.owned,
                };
                let index = if let Some(index) = states.iter().position(|&s| s == child_state) {
                    index
                } else {
                    states.push(child_state);
                    states.len() - 1
                };
                row[digit] = Child {
                    digit: digit as u8,
                    state: u16::try_from(index).map_err(|_| fail("too many states".into()))?,
                    owned: child_state.owned,
                    corners: corners_of_child(version, state, digit as u8, interior)?,
                };
            }
            children.push(row);
        }
        let mut boundary = Vec::new();
        let mut boundary_start = vec![0];
        for row in &children {
            for (position, child) in row.iter().enumerate() {
                let [a, b, c] = child.corners;
                // In the order of CANDIDATE_BITS: edges opposite 0, 1, 2,
                // then vertices 0, 1, 2.
                let candidates = [[b, c], [c, a], [a, b], [a, a], [b, b], [c, c]];
                for (ends, bit) in candidates.into_iter().zip(CANDIDATE_BITS) {
                    if child.owned & (1 << bit) != 0 {
                        boundary.push(BoundaryFace {
                            child: position as u8,
                            ends,
                        });
                    }
                }
            }
            boundary_start.push(boundary.len());
        }
        Ok(Table {
            states,
            children,
            boundary,
            boundary_start,
        })
    }

    /// The boundary faces the children of a node in `state` own.
    #[inline(always)]
    fn boundary_of(&self, state: u16) -> &[BoundaryFace] {
        let state = usize::from(state);
        &self.boundary[self.boundary_start[state]..self.boundary_start[state + 1]]
    }

    /// The number of reachable node states.
    #[must_use]
    pub fn state_count(&self) -> usize {
        self.states.len()
    }
}

/// Where the child's local vertices are among the parent's level-1
/// vertices, learnt from the step itself: the step is one affine map `A`
/// on the open child, so for a parent vertex `X` and the child's interior
/// point `p`, the midpoint `q = (p + X) / 2` (inside the child when `X` is
/// one of its corners) gives `A(X) = 2 A(q) - A(p)`; `X` is the child's
/// vertex `j` when `A(X)` is the `j`-th unit vector.
fn corners_of_child(
    version: WalkVersion,
    state: NodeState,
    digit: u8,
    interior: (i64, i64),
) -> Result<[u8; 3], ProveError> {
    let fail = |why: String| ProveError::Table(why);
    let (px, py) = interior;
    let at_interior = step_once(version, px, py, 3, state)
        .ok_or_else(|| fail("interior point does not fit".into()))?;
    let one = Fixed64::ONE.raw();
    let mut corners = [None; 3];
    for (source, &(vx, vy)) in LEVEL1_VERTICES.iter().enumerate() {
        // (p + X) / 2 at scale 16.
        let Some(halfway) = step_once(version, px + vx, py + vy, 4, state) else {
            continue;
        };
        if halfway.digit != digit || halfway.flags != at_interior.flags {
            continue; // `q` is in another child: `X` is not a corner of this one.
        }
        let image: [i64; 3] =
            std::array::from_fn(|c| 2 * halfway.barycentrics[c] - at_interior.barycentrics[c]);
        for (j, corner) in corners.iter_mut().enumerate() {
            let unit: [i64; 3] = std::array::from_fn(|c| if c == j { one } else { 0 });
            if image == unit {
                if corner.is_some() {
                    return Err(fail(format!("child {digit} has two vertices {j}")));
                }
                *corner = Some(source as u8);
            }
        }
    }
    let mut found = [0u8; 3];
    for (j, corner) in corners.iter().enumerate() {
        found[j] = corner.ok_or_else(|| fail(format!("child {digit}: vertex {j} not found")))?;
    }
    Ok(found)
}

// ---------------------------------------------------------------------------
// The descent.

/// A node of the subdivision tree: state, owned mask, index prefix and its
/// corners in global coordinates at scale `2^level` (`x = u * 2^level`).
#[derive(Clone, Copy, Debug)]
struct Node {
    state: u16,
    owned: u8,
    index: u64,
    corners: [[u64; 2]; 3],
}

impl Node {
    fn root(level: Level) -> Node {
        let side = 1u64 << level.get();
        Node {
            state: 0,
            owned: ALL_OWNED,
            index: 0,
            corners: [[0, 0], [side, 0], [0, side]],
        }
    }
}

/// What the descent does at each node it reaches (a trait, not a closure,
/// so that the hot visitor is inlined into the descent).
trait Visitor {
    fn visit(&mut self, node: &Node);
}

/// A node's corners and edge midpoints in the order of
/// [`LEVEL1_VERTICES`]: the corners of its children.
#[inline(always)]
fn level1_points(corners: [[u64; 2]; 3]) -> [[u64; 2]; 6] {
    let [a, b, c] = corners;
    // Corners are multiples of 2 above the leaves: the halves are exact.
    let mid = |p: [u64; 2], q: [u64; 2]| [(p[0] + q[0]) / 2, (p[1] + q[1]) / 2];
    [a, b, c, mid(a, b), mid(b, c), mid(c, a)]
}

/// The child of `node` at `position` (the children are in digit order).
#[inline(always)]
fn child_node(node: &Node, child: &Child, points: &[[u64; 2]; 6]) -> Node {
    Node {
        state: child.state,
        owned: child.owned,
        index: (node.index << 2) | u64::from(child.digit),
        corners: child.corners.map(|k| points[usize::from(k)]),
    }
}

/// The four children of `node`, in digit order.
#[inline(always)]
fn children(table: &Table, node: &Node) -> [Node; 4] {
    let points = level1_points(node.corners);
    table.children[usize::from(node.state)].map(|child| child_node(node, &child, &points))
}

/// Visits every node `depth` levels below `node`, in index order.
fn descend<V: Visitor>(table: &Table, node: &Node, depth: u32, visitor: &mut V) {
    if depth == 0 {
        visitor.visit(node);
    } else {
        for child in &children(table, node) {
            descend(table, child, depth - 1, visitor);
        }
    }
}

/// A leaf's faces, one representative point each at scale `4 * 2^level`:
/// `(4a + 1, 4b + 1)` / `(4a + 3, 4b + 3)` for the upright / upside-down
/// micro-triangle of cell `(a, b)`, then `2(A + B)` for each edge `AB` and
/// `4P` for each vertex `P` (the points [`lattice::faces`] uses), in the
/// order of the owned-mask bits [`CANDIDATE_BITS`].
fn leaf_candidates(corners: [[u64; 2]; 3]) -> ([u64; 2], [[u64; 2]; 6]) {
    let [a, b, c] = corners;
    let vertex = |p: [u64; 2]| [4 * p[0], 4 * p[1]];
    (
        interior_point(corners),
        [
            edge(b, c),
            edge(c, a),
            edge(a, b),
            vertex(a),
            vertex(b),
            vertex(c),
        ],
    )
}

/// The representative of a leaf's interior at scale `4 * 2^level`.
#[inline(always)]
fn interior_point([a, b, c]: [[u64; 2]; 3]) -> [u64; 2] {
    // Upright: the corner sums are 3a+1 with minimum a; upside-down 3a+2.
    // Both give 2 * sum - 2 * min - 1 = 4a+1 resp. 4a+3.
    let coordinate = |i: usize| {
        let sum = a[i] + b[i] + c[i];
        2 * sum - 2 * a[i].min(b[i]).min(c[i]) - 1
    };
    [coordinate(0), coordinate(1)]
}

/// The representative of the edge `PQ` (of the vertex `P` if `P == Q`) at
/// scale `4 * 2^level`.
#[inline(always)]
fn edge(p: [u64; 2], q: [u64; 2]) -> [u64; 2] {
    [2 * (p[0] + q[0]), 2 * (p[1] + q[1])]
}

/// The owned-mask bit of each of [`leaf_candidates`]' six boundary faces:
/// the edges opposite vertices 0, 1, 2, then the vertices 0, 1, 2.
const CANDIDATE_BITS: [u8; 6] = [3, 4, 5, 0, 1, 2];

/// The number of faces a leaf with each owned mask has: its interior and
/// one per set bit.
const OWNED_FACES: [u8; 64] = {
    let mut counts = [0; 64];
    let mut mask = 0;
    while mask < 64 {
        counts[mask] = 1 + (mask as u8).count_ones() as u8;
        mask += 1;
    }
    counts
};

/// The faces a leaf owns, interior first.
#[derive(Clone, Copy)]
struct LeafFaces {
    points: [[u64; 2]; 7],
    len: usize,
}

impl LeafFaces {
    fn of(corners: [[u64; 2]; 3], owned: u8) -> LeafFaces {
        let (interior, candidates) = leaf_candidates(corners);
        let mut points = [interior; 7];
        let mut len = 1;
        for (point, bit) in candidates.into_iter().zip(CANDIDATE_BITS) {
            if owned & (1 << bit) != 0 {
                points[len] = point;
                len += 1;
            }
        }
        LeafFaces { points, len }
    }

    fn as_slice(&self) -> &[[u64; 2]] {
        &self.points[..self.len]
    }
}

/// The kind of the face whose representative is `(x, y)` at scale
/// `4 * 2^level` (only needed for mismatches).
fn kind_of(x: u64, y: u64) -> FaceKind {
    match (x % 4, y % 4) {
        (0, 0) => FaceKind::Vertex,
        (2, 0) => FaceKind::HorizontalEdge,
        (0, 2) => FaceKind::VerticalEdge,
        (2, 2) => FaceKind::DiagonalEdge,
        (1, 1) => FaceKind::Upright,
        _ => FaceKind::UpsideDown,
    }
}

/// A node one level above the leaves, with its four leaves' faces: what
/// the hot loop walks (faces come from the table's lists, so there is no
/// branch per leaf).
struct Twig<'t> {
    node: Node,
    /// [`level1_points`], padded to 8 so that `k & 7` indexes without a
    /// bounds check.
    points: [[u64; 2]; 8],
    children: &'t [Child; 4],
    boundary: &'t [BoundaryFace],
}

impl<'t> Twig<'t> {
    #[inline(always)]
    fn new(table: &'t Table, node: &Node) -> Twig<'t> {
        let [a, b, c, ab, bc, ca] = level1_points(node.corners);
        Twig {
            node: *node,
            points: [a, b, c, ab, bc, ca, a, a],
            children: &table.children[usize::from(node.state)],
            boundary: table.boundary_of(node.state),
        }
    }

    /// The leaf at `position` (in digit order).
    fn leaf(&self, position: usize) -> Node {
        let [a, b, c, ab, bc, ca, ..] = self.points;
        child_node(&self.node, &self.children[position], &[a, b, c, ab, bc, ca])
    }

    /// The walk's index of the leaf at `position`.
    #[inline(always)]
    fn leaf_index(&self, position: usize) -> u64 {
        (self.node.index << 2) | u64::from(self.children[position].digit)
    }

    /// The interior representative of the leaf at `position`.
    #[inline(always)]
    fn interior(&self, position: usize) -> [u64; 2] {
        let corners = self.children[position].corners;
        interior_point(corners.map(|k| self.points[usize::from(k & 7)]))
    }

    /// The owned open edges and vertices: (leaf position, representative).
    #[inline(always)]
    fn boundary_faces(&self) -> impl Iterator<Item = (usize, [u64; 2])> + '_ {
        self.boundary.iter().map(|face| {
            let [p, q] = face.ends.map(|k| self.points[usize::from(k & 7)]);
            (usize::from(face.child & 3), edge(p, q))
        })
    }
}

/// Calls `visit` with every face of the level's lattice and the index the
/// walk gives it, on one thread. These are the faces and indices the hot
/// loop of [`prove_level`] compares, exposed so that they can be checked
/// against the direct walk.
///
/// ```
/// use micromap_index_verify::prove::{for_each_face, WalkVersion};
/// use micromap_index::{uv2index, Level};
/// let level = Level::new(3).unwrap();
/// let mut faces = 0;
/// for_each_face(level, WalkVersion::Version2, |face, index| {
///     let (u, v) = face.to_fixed64();
///     assert_eq!(uv2index::index_unchecked(u, v, level), index);
///     faces += 1;
/// }).unwrap();
/// assert_eq!(faces, 217);
/// ```
pub fn for_each_face(
    level: Level,
    version: WalkVersion,
    visit: impl FnMut(Face, u64),
) -> Result<(), ProveError> {
    struct EveryFace<'t, F> {
        table: &'t Table,
        level: Level,
        visit: F,
    }
    impl<F: FnMut(Face, u64)> EveryFace<'_, F> {
        fn face(&mut self, [x, y]: [u64; 2], index: u64) {
            let kind = kind_of(x, y);
            let level = self.level;
            (self.visit)(Face { level, x, y, kind }, index);
        }
    }
    impl<F: FnMut(Face, u64)> Visitor for EveryFace<'_, F> {
        fn visit(&mut self, node: &Node) {
            let twig = Twig::new(self.table, node);
            for position in 0..4 {
                self.face(twig.interior(position), twig.leaf_index(position));
            }
            for (position, point) in twig.boundary_faces() {
                self.face(point, twig.leaf_index(position));
            }
        }
    }
    let table = Table::build(version)?;
    let mut every_face = EveryFace {
        table: &table,
        level,
        visit,
    };
    if let Some(twig_depth) = level.get().checked_sub(1) {
        descend(&table, &Node::root(level), twig_depth, &mut every_face);
    } else {
        // Level 0: the root is the only leaf.
        let root = Node::root(level);
        for &point in LeafFaces::of(root.corners, root.owned).as_slice() {
            every_face.face(point, root.index);
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// Running a level on all cores.

/// Counts of one unit of work.
#[derive(Clone, Debug, Default)]
struct Tally {
    faces: u64,
    mismatches_by_kind: [u64; 6],
    examples: Vec<Mismatch>,
}

impl Tally {
    #[cold]
    #[inline(never)]
    fn record_mismatch(
        &mut self,
        level: Level,
        x: u64,
        y: u64,
        walk: u64,
        reference: u64,
        keep: usize,
    ) {
        let kind = kind_of(x, y);
        self.mismatches_by_kind[kind_slot(kind)] += 1;
        if self.examples.len() < keep {
            self.examples.push(Mismatch {
                face: Face { level, x, y, kind },
                walk,
                reference,
            });
        }
    }
}

/// The tallies of the units that finished, in unit order, and whether
/// that is all of them.
struct Finished {
    tallies: Vec<Tally>,
    all: bool,
}

/// Runs `unit(i)` for `i in 0..units` on `threads` threads, stopping early
/// when cancelled. Only finished units are stored, so a huge unit count
/// (a sample of `u64::MAX` faces) costs no memory up front.
fn run_units(
    units: u64,
    threads: usize,
    progress: &Progress,
    unit: impl Fn(u64) -> Tally + Sync,
) -> Finished {
    progress.start(units);
    let next = AtomicU64::new(0);
    let finished: Mutex<Vec<(u64, Tally)>> = Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..threads.max(1) {
            scope.spawn(|| loop {
                if progress.is_cancelled() {
                    break;
                }
                let i = next.fetch_add(1, Ordering::Relaxed);
                if i >= units {
                    break;
                }
                let tally = unit(i);
                if let Ok(mut finished) = finished.lock() {
                    finished.push((i, tally));
                }
                progress.finish_unit();
            });
        }
    });
    let mut finished = finished
        .into_inner()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    finished.sort_unstable_by_key(|&(i, _)| i);
    Finished {
        all: finished.len() as u64 == units,
        tallies: finished.into_iter().map(|(_, tally)| tally).collect(),
    }
}

fn thread_count(settings: &Settings) -> usize {
    if settings.threads > 0 {
        settings.threads
    } else {
        std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
    }
}

impl Reference {
    /// The reference's integer half on a cell.
    #[inline(always)]
    fn index_from_cell(self, cell: spec::Cell, level: Level) -> u64 {
        match self {
            // level <= 16: the cell is at most 2^16 and fits u32.
            Reference::Spec => u64::from(spec::index_from_cell(
                cell.iu as u32,
                cell.iv as u32,
                cell.diagonal,
                level.get(),
            )),
            Reference::SpecWide => {
                spec::wide_index_from_cell(cell.iu, cell.iv, cell.diagonal, level.get())
            }
        }
    }

    /// The reference's index for the point `(x, y) / 2^(level + 2)`.
    fn index(self, x: u64, y: u64, level: Level) -> u64 {
        // scale_log2 = level + 2 <= 34 is within cell_dyadic's 62.
        let cell = spec::cell_dyadic(x, y, level.get() + 2, level).expect("scale within 2^62");
        self.index_from_cell(cell, level)
    }
}

fn checked_level(level: Level, reference: Reference) -> Result<Level, ProveError> {
    if level.get() > reference.max_level() {
        Err(ProveError::Level(Error::LevelTooHigh {
            level: level.get(),
            max: reference.max_level(),
        }))
    } else {
        Ok(level)
    }
}

/// Depth at which the tree is cut into units of work: 4^6 = 4096 units
/// balance two or more threads and keep cancellation prompt.
const UNIT_DEPTH: u32 = 6;

/// Compares the walk with the reference on every face of the level's
/// lattice, on all cores. A complete report with no mismatches and
/// `faces_checked == faces_expected` proves the two equal at every real
/// point of the closed triangle at that level ([`LevelReport::is_proof`]).
pub fn prove_level(
    level: Level,
    settings: &Settings,
    progress: &Progress,
) -> Result<LevelReport, ProveError> {
    let started = Instant::now();
    let level = checked_level(level, settings.reference)?;
    let table = Table::build(settings.walk)?;
    let keep = settings.examples;
    let Some(twig_depth) = level.get().checked_sub(1) else {
        // Level 0: one leaf, the root, checked face by face.
        let root = Node::root(level);
        let mut checker = Checker {
            table: &table,
            level,
            reference: settings.reference,
            keep,
            tally: Tally::default(),
        };
        progress.start(1);
        checker.check_each_face(&root);
        checker.tally.faces = u64::from(OWNED_FACES[usize::from(ALL_OWNED)]);
        progress.finish_unit();
        return Ok(merge(
            empty_report(
                level,
                settings,
                Method::Exhaustive,
                lattice::face_count(level),
            ),
            Finished {
                tallies: vec![checker.tally],
                all: true,
            },
            keep,
            started,
        ));
    };
    let unit_depth = twig_depth.min(UNIT_DEPTH);
    let mut units = Units(Vec::new());
    descend(&table, &Node::root(level), unit_depth, &mut units);
    let units = units.0;
    let below = twig_depth - unit_depth;
    let finished = match settings.reference {
        // `units` has at most 4^UNIT_DEPTH entries: the casts are exact.
        Reference::Spec => run_units(units.len() as u64, thread_count(settings), progress, |i| {
            check_subtree(
                &table,
                &units[i as usize],
                below,
                level,
                Reference::Spec,
                keep,
            )
        }),
        Reference::SpecWide => {
            run_units(units.len() as u64, thread_count(settings), progress, |i| {
                check_subtree(
                    &table,
                    &units[i as usize],
                    below,
                    level,
                    Reference::SpecWide,
                    keep,
                )
            })
        }
    };
    Ok(merge(
        empty_report(
            level,
            settings,
            Method::Exhaustive,
            lattice::face_count(level),
        ),
        finished,
        keep,
        started,
    ))
}

/// A report with nothing counted yet.
fn empty_report(level: Level, settings: &Settings, method: Method, expected: u128) -> LevelReport {
    LevelReport {
        level,
        walk: settings.walk,
        reference: settings.reference,
        method,
        faces_checked: 0,
        faces_expected: expected,
        mismatches_by_kind: [0; 6],
        examples: Vec::new(),
        seconds: 0.0,
        complete: true,
    }
}

/// Collects the nodes it visits: the units of work.
struct Units(Vec<Node>);

impl Visitor for Units {
    fn visit(&mut self, node: &Node) {
        self.0.push(*node);
    }
}

/// Compares every face below the twigs it visits with the reference (the
/// hot loop).
///
/// The reference is a function of the face's cell `(iu, iv, diagonal)`
/// ([`spec::cell_dyadic`]) alone, and the faces a leaf owns normally have
/// the cell of its interior. So the integer half runs once per leaf, on the
/// interior, and each other face only has its cell compared with that
/// leaf's; a twig where anything differs is checked again face by face
/// ([`Checker::check_each_face`]), which also reports the mismatches.
struct Checker<'t> {
    table: &'t Table,
    level: Level,
    reference: Reference,
    keep: usize,
    tally: Tally,
}

impl Checker<'_> {
    #[inline(always)]
    fn cell_of(&self, [x, y]: [u64; 2]) -> spec::Cell {
        // scale_log2 = level + 2 <= 34 is within cell_dyadic's 62.
        spec::cell_dyadic(x, y, self.level.get() + 2, self.level).expect("scale within 2^62")
    }

    /// Every face of one leaf through the whole reference.
    #[cold]
    #[inline(never)]
    fn check_each_face(&mut self, leaf: &Node) {
        for &point in LeafFaces::of(leaf.corners, leaf.owned).as_slice() {
            let expected = self
                .reference
                .index_from_cell(self.cell_of(point), self.level);
            if expected != leaf.index {
                let keep = self.keep;
                self.tally
                    .record_mismatch(self.level, point[0], point[1], leaf.index, expected, keep);
            }
        }
    }
}

impl Visitor for Checker<'_> {
    #[inline(always)]
    fn visit(&mut self, node: &Node) {
        let twig = Twig::new(self.table, node);
        let mut cells = [spec::Cell {
            iu: 0,
            iv: 0,
            diagonal: false,
        }; 4];
        let mut differs = false;
        for (position, cell) in cells.iter_mut().enumerate() {
            *cell = self.cell_of(twig.interior(position));
            let expected = self.reference.index_from_cell(*cell, self.level);
            differs |= expected != twig.leaf_index(position);
        }
        for (position, point) in twig.boundary_faces() {
            let cell = self.cell_of(point);
            let own = cells[position];
            // `&`, not `&&`: no branch on data.
            differs |=
                !((cell.iu == own.iu) && (cell.iv == own.iv) && (cell.diagonal == own.diagonal));
        }
        self.tally.faces += 4 + twig.boundary.len() as u64;
        if differs {
            for position in 0..4 {
                self.check_each_face(&twig.leaf(position));
            }
        }
    }
}

/// Every face below the twigs `depth` levels below `node`, compared with
/// the reference.
#[inline(always)]
fn check_subtree(
    table: &Table,
    node: &Node,
    depth: u32,
    level: Level,
    reference: Reference,
    keep: usize,
) -> Tally {
    let mut checker = Checker {
        table,
        level,
        reference,
        keep,
        tally: Tally::default(),
    };
    descend(table, node, depth, &mut checker);
    checker.tally
}

fn merge(
    mut report: LevelReport,
    finished: Finished,
    keep: usize,
    started: Instant,
) -> LevelReport {
    report.complete = finished.all;
    for tally in finished.tallies {
        report.faces_checked += u128::from(tally.faces);
        for (total, count) in report
            .mismatches_by_kind
            .iter_mut()
            .zip(tally.mismatches_by_kind)
        {
            *total += u128::from(count);
        }
        let room = keep.saturating_sub(report.examples.len());
        report
            .examples
            .extend(tally.examples.into_iter().take(room));
    }
    report.seconds = started.elapsed().as_secs_f64();
    report
}

// ---------------------------------------------------------------------------
// Random faces, for levels too large to enumerate.

/// Uniform integers in `0..bound` (`bound > 0`) without modulo bias
/// (Lemire's multiply-and-reject); the rejection threshold costs a
/// division, so it is computed once.
#[derive(Clone, Copy)]
struct Below {
    bound: u64,
    threshold: u64,
}

impl Below {
    fn new(bound: u64) -> Below {
        Below {
            bound,
            threshold: bound.wrapping_neg() % bound,
        }
    }

    fn draw(self, rng: &mut SplitMix64) -> u64 {
        loop {
            let product = u128::from(rng.next_u64()) * u128::from(self.bound);
            if (product as u64) >= self.threshold {
                return (product >> 64) as u64;
            }
        }
    }
}

/// Draws faces uniformly among all faces of a level: a uniform anchor cell
/// `(a, b)` in `0..=2^level` squared and one of the six faces anchored
/// there (as [`lattice::faces`] anchors them), redrawn if outside the
/// triangle. Every face has exactly one anchor, so all are equally likely.
struct FaceSampler {
    level: Level,
    anchor: Below,
    kind: Below,
}

impl FaceSampler {
    fn new(level: Level) -> FaceSampler {
        FaceSampler {
            level,
            anchor: Below::new((1u64 << level.get()) + 1),
            kind: Below::new(6),
        }
    }

    fn draw(&self, rng: &mut SplitMix64) -> Face {
        let limit = 4 << self.level.get();
        loop {
            let a = self.anchor.draw(rng);
            let b = self.anchor.draw(rng);
            let (dx, dy, kind) = crate::lattice::FACE_OFFSETS[self.kind.draw(rng) as usize];
            let (x, y) = (4 * a + dx, 4 * b + dy);
            if x + y <= limit {
                return Face {
                    level: self.level,
                    x,
                    y,
                    kind,
                };
            }
        }
    }
}

/// Samples per unit of work.
const SAMPLES_PER_UNIT: u64 = 1 << 20;

/// Compares the walk, run step by step on exact [`Fixed64`] points, with
/// the reference on `samples` uniformly random faces of the level. Not a
/// proof; for levels too large to enumerate. The same `seed` draws the
/// same faces, whatever the thread count.
///
/// ```
/// use micromap_index_verify::prove::{sample_level, Progress, Reference, Settings};
/// use micromap_index::Level;
/// let settings = Settings { reference: Reference::SpecWide, ..Settings::default() };
/// let report = sample_level(Level::new(32).unwrap(), 10_000, 7, &settings, &Progress::new()).unwrap();
/// assert_eq!((report.faces_checked, report.mismatches()), (10_000, 0));
/// ```
pub fn sample_level(
    level: Level,
    samples: u64,
    seed: u64,
    settings: &Settings,
    progress: &Progress,
) -> Result<LevelReport, ProveError> {
    let started = Instant::now();
    let level = checked_level(level, settings.reference)?;
    let units = samples.div_ceil(SAMPLES_PER_UNIT);
    let keep = settings.examples;
    let (walk, reference) = (settings.walk, settings.reference);
    let sampler = FaceSampler::new(level);
    let finished = run_units(units, thread_count(settings), progress, |i| {
        let first = i * SAMPLES_PER_UNIT;
        let count = SAMPLES_PER_UNIT.min(samples - first);
        // Each unit has its own stream, so results do not depend on the
        // thread count.
        let mut rng = SplitMix64::new(seed ^ i.wrapping_mul(0xd1b5_4a32_d192_ed03));
        rng.next_u64();
        let mut tally = Tally::default();
        for _ in 0..count {
            let face = sampler.draw(&mut rng);
            let (u, v) = face.to_fixed64();
            let by_walk = walk.index(u, v, level);
            let by_reference = reference.index(face.x, face.y, level);
            if by_walk != by_reference {
                tally.record_mismatch(level, face.x, face.y, by_walk, by_reference, keep);
            }
        }
        tally.faces = count;
        tally
    });
    Ok(merge(
        empty_report(
            level,
            settings,
            Method::Sampled { seed },
            u128::from(samples),
        ),
        finished,
        keep,
        started,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tables `docs/verification.md` describes: 8 states for version
    /// 2, 6 for version 1 (no flags); children of the root in digit order
    /// as (digit, owned mask, corners among V0 V1 V2 M01 M12 M20).
    #[test]
    fn tables_are_the_documented_ones() {
        let row = |table: &Table, state: usize| {
            table.children[state].map(|child| (child.digit, child.owned, child.corners))
        };
        let version2 = Table::build(WalkVersion::Version2).unwrap();
        assert_eq!(version2.state_count(), 8);
        assert_eq!(
            row(&version2, 0),
            [
                (0, 0b11_0001, [0, 3, 5]),
                (1, 0b01_0000, [5, 4, 3]),
                (2, 0b11_1011, [3, 1, 4]),
                (3, 0b11_1111, [5, 4, 2]),
            ]
        );
        let version1 = Table::build(WalkVersion::Version1).unwrap();
        assert_eq!(version1.state_count(), 6);
        assert!(version1.states.iter().all(|s| !s.mid_flip && !s.top_flip));
        // Version 1 enters the top child rotated: M12 and M20 swap roles.
        assert_eq!(row(&version1, 0)[3], (3, 0b11_1111, [4, 5, 2]));
    }

    /// The twig lists give each leaf exactly the faces [`LeafFaces`] gives it.
    #[test]
    fn twig_lists_match_leaf_faces() {
        for version in [WalkVersion::Version2, WalkVersion::Version1] {
            let table = Table::build(version).unwrap();
            for state in 0..table.state_count() {
                let node = Node {
                    state: state as u16,
                    owned: table.states[state].owned,
                    index: 0,
                    corners: [[0, 0], [2, 0], [0, 2]],
                };
                let twig = Twig::new(&table, &node);
                for position in 0..4 {
                    let leaf = twig.leaf(position);
                    let mut from_twig = vec![twig.interior(position)];
                    from_twig.extend(
                        twig.boundary_faces()
                            .filter(|&(p, _)| p == position)
                            .map(|(_, point)| point),
                    );
                    let from_leaf = LeafFaces::of(leaf.corners, leaf.owned);
                    assert_eq!(from_twig, from_leaf.as_slice(), "{version:?} state {state}");
                }
            }
        }
    }

    #[test]
    fn random_faces_are_faces() {
        let mut rng = SplitMix64::new(1);
        for level in [0, 1, 5, 32] {
            let level = Level::new(level).unwrap();
            let sampler = FaceSampler::new(level);
            for _ in 0..1000 {
                let face = sampler.draw(&mut rng);
                assert!(face.x + face.y <= 4 << level.get());
                assert_eq!(kind_of(face.x, face.y), face.kind);
            }
        }
    }
}
