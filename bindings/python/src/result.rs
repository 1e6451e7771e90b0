//! A finished bake as the Python layer wraps it (`BakeResult`): the four
//! files' bytes, the statistics (summary.json's keys) and, per mesh, what
//! summary.json's `jobs` say.

use crate::fallible::try_vec;
use crate::options::value_error;
use micromap_index::bake::mesh::MeshBake;
use micromap_index::bake::Sampler;
use micromap_index::micromap::{usage_counts_to_le_bytes, IndexWidth};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};

/// What the result reports per mesh (the CLI's `jobs` in summary.json).
pub(crate) struct MeshInfo {
    pub(crate) name: String,
    pub(crate) size: (u32, u32),
    pub(crate) sampler: Sampler,
    pub(crate) cutoff: f32,
    pub(crate) alpha_factor: f32,
    pub(crate) triangles: usize,
}

/// `bake` as a dict of the bytes, statistics and meshes.
pub(crate) fn result<'py>(
    py: Python<'py>,
    bake: &MeshBake,
    width: IndexWidth,
    meshes: &[MeshInfo],
) -> PyResult<Bound<'py, PyDict>> {
    let buffers = &bake.buffers;
    let total: usize = meshes.iter().map(|m| m.triangles).sum();
    let mut indices = try_vec(total.saturating_mul(width.bytes()), "indices")?;
    for g in 0..buffers.geometry_count() {
        indices.extend(buffers.index_bytes(g, width).map_err(value_error)?);
    }
    let out = PyDict::new(py);
    out.set_item("data", PyBytes::new(py, buffers.data()))?;
    out.set_item("triangles", PyBytes::new(py, &buffers.records_le_bytes()))?;
    out.set_item(
        "usage",
        PyBytes::new(py, &usage_counts_to_le_bytes(buffers.usage_counts())),
    )?;
    out.set_item("indices", PyBytes::new(py, &indices))?;
    out.set_item("index_width", width.bytes() * 8)?;
    let r = &bake.report;
    let stats = PyDict::new(py);
    stats.set_item("triangles", r.triangles)?;
    stats.set_item("levels", r.levels.clone())?;
    let counts = PyDict::new(py);
    for (name, count) in [
        "transparent",
        "opaque",
        "unknown_transparent",
        "unknown_opaque",
    ]
    .iter()
    .zip(r.counts)
    {
        counts.set_item(name, count)?;
    }
    stats.set_item("micro_triangles", counts)?;
    stats.set_item("known_fraction", r.known_fraction)?;
    stats.set_item("known_area_fraction", r.known_area_fraction)?;
    let status = PyDict::new(py);
    status.set_item("exact", r.status.exact)?;
    status.set_item("not_finite", r.status.not_finite)?;
    status.set_item("out_of_exact_range", r.status.out_of_exact_range)?;
    status.set_item("budget_exceeded", r.status.block_budget_exceeded)?;
    status.set_item("work_budget_exceeded", r.status.work_budget_exceeded)?;
    stats.set_item("status", status)?;
    stats.set_item("distinct_triangles", r.distinct_triangles)?;
    stats.set_item("work_units", r.work)?;
    stats.set_item("period_level_zero_triangles", r.period_level_zero)?;
    stats.set_item("micromaps_after_dedup", r.micromaps)?;
    stats.set_item("special_index_triangles", r.special_index_triangles)?;
    stats.set_item("bytes_flat", r.bytes_flat)?;
    stats.set_item("bytes_paper_tree", r.bytes_paper_tree)?;
    stats.set_item("bytes_level_order_tree", r.bytes_level_order_tree)?;
    out.set_item("stats", stats)?;
    let list = PyList::empty(py);
    let mut first_index = 0;
    for (geometry, m) in meshes.iter().enumerate() {
        let d = PyDict::new(py);
        d.set_item("name", &m.name)?;
        d.set_item("texture", (m.size.0, m.size.1))?;
        d.set_item("filter", m.sampler.filter.name())?;
        d.set_item(
            "address",
            (m.sampler.address_u.name(), m.sampler.address_v.name()),
        )?;
        d.set_item("cutoff", m.cutoff)?;
        d.set_item("alpha_factor", m.alpha_factor)?;
        d.set_item("triangles", m.triangles)?;
        d.set_item("first_index", first_index)?;
        // The CLI's `mixed_special_indices` of the job (summary.json).
        d.set_item(
            "mixed_special_indices",
            buffers.is_mixed(geometry).map_err(value_error)?,
        )?;
        first_index += m.triangles;
        list.append(d)?;
    }
    out.set_item("meshes", list)?;
    Ok(out)
}
