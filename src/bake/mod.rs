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
//! ## The unit
//!
//! One **work unit** is one lookup of a block's (or a single texel's)
//! classes in the baker's texel tables: the bounding-block lookup of each
//! node the walk visits, the vertex and edge-midpoint lookups of a
//! finest-level micro-triangle (a vertex shared by siblings is read and
//! counted once), and each block or texel test of its exact search; a
//! finest-level micro-triangle its vertices decide costs one unit more
//! (its centroid's texel), so every one costs at least one. Each unit is a few prefix-sum reads plus, for a search test, an
//! exact triangle-block intersection, so units are close to proportional
//! to time: about 50 ns each in the costliest case measured (searches over
//! footprints of many texture periods, 2^26 units in 3.4 s of CPU on a
//! 2-core AMD EPYC; `docs/bake.md`, "Bounded work").
//!
//! ## What a budget does
//!
//! [`Baker::bake_within`](crate::bake::Baker::bake_within) checks the units
//! spent before each node of its walk: once they reach the budget, that
//! node and every node not yet visited become unknown as whole subtrees
//! (split into unknown-opaque / unknown-transparent by each subtree's
//! centroid texel, as every unknown is), which is sound, and the triangle's
//! status is [`TriangleStatus::WorkBudgetExceeded`](crate::bake::TriangleStatus).
//! A triangle may overshoot its budget by the cost of one micro-triangle:
//! at most seven lookups plus the larger of its block budget and 36 under
//! the exact model, and under the GPU model eight lookups plus twice that
//! (a finest-level micro-triangle may be classified under both models, for
//! the widening's count).
//! [`bake_meshes`](crate::bake::mesh::bake_meshes) gives each triangle the
//! smaller of the per-triangle budget and what the per-bake budget has
//! left, in triangle order, so the output stays a function of the inputs.
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

mod alpha_test;
mod baker;
mod classify;
mod exact;
mod float;
mod gpu;
mod level;
mod material;
pub mod mesh;
mod mips;
mod parallel;
mod split;
mod texture;
mod texture_unit;
mod triangle;
mod uv_transform;
mod verify;
mod walk;
mod walk_variants;
mod work;

pub use baker::{Baker, DEFAULT_BLOCK_BUDGET};
pub use exact::TexelPoint;
pub use gpu::Model;
pub use level::{
    bake_level, level_within_periods, levels_within_budget, spans_whole_periods, useful_level,
    BakeLevel, BakeLevelError, MAX_BAKE_LEVEL,
};
pub use parallel::Threads;
pub use texture::{
    faithful_f32, AddressMode, AlphaTexture, Comparison, Cutoff, F32Texture, Filter, Sampler,
    SliceTexture, Texel, TextureError, Unorm16Texture, Unorm8Texture,
};
pub use texture_unit::{Interpolation, LinearRule, TextureUnit, TextureUnitError};
pub use triangle::{BakeError, BakedTriangle, TriangleStatus, UvTriangle};
pub use uv_transform::{UvTransform, UvTransformError, MAX_ROTATION};
pub use verify::{Contradiction, Verification, VerifyCounts};
pub use work::{DEFAULT_BAKE_WORK_BUDGET, DEFAULT_TRIANGLE_WORK_BUDGET};
