//! `verify`: anyone's micromap buffers checked against an alpha texture
//! (the CLI's `verify-bake`): `micromap::read_buffers` validates the
//! bytes, then `bake::mesh::verify_mesh` (the verifier every front end
//! uses, with the bake's alpha factor) checks every known micro-triangle,
//! with the GIL released. Work is bounded by `max_checks`, memory by
//! `max_report` (contradictions kept) and the inputs' sizes.

use crate::fallible::try_vec;
use crate::inputs::{AlphaArray, UvArray};
use crate::options::{self, value_error};
use micromap_index::bake::mesh::{
    verify_mesh, Material, Mesh, MeshOptions, MeshTriangles, MeshVerification,
};
use micromap_index::bake::Contradiction;
use micromap_index::micromap::{
    read_buffers, BufferBytes, MicromapIndex, Overlap, ReadOptions, TriangleOpacity, TriangleRecord,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The most micromap data `lenient_layout` lets overlapping records decode
/// (the CLI's `micromap-data.bin` limit).
const MAX_DECODED_BYTES: u64 = (1 << 32) + (1 << 30);

/// Verifies buffers (the four files of `micromap-index bake`, as bytes)
/// against `alpha` and `uvs`; the Python layer documents the options.
#[pyfunction]
#[pyo3(signature = (alpha, uvs, *, data, triangles, indices, index_width, usage, filter,
    address, border_alpha, cutoff, opaque_above, alpha_factor, model, subtexel_bits, interpolation, filter_error, linear, max_report, max_checks,
    lenient_layout, record_stride, index_stride, uv_transform=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn verify<'py>(
    py: Python<'py>,
    alpha: &Bound<'py, PyAny>,
    uvs: &Bound<'py, PyAny>,
    data: &[u8],
    triangles: &[u8],
    indices: &[u8],
    index_width: i64,
    usage: Option<&[u8]>,
    filter: &str,
    address: &Bound<'py, PyAny>,
    border_alpha: f32,
    cutoff: f32,
    opaque_above: bool,
    alpha_factor: f32,
    model: &str,
    subtexel_bits: i64,
    interpolation: &str,
    filter_error: f32,
    linear: &str,
    max_report: i64,
    max_checks: Option<i64>,
    lenient_layout: bool,
    record_stride: Option<i64>,
    index_stride: Option<i64>,
    uv_transform: Option<([f32; 2], f32, [f32; 2])>,
) -> PyResult<Bound<'py, PyDict>> {
    let alpha = AlphaArray::new(alpha)?;
    let uvs = UvArray::new(uvs)?;
    let width = options::index_width(index_width)?;
    let stride = |value: i64, what: &str| {
        usize::try_from(options::count(value, what)?)
            .map_err(|_| value_error(format!("{what} {value} does not fit in memory")))
    };
    let read_options = ReadOptions {
        overlap: if lenient_layout {
            Overlap::Allow {
                max_decoded_bytes: MAX_DECODED_BYTES,
            }
        } else {
            Overlap::Forbid
        },
        record_stride: record_stride
            .map(|s| stride(s, "record_stride"))
            .transpose()?
            .unwrap_or(TriangleRecord::SIZE),
        index_stride: index_stride
            .map(|s| stride(s, "index_stride"))
            .transpose()?,
        ..ReadOptions::default()
    };
    // A stride the APIs do not allow, before anything is read.
    read_options
        .check_strides(Some(width))
        .map_err(value_error)?;
    let sampler = options::sampler(
        options::filter(filter)?,
        options::address_pair(address)?,
        border_alpha,
    )?;
    let cutoff = options::cutoff(cutoff, opaque_above)?;
    if !(alpha_factor.is_finite() && alpha_factor >= 0.0) {
        return Err(value_error(format!(
            "alpha_factor {alpha_factor}: expected a finite number >= 0"
        )));
    }
    let material = Material {
        sampler,
        cutoff,
        alpha_factor,
        uv_transform: options::uv_transform(uv_transform)?,
    };
    let model = options::model(model)?;
    let unit = options::texture_unit(subtexel_bits, interpolation, filter_error, linear)?;
    let judge = MeshOptions {
        model,
        texture_unit: unit,
        ..MeshOptions::default()
    };
    let max_checks = max_checks
        .map(|m| options::count(m, "max_checks"))
        .transpose()?
        .unwrap_or(u64::MAX);
    let max_report =
        usize::try_from(options::count(max_report, "max_report")?).unwrap_or(usize::MAX);
    // The buffers first: their index count must be the triangles' before
    // the triangles are copied.
    let read = py
        .allow_threads(|| {
            read_buffers(
                &BufferBytes {
                    records: triangles,
                    data,
                    usage_counts: usage,
                    indices: Some((indices, width)),
                },
                &read_options,
            )
        })
        .map_err(value_error)?;
    let index = read.indices.unwrap_or_default();
    if index.len() != uvs.len() {
        return Err(value_error(format!(
            "the buffers have {} indices for {} triangles",
            index.len(),
            uvs.len()
        )));
    }
    let uv = uvs.copy()?;
    let alpha = alpha.copy()?;
    let mut opacities = try_vec(index.len(), "indices")?;
    opacities.extend(index.iter().map(|i| match *i {
        MicromapIndex::Record(r) => TriangleOpacity::Micromap(&read.micromaps[r as usize]),
        MicromapIndex::Special(state) => TriangleOpacity::Special(state),
    }));
    let outcome = py.allow_threads(|| -> Result<_, String> {
        let texture = alpha.texture().map_err(|e| e.to_string())?;
        let mesh = Mesh {
            triangles: MeshTriangles::Uv(&uv),
            texture: &*texture,
            material,
            vertex_alpha: None,
        };
        let mut first: Vec<(usize, Contradiction, f64)> = Vec::new();
        let totals = verify_mesh(&mesh, &opacities, &judge, max_checks, &mut |t, c| {
            // Only the first max_report are kept: memory stays bounded
            // however wrong the buffers are.
            if first.len() < max_report {
                // The texel's own alpha, before alpha_factor.
                let alpha = match c.texel {
                    Some((x, y)) => texture.alpha(x, y),
                    None => f64::from(sampler.border_alpha),
                };
                first.push((t, c, alpha));
            }
        })
        .map_err(|e| e.to_string())?;
        Ok((totals, first))
    });
    let (totals, first): (MeshVerification, _) = outcome.map_err(value_error)?;
    let out = PyDict::new(py);
    out.set_item("model", model.name())?;
    let unit_dict = PyDict::new(py);
    unit_dict.set_item("subtexel_bits", unit.subtexel_bits)?;
    unit_dict.set_item("interpolation", unit.interpolation.name())?;
    unit_dict.set_item("filter_error", unit.filter_error)?;
    unit_dict.set_item("linear", unit.linear.name())?;
    out.set_item("texture_unit", unit_dict)?;
    out.set_item("triangles", uv.len())?;
    out.set_item("triangles_checked", totals.triangles_checked)?;
    out.set_item("known_micro_triangles", totals.known)?;
    out.set_item("unknown_micro_triangles", totals.unknown)?;
    let micro = totals.known + totals.unknown;
    out.set_item(
        "unknown_fraction",
        totals.unknown as f64 / micro.max(1) as f64,
    )?;
    out.set_item("undecided", totals.undecided)?;
    out.set_item("unchecked_micro_triangles", totals.unchecked)?;
    let complete = totals.unchecked == 0;
    out.set_item("complete", complete)?;
    out.set_item("contradictions", totals.contradictions)?;
    let mut list = Vec::with_capacity(first.len());
    for (t, c, texel_alpha) in first {
        let d = PyDict::new(py);
        d.set_item("triangle", t)?;
        d.set_item("micro_triangle", c.micro_triangle)?;
        d.set_item("state", c.state.to_string())?;
        // Exact: (numerator, log2 denominator) per texel-space axis.
        d.set_item(
            "witness_texel_space",
            c.witness.map(|w| ((w.x, w.shift_x), (w.y, w.shift_y))),
        )?;
        d.set_item(
            "witness_uv",
            c.witness.map(|w| w.uv_f64(alpha.width, alpha.height)),
        )?;
        d.set_item("texel", c.texel)?;
        d.set_item("texel_alpha", texel_alpha)?;
        list.push(d);
    }
    out.set_item("first_contradictions", list)?;
    out.set_item("usage_counts_checked", usage.is_some())?;
    out.set_item("sound", totals.contradictions == 0 && complete)?;
    Ok(out)
}
