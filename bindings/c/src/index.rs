//! The index function (`spec`, `batch`) and its inverse (`inverse`).

use crate::ffi::{guard, mmi_result, slice, slice_mut, write, Error, Result};
use crate::ffi::{MMI_ERROR_INVALID_ARGUMENT, MMI_ERROR_INVALID_LEVEL};
use micromap_index::{batch, inverse, spec, Level, SpecLevel};

fn spec_level(level: u32) -> Result<SpecLevel> {
    SpecLevel::new(level).map_err(|e| Error::new(MMI_ERROR_INVALID_LEVEL, e.to_string()))
}

fn level(level: u32) -> Result<Level> {
    Level::new(level).map_err(|e| Error::new(MMI_ERROR_INVALID_LEVEL, e.to_string()))
}

/// The micro-triangle index of the point `(u, v)` at `level` (0..=16), as
/// the Vulkan reference computes it in binary32 (every `float` pair,
/// NaN and points outside the triangle included: `spec::index_f32`).
///
/// # Safety
/// `out` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_index_f32(u: f32, v: f32, level: u32, out: *mut u32) -> mmi_result {
    guard(|| {
        let level = spec_level(level)?;
        // SAFETY: the caller's promise about `out`.
        unsafe { write(out, spec::index_f32(u, v, level), "out") }
    })
}

/// `out[i] = mmi_index_f32(us[i], vs[i], level)` for `i < count`, by the
/// library's batch kernels (`batch::index_f32`, the fastest backend of this
/// CPU). With `count == 0` the pointers may be NULL. On an error nothing is
/// written.
///
/// # Safety
/// `us` and `vs` must be NULL or point to `count` floats, `out` to `count`
/// writable `uint32_t` not overlapping them.
#[no_mangle]
pub unsafe extern "C" fn mmi_index_f32_batch(
    us: *const f32,
    vs: *const f32,
    count: usize,
    level: u32,
    out: *mut u32,
) -> mmi_result {
    guard(|| {
        let level = spec_level(level)?;
        // SAFETY: the caller's promises about the three arrays.
        let (us, vs, out) = unsafe {
            (
                slice(us, count, "us")?,
                slice(vs, count, "vs")?,
                slice_mut(out, count, "out")?,
            )
        };
        batch::index_f32(us, vs, level, out)
            .map_err(|e| Error::new(MMI_ERROR_INVALID_ARGUMENT, e.to_string()))
    })
}

/// The reference widened to 64-bit words (`spec::wide_index_f32`): levels
/// 0..=32; equal to `mmi_index_f32` for levels 0..=16.
///
/// # Safety
/// `out` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_wide_index_f32(
    u: f32,
    v: f32,
    level: u32,
    out: *mut u64,
) -> mmi_result {
    guard(|| {
        let level = self::level(level)?;
        // SAFETY: the caller's promise about `out`.
        unsafe { write(out, spec::wide_index_f32(u, v, level), "out") }
    })
}

/// `out[i] = mmi_wide_index_f32(us[i], vs[i], level)` by the batch kernels
/// (`batch::wide_index_f32`).
///
/// # Safety
/// As `mmi_index_f32_batch`, with `out` holding `count` `uint64_t`.
#[no_mangle]
pub unsafe extern "C" fn mmi_wide_index_f32_batch(
    us: *const f32,
    vs: *const f32,
    count: usize,
    level: u32,
    out: *mut u64,
) -> mmi_result {
    guard(|| {
        let level = self::level(level)?;
        // SAFETY: the caller's promises about the three arrays.
        let (us, vs, out) = unsafe {
            (
                slice(us, count, "us")?,
                slice(vs, count, "vs")?,
                slice_mut(out, count, "out")?,
            )
        };
        batch::wide_index_f32(us, vs, level, out)
            .map_err(|e| Error::new(MMI_ERROR_INVALID_ARGUMENT, e.to_string()))
    })
}

/// One micro-triangle, exactly: its vertices as `(u, v)` numerators over
/// `2^level`, in the walk's local order.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct mmi_micro_triangle {
    /// The subdivision level.
    pub level: u32,
    /// 1 if it has the base triangle's orientation, 0 if upside down.
    pub upright: u32,
    /// Its index on the space-filling curve.
    pub index: u64,
    /// `u0, v0, u1, v1, u2, v2`, each over `2^level`.
    pub vertices: [u64; 6],
}

/// The micro-triangle with `index` at `level` (0..=32;
/// `inverse::micro_triangle`): `MMI_ERROR_INVALID_LEVEL` above 32,
/// `MMI_ERROR_INVALID_ARGUMENT` for an index `>= 4^level`.
///
/// # Safety
/// `out` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_inverse_micro_triangle(
    level: u32,
    index: u64,
    out: *mut mmi_micro_triangle,
) -> mmi_result {
    guard(|| {
        let level = self::level(level)?;
        let t = inverse::micro_triangle(level, index)
            .map_err(|e| Error::new(MMI_ERROR_INVALID_ARGUMENT, e.to_string()))?;
        let v = t.vertices_scaled();
        let value = mmi_micro_triangle {
            level: t.level().get(),
            upright: u32::from(t.upright()),
            index: t.index(),
            vertices: [v[0].0, v[0].1, v[1].0, v[1].1, v[2].0, v[2].1],
        };
        // SAFETY: the caller's promise about `out`.
        unsafe { write(out, value, "out") }
    })
}
