//! numpy arrays in, checked: a wrong dtype is a `TypeError`, a wrong shape
//! a `ValueError` (callers check shapes before anything is copied). Arrays
//! are read in C order (a strided, Fortran-ordered or broadcast view is
//! read as numpy shows it) in one of two ways:
//!
//! - [`copy_c_order`]: the elements copied out, into a fallibly reserved
//!   buffer, for calls that release the GIL (nothing borrowed from Python
//!   is read while other Python threads may write to it);
//! - [`zip_chunks`]: read in place, chunk by chunk, for calls that keep the
//!   GIL (a broadcast view of 2^40 elements is never copied whole).

use crate::fallible::try_vec;
use numpy::ndarray::ArrayViewD;
use numpy::{
    Element, PyArrayDescrMethods, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

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

/// `array` (already known to hold `T`) borrowed for reading.
pub(crate) fn readonly<'py, T: Element>(
    array: &Bound<'py, PyUntypedArray>,
    what: &str,
) -> PyResult<PyReadonlyArrayDyn<'py, T>> {
    let typed = array.downcast::<PyArrayDyn<T>>().map_err(|_| {
        PyTypeError::new_err(format!("{what}: unexpected dtype {}", dtype_name(array)))
    })?;
    typed
        .try_readonly()
        .map_err(|e| PyValueError::new_err(format!("{what}: {e}")))
}

/// `array` (already known to hold `T`) copied out in C order into a
/// buffer reserved first: too many elements are a `MemoryError`.
pub(crate) fn copy_c_order<T: Element + Copy>(
    array: &Bound<'_, PyUntypedArray>,
    what: &str,
) -> PyResult<Vec<T>> {
    let read = readonly::<T>(array, what)?;
    let view = read.as_array();
    let mut elements = try_vec(view.len(), what)?;
    // ndarray's `as_slice` is C order only (numpy's would accept Fortran
    // order too); otherwise ndarray iterates in logical (C) order.
    match view.as_slice() {
        Some(slice) => elements.extend_from_slice(slice),
        None => elements.extend(view.iter().copied()),
    }
    Ok(elements)
}

/// Elements read at a time from a view that is not C-contiguous.
const CHUNK: usize = 4096;

/// Calls `f` on consecutive chunks of `a` and `b` (of one shape) in C
/// order, equal chunks of each: the whole arrays at once when both are
/// C-contiguous, else [`CHUNK`] elements at a time through a small buffer,
/// so that a broadcast or strided view is never copied whole.
pub(crate) fn zip_chunks<T: Copy>(
    a: &ArrayViewD<'_, T>,
    b: &ArrayViewD<'_, T>,
    mut f: impl FnMut(&[T], &[T]) -> PyResult<()>,
) -> PyResult<()> {
    debug_assert_eq!(a.shape(), b.shape());
    if let (Some(a), Some(b)) = (a.as_slice(), b.as_slice()) {
        return f(a, b);
    }
    let (mut x, mut y) = (
        Vec::with_capacity(CHUNK.min(a.len())),
        Vec::with_capacity(CHUNK.min(a.len())),
    );
    for (&p, &q) in a.iter().zip(b.iter()) {
        x.push(p);
        y.push(q);
        if x.len() == CHUNK {
            f(&x, &y)?;
            x.clear();
            y.clear();
        }
    }
    if !x.is_empty() {
        f(&x, &y)?;
    }
    Ok(())
}
