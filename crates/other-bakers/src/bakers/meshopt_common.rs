//! What the two meshoptimizer builds share: their conventions (the Rust
//! port is byte-identical to the C++ by its own claim, and the tests check
//! it), the conversion of their output, the sampler they accept, and their
//! sampler written out again for checks.

use crate::input::AlphaTexture;
use crate::output::{Format, Micromaps, Record};

use super::baker::{Baked, Conventions, SamplerRequest};

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

/// Both meshoptimizer bakers share the algorithm, hence their
/// conventions; only the references differ.
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
