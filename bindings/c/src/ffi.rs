//! The boundary itself: result codes, the thread's last error message, the
//! panic guard, and the checked conversions of C pointers to Rust
//! references and slices (the only `unsafe` of the crate besides the
//! handle frees).

use core::ffi::c_char;
use std::cell::RefCell;
use std::ffi::CString;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// A status code: [`MMI_OK`] or one of the `MMI_ERROR_*` codes.
pub type mmi_result = i32;

/// Success.
pub const MMI_OK: mmi_result = 0;
/// A pointer that must not be null was null.
pub const MMI_ERROR_NULL_POINTER: mmi_result = 1;
/// A subdivision level outside the range the function takes.
pub const MMI_ERROR_INVALID_LEVEL: mmi_result = 2;
/// A `uint32_t` enum value that names no case.
pub const MMI_ERROR_INVALID_ENUM: mmi_result = 3;
/// Lengths that disagree or are not a whole number of items, or a pointer
/// not aligned for its type.
pub const MMI_ERROR_LENGTH: mmi_result = 4;
/// The caller's output buffer is too short; the required length was
/// written where the function says.
pub const MMI_ERROR_BUFFER_TOO_SMALL: mmi_result = 5;
/// A value out of its range (an index past the end, a NaN cutoff, an empty
/// texture, a stride below 8 bytes, an index width the buffers cannot use).
pub const MMI_ERROR_INVALID_ARGUMENT: mmi_result = 6;
/// Bytes refused by the buffer validator or the tree reader.
pub const MMI_ERROR_MALFORMED: mmi_result = 7;
/// The bake failed in the library (its message says why).
pub const MMI_ERROR_BAKE: mmi_result = 8;
/// A combination this version does not support.
pub const MMI_ERROR_UNSUPPORTED: mmi_result = 9;
/// A Rust panic was caught at the boundary (a bug: please report it).
pub const MMI_ERROR_PANIC: mmi_result = 10;
/// Memory sized by the input could not be had (the allocator refused, or
/// the size does not fit the address space); nothing was kept.
pub const MMI_ERROR_OUT_OF_MEMORY: mmi_result = 11;
/// The output may exceed a limit the caller sets
/// (`mmi_bake_options::max_bytes`); nothing was baked.
pub const MMI_ERROR_LIMIT: mmi_result = 12;

/// A failure: its code and message.
#[derive(Debug)]
pub(crate) struct Error {
    pub(crate) code: mmi_result,
    pub(crate) message: String,
}

impl Error {
    pub(crate) fn new(code: mmi_result, message: impl Into<String>) -> Error {
        Error {
            code,
            message: message.into(),
        }
    }
}

pub(crate) type Result<T> = core::result::Result<T, Error>;

/// `MMI_ERROR_NULL_POINTER` naming the argument.
pub(crate) fn null(name: &str) -> Error {
    Error::new(MMI_ERROR_NULL_POINTER, format!("{name} is NULL"))
}

/// An empty vector with room for `len` items, or
/// [`MMI_ERROR_OUT_OF_MEMORY`] naming `what`: the one way this crate
/// allocates memory sized by its input.
pub(crate) fn try_vec<T>(len: usize, what: &str) -> Result<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(len)
        .map_err(|_| out_of_memory(len, size_of::<T>(), what))?;
    Ok(v)
}

/// [`MMI_ERROR_OUT_OF_MEMORY`] for `len` items of `size` bytes.
pub(crate) fn out_of_memory(len: usize, size: usize, what: &str) -> Error {
    let bytes = (len as u128) * (size as u128);
    Error::new(
        MMI_ERROR_OUT_OF_MEMORY,
        format!("cannot allocate {bytes} bytes for {what}"),
    )
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_last_error(message: &str) {
    let text = CString::new(message.replace('\0', " ")).unwrap_or_default();
    LAST_ERROR.with(|last| *last.borrow_mut() = text);
}

/// Runs `body` at the boundary: its error becomes the code and the thread's
/// last message; a panic becomes [`MMI_ERROR_PANIC`]; success clears the
/// message.
pub(crate) fn guard(body: impl FnOnce() -> Result<()>) -> mmi_result {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => {
            set_last_error("");
            MMI_OK
        }
        Ok(Err(e)) => {
            set_last_error(&e.message);
            e.code
        }
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| (*s).to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown payload".into());
            set_last_error(&format!("panic caught at the C boundary: {what}"));
            MMI_ERROR_PANIC
        }
    }
}

/// The message of the last failed call on this thread (`""` after a call
/// that succeeded). The pointer stays valid until the next `mmi_` call on
/// this thread; never NULL.
#[no_mangle]
pub extern "C" fn mmi_last_error_message() -> *const c_char {
    catch_unwind(|| LAST_ERROR.with(|last| last.borrow().as_ptr()))
        .unwrap_or(c"panic while reading the last error".as_ptr())
}

/// The crate version as `major * 10000 + minor * 100 + patch`, to compare
/// with the header's `MICROMAP_INDEX_VERSION`.
#[no_mangle]
pub extern "C" fn mmi_version() -> u32 {
    let part = |s: &str| s.parse::<u32>().unwrap_or(0);
    part(env!("CARGO_PKG_VERSION_MAJOR")) * 10000
        + part(env!("CARGO_PKG_VERSION_MINOR")) * 100
        + part(env!("CARGO_PKG_VERSION_PATCH"))
}

/// The crate version as a static NUL-terminated string, e.g. `"0.1.0"`.
#[no_mangle]
pub extern "C" fn mmi_version_string() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr().cast()
}

/// Checks a pointer and a count for a slice of `T`.
fn check_slice<T>(ptr: *const T, len: usize, name: &str) -> Result<()> {
    if ptr.is_null() {
        return Err(null(name));
    }
    if !ptr.is_aligned() {
        return Err(Error::new(
            MMI_ERROR_LENGTH,
            format!("{name} is not aligned to {} bytes", align_of::<T>()),
        ));
    }
    if len
        .checked_mul(size_of::<T>())
        .map_or(true, |b| b > isize::MAX as usize)
    {
        return Err(Error::new(
            MMI_ERROR_LENGTH,
            format!("{name}: {len} items do not fit in memory"),
        ));
    }
    Ok(())
}

/// `len` items at `ptr` as a slice; an empty slice when `len == 0` (then
/// `ptr` may be NULL).
///
/// # Safety
/// Unless `len == 0`, `ptr` must be NULL or point to `len` initialised `T`
/// that stay unchanged and unaliased by writes for `'a`.
pub(crate) unsafe fn slice<'a, T>(ptr: *const T, len: usize, name: &str) -> Result<&'a [T]> {
    if len == 0 {
        return Ok(&[]);
    }
    check_slice(ptr, len, name)?;
    // SAFETY: `ptr` is non-null and aligned (checked), the size fits
    // `isize` (checked), and the caller promises `len` initialised items.
    Ok(unsafe { core::slice::from_raw_parts(ptr, len) })
}

/// `len` writable items at `ptr`; empty when `len == 0`.
///
/// # Safety
/// Unless `len == 0`, `ptr` must be NULL or point to `len` writable `T`
/// not otherwise accessed for `'a`.
pub(crate) unsafe fn slice_mut<'a, T>(ptr: *mut T, len: usize, name: &str) -> Result<&'a mut [T]> {
    if len == 0 {
        return Ok(&mut []);
    }
    check_slice(ptr, len, name)?;
    // SAFETY: as in `slice`, and the caller promises exclusive access.
    Ok(unsafe { core::slice::from_raw_parts_mut(ptr, len) })
}

/// The `T` at `ptr`.
///
/// # Safety
/// `ptr` must be NULL or point to an initialised `T` valid for `'a`.
pub(crate) unsafe fn reference<'a, T>(ptr: *const T, name: &str) -> Result<&'a T> {
    check_slice(ptr, 1, name)?;
    // SAFETY: non-null and aligned (checked); the caller promises a `T`.
    Ok(unsafe { &*ptr })
}

/// Writes `value` to `ptr`.
///
/// # Safety
/// `ptr` must be NULL or point to writable memory for a `T`.
pub(crate) unsafe fn write<T>(ptr: *mut T, value: T, name: &str) -> Result<()> {
    check_slice(ptr, 1, name)?;
    // SAFETY: non-null and aligned (checked); the caller promises the
    // memory is writable. `write` does not read or drop the old value.
    unsafe { ptr.write(value) };
    Ok(())
}

/// Copies `bytes` into the caller's buffer in the sizes-queried-first
/// style: `*len` receives `bytes.len()`; with `out == NULL` nothing else
/// happens (a size query); otherwise `capacity` must be at least the
/// length ([`MMI_ERROR_BUFFER_TOO_SMALL`]).
///
/// # Safety
/// `out` must be NULL or point to `capacity` writable bytes; `len` must be
/// NULL or writable.
pub(crate) unsafe fn copy_out(
    bytes: &[u8],
    out: *mut u8,
    capacity: usize,
    len: *mut usize,
    name: &str,
) -> Result<()> {
    // SAFETY: forwarded from the caller's promise about `len`.
    unsafe { write(len, bytes.len(), "len") }?;
    if out.is_null() {
        return Ok(());
    }
    if capacity < bytes.len() {
        return Err(Error::new(
            MMI_ERROR_BUFFER_TOO_SMALL,
            format!(
                "{name} needs {} bytes, the buffer holds {capacity}",
                bytes.len()
            ),
        ));
    }
    // SAFETY: forwarded from the caller's promise about `out`.
    let target = unsafe { slice_mut(out, bytes.len(), name) }?;
    target.copy_from_slice(bytes);
    Ok(())
}

/// Returns a pointer and length to memory owned by a handle.
///
/// # Safety
/// `ptr` and `len` must each be NULL or writable.
pub(crate) unsafe fn lend(bytes: &[u8], ptr: *mut *const u8, len: *mut usize) -> Result<()> {
    if ptr.is_null() {
        return Err(null("data"));
    }
    if len.is_null() {
        return Err(null("len"));
    }
    // SAFETY: both checked non-null; the caller promises they are writable.
    unsafe {
        write(ptr, bytes.as_ptr(), "data")?;
        write(len, bytes.len(), "len")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_becomes_its_code_and_message() {
        let code = guard(|| panic!("on purpose"));
        assert_eq!(code, MMI_ERROR_PANIC);
        // SAFETY: the pointer is the thread's message, valid until the next call.
        let message = unsafe { core::ffi::CStr::from_ptr(mmi_last_error_message()) };
        assert_eq!(
            message.to_str().unwrap(),
            "panic caught at the C boundary: on purpose"
        );
        assert_eq!(guard(|| Ok(())), MMI_OK);
        // SAFETY: as above.
        let message = unsafe { core::ffi::CStr::from_ptr(mmi_last_error_message()) };
        assert!(message.is_empty());
    }

    #[test]
    fn versions_agree() {
        // SAFETY: a static NUL-terminated string.
        let text = unsafe { core::ffi::CStr::from_ptr(mmi_version_string()) };
        assert_eq!(text.to_str().unwrap(), env!("CARGO_PKG_VERSION"));
        let minor: u32 = env!("CARGO_PKG_VERSION_MINOR").parse().unwrap();
        assert_eq!(mmi_version() / 100 % 100, minor);
    }
}
