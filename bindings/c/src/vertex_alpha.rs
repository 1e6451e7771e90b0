//! A mesh's per-vertex alpha (glTF's `COLOR_0` alpha) gathered into the
//! library's form: three alphas per triangle, in the triangles' order.

use crate::bake::mmi_mesh;
use crate::ffi::{slice, Error, Result, MMI_ERROR_INVALID_ARGUMENT, MMI_ERROR_LENGTH};

/// The alphas of each triangle's three vertices, or `None` when
/// `vertex_alpha` is NULL (alpha 1). Vertex `i`'s alpha is the float at
/// byte `i * vertex_alpha_stride` (0 means 4); the corners are those of
/// the triangles (`indices`, or `3t..3t + 3` without them). Values outside
/// `[0, 1]` are left to the library, which refuses them.
///
/// # Safety
/// `m.vertex_alpha` must be NULL or point to `vertex_count` vertices of
/// `vertex_alpha_stride` bytes (the last one at least 4); `m.indices` to
/// `index_count` `uint32_t`.
pub(crate) unsafe fn vertex_alphas(m: &mmi_mesh) -> Result<Option<Vec<[f32; 3]>>> {
    if m.vertex_alpha.is_null() {
        return Ok(None);
    }
    let stride_bytes = match m.vertex_alpha_stride {
        0 => 4,
        s => s,
    };
    if stride_bytes % 4 != 0 {
        return Err(Error::new(
            MMI_ERROR_INVALID_ARGUMENT,
            format!("vertex_alpha_stride {stride_bytes}: expected a multiple of 4"),
        ));
    }
    let stride = stride_bytes / 4;
    let floats = match m.vertex_count {
        0 => 0,
        n => (n - 1)
            .checked_mul(stride)
            .and_then(|f| f.checked_add(1))
            .ok_or_else(|| {
                Error::new(MMI_ERROR_LENGTH, "the vertex alphas do not fit in memory")
            })?,
    };
    // SAFETY: the caller's promise about `vertex_alpha`.
    let alphas = unsafe { slice(m.vertex_alpha, floats, "vertex_alpha") }?;
    let alpha = |i: usize| -> Result<f32> {
        if i >= m.vertex_count {
            return Err(Error::new(
                MMI_ERROR_INVALID_ARGUMENT,
                format!("index {i} names no vertex"),
            ));
        }
        Ok(alphas[i * stride])
    };
    let corners: Vec<usize> = if m.indices.is_null() {
        (0..m.vertex_count - m.vertex_count % 3).collect()
    } else {
        // SAFETY: the caller's promise about `indices`.
        let indices = unsafe { slice(m.indices, m.index_count, "indices") }?;
        indices.iter().map(|&i| i as usize).collect()
    };
    corners
        .chunks_exact(3)
        .map(|c| Ok([alpha(c[0])?, alpha(c[1])?, alpha(c[2])?]))
        .collect::<Result<Vec<_>>>()
        .map(Some)
}
