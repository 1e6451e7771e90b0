//! Conversions at the host's edges: a failed call's `vk::Result` into
//! [`RenderError`], the driver's fixed-size strings into text, version
//! words into `major.minor.patch`.

use crate::error::RenderError;
use ash::vk;
use std::ffi::{CStr, FromBytesUntilNulError};

/// The error of the Vulkan call `call` that returned `result`.
pub(crate) fn failed(call: &'static str) -> impl Fn(vk::Result) -> RenderError {
    move |result| RenderError::Vulkan { call, result }
}

/// The driver's string, or `?` where it has no terminating NUL.
pub(crate) fn text(c: Result<&CStr, FromBytesUntilNulError>) -> String {
    c.map_or_else(|_| "?".into(), |c| c.to_string_lossy().into_owned())
}

/// A Vulkan version word as `major.minor.patch`.
pub(crate) fn version_text(v: u32) -> String {
    format!(
        "{}.{}.{}",
        vk::api_version_major(v),
        vk::api_version_minor(v),
        vk::api_version_patch(v)
    )
}
