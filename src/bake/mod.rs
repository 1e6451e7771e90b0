//! Baking opacity micromaps from alpha textures, exactly, and checking
//! anyone's micromaps against the texture (feature `alloc`).
//!
//! # The model
//!
//! A mesh triangle carries three texture coordinates ([`UvTriangle`]); the
//! hit with barycentrics `(b1, b2)` reads the texture at the affine mix
//! `(1 - b1 - b2) uv0 + b1 uv1 + b2 uv2`. The texture ([`AlphaTexture`]) is
//! `width x height` texels, texel `(i, j)` covering `[i/W, (i+1)/W) x
//! [j/H, (j+1)/H)`, row 0 at `v = 0` (the image's top row, as in Vulkan and
//! glTF). The sampler ([`Sampler`]) follows Vulkan's texel selection:
//!
//! - [`Filter::Nearest`] reads texel `floor(u W), floor(v H)`;
//! - [`Filter::Linear`] mixes the 2x2 texels from `floor(u W - 1/2),
//!   floor(v H - 1/2)`. The GPU quantizes the weights (Vulkan guarantees at
//!   least 4 sub-texel bits, and an implementation may use more), so the
//!   baker treats every one of the four texels as possibly read: whatever the
//!   quantization, a mix of texels that all pass the cutoff passes it, and
//!   one of texels that all fail it fails it. This is the tightest rule that
//!   holds for every quantization, since a weight of a texel near a sample
//!   point may round up from any positive value.
//! - the address modes ([`AddressMode`], per axis) wrap the integer texel
//!   coordinates after `floor`, as Vulkan's wrapping operation does;
//!   clamp-to-border reads [`Sampler::border_alpha`].
//!
//! A texel is opaque when its alpha passes the [`Cutoff`] (glTF `MASK`:
//! `alpha >= cutoff`, or the OMM SDK's `alpha > cutoff`). A micro-triangle
//! is **opaque** (transparent) only if every point of the closed
//! micro-triangle can read only opaque (transparent) texels; otherwise it is
//! **unknown**. Unknowns are split by the texel under the micro-triangle's
//! centroid (unknown-opaque if that texel is opaque), a heuristic for the
//! hardware's "force 2-state" fallback that soundness does not rely on.
//!
//! # Exact, not epsilon-based
//!
//! The micro-triangle's vertices are exact dyadic points (the [inverse
//! map](crate::inverse)), so their texture coordinates times the texture
//! size are dyadic rationals of the binary32 inputs: the baker places them
//! on an integer grid and decides with integer arithmetic (products up to
//! 256 bits) whether a closed micro-triangle meets a half-open block of
//! texels. It starts from the micro-triangle's bounding block of texels,
//! read from prefix sums of the texel classes after wrapping (one lookup
//! decides most micro-triangles), and splits mixed blocks until each part
//! is uniform or misses the triangle. `tests/bake.rs` checks the result
//! against an independent oracle on exact rational sample points.
//!
//! Edge cases, all total: a NaN or infinite coordinate, or coordinates whose
//! binary exponents are too far apart for the 100-bit grid, make the whole
//! triangle the unknown-opaque special index ([`TriangleStatus`]); a
//! degenerate (zero-area) UV triangle is classified exactly as the segment or
//! point it is; a micro-triangle whose footprint would need more than the
//! block budget of tests is unknown.
//!
//! # Level choice
//!
//! [`useful_level`] is the paper's eq. 1: the lowest level at which every
//! micro-triangle edge is at most one texel long; [`levels_within_budget`]
//! lowers the highest levels first until the micromaps fit a byte budget;
//! [`level_within_periods`] bakes at level 0 a triangle whose
//! micro-triangles would each hold a whole texture period (no level knows
//! more there).
//!
//! # Bounded work
//!
//! Every bake is capped in work units (texel-table lookups, [`work`]): per
//! triangle ([`Baker::bake_within`]) and per whole bake
//! ([`mesh::MeshOptions::bake_work_budget`]); what is left when a budget
//! runs out is unknown, never guessed.
//!
//! # Whole meshes
//!
//! [`mesh::bake_meshes`] does all of it for meshes (UV triangles, or
//! indices into strided UVs, each with its texture and [`mesh::Material`]):
//! levels, budget, the bake, the deduplicated API buffers and a
//! [`mesh::BakeReport`].
//!
//! ```
//! use micromap_index::bake::{useful_level, Baker, Cutoff, Sampler, Unorm8Texture};
//! use micromap_index::micromap::{Format, State};
//! use micromap_index::Level;
//!
//! let texels: Vec<u8> = (0..64).map(|i| if (i % 8) < 3 { 255 } else { 0 }).collect();
//! let texture = Unorm8Texture::new(8, 8, &texels).unwrap();
//! let baker = Baker::new(&texture, Sampler::default(), Cutoff::default()).unwrap();
//! let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
//! let level = useful_level(&uv, baker.size(), Level::new(12).unwrap());
//! assert_eq!(level.get(), 4); // edges of 8, 8 and 11.3 texels: 11.3 <= 2^4
//! let baked = baker.bake(&uv, level, Format::FourState, Default::default()).unwrap();
//! let unknown = baked.counts[State::UnknownOpaque.bits() as usize]
//!     + baked.counts[State::UnknownTransparent.bits() as usize];
//! assert!(unknown > 0 && unknown < 256);
//! ```

mod baker;
mod classify;
mod exact;
mod gpu;
pub mod mesh;
mod mips;
mod parallel;
mod texture;
pub mod work;

pub use baker::{
    BakeError, BakedOpacity, BakedTriangle, Baker, Contradiction, TexelPoint, TriangleStatus,
    UvTriangle, Verification, VerifyCounts, DEFAULT_BLOCK_BUDGET,
};
pub use gpu::Model;
pub use parallel::Threads;
pub use texture::{
    AddressMode, AlphaTexture, Comparison, Cutoff, F32Texture, Filter, Sampler, SliceTexture,
    Texel, TextureError, Unorm16Texture, Unorm8Texture,
};
pub use work::{
    level_within_periods, spans_whole_periods, DEFAULT_BAKE_WORK_BUDGET,
    DEFAULT_TRIANGLE_WORK_BUDGET,
};

use crate::micromap::{Format, Micromap};
use crate::Level;
use alloc::vec::Vec;

/// The paper's highest useful level (eq. 1): the smallest `n` with every UV
/// edge, measured in texels (`(du W, dv H)`), at most `2^n` long, capped at
/// `max` and at [`Micromap::MAX_LEVEL`] (16, the highest level a micromap
/// has and the baker bakes). A triangle with a non-finite coordinate gets
/// level 0.
///
/// ```
/// use micromap_index::bake::useful_level;
/// use micromap_index::Level;
/// let max = Level::new(12).unwrap();
/// // 64 texels across on a 256-texel texture: level 6.
/// assert_eq!(useful_level(&[[0.0, 0.0], [0.25, 0.0], [0.0, 0.25]], (256, 256), max).get(), 7);
/// assert_eq!(useful_level(&[[0.0, 0.0], [0.25, 0.0], [0.25, 0.0]], (256, 256), max).get(), 6);
/// assert_eq!(useful_level(&[[0.0, 0.0], [f32::NAN, 0.0], [0.0, 1.0]], (256, 256), max).get(), 0);
/// assert_eq!(useful_level(&[[0.0, 0.0], [100.0, 0.0], [0.0, 1.0]], (256, 256), max).get(), 12);
/// ```
#[must_use]
pub fn useful_level(uv: &UvTriangle, (width, height): (u32, u32), max: Level) -> Level {
    let mut longest = 0f64;
    for k in 0..3 {
        let (a, b) = (uv[k], uv[(k + 1) % 3]);
        let du = (f64::from(b[0]) - f64::from(a[0])) * f64::from(width);
        let dv = (f64::from(b[1]) - f64::from(a[1])) * f64::from(height);
        // Squared lengths: no square root needed (nor available without
        // std); `length <= 2^n` iff `length^2 <= 4^n`.
        let squared = du * du + dv * dv;
        if !squared.is_finite() {
            return Level(0);
        }
        longest = longest.max(squared);
    }
    let max = max.get().min(Micromap::MAX_LEVEL);
    let mut level = 0;
    let mut span = 1f64;
    while span < longest && level < max {
        level += 1;
        span *= 4.0;
    }
    Level(level as u8)
}

/// Levels for many triangles that fit `budget_bytes` of micromap data: each
/// triangle's `wanted` level, capped by one level for all, the highest cap
/// whose total [`Micromap::byte_len`] fits. If even level 0 does not fit,
/// every triangle gets level 0. Wanted levels above
/// [`Micromap::MAX_LEVEL`] (16) are taken as 16; the total saturates, so
/// no level or count overflows it.
///
/// ```
/// use micromap_index::bake::levels_within_budget;
/// use micromap_index::micromap::Format;
/// use micromap_index::Level;
/// let l = |n| Level::new(n).unwrap();
/// // Level 4 (4-state) is 64 bytes, level 3 is 16 bytes.
/// let wanted = [l(4), l(4), l(2)];
/// assert_eq!(levels_within_budget(&wanted, Format::FourState, 200), vec![l(4), l(4), l(2)]);
/// assert_eq!(levels_within_budget(&wanted, Format::FourState, 100), vec![l(3), l(3), l(2)]);
/// ```
#[must_use]
pub fn levels_within_budget(wanted: &[Level], format: Format, budget_bytes: u64) -> Vec<Level> {
    let total = |cap: u32| -> u64 {
        wanted.iter().fold(0u64, |sum, l| {
            let bytes = Micromap::byte_len(Level(l.get().min(cap) as u8), format) as u64;
            sum.saturating_add(bytes)
        })
    };
    let mut cap = wanted
        .iter()
        .map(|l| l.get())
        .max()
        .unwrap_or(0)
        .min(Micromap::MAX_LEVEL);
    while cap > 0 && total(cap) > budget_bytes {
        cap -= 1;
    }
    wanted
        .iter()
        .map(|l| Level(l.get().min(cap) as u8))
        .collect()
}
