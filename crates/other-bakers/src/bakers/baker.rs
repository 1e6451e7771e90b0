//! What every baker of this tool is: the [`Baker`] trait, the [`Request`]
//! it is given (texture, triangles, level, format, sampler), the [`Baked`]
//! result it returns (already the Vulkan layout) and the [`Conventions`]
//! it documents.

use micromap_index::bake::{AddressMode, Filter};
use serde::Serialize;

use crate::input::{AlphaTexture, UvTriangle};
use crate::output::{Format, Micromaps};

/// What a baker is asked to do.
#[derive(Clone, Copy)]
pub struct Request<'a> {
    /// The alpha texture, mip 0 only.
    pub texture: &'a AlphaTexture,
    /// UV triangles, one micromap reference each.
    pub triangles: &'a [UvTriangle],
    /// Subdivision level for every triangle (0..=12).
    pub level: u8,
    /// 2- or 4-state.
    pub format: Format,
    /// The run-time sampler the micromaps are for.
    pub sampler: SamplerRequest,
}

/// The sampler a bake is asked for (`--filter`, `--address`); a baker that
/// cannot model it refuses. The default, linear with clamp-to-edge, is the
/// one every baker here takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SamplerRequest {
    /// Nearest or linear.
    pub filter: Filter,
    /// Both axes.
    pub address: AddressMode,
}

impl Default for SamplerRequest {
    fn default() -> Self {
        Self {
            filter: Filter::Linear,
            address: AddressMode::ClampToEdge,
        }
    }
}

/// A baker's result, already in the Vulkan layout.
pub struct Baked {
    /// Data, records, indices.
    pub maps: Micromaps,
    /// Micro-triangles the baker classified (before its own deduplication
    /// and special-index compaction): sum of `4^level` over the micromaps it
    /// rasterized.
    pub micro_triangles_baked: u64,
}

/// The sampling model a baker classifies against, as read from its source.
/// A verifier must check the baker's output against this model.
#[derive(Clone, Debug, Serialize)]
pub struct Conventions {
    /// `nearest` or `linear` (bilinear).
    pub filter: &'static str,
    /// How UVs outside `[0, 1]` and texels past the edges are addressed.
    pub address_mode: &'static str,
    /// Where texel `(i, j)`'s value sits in UV space.
    pub texel_centres: &'static str,
    /// Sub-texel precision of the sample position.
    pub sample_position_precision: &'static str,
    /// The alpha cutoff.
    pub cutoff: f32,
    /// Opaque when alpha is `>` or `>=` the cutoff, in each use.
    pub comparison: &'static str,
    /// How a micro-triangle's state is decided.
    pub classification: &'static str,
    /// Whether the level can be forced, and how the tool forces it.
    pub level_control: &'static str,
    /// Other steps of the pipeline that change the output.
    pub pipeline: &'static str,
    /// Micro-triangle order of the data.
    pub order: &'static str,
    /// Source references (paths under `~/.cargo/registry/src/index.crates.io-*/`).
    pub references: &'static [&'static str],
}

/// One baker.
pub trait Baker {
    /// Name on the command line (`--baker`).
    fn name(&self) -> &'static str;
    /// Package and version, e.g. `meshopt 0.7.0 (meshoptimizer 1.3)`.
    fn version(&self) -> &'static str;
    /// Its sampler and cutoff conventions.
    fn conventions(&self) -> Conventions;
    /// Runs the whole bake: everything timed is inside this call.
    fn bake(&self, request: &Request<'_>) -> Result<Baked, String>;
}
