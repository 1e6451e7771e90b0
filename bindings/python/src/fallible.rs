//! Allocations sized by input, made fallible: a buffer that cannot be
//! reserved is a `MemoryError` naming what it was for and how large it
//! was, never an abort of the interpreter (Rust's infallible allocation
//! aborts the process on failure). Every vector whose length comes from
//! an input array, a count or a file goes through [`try_vec`].

use pyo3::exceptions::PyMemoryError;
use pyo3::PyErr;

/// An empty vector with room for exactly `len` elements, or a
/// `MemoryError` naming `what` (e.g. `"alpha"`, `"index's result"`).
pub(crate) fn try_vec<T>(len: usize, what: &str) -> Result<Vec<T>, PyErr> {
    let mut v = Vec::new();
    v.try_reserve_exact(len)
        .map_err(|_| memory_error(what, len, std::mem::size_of::<T>()))?;
    Ok(v)
}

/// The `MemoryError` for `len` elements of `element_bytes` each.
pub(crate) fn memory_error(what: &str, len: usize, element_bytes: usize) -> PyErr {
    // u128: the product of two usizes never overflows it.
    let bytes = len as u128 * element_bytes as u128;
    PyMemoryError::new_err(format!(
        "{what}: cannot allocate {bytes} bytes ({len} elements of {element_bytes} bytes)"
    ))
}
