//! The tags a case can carry. A case has one or more; a point that belongs
//! to several classes (a ±1 ulp neighbour of 0 is also subnormal and maybe
//! outside the triangle) carries all of them.

/// A lattice vertex `(a, b) / 2^level`.
pub const VERTEX: &str = "vertex";
/// The midpoint of a lattice edge (with one of the three edge tags).
pub const EDGE_MIDPOINT: &str = "edge-midpoint";
/// On a line `v = k / 2^level`.
pub const HORIZONTAL_EDGE: &str = "horizontal-edge";
/// On a line `u = k / 2^level`.
pub const VERTICAL_EDGE: &str = "vertical-edge";
/// On a line `u + v = k / 2^level`.
pub const DIAGONAL_EDGE: &str = "diagonal-edge";
/// The point lies on an edge shared by two micro-triangles (not at a
/// vertex): which of the two is the index is a tie-break. Derived exactly
/// from the point, whatever its class.
pub const SHARED_EDGE: &str = "shared-edge";
/// The point is a lattice vertex shared by two or more micro-triangles
/// (any vertex but the base triangle's corners): a tie-break. Derived
/// exactly from the point.
pub const SHARED_VERTEX: &str = "shared-vertex";
/// The centroid of a micro-triangle (exact in `spec-exact`, the nearest
/// binary32 point elsewhere), with `upright` or `upside-down`.
pub const CENTROID: &str = "centroid";
/// A micro-triangle with the right angle at its lower left.
pub const UPRIGHT: &str = "upright";
/// A micro-triangle with the right angle at its upper right.
pub const UPSIDE_DOWN: &str = "upside-down";
/// One binary32 ulp away from a lattice point, in `u`, `v` or both.
pub const ULP_NEIGHBOUR: &str = "ulp-neighbour";
/// ... of a vertex (all 8 directions).
pub const NEAR_VERTEX: &str = "near-vertex";
/// ... of a horizontal edge's midpoint (`v` ± 1 ulp).
pub const NEAR_HORIZONTAL_EDGE: &str = "near-horizontal-edge";
/// ... of a vertical edge's midpoint (`u` ± 1 ulp).
pub const NEAR_VERTICAL_EDGE: &str = "near-vertical-edge";
/// ... of a diagonal edge's midpoint (`u` or `v` ± 1 ulp).
pub const NEAR_DIAGONAL_EDGE: &str = "near-diagonal-edge";
/// The reference in binary32 differs from its exact reading: the real
/// `uf + vf` is in `[1 - 2^-25, 1)` and `iu + iv < 2^level - 1`.
pub const ROUNDING_WINDOW: &str = "rounding-window";
/// The real `uf + vf` is in the window but the reference ignores the
/// diagonal test there (`iu + iv >= 2^level - 1`): no difference.
pub const ROUNDING_WINDOW_IGNORED: &str = "rounding-window-ignored";
/// Probes just outside the window (`uf + vf` exactly 1, or just below
/// `1 - 2^-25`): binary32 and exact agree.
pub const ROUNDING_WINDOW_EDGE: &str = "rounding-window-edge";
/// Not a finite point of the closed triangle: the reference's clamping
/// decides (with one or more of the next five tags).
pub const CLAMP: &str = "clamp";
/// A coordinate is NaN (quiet, signalling or negative).
pub const NAN: &str = "nan";
/// A coordinate is a signalling NaN (quiet bit clear). The reference
/// clamps it to 0 with IEEE 754-2019 `maximumNumber` / SPIR-V `NMax`
/// semantics (what this crate implements); IEEE 754-2008 `maxNum`, as
/// glibc's `fmaxf`, returns a quiet NaN for it instead, which the
/// following `min` turns into 1.
pub const SIGNALLING_NAN: &str = "signalling-nan";
/// A coordinate is +inf or -inf.
pub const INFINITY: &str = "infinity";
/// A finite coordinate below zero.
pub const NEGATIVE: &str = "negative";
/// A finite coordinate above one.
pub const ABOVE_ONE: &str = "above-one";
/// Both coordinates in `[0, 1]` but `u + v > 1` (decided exactly).
pub const SUM_ABOVE_ONE: &str = "sum-above-one";
/// A coordinate is `-0.0` (binary32 set only).
pub const SIGNED_ZERO: &str = "signed-zero";
/// A coordinate is a nonzero binary32 subnormal.
pub const SUBNORMAL: &str = "subnormal";
/// A seeded uniform point of the triangle.
pub const RANDOM: &str = "random";

/// Every tag, in the order the docs list them.
pub const ALL: [&str; 28] = [
    VERTEX,
    EDGE_MIDPOINT,
    HORIZONTAL_EDGE,
    VERTICAL_EDGE,
    DIAGONAL_EDGE,
    SHARED_EDGE,
    SHARED_VERTEX,
    CENTROID,
    UPRIGHT,
    UPSIDE_DOWN,
    ULP_NEIGHBOUR,
    NEAR_VERTEX,
    NEAR_HORIZONTAL_EDGE,
    NEAR_VERTICAL_EDGE,
    NEAR_DIAGONAL_EDGE,
    ROUNDING_WINDOW,
    ROUNDING_WINDOW_IGNORED,
    ROUNDING_WINDOW_EDGE,
    CLAMP,
    NAN,
    SIGNALLING_NAN,
    INFINITY,
    NEGATIVE,
    ABOVE_ONE,
    SUM_ABOVE_ONE,
    SIGNED_ZERO,
    SUBNORMAL,
    RANDOM,
];
