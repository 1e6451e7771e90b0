//! The inverse map: from a micro-triangle's index to its vertices.
//!
//! [`micro_triangle`] inverts the reference's integer half in a fixed number
//! of word operations, whatever the level (the derivation is in
//! `src/inverse/by_bits.rs`); [`micro_triangles`] visits every
//! micro-triangle of a level in curve order, for bakers. Both are checked
//! against the oracle `micro_triangle_ref` (in `internals`), which reads the
//! index's base-4 digits from the top and replays the [`uv2index`] walk:
//! each digit picks the Left, Middle, Right or Top child exactly as
//! [`Walk::step`] numbers them (a `top_flip`, toggled by every Top step,
//! swaps the digits of Left and Right), and the current triangle's vertices
//! are replaced by the child's. The vertices stay exact: at level `n` every
//! vertex is a lattice point `(a / 2^n, b / 2^n)`, stored as the integer
//! numerators `(a, b)`.
//!
//! # Vertex order
//!
//! The vertices come in the order of the walk's local frame at depth `n`:
//! `vertices[0]`, `vertices[1]` and `vertices[2]` are the points whose
//! barycentric weights are the walk's `w`, `u` and `v` inside this
//! micro-triangle. So after [`Walk::step`] has run `level` times on a point
//! of the micro-triangle, `w * vertices[0] + u * vertices[1] + v *
//! vertices[2]` is the point again: a baker can use the walk's final state
//! directly as coordinates within the micro-triangle. At level 0 the order is
//! the base triangle's: `(0, 0)` (vertex 0, weight `w`), `(1, 0)` (vertex 1,
//! weight `u`), `(0, 1)` (vertex 2, weight `v`).
//!
//! The Left, Right and Top children keep their parent's orientation and the
//! Middle child turns it upside down; in the local frame the Middle child's
//! vertex order also reverses its winding. The order depends only on the
//! orientation (every child is its parent's affine image): an upright
//! micro-triangle in cell `(a, b)` is always `(a, b), (a + 1, b), (a, b + 1)`
//! and an upside-down one `(a, b + 1), (a + 1, b + 1), (a + 1, b)`. Hence the vertices wind
//! counter-clockwise in the `(u, v)` plane exactly when the micro-triangle is
//! [upright](MicroTriangle::upright).
//!
//! Edges are numbered by the vertex they face: edge `i` joins the two
//! vertices other than `vertices[i]`
//! (`edge_midpoints_rational`, feature `exact`,
//! [`neighbours`](MicroTriangle::neighbours)).
//!
//! ```
//! use micromap_index::inverse::micro_triangle;
//! use micromap_index::{uv2index, Level};
//!
//! let level = Level::new(2).unwrap();
//! let triangle = micro_triangle(level, 5).unwrap();
//! // Numerators over 2^level = 4: the corners (1/4, 1/4), (1/2, 1/4), (1/4, 1/2).
//! assert_eq!(triangle.vertices_scaled(), [(1, 1), (2, 1), (1, 2)]);
//! assert!(triangle.upright());
//! // Its centroid walks back to it.
//! let (u, v) = triangle.centroid_f64();
//! assert_eq!(uv2index::exact_index_f64(u, v, level), Ok(5));
//! ```
//!
//! [`Walk::step`]: crate::uv2index::Walk::step

mod by_bits;
mod iter;

pub use iter::{micro_triangles, MicroTriangles};

use crate::num::Fixed64;
use crate::uv2index::{self, digit};
use crate::{Error, Level};
#[cfg(feature = "exact")]
use num_bigint::BigInt;
#[cfg(feature = "exact")]
use num_rational::BigRational;

/// One micro-triangle of a level-`n` micromap: its index, its exact
/// vertices and its orientation. Built by [`micro_triangle`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MicroTriangle {
    level: Level,
    index: u64,
    /// `(u, v)` numerators over `2^level`, in the walk's local order.
    vertices: [(u64, u64); 3],
    upright: bool,
}

/// The four children of a triangle split at its edge midpoints.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Child {
    Left,
    Middle,
    Right,
    Top,
}

impl Child {
    /// The child a digit names, undoing [`Walk::step`](uv2index::Walk::step)'s
    /// numbering: a `top_flip` swaps the digits of Left and Right.
    fn from_digit(child_digit: u8, top_flip: bool) -> Child {
        let (left, right) = if top_flip {
            (Child::Right, Child::Left)
        } else {
            (Child::Left, Child::Right)
        };
        match child_digit {
            digit::LEFT => left,
            digit::MIDDLE => Child::Middle,
            digit::RIGHT => right,
            _ => Child::Top,
        }
    }

    /// The child's vertices in its local frame, derived from the walk's
    /// barycentric updates (`P = w*V0 + u*V1 + v*V2` must stay the same
    /// point): e.g. Left's `(2u, 2v, w - u - v)` means `V0`, `mid(V0, V1)`,
    /// `mid(V0, V2)`.
    ///
    /// Generic over the point type: `midpoint` commutes with affine maps,
    /// so any affine image of the vertices (the baker's texel-grid points)
    /// steps the same way.
    fn vertices<P: Copy>(self, [v0, v1, v2]: [P; 3], midpoint: impl Fn(P, P) -> P) -> [P; 3] {
        match self {
            Child::Left => [v0, midpoint(v0, v1), midpoint(v0, v2)],
            Child::Right => [midpoint(v0, v1), v1, midpoint(v1, v2)],
            Child::Top => [midpoint(v0, v2), midpoint(v1, v2), v2],
            // (u+v-w, w+u-v, v+w-u): a half-turn plus a swap of V0 and V1.
            Child::Middle => [midpoint(v0, v2), midpoint(v1, v2), midpoint(v0, v1)],
        }
    }
}

/// One step of the digit replay (`replay`), for a caller that walks
/// the tree top-down: the vertices of the child with digit `child_digit`
/// of a node with `vertices` (any affine image of the walk's, stepped by
/// `midpoint`) and `top_flip`, and the child's `top_flip`.
#[cfg(feature = "alloc")]
#[inline]
pub(crate) fn child_vertices<P: Copy>(
    child_digit: u8,
    top_flip: bool,
    vertices: [P; 3],
    midpoint: impl Fn(P, P) -> P,
) -> ([P; 3], bool) {
    let child = Child::from_digit(child_digit, top_flip);
    (
        child.vertices(vertices, midpoint),
        top_flip != (child == Child::Top),
    )
}

/// The midpoint of two points. Exact: at depth `d < level` every numerator
/// is a multiple of `2^(level - d)`, so the sums are even (and below `2^34`).
fn midpoint(a: (u64, u64), b: (u64, u64)) -> (u64, u64) {
    ((a.0 + b.0) / 2, (a.1 + b.1) / 2)
}

/// The micro-triangle with index `index` at `level`: its vertices (in the
/// walk's local order, see the [module docs](self)) and orientation.
///
/// Every level `0..=32` is supported, in constant time; an index
/// `>= 4^level` is [`Error::IndexOutOfRange`]. Never panics.
///
/// ```
/// use micromap_index::inverse::micro_triangle;
/// use micromap_index::{Error, Level};
///
/// let level = Level::new(1).unwrap();
/// // The upside-down centre triangle; its local frame starts at (0, 1/2).
/// let middle = micro_triangle(level, 1).unwrap();
/// assert_eq!(middle.vertices_scaled(), [(0, 1), (1, 1), (1, 0)]);
/// assert!(!middle.upright());
/// assert_eq!(
///     micro_triangle(level, 4),
///     Err(Error::IndexOutOfRange { index: 4, level: 1 })
/// );
/// ```
#[inline]
pub fn micro_triangle(level: Level, index: u64) -> Result<MicroTriangle, Error> {
    check_index(level, index)?;
    let ((iu, iv), upright) = by_bits::cell_and_orientation(level, index);
    let origin = if upright { (iu, iv) } else { (iu, iv + 1) };
    Ok(MicroTriangle::from_origin(level, index, origin, upright))
}

/// [`Error::IndexOutOfRange`] unless `index < 4^level`.
#[inline]
fn check_index(level: Level, index: u64) -> Result<(), Error> {
    if u128::from(index) >= level.micro_triangle_count() {
        Err(Error::IndexOutOfRange {
            index,
            level: level.get(),
        })
    } else {
        Ok(())
    }
}

unstable_pub_fn! {
    /// [`micro_triangle`] by replaying the walk digit by digit (see the
    /// [module docs](self)): the oracle the constant-time inversion and the
    /// iterator are tested against.
    fn micro_triangle_ref(level: Level, index: u64) -> Result<MicroTriangle, Error> {
        check_index(level, index)?;
        Ok(replay(level, index))
    }
}

/// The digit replay of [`micro_triangle_ref`], for an index in range.
fn replay(level: Level, index: u64) -> MicroTriangle {
    let side = 1u64 << level.get();
    let mut vertices = [(0, 0), (side, 0), (0, side)];
    let mut top_flip = false;
    let mut upright = true;
    // Most significant digit first: the walk appends digits at the bottom.
    for depth in (0..level.get()).rev() {
        let child_digit = ((index >> (2 * depth)) & 3) as u8;
        let child = Child::from_digit(child_digit, top_flip);
        vertices = child.vertices(vertices, midpoint);
        match child {
            Child::Top => top_flip = !top_flip,
            Child::Middle => upright = !upright,
            Child::Left | Child::Right => {}
        }
    }
    MicroTriangle {
        level,
        index,
        vertices,
        upright,
    }
}

impl MicroTriangle {
    /// The micro-triangle whose `vertices[0]` is `origin` (numerators over
    /// `2^level`): the other two follow from the orientation (module docs).
    #[inline]
    fn from_origin(level: Level, index: u64, origin: (u64, u64), upright: bool) -> MicroTriangle {
        let (a, b) = origin;
        // Third vertex (a, b + 1) upright, (a + 1, b - 1) upside down,
        // without a branch (the orientation is irregular along the curve).
        let down = u64::from(!upright);
        MicroTriangle {
            level,
            index,
            vertices: [
                (a, b),
                (a + 1, b),
                (a + down, (b + 1).wrapping_sub(2 * down)),
            ],
            upright,
        }
    }

    /// The grid cell `(iu, iv)` holding the micro-triangle: numerators over
    /// `2^level` of the lower-left corner of the square it lies in (the
    /// upside-down triangle is the upper-right half of its cell), as the
    /// reference's `trunc(u * 2^level)`, `trunc(v * 2^level)` of its
    /// interior points.
    ///
    /// ```
    /// use micromap_index::{inverse::micro_triangle, Level};
    /// let level = Level::new(1).unwrap();
    /// assert_eq!(micro_triangle(level, 1).unwrap().cell(), (0, 0));
    /// assert_eq!(micro_triangle(level, 3).unwrap().cell(), (0, 1));
    /// ```
    #[inline]
    #[must_use]
    pub fn cell(&self) -> (u64, u64) {
        let (a, b) = self.vertices[0];
        if self.upright {
            (a, b)
        } else {
            (a, b - 1)
        }
    }

    /// The subdivision level.
    ///
    /// ```
    /// use micromap_index::{inverse::micro_triangle, Level};
    /// let level = Level::new(7).unwrap();
    /// assert_eq!(micro_triangle(level, 100).unwrap().level(), level);
    /// ```
    #[must_use]
    pub fn level(&self) -> Level {
        self.level
    }

    /// The index on the space-filling curve.
    ///
    /// ```
    /// use micromap_index::{inverse::micro_triangle, Level};
    /// assert_eq!(micro_triangle(Level::new(7).unwrap(), 100).unwrap().index(), 100);
    /// ```
    #[must_use]
    pub fn index(&self) -> u64 {
        self.index
    }

    /// Whether the micro-triangle has the base triangle's orientation (its
    /// vertices are `(a, b)`, `(a + 1, b)`, `(a, b + 1)` in units of
    /// `2^-level`) rather than being upside down (`(a + 1, b)`, `(a, b + 1)`,
    /// `(a + 1, b + 1)`).
    ///
    /// ```
    /// use micromap_index::{inverse::micro_triangle, Level};
    /// let level = Level::new(1).unwrap();
    /// let upright: Vec<bool> = (0..4).map(|i| micro_triangle(level, i).unwrap().upright()).collect();
    /// assert_eq!(upright, [true, false, true, true]);
    /// ```
    #[must_use]
    pub fn upright(&self) -> bool {
        self.upright
    }

    /// The vertices as `(u, v)` numerators over `2^level`, in the walk's
    /// local order (see the [module docs](self)). Every numerator is at most
    /// `2^level`.
    ///
    /// ```
    /// use micromap_index::{inverse::micro_triangle, Level};
    /// // Level 1, index 3: the Top corner (v >= 1/2).
    /// let top = micro_triangle(Level::new(1).unwrap(), 3).unwrap();
    /// assert_eq!(top.vertices_scaled(), [(0, 1), (1, 1), (0, 2)]);
    /// ```
    #[must_use]
    pub fn vertices_scaled(&self) -> [(u64, u64); 3] {
        self.vertices
    }

    #[cfg(feature = "exact")]
    /// The vertices as exact `(u, v)` rationals.
    ///
    /// ```
    /// use micromap_index::{inverse::micro_triangle, Level};
    /// use num_rational::BigRational;
    /// let r = |s: &str| s.parse::<BigRational>().unwrap();
    /// let top = micro_triangle(Level::new(1).unwrap(), 3).unwrap();
    /// assert_eq!(top.vertices_rational()[1], (r("1/2"), r("1/2")));
    /// ```
    #[must_use]
    pub fn vertices_rational(&self) -> [(BigRational, BigRational); 3] {
        let denominator = self.denominator();
        self.vertices.map(|(u, v)| {
            (
                BigRational::new(u.into(), denominator.clone()),
                BigRational::new(v.into(), denominator.clone()),
            )
        })
    }

    /// The vertices in binary64: exact at every level (numerators have at
    /// most 33 bits).
    ///
    /// ```
    /// use micromap_index::{inverse::micro_triangle, Level};
    /// let top = micro_triangle(Level::new(1).unwrap(), 3).unwrap();
    /// assert_eq!(top.vertices_f64(), [(0.0, 0.5), (0.5, 0.5), (0.0, 1.0)]);
    /// ```
    #[must_use]
    pub fn vertices_f64(&self) -> [(f64, f64); 3] {
        let scale = self.scale_f64();
        // u64 -> f64 is exact below 2^53; multiplying by a power of two is exact.
        self.vertices
            .map(|(u, v)| (u as f64 * scale, v as f64 * scale))
    }

    /// The vertices in binary32: exact for levels `0..=24`. Above, a
    /// numerator can need more than 24 significant bits; each coordinate is
    /// then rounded to the nearest `f32` (ties to even), and distinct lattice
    /// points may round to the same pair.
    ///
    /// ```
    /// use micromap_index::{inverse::micro_triangle, uv2index, Level};
    /// let level = Level::new(25).unwrap();
    /// // The micro-triangle in the corner at vertex 1, (u, v) = (1, 0).
    /// let corner = micro_triangle(level, uv2index::exact_index_f64(1.0, 0.0, level).unwrap()).unwrap();
    /// let near_corner = ((1 << 25) - 1, 0); // (1 - 2^-25, 0)
    /// assert!(corner.vertices_scaled().contains(&near_corner));
    /// // 1 - 2^-25 is halfway between the f32 values 1 - 2^-24 and 1: it ties to 1.
    /// let rounded = corner.vertices_f32();
    /// assert_eq!(rounded.iter().filter(|&&p| p == (1.0, 0.0)).count(), 2);
    /// ```
    #[must_use]
    pub fn vertices_f32(&self) -> [(f32, f32); 3] {
        let scale = self.scale_f32();
        // `as f32` rounds to nearest-even; the power-of-two scale is exact.
        self.vertices
            .map(|(u, v)| (u as f32 * scale, v as f32 * scale))
    }

    #[cfg(feature = "exact")]
    /// The centroid, the mean of the vertices, as exact rationals. It lies
    /// strictly inside the micro-triangle, so every implementation in this
    /// crate maps it back to [`index`](Self::index) (the reference only up
    /// to its level 16).
    ///
    /// ```
    /// use micromap_index::{inverse::micro_triangle, spec, Level, SpecLevel};
    /// let level = SpecLevel::new(3).unwrap();
    /// let (u, v) = micro_triangle(level.into(), 42).unwrap().centroid_rational();
    /// assert_eq!(spec::index_real(&u, &v, level), 42);
    /// ```
    #[must_use]
    pub fn centroid_rational(&self) -> (BigRational, BigRational) {
        let (u_sum, v_sum) = self.vertex_sums();
        let denominator = self.denominator() * BigInt::from(3);
        (
            BigRational::new(u_sum.into(), denominator.clone()),
            BigRational::new(v_sum.into(), denominator),
        )
    }

    /// The centroid rounded to the nearest binary64 values (ties to even).
    ///
    /// ```
    /// use micromap_index::{inverse::micro_triangle, Level};
    /// let triangle = micro_triangle(Level::new(0).unwrap(), 0).unwrap();
    /// assert_eq!(triangle.centroid_f64(), (1.0 / 3.0, 1.0 / 3.0));
    /// ```
    #[must_use]
    pub fn centroid_f64(&self) -> (f64, f64) {
        let (u_sum, v_sum) = self.vertex_sums();
        let scale = self.scale_f64();
        // Sums are below 2^35 (exact); one correctly rounded division, then
        // an exact power-of-two scale (results stay far from subnormals).
        (u_sum as f64 / 3.0 * scale, v_sum as f64 / 3.0 * scale)
    }

    /// The centroid rounded to the nearest binary32 values (ties to even),
    /// at every level: a handy interior sample point for float code.
    ///
    /// ```
    /// use micromap_index::{inverse::micro_triangle, uv2index, Level};
    /// let level = Level::new(5).unwrap();
    /// let (u, v) = micro_triangle(level, 700).unwrap().centroid_f32();
    /// assert_eq!(uv2index::exact_index_f32(u, v, level), Ok(700));
    /// ```
    #[must_use]
    pub fn centroid_f32(&self) -> (f32, f32) {
        // Rounding the binary64 value again cannot double-round wrongly. For
        // x = (sum / 3) * 2^-level in [2^e, 2^(e+1)), a binary32 halfway point
        // m near x is a multiple of 2^(e-24) and x one of 2^-level / 3; so
        // x != m differs from m by at least min(2^-level, 2^(e-24)) / 3, far
        // more than x's binary64 rounding error 2^(e-53). So the first
        // rounding lands on m only when x == m, and the second then rounds x
        // itself.
        let (u, v) = self.centroid_f64();
        (u as f32, v as f32)
    }

    #[cfg(feature = "exact")]
    /// The midpoints of the three edges as exact rationals; entry `i` is the
    /// midpoint of edge `i`, the edge facing `vertices[i]`.
    ///
    /// ```
    /// use micromap_index::{inverse::micro_triangle, Level};
    /// use num_rational::BigRational;
    /// let r = |s: &str| s.parse::<BigRational>().unwrap();
    /// let whole = micro_triangle(Level::new(0).unwrap(), 0).unwrap();
    /// assert_eq!(
    ///     whole.edge_midpoints_rational(),
    ///     [(r("1/2"), r("1/2")), (r("0"), r("1/2")), (r("1/2"), r("0"))]
    /// );
    /// ```
    #[must_use]
    pub fn edge_midpoints_rational(&self) -> [(BigRational, BigRational); 3] {
        let denominator = self.denominator() * BigInt::from(2);
        self.edges().map(|[_, a, b]| {
            (
                BigRational::new((a.0 + b.0).into(), denominator.clone()),
                BigRational::new((a.1 + b.1).into(), denominator.clone()),
            )
        })
    }

    /// The indices of the micro-triangles across each edge, `None` where the
    /// edge lies on the base triangle's boundary. Entry `i` is across edge
    /// `i`, the edge facing `vertices[i]`.
    ///
    /// Each neighbour is located by running the exact walk on a point
    /// strictly inside it, so the answer is the index the walk (and the
    /// reference, up to level 16) assigns to that whole micro-triangle.
    ///
    /// ```
    /// use micromap_index::{inverse::micro_triangle, Level};
    /// let level = Level::new(1).unwrap();
    /// // The centre triangle touches the three corners ...
    /// assert_eq!(micro_triangle(level, 1).unwrap().neighbours(), [Some(2), Some(0), Some(3)]);
    /// // ... and each corner touches only the centre.
    /// assert_eq!(micro_triangle(level, 3).unwrap().neighbours(), [None, None, Some(1)]);
    /// ```
    #[must_use]
    pub fn neighbours(&self) -> [Option<u64>; 3] {
        let side = 1i64 << self.level.get();
        self.edges().map(|edge| {
            // Numerators are at most 2^32: i64 arithmetic cannot overflow.
            let [apex, a, b] = edge.map(|(u, v)| (u as i64, v as i64));
            // The neighbour is this triangle turned half-way about the edge's
            // midpoint: its far vertex is the apex reflected through it.
            let far = (a.0 + b.0 - apex.0, a.1 + b.1 - apex.1);
            if far.0 < 0 || far.1 < 0 || far.0 + far.1 > side {
                return None;
            }
            // (a + b + 2 far) / 4: weights 1/4, 1/4, 1/2, strictly inside.
            Some(self.walk_dyadic(a.0 + b.0 + 2 * far.0, a.1 + b.1 + 2 * far.1))
        })
    }

    #[cfg(feature = "exact")]
    /// `2^level` as a big integer.
    fn denominator(&self) -> BigInt {
        BigInt::from(1u64 << self.level.get())
    }

    /// `2^-level`, exact in binary64.
    fn scale_f64(&self) -> f64 {
        1.0 / (1u64 << self.level.get()) as f64
    }

    /// `2^-level`, exact in binary32 (the exponent range reaches `2^-126`).
    fn scale_f32(&self) -> f32 {
        1.0 / (1u64 << self.level.get()) as f32
    }

    /// The sums of the vertices' `u` and `v` numerators.
    fn vertex_sums(&self) -> (u64, u64) {
        let [p, q, r] = self.vertices;
        (p.0 + q.0 + r.0, p.1 + q.1 + r.1)
    }

    /// Each edge as `[the vertex it faces, its two endpoints]`; edge `i`
    /// faces `vertices[i]`.
    fn edges(&self) -> [[(u64, u64); 3]; 3] {
        let [p, q, r] = self.vertices;
        [[p, q, r], [q, r, p], [r, p, q]]
    }

    /// The walk's index of the point `(x, y) / 2^(level + 2)` (coordinates
    /// non-negative and at most `2^(level + 2)`), exact on [`Fixed64`].
    fn walk_dyadic(&self, x: i64, y: i64) -> u64 {
        // level + 2 <= 34 fractional bits fit in Fixed64's 60.
        let shift = Fixed64::ONE_LOG2 - (self.level.get() + 2);
        let to_fixed = |n: i64| Fixed64::from_raw(n << shift);
        uv2index::index_unchecked(to_fixed(x), to_fixed(y), self.level)
    }
}
