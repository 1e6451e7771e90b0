//! `bake` (an alpha array and UV triangles) and `bake_gltf` (a glTF file
//! through micromap-index-assets), both by `bake::mesh::bake_meshes` with
//! the GIL released, into the API buffers `micromap-index bake` writes
//! (`result`), refused first when the output may exceed `max_bytes`.

use crate::bake_options::{BakeOptions, Common};
use crate::gltf_out::GltfOut;
use crate::inputs::{AlphaArray, UvArray};
use crate::options::{self, value_error};
use crate::result::{result, MeshInfo};
use micromap_index::bake::mesh::{
    bake_meshes, output_bytes_bound, Material, Mesh, MeshBake, MeshBakeError, MeshTriangles,
};
use micromap_index::bake::Sampler;
use micromap_index_assets::{read_gltf_file, AssetError, Limits, RefusedPrimitive};
use pyo3::exceptions::{PyMemoryError, PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;

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

fn bake_error(e: MeshBakeError, names: &[MeshInfo]) -> PyErr {
    match e {
        e if e.is_allocation_failure() => PyMemoryError::new_err(e.to_string()),
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
#[pyo3(signature = (alpha, uvs, options, *, filter, address, border_alpha, cutoff,
    opaque_above, alpha_factor, uv_transform=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn bake<'py>(
    py: Python<'py>,
    alpha: &Bound<'py, PyAny>,
    uvs: &Bound<'py, PyAny>,
    options: BakeOptions<'py>,
    filter: &str,
    address: &Bound<'py, PyAny>,
    border_alpha: f32,
    cutoff: f32,
    opaque_above: bool,
    alpha_factor: f32,
    uv_transform: Option<([f32; 2], f32, [f32; 2])>,
) -> PyResult<Bound<'py, PyDict>> {
    let alpha = AlphaArray::new(alpha)?;
    let uvs = UvArray::new(uvs)?;
    let uv_transform = options::uv_transform(uv_transform)?;
    let c = options.check()?;
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
    // Every triangle gets an index: more triangles than max_bytes holds
    // indices for are refused before they are copied (output_bytes_bound
    // would refuse them after).
    let index_bytes = uvs.len() as u128 * c.width.bytes() as u128;
    if index_bytes > u128::from(c.max_bytes) {
        return Err(value_error(format!(
            "uvs holds {} triangles, whose indices alone take {index_bytes} bytes, over \
             the limit of max_bytes={} bytes; nothing baked (max_bytes raises the limit)",
            uvs.len(),
            c.max_bytes
        )));
    }
    let triangles = uvs.copy()?;
    let alpha = alpha.copy()?;
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
                uv_transform,
            },
            vertex_alpha: None,
        };
        bake_within(&[mesh], &c, &info)
    })?;
    result(py, &baked, c.width, &info)
}

/// Bakes a glTF 2.0 asset's alpha-masked primitives (the CLI's
/// `bake --gltf`): `filter`, `address`, `border_alpha`, `cutoff` and
/// `opaque_above` override the asset's own when given (not with
/// `gltf_out`, whose micromaps must match the asset's own sampling, as
/// `--gltf-out` refuses them). With `gltf_out`, the result's `gltf_files`
/// are the files `--gltf-out` writes, for `gltf_out`'s directory.
#[pyfunction]
#[pyo3(signature = (path, options, *, filter, address, border_alpha, cutoff, opaque_above,
    gltf_out, strict))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn bake_gltf<'py>(
    py: Python<'py>,
    path: PathBuf,
    options: BakeOptions<'py>,
    filter: Option<&str>,
    address: Option<&Bound<'py, PyAny>>,
    border_alpha: Option<f32>,
    cutoff: Option<f32>,
    opaque_above: bool,
    gltf_out: Option<PathBuf>,
    strict: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let c = options.check()?;
    let gltf_out = gltf_out.as_deref().map(GltfOut::new).transpose()?;
    if gltf_out.is_some() {
        let given = [
            ("filter", filter.is_some()),
            ("address", address.is_some()),
            ("border_alpha", border_alpha.is_some()),
            ("cutoff", cutoff.is_some()),
            ("opaque_above", opaque_above),
        ];
        if let Some((keyword, _)) = given.iter().find(|(_, given)| *given) {
            return Err(value_error(format!(
                "{keyword} with gltf_out: the micromaps must match the asset's own samplers \
                 and alphaCutoff, which the renderer uses"
            )));
        }
    }
    let filter = filter.map(options::filter).transpose()?;
    let address = address.map(options::address_pair).transpose()?;
    let border_alpha = options::border(border_alpha.unwrap_or(0.0))?;
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
    // A primitive the model does not cover: an error when strict, or when
    // nothing else is left to bake; else left out and listed.
    if let Some(refusal) = RefusedPrimitive::refusal(&gltf.refused) {
        if strict || gltf.primitives.is_empty() {
            return Err(value_error(format!("{shown}: {refusal}")));
        }
    }
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
            uv_transform: prim.uv_transform,
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
    let refused = PyList::empty(py);
    for r in &gltf.refused {
        let item = PyDict::new(py);
        item.set_item("mesh", r.mesh)?;
        item.set_item("primitive", r.primitive)?;
        item.set_item("reason", r.reason.to_string())?;
        refused.append(item)?;
    }
    out.set_item("refused_primitives", refused)?;
    if let Some(gltf_out) = gltf_out {
        let primitives: Vec<(usize, usize)> = gltf
            .primitives
            .iter()
            .map(|p| (p.mesh, p.primitive))
            .collect();
        let files = py.allow_threads(|| gltf_out.files(&path, &baked.buffers, &primitives))?;
        let list: Vec<(String, Bound<'py, pyo3::types::PyBytes>)> = files
            .into_iter()
            .map(|(name, bytes)| (name, pyo3::types::PyBytes::new(py, &bytes)))
            .collect();
        out.set_item("gltf_files", list)?;
        out.set_item("gltf_dir", gltf_out.dir())?;
    }
    Ok(out)
}
