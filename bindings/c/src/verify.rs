//! The buffer validator (`micromap::read_buffers`) and the verifier of any
//! baker's buffers against a mesh (`bake::mesh::verify_mesh`, in bounded
//! memory: the caller's witnesses are kept, the rest counted).

use crate::bake::{mmi_bake_options, texture_unit};
use crate::constants::MMI_MODEL_GPU_BINARY32;
use crate::ffi::{
    guard, mmi_result, reference, slice, slice_mut, try_vec, write, Error, Result,
    MMI_ERROR_INVALID_ARGUMENT, MMI_ERROR_INVALID_ENUM, MMI_ERROR_LENGTH, MMI_ERROR_MALFORMED,
    MMI_ERROR_OUT_OF_MEMORY,
};
use crate::mesh::{mesh_error, mmi_mesh, MeshInput};
use micromap_index::bake::mesh::{verify_mesh, MeshOptions, MeshVerifyError};
use micromap_index::bake::{AlphaTexture, Contradiction};
use micromap_index::micromap::{
    read_buffers, BufferBytes, IndexWidth, MicromapError, MicromapIndex, Overlap, ReadBuffers,
    ReadError, ReadOptions, TriangleOpacity, TriangleRecord,
};

/// Micromap buffers in the caller's memory, in the API layouts (little
/// endian; records and indices tight or at the strides given).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct mmi_buffers_view {
    /// The packed micromap data.
    pub data: *const u8,
    /// Its length in bytes.
    pub data_len: usize,
    /// The 8-byte triangle records.
    pub records: *const u8,
    /// Their length in bytes (a multiple of 8 when tight; see
    /// `record_stride`).
    pub records_len: usize,
    /// The 12-byte usage counts, or NULL: not checked.
    pub usage_counts: *const u8,
    /// Their length in bytes.
    pub usage_counts_len: usize,
    /// One geometry's per-triangle index buffer, or NULL: none.
    pub indices: *const u8,
    /// Its length in bytes.
    pub indices_len: usize,
    /// The index width in bits: 8, 16 or 32 (ignored without indices).
    pub index_width_bits: u32,
    /// Bytes from one triangle record to the next (Vulkan's
    /// `triangleArrayStride`): 0 means 8 (tight); otherwise at least 8 and
    /// a multiple of 4 (`MMI_ERROR_INVALID_ARGUMENT` if not). The bytes
    /// between records are ignored; `records_len` covers whole strides or
    /// ends right after the last record (`MMI_ERROR_MALFORMED` if not).
    pub record_stride: usize,
    /// Bytes from one index to the next (Vulkan's `indexStride`): 0 means
    /// the index width (tight); otherwise a multiple of the width
    /// (`MMI_ERROR_INVALID_ARGUMENT` if not). The bytes between indices
    /// are ignored; `indices_len` covers whole strides or ends right after
    /// the last index (`MMI_ERROR_MALFORMED` if not). Ignored without
    /// indices.
    pub index_stride: usize,
}

/// Options of `mmi_validate_buffers` (`micromap::ReadOptions`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct mmi_read_options {
    /// Non-zero: records may share or overlap data, as long as their
    /// blocks total at most `max_decoded_bytes`; zero: blocks must be
    /// disjoint (the glTF draft's rule).
    pub allow_overlap: u32,
    /// The highest level accepted (at most 16; 12 for DXR).
    pub max_level: u32,
    /// Added to every regular index (Vulkan's `baseTriangle`).
    pub base_triangle: u32,
    /// Padding, 0.
    pub reserved: u32,
    /// With `allow_overlap`: the limit on the records' block sizes.
    pub max_decoded_bytes: u64,
}

/// What `mmi_validate_buffers` read.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct mmi_buffers_info {
    /// Triangle records.
    pub records: u64,
    /// Indices in the index buffer (0 without one).
    pub indices: u64,
    /// Indices that are special (-1..-4).
    pub special_indices: u64,
}

/// What `mmi_verify` found over all triangles.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct mmi_verify_report {
    /// Triangles in the mesh.
    pub triangles: u64,
    /// Triangles checked (finite coordinates on the exact grid).
    pub triangles_checked: u64,
    /// Known micro-triangles checked.
    pub known: u64,
    /// Unknown micro-triangles (never wrong).
    pub unknown: u64,
    /// Known micro-triangles the block budget could not decide.
    pub undecided: u64,
    /// Micro-triangles whose known state the texture contradicts (0: sound).
    pub contradictions: u64,
    /// Contradictions written to the caller's array (at most its capacity).
    pub witnesses_written: u64,
}

/// One contradiction: a micro-triangle whose known state the texture
/// contradicts, with an exact witness point.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct mmi_contradiction {
    /// The triangle.
    pub triangle: u64,
    /// The micro-triangle (0 for a special index).
    pub micro_triangle: u64,
    /// The state the buffers give it (`MMI_STATE_*`).
    pub state: u32,
    /// 1 if the witness fields hold a point, 0 if the exact point search
    /// gave up (the block search alone proved the contradiction).
    pub has_witness: u32,
    /// The witness's horizontal texel coordinate `x / 2^shift_x`, `x` a
    /// 128-bit two's complement number: high 64 bits.
    pub witness_x_hi: i64,
    /// Low 64 bits of `x`.
    pub witness_x_lo: u64,
    /// The vertical texel coordinate `y / 2^shift_y`: high 64 bits.
    pub witness_y_hi: i64,
    /// Low 64 bits of `y`.
    pub witness_y_lo: u64,
    /// The exponent of `x`'s denominator.
    pub witness_shift_x: u32,
    /// The exponent of `y`'s denominator.
    pub witness_shift_y: u32,
    /// The witness in texture coordinates, rounded to double.
    pub witness_u: f64,
    /// The witness's v.
    pub witness_v: f64,
    /// 1 if `texel_x`, `texel_y` name the texel of the other class, 0 if it
    /// is the border colour.
    pub has_texel: u32,
    /// The texel's column (after wrapping).
    pub texel_x: u32,
    /// The texel's row.
    pub texel_y: u32,
    /// Padding, 0.
    pub reserved: u32,
    /// The texel's alpha (or the border alpha).
    pub texel_alpha: f64,
}

fn width(bits: u32) -> Result<IndexWidth> {
    match bits {
        8 => Ok(IndexWidth::U8),
        16 => Ok(IndexWidth::U16),
        32 => Ok(IndexWidth::U32),
        other => Err(Error::new(
            MMI_ERROR_INVALID_ENUM,
            format!("index_width_bits {other}: expected 8, 16 or 32"),
        )),
    }
}

/// Reads the view's buffers at its strides (0: tight) under `options`,
/// whose strides are replaced; a stride the APIs do not allow is
/// `MMI_ERROR_INVALID_ARGUMENT` (`ReadOptions::check_strides`), checked
/// before any byte is read, a micromap whose copy cannot be allocated
/// `MMI_ERROR_OUT_OF_MEMORY`, and every other refusal
/// `MMI_ERROR_MALFORMED`.
///
/// # Safety
/// The view's pointers must each be NULL or point to their lengths in bytes.
unsafe fn read(view: &mmi_buffers_view, options: &ReadOptions) -> Result<ReadBuffers> {
    // SAFETY: the caller's promises about the view's arrays.
    let (data, records) = unsafe {
        (
            slice(view.data, view.data_len, "buffers.data")?,
            slice(view.records, view.records_len, "buffers.records")?,
        )
    };
    let usage_counts = if view.usage_counts.is_null() {
        None
    } else {
        // SAFETY: as above.
        Some(unsafe {
            slice(
                view.usage_counts,
                view.usage_counts_len,
                "buffers.usage_counts",
            )
        }?)
    };
    let indices = if view.indices.is_null() {
        None
    } else {
        // SAFETY: as above.
        let bytes = unsafe { slice(view.indices, view.indices_len, "buffers.indices") }?;
        Some((bytes, width(view.index_width_bits)?))
    };
    let options = ReadOptions {
        record_stride: match view.record_stride {
            0 => TriangleRecord::SIZE,
            stride => stride,
        },
        index_stride: (view.index_stride != 0).then_some(view.index_stride),
        ..*options
    };
    options
        .check_strides(indices.map(|(_, width)| width))
        .map_err(|e| Error::new(MMI_ERROR_INVALID_ARGUMENT, e.to_string()))?;
    read_buffers(
        &BufferBytes {
            records,
            data,
            usage_counts,
            indices,
        },
        &options,
    )
    .map_err(|e| {
        let code = match e {
            ReadError::Micromap {
                error: MicromapError::AllocationFailed { .. },
                ..
            } => MMI_ERROR_OUT_OF_MEMORY,
            _ => MMI_ERROR_MALFORMED,
        };
        Error::new(code, e.to_string())
    })
}

/// The validator's defaults: disjoint blocks, levels up to 16, base
/// triangle 0 (`micromap::ReadOptions::default`).
///
/// # Safety
/// `options` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_read_options_default(options: *mut mmi_read_options) -> mmi_result {
    guard(|| {
        let d = ReadOptions::default();
        let value = mmi_read_options {
            allow_overlap: 0,
            max_level: d.max_level,
            base_triangle: d.base_triangle,
            reserved: 0,
            max_decoded_bytes: 0,
        };
        // SAFETY: the caller's promise about `options`.
        unsafe { write(options, value, "options") }
    })
}

/// Checks untrusted micromap buffers as the APIs require
/// (`micromap::read_buffers`: record layout, formats and levels, blocks in
/// bounds and disjoint unless allowed, usage counts matching the records,
/// indices naming records or special, at the view's strides): `MMI_OK`,
/// or `MMI_ERROR_MALFORMED` with the first problem as the message;
/// `MMI_ERROR_INVALID_ARGUMENT` for a stride the APIs do not allow,
/// `MMI_ERROR_INVALID_ENUM` for an index width other than 8, 16, 32,
/// `MMI_ERROR_OUT_OF_MEMORY` when a decoded micromap cannot be allocated.
/// `options` may be NULL (the defaults); `info` may be NULL.
///
/// # Safety
/// `buffers` must be readable and its pointers satisfy `mmi_buffers_view`;
/// `options` NULL or readable; `info` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_validate_buffers(
    buffers: *const mmi_buffers_view,
    options: *const mmi_read_options,
    info: *mut mmi_buffers_info,
) -> mmi_result {
    guard(|| {
        // SAFETY: the caller's promise about `buffers`.
        let view = unsafe { reference(buffers, "buffers") }?;
        let options = if options.is_null() {
            ReadOptions::default()
        } else {
            // SAFETY: the caller's promise about `options`.
            let o = unsafe { reference(options, "options") }?;
            ReadOptions {
                overlap: if o.allow_overlap == 0 {
                    Overlap::Forbid
                } else {
                    Overlap::Allow {
                        max_decoded_bytes: o.max_decoded_bytes,
                    }
                },
                max_level: o.max_level,
                base_triangle: o.base_triangle,
                // The strides are the view's (`read`).
                ..ReadOptions::default()
            }
        };
        // SAFETY: forwarded.
        let read = unsafe { read(view, &options) }?;
        if !info.is_null() {
            let indices = read.indices.as_deref().unwrap_or_default();
            let value = mmi_buffers_info {
                records: read.records.len() as u64,
                indices: indices.len() as u64,
                special_indices: indices
                    .iter()
                    .filter(|i| matches!(i, MicromapIndex::Special(_)))
                    .count() as u64,
            };
            // SAFETY: the caller's promise about `info`.
            unsafe { write(info, value, "info") }?;
        }
        Ok(())
    })
}

/// Checks any baker's buffers (one geometry: data, records and an index
/// buffer with one index per triangle of `mesh`) against `mesh`, as
/// `micromap-index verify-bake` does (`bake::mesh::verify_mesh`), under
/// the default GPU binary32 model: `mmi_verify_with_model` with
/// `MMI_MODEL_GPU_BINARY32`.
///
/// # Safety
/// As `mmi_verify_with_model`.
#[no_mangle]
pub unsafe extern "C" fn mmi_verify(
    mesh: *const mmi_mesh,
    buffers: *const mmi_buffers_view,
    report: *mut mmi_verify_report,
    witnesses: *mut mmi_contradiction,
    witness_capacity: usize,
) -> mmi_result {
    // SAFETY: forwarded from the caller.
    unsafe {
        mmi_verify_with_model(
            mesh,
            buffers,
            MMI_MODEL_GPU_BINARY32,
            report,
            witnesses,
            witness_capacity,
        )
    }
}

/// A contradiction of `triangle` as C reads it: `texel_alpha` is the
/// texel's alpha as `texture` holds it (before the alpha factor and vertex
/// alpha), or `border_alpha` when the border was read.
fn contradiction(
    triangle: usize,
    c: &Contradiction,
    texture: &dyn AlphaTexture,
    border_alpha: f32,
) -> mmi_contradiction {
    let (width, height) = (texture.width(), texture.height());
    let (witness_u, witness_v) = c.witness.map_or((0.0, 0.0), |w| w.uv_f64(width, height));
    let w = c.witness;
    mmi_contradiction {
        triangle: triangle as u64,
        micro_triangle: c.micro_triangle,
        state: u32::from(c.state.bits()),
        has_witness: u32::from(w.is_some()),
        witness_x_hi: w.map_or(0, |w| (w.x >> 64) as i64),
        witness_x_lo: w.map_or(0, |w| w.x as u64),
        witness_y_hi: w.map_or(0, |w| (w.y >> 64) as i64),
        witness_y_lo: w.map_or(0, |w| w.y as u64),
        witness_shift_x: w.map_or(0, |w| w.shift_x),
        witness_shift_y: w.map_or(0, |w| w.shift_y),
        witness_u,
        witness_v,
        has_texel: u32::from(c.texel.is_some()),
        texel_x: c.texel.map_or(0, |p| p.0),
        texel_y: c.texel.map_or(0, |p| p.1),
        reserved: 0,
        texel_alpha: match c.texel {
            Some((x, y)) => texture.alpha(x, y),
            None => f64::from(border_alpha),
        },
    }
}

/// Checks any baker's buffers (one geometry: data, records and an index
/// buffer with one index per triangle of `mesh`) against `mesh` under
/// `model` (`MMI_MODEL_*`), as `micromap-index verify-bake --model` does
/// (`bake::mesh::verify_mesh`: texture, sampler, cutoff, alpha factor and
/// vertex alpha as `mmi_bake` models them): every known micro-triangle
/// whose closed area can read a texel of the other class is a
/// contradiction. Records may share data. The first `witness_capacity`
/// contradictions are written to `witnesses` (which may be NULL when the
/// capacity is 0); `report` counts them all, in memory that does not grow
/// with their number. Returns `MMI_OK` whether or not contradictions were
/// found (`report->contradictions` says); `MMI_ERROR_MALFORMED` for
/// buffers the validator refuses, `MMI_ERROR_INVALID_ARGUMENT` for a
/// stride the APIs do not allow (`mmi_buffers_view`), `MMI_ERROR_LENGTH`
/// when the index count is not the triangle count,
/// `MMI_ERROR_INVALID_ENUM` for an unknown model, a mesh `mmi_bake` would
/// refuse with `mmi_bake`'s code, `MMI_ERROR_OUT_OF_MEMORY` when memory
/// sized by the input cannot be had.
///
/// # Safety
/// `mesh` and `buffers` must be readable with pointers as their types
/// describe; `report` writable; `witnesses` NULL or `witness_capacity`
/// writable records.
#[no_mangle]
pub unsafe extern "C" fn mmi_verify_with_model(
    mesh: *const mmi_mesh,
    buffers: *const mmi_buffers_view,
    model: u32,
    report: *mut mmi_verify_report,
    witnesses: *mut mmi_contradiction,
    witness_capacity: usize,
) -> mmi_result {
    guard(|| {
        let judge = MeshOptions {
            model: crate::mesh::model(model)?,
            ..MeshOptions::default()
        };
        // SAFETY: forwarded from the caller.
        unsafe { verify_with(mesh, buffers, &judge, report, witnesses, witness_capacity) }
    })
}

/// [`mmi_verify_with_model`] judged by `options` as `mmi_bake` would bake
/// with them: the model, the texture unit and the block budget (the other
/// fields are not read).
///
/// # Safety
/// As `mmi_verify_with_model`; `options` readable.
#[no_mangle]
pub unsafe extern "C" fn mmi_verify_with_options(
    mesh: *const mmi_mesh,
    buffers: *const mmi_buffers_view,
    options: *const mmi_bake_options,
    report: *mut mmi_verify_report,
    witnesses: *mut mmi_contradiction,
    witness_capacity: usize,
) -> mmi_result {
    guard(|| {
        // SAFETY: the caller's promise about `options`.
        let o = unsafe { reference(options, "options") }?;
        let judge = MeshOptions {
            model: crate::mesh::model(o.model)?,
            texture_unit: texture_unit(o)?,
            block_budget: if o.block_budget == 0 {
                micromap_index::bake::DEFAULT_BLOCK_BUDGET
            } else {
                o.block_budget
            },
            ..MeshOptions::default()
        };
        // SAFETY: forwarded from the caller.
        unsafe { verify_with(mesh, buffers, &judge, report, witnesses, witness_capacity) }
    })
}

/// The body of the verify functions, judged by `judge`.
///
/// # Safety
/// As `mmi_verify_with_model`.
unsafe fn verify_with(
    mesh: *const mmi_mesh,
    buffers: *const mmi_buffers_view,
    judge: &MeshOptions,
    report: *mut mmi_verify_report,
    witnesses: *mut mmi_contradiction,
    witness_capacity: usize,
) -> Result<()> {
    // SAFETY: the caller's promises about the pointers.
    let (mesh, view, witnesses) = unsafe {
        (
            reference(mesh, "mesh")?,
            reference(buffers, "buffers")?,
            slice_mut(witnesses, witness_capacity, "witnesses")?,
        )
    };
    if report.is_null() {
        return Err(crate::ffi::null("report"));
    }
    if view.indices.is_null() {
        return Err(crate::ffi::null("buffers.indices"));
    }
    // SAFETY: the caller's promises about the mesh's pointers.
    let input = unsafe { MeshInput::read(mesh) }?;
    let texture = input.texture()?;
    let options = ReadOptions {
        overlap: Overlap::Allow {
            max_decoded_bytes: 1 << 32,
        },
        ..ReadOptions::default()
    };
    // SAFETY: forwarded.
    let read = unsafe { self::read(view, &options) }?;
    let indices = read.indices.unwrap_or_default();
    let mut opacities = try_vec(indices.len(), "the triangles' opacities")?;
    for index in &indices {
        opacities.push(match *index {
            // `read_buffers` checked that every record index names one.
            MicromapIndex::Record(r) => {
                TriangleOpacity::Micromap(read.micromaps.get(r as usize).ok_or_else(|| {
                    Error::new(MMI_ERROR_MALFORMED, format!("index {r} names no record"))
                })?)
            }
            MicromapIndex::Special(state) => TriangleOpacity::Special(state),
        });
    }
    let border_alpha = input.material.sampler.border_alpha;
    let mut written = 0;
    let verified = verify_mesh(
        &input.mesh(&*texture),
        &opacities,
        judge,
        u64::MAX,
        &mut |t, c| {
            if let Some(slot) = witnesses.get_mut(written) {
                *slot = contradiction(t, &c, &*texture, border_alpha);
                written += 1;
            }
        },
    );
    let v = verified.map_err(|e| match e {
        MeshVerifyError::Count {
            opacities,
            triangles,
        } => Error::new(
            MMI_ERROR_LENGTH,
            format!("the buffers have {opacities} indices for {triangles} triangles"),
        ),
        MeshVerifyError::Mesh(e) => mesh_error(&e),
        other => Error::new(MMI_ERROR_INVALID_ARGUMENT, other.to_string()),
    })?;
    let out = mmi_verify_report {
        triangles: opacities.len() as u64,
        triangles_checked: v.triangles_checked as u64,
        known: v.known,
        unknown: v.unknown,
        undecided: v.undecided,
        contradictions: v.contradictions,
        witnesses_written: written as u64,
    };
    // SAFETY: checked non-null; the caller's promise that it is writable.
    unsafe { write(report, out, "report") }
}
