//! `micromap_index._native`: the pyo3 layer of the Python package
//! `micromap_index` (`python/micromap_index/__init__.py` is the public
//! face; docs/python.md). Thin: every answer is the library's
//! (`batch`, `spec`, `bake::mesh`, `Baker::verify_each`,
//! `micromap::read_buffers`, `succinct`, the assets crate's readers); this
//! crate only converts arrays and options and turns errors into Python
//! exceptions (`TypeError` for a wrong type or dtype, `ValueError` for a
//! wrong shape or value, `OSError` for files), never a crash.

use pyo3::prelude::*;

mod arrays;
mod assets;
mod bake;
mod bake_options;
mod fallible;
mod gltf_out;
mod index;
mod inputs;
mod options;
mod result;
mod tree;
mod verify;

/// The extension module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(index::index, m)?)?;
    m.add_function(wrap_pyfunction!(index::wide_index, m)?)?;
    m.add_function(wrap_pyfunction!(bake::bake, m)?)?;
    m.add_function(wrap_pyfunction!(bake::bake_gltf, m)?)?;
    m.add_function(wrap_pyfunction!(verify::verify, m)?)?;
    m.add_function(wrap_pyfunction!(assets::read_alpha, m)?)?;
    m.add_function(wrap_pyfunction!(assets::read_triangles, m)?)?;
    m.add_class::<tree::Tree>()?;
    Ok(())
}
