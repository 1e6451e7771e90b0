//! Evaluating any variant on parsed values: the engine behind the CLI's
//! `eval` command (JSON lines in, JSON lines out), kept in the library so it
//! is tested, fuzzed and reusable.
//!
//! ```
//! use micromap_index_conformance::eval::{eval_line, Variant};
//! let out = eval_line(Variant::SpecF32, r#"{"u": "0x3e800000", "v": "0.25", "level": 1}"#);
//! assert_eq!(out, r#"{"index":1}"#);
//! let out = eval_line(Variant::WalkReal, r#"{"u": "2/3", "v": "1/2", "level": 3}"#);
//! assert_eq!(out, r#"{"error":"point is outside the triangle: u + v > 1"}"#);
//! ```

use crate::value::{Value, ValueError};
use micromap_index::{spec, uv2index, Error, Level, SpecLevel};
use serde::Deserialize;
use serde_json::value::RawValue;
use std::fmt;

/// The implementations the CLI can evaluate. Each CLI name says the
/// guarantee, like the library function it calls; the names of earlier
/// releases stay accepted as aliases ([`Variant::from_name`]), so published
/// vectors and scripts keep working.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Variant {
    /// `spec-f32`, [`spec::index_f32`]: the Vulkan reference in binary32, the
    /// GPU's bits.
    SpecF32,
    /// `spec-f32-by-integers` (was `fixed-mirror`),
    /// [`spec::index_f32_by_integers`]: the same bits with integers only.
    SpecF32ByIntegers,
    /// `spec-real` (was `spec-exact`), [`spec::index_real`]: the reference's
    /// steps over the reals.
    SpecReal,
    /// `spec-wide-f32`, [`spec::wide_index_f32`]: the reference's steps in
    /// binary32 with 64-bit words, levels 0..=32.
    SpecWideF32,
    /// `spec-wide-real` (was `spec-wide`), [`spec::wide_index_real`]: the
    /// reference's steps over the reals with 64-bit words, levels 0..=32.
    SpecWideReal,
    /// `walk-real` (was `uv2index-exact`), [`uv2index::index_real`]: the walk
    /// over the reals.
    WalkReal,
    /// `walk-exact-float` (was `fixed-exact`), [`uv2index::exact_index_f64`]:
    /// the walk's exact answer for every finite float input (binary32 or
    /// binary64 values), with integers only.
    WalkExactFloat,
    /// `walk-f32-arithmetic` (was `uv2index-f32`),
    /// [`uv2index::index_in_f32_arithmetic`]: the walk evaluated in binary32;
    /// not exact.
    WalkF32Arithmetic,
    /// `walk-f64-arithmetic` (was `uv2index-f64`),
    /// [`uv2index::index_in_f64_arithmetic`]: the walk evaluated in binary64;
    /// not exact.
    WalkF64Arithmetic,
}

impl Variant {
    /// Every variant, in the order the CLI lists them.
    pub const ALL: [Variant; 9] = [
        Variant::SpecF32,
        Variant::SpecF32ByIntegers,
        Variant::SpecReal,
        Variant::SpecWideF32,
        Variant::SpecWideReal,
        Variant::WalkReal,
        Variant::WalkExactFloat,
        Variant::WalkF32Arithmetic,
        Variant::WalkF64Arithmetic,
    ];

    /// The variant's CLI name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Variant::SpecF32 => "spec-f32",
            Variant::SpecF32ByIntegers => "spec-f32-by-integers",
            Variant::SpecReal => "spec-real",
            Variant::SpecWideF32 => "spec-wide-f32",
            Variant::SpecWideReal => "spec-wide-real",
            Variant::WalkReal => "walk-real",
            Variant::WalkExactFloat => "walk-exact-float",
            Variant::WalkF32Arithmetic => "walk-f32-arithmetic",
            Variant::WalkF64Arithmetic => "walk-f64-arithmetic",
        }
    }

    /// The name earlier releases used, if it differs from [`Variant::name`];
    /// still accepted by [`Variant::from_name`] and written in the published
    /// vector files' `function` fields.
    #[must_use]
    pub fn legacy_name(self) -> Option<&'static str> {
        match self {
            Variant::SpecF32 | Variant::SpecWideF32 => None,
            Variant::SpecF32ByIntegers => Some("fixed-mirror"),
            Variant::SpecReal => Some("spec-exact"),
            Variant::SpecWideReal => Some("spec-wide"),
            Variant::WalkReal => Some("uv2index-exact"),
            Variant::WalkExactFloat => Some("fixed-exact"),
            Variant::WalkF32Arithmetic => Some("uv2index-f32"),
            Variant::WalkF64Arithmetic => Some("uv2index-f64"),
        }
    }

    /// The variant with that CLI name, or that legacy name.
    ///
    /// ```
    /// use micromap_index_conformance::eval::Variant;
    /// assert_eq!(Variant::from_name("spec-real"), Some(Variant::SpecReal));
    /// assert_eq!(Variant::from_name("spec-exact"), Some(Variant::SpecReal));
    /// assert_eq!(Variant::from_name("spec"), None);
    /// ```
    #[must_use]
    pub fn from_name(name: &str) -> Option<Variant> {
        Variant::ALL
            .into_iter()
            .find(|v| v.name() == name || v.legacy_name() == Some(name))
    }

    /// The highest level the variant supports: 16 for the 32-bit reference,
    /// 32 otherwise.
    #[must_use]
    pub fn max_level(self) -> u32 {
        match self {
            Variant::SpecF32 | Variant::SpecF32ByIntegers | Variant::SpecReal => SpecLevel::MAX,
            _ => Level::MAX,
        }
    }

    /// The index of `(u, v)` at `level` under this variant.
    ///
    /// ```
    /// use micromap_index_conformance::eval::Variant;
    /// use micromap_index_conformance::value::Value;
    /// let half = Value::parse("1/2").unwrap();
    /// let zero = Value::parse("0").unwrap();
    /// assert_eq!(Variant::SpecReal.evaluate(&half, &zero, 1), Ok(2));
    /// assert!(Variant::SpecF32.evaluate(&half, &zero, 17).is_err());
    /// ```
    pub fn evaluate(self, u: &Value, v: &Value, level: u64) -> Result<u64, EvalError> {
        let max = self.max_level();
        let level = u32::try_from(level)
            .ok()
            .filter(|&level| level <= max)
            .ok_or(EvalError::LevelTooHigh {
                variant: self,
                level,
            })?;
        let spec_level = || SpecLevel::new(level);
        let level = Level::new(level)?;
        let index = match self {
            Variant::SpecF32 => u64::from(spec::index_f32(u.to_f32()?, v.to_f32()?, spec_level()?)),
            Variant::SpecF32ByIntegers => u64::from(spec::index_f32_by_integers(
                u.to_f32()?,
                v.to_f32()?,
                spec_level()?,
            )),
            Variant::SpecReal => u64::from(spec::index_real(
                &u.to_exact()?,
                &v.to_exact()?,
                spec_level()?,
            )),
            Variant::SpecWideF32 => spec::wide_index_f32(u.to_f32()?, v.to_f32()?, level),
            Variant::SpecWideReal => spec::wide_index_real(&u.to_exact()?, &v.to_exact()?, level),
            Variant::WalkReal => uv2index::index_real(&u.to_exact()?, &v.to_exact()?, level)?,
            Variant::WalkExactFloat => uv2index::exact_index_f64(u.to_f64()?, v.to_f64()?, level)?,
            Variant::WalkF32Arithmetic => {
                uv2index::index_in_f32_arithmetic(u.to_f32()?, v.to_f32()?, level)?
            }
            Variant::WalkF64Arithmetic => {
                uv2index::index_in_f64_arithmetic(u.to_f64()?, v.to_f64()?, level)?
            }
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
    /// The line's `level` is a JSON number that is not an integer in
    /// `0..=u64::MAX` (negative, fractional, or larger): not a level of any
    /// variant.
    LevelNotAnInteger {
        /// The variant asked for.
        variant: Variant,
        /// The number as written (shortened if long).
        text: String,
    },
    /// The level is above what the variant supports.
    LevelTooHigh {
        /// The variant asked for.
        variant: Variant,
        /// The level asked for.
        level: u64,
    },
}

impl fmt::Display for EvalError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EvalError::Malformed(why) => write!(f, "malformed input line: {why}"),
            EvalError::Value(e) => e.fmt(f),
            EvalError::Input(e) => e.fmt(f),
            EvalError::LevelNotAnInteger { variant, text } => write!(
                f,
                "level {text} is not an integer in 0..={}, the levels {variant} supports",
                variant.max_level()
            ),
            EvalError::LevelTooHigh { variant, level } => write!(
                f,
                "level {level} is too high: {variant} supports levels 0..={}",
                variant.max_level()
            ),
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
    /// Read as written: serde would turn `18446744073709551616` into a
    /// float and report "invalid type: floating point".
    level: Box<RawValue>,
}

/// The line's `level` (its JSON text): digits that fit a `u64`, or an
/// error that says what it is.
fn parse_level(variant: Variant, raw: &RawValue) -> Result<u64, EvalError> {
    let text = raw.get().trim();
    if !text.is_empty() && text.bytes().all(|b| b.is_ascii_digit()) {
        if let Ok(level) = text.parse::<u64>() {
            return Ok(level);
        }
    }
    let mut shown: String = text.chars().take(40).collect();
    if shown.len() < text.len() {
        shown.push('…');
    }
    if text.starts_with(|c: char| c == '-' || c.is_ascii_digit()) {
        Err(EvalError::LevelNotAnInteger {
            variant,
            text: shown,
        })
    } else {
        Err(EvalError::Malformed(format!(
            "level must be an integer, got {shown}"
        )))
    }
}

/// Evaluates one JSON input line `{"u": U, "v": V, "level": L}` and returns
/// the output line (without newline): `{"index": N}` or `{"error": "..."}`.
/// Never panics; every problem becomes an error line.
#[must_use]
pub fn eval_line(variant: Variant, line: &str) -> String {
    // serde would also read a struct from a JSON array (`["0.5", "0", 1]`);
    // the input format is an object, so anything else is malformed.
    let result = if line.trim_start().starts_with('{') {
        serde_json::from_str::<InputLine>(line).map_err(|e| EvalError::Malformed(e.to_string()))
    } else {
        Err(EvalError::Malformed("expected a JSON object".into()))
    }
    .and_then(|input| {
        let level = parse_level(variant, &input.level)?;
        let u = Value::parse(&input.u)?;
        let v = Value::parse(&input.v)?;
        variant.evaluate(&u, &v, level)
    });
    match result {
        Ok(index) => format!("{{\"index\":{index}}}"),
        Err(e) => serde_json::json!({ "error": e.to_string() }).to_string(),
    }
}

/// [`eval_line`] on raw bytes: a line that is not UTF-8 yields an error
/// line instead of being guessed at.
#[must_use]
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
            r#"{"u": "0.5", "v": "0"}"#,
            r#"{"u": "0.5", "v": "0", "level": "3"}"#,
            r#"{"u": "0.5", "v": "0", "level": null}"#,
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
            Variant::WalkReal,
            r#"{"u": "0x7fc00000", "v": "0", "level": 1}"#,
        );
        assert_eq!(
            out,
            r#"{"error":"0x7fc00000 is not a real number (NaN or infinite)"}"#
        );
        let out = eval_line(Variant::WalkReal, r#"{"u": "0", "v": "0", "level": 33}"#);
        assert_eq!(
            out,
            r#"{"error":"level 33 is too high: walk-real supports levels 0..=32"}"#
        );
        let out = eval_line(
            Variant::SpecF32,
            r#"{"u": "0", "v": "0", "level": 99999999999}"#,
        );
        assert_eq!(
            out,
            r#"{"error":"level 99999999999 is too high: spec-f32 supports levels 0..=16"}"#
        );
        let out = eval_line(
            Variant::SpecF32,
            r#"{"u": "0x7fc00000", "v": "0", "level": 16}"#,
        );
        assert_eq!(out, r#"{"index":0}"#);
    }

    /// Issue 9: a level that is not a `u64` said "invalid type: floating
    /// point"; a level above 16 for spec-f32 said "supports levels 0..=32".
    #[test]
    fn level_messages_name_the_variants_range() {
        let line = |level: &str| format!(r#"{{"u": "0", "v": "0", "level": {level}}}"#);
        for (variant, level, message) in [
            (
                Variant::SpecF32,
                "33",
                "level 33 is too high: spec-f32 supports levels 0..=16",
            ),
            (
                Variant::SpecF32,
                "17",
                "level 17 is too high: spec-f32 supports levels 0..=16",
            ),
            (
                Variant::SpecF32,
                "18446744073709551616",
                "level 18446744073709551616 is not an integer in 0..=16, the levels spec-f32 supports",
            ),
            (
                Variant::WalkReal,
                "18446744073709551615",
                "level 18446744073709551615 is too high: walk-real supports levels 0..=32",
            ),
            (
                Variant::WalkReal,
                "-1",
                "level -1 is not an integer in 0..=32, the levels walk-real supports",
            ),
            (
                Variant::WalkReal,
                "1.5",
                "level 1.5 is not an integer in 0..=32, the levels walk-real supports",
            ),
            (
                Variant::SpecWideReal,
                "1e400",
                "level 1e400 is not an integer in 0..=32, the levels spec-wide-real supports",
            ),
        ] {
            let out = eval_line(variant, &line(level));
            let expected = serde_json::json!({ "error": message }).to_string();
            assert_eq!(out, expected, "{variant} at level {level}");
        }
        assert_eq!(eval_line(Variant::SpecF32, &line("16")), r#"{"index":0}"#);
        assert_eq!(eval_line(Variant::WalkReal, &line("32")), r#"{"index":0}"#);
    }
}
