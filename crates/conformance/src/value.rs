//! The value syntax shared by the CLI and the conformance vectors.
//!
//! A coordinate is written as a string in one of three forms:
//!
//! * `0x` and exactly 8 hex digits: the bits of an IEEE binary32 value
//!   (`"0x3f000000"` is 0.5; NaN, infinities and `-0` can be written);
//! * `0x` and exactly 16 hex digits: the bits of a binary64 value;
//! * an exact decimal (`"0.375"`, `"-1.5e-3"`) or rational (`"3/8"`,
//!   `"-3/8"`): a real number, with no rounding anywhere.
//!
//! [`Value::to_f32`] and [`Value::to_f64`] accept a value only if it is
//! exactly representable in that type, so a float variant never evaluates a
//! rounded input; NaN and infinities convert between the float types (their
//! payloads do not matter to any function here). [`Value::to_exact`] rejects
//! NaN and infinities, which are not real numbers.
//!
//! # Size limits
//!
//! Exact values cost time with their size (parsing, reducing, and every
//! step of an exact walk multiply big integers), so their size is bounded;
//! a value over a limit is a [`ValueError::OverLimit`] that names the limit:
//!
//! * at most [`MAX_VALUE_LEN`] (20,000) characters in all;
//! * a decimal: at most [`MAX_DECIMAL_DIGITS`] (4096) digits, and an
//!   exponent of at most [`MAX_DECIMAL_EXPONENT`] (4096) in magnitude
//!   (`"1e999999999"` is over the exponent limit);
//! * a rational `p/q` (or a plain integer): at most [`MAX_RATIONAL_DIGITS`]
//!   (8200) digits in `p` and in `q`.
//!
//! Within these limits one `eval` line at level 32 costs milliseconds for
//! every variant (see `docs/cli.md` for measured times).
//!
//! ```
//! use micromap_index_conformance::value::Value;
//! assert_eq!(Value::parse("0x3f000000").unwrap().to_f32(), Ok(0.5));
//! assert_eq!(Value::parse("3/8").unwrap().to_f64(), Ok(0.375));
//! assert!(Value::parse("0.1").unwrap().to_f32().is_err()); // not a binary32 value
//! assert!(Value::parse("0.5x").is_err());
//! ```

use num_bigint::{BigInt, Sign};
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};
use std::fmt;

/// Longest accepted value text: bounds the cost of exact parsing. Large
/// enough for the canonical text ([`Value`]'s `Display`) of every value
/// [`Value::parse`] accepts, so that text always parses back.
pub const MAX_VALUE_LEN: usize = 20_000;
/// Most digits in a decimal's significand (`whole` and `fraction` together).
pub const MAX_DECIMAL_DIGITS: usize = 4096;
/// Largest accepted decimal exponent magnitude (`1e-4096` is fine,
/// `1e-99999` is not).
pub const MAX_DECIMAL_EXPONENT: u32 = 4096;
/// Most digits in a rational's numerator or denominator. A decimal within
/// the two limits above reduces to at most `4096 + 4096 + 1` digits on
/// either side, so its canonical `p/q` text is accepted again.
pub const MAX_RATIONAL_DIGITS: usize = 8200;

/// A parsed coordinate.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Value {
    /// The bits of a binary32 value.
    F32Bits(u32),
    /// The bits of a binary64 value.
    F64Bits(u64),
    /// An exact rational number.
    Exact(BigRational),
}

/// Why a value could not be parsed or converted.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ValueError {
    /// The text is not in any of the accepted forms.
    Syntax(String),
    /// The value is not exactly representable in the float type.
    NotRepresentable {
        /// The text of the value as given.
        value: String,
        /// `"f32"` or `"f64"`.
        float: &'static str,
    },
    /// NaN or an infinity where a real number is needed.
    NotReal(String),
    /// The value is well formed but over one of the size limits (see the
    /// module docs); the message names the limit.
    OverLimit(String),
}

impl fmt::Display for ValueError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ValueError::Syntax(why) | ValueError::OverLimit(why) => f.write_str(why),
            ValueError::NotRepresentable { value, float } => {
                write!(f, "{value} is not exactly representable as {float}")
            }
            ValueError::NotReal(value) => {
                write!(f, "{value} is not a real number (NaN or infinite)")
            }
        }
    }
}

impl std::error::Error for ValueError {}

impl Value {
    /// Parses one value (see the module docs for the forms).
    pub fn parse(text: &str) -> Result<Value, ValueError> {
        let syntax = |why: &str| Err(ValueError::Syntax(format!("{why}: {}", shorten(text))));
        if text.len() > MAX_VALUE_LEN {
            return Err(ValueError::OverLimit(format!(
                "value of {} characters is over the limit of {MAX_VALUE_LEN}: {}",
                text.len(),
                shorten(text)
            )));
        }
        if let Some(hex) = text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
            if !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
                return syntax("bad hex digits");
            }
            return match hex.len() {
                8 => Ok(Value::F32Bits(u32::from_str_radix(hex, 16).map_err(
                    |_| ValueError::Syntax(format!("bad hex digits: {}", shorten(text))),
                )?)),
                16 => Ok(Value::F64Bits(u64::from_str_radix(hex, 16).map_err(
                    |_| ValueError::Syntax(format!("bad hex digits: {}", shorten(text))),
                )?)),
                _ => syntax("hex values need exactly 8 (binary32) or 16 (binary64) digits"),
            };
        }
        match text.split_once('/') {
            Some((numerator, denominator)) => {
                let numerator = parse_integer(numerator, true, "numerator", text)?;
                let denominator = parse_integer(denominator, false, "denominator", text)?;
                if denominator.is_zero() {
                    return syntax("zero denominator");
                }
                Ok(Value::Exact(BigRational::new(numerator, denominator)))
            }
            None => parse_decimal(text).map(Value::Exact),
        }
    }

    /// The value as a binary32 number, if it is exactly one.
    pub fn to_f32(&self) -> Result<f32, ValueError> {
        let not_representable = || ValueError::NotRepresentable {
            value: self.to_string(),
            float: "f32",
        };
        match self {
            Value::F32Bits(bits) => Ok(f32::from_bits(*bits)),
            Value::F64Bits(bits) => {
                let x = f64::from_bits(*bits);
                let narrow = x as f32;
                if x.is_nan() || f64::from(narrow) == x {
                    Ok(narrow)
                } else {
                    Err(not_representable())
                }
            }
            Value::Exact(r) => dyadic_to_float(r, 24, -149, 128)
                .map(|x| x as f32)
                .ok_or_else(not_representable),
        }
    }

    /// The value as a binary64 number, if it is exactly one.
    pub fn to_f64(&self) -> Result<f64, ValueError> {
        match self {
            Value::F32Bits(bits) => Ok(f64::from(f32::from_bits(*bits))),
            Value::F64Bits(bits) => Ok(f64::from_bits(*bits)),
            Value::Exact(r) => {
                dyadic_to_float(r, 53, -1074, 1024).ok_or_else(|| ValueError::NotRepresentable {
                    value: self.to_string(),
                    float: "f64",
                })
            }
        }
    }

    /// The value as an exact rational (NaN and infinities are errors).
    pub fn to_exact(&self) -> Result<BigRational, ValueError> {
        let from_float = |x: f64| {
            BigRational::from_float(x).ok_or_else(|| ValueError::NotReal(self.to_string()))
        };
        match self {
            Value::F32Bits(bits) => from_float(f64::from(f32::from_bits(*bits))),
            Value::F64Bits(bits) => from_float(f64::from_bits(*bits)),
            Value::Exact(r) => Ok(r.clone()),
        }
    }
}

impl fmt::Display for Value {
    /// The canonical text of the value: hex bits for floats, `p/q` (or an
    /// integer) for exact values; it parses back to an equal [`Value`].
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::F32Bits(bits) => write!(f, "0x{bits:08x}"),
            Value::F64Bits(bits) => write!(f, "0x{bits:016x}"),
            Value::Exact(r) => write!(f, "{r}"),
        }
    }
}

fn shorten(text: &str) -> String {
    let mut short: String = text.chars().take(64).collect();
    if short.len() < text.len() {
        short.push('…');
    }
    format!("{short:?}")
}

/// An optionally signed (`allow_sign`) string of ASCII digits, at most
/// [`MAX_RATIONAL_DIGITS`] of them; `what` and `value` (the whole value's
/// text) are for the message.
fn parse_integer(
    text: &str,
    allow_sign: bool,
    what: &str,
    value: &str,
) -> Result<BigInt, ValueError> {
    let (negative, digits) = match text.as_bytes().first() {
        Some(b'-') if allow_sign => (true, &text[1..]),
        Some(b'+') if allow_sign => (false, &text[1..]),
        _ => (false, text),
    };
    let bad = || ValueError::Syntax(format!("bad {what}: {}", shorten(value)));
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return Err(bad());
    }
    if digits.len() > MAX_RATIONAL_DIGITS {
        return Err(ValueError::OverLimit(format!(
            "{what} of {} digits is over the limit of {MAX_RATIONAL_DIGITS} digits: {}",
            digits.len(),
            shorten(value)
        )));
    }
    let magnitude = BigInt::parse_bytes(digits.as_bytes(), 10).ok_or_else(bad)?;
    Ok(if negative { -magnitude } else { magnitude })
}

/// `[+-]digits[.digits][(e|E)[+-]digits]`, at least one digit in the
/// mantissa, exactly; within the decimal limits.
fn parse_decimal(text: &str) -> Result<BigRational, ValueError> {
    let syntax = || {
        ValueError::Syntax(format!(
            "expected 0x + 8 or 16 hex digits, a decimal or p/q: {}",
            shorten(text)
        ))
    };
    let (mantissa, exponent) = match text.find(['e', 'E']) {
        Some(at) => (&text[..at], Some(&text[at + 1..])),
        None => (text, None),
    };
    let (negative, mantissa) = match mantissa.as_bytes().first() {
        Some(b'-') => (true, &mantissa[1..]),
        Some(b'+') => (false, &mantissa[1..]),
        _ => (false, mantissa),
    };
    let (whole, fraction) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    let all_digits = |s: &str| s.bytes().all(|b| b.is_ascii_digit());
    if whole.len() + fraction.len() == 0 || !all_digits(whole) || !all_digits(fraction) {
        return Err(syntax());
    }
    let exponent: i64 = match exponent {
        None => 0,
        Some(e) => {
            let digits = e.strip_prefix(['+', '-']).unwrap_or(e);
            if digits.is_empty() || !all_digits(digits) {
                return Err(syntax());
            }
            let significant = digits.trim_start_matches('0');
            let magnitude = match significant.len() {
                0 => Some(0),
                1..=6 => significant.parse::<i64>().ok(),
                _ => None,
            }
            .filter(|&m| m <= i64::from(MAX_DECIMAL_EXPONENT));
            let Some(magnitude) = magnitude else {
                let mut shown: String = e.chars().take(24).collect();
                if shown.len() < e.len() {
                    shown.push('…');
                }
                return Err(ValueError::OverLimit(format!(
                    "exponent {shown} is over the limit of {MAX_DECIMAL_EXPONENT} in magnitude: {}",
                    shorten(text)
                )));
            };
            if e.starts_with('-') {
                -magnitude
            } else {
                magnitude
            }
        }
    };
    // A plain integer is also the canonical text of an integral rational,
    // so it gets the rational limit; anything scaled by a fraction or an
    // exponent gets the decimal one.
    let plain_integer = exponent == 0 && !mantissa.contains('.');
    let limit = if plain_integer {
        MAX_RATIONAL_DIGITS
    } else {
        MAX_DECIMAL_DIGITS
    };
    if whole.len() + fraction.len() > limit {
        return Err(ValueError::OverLimit(format!(
            "decimal of {} digits is over the limit of {limit} digits: {}",
            whole.len() + fraction.len(),
            shorten(text)
        )));
    }
    let digits = format!("{whole}{fraction}");
    let mut numerator = BigInt::parse_bytes(digits.as_bytes(), 10).ok_or_else(syntax)?;
    if negative {
        numerator = -numerator;
    }
    let power = exponent - fraction.len() as i64;
    let ten_to = |k: u64| num_traits::pow(BigInt::from(10u32), k as usize);
    Ok(if power >= 0 {
        BigRational::from_integer(numerator * ten_to(power as u64))
    } else {
        BigRational::new(numerator, ten_to(power.unsigned_abs()))
    })
}

/// `r` as an `f64` if it equals `m * 2^e` with `m < 2^significand_bits`,
/// `e >= min_exponent` and `|r| < 2^max_exponent`: exactly the numbers of an
/// IEEE binary format with those parameters (the result is computed in
/// binary64, exactly, and narrows exactly to the smaller format).
fn dyadic_to_float(
    r: &BigRational,
    significand_bits: u64,
    min_exponent: i64,
    max_exponent: i64,
) -> Option<f64> {
    if r.is_zero() {
        return Some(0.0);
    }
    let denominator = r.denom(); // positive, coprime with the numerator
    let denominator_log2 = denominator.trailing_zeros()?;
    if !(denominator >> denominator_log2).is_one() {
        return None; // not dyadic
    }
    let numerator = r.numer();
    let numerator_zeros = numerator.trailing_zeros()?;
    let odd = numerator.abs() >> numerator_zeros;
    let exponent = numerator_zeros as i64 - denominator_log2 as i64;
    let odd_bits = odd.bits() as i64;
    if odd_bits > significand_bits as i64
        || exponent < min_exponent
        || odd_bits + exponent > max_exponent
    {
        return None;
    }
    let magnitude =
        odd.to_u64()? as f64 * pow2(exponent.max(-1022)) * pow2((exponent + 1022).min(0));
    Some(if numerator.sign() == Sign::Minus {
        -magnitude
    } else {
        magnitude
    })
}

/// `2^e` for `-1022 <= e <= 1023`, built from its bits (exact).
fn pow2(e: i64) -> f64 {
    f64::from_bits(((e + 1023) as u64) << 52)
}

/// The next binary32 value toward +inf (IEEE 754 `nextUp`): `-0` and `+0`
/// step to the smallest positive subnormal; NaN and +inf stay put.
///
/// `f32::next_up` does the same but needs Rust 1.86; this crate supports
/// 1.81. Test inputs ("one ulp past a lattice line") are built with it.
///
/// ```
/// use micromap_index_conformance::value::next_up_f32;
/// assert_eq!(next_up_f32(1.0), 1.0 + f32::EPSILON);
/// assert_eq!(next_up_f32(-0.0), f32::from_bits(1));
/// assert_eq!(next_up_f32(-f32::from_bits(1)).to_bits(), (-0.0f32).to_bits());
/// assert_eq!(next_up_f32(f32::MAX), f32::INFINITY);
/// assert!(next_up_f32(f32::NAN).is_nan());
/// ```
#[must_use]
pub fn next_up_f32(x: f32) -> f32 {
    if x.is_nan() || x == f32::INFINITY {
        x
    } else if x == 0.0 {
        f32::from_bits(1)
    } else if x > 0.0 {
        f32::from_bits(x.to_bits() + 1)
    } else {
        // Negative: a smaller magnitude is one bit pattern down.
        f32::from_bits(x.to_bits() - 1)
    }
}

/// The next binary32 value toward -inf (IEEE 754 `nextDown`), `-next_up(-x)`.
///
/// ```
/// use micromap_index_conformance::value::next_down_f32;
/// assert_eq!(next_down_f32(1.0), 1.0 - f32::EPSILON / 2.0);
/// assert_eq!(next_down_f32(0.0), -f32::from_bits(1));
/// assert_eq!(next_down_f32(f32::NEG_INFINITY), f32::NEG_INFINITY);
/// ```
#[must_use]
pub fn next_down_f32(x: f32) -> f32 {
    -next_up_f32(-x)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn exact(text: &str) -> BigRational {
        Value::parse(text).unwrap().to_exact().unwrap()
    }

    #[test]
    fn decimals_and_rationals_are_exact() {
        assert_eq!(exact("0.375"), exact("3/8"));
        assert_eq!(exact("-1.5e-3"), exact("-3/2000"));
        assert_eq!(exact("1E2"), exact("100"));
        assert_eq!(exact(".5"), exact("1/2"));
        assert_eq!(exact("5."), exact("5"));
        for bad in [
            "",
            ".",
            "e5",
            "1e",
            "1/0",
            "1/-2",
            "0x123",
            "0xzzzzzzzz",
            "1.2.3",
            "--1",
            "1e99999",
        ] {
            assert!(Value::parse(bad).is_err(), "{bad:?} should not parse");
        }
    }

    #[test]
    fn float_conversions_are_exact_or_refused() {
        let f32_of = |t: &str| Value::parse(t).unwrap().to_f32();
        let f64_of = |t: &str| Value::parse(t).unwrap().to_f64();
        assert_eq!(f32_of("0.5"), Ok(0.5));
        assert_eq!(f32_of("-3/8"), Ok(-0.375));
        assert!(f32_of("0.1").is_err());
        assert!(f32_of("0x3fb999999999999a").is_err()); // 0.1 as f64
        assert_eq!(f32_of("0x3fe0000000000000"), Ok(0.5));
        assert!(f32_of("0x7ff8000000000000").unwrap().is_nan());
        // smallest subnormals
        let tiny32 = format!("1/{}", BigInt::from(1) << 149);
        assert_eq!(f32_of(&tiny32), Ok(f32::from_bits(1)));
        let tiny64 = format!("1/{}", BigInt::from(1) << 1074);
        assert_eq!(f64_of(&tiny64), Ok(f64::from_bits(1)));
        let below64 = format!("1/{}", BigInt::from(1) << 1075);
        assert!(f64_of(&below64).is_err());
        assert_eq!(f64_of("16777217"), Ok(16777217.0));
        assert!(f32_of("16777217").is_err());
        assert_eq!(f64_of("0x3f800000"), Ok(1.0));
        // f64 subnormal with a full significand
        let x = f64::from_bits(0x000f_ffff_ffff_ffff);
        let text = BigRational::from_float(x).unwrap().to_string();
        assert_eq!(f64_of(&text), Ok(x));
        assert!(Value::parse("0x7f800000").unwrap().to_exact().is_err());
    }

    /// Issue 9: "1e999999999" said "expected a decimal", a 10,000-digit
    /// denominator "bad denominator"; both are over a limit, which the
    /// message names. Each limit is tested at and one past it.
    #[test]
    fn over_limit_values_name_the_limit() {
        let over = |text: &str| match Value::parse(text) {
            Err(ValueError::OverLimit(message)) => message,
            other => panic!("{:?}: {other:?}", shorten(text)),
        };
        assert!(over("1e999999999").starts_with(
            "exponent 999999999 is over the limit of 4096 in magnitude: \"1e999999999\""
        ));
        assert!(over("1e-4097").starts_with("exponent -4097 is over the limit of 4096"));
        assert!(Value::parse("1e-4096").is_ok());
        assert!(Value::parse("1e+0004096").is_ok());
        let nines = |n: usize| "9".repeat(n);
        assert!(Value::parse(&format!("1/{}", nines(MAX_RATIONAL_DIGITS))).is_ok());
        assert!(over(&format!("1/{}", nines(MAX_RATIONAL_DIGITS + 1)))
            .starts_with("denominator of 8201 digits is over the limit of 8200 digits"));
        assert!(Value::parse(&format!("-{}/3", nines(MAX_RATIONAL_DIGITS))).is_ok());
        assert!(over(&format!("-{}/3", nines(MAX_RATIONAL_DIGITS + 1)))
            .starts_with("numerator of 8201 digits is over the limit of 8200 digits"));
        assert!(over(&format!("1/{}", nines(10_000))).contains("over the limit of 8200 digits"));
        assert!(Value::parse(&format!("0.{}", nines(MAX_DECIMAL_DIGITS - 1))).is_ok());
        assert!(over(&format!("0.{}", nines(MAX_DECIMAL_DIGITS)))
            .starts_with("decimal of 4097 digits is over the limit of 4096 digits"));
        assert!(Value::parse(&nines(MAX_RATIONAL_DIGITS)).is_ok());
        assert!(over(&nines(MAX_RATIONAL_DIGITS + 1)).starts_with("decimal of 8201 digits"));
        assert!(over(&"1".repeat(MAX_VALUE_LEN + 1))
            .starts_with("value of 20001 characters is over the limit of 20000"));
        // Malformed stays a syntax error.
        assert!(matches!(Value::parse("1e+"), Err(ValueError::Syntax(_))));
        assert!(matches!(Value::parse("1/x"), Err(ValueError::Syntax(_))));
    }

    #[test]
    fn display_round_trips() {
        // Fuzz finding F1: extreme exponents print long, and must still parse back.
        for text in [
            "0x3f000000",
            "0x3fe0000000000000",
            "-3/8",
            "7",
            "1e4096",
            "1e-4094",
            "-9.99e-4096",
        ] {
            let value = Value::parse(text).unwrap();
            assert_eq!(Value::parse(&value.to_string()).unwrap(), value);
        }
    }
}
