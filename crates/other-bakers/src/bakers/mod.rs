//! The bakers this tool can run, each converted to [`Micromaps`].

use micromap_index::bake::{AddressMode, Filter};
use serde::Serialize;

use crate::input::{AlphaTexture, UvTriangle};
use crate::output::{Format, Micromaps, Record};

pub mod exact;
pub mod meshopt_cpp;
pub mod meshopt_rs;
pub mod omm_sdk;

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

/// Every baker compiled into this build.
pub fn all() -> Vec<Box<dyn Baker>> {
    let v: Vec<Box<dyn Baker>> = vec![
        Box::new(meshopt_cpp::MeshoptCpp),
        Box::new(meshopt_rs::MeshoptRs),
        Box::new(exact::MicromapIndex),
        Box::new(omm_sdk::OmmSdk),
    ];
    v
}

/// The baker named `name`.
pub fn by_name(name: &str) -> Option<Box<dyn Baker>> {
    all().into_iter().find(|b| b.name() == name)
}

/// Both meshoptimizer bakers share the algorithm (the Rust port is
/// byte-identical by its own claim, and this tool checks it), hence their
/// conventions; only the references differ.
/// meshoptimizer's result (either build) in the Vulkan layout, which its
/// layout already is: `offsets[k]` / `levels[k]` describe entry k, its bytes
/// pack micro-triangle i LSB first (opacitymap.cpp l.239, l.260; opacity.rs
/// l.802, l.819), and compacted indices are a record or -(state + 1).
pub(crate) fn meshopt_baked(
    offsets: &[u32],
    levels: &[u8],
    format: Format,
    data: Vec<u8>,
    indices: Vec<i32>,
    micro_triangles_baked: u64,
) -> Baked {
    let records = offsets
        .iter()
        .zip(levels)
        .map(|(&data_offset, &level)| Record {
            data_offset,
            level: u16::from(level),
            format: format.vk(),
        })
        .collect();
    Baked {
        maps: Micromaps {
            data,
            records,
            indices,
        },
        micro_triangles_baked,
    }
}

/// meshoptimizer's sampler is fixed (linear, footprint clamped to the
/// texture; `meshopt_sample`): any other request is refused.
pub(crate) fn meshopt_sampler(sampler: SamplerRequest) -> Result<(), String> {
    if sampler == SamplerRequest::default() {
        Ok(())
    } else {
        Err(format!(
            "meshoptimizer samples linear with its footprint clamped to the texture only, \
             not --filter {} --address {}",
            sampler.filter, sampler.address
        ))
    }
}

pub(crate) fn meshopt_conventions(references: &'static [&'static str]) -> Conventions {
    Conventions {
        filter: "linear (bilinear), always; mip 0 only (the caller picks the mip)",
        address_mode: "a coordinate outside [0, 1] is wrapped by t - floor(t) (one exactly 1.0 is \
            kept); the bilinear footprint is then CLAMPED to the texture: texel index below 0 \
            becomes 0 (left/top) and the +1 neighbour of the last column/row is the last \
            column/row itself (right/bottom), so nothing blends across the wrap seam, unlike a \
            GPU sampler in REPEAT mode",
        texel_centres: "texel (i, j) at ((i + 0.5) / W, (j + 0.5) / H); v = 0 is row 0 of the \
            data (the image's top row)",
        sample_position_precision: "16.8 fixed point: int(u * W * 256 - 127.5), i.e. the \
            position relative to texel centres rounded to the nearest 1/256 texel (half up); \
            bilinear weights are those 8-bit fractions; value = integer bilinear / (255 * 65536) \
            as f32",
        cutoff: 0.5,
        comparison: "4-state KNOWN states: transparent iff every corner/centroid sample < 0.5 \
            and no edge sample >= 0.5; opaque iff every corner/centroid sample > 0.5 and every \
            edge sample >= 0.5 (so an edge sample exactly 0.5 counts as opaque, a corner/centroid \
            sample exactly 0.5 makes it unknown); UNKNOWN states and all 2-state states: \
            estimated coverage >= 0.5 gives unknown-opaque / opaque, else unknown-transparent / \
            transparent",
        classification: "point samples only, NOT conservative: per micro-triangle its 3 corners \
            and its centroid, plus edgeres samples evenly spaced along each edge, where edgeres = \
            clamp(int(0.75 * sqrt(triangle texel area) / 2^level), 0, 7); coverage estimate = \
            0.12 * (corners) + 0.64 * centroid, or with edge samples 0.22 * centroid + 0.23 * \
            (fraction of edge samples >= 0.5, summed over the 3 edges) + 0.03 * (corners). \
            A feature between the samples is missed",
        level_control: "forced: opacity_map_measure with max_level = L and target_edge = 0 gives \
            every triangle level L (adaptive level only when target_edge > 0)",
        pipeline: "measure (deduplicates triangles whose UVs agree after rounding to 1/4 texel, \
            and picks levels) -> rasterize each unique entry -> compact (a micromap whose states \
            are all equal becomes special index -(state + 1); identical micromaps are merged by \
            content); data offsets are consecutive, no alignment",
        order: "the Vulkan space-filling (bird) curve: recursive split with children \
            (c0, m01, m20), (m20, m12, m01), (m01, c1, m12), (m12, m20, c2) numbered 4i + k, \
            checked against micromap-index's curve by this crate's tests",
        references,
    }
}

#[cfg(test)]
pub(crate) mod tests;

/// meshoptimizer's sampler (opacitymap.cpp l.29-69), written out again for
/// checks of its output against its own samples (the tests and
/// `examples/dense_check.rs`).
pub fn meshopt_sample(t: &AlphaTexture, u: f32, v: f32) -> f32 {
    let wrap = |x: f32| {
        if (x - 0.5).abs() > 0.5 {
            x - x.floor()
        } else {
            x
        }
    };
    let (u, v) = (wrap(u), wrap(v));
    let uf = ((u * (t.width as f32 * 256.0) - 127.5) as i32).max(0);
    let vf = ((v * (t.height as f32 * 256.0) - 127.5) as i32).max(0);
    let (x, y, rx, ry) = (uf >> 8, vf >> 8, uf & 255, vf & 255);
    let (x, y) = (x as usize, y as usize);
    let (w, h) = (t.width as usize, t.height as usize);
    let x1 = if x + 1 < w { x + 1 } else { x };
    let y1 = if y + 1 < h { y + 1 } else { y };
    let a = |x: usize, y: usize| i32::from(t.alpha[y * w + x]);
    let ax0 = a(x, y) * 256 + (a(x1, y) - a(x, y)) * rx;
    let ax1 = a(x, y1) * 256 + (a(x1, y1) - a(x, y1)) * rx;
    let axy = ax0 * 256 + (ax1 - ax0) * ry;
    axy as f32 * (1.0 / (255.0 * 65536.0))
}
