//! `index` and `wide_index`: the Vulkan reference in binary32 on numpy
//! arrays (through the library's SIMD batch kernels) or on scalars. Arrays
//! are read in place, chunk by chunk when not C-contiguous (the GIL is held
//! for the whole call, so nothing can change them meanwhile); the one
//! allocation sized by the input, the result, is fallible.

use crate::arrays::{dtype_name, has_dtype, readonly, type_name, zip_chunks};
use crate::fallible::try_vec;
use micromap_index::{batch, spec, Level, SpecLevel};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

fn float32<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<PyReadonlyArrayDyn<'py, f32>> {
    let array = obj
        .downcast::<PyUntypedArray>()
        .map_err(|_| PyTypeError::new_err(format!("{what}: expected a numpy array")))?;
    if !has_dtype::<f32>(array) {
        return Err(PyTypeError::new_err(format!(
            "{what} must have dtype float32 (the hit's binary32 barycentrics), not {}; \
             convert with numpy.asarray({what}, numpy.float32)",
            dtype_name(array)
        )));
    }
    readonly(array, what)
}

/// Reads `u`, `v` and calls `scalar` or `batch` on them; the result is a
/// Python int or an array of `u`'s shape.
fn run<O: numpy::Element + Copy + Default>(
    u: &Bound<'_, PyAny>,
    v: &Bound<'_, PyAny>,
    scalar: impl Fn(f32, f32) -> u64,
    batch: impl Fn(&[f32], &[f32], &mut [O]) -> Result<(), batch::BatchError>,
) -> PyResult<PyObject> {
    let py = u.py();
    match (
        u.downcast::<PyUntypedArray>().is_ok(),
        v.downcast::<PyUntypedArray>().is_ok(),
    ) {
        (false, false) => {
            let number = |x: &Bound<'_, PyAny>, what: &str| {
                x.extract::<f32>().map_err(|_| {
                    PyTypeError::new_err(format!(
                        "{what} must be a number or a float32 numpy array, not {}",
                        type_name(x)
                    ))
                })
            };
            let (u, v) = (number(u, "u")?, number(v, "v")?);
            Ok(scalar(u, v).into_pyobject(py)?.into_any().unbind())
        }
        (true, true) => {
            let (ru, rv) = (float32(u, "u")?, float32(v, "v")?);
            if ru.shape() != rv.shape() {
                return Err(PyValueError::new_err(format!(
                    "u and v must have the same shape, not {:?} and {:?}",
                    ru.shape(),
                    rv.shape()
                )));
            }
            let (u, v) = (ru.as_array(), rv.as_array());
            let mut out: Vec<O> = try_vec(u.len(), "the result")?;
            zip_chunks(&u, &v, |u, v| {
                let start = out.len();
                // Within the reserved capacity: never reallocates.
                out.resize(start + u.len(), O::default());
                batch(u, v, &mut out[start..]).map_err(|e| PyValueError::new_err(e.to_string()))
            })?;
            Ok(PyArray1::from_vec(py, out)
                .reshape(u.shape())?
                .into_any()
                .unbind())
        }
        _ => Err(PyTypeError::new_err(
            "u and v must both be numpy arrays or both be numbers",
        )),
    }
}

/// The micro-triangle index a GPU reads for the hit `(u, v)` at `level`
/// (0..=16): the Vulkan reference in binary32, bit for bit
/// (`micromap_index::index`). Arrays (float32, equal shapes) give a uint32
/// array of that shape through the SIMD batch kernels; numbers (rounded to
/// float32 first) give an int.
#[pyfunction]
pub(crate) fn index(u: &Bound<'_, PyAny>, v: &Bound<'_, PyAny>, level: i64) -> PyResult<PyObject> {
    let level = u32::try_from(level)
        .ok()
        .and_then(|l| SpecLevel::new(l).ok())
        .ok_or_else(|| {
            PyValueError::new_err(format!(
                "level {level}: expected 0..=16 (wide_index takes 0..=32)"
            ))
        })?;
    run(
        u,
        v,
        |u, v| u64::from(spec::index_f32(u, v, level)),
        |u, v, out| batch::index_f32(u, v, level, out),
    )
}

/// The reference widened to 64-bit words, levels 0..=32
/// (`spec::wide_index_f32`); arrays give uint64.
#[pyfunction]
pub(crate) fn wide_index(
    u: &Bound<'_, PyAny>,
    v: &Bound<'_, PyAny>,
    level: i64,
) -> PyResult<PyObject> {
    let level = u32::try_from(level)
        .ok()
        .and_then(|l| Level::new(l).ok())
        .ok_or_else(|| PyValueError::new_err(format!("level {level}: expected 0..=32")))?;
    run(
        u,
        v,
        |u, v| spec::wide_index_f32(u, v, level),
        |u, v, out| batch::wide_index_f32(u, v, level, out),
    )
}
