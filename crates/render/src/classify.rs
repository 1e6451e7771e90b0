//! Contradictions explained exactly on the host: for a candidate whose
//! known state the shader's alpha test contradicted, recompute from the
//! recorded binary32 barycentrics `(b1, b2)` the exact hit point
//! `(1 - b1 - b2) uv0 + b1 uv1 + b2 uv2` in rationals, the micro-triangle
//! and state the library looks up there, and the alpha test at the exact
//! point (the vertex alpha interpolated there exactly too). If the exact alpha test agrees with the micromap, the shader's
//! binary32 texture coordinate rounded across a texel boundary
//! ([`ContradictionClass::Binary32Rounding`]); otherwise the micromap is
//! wrong for the exact hit point ([`ContradictionClass::MicromapWrong`]).
//! Under the sampler lookup the first class is the texture unit's
//! ([`ContradictionClass::TextureUnit`]): its reading of the binary32
//! coordinate (sub-texel snapping, filter arithmetic) or the coordinate
//! itself disagrees with the exact point.

use crate::frame::Contradiction;
use crate::method::Lookup;
use crate::scene::{Micromaps, Scene};
use micromap_index::bake::Filter;
use micromap_index::micromap::{MicromapIndex, State};
use micromap_index::{spec, SpecLevel};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, ToPrimitive, Zero};

/// Why a known state was contradicted.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ContradictionClass {
    /// The alpha test at the exact hit point disagrees with the micromap:
    /// the micromap is wrong there.
    MicromapWrong,
    /// The exact hit point agrees with the micromap; the shader's binary32
    /// texture coordinate read another texel.
    Binary32Rounding,
    /// The exact hit point agrees with the micromap; the device's texture
    /// unit (the sampler lookup), reading the binary32 coordinate, did
    /// not: its sub-texel snapping or filter arithmetic, or the
    /// coordinate's rounding.
    TextureUnit,
}

impl ContradictionClass {
    /// The name in `render.json`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ContradictionClass::MicromapWrong => "micromap-wrong",
            ContradictionClass::Binary32Rounding => "binary32-rounding",
            ContradictionClass::TextureUnit => "texture-unit",
        }
    }
}

/// A contradiction with its exact explanation.
#[derive(Clone, Debug, PartialEq)]
pub struct Classified {
    /// What the shader recorded.
    pub contradiction: Contradiction,
    /// The class.
    pub class: ContradictionClass,
    /// The triangle's micromap level (`None` for a special index).
    pub level: Option<u32>,
    /// The micro-triangle the library's `spec::index_f32` gives for
    /// `(b1, b2)` (0 for a special index); the shader's is in
    /// [`Contradiction::micro_triangle`].
    pub micro_triangle: u32,
    /// The library's state there (before any deliberate fault).
    pub library_state: Option<State>,
    /// The exact hit point in texel units (`u * width`, `v * height`), as
    /// reduced fractions `n/d`.
    pub exact_texel_point: [String; 2],
    /// The texels the exact point reads (one for nearest, up to four with
    /// nonzero weight for linear; border reads are left out) and their
    /// binary32 alphas.
    pub texels: Vec<(u32, u32, f32)>,
    /// The alpha test at the exact point.
    pub exact_opaque: bool,
    /// The alpha it compares at the exact point (filtered, times the
    /// factor and the vertex alpha), rounded to `f64`.
    pub exact_alpha: f64,
    /// The alpha the lookup compared ([`Contradiction::alpha_bits`]).
    pub judged_alpha: f32,
    /// The texture coordinate the shader computed (binary32, its order of
    /// operations, no fused multiply-add) and its texel.
    pub binary32_uv: [f32; 2],
}

fn rational(x: f32) -> BigRational {
    BigRational::from_float(x).unwrap_or_else(BigRational::zero)
}

fn text(r: &BigRational) -> String {
    if r.denom().is_one() {
        r.numer().to_string()
    } else {
        format!("{}/{}", r.numer(), r.denom())
    }
}

/// The integer part, as `i64` (saturating: a texel coordinate beyond
/// `i64` wraps like any other far one).
fn floor_i64(r: &BigRational) -> i64 {
    let f = r.floor().to_integer();
    i64::try_from(f.clone()).unwrap_or(if f < BigInt::zero() {
        i64::MIN
    } else {
        i64::MAX
    })
}

/// Explains `c` exactly (see the module docs). `None` when `c` names a
/// triangle the scene does not have.
#[must_use]
pub fn classify(scene: &Scene, micromaps: &Micromaps, c: &Contradiction) -> Option<Classified> {
    classify_lookup(scene, micromaps, c, Lookup::Shader)
}

/// [`classify`] for a frame traced with `lookup`: under
/// [`Lookup::Sampler`] a contradiction the exact point does not explain is
/// [`ContradictionClass::TextureUnit`].
#[must_use]
pub fn classify_lookup(
    scene: &Scene,
    micromaps: &Micromaps,
    c: &Contradiction,
    lookup: Lookup,
) -> Option<Classified> {
    let t = c.triangle as usize;
    let mesh = scene.mesh_of(t)?;
    let uv = scene.uvs()[t];
    let texture = scene.texture(mesh.texture)?;
    let (b1, b2) = (f32::from_bits(c.b1_bits), f32::from_bits(c.b2_bits));
    // The library's lookup at the same barycentrics.
    let (level, micro_triangle, library_state) = match micromaps.read().indices.as_ref()?.get(t)? {
        MicromapIndex::Special(state) => (None, 0, Some(*state)),
        MicromapIndex::Record(r) => {
            let map = micromaps.read().micromaps.get(*r as usize)?;
            let level = map.level().get();
            let index = SpecLevel::new(level).map_or(0, |l| spec::index_f32(b1, b2, l));
            (Some(level), index, map.get(u64::from(index)))
        }
    };
    // The exact point, in texel units.
    let (rb1, rb2) = (rational(b1), rational(b2));
    let rb0 = BigRational::one() - &rb1 - &rb2;
    let size = [texture.width, texture.height];
    let point: [BigRational; 2] = [0, 1].map(|k| {
        (&rb0 * rational(uv[0][k]) + &rb1 * rational(uv[1][k]) + &rb2 * rational(uv[2][k]))
            * BigRational::from_integer(BigInt::from(size[k]))
    });
    let sampler = mesh.material.sampler;
    let fetch = |x: i64, y: i64| -> (Option<(u32, u32)>, f32) {
        match (
            sampler.address_u.wrap(x, texture.width),
            sampler.address_v.wrap(y, texture.height),
        ) {
            (Some(x), Some(y)) => (
                Some((x, y)),
                texture.alphas[(y as usize) * (texture.width as usize) + x as usize],
            ),
            _ => (None, sampler.border_alpha),
        }
    };
    let mut texels = Vec::new();
    let mut filtered = BigRational::zero();
    match sampler.filter {
        Filter::Nearest => {
            let (at, alpha) = fetch(floor_i64(&point[0]), floor_i64(&point[1]));
            texels.extend(at.map(|(x, y)| (x, y, alpha)));
            filtered = rational(alpha);
        }
        Filter::Linear => {
            let half = BigRational::new(BigInt::one(), BigInt::from(2));
            let shifted = [&point[0] - &half, &point[1] - &half];
            let base = [floor_i64(&shifted[0]), floor_i64(&shifted[1])];
            let frac = [
                &shifted[0] - shifted[0].floor(),
                &shifted[1] - shifted[1].floor(),
            ];
            for (dy, wy) in [(0, BigRational::one() - &frac[1]), (1, frac[1].clone())] {
                for (dx, wx) in [(0, BigRational::one() - &frac[0]), (1, frac[0].clone())] {
                    let weight = &wx * &wy;
                    if weight.is_zero() {
                        continue;
                    }
                    let (at, alpha) = fetch(base[0].saturating_add(dx), base[1].saturating_add(dy));
                    texels.extend(at.map(|(x, y)| (x, y, alpha)));
                    filtered += weight * rational(alpha);
                }
            }
        }
    }
    let mut value = filtered * rational(mesh.material.alpha_factor);
    // glTF's COLOR_0 alpha at the exact point.
    if let Some(a) = scene.vertex_alpha(t) {
        value *= &rb0 * rational(a[0]) + &rb1 * rational(a[1]) + &rb2 * rational(a[2]);
    }
    let exact_alpha = value.to_f64().unwrap_or(f64::NAN);
    let cutoff = rational(mesh.material.cutoff.alpha());
    let exact_opaque = match mesh.material.cutoff.comparison() {
        micromap_index::bake::Comparison::AtLeast => value >= cutoff,
        micromap_index::bake::Comparison::Above => value > cutoff,
    };
    // The shader's binary32 coordinate (`precise`: no contraction).
    let w0 = 1.0 - b1 - b2;
    let binary32_uv = [0, 1].map(|k| w0 * uv[0][k] + b1 * uv[1][k] + b2 * uv[2][k]);
    // The state the shader decided by (a deliberate fault included).
    let class = if (c.state == 1) != exact_opaque {
        ContradictionClass::MicromapWrong
    } else if lookup == Lookup::Sampler {
        ContradictionClass::TextureUnit
    } else {
        ContradictionClass::Binary32Rounding
    };
    Some(Classified {
        contradiction: *c,
        class,
        level,
        micro_triangle,
        library_state,
        exact_texel_point: [text(&point[0]), text(&point[1])],
        texels,
        exact_opaque,
        exact_alpha,
        judged_alpha: f32::from_bits(c.alpha_bits),
        binary32_uv,
    })
}
