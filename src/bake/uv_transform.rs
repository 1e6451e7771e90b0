//! glTF's `KHR_texture_transform` as a renderer applies it: to the
//! *interpolated* texture coordinate, in the shader, in binary32
//! ([`UvTransform`]). The baker places each triangle at its vertices'
//! transformed coordinates (rounded to binary32, [`UvTransform::place`])
//! and widens the GPU model's margin by a bound on everything that differs
//! from the exact transform of the exact hit point
//! ([`UvTransform::axis_errors`]); `docs/bake.md` ("Texture transforms")
//! derives the bound. The steps, each with its contract:
//!
//! 1. **Sine and cosine** ([`sin_cos`]): of the binary32 rotation, in
//!    `f64` without `std`, within [`TRIG_ERROR`] of the real values for
//!    `|rotation| <= MAX_ROTATION` (tested against the platform's `libm`).
//! 2. **Placement** ([`UvTransform::place`]): `offset + R (scale * uv)`
//!    in `f64`, rounded once to binary32; within [`UvTransform::axis_errors`]'s
//!    `rho` of the exact image.
//! 3. **The shader's error** (`tau` of [`UvTransform::axis_errors`]): what
//!    a renderer's binary32 evaluation of the transform on a binary32
//!    coordinate can add, for the matrix built on the CPU (in `f64` or
//!    binary32, from the binary32 or the `f64` parameters, sine and cosine
//!    within a binary32 unit in the last place) and applied in any order,
//!    with or without fused multiply-adds.

use super::float::{abs, exp2};

/// The largest `|rotation|` accepted, in radians: far beyond any asset's
/// (glTF exporters write angles in `[-2 pi, 2 pi]`), small enough that the
/// argument reduction of the sine and cosine stays exact (`k * PIO2_HI` exact for
/// `|k| < 2^20`).
pub const MAX_ROTATION: f32 = 65536.0;

/// A bound on `|sin_cos(x) - (sin x, cos x)|` per component, for
/// `|x| <= MAX_ROTATION`: far above the few units in the last place of
/// `f64` the reduction and the polynomials lose (the tests measure below
/// `2^-50`), and far below every other term of the margin.
pub(crate) const TRIG_ERROR: f64 = 1.0 / (1u64 << 40) as f64;

/// `(sin x, cos x)` for `|x| <= MAX_ROTATION`, within [`TRIG_ERROR`].
///
/// Cody and Waite's reduction by `pi / 2` in two parts (fdlibm's
/// `pio2_1`, the first 33 bits, and `pio2_1t`, the rest): `k * PIO2_HI` is
/// exact for `|k| < 2^20` and `x - k * PIO2_HI` is exact (the operands are
/// within a factor two), so `r` errs by the rounding of `k * PIO2_LO` and
/// of the last subtraction, below `2^-52`. Then Taylor polynomials on
/// `|r| <= pi/4 + 2^-40`, to degree 21 and 22 (truncation below `2^-70`).
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    const PIO2_HI: f64 = 1.570_796_326_734_125_6; // 0x3FF921FB54400000
    const PIO2_LO: f64 = 6.077_100_506_506_192e-11; // 0x3DD0B4611A626331
    const TWO_OVER_PI: f64 = core::f64::consts::FRAC_2_PI;
    // round(x * 2 / pi) without std: the nearest integer of a value below
    // 2^17, by adding and subtracting 1.5 * 2^52.
    let shift = 6_755_399_441_055_744.0;
    let k = (x * TWO_OVER_PI + shift) - shift;
    let r = (x - k * PIO2_HI) - k * PIO2_LO;
    let r2 = r * r;
    // sin r = r (1 - r^2/3! (1 - r^2/(4 5) (1 - ...))), Horner from the top.
    let mut s = 1.0;
    let mut c = 1.0;
    for n in (1..=10).rev() {
        let n = f64::from(n);
        s = 1.0 - r2 / ((2.0 * n) * (2.0 * n + 1.0)) * s;
        c = 1.0 - r2 / ((2.0 * n - 1.0) * (2.0 * n)) * c;
    }
    let (s, c) = (r * s, c);
    match (k as i64).rem_euclid(4) {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// A texture-coordinate transform: `uv' = offset + R(rotation) (scale *
/// uv)`, `R` the counter-clockwise rotation whose columns are
/// `(cos, sin)` and `(-sin, cos)` (the extension's `translation *
/// rotation * scale`, GLSL's column-major `mat3`s). Its parameters are
/// binary32, as the renderer's uniforms are.
///
/// ```
/// use micromap_index::bake::UvTransform;
/// let t = UvTransform::new([0.5, 0.0], 0.0, [2.0, 1.0]).unwrap();
/// assert_eq!(t.place([0.25, 0.75]), [1.0, 0.75]);
/// let quarter = UvTransform::new([0.0, 0.0], core::f32::consts::FRAC_PI_2, [1.0, 1.0]).unwrap();
/// // (1, 0) turns to (0, 1), up to the binary32 rounding of pi / 2.
/// let [u, v] = quarter.place([1.0, 0.0]);
/// assert!(u.abs() < 1e-7 && v == 1.0);
/// assert!(UvTransform::IDENTITY.is_identity());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    offset: [f32; 2],
    rotation: f32,
    scale: [f32; 2],
    /// `sin_cos(rotation)`.
    sin: f64,
    cos: f64,
}

/// Why [`UvTransform::new`] refuses its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum UvTransformError {
    /// An offset, rotation or scale is NaN or infinite.
    NotFinite,
    /// `|rotation|` is above [`MAX_ROTATION`].
    Rotation(f32),
}

impl core::fmt::Display for UvTransformError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            UvTransformError::NotFinite => {
                write!(f, "a texture transform's offset, rotation and scale must be finite")
            }
            UvTransformError::Rotation(r) => write!(
                f,
                "texture transform rotation {r}: expected at most {MAX_ROTATION} radians in magnitude"
            ),
        }
    }
}

impl core::error::Error for UvTransformError {}

impl Default for UvTransform {
    /// [`UvTransform::IDENTITY`].
    fn default() -> Self {
        UvTransform::IDENTITY
    }
}

/// What the margin of one axis needs to know of a transformed triangle
/// (in texture-coordinate units, before the texture size).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct AxisErrors {
    /// `sum_j |L_aj| A_j`: the axis's row of the linear part `L` applied
    /// to the source coordinates' magnitudes `A_j = max_k |uv_k[j]|`; the
    /// shader's interpolation error, `2^-20 A_j` per source axis, reaches
    /// this axis through `L`.
    pub(crate) interpolated: f64,
    /// `sum_j |L_aj|`: what an absolute interpolation error (16-bit
    /// floats' subnormal spacing) becomes on this axis.
    pub(crate) row_sum: f64,
    /// `tau`: the shader's binary32 evaluation of the transform.
    pub(crate) tau: f64,
    /// `rho`: the placement's distance from the exact image of a vertex.
    pub(crate) rho: f64,
    /// `max_j A_j` (16-bit interpolation needs it below `2^15`).
    pub(crate) source_max: f64,
}

impl UvTransform {
    /// No transform: every coordinate as it is.
    pub const IDENTITY: UvTransform = UvTransform {
        offset: [0.0, 0.0],
        rotation: 0.0,
        scale: [1.0, 1.0],
        sin: 0.0,
        cos: 1.0,
    };

    /// The transform `offset + R(rotation) (scale * uv)`, each parameter a
    /// finite binary32 value (glTF's JSON numbers rounded once), the
    /// rotation in radians, at most [`MAX_ROTATION`] in magnitude.
    pub fn new(offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> Result<Self, UvTransformError> {
        if !offset
            .iter()
            .chain(&scale)
            .chain(core::iter::once(&rotation))
            .all(|x| x.is_finite())
        {
            return Err(UvTransformError::NotFinite);
        }
        if abs(f64::from(rotation)) > f64::from(MAX_ROTATION) {
            return Err(UvTransformError::Rotation(rotation));
        }
        let (sin, cos) = if rotation == 0.0 {
            (0.0, 1.0)
        } else {
            sin_cos(f64::from(rotation))
        };
        Ok(UvTransform {
            offset,
            rotation,
            scale,
            sin,
            cos,
        })
    }

    /// The offset.
    #[must_use]
    pub fn offset(&self) -> [f32; 2] {
        self.offset
    }

    /// The rotation, in radians.
    #[must_use]
    pub fn rotation(&self) -> f32 {
        self.rotation
    }

    /// The scale.
    #[must_use]
    pub fn scale(&self) -> [f32; 2] {
        self.scale
    }

    /// Whether every coordinate maps to itself (offset 0, rotation 0,
    /// scale 1): the baker then places the triangle as given.
    #[must_use]
    pub fn is_identity(&self) -> bool {
        self.offset == [0.0, 0.0] && self.rotation == 0.0 && self.scale == [1.0, 1.0]
    }

    /// The linear part `L` (row `a`, column `j`): `L = R diag(scale)`.
    fn linear(&self) -> [[f64; 2]; 2] {
        let [sx, sy] = self.scale.map(f64::from);
        [
            [self.cos * sx, -self.sin * sy],
            [self.sin * sx, self.cos * sy],
        ]
    }

    /// The transformed coordinate of `uv`, computed in `f64` and rounded
    /// once to binary32: where the baker places a vertex. Exact whenever
    /// the image is a binary32 pair and the rotation is 0 (the products of
    /// two binary32 values are exact in `f64`, and so is a sum that is
    /// exact in binary32).
    #[must_use]
    pub fn place(&self, uv: [f32; 2]) -> [f32; 2] {
        if self.is_identity() {
            return uv;
        }
        let l = self.linear();
        let [u, v] = uv.map(f64::from);
        [0, 1].map(|a| {
            if self.rotation == 0.0 {
                // One product and one sum: exact when the result is.
                (l[a][a] * [u, v][a] + f64::from(self.offset[a])) as f32
            } else {
                (f64::from(self.offset[a]) + l[a][0] * u + l[a][1] * v) as f32
            }
        })
    }

    /// A triangle's vertices each [`place`](Self::place)d: the triangle the
    /// shader samples, for level choices, area weights, previews and
    /// renderers that transform per vertex.
    #[must_use]
    pub fn place_triangle(&self, uv: &[[f32; 2]; 3]) -> [[f32; 2]; 3] {
        uv.map(|c| self.place(c))
    }

    /// The image of `uv` if it is exactly a binary32 pair (rotation 0 and
    /// `scale * uv + offset` exact; checked with an exact two-sum), as the
    /// exact model needs it; `None` otherwise.
    #[must_use]
    pub fn exact_image(&self, uv: [f32; 2]) -> Option<[f32; 2]> {
        if self.is_identity() {
            return Some(uv);
        }
        if self.rotation != 0.0 {
            return None;
        }
        let image = |a: usize| -> Option<f32> {
            // The product of two binary32 values is exact in f64.
            let p = f64::from(self.scale[a]) * f64::from(uv[a]);
            let o = f64::from(self.offset[a]);
            let s = p + o;
            // Knuth's two-sum: the rounding error of `p + o`, exactly.
            let bb = s - p;
            let error = (p - (s - bb)) + (o - bb);
            let narrow = s as f32;
            (error == 0.0 && s.is_finite() && f64::from(narrow) == s).then_some(narrow)
        };
        Some([image(0)?, image(1)?])
    }

    /// The per-axis error terms of `docs/bake.md` ("Texture transforms")
    /// for the source triangle `uv` placed at `placed`
    /// ([`place`](Self::place) of each vertex), in texture-coordinate
    /// units. With `u = 2^-24` and `Ā_j = A_j (1 + 2^-18)` (the magnitude
    /// of a binary32 interpolated coordinate):
    ///
    /// - `tau_a = 2^-20 (sum_j |L_aj| Ā_j + |o_a|) + u |rotation| sum_j
    ///   |s_j| Ā_j`: the shader's at most five roundings (`2^-21` of the
    ///   terms' magnitudes), the matrix entries' own (the sine and cosine
    ///   within a binary32 unit, the scale, offset and products rounded
    ///   from `f64` or binary32 parameters: `2^-21` relative), and an
    ///   angle read as `f64` instead of binary32 (`u |rotation|`);
    /// - `rho_a = u A'_a + 2^-40 (sum_j |s_j| Ā_j + |o_a|) + 2^-126`: the
    ///   rounding of the placed vertex (`A'_a` its axis's largest
    ///   magnitude), the `f64` sine and cosine's error with room for the
    ///   `f64` arithmetic, and subnormal spacing.
    pub(crate) fn axis_errors(
        &self,
        uv: &[[f32; 2]; 3],
        placed: &[[f32; 2]; 3],
    ) -> [AxisErrors; 2] {
        let max = |x: f64, y: f64| if x >= y { x } else { y };
        let source = [0, 1].map(|j| uv.iter().map(|c| abs(f64::from(c[j]))).fold(0.0, max));
        let bar = source.map(|a| a * (1.0 + exp2(-18)));
        let l = self.linear();
        let scaled: f64 = (0..2).map(|j| abs(f64::from(self.scale[j])) * bar[j]).sum();
        let rotation = abs(f64::from(self.rotation));
        [0, 1].map(|a| {
            let interpolated = abs(l[a][0]) * source[0] + abs(l[a][1]) * source[1];
            let through = abs(l[a][0]) * bar[0] + abs(l[a][1]) * bar[1];
            let offset = abs(f64::from(self.offset[a]));
            let placed_max = placed.iter().map(|c| abs(f64::from(c[a]))).fold(0.0, max);
            AxisErrors {
                interpolated,
                row_sum: abs(l[a][0]) + abs(l[a][1]),
                tau: exp2(-20) * (through + offset) + exp2(-24) * rotation * scaled,
                rho: exp2(-24) * placed_max + TRIG_ERROR * (scaled + offset) + exp2(-126),
                source_max: max(source[0], source[1]),
            }
        })
    }
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;

    #[test]
    fn sin_cos_is_within_its_bound_of_libm() {
        let mut worst: f64 = 0.0;
        let mut x = -f64::from(MAX_ROTATION);
        // Every 1/1000 radian near 0, and a sweep to the largest rotation.
        let mut check = |x: f64| {
            let (s, c) = sin_cos(x);
            worst = worst.max((s - x.sin()).abs()).max((c - x.cos()).abs());
        };
        while x <= f64::from(MAX_ROTATION) {
            check(x);
            x += 0.618_033_988_7;
        }
        for i in -20_000..=20_000 {
            check(f64::from(i) / 1000.0);
        }
        for k in -40..=40 {
            // Near multiples of pi / 2, where the reduction cancels most.
            let m = f64::from(k) * core::f64::consts::FRAC_PI_2;
            for d in [-1e-9, 0.0, 1e-9] {
                check(m + d);
                check(f64::from((m + d) as f32));
            }
        }
        check(f64::from(MAX_ROTATION));
        check(-f64::from(MAX_ROTATION));
        assert!(worst < exp2(-50), "worst {worst:e}");
        assert!(worst < TRIG_ERROR);
    }

    #[test]
    fn new_refuses_what_it_cannot_model() {
        assert_eq!(
            UvTransform::new([f32::NAN, 0.0], 0.0, [1.0, 1.0]),
            Err(UvTransformError::NotFinite)
        );
        assert_eq!(
            UvTransform::new([0.0, 0.0], 0.0, [1.0, f32::INFINITY]),
            Err(UvTransformError::NotFinite)
        );
        assert_eq!(
            UvTransform::new([0.0, 0.0], 70000.0, [1.0, 1.0]),
            Err(UvTransformError::Rotation(70000.0))
        );
        assert!(UvTransform::new([0.0, 0.0], -MAX_ROTATION, [1.0, 1.0]).is_ok());
    }

    #[test]
    fn placement_is_the_rounded_image() {
        // 0.4 radians: a rotation exporters write (not pi / 8).
        let (rotation, sc, o) = (
            0.4f32,
            f64::from(0.35f32),
            [0.705f32, 0.285f32].map(f64::from),
        );
        let t = UvTransform::new([0.705, 0.285], rotation, [0.35, 0.35]).unwrap();
        let (s, c) = f64::from(rotation).sin_cos();
        for uv in [[0.0f32, 0.0], [1.0, 0.0], [0.3, 0.9], [100.25, -3.5]] {
            let [u, v] = uv.map(f64::from);
            let exact = [
                o[0] + c * sc * u - s * sc * v,
                o[1] + s * sc * u + c * sc * v,
            ];
            let placed = t.place(uv);
            let errors = t.axis_errors(&[uv; 3], &[placed; 3]);
            for a in 0..2 {
                let d = (f64::from(placed[a]) - exact[a]).abs();
                assert!(d <= errors[a].rho, "{uv:?} axis {a}: {d:e}");
                assert_eq!(placed[a], exact[a] as f32, "{uv:?} axis {a}");
            }
        }
    }

    #[test]
    fn exact_images_only_without_rotation() {
        let t = UvTransform::new([0.25, -1.0], 0.0, [0.5, 2.0]).unwrap();
        assert_eq!(t.exact_image([0.5, 0.75]), Some([0.5, 0.5]));
        // 0.1f32 / 2 + 0.25 needs more than 24 bits.
        assert_eq!(t.exact_image([0.1, 0.0]), None);
        let turned = UvTransform::new([0.0, 0.0], 0.5, [1.0, 1.0]).unwrap();
        assert_eq!(turned.exact_image([0.0, 0.0]), None);
        assert_eq!(
            UvTransform::IDENTITY.exact_image([0.1, 0.7]),
            Some([0.1, 0.7])
        );
        // Exact images are what `place` gives.
        assert_eq!(t.place([0.5, 0.75]), [0.5, 0.5]);
    }
}
