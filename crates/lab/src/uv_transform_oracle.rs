//! An oracle for bakes of transformed texture coordinates
//! (`KHR_texture_transform`, `bake::UvTransform`), written apart from the
//! baker: what a GPU reads at a binary32 hit when its shader interpolates
//! the *untransformed* coordinates and transforms them in binary32, in the
//! orders renderers use, then scales, snaps and floors (nearest filter).
//! Used by `tests/bake_uv_transform.rs` and the `bake_transformed` fuzz
//! body.
//!
//! The forms, each in binary32 with every operation rounded:
//! - interpolation: `w c0 + b1 c1 + b2 c2` with `w = (1 - b1) - b2` or
//!   `1 - (b1 + b2)`, `c0 + b1 (c1 - c0) + b2 (c2 - c0)`, and both fused;
//! - transform: a matrix built on the CPU in `f64` and stored as binary32,
//!   applied left to right or fused; scale, rotate and offset in steps with
//!   the sine and cosine of `f32` or `f64`, fused or not;
//! - the sampler: `x = u' W` (±1 ulp), snapped to 1/256 texel by rounding
//!   or truncation, `floor`, Vulkan's address modes.

use micromap_index::bake::{AddressMode, Sampler, UvTriangle};
use micromap_index::inverse::micro_triangle;
use micromap_index::micromap::State;
use micromap_index::{spec, Level, SpecLevel};
use micromap_index_test_support::step_ulps;

/// A transform's parameters: offset, rotation (radians), scale.
pub type TransformParams = ([f32; 2], f32, [f32; 2]);

/// A bake to judge: an 8-bit texture (opaque where the code is at least
/// 128, glTF's cutoff 0.5), its nearest sampler (border alpha 0:
/// transparent), the stored triangle and the transform's parameters
/// (offset, rotation, scale).
pub struct Case<'a> {
    /// Row-major texel codes, `width * height`.
    pub texels: &'a [u8],
    /// Texels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Its address modes (the filter is taken as nearest).
    pub sampler: Sampler,
    /// The stored (untransformed) texture coordinates.
    pub uv: UvTriangle,
    /// `(offset, rotation, scale)`.
    pub transform: TransformParams,
}

/// Every transformed texture coordinate some renderer computes for the hit
/// `(b1, b2)` (see the module's forms).
#[must_use]
pub fn shader_coordinates(case: &Case<'_>, b1: f32, b2: f32) -> Vec<[f32; 2]> {
    let (offset, rotation, scale) = case.transform;
    let interpolate = |k: usize| -> [f32; 5] {
        let [c0, c1, c2] = case.uv.map(|c| c[k]);
        let w = (1.0 - b1) - b2;
        let w2 = 1.0 - (b1 + b2);
        [
            w * c0 + b1 * c1 + b2 * c2,
            w2 * c0 + b1 * c1 + b2 * c2,
            c0 + b1 * (c1 - c0) + b2 * (c2 - c0),
            b2.mul_add(c2, b1.mul_add(c1, w * c0)),
            b2.mul_add(c2 - c0, b1.mul_add(c1 - c0, c0)),
        ]
    };
    let (xs, ys) = (interpolate(0), interpolate(1));
    let (s64, c64) = f64::from(rotation).sin_cos();
    let [sx, sy] = scale;
    let m = [
        [(c64 * f64::from(sx)) as f32, (-s64 * f64::from(sy)) as f32],
        [(s64 * f64::from(sx)) as f32, (c64 * f64::from(sy)) as f32],
    ];
    let trig = [(s64 as f32, c64 as f32), rotation.sin_cos()];
    let mut out = Vec::with_capacity(xs.len() * 6);
    for (&x, &y) in xs.iter().zip(&ys) {
        out.push([
            m[0][0] * x + m[0][1] * y + offset[0],
            m[1][0] * x + m[1][1] * y + offset[1],
        ]);
        out.push([
            m[0][1].mul_add(y, m[0][0].mul_add(x, offset[0])),
            m[1][1].mul_add(y, m[1][0].mul_add(x, offset[1])),
        ]);
        for &(s, c) in &trig {
            let (u, v) = (sx * x, sy * y);
            out.push([(c * u - s * v) + offset[0], (s * u + c * v) + offset[1]]);
            out.push([
                offset[0] + c.mul_add(u, -(s * v)),
                offset[1] + s.mul_add(u, c * v),
            ]);
        }
    }
    out
}

/// The texel coordinates (after wrapping; `None` for a border read) one
/// axis's coordinate `c` can give: `c * size` and its neighbours 1 ulp
/// away, each snapped to 1/256 by rounding and by truncation, floored.
fn axis_texels(c: f32, size: u32, mode: AddressMode) -> Vec<Option<u32>> {
    let x = c * size as f32;
    let mut out = Vec::with_capacity(6);
    for d in -1..=1 {
        let x = step_ulps(x, d);
        for snapped in [(x * 256.0).round() / 256.0, (x * 256.0).floor() / 256.0] {
            out.push(mode.wrap(snapped.floor() as i64, size));
        }
    }
    out
}

/// The classes (bit 0 transparent, bit 1 opaque) a GPU can read at the hit
/// `(b1, b2)`; `None` when some form's coordinate is not finite or beyond
/// `2^20` in magnitude (outside what the oracle judges).
#[must_use]
pub fn classes_read(case: &Case<'_>, b1: f32, b2: f32) -> Option<u8> {
    let mut read = 0;
    for c in shader_coordinates(case, b1, b2) {
        if c.iter().any(|x| !x.is_finite() || x.abs() > 1048576.0) {
            return None;
        }
        let us = axis_texels(c[0], case.width, case.sampler.address_u);
        let vs = axis_texels(c[1], case.height, case.sampler.address_v);
        for u in &us {
            for v in &vs {
                let opaque = match (u, v) {
                    (Some(u), Some(v)) => case.texels[(v * case.width + u) as usize] >= 128,
                    _ => false,
                };
                read |= if opaque { 2 } else { 1 };
            }
        }
        if read == 3 {
            // Both classes: nothing more to learn (unless a later form is
            // out of range, which only matters to a caller judging
            // nothing at this hit).
            break;
        }
    }
    Some(read)
}

/// The hits judged for micro-triangle `index` at `level`: its vertices and
/// edge midpoints, and four points inside, each with both barycentrics
/// moved by -1, 0 and +1 ulp; only those in the closed triangle that
/// `spec::index_f32` assigns to `index`.
fn hits(level: u32, index: u64) -> Vec<(f32, f32)> {
    let Ok(t) = micro_triangle(Level::new(level).expect("level"), index) else {
        return Vec::new();
    };
    let side = (1u64 << level) as f32;
    let v = t
        .vertices_scaled()
        .map(|(a, b)| [a as f32 / side, b as f32 / side]);
    let mut points = Vec::new();
    for k in 0..3 {
        points.push(v[k]);
        let n = v[(k + 1) % 3];
        points.push([(v[k][0] + n[0]) / 2.0, (v[k][1] + n[1]) / 2.0]);
    }
    for (r1, r2) in [(0.2f32, 0.3f32), (0.6, 0.1), (0.1, 0.7), (0.33, 0.33)] {
        points.push([
            v[0][0] + r1 * (v[1][0] - v[0][0]) + r2 * (v[2][0] - v[0][0]),
            v[0][1] + r1 * (v[1][1] - v[0][1]) + r2 * (v[2][1] - v[0][1]),
        ]);
    }
    let spec_level = SpecLevel::new(level).expect("level");
    let mut out = Vec::new();
    for p in points {
        for d1 in -1..=1 {
            for d2 in -1..=1 {
                let (b1, b2) = (step_ulps(p[0], d1), step_ulps(p[1], d2));
                let inside = b1 >= 0.0 && b2 >= 0.0 && f64::from(b1) + f64::from(b2) <= 1.0;
                if inside && u64::from(spec::index_f32(b1, b2, spec_level)) == index {
                    out.push((b1, b2));
                }
            }
        }
    }
    out
}

/// The known micro-triangles of `states` (one per micro-triangle of
/// `level`, in order) and those of them the oracle contradicts (a hit that
/// reads the other class); the first contradicted one's index and hit.
#[must_use]
pub fn judge(case: &Case<'_>, states: &[State], level: u32) -> (u64, u64, Option<(u64, f32, f32)>) {
    let (mut known, mut wrong, mut first) = (0, 0, None);
    for (index, &state) in (0u64..).zip(states) {
        if !state.is_known() {
            continue;
        }
        known += 1;
        let other = if state == State::Opaque { 1 } else { 2 };
        let hit = hits(level, index)
            .into_iter()
            .find(|&(b1, b2)| classes_read(case, b1, b2).is_some_and(|read| read & other != 0));
        if let Some((b1, b2)) = hit {
            wrong += 1;
            first.get_or_insert((index, b1, b2));
        }
    }
    (known, wrong, first)
}
