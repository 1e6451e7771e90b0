//! The assets crate's readers: a PNG or JPEG's alpha channel as a 2-D
//! array, a TRIS.json triangle list as `(N, 3, 2)` float32 (what `bake`
//! takes), so a script bakes exactly what `micromap-index bake --texture
//! --triangles` bakes.

use crate::fallible::try_vec;
use micromap_index_assets::{decode_alpha_image, read_triangles_json, AlphaTexels, Limits};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use std::io::Read as _;
use std::path::Path;

/// `path`'s bytes, refused past `limit` (at most `limit + 1` are read, so
/// a pipe or a device cannot exhaust memory).
fn read(path: &Path, limit: u64) -> PyResult<Vec<u8>> {
    let shown = path.display();
    let io = |e: std::io::Error| PyOSError::new_err(format!("cannot read {shown}: {e}"));
    let file = std::fs::File::open(path).map_err(io)?;
    // Room for the whole file (within the limit) reserved fallibly first;
    // a file that grows meanwhile still stops at `limit + 1` bytes.
    let size = file.metadata().map_or(0, |m| m.len()).min(limit + 1);
    let mut bytes = try_vec(usize::try_from(size).unwrap_or(usize::MAX), "the file")?;
    file.take(limit + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(PyValueError::new_err(format!(
            "{shown}: over the limit of {limit} bytes"
        )));
    }
    Ok(bytes)
}

/// The alpha channel of a PNG or JPEG (its grey value when it has no
/// alpha), as `micromap-index bake --texture` reads it: a `(height, width)`
/// uint8 array, or uint16 for 16-bit PNGs; row 0 is the top row.
#[pyfunction]
pub(crate) fn read_alpha(py: Python<'_>, path: std::path::PathBuf) -> PyResult<PyObject> {
    let limits = Limits::default();
    let bytes = read(&path, limits.max_bytes)?;
    let image = py
        .allow_threads(|| decode_alpha_image(&bytes, &limits))
        .map_err(|e| PyValueError::new_err(format!("{}: {e}", path.display())))?;
    let shape = [image.height as usize, image.width as usize];
    Ok(match image.texels {
        AlphaTexels::Unorm8(t) => PyArray1::from_vec(py, t)
            .reshape(shape)?
            .into_any()
            .unbind(),
        AlphaTexels::Unorm16(t) => PyArray1::from_vec(py, t)
            .reshape(shape)?
            .into_any()
            .unbind(),
        AlphaTexels::Float(t) => PyArray1::from_vec(py, t)
            .reshape(shape)?
            .into_any()
            .unbind(),
    })
}

/// A TRIS.json triangle list (`micromap-index bake --triangles`) as a
/// `(N, 3, 2)` float32 array.
#[pyfunction]
pub(crate) fn read_triangles(py: Python<'_>, path: std::path::PathBuf) -> PyResult<PyObject> {
    let bytes = read(&path, Limits::default().max_bytes)?;
    let triangles = read_triangles_json(&bytes)
        .map_err(|e| PyValueError::new_err(format!("{}: {e}", path.display())))?;
    let n = triangles.len();
    let mut flat = try_vec(n.saturating_mul(6), "the triangles")?;
    flat.extend(triangles.iter().flatten().flatten().copied());
    Ok(PyArray1::from_vec(py, flat)
        .reshape([n, 3, 2])?
        .into_any()
        .unbind())
}
