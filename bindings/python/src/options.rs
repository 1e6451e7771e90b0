//! Keyword options as the library's types; names as the CLI's flags
//! (`micromap-index bake --help`), every bad value a `ValueError` naming
//! what was expected.

use micromap_index::bake::{AddressMode, Comparison, Cutoff, Filter, Model, Sampler};
use micromap_index::micromap::{Format, IndexWidth, UnknownPolicy};
use micromap_index::Level;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

pub(crate) fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

pub(crate) fn filter(name: &str) -> PyResult<Filter> {
    match name {
        "nearest" => Ok(Filter::Nearest),
        "linear" => Ok(Filter::Linear),
        other => Err(value_error(format!(
            "filter {other:?}: expected \"nearest\" or \"linear\""
        ))),
    }
}

pub(crate) fn address(name: &str) -> PyResult<AddressMode> {
    Ok(match name {
        "repeat" => AddressMode::Repeat,
        "mirrored-repeat" => AddressMode::MirroredRepeat,
        "clamp-to-edge" => AddressMode::ClampToEdge,
        "clamp-to-border" => AddressMode::ClampToBorder,
        "mirror-clamp-to-edge" => AddressMode::MirrorClampToEdge,
        other => {
            return Err(value_error(format!(
                "address mode {other:?}: expected repeat, mirrored-repeat, clamp-to-edge, \
                 clamp-to-border or mirror-clamp-to-edge"
            )))
        }
    })
}

pub(crate) fn address_name(mode: AddressMode) -> &'static str {
    match mode {
        AddressMode::Repeat => "repeat",
        AddressMode::MirroredRepeat => "mirrored-repeat",
        AddressMode::ClampToEdge => "clamp-to-edge",
        AddressMode::ClampToBorder => "clamp-to-border",
        AddressMode::MirrorClampToEdge => "mirror-clamp-to-edge",
    }
}

/// `address`: one mode for both axes, or a `(u, v)` pair.
pub(crate) fn address_pair(obj: &Bound<'_, PyAny>) -> PyResult<(AddressMode, AddressMode)> {
    if let Ok(name) = obj.extract::<String>() {
        let mode = address(&name)?;
        return Ok((mode, mode));
    }
    if let Ok((u, v)) = obj.extract::<(String, String)>() {
        return Ok((address(&u)?, address(&v)?));
    }
    Err(PyTypeError::new_err(
        "address must be a mode name or a (u, v) pair of mode names",
    ))
}

/// The sampler; `border_alpha` must be finite (as `--border`).
pub(crate) fn sampler(
    filter: Filter,
    (address_u, address_v): (AddressMode, AddressMode),
    border_alpha: f32,
) -> PyResult<Sampler> {
    Ok(Sampler {
        filter,
        address_u,
        address_v,
        border_alpha: border(border_alpha)?,
    })
}

/// The clamp-to-border alpha, finite (as `--border`).
pub(crate) fn border(value: f32) -> PyResult<f32> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(value_error(format!(
            "border_alpha {value}: expected a finite number"
        )))
    }
}

/// The cutoff rule: `alpha >= cutoff` (glTF's), or `alpha > cutoff` with
/// `opaque_above`; `cutoff` in `[0, 1]` (as `--cutoff`).
pub(crate) fn cutoff(value: f32, opaque_above: bool) -> PyResult<Cutoff> {
    if !(0.0..=1.0).contains(&value) {
        return Err(value_error(format!(
            "cutoff {value}: expected an alpha in [0, 1]"
        )));
    }
    let comparison = if opaque_above {
        Comparison::Above
    } else {
        Comparison::AtLeast
    };
    Cutoff::new(value, comparison).map_err(value_error)
}

pub(crate) fn model(name: &str) -> PyResult<Model> {
    name.parse().map_err(|e| value_error(format!("model {name:?}: {e}")))
}

pub(crate) fn format(value: i64) -> PyResult<Format> {
    match value {
        2 => Ok(Format::TwoState),
        4 => Ok(Format::FourState),
        other => Err(value_error(format!("format {other}: expected 2 or 4"))),
    }
}

pub(crate) fn format_number(format: Format) -> u32 {
    match format {
        Format::TwoState => 2,
        Format::FourState => 4,
    }
}

pub(crate) fn unknown(name: &str) -> PyResult<UnknownPolicy> {
    match name {
        "fallback" => Ok(UnknownPolicy::Fallback),
        "opaque" => Ok(UnknownPolicy::Opaque),
        "transparent" => Ok(UnknownPolicy::Transparent),
        other => Err(value_error(format!(
            "unknown {other:?}: expected \"fallback\", \"opaque\" or \"transparent\""
        ))),
    }
}

/// A bake level 0..=16.
pub(crate) fn bake_level(value: i64, what: &str) -> PyResult<Level> {
    u32::try_from(value)
        .ok()
        .filter(|&l| l <= 16)
        .and_then(|l| Level::new(l).ok())
        .ok_or_else(|| value_error(format!("{what} {value}: expected a level 0..=16")))
}

/// `level`: an int 0..=16, or `"auto"` (`None`).
pub(crate) fn level_or_auto(obj: &Bound<'_, PyAny>) -> PyResult<Option<Level>> {
    if let Ok(text) = obj.extract::<String>() {
        return if text == "auto" {
            Ok(None)
        } else {
            Err(value_error(format!(
                "level {text:?}: expected a level 0..=16 or \"auto\""
            )))
        };
    }
    match obj.extract::<i64>() {
        Ok(level) => bake_level(level, "level").map(Some),
        Err(_) => Err(PyTypeError::new_err(
            "level must be an int 0..=16 or \"auto\"",
        )),
    }
}

pub(crate) fn index_width(bits: i64) -> PyResult<IndexWidth> {
    match bits {
        16 => Ok(IndexWidth::U16),
        32 => Ok(IndexWidth::U32),
        other => Err(value_error(format!(
            "index_width {other}: expected 16 or 32 (the widths Vulkan accepts)"
        ))),
    }
}

/// A count or byte budget: an int `>= 0`.
pub(crate) fn count(value: i64, what: &str) -> PyResult<u64> {
    u64::try_from(value).map_err(|_| value_error(format!("{what} {value}: expected a count >= 0")))
}
