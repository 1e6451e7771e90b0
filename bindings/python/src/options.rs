//! Keyword options as the library's types, parsed by the library's own
//! `FromStr` (names, levels) so that Python accepts exactly the CLI's
//! spellings; every bad value is a `ValueError` reading
//! `<keyword> <value>: <the library's message>`.

use micromap_index::bake::mesh::Mips;
use micromap_index::bake::{
    bake_level as library_bake_level, AddressMode, Comparison, Cutoff, Filter, Model, Sampler,
    TextureUnit, Threads, UvTransform,
};
use micromap_index::micromap::{Format, IndexWidth, UnknownPolicy};
use micromap_index::names::ParseNameError;
use micromap_index::Level;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

pub(crate) fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// `text` as the library's `T`, or `<keyword> "text": expected ...`.
fn named<T: std::str::FromStr<Err = ParseNameError>>(keyword: &str, text: &str) -> PyResult<T> {
    text.parse()
        .map_err(|e| value_error(format!("{keyword} {text:?}: {e}")))
}

pub(crate) fn filter(name: &str) -> PyResult<Filter> {
    named("filter", name)
}

pub(crate) fn address(name: &str) -> PyResult<AddressMode> {
    named("address", name)
}

pub(crate) fn unknown(name: &str) -> PyResult<UnknownPolicy> {
    named("unknown", name)
}

pub(crate) fn model(name: &str) -> PyResult<Model> {
    named("model", name)
}

/// The texture unit from `subtexel_bits`, `interpolation`, `filter_error`
/// and `linear` (`--subtexel-bits`, `--interpolation`, `--filter-error`,
/// `--linear`), checked by the library.
pub(crate) fn texture_unit(
    subtexel_bits: i64,
    interpolation: &str,
    filter_error: f32,
    linear: &str,
) -> PyResult<TextureUnit> {
    let bits = u32::try_from(subtexel_bits)
        .map_err(|_| value_error(format!("subtexel_bits {subtexel_bits}: expected 4..=16")))?;
    TextureUnit::default()
        .with_subtexel_bits(bits)
        .with_interpolation(named("interpolation", interpolation)?)
        .with_filter_error(filter_error)
        .with_linear_rule(named("linear", linear)?)
        .check()
        .map_err(value_error)
}

/// `format`: the int 2 or 4, as `--format` reads its text.
pub(crate) fn format(value: i64) -> PyResult<Format> {
    value
        .to_string()
        .parse()
        .map_err(|e| value_error(format!("format {value}: {e}")))
}

/// `mips`: an int `>= 0` (as `--mips N`) or `"all"`.
pub(crate) fn mips(obj: &Bound<'_, PyAny>) -> PyResult<Mips> {
    if let Ok(text) = obj.extract::<String>() {
        return named("mips", &text);
    }
    match obj.extract::<i64>() {
        // The library reads digits only: a negative int is refused there.
        Ok(n) => n
            .to_string()
            .parse()
            .map_err(|e| value_error(format!("mips {n}: {e}"))),
        Err(_) => Err(PyTypeError::new_err(
            "mips must be an int (a mip level) or \"all\"",
        )),
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
/// `uv_transform=(offset, rotation, scale)` (glTF's
/// `KHR_texture_transform`, applied by the shader to the interpolated
/// coordinate), or the identity for `None`: a `ValueError` for values
/// `UvTransform::new` refuses.
pub(crate) fn uv_transform(value: Option<([f32; 2], f32, [f32; 2])>) -> PyResult<UvTransform> {
    match value {
        None => Ok(UvTransform::IDENTITY),
        Some((offset, rotation, scale)) => UvTransform::new(offset, rotation, scale)
            .map_err(|e| value_error(format!("uv_transform: {e}"))),
    }
}

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

/// A bake level: `bake::bake_level`'s range, in its words.
pub(crate) fn bake_level(value: i64, what: &str) -> PyResult<Level> {
    let level = u32::try_from(value).unwrap_or(u32::MAX);
    library_bake_level(level).map_err(|e| value_error(format!("{what} {value}: {e}")))
}

/// The library's words for the bake level range ("expected a level
/// 0..=12 (...)"), from its own refusal.
fn range_words() -> String {
    library_bake_level(u32::MAX)
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default()
}

/// `level`: an int in `bake_level`'s range, or `"auto"` (`None`).
pub(crate) fn level_or_auto(obj: &Bound<'_, PyAny>) -> PyResult<Option<Level>> {
    if let Ok(text) = obj.extract::<String>() {
        return if text == "auto" {
            Ok(None)
        } else {
            Err(value_error(format!(
                "level {text:?}: {} or \"auto\"",
                range_words()
            )))
        };
    }
    match obj.extract::<i64>() {
        Ok(level) => bake_level(level, "level").map(Some),
        Err(_) => Err(PyTypeError::new_err(format!(
            "level must be an int ({}) or \"auto\"",
            range_words()
        ))),
    }
}

/// `index_width`: 16 or 32 bits (`--index-width` also takes 8, which the
/// signed `indices` arrays of `BakeResult` cannot show: records 128..=250
/// would read as negative).
pub(crate) fn index_width(bits: i64) -> PyResult<IndexWidth> {
    match bits {
        16 => Ok(IndexWidth::U16),
        32 => Ok(IndexWidth::U32),
        other => Err(value_error(format!(
            "index_width {other}: expected 16 or 32 (the widths Vulkan accepts)"
        ))),
    }
}

/// `threads`: `None` every core, else a count `>= 1` (as `--threads`).
pub(crate) fn threads(value: Option<i64>) -> PyResult<Threads> {
    match value {
        None => Ok(Threads::All),
        Some(n) => usize::try_from(n)
            .ok()
            .filter(|&n| n >= 1)
            .map(Threads::Exactly)
            .ok_or_else(|| {
                value_error(format!(
                    "threads {n}: expected a number of threads, at least 1"
                ))
            }),
    }
}

/// A count or byte budget: an int `>= 0`.
pub(crate) fn count(value: i64, what: &str) -> PyResult<u64> {
    u64::try_from(value).map_err(|_| value_error(format!("{what} {value}: expected a count >= 0")))
}
