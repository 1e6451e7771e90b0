//! `verify`: anyone's micromap buffers checked against an alpha texture
//! (the CLI's `verify-bake`): `micromap::read_buffers` validates the
//! bytes, `Baker::verify_each` checks every known micro-triangle, with the
//! GIL released.

use crate::bake::{uv_triangles, Alpha};
use crate::options::{self, value_error};
use micromap_index::bake::{Baker, Contradiction};
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
    address, border_alpha, cutoff, opaque_above, model, max_report, max_checks,
    lenient_layout, record_stride, index_stride))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn verify<'py>(
    py: Python<'py>,
    alpha: &Bound<'py, PyAny>,
    uvs: &Bound<'py, PyAny>,
    data: Vec<u8>,
    triangles: Vec<u8>,
    indices: Vec<u8>,
    index_width: i64,
    usage: Option<Vec<u8>>,
    filter: &str,
    address: &Bound<'py, PyAny>,
    border_alpha: f32,
    cutoff: f32,
    opaque_above: bool,
    model: &str,
    max_report: i64,
    max_checks: Option<i64>,
    lenient_layout: bool,
    record_stride: Option<i64>,
    index_stride: Option<i64>,
) -> PyResult<Bound<'py, PyDict>> {
    let alpha = Alpha::new(alpha)?;
    let uv = uv_triangles(uvs)?;
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
    let model = options::model(model)?;
    let max_checks = max_checks
        .map(|m| options::count(m, "max_checks"))
        .transpose()?
        .unwrap_or(u64::MAX);
    let max_report =
        usize::try_from(options::count(max_report, "max_report")?).unwrap_or(usize::MAX);
    let outcome = py.allow_threads(|| -> Result<_, String> {
        let read = read_buffers(
            &BufferBytes {
                records: &triangles,
                data: &data,
                usage_counts: usage.as_deref(),
                indices: Some((&indices, width)),
            },
            &read_options,
        )
        .map_err(|e| e.to_string())?;
        let index = read.indices.unwrap_or_default();
        if index.len() != uv.len() {
            return Err(format!(
                "the buffers have {} indices for {} triangles",
                index.len(),
                uv.len()
            ));
        }
        let texture = alpha.texture().map_err(|e| e.to_string())?;
        let baker = Baker::new(&*texture, sampler, cutoff)
            .map_err(|e| e.to_string())?
            .with_model(model);
        let mut totals = Totals::default();
        let mut first: Vec<(usize, Contradiction, f64)> = Vec::new();
        for (t, (uv, index)) in uv.iter().zip(&index).enumerate() {
            let opacity = match *index {
                MicromapIndex::Record(r) => TriangleOpacity::Micromap(&read.micromaps[r as usize]),
                MicromapIndex::Special(state) => TriangleOpacity::Special(state),
            };
            let remaining = max_checks.saturating_sub(totals.known);
            let v = baker.verify_each(uv, &opacity, remaining, |c| {
                if first.len() < max_report {
                    let alpha = match c.texel {
                        Some((x, y)) => texture.alpha(x, y),
                        None => f64::from(sampler.border_alpha),
                    };
                    first.push((t, c, alpha));
                }
            });
            totals.checked += usize::from(v.checked);
            totals.known += v.known;
            totals.unchecked += v.unchecked;
            totals.unknown += v.unknown;
            totals.undecided += v.undecided;
            totals.contradictions += v.contradictions;
        }
        Ok((totals, first))
    });
    let (totals, first) = outcome.map_err(value_error)?;
    let out = PyDict::new(py);
    out.set_item("model", model.name())?;
    out.set_item("triangles", uv.len())?;
    out.set_item("triangles_checked", totals.checked)?;
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

/// The counts over all triangles.
#[derive(Default)]
struct Totals {
    checked: usize,
    known: u64,
    unchecked: u64,
    unknown: u64,
    undecided: u64,
    contradictions: u64,
}
