//! The faces of the level-`n` lattice: one representative point for every
//! vertex, every open edge segment and every open micro-triangle.
//!
//! With `cells = 2^level`, the lattice lines are `u = k/cells`,
//! `v = k/cells` and `u + v = k/cells`. Both the reference and the walk only
//! compare the point against these lines, so they are constant on every face
//! and one point per face decides them everywhere (`docs/verification.md`).
//!
//! Points are given in units of `1 / (4 * cells)`: with `a`, `b` the cell
//! coordinates, `(4a, 4b)` is a vertex, `(4a+2, 4b)`, `(4a, 4b+2)` and
//! `(4a+2, 4b+2)` are midpoints of the horizontal, vertical and diagonal
//! edges, `(4a+1, 4b+1)` is inside the upright micro-triangle of the cell and
//! `(4a+3, 4b+3)` inside the upside-down one.
//!
//! ```
//! use micromap_index_lab::lattice::{faces, face_count};
//! use micromap_index::Level;
//! let level = Level::new(3).unwrap();
//! assert_eq!(faces(level).count() as u128, face_count(level));
//! assert_eq!(face_count(level), 45 + 108 + 64);
//! ```

use micromap_index::num::Fixed64;
use micromap_index::Level;
use num_bigint::BigInt;
use num_rational::BigRational;

/// What kind of face a representative point stands for. The declaration
/// order is the one order of kinds everywhere ([`FaceKind::ALL`],
/// [`FACE_OFFSETS`], per-kind counts such as the prover's
/// `mismatches_by_kind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FaceKind {
    /// A lattice vertex.
    Vertex,
    /// An open segment of a line `v = k / cells`.
    HorizontalEdge,
    /// An open segment of a line `u = k / cells`.
    VerticalEdge,
    /// An open segment of a line `u + v = k / cells`.
    DiagonalEdge,
    /// The open interior of an upright micro-triangle.
    Upright,
    /// The open interior of an upside-down micro-triangle.
    UpsideDown,
}

impl FaceKind {
    /// Every kind, in declaration order.
    pub const ALL: [FaceKind; 6] = [
        FaceKind::Vertex,
        FaceKind::HorizontalEdge,
        FaceKind::VerticalEdge,
        FaceKind::DiagonalEdge,
        FaceKind::Upright,
        FaceKind::UpsideDown,
    ];

    /// The position of the kind in [`FaceKind::ALL`] (and [`FACE_OFFSETS`]):
    /// the slot of per-kind counts.
    ///
    /// ```
    /// use micromap_index_lab::lattice::FaceKind;
    /// assert!(FaceKind::ALL.iter().enumerate().all(|(i, k)| k.index() == i));
    /// ```
    #[must_use]
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The offset of the kind's representative point from its cell's
    /// lower-left vertex `(4a, 4b)`, in units of `1 / (4 * 2^level)`
    /// ([`FACE_OFFSETS`]).
    #[must_use]
    pub const fn offset(self) -> (u64, u64) {
        let (dx, dy, _) = FACE_OFFSETS[self.index()];
        (dx, dy)
    }

    /// The kind of the face whose representative point is `(x, y)` in units
    /// of `1 / (4 * 2^level)` (a point of [`faces`]): the inverse of
    /// [`FaceKind::offset`], by `(x % 4, y % 4)`.
    ///
    /// ```
    /// use micromap_index_lab::lattice::FaceKind;
    /// assert_eq!(FaceKind::at(6, 4), FaceKind::HorizontalEdge);
    /// assert_eq!(FaceKind::at(7, 3), FaceKind::UpsideDown);
    /// ```
    #[must_use]
    pub const fn at(x: u64, y: u64) -> FaceKind {
        KIND_AT_RESIDUE[(y % 4 * 4 + x % 4) as usize]
    }

    /// Whether the face is the interior of a micro-triangle.
    #[must_use]
    pub fn is_open_triangle(self) -> bool {
        matches!(self, FaceKind::Upright | FaceKind::UpsideDown)
    }

    /// A short lower-case name (`vertex`, `horizontal-edge`, ...).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            FaceKind::Vertex => "vertex",
            FaceKind::HorizontalEdge => "horizontal-edge",
            FaceKind::VerticalEdge => "vertical-edge",
            FaceKind::DiagonalEdge => "diagonal-edge",
            FaceKind::Upright => "upright",
            FaceKind::UpsideDown => "upside-down",
        }
    }
}

/// One point per face: `u = x / 2^(level+2)`, `v = y / 2^(level+2)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Face {
    /// The level whose lattice this face belongs to.
    pub level: Level,
    /// `u` in units of `1 / (4 * 2^level)`.
    pub x: u64,
    /// `v` in units of `1 / (4 * 2^level)`.
    pub y: u64,
    /// The kind of face.
    pub kind: FaceKind,
}

impl Face {
    /// `log2` of the denominator of the coordinates: `level + 2`.
    #[must_use]
    pub fn scale_log2(&self) -> u32 {
        self.level.get() + 2
    }

    /// The point as exact rationals.
    #[must_use]
    pub fn to_rational(&self) -> (BigRational, BigRational) {
        let denominator = BigInt::from(1u64) << self.scale_log2();
        (
            BigRational::new(self.x.into(), denominator.clone()),
            BigRational::new(self.y.into(), denominator),
        )
    }

    /// The point in [`Fixed64`] (exact for every level up to 32).
    #[must_use]
    pub fn to_fixed64(&self) -> (Fixed64, Fixed64) {
        let shift = Fixed64::ONE_LOG2 - self.scale_log2();
        (
            Fixed64::from_raw((self.x as i64) << shift),
            Fixed64::from_raw((self.y as i64) << shift),
        )
    }
}

/// The number of faces at `level`: `(n+1)(n+2)/2` vertices, `3n(n+1)/2`
/// edges and `n^2` micro-triangles, `n = 2^level`.
#[must_use]
pub fn face_count(level: Level) -> u128 {
    let n = 1u128 << level.get();
    (n + 1) * (n + 2) / 2 + 3 * n * (n + 1) / 2 + n * n
}

/// Every face of the level's lattice, row by row (`v` ascending).
pub fn faces(level: Level) -> impl Iterator<Item = Face> {
    let cells = 1u64 << level.get();
    (0..=cells).flat_map(move |b| (0..=cells - b).flat_map(move |a| faces_of_cell(level, a, b)))
}

/// The six faces anchored at a cell `(a, b)`, as offsets from `(4a, 4b)` in
/// units of `1 / (4 * 2^level)`: its lower-left vertex, the three edges
/// leaving it, and the cell's two micro-triangles.
pub const FACE_OFFSETS: [(u64, u64, FaceKind); 6] = [
    (0, 0, FaceKind::Vertex),
    (2, 0, FaceKind::HorizontalEdge),
    (0, 2, FaceKind::VerticalEdge),
    (2, 2, FaceKind::DiagonalEdge),
    (1, 1, FaceKind::Upright),
    (3, 3, FaceKind::UpsideDown),
];

// FACE_OFFSETS lists the kinds in declaration order (FaceKind::offset and
// FaceKind::index rely on it).
const _: () = {
    let mut i = 0;
    while i < FACE_OFFSETS.len() {
        assert!(FACE_OFFSETS[i].2 as usize == i);
        i += 1;
    }
};

/// [`FaceKind::at`]'s table, indexed by `(y % 4) * 4 + x % 4`, built from
/// [`FACE_OFFSETS`] (residues that are no representative read upside-down).
const KIND_AT_RESIDUE: [FaceKind; 16] = {
    let mut table = [FaceKind::UpsideDown; 16];
    let mut i = 0;
    while i < FACE_OFFSETS.len() {
        let (dx, dy, kind) = FACE_OFFSETS[i];
        table[(dy * 4 + dx) as usize] = kind;
        i += 1;
    }
    table
};

/// The faces anchored at cell `(a, b)` of `level` that lie in the closed
/// triangle. A cell outside the lattice (`a + b > 2^level`) has none.
///
/// ```
/// use micromap_index_lab::lattice::faces_of_cell;
/// use micromap_index::Level;
/// let level = Level::new(1).unwrap();
/// // Cell (1, 0) at level 1 touches the hypotenuse: no upside-down
/// // micro-triangle there.
/// assert_eq!(faces_of_cell(level, 1, 0).count(), 5);
/// // At (1, 1) only the vertex (1/2, 1/2) is in the triangle; (2, 1) is past it.
/// assert_eq!(faces_of_cell(level, 1, 1).count(), 1);
/// assert_eq!(faces_of_cell(level, 2, 1).count(), 0);
/// assert_eq!(faces_of_cell(level, u64::MAX, 0).count(), 0);
/// ```
pub fn faces_of_cell(level: Level, a: u64, b: u64) -> impl Iterator<Item = Face> {
    let side = 1u64 << level.get();
    let inside = a <= side && b <= side - a;
    let limit = 4 << level.get();
    FACE_OFFSETS
        .into_iter()
        .filter(move |_| inside)
        .map(move |(dx, dy, kind)| Face {
            level,
            x: 4 * a + dx,
            y: 4 * b + dy,
            kind,
        })
        .filter(move |face| face.x + face.y <= limit)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    #[test]
    fn counts_per_kind_match_the_formula() {
        for level in 0..=6 {
            let level = Level::new(level).unwrap();
            let n = 1u128 << level.get();
            let mut per_kind: HashMap<FaceKind, u128> = HashMap::new();
            for face in faces(level) {
                *per_kind.entry(face.kind).or_default() += 1;
            }
            assert_eq!(per_kind[&FaceKind::Vertex], (n + 1) * (n + 2) / 2);
            for edge in [
                FaceKind::HorizontalEdge,
                FaceKind::VerticalEdge,
                FaceKind::DiagonalEdge,
            ] {
                assert_eq!(per_kind[&edge], n * (n + 1) / 2);
            }
            assert_eq!(per_kind[&FaceKind::Upright], n * (n + 1) / 2);
            assert_eq!(
                per_kind.get(&FaceKind::UpsideDown).copied().unwrap_or(0),
                n * (n - 1) / 2
            );
        }
    }
}
