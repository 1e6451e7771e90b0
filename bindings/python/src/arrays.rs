//! numpy arrays in, checked: a wrong dtype is a `TypeError`, a wrong shape
//! a `ValueError`, and the elements are copied out in C order (so a
//! strided or Fortran-ordered view is read as numpy shows it, and nothing
//! borrowed from Python is read after the GIL is released).

use numpy::{
    Element, PyArrayDescrMethods, PyArrayDyn, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// A numpy array's shape and its elements in C order.
pub(crate) struct Owned<T> {
    pub(crate) shape: Vec<usize>,
    pub(crate) elements: Vec<T>,
}

/// `obj` as an untyped numpy array, or a `TypeError` naming `what`.
pub(crate) fn untyped<'a, 'py>(
    obj: &'a Bound<'py, PyAny>,
    what: &str,
) -> PyResult<&'a Bound<'py, PyUntypedArray>> {
    obj.downcast::<PyUntypedArray>().map_err(|_| {
        PyTypeError::new_err(format!(
            "{what} must be a numpy array, not {}",
            type_name(obj)
        ))
    })
}

/// The Python type name of `obj`, for messages.
pub(crate) fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map_or_else(|_| "an object".into(), |n| n.to_string())
}

/// The dtype's text (`float64`, `>f4`), for messages.
pub(crate) fn dtype_name(array: &Bound<'_, PyUntypedArray>) -> String {
    array
        .dtype()
        .str()
        .map_or_else(|_| "unknown".into(), |s| s.to_string())
}

/// Whether `array`'s dtype is `T` in native byte order.
pub(crate) fn has_dtype<T: Element>(array: &Bound<'_, PyUntypedArray>) -> bool {
    array.dtype().is_equiv_to(&numpy::dtype::<T>(array.py()))
}

/// `array` (already known to hold `T`) copied out in C order.
pub(crate) fn copy<T: Element + Copy>(
    array: &Bound<'_, PyUntypedArray>,
    what: &str,
) -> PyResult<Owned<T>> {
    let typed = array.downcast::<PyArrayDyn<T>>().map_err(|_| {
        PyTypeError::new_err(format!("{what}: unexpected dtype {}", dtype_name(array)))
    })?;
    let read = typed
        .try_readonly()
        .map_err(|e| PyValueError::new_err(format!("{what}: {e}")))?;
    // `as_slice` also accepts Fortran order (memory order, not numpy's
    // logical order): only a C-contiguous array is copied as one slice.
    let elements = match read.as_slice() {
        Ok(slice) if array.is_c_contiguous() => slice.to_vec(),
        // ndarray iterates in logical (C) order.
        _ => read.as_array().iter().copied().collect(),
    };
    Ok(Owned {
        shape: array.shape().to_vec(),
        elements,
    })
}
