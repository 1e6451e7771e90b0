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

use core::cmp::Ordering;

/// A signed 256-bit integer, enough for the product of two coordinates
/// below `2^126` plus a sum of two such products. Ordered as integers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Wide {
    hi: i128,
    lo: u128,
}

impl Ord for Wide {
    fn cmp(&self, other: &Self) -> Ordering {
        self.hi.cmp(&other.hi).then(self.lo.cmp(&other.lo))
    }
}

impl PartialOrd for Wide {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Wide {
    #[inline]
    fn from_i128(x: i128) -> Wide {
        Wide {
            hi: if x < 0 { -1 } else { 0 },
            lo: x as u128,
        }
    }

    /// The exact product `a * b`.
    #[inline]
    pub(crate) fn mul(a: i128, b: i128) -> Wide {
        // Most products of a bake fit in 128 bits (coordinates near the
        // texture's scale); the 4-limb path is the general case.
        const SMALL: i128 = 1 << 62;
        if (-SMALL..SMALL).contains(&a) && (-SMALL..SMALL).contains(&b) {
            return Wide::from_i128(a * b);
        }
        let negative = (a < 0) != (b < 0);
        let (x, y) = (a.unsigned_abs(), b.unsigned_abs());
        let (x1, x0) = (x >> 64, x & u128::from(u64::MAX));
        let (y1, y0) = (y >> 64, y & u128::from(u64::MAX));
        let p00 = x0 * y0;
        let p01 = x0 * y1;
        let p10 = x1 * y0;
        let p11 = x1 * y1;
        // Sum the middle terms with their carries into the high half.
        let (mid, carry_mid) = p01.overflowing_add(p10);
        let (lo, carry_lo) = p00.overflowing_add(mid << 64);
        let hi = p11 + (mid >> 64) + (u128::from(carry_mid) << 64) + u128::from(carry_lo);
        let magnitude = Wide { hi: hi as i128, lo };
        if negative {
            magnitude.neg()
        } else {
            magnitude
        }
    }

    #[inline]
    fn neg(self) -> Wide {
        let lo = (!self.lo).wrapping_add(1);
        let hi = (!self.hi).wrapping_add(i128::from(lo == 0));
        Wide { hi, lo }
    }

    /// `self + other`; exact while the sum stays below `2^254` in
    /// magnitude, which products of coordinates below `2^126` guarantee.
    #[inline]
    pub(crate) fn add(self, other: Wide) -> Wide {
        let (lo, carry) = self.lo.overflowing_add(other.lo);
        Wide {
            hi: self
                .hi
                .wrapping_add(other.hi)
                .wrapping_add(i128::from(carry)),
            lo,
        }
    }
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
    /// micro-triangles of `level`.
    pub(crate) fn new(c: [f32; 3], size: u32, level: u32) -> Result<AxisFrame, FrameError> {
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
        let shift = (level - e_min + 1).max(1);
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

/// A closed triangle on the grid (three vertices, any orientation, possibly
/// degenerate), with its projections precomputed for the separating-axis
/// test of [`ExactTriangle::meets`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct ExactTriangle {
    pub(crate) x: [i128; 3],
    pub(crate) y: [i128; 3],
    /// Edge normals `(-dy, dx)` of the non-degenerate edges.
    axes: [(i128, i128); 3],
    axis_count: usize,
    /// The triangle's projection `[min, max]` on each axis.
    span: [(Wide, Wide); 3],
    /// Every coordinate is below `2^60` in magnitude: projections of points
    /// within a few texels fit in `i128` (the common case, tested first).
    small: bool,
    /// `span` as `i128` when `small`.
    span_small: [(i128, i128); 3],
}

impl ExactTriangle {
    pub(crate) fn new(x: [i128; 3], y: [i128; 3]) -> ExactTriangle {
        let mut t = ExactTriangle {
            x,
            y,
            axes: [(0, 0); 3],
            axis_count: 0,
            span: [(Wide::from_i128(0), Wide::from_i128(0)); 3],
            small: x
                .iter()
                .chain(&y)
                .all(|c| c.unsigned_abs() < SMALL_COORDINATE),
            span_small: [(0, 0); 3],
        };
        for edge in 0..3 {
            let (a, b) = (edge, (edge + 1) % 3);
            let (dx, dy) = (x[b] - x[a], y[b] - y[a]);
            if dx == 0 && dy == 0 {
                continue;
            }
            let axis = (-dy, dx);
            t.axes[t.axis_count] = axis;
            if t.small {
                let on_edge = axis.0 * x[a] + axis.1 * y[a];
                let third = axis.0 * x[3 - a - b] + axis.1 * y[3 - a - b];
                t.span_small[t.axis_count] = (on_edge.min(third), on_edge.max(third));
                t.span[t.axis_count] = (
                    Wide::from_i128(t.span_small[t.axis_count].0),
                    Wide::from_i128(t.span_small[t.axis_count].1),
                );
            } else {
                let on_edge = Self::project(axis, x[a], y[a]);
                let third = Self::project(axis, x[3 - a - b], y[3 - a - b]);
                t.span[t.axis_count] = (on_edge.min(third), on_edge.max(third));
            }
            t.axis_count += 1;
        }
        t
    }

    #[inline]
    fn project((ax, ay): (i128, i128), px: i128, py: i128) -> Wide {
        Wide::mul(ax, px).add(Wide::mul(ay, py))
    }

    pub(crate) fn min_x(&self) -> i128 {
        self.x[0].min(self.x[1]).min(self.x[2])
    }
    pub(crate) fn max_x(&self) -> i128 {
        self.x[0].max(self.x[1]).max(self.x[2])
    }
    pub(crate) fn min_y(&self) -> i128 {
        self.y[0].min(self.y[1]).min(self.y[2])
    }
    pub(crate) fn max_y(&self) -> i128 {
        self.y[0].max(self.y[1]).max(self.y[2])
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
    pub(crate) fn meets(&self, x0: i128, x1: i128, y0: i128, y1: i128) -> bool {
        // Axis (1, 0): [min x, max x] against [x0, x1 - e].
        if self.max_x() < x0 || self.min_x() >= x1 {
            return false;
        }
        if self.max_y() < y0 || self.min_y() >= y1 {
            return false;
        }
        let bound = SMALL_COORDINATE as i128;
        if self.small && [x0, x1, y0, y1].iter().all(|c| (-bound..bound).contains(c)) {
            // Every coordinate and corner below 2^60: an axis (a difference,
            // below 2^61) times a coordinate is below 2^121, a projection
            // below 2^122, so i128 is exact.
            self.no_edge_separates(
                &self.span_small,
                |(ax, ay), px, py| ax * px + ay * py,
                [x0, x1, y0, y1],
            )
        } else {
            self.no_edge_separates(&self.span, Self::project, [x0, x1, y0, y1])
        }
    }

    /// The edge-normal half of [`meets`](Self::meets), written once for
    /// both number types: `project` computes `a . p` exactly in `T`, and
    /// `spans` holds the triangle's projections in `T`.
    fn no_edge_separates<T: Ord + Copy>(
        &self,
        spans: &[(T, T); 3],
        project: impl Fn((i128, i128), i128, i128) -> T,
        [x0, x1, y0, y1]: [i128; 4],
    ) -> bool {
        for (&(ax, ay), &(t_min, t_max)) in self.axes[..self.axis_count].iter().zip(spans) {
            // The rectangle's lowest projection is at x0 when ax >= 0, else
            // at x1 - e (which rises as e grows): slope > 0 iff a corner
            // coordinate with a negative weight is used.
            let low_x = if ax >= 0 { x0 } else { x1 };
            let low_y = if ay >= 0 { y0 } else { y1 };
            let s_min = project((ax, ay), low_x, low_y);
            let s_min_rises = ax < 0 || ay < 0;
            if s_min > t_max || (s_min == t_max && s_min_rises) {
                return false;
            }
            let high_x = if ax > 0 { x1 } else { x0 };
            let high_y = if ay > 0 { y1 } else { y0 };
            let s_max = project((ax, ay), high_x, high_y);
            let s_max_falls = ax > 0 || ay > 0;
            if s_max < t_min || (s_max == t_min && s_max_falls) {
                return false;
            }
        }
        true
    }

    /// Is the point `(px, py)` in the closed triangle? Exact.
    pub(crate) fn contains(&self, px: i128, py: i128) -> bool {
        if px < self.min_x() || px > self.max_x() || py < self.min_y() || py > self.max_y() {
            return false;
        }
        (0..self.axis_count).all(|k| {
            let p = Self::project(self.axes[k], px, py);
            self.span[k].0 <= p && p <= self.span[k].1
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wide_products_match_i128_where_they_fit_and_big_ones_compare() {
        let values = [
            0i128,
            1,
            -1,
            (1 << 62) - 1,
            -(1 << 62),
            1 << 62,
            (1 << 100) + 12345,
            -(1 << 100) - 7,
            (1 << 63) + 1,
        ];
        for &a in &values {
            for &b in &values {
                if let Some(p) = a.checked_mul(b) {
                    assert_eq!(Wide::mul(a, b), Wide::from_i128(p), "{a} * {b}");
                }
                // Sign and order agree with a split computation.
                let w = Wide::mul(a, b);
                let zero = Wide::from_i128(0);
                assert_eq!(w.cmp(&zero), (a.signum() * b.signum()).cmp(&0), "{a} * {b}");
                assert_eq!(w.add(w.neg()), zero);
            }
        }
        // (2^100 + 1)^2 = 2^200 + 2^101 + 1 > 2^200.
        let big = Wide::mul((1 << 100) + 1, (1 << 100) + 1);
        let p200 = Wide::mul(1 << 100, 1 << 100);
        assert!(big > p200);
        assert_eq!(big.add(p200.neg()), Wide::from_i128((1 << 101) + 1));
        assert!(p200.neg() < Wide::from_i128(i128::MIN));
    }

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
}
