//! The arrays `bake` and `verify` take, checked before anything is copied
//! (dtype, shape, the library's texture dimension rule), then copied out
//! in C order into fallibly reserved buffers: the calls release the GIL,
//! so nothing borrowed from Python is read while they work.
//!
//! - `alpha`: a 2-D `uint8` (unorm8), `uint16` (unorm16) or `float32`
//!   array of shape `(height, width)`; row 0 is the image's top row
//!   (`v = 0`), as the PNG reader returns it.
//! - `uvs`: a `float32` array of shape `(N, 3, 2)`, triangle `t`'s vertex
//!   `i` at `uvs[t, i]`.

use crate::arrays::{copy_c_order, dtype_name, has_dtype, readonly, untyped};
use crate::fallible::try_vec;
use crate::options::value_error;
use micromap_index::bake::{
    AlphaTexture, F32Texture, TextureError, Unorm16Texture, Unorm8Texture, UvTriangle,
};
use numpy::{PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// An alpha array's texels, owned, by dtype.
pub(crate) enum Texels {
    U8(Vec<u8>),
    U16(Vec<u16>),
    F32(Vec<f32>),
}

/// A 2-D alpha array, copied: its width, height and texels.
pub(crate) struct Alpha {
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) texels: Texels,
}

/// The element types `alpha` may have.
#[derive(Clone, Copy)]
enum AlphaType {
    U8,
    U16,
    F32,
}

/// A checked, not yet copied, alpha array.
pub(crate) struct AlphaArray<'a, 'py> {
    array: &'a Bound<'py, PyUntypedArray>,
    kind: AlphaType,
    width: u32,
    height: u32,
}

impl<'a, 'py> AlphaArray<'a, 'py> {
    /// `obj` checked: its dtype, a 2-D shape, and the library's dimension
    /// rule (not empty, under 2^32 texels), so that an array too large for
    /// any texture is refused before it is copied.
    pub(crate) fn new(obj: &'a Bound<'py, PyAny>) -> PyResult<Self> {
        let array = untyped(obj, "alpha")?;
        let kind = if has_dtype::<u8>(array) {
            AlphaType::U8
        } else if has_dtype::<u16>(array) {
            AlphaType::U16
        } else if has_dtype::<f32>(array) {
            AlphaType::F32
        } else {
            return Err(PyTypeError::new_err(format!(
                "alpha must have dtype uint8, uint16 or float32, not {}",
                dtype_name(array)
            )));
        };
        let shape = array.shape();
        let &[height, width] = shape else {
            return Err(PyValueError::new_err(format!(
                "alpha must be 2-D (height, width), not of shape {shape:?}"
            )));
        };
        let dimension = |n: usize, what: &str| {
            u32::try_from(n)
                .map_err(|_| value_error(format!("alpha's {what} {n} is over 2^32 - 1")))
        };
        let (width, height) = (dimension(width, "width")?, dimension(height, "height")?);
        // The texture constructor's own checks, on no texels: only the
        // length can then be wrong, and that is not the array's fault.
        match Unorm8Texture::new(width, height, &[]) {
            Ok(_) | Err(TextureError::WrongLength { .. }) => {}
            Err(e) => return Err(value_error(format!("alpha: {e}"))),
        }
        Ok(AlphaArray {
            array,
            kind,
            width,
            height,
        })
    }

    /// The texels copied out (a `MemoryError` when they do not fit).
    pub(crate) fn copy(&self) -> PyResult<Alpha> {
        let texels = match self.kind {
            AlphaType::U8 => Texels::U8(copy_c_order(self.array, "alpha")?),
            AlphaType::U16 => Texels::U16(copy_c_order(self.array, "alpha")?),
            AlphaType::F32 => Texels::F32(copy_c_order(self.array, "alpha")?),
        };
        Ok(Alpha {
            width: self.width,
            height: self.height,
            texels,
        })
    }
}

impl Alpha {
    /// The library's view of the texels.
    pub(crate) fn texture(&self) -> Result<Box<dyn AlphaTexture + '_>, TextureError> {
        let (w, h) = (self.width, self.height);
        Ok(match &self.texels {
            Texels::U8(t) => Box::new(Unorm8Texture::new(w, h, t)?),
            Texels::U16(t) => Box::new(Unorm16Texture::new(w, h, t)?),
            Texels::F32(t) => Box::new(F32Texture::new(w, h, t)?),
        })
    }
}

/// A checked, not yet copied, `uvs` array.
pub(crate) struct UvArray<'a, 'py> {
    array: &'a Bound<'py, PyUntypedArray>,
    len: usize,
}

impl<'a, 'py> UvArray<'a, 'py> {
    /// `obj` checked: dtype float32, shape `(N, 3, 2)`.
    pub(crate) fn new(obj: &'a Bound<'py, PyAny>) -> PyResult<Self> {
        let array = untyped(obj, "uvs")?;
        if !has_dtype::<f32>(array) {
            return Err(PyTypeError::new_err(format!(
                "uvs must have dtype float32 (the UVs a GPU interpolates), not {}",
                dtype_name(array)
            )));
        }
        let shape = array.shape();
        if shape.len() != 3 || shape[1] != 3 || shape[2] != 2 {
            return Err(PyValueError::new_err(format!(
                "uvs must have shape (N, 3, 2), not {shape:?}"
            )));
        }
        Ok(UvArray {
            array,
            len: shape[0],
        })
    }

    /// The number of triangles, `N`.
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    /// The triangles copied out (a `MemoryError` when they do not fit).
    pub(crate) fn copy(&self) -> PyResult<Vec<UvTriangle>> {
        let read = readonly::<f32>(self.array, "uvs")?;
        let view = read.as_array();
        let mut triangles: Vec<UvTriangle> = try_vec(self.len, "uvs")?;
        let triangle = |c: &[f32]| [[c[0], c[1]], [c[2], c[3]], [c[4], c[5]]];
        if let Some(slice) = view.as_slice() {
            triangles.extend(slice.chunks_exact(6).map(triangle));
            return Ok(triangles);
        }
        // In C order: u0 v0 u1 v1 u2 v2 per triangle.
        let mut six = [0f32; 6];
        for (i, &x) in view.iter().enumerate() {
            six[i % 6] = x;
            if i % 6 == 5 {
                triangles.push(triangle(&six));
            }
        }
        Ok(triangles)
    }
}
