//! Evaluating any variant on parsed values: the engine behind the CLI's
//! `eval` command (JSON lines in, JSON lines out), kept in the library so it
//! is tested, fuzzed and reusable.
//!
//! ```
//! use micromap_index::eval::{eval_line, Variant};
//! let out = eval_line(Variant::SpecF32, r#"{"u": "0x3e800000", "v": "0.25", "level": 1}"#);
//! assert_eq!(out, r#"{"index":1}"#);
//! let out = eval_line(Variant::Uv2indexExact, r#"{"u": "2/3", "v": "1/2", "level": 3}"#);
//! assert_eq!(out, r#"{"error":"point is outside the triangle: u + v > 1"}"#);
//! ```

use crate::value::{Value, ValueError};
use crate::{fixed, spec, uv2index, Error, Level};
use serde::Deserialize;
use std::fmt;

/// The implementations the CLI can evaluate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Variant {
    /// [`spec::index_f32_checked`]: the Vulkan reference in binary32.
    SpecF32,
    /// [`spec::index_exact`]: the reference's steps over the reals.
    SpecExact,
    /// [`uv2index::index_exact`]: the walk over the reals.
    Uv2indexExact,
    /// [`uv2index::index_f32`]: the walk in binary32.
    Uv2indexF32,
    /// [`uv2index::index_f64`]: the walk in binary64.
    Uv2indexF64,
    /// [`fixed::index_f64`]: the walk on fixed-point integers, exact for every
    /// finite float input (binary32 or binary64 values).
    FixedExact,
    /// [`spec::index_wide_exact`]: the reference's steps over the reals with
    /// 64-bit words, levels 0..=32.
    SpecWide,
    /// [`spec::index_wide_f32`]: the reference's steps in binary32 with
    /// 64-bit words, levels 0..=32.
    SpecWideF32,
    /// [`fixed::index_mirror_f32_checked`]: the reference in binary32,
    /// reproduced with integer operations only.
    FixedMirror,
}

impl Variant {
    /// Every variant, in the order the CLI lists them.
    pub const ALL: [Variant; 9] = [
        Variant::SpecF32,
        Variant::SpecExact,
        Variant::Uv2indexExact,
        Variant::Uv2indexF32,
        Variant::Uv2indexF64,
        Variant::FixedExact,
        Variant::SpecWide,
        Variant::SpecWideF32,
        Variant::FixedMirror,
    ];

    /// The variant's CLI name.
    pub fn name(self) -> &'static str {
        match self {
            Variant::SpecF32 => "spec-f32",
            Variant::SpecExact => "spec-exact",
            Variant::Uv2indexExact => "uv2index-exact",
            Variant::Uv2indexF32 => "uv2index-f32",
            Variant::Uv2indexF64 => "uv2index-f64",
            Variant::FixedExact => "fixed-exact",
            Variant::SpecWide => "spec-wide",
            Variant::SpecWideF32 => "spec-wide-f32",
            Variant::FixedMirror => "fixed-mirror",
        }
    }

    /// The variant with that CLI name.
    pub fn from_name(name: &str) -> Option<Variant> {
        Variant::ALL.into_iter().find(|v| v.name() == name)
    }

    /// The index of `(u, v)` at `level` under this variant.
    ///
    /// ```
    /// use micromap_index::eval::Variant;
    /// use micromap_index::value::Value;
    /// let half = Value::parse("1/2").unwrap();
    /// let zero = Value::parse("0").unwrap();
    /// assert_eq!(Variant::SpecExact.evaluate(&half, &zero, 1), Ok(2));
    /// assert!(Variant::SpecF32.evaluate(&half, &zero, 17).is_err());
    /// ```
    pub fn evaluate(self, u: &Value, v: &Value, level: u64) -> Result<u64, EvalError> {
        let level = u32::try_from(level).map_err(|_| {
            EvalError::Malformed(format!("level {level} is too high: levels go up to 32"))
        })?;
        let level = Level::new(level)?;
        let index = match self {
            Variant::SpecF32 => {
                u64::from(spec::index_f32_checked(u.to_f32()?, v.to_f32()?, level)?)
            }
            Variant::SpecExact => {
                u64::from(spec::index_exact(&u.to_exact()?, &v.to_exact()?, level)?)
            }
            Variant::Uv2indexExact => uv2index::index_exact(&u.to_exact()?, &v.to_exact()?, level)?,
            Variant::Uv2indexF32 => uv2index::index_f32(u.to_f32()?, v.to_f32()?, level)?,
            Variant::Uv2indexF64 => uv2index::index_f64(u.to_f64()?, v.to_f64()?, level)?,
            Variant::FixedExact => fixed::index_f64(u.to_f64()?, v.to_f64()?, level)?,
            Variant::SpecWide => spec::index_wide_exact(&u.to_exact()?, &v.to_exact()?, level),
            Variant::SpecWideF32 => spec::index_wide_f32(u.to_f32()?, v.to_f32()?, level),
            Variant::FixedMirror => u64::from(fixed::index_mirror_f32_checked(
                u.to_f32()?,
                v.to_f32()?,
                level,
            )?),
        };
        Ok(index)
    }
}

impl fmt::Display for Variant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Why one input could not be evaluated.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EvalError {
    /// The line is not a JSON object with string `u`, `v` and integer `level`.
    Malformed(String),
    /// A coordinate could not be parsed or converted.
    Value(ValueError),
    /// The function rejected the input.
    Input(Error),
}

impl fmt::Display for EvalError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EvalError::Malformed(why) => write!(f, "malformed input line: {why}"),
            EvalError::Value(e) => e.fmt(f),
            EvalError::Input(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for EvalError {}

impl From<ValueError> for EvalError {
    fn from(e: ValueError) -> Self {
        EvalError::Value(e)
    }
}

impl From<Error> for EvalError {
    fn from(e: Error) -> Self {
        EvalError::Input(e)
    }
}

#[derive(Deserialize)]
struct InputLine {
    u: String,
    v: String,
    level: u64,
}

/// Evaluates one JSON input line `{"u": U, "v": V, "level": L}` and returns
/// the output line (without newline): `{"index": N}` or `{"error": "..."}`.
/// Never panics; every problem becomes an error line.
pub fn eval_line(variant: Variant, line: &str) -> String {
    // serde would also read a struct from a JSON array (`["0.5", "0", 1]`);
    // the input format is an object, so anything else is malformed.
    let result = if line.trim_start().starts_with('{') {
        serde_json::from_str::<InputLine>(line).map_err(|e| EvalError::Malformed(e.to_string()))
    } else {
        Err(EvalError::Malformed("expected a JSON object".into()))
    }
    .and_then(|input| {
        let u = Value::parse(&input.u)?;
        let v = Value::parse(&input.v)?;
        variant.evaluate(&u, &v, input.level)
    });
    match result {
        Ok(index) => format!("{{\"index\":{index}}}"),
        Err(e) => serde_json::json!({ "error": e.to_string() }).to_string(),
    }
}

/// [`eval_line`] on raw bytes: a line that is not UTF-8 yields an error
/// line instead of being guessed at.
pub fn eval_line_bytes(variant: Variant, line: &[u8]) -> String {
    match std::str::from_utf8(line) {
        Ok(text) => eval_line(variant, text),
        Err(e) => serde_json::json!({ "error": format!("malformed input line: not UTF-8 ({e})") })
            .to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for variant in Variant::ALL {
            assert_eq!(Variant::from_name(variant.name()), Some(variant));
        }
        assert_eq!(Variant::from_name("spec"), None);
    }

    #[test]
    fn bad_lines_become_error_lines() {
        for line in [
            "",
            "{",
            "[]",
            r#"{"u": 0.5, "v": "0", "level": 1}"#,
            r#"{"u": "0.5", "v": "0", "level": -1}"#,
            r#"{"u": "0.5", "v": "0", "level": 99999999999999999999}"#,
            r#"{"u": "0.5", "v": "0", "level": 99999999999}"#,
            r#"{"u": "0.5", "v": "0"}"#,
            r#"["0x3f000000", "0x3e800000", 1]"#,
        ] {
            let out = eval_line(Variant::SpecF32, line);
            assert!(
                out.starts_with(r#"{"error":"malformed input line"#),
                "{line:?} -> {out}"
            );
        }
        let out = eval_line(Variant::SpecF32, r#"{"u": "0.1", "v": "0", "level": 1}"#);
        assert_eq!(
            out,
            r#"{"error":"1/10 is not exactly representable as f32"}"#
        );
        let out = eval_line(
            Variant::Uv2indexExact,
            r#"{"u": "0x7fc00000", "v": "0", "level": 1}"#,
        );
        assert_eq!(
            out,
            r#"{"error":"0x7fc00000 is not a real number (NaN or infinite)"}"#
        );
        let out = eval_line(
            Variant::Uv2indexExact,
            r#"{"u": "0", "v": "0", "level": 33}"#,
        );
        assert_eq!(
            out,
            r#"{"error":"level 33 is too high: this function supports levels 0..=32"}"#
        );
        let out = eval_line(
            Variant::SpecF32,
            r#"{"u": "0x7fc00000", "v": "0", "level": 16}"#,
        );
        assert_eq!(out, r#"{"index":0}"#);
    }
}
