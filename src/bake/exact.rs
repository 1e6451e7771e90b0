//! Exact texel-space geometry: a mesh triangle's `f32` texture coordinates
//! turned into integers on a dyadic grid, micro-triangle vertices on that
//! grid, and the one predicate the classifier needs — does a closed triangle
//! meet a half-open rectangle `[x0, x1) x [y0, y1)` — decided without
//! rounding.
//!
//! Why integers suffice: a micro-triangle vertex has barycentrics
//! `(a, b) / 2^level`, so its texture coordinate
//! `((2^level - a - b) c0 + a c1 + b c2) / 2^level` is a sum of binary32
//! values times integers over a power of two, and times the texture size it
//! is still a dyadic rational. [`AxisFrame`] picks, per axis, the one power
//! of two that makes every such value (and every half-texel boundary) an
//! integer. Products of two coordinates need up to 2 x 101 bits: [`Wide`]
//! holds them exactly.

use crate::num::wide::Wide;
use core::ops::{Add, Mul};

/// An exact point in texel space: `x / 2^shift_x` texels from the texture's
/// left edge, `y / 2^shift_y` from its top (the texture repeats, mirrors or
/// clamps beyond as the sampler says).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TexelPoint {
    /// Numerator of the horizontal texel coordinate.
    pub x: i128,
    /// Its power-of-two denominator's exponent.
    pub shift_x: u32,
    /// Numerator of the vertical texel coordinate.
    pub y: i128,
    /// Its power-of-two denominator's exponent.
    pub shift_y: u32,
}

impl TexelPoint {
    /// The point's texture coordinates `(u, v)`, rounded to `f64`.
    #[must_use]
    pub fn uv_f64(&self, width: u32, height: u32) -> (f64, f64) {
        let scale = |n: i128, shift: u32, size: u32| {
            n as f64 * libm_exp2(-(shift as i32)) / f64::from(size)
        };
        (
            scale(self.x, self.shift_x, width),
            scale(self.y, self.shift_y, height),
        )
    }
}

/// `2^e` for the exponents a [`TexelPoint`] can have (no `std` needed).
fn libm_exp2(e: i32) -> f64 {
    let mut r = 1.0f64;
    let step = if e < 0 { 0.5 } else { 2.0 };
    for _ in 0..e.unsigned_abs() {
        r *= step;
    }
    r
}

/// `values` in `i64` when every one is below `bound` (at most `2^63`) in
/// magnitude, else `None`: how a caller checks the bound that lets it run
/// in `i64` (see [`GridInt`](crate::num::wide::GridInt)).
pub(crate) fn narrowed_below<const N: usize>(values: [i128; N], bound: u128) -> Option<[i64; N]> {
    // Exact casts once the bound holds.
    values
        .iter()
        .all(|v| v.unsigned_abs() < bound)
        .then(|| values.map(|v| v as i64))
}

/// Coordinates of the grid: every texel-space coordinate the classifier
/// handles is below this in magnitude, so products and sums of two products
/// stay exact in [`Wide`].
pub(crate) const COORDINATE_LIMIT: i128 = 1 << 100;

/// Below this, coordinates take the `i128` path of [`ExactTriangle::meets`].
const SMALL_COORDINATE: u128 = 1 << 60;

/// One axis of a mesh triangle in texel space: the three corner values on
/// a common integer grid of spacing `2^-shift` texels.
///
/// A micro-triangle vertex with barycentric numerators `(a, b)` over
/// `2^level` lies at `(2^level - a - b) * corner[0] + a * corner[1] +
/// b * corner[2]` grid units ([`AxisFrame::at`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct AxisFrame {
    pub(crate) corner: [i128; 3],
    /// Grid units per texel, as a power of two: `>= 1`, so half texels are
    /// on the grid too (linear filtering's sample offset).
    pub(crate) shift: u32,
}

/// Why a triangle has no exact frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FrameError {
    /// A coordinate is NaN or infinite.
    NotFinite,
    /// The coordinates' exponents are too far apart (or too large) for the
    /// 100-bit grid; see [`COORDINATE_LIMIT`].
    OutOfRange,
}

/// `x = mantissa * 2^exponent` exactly, for a finite `x`; `(0, 0)` for zero.
fn decompose(x: f32) -> (i64, i32) {
    let bits = x.to_bits();
    let sign = if bits >> 31 == 1 { -1 } else { 1 };
    let biased = ((bits >> 23) & 0xff) as i32;
    let fraction = i64::from(bits & 0x7f_ffff);
    let (mantissa, exponent) = if biased == 0 {
        (fraction, -149)
    } else {
        (fraction | 0x80_0000, biased - 150)
    };
    if mantissa == 0 {
        return (0, 0);
    }
    // Strip trailing zeros so the exponent is the value's own ulp scale.
    let zeros = mantissa.trailing_zeros();
    (sign * (mantissa >> zeros), exponent + zeros as i32)
}

impl AxisFrame {
    /// The frame of one axis: coordinates `c` scaled by `size` texels, for
    /// micro-triangles of `level`, on a grid of at least `min_shift`
    /// (`2^min_shift` units per texel; 0 for the coarsest exact grid).
    pub(crate) fn new(
        c: [f32; 3],
        size: u32,
        level: u32,
        min_shift: u32,
    ) -> Result<AxisFrame, FrameError> {
        if c.iter().any(|x| !x.is_finite()) {
            return Err(FrameError::NotFinite);
        }
        let parts = c.map(decompose);
        let e_min = parts
            .iter()
            .filter(|p| p.0 != 0)
            .map(|p| p.1)
            .min()
            .unwrap_or(0);
        // value_k = m_k 2^(e_k - e_min) 2^e_min; a vertex is
        // sum n_k value_k / 2^level; on a grid of 2^-shift texels it is
        // sum n_k (size m_k 2^(e_k - e_min) 2^(e_min - level + shift)).
        let level = level as i32;
        let shift = (level - e_min + 1).max(1).max(min_shift.min(200) as i32);
        let extra = e_min - level + shift; // >= 1
        let mut corner = [0i128; 3];
        for (out, &(m, e)) in corner.iter_mut().zip(&parts) {
            if m == 0 {
                continue;
            }
            let up = (e - e_min + extra) as u32;
            // |m| < 2^24, size < 2^32: the product is below 2^56; the value
            // must stay below the limit over 2^level (a vertex sums weights
            // up to 2^level).
            if up > 120 {
                return Err(FrameError::OutOfRange);
            }
            let value = i128::from(m) * i128::from(size);
            let scaled = value
                .checked_mul(1i128 << up)
                .ok_or(FrameError::OutOfRange)?;
            if scaled.unsigned_abs() >= (COORDINATE_LIMIT >> (level + 2)) as u128 {
                return Err(FrameError::OutOfRange);
            }
            *out = scaled;
        }
        if shift > 96 {
            return Err(FrameError::OutOfRange);
        }
        Ok(AxisFrame {
            corner,
            shift: shift as u32,
        })
    }

    /// The grid coordinate of the vertex with barycentric numerators
    /// `(a, b)` over `2^level` (`a + b <= 2^level`).
    #[inline]
    pub(crate) fn at(&self, level: u32, a: u64, b: u64) -> i128 {
        let w = (1i128 << level) - i128::from(a) - i128::from(b);
        w * self.corner[0] + i128::from(a) * self.corner[1] + i128::from(b) * self.corner[2]
    }
}

/// Below this, coordinates take the `i64` path of [`ExactTriangle::meets`]:
/// an axis (a difference, below `2^31`) times a coordinate is below
/// `2^61`, a projection (two such) below `2^62`. Bakes at ordinary levels
/// and texture sizes stay far below it (a 4096-texel texture at level 12
/// with `1/8`-aligned coordinates: `2^12 * 2^16 = 2^28`).
const NARROW_COORDINATE: u128 = 1 << 30;

/// A closed triangle on the grid (three vertices, any orientation, possibly
/// degenerate), with its projections precomputed for the separating-axis
/// test of [`ExactTriangle::meets`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct ExactTriangle {
    pub(crate) x: [i128; 3],
    pub(crate) y: [i128; 3],
    /// The bounding box `[min_x, max_x] x [min_y, max_y]`.
    bounds: [i128; 4],
    /// Edge normals `(-dy, dx)` of the non-degenerate edges.
    axes: [(i128, i128); 3],
    /// The first vertex of each axis's edge (the third vertex follows).
    from: [usize; 3],
    axis_count: usize,
    /// The triangle's projection `[min, max]` on each axis, in the
    /// narrowest exact type its coordinates allow.
    spans: Spans,
}

/// An [`ExactTriangle`]'s projections in the narrowest exact number type
/// (the narrow ones are the common case: a bake's coordinates are small).
#[derive(Clone, Copy, Debug)]
enum Spans {
    /// Every coordinate below [`NARROW_COORDINATE`]: `i64` axes too.
    Narrow {
        axes: [(i64, i64); 3],
        spans: [(i64, i64); 3],
    },
    /// Every coordinate below [`SMALL_COORDINATE`].
    Small([(i128, i128); 3]),
    /// Any coordinate below [`COORDINATE_LIMIT`].
    Wide([(Wide, Wide); 3]),
}

/// The largest magnitude among `c`.
#[inline]
fn magnitude(c: &[i128]) -> u128 {
    c.iter().map(|v| v.unsigned_abs()).max().unwrap_or(0)
}

/// `a . p` in the coordinates' own integer type: exact for narrow
/// coordinates in `i64` and small ones in `i128`.
#[inline]
fn project_int<T: Copy + Mul<Output = T> + Add<Output = T>>((ax, ay): (T, T), px: T, py: T) -> T {
    ax * px + ay * py
}

/// `a . p` exactly in [`Wide`], for any grid coordinates.
#[inline]
fn project_wide((ax, ay): (i128, i128), px: i128, py: i128) -> Wide {
    Wide::mul(ax, px).add(Wide::mul(ay, py))
}

/// The projections `[min, max]` of a triangle on its axes, written once
/// for every number type: the edge's first vertex and the third vertex
/// bound it (the edge's second vertex projects as the first).
#[inline]
fn spans_of<C: Copy, T: Ord + Copy + Default>(
    axes: &[(C, C); 3],
    from: &[usize; 3],
    count: usize,
    (x, y): ([C; 3], [C; 3]),
    project: impl Fn((C, C), C, C) -> T,
) -> [(T, T); 3] {
    let mut spans = [(T::default(), T::default()); 3];
    for k in 0..count {
        let (a, third) = (from[k], (from[k] + 2) % 3);
        let on_edge = project(axes[k], x[a], y[a]);
        let other = project(axes[k], x[third], y[third]);
        spans[k] = (on_edge.min(other), on_edge.max(other));
    }
    spans
}

/// The edge-normal half of [`ExactTriangle::meets`], written once for
/// every number type: `project` computes `a . p` exactly in `T`, `spans`
/// holds the triangle's projections on `axes` in `T`, and the rectangle
/// `[x0, x1) x [y0, y1)` is in the axes' coordinate type `C`.
#[inline]
fn no_edge_separates<C: Copy + Ord + Default, T: Ord + Copy>(
    axes: &[(C, C)],
    spans: &[(T, T)],
    project: impl Fn((C, C), C, C) -> T,
    [x0, x1, y0, y1]: [C; 4],
) -> bool {
    let zero = C::default();
    for (&(ax, ay), &(t_min, t_max)) in axes.iter().zip(spans) {
        // The rectangle's lowest projection is at x0 when ax >= 0, else
        // at x1 - e (which rises as e grows): slope > 0 iff a corner
        // coordinate with a negative weight is used.
        let low_x = if ax >= zero { x0 } else { x1 };
        let low_y = if ay >= zero { y0 } else { y1 };
        let s_min = project((ax, ay), low_x, low_y);
        let s_min_rises = ax < zero || ay < zero;
        if s_min > t_max || (s_min == t_max && s_min_rises) {
            return false;
        }
        let high_x = if ax > zero { x1 } else { x0 };
        let high_y = if ay > zero { y1 } else { y0 };
        let s_max = project((ax, ay), high_x, high_y);
        let s_max_falls = ax > zero || ay > zero;
        if s_max < t_min || (s_max == t_min && s_max_falls) {
            return false;
        }
    }
    true
}

impl ExactTriangle {
    pub(crate) fn new(x: [i128; 3], y: [i128; 3]) -> ExactTriangle {
        let mut axes = [(0, 0); 3];
        let mut from = [0; 3];
        let mut count = 0;
        for edge in 0..3 {
            let (a, b) = (edge, (edge + 1) % 3);
            let (dx, dy) = (x[b] - x[a], y[b] - y[a]);
            if dx == 0 && dy == 0 {
                continue;
            }
            axes[count] = (-dy, dx);
            from[count] = a;
            count += 1;
        }
        let size = magnitude(&x).max(magnitude(&y));
        let spans = if size < NARROW_COORDINATE {
            // Exact casts: every coordinate and axis is below 2^31.
            let narrow = |c: [i128; 3]| c.map(|v| v as i64);
            let axes = axes.map(|(ax, ay)| (ax as i64, ay as i64));
            Spans::Narrow {
                axes,
                spans: spans_of(&axes, &from, count, (narrow(x), narrow(y)), project_int),
            }
        } else if size < SMALL_COORDINATE {
            Spans::Small(spans_of(&axes, &from, count, (x, y), project_int))
        } else {
            Spans::Wide(spans_of(&axes, &from, count, (x, y), project_wide))
        };
        ExactTriangle {
            x,
            y,
            bounds: [
                x[0].min(x[1]).min(x[2]),
                x[0].max(x[1]).max(x[2]),
                y[0].min(y[1]).min(y[2]),
                y[0].max(y[1]).max(y[2]),
            ],
            axes,
            from,
            axis_count: count,
            spans,
        }
    }

    #[inline]
    pub(crate) fn min_x(&self) -> i128 {
        self.bounds[0]
    }
    #[inline]
    pub(crate) fn max_x(&self) -> i128 {
        self.bounds[1]
    }
    #[inline]
    pub(crate) fn min_y(&self) -> i128 {
        self.bounds[2]
    }
    #[inline]
    pub(crate) fn max_y(&self) -> i128 {
        self.bounds[3]
    }

    /// The projections in `i128` (stored, or computed for a rectangle
    /// wider than the triangle's own tier).
    fn spans_small(&self) -> [(i128, i128); 3] {
        match self.spans {
            Spans::Small(spans) => spans,
            _ => spans_of(
                &self.axes,
                &self.from,
                self.axis_count,
                (self.x, self.y),
                project_int,
            ),
        }
    }

    /// The projections in [`Wide`] (stored, or computed).
    fn spans_wide(&self) -> [(Wide, Wide); 3] {
        match self.spans {
            Spans::Wide(spans) => spans,
            _ => spans_of(
                &self.axes,
                &self.from,
                self.axis_count,
                (self.x, self.y),
                project_wide,
            ),
        }
    }

    /// Does this closed triangle share a point with the half-open rectangle
    /// `[x0, x1) x [y0, y1)` (`x0 < x1`, `y0 < y1`)? Exact.
    ///
    /// Why this is right: the triangle meets the half-open rectangle iff it
    /// meets the closed `[x0, x1 - e] x [y0, y1 - e]` for some `e > 0`, and
    /// two compact convex polygons are disjoint iff some edge normal of
    /// either strictly separates their projections (the separating-axis
    /// theorem; a degenerate triangle's normals still include its line's).
    /// The rectangle's projection on an axis moves linearly with `e`, so
    /// "separated for every small `e`" is a comparison at `e = 0` plus the
    /// sign of the slope, both exact.
    #[inline]
    pub(crate) fn meets(&self, x0: i128, x1: i128, y0: i128, y1: i128) -> bool {
        // Axis (1, 0): [min x, max x] against [x0, x1 - e].
        if self.max_x() < x0 || self.min_x() >= x1 {
            return false;
        }
        if self.max_y() < y0 || self.min_y() >= y1 {
            return false;
        }
        let rect = [x0, x1, y0, y1];
        let count = self.axis_count;
        let reach = magnitude(&rect);
        match &self.spans {
            // Triangle and rectangle below 2^30: i64 is exact.
            Spans::Narrow { axes, spans } if reach < NARROW_COORDINATE => no_edge_separates(
                &axes[..count],
                &spans[..count],
                project_int,
                rect.map(|c| c as i64),
            ),
            // Both below 2^60: an axis (below 2^61) times a coordinate is
            // below 2^121, a projection below 2^122.
            Spans::Narrow { .. } | Spans::Small(_) if reach < SMALL_COORDINATE => {
                no_edge_separates(
                    &self.axes[..count],
                    &self.spans_small()[..count],
                    project_int,
                    rect,
                )
            }
            _ => no_edge_separates(
                &self.axes[..count],
                &self.spans_wide()[..count],
                project_wide,
                rect,
            ),
        }
    }

    /// Is the point `(px, py)` in the closed triangle? Exact.
    pub(crate) fn contains(&self, px: i128, py: i128) -> bool {
        if px < self.min_x() || px > self.max_x() || py < self.min_y() || py > self.max_y() {
            return false;
        }
        let spans = self.spans_wide();
        (0..self.axis_count).all(|k| {
            let p = project_wide(self.axes[k], px, py);
            spans[k].0 <= p && p <= spans[k].1
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use micromap_index_test_support::SplitMix64;

    #[test]
    fn decompose_is_exact() {
        for x in [0.5f32, 0.3, -1.0e-40, 3.0e38, 1.0, -7.25, f32::MIN_POSITIVE] {
            let (m, e) = decompose(x);
            assert_eq!(m as f64 * 2f64.powi(e), f64::from(x), "{x}");
            assert!(m % 2 != 0);
        }
        assert_eq!(decompose(-0.0), (0, 0));
    }

    /// The unit square [0, 2) x [0, 2) against triangles touching it only at
    /// its closed or open sides.
    #[test]
    fn half_open_rectangle_contacts() {
        let meets = |x: [i128; 3], y: [i128; 3]| ExactTriangle::new(x, y).meets(0, 2, 0, 2);
        // Vertex exactly on the included corner (0, 0) from outside.
        assert!(meets([0, -1, 0], [0, 0, -1]));
        // Vertex on the excluded corner (2, 2) from outside.
        assert!(!meets([2, 3, 2], [2, 2, 3]));
        // Edge lying on the excluded side x = 2.
        assert!(!meets([2, 3, 2], [0, 1, 1]));
        // Edge lying on the included side x = 0.
        assert!(meets([0, -1, 0], [0, 1, 1]));
        // Vertex on the excluded corner (2, 0): x = 2 is out.
        assert!(!meets([2, 3, 3], [0, 0, -1]));
        // Diagonal edge through the excluded corner (2, 2) only.
        assert!(!meets([1, 3, 3], [3, 1, 3]));
        // ...and one crossing just inside.
        assert!(meets([1, 3, 3], [2, 0, 3]));
        // A degenerate (point) triangle inside, on the included and on the
        // excluded side.
        assert!(meets([1, 1, 1], [1, 1, 1]));
        assert!(meets([0, 0, 0], [1, 1, 1]));
        assert!(!meets([2, 2, 2], [1, 1, 1]));
        // A segment crossing the rectangle, and one passing the excluded
        // corner diagonally outside.
        assert!(meets([-1, 3, 3], [1, 1, 1]));
        assert!(!meets([1, 3, 1], [3, 1, 3]));
    }

    /// `meets` in every number type that can hold the inputs, past the
    /// bounding-box test: `[narrow, small, wide]`, `None` where a type
    /// cannot hold them.
    fn meets_each_way(t: &ExactTriangle, rect: [i128; 4]) -> [Option<bool>; 3] {
        let n = t.axis_count;
        let size = magnitude(&t.x).max(magnitude(&t.y)).max(magnitude(&rect));
        let narrow = (size < NARROW_COORDINATE).then(|| {
            let axes = t.axes.map(|(ax, ay)| (ax as i64, ay as i64));
            let narrow = |c: [i128; 3]| c.map(|v| v as i64);
            let spans = spans_of(&axes, &t.from, n, (narrow(t.x), narrow(t.y)), project_int);
            no_edge_separates(&axes[..n], &spans[..n], project_int, rect.map(|c| c as i64))
        });
        let small = (size < SMALL_COORDINATE).then(|| {
            let spans = spans_of(&t.axes, &t.from, n, (t.x, t.y), project_int);
            no_edge_separates(&t.axes[..n], &spans[..n], project_int, rect)
        });
        let spans = spans_of(&t.axes, &t.from, n, (t.x, t.y), project_wide);
        let wide = no_edge_separates(&t.axes[..n], &spans[..n], project_wide, rect);
        [narrow, small, Some(wide)]
    }

    /// The `i64` and `i128` paths agree with the 256-bit one on random
    /// triangles and rectangles straddling the thresholds where `meets`
    /// switches between them (coordinates near `+-2^30` and `+-2^60`, with
    /// differences up to twice that), and `meets` agrees with all of them.
    #[test]
    fn narrow_small_and_wide_paths_agree_near_their_thresholds() {
        let mut rng = SplitMix64::new(0x5eed);
        let mut next = move || rng.next_u64();
        let mut seen = [[0u32; 2]; 3];
        for threshold in [NARROW_COORDINATE as i128, SMALL_COORDINATE as i128] {
            for case in 0..20_000 {
                // A centre at +-threshold, and points within `spread` of it:
                // small spreads test fine contacts, large ones the extremes.
                let sign = if case % 2 == 0 { 1 } else { -1 };
                let spread = 1i128 << (next() % 62).min(u64::from(threshold.trailing_zeros()) + 1);
                let centre = sign * threshold;
                // Mostly just inside the threshold; one case in four lets
                // points step over it by one unit.
                let over = i128::from(case % 4 == 0);
                let mut point = || centre - sign * ((i128::from(next()) % spread) - over);
                let (x, y) = ([point(), point(), point()], [point(), point(), point()]);
                let t = match case % 5 {
                    // Degenerate: a repeated vertex, a point.
                    0 => ExactTriangle::new([x[0], x[1], x[1]], [y[0], y[1], y[1]]),
                    1 => ExactTriangle::new([x[0]; 3], [y[0]; 3]),
                    _ => ExactTriangle::new(x, y),
                };
                let (mut a, mut b, mut c, mut d) = (point(), point(), point(), point());
                if a == b || c == d {
                    continue;
                }
                if a > b {
                    core::mem::swap(&mut a, &mut b);
                }
                if c > d {
                    core::mem::swap(&mut c, &mut d);
                }
                let rect = [a, b, c, d];
                let each = meets_each_way(&t, rect);
                let wide = each[2].unwrap();
                for (k, got) in each.iter().enumerate() {
                    if let Some(got) = got {
                        assert_eq!(*got, wide, "path {k}: {t:?} {rect:?}");
                        seen[k][usize::from(*got)] += 1;
                    }
                }
                let in_box = t.max_x() >= a && t.min_x() < b && t.max_y() >= c && t.min_y() < d;
                assert_eq!(t.meets(a, b, c, d), in_box && wide, "{t:?} {rect:?}");
            }
        }
        // Every path answered both ways many times.
        for (k, counts) in seen.iter().enumerate() {
            assert!(counts[0] > 1000 && counts[1] > 1000, "path {k}: {counts:?}");
        }
    }
}
