//! `bake` (an alpha array and UV triangles) and `bake_gltf` (a glTF file
//! through micromap-index-assets), both by `bake::mesh::bake_meshes` with
//! the GIL released, into the API buffers `micromap-index bake` writes.

use crate::arrays::{copy, dtype_name, has_dtype, untyped};
use crate::options::{self, value_error};
use micromap_index::bake::mesh::{
    bake_meshes, output_bytes_bound, LevelRule, Material, Mesh, MeshBake, MeshBakeError,
    MeshOptions, MeshTriangles,
};
use micromap_index::bake::{
    AlphaTexture, F32Texture, Sampler, TextureError, Unorm16Texture, Unorm8Texture, UvTriangle,
};
use micromap_index::micromap::{usage_counts_to_le_bytes, BuildOptions, IndexWidth};

use micromap_index_assets::{read_gltf_file, AssetError, Limits};
use pyo3::exceptions::{PyOSError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};
use std::path::PathBuf;

/// An alpha array's texels, owned, by dtype; row 0 is the image's top row
/// (`v = 0`), as the PNG reader returns it.
pub(crate) enum Texels {
    U8(Vec<u8>),
    U16(Vec<u16>),
    F32(Vec<f32>),
}

/// A 2-D alpha array: its width, height and texels.
pub(crate) struct Alpha {
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) texels: Texels,
}

impl Alpha {
    /// `alpha` as the baker reads it: a 2-D `uint8` (unorm8), `uint16`
    /// (unorm16) or `float32` array of shape `(height, width)`.
    pub(crate) fn new(obj: &Bound<'_, PyAny>) -> PyResult<Alpha> {
        let array = untyped(obj, "alpha")?;
        let texels = if has_dtype::<u8>(array) {
            Texels::U8(copy(array, "alpha")?.elements)
        } else if has_dtype::<u16>(array) {
            Texels::U16(copy(array, "alpha")?.elements)
        } else if has_dtype::<f32>(array) {
            Texels::F32(copy(array, "alpha")?.elements)
        } else {
            return Err(PyTypeError::new_err(format!(
                "alpha must have dtype uint8, uint16 or float32, not {}",
                dtype_name(array)
            )));
        };
        let shape = numpy::PyUntypedArrayMethods::shape(array);
        let &[height, width] = shape else {
            return Err(PyValueError::new_err(format!(
                "alpha must be 2-D (height, width), not of shape {shape:?}"
            )));
        };
        let dimension = |n: usize, what: &str| {
            u32::try_from(n)
                .map_err(|_| value_error(format!("alpha's {what} {n} is over 2^32 - 1")))
        };
        Ok(Alpha {
            width: dimension(width, "width")?,
            height: dimension(height, "height")?,
            texels,
        })
    }

    /// The library's view of the texels (it refuses empty textures).
    pub(crate) fn texture(&self) -> Result<Box<dyn AlphaTexture + '_>, TextureError> {
        let (w, h) = (self.width, self.height);
        Ok(match &self.texels {
            Texels::U8(t) => Box::new(Unorm8Texture::new(w, h, t)?),
            Texels::U16(t) => Box::new(Unorm16Texture::new(w, h, t)?),
            Texels::F32(t) => Box::new(F32Texture::new(w, h, t)?),
        })
    }
}

/// `uvs`: a float32 array of shape `(N, 3, 2)`, triangle `t`'s vertex `i`
/// at `uvs[t, i]`.
pub(crate) fn uv_triangles(obj: &Bound<'_, PyAny>) -> PyResult<Vec<UvTriangle>> {
    let array = untyped(obj, "uvs")?;
    if !has_dtype::<f32>(array) {
        return Err(PyTypeError::new_err(format!(
            "uvs must have dtype float32 (the UVs a GPU interpolates), not {}",
            dtype_name(array)
        )));
    }
    let owned = copy::<f32>(array, "uvs")?;
    if owned.shape.len() != 3 || owned.shape[1] != 3 || owned.shape[2] != 2 {
        return Err(PyValueError::new_err(format!(
            "uvs must have shape (N, 3, 2), not {:?}",
            owned.shape
        )));
    }
    Ok(owned
        .elements
        .chunks_exact(6)
        .map(|c| [[c[0], c[1]], [c[2], c[3]], [c[4], c[5]]])
        .collect())
}

/// The options both bakes take.
struct Common {
    options: MeshOptions,
    width: IndexWidth,
    max_bytes: u64,
}

#[allow(clippy::too_many_arguments)]
fn common(
    level: &Bound<'_, PyAny>,
    max_level: i64,
    format: i64,
    unknown: &str,
    model: &str,
    budget: Option<i64>,
    index_width: i64,
    max_bytes: i64,
    no_mixed_special: bool,
) -> PyResult<Common> {
    let fixed = options::level_or_auto(level)?;
    let max = options::bake_level(max_level, "max_level")?;
    let budget = budget.map(|b| options::count(b, "budget")).transpose()?;
    if budget.is_some() && fixed.is_some() {
        return Err(value_error(
            "budget chooses levels: it goes with level=\"auto\"",
        ));
    }
    Ok(Common {
        options: MeshOptions {
            levels: fixed.map_or(LevelRule::Useful { max }, LevelRule::Fixed),
            format: options::format(format)?,
            unknown: options::unknown(unknown)?,
            budget_bytes: budget,
            model: options::model(model)?,
            buffers: BuildOptions {
                no_mixed_special_indices: no_mixed_special,
                ..BuildOptions::default()
            },
            ..MeshOptions::default()
        },
        width: options::index_width(index_width)?,
        max_bytes: options::count(max_bytes, "max_bytes")?,
    })
}

/// Bakes `meshes`, refusing first (as `micromap-index bake --max-bytes`)
/// a bake whose output may exceed `c.max_bytes`: the allocator would abort
/// the interpreter long before such a bake finished.
fn bake_within(meshes: &[Mesh<'_>], c: &Common, info: &[MeshInfo]) -> PyResult<MeshBake> {
    let estimate =
        output_bytes_bound(meshes, &c.options, c.width).map_err(|e| bake_error(e, info))?;
    if estimate > c.max_bytes {
        return Err(value_error(format!(
            "the output may take up to {estimate} bytes (before deduplication), over the \
             limit of max_bytes={} bytes; nothing baked (max_bytes raises the limit, \
             budget or a lower level/max_level shrinks the output)",
            c.max_bytes
        )));
    }
    bake_meshes(meshes, &c.options, &mut |_, _| {}).map_err(|e| bake_error(e, info))
}

/// A finished bake as the Python layer wraps it: the four files'
/// bytes, the statistics and where each geometry's indices start.
fn result<'py>(
    py: Python<'py>,
    bake: &MeshBake,
    width: IndexWidth,
    meshes: &[MeshInfo],
) -> PyResult<Bound<'py, PyDict>> {
    let buffers = &bake.buffers;
    let mut indices = Vec::new();
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
        d.set_item(
            "filter",
            match m.sampler.filter {
                micromap_index::bake::Filter::Nearest => "nearest",
                micromap_index::bake::Filter::Linear => "linear",
            },
        )?;
        d.set_item(
            "address",
            (
                options::address_name(m.sampler.address_u),
                options::address_name(m.sampler.address_v),
            ),
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

/// What the result reports per mesh (the CLI's `jobs` in summary.json).
struct MeshInfo {
    name: String,
    size: (u32, u32),
    sampler: Sampler,
    cutoff: f32,
    alpha_factor: f32,
    triangles: usize,
}

fn bake_error(e: MeshBakeError, names: &[MeshInfo]) -> PyErr {
    match e {
        MeshBakeError::Texture { mesh, error } => value_error(format!(
            "{}: {error}",
            names.get(mesh).map_or("mesh", |m| m.name.as_str())
        )),
        other => value_error(other),
    }
}

/// Bakes one alpha texture and its UV triangles (the CLI's
/// `bake --texture --triangles`); the Python layer documents the options.
#[pyfunction]
#[pyo3(signature = (alpha, uvs, *, level, max_level, format, unknown, filter, address,
    border_alpha, cutoff, opaque_above, model, budget, index_width, alpha_factor, max_bytes,
    no_mixed_special))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn bake<'py>(
    py: Python<'py>,
    alpha: &Bound<'py, PyAny>,
    uvs: &Bound<'py, PyAny>,
    level: &Bound<'py, PyAny>,
    max_level: i64,
    format: i64,
    unknown: &str,
    filter: &str,
    address: &Bound<'py, PyAny>,
    border_alpha: f32,
    cutoff: f32,
    opaque_above: bool,
    model: &str,
    budget: Option<i64>,
    index_width: i64,
    alpha_factor: f32,
    max_bytes: i64,
    no_mixed_special: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let alpha = Alpha::new(alpha)?;
    let triangles = uv_triangles(uvs)?;
    let c = common(
        level,
        max_level,
        format,
        unknown,
        model,
        budget,
        index_width,
        max_bytes,
        no_mixed_special,
    )?;
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
    let info = [MeshInfo {
        name: "alpha".into(),
        size: (alpha.width, alpha.height),
        sampler,
        cutoff: cutoff.alpha(),
        alpha_factor,
        triangles: triangles.len(),
    }];
    let baked = py.allow_threads(|| {
        let texture = alpha
            .texture()
            .map_err(|error| bake_error(MeshBakeError::Texture { mesh: 0, error }, &info))?;
        let mesh = Mesh {
            triangles: MeshTriangles::Uv(&triangles),
            texture: &*texture,
            material: Material {
                sampler,
                cutoff,
                alpha_factor,
            },
            vertex_alpha: None,
        };
        bake_within(&[mesh], &c, &info)
    })?;
    result(py, &baked, c.width, &info)
}

/// Bakes a glTF 2.0 asset's alpha-masked primitives (the CLI's
/// `bake --gltf`): `filter`, `address` and `cutoff` override the asset's
/// own when given.
#[pyfunction]
#[pyo3(signature = (path, *, level, max_level, format, unknown, filter, address,
    border_alpha, cutoff, opaque_above, model, budget, index_width, max_bytes,
    no_mixed_special))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn bake_gltf<'py>(
    py: Python<'py>,
    path: PathBuf,
    level: &Bound<'py, PyAny>,
    max_level: i64,
    format: i64,
    unknown: &str,
    filter: Option<&str>,
    address: Option<&Bound<'py, PyAny>>,
    border_alpha: f32,
    cutoff: Option<f32>,
    opaque_above: bool,
    model: &str,
    budget: Option<i64>,
    index_width: i64,
    max_bytes: i64,
    no_mixed_special: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let c = common(
        level,
        max_level,
        format,
        unknown,
        model,
        budget,
        index_width,
        max_bytes,
        no_mixed_special,
    )?;
    let filter = filter.map(options::filter).transpose()?;
    let address = address.map(options::address_pair).transpose()?;
    let border_alpha = options::border(border_alpha)?;
    if let Some(value) = cutoff {
        options::cutoff(value, opaque_above)?;
    }
    let shown = path.display().to_string();
    let gltf = py
        .allow_threads(|| read_gltf_file(&path, &Limits::default()))
        .map_err(|e| {
            let message = format!("{shown}: {e}");
            if matches!(e.root(), AssetError::Io { .. }) {
                PyOSError::new_err(message)
            } else {
                PyValueError::new_err(message)
            }
        })?;
    let mut info = Vec::with_capacity(gltf.primitives.len());
    let mut materials = Vec::with_capacity(gltf.primitives.len());
    for prim in &gltf.primitives {
        let (address_u, address_v) =
            address.unwrap_or((prim.sampler.address_u, prim.sampler.address_v));
        let sampler = Sampler {
            filter: filter.unwrap_or(prim.sampler.filter),
            address_u,
            address_v,
            border_alpha,
        };
        let cutoff = options::cutoff(cutoff.unwrap_or(prim.cutoff.alpha()), opaque_above)?;
        let image = &gltf.images[prim.image];
        info.push(MeshInfo {
            name: format!("mesh {} primitive {}", prim.mesh, prim.primitive),
            size: (image.width, image.height),
            sampler,
            cutoff: cutoff.alpha(),
            alpha_factor: prim.alpha_factor,
            triangles: prim.triangles.len(),
        });
        materials.push(Material {
            sampler,
            cutoff,
            alpha_factor: prim.alpha_factor,
        });
    }
    if info.is_empty() {
        return Err(value_error(format!(
            "{shown}: no primitive with an alphaMode MASK material and a base colour texture"
        )));
    }
    let baked = py.allow_threads(|| {
        let textures = gltf
            .images
            .iter()
            .map(micromap_index_assets::AlphaImage::texture)
            .collect::<Result<Vec<_>, _>>()
            .map_err(|error| bake_error(MeshBakeError::Texture { mesh: 0, error }, &info))?;
        let meshes: Vec<Mesh<'_>> = gltf
            .primitives
            .iter()
            .zip(&materials)
            .map(|(prim, material)| Mesh {
                triangles: MeshTriangles::Uv(&prim.triangles),
                texture: &textures[prim.image],
                material: *material,
                vertex_alpha: prim.vertex_alpha.as_deref(),
            })
            .collect();
        bake_within(&meshes, &c, &info)
    })?;
    let out = result(py, &baked, c.width, &info)?;
    out.set_item("warnings", gltf.warnings.clone())?;
    Ok(out)
}
