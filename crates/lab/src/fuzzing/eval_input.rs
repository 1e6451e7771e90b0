//! The body of the fuzz target `eval_input`, replayed on stable by
//! `crates/lab/tests/fuzz_corpus.rs`.

#[allow(clippy::wildcard_imports)]
use super::*;

/// The CLI's input path on arbitrary bytes: [`eval_line_bytes`] for every
/// [`Variant`], and [`Value::parse`] on the same bytes.
///
/// The whole input is one line (no decoding). Checks:
///
/// * every variant returns a single line holding a JSON object with exactly
///   one member, `"index"` (an unsigned integer below `4^level`, the input's
///   `level`) or `"error"` (a string);
/// * variants that must agree do: `spec-f32` and `fixed-mirror` give the
///   same line; where two of `uv2index-exact`, `fixed-exact`, `spec-exact`
///   and `spec-wide` all return an index, the indices are equal;
/// * if the bytes are UTF-8 and [`Value::parse`] accepts them, the value's
///   text parses back to the same value, and its `f32`, `f64` and exact
///   readings are consistent (NaN and infinities have no exact reading but
///   both float readings).
///
/// ```
/// use micromap_index_lab::fuzzing::eval_input;
/// eval_input(br#"{"u": "0x3e000000", "v": "1/8", "level": 2}"#);
/// eval_input(b"\xff\xfe not UTF-8");
/// eval_input(b"-3/8");
/// ```
///
/// # Panics
///
/// When a property fails.
pub fn eval_input(data: &[u8]) {
    let input_level = std::str::from_utf8(data)
        .ok()
        .and_then(|text| serde_json::from_str::<serde_json::Value>(text).ok())
        .and_then(|json| {
            // The line's serde reading also accepts `[u, v, level]`.
            match &json {
                serde_json::Value::Array(items) => items.get(2).and_then(serde_json::Value::as_u64),
                _ => json.get("level").and_then(serde_json::Value::as_u64),
            }
        });
    let mut lines = Vec::with_capacity(Variant::ALL.len());
    for variant in Variant::ALL {
        let line = eval_line_bytes(variant, data);
        assert!(
            !line.contains(['\n', '\r']),
            "{variant} wrote more than one line: {line:?} for input {data:?}"
        );
        let json: serde_json::Value = match serde_json::from_str(&line) {
            Ok(json) => json,
            Err(e) => panic!("{variant} wrote invalid JSON {line:?} ({e}) for input {data:?}"),
        };
        let member = json
            .as_object()
            .filter(|object| object.len() == 1)
            .and_then(|object| object.iter().next());
        let index = match member {
            Some((key, serde_json::Value::String(_))) if key == "error" => None,
            Some((key, value)) if key == "index" && value.as_u64().is_some() => value.as_u64(),
            _ => panic!("{variant} wrote {line:?}, not one index or error, for input {data:?}"),
        };
        if let Some(index) = index {
            let Some(level) = input_level.filter(|&level| level <= 32) else {
                panic!("{variant} wrote {line:?} for input {data:?} without a level 0..=32");
            };
            assert!(
                u128::from(index) < 1u128 << (2 * level),
                "{variant} wrote index {index} >= 4^{level} for input {data:?}"
            );
        }
        lines.push((variant, line, index));
    }
    let line_of = |wanted: Variant| {
        lines
            .iter()
            .find(|(variant, _, _)| *variant == wanted)
            .map(|(_, line, index)| (line.as_str(), *index))
    };
    if let (Some((spec_line, _)), Some((mirror_line, _))) = (
        line_of(Variant::SpecF32),
        line_of(Variant::SpecF32ByIntegers),
    ) {
        assert_eq!(
            naming_no_variant(spec_line, Variant::SpecF32),
            naming_no_variant(mirror_line, Variant::SpecF32ByIntegers),
            "spec-f32 and fixed-mirror differ for input {data:?}"
        );
    }
    let exact: Vec<(Variant, u64)> = [
        Variant::WalkReal,
        Variant::WalkExactFloat,
        Variant::SpecReal,
        Variant::SpecWideReal,
    ]
    .into_iter()
    .filter_map(|variant| Some((variant, line_of(variant)?.1?)))
    .collect();
    if let Some(&(first, first_index)) = exact.first() {
        for &(variant, index) in &exact {
            assert_eq!(
                index, first_index,
                "{variant} says {index} but {first} says {first_index} for input {data:?}"
            );
        }
    }

    if let Some(value) = std::str::from_utf8(data)
        .ok()
        .and_then(|text| Value::parse(text).ok())
    {
        check_value(&value);
    }
}

/// The consistency of one parsed value's readings (see [`eval_input`]).
fn check_value(value: &Value) {
    let text = value.to_string();
    let reparsed = Value::parse(&text);
    // Finding F1 (docs/fuzzing.md), fixed: the canonical text of every
    // parsed value parses back, however long.
    assert!(
        text.len() <= MAX_VALUE_LEN,
        "{value:?} prints as {} characters",
        text.len()
    );
    assert_eq!(
        reparsed.as_ref(),
        Ok(value),
        "{value:?} prints as {text:?}, which does not parse back"
    );
    let as_f32 = value.to_f32();
    let as_f64 = value.to_f64();
    if let Ok(exact) = value.to_exact() {
        if let Ok(x) = as_f32 {
            assert_eq!(
                BigRational::from_float(x).as_ref(),
                Some(&exact),
                "{text}: to_f32 = 0x{:08x} but to_exact = {exact}",
                x.to_bits()
            );
        }
        if let Ok(x) = as_f64 {
            assert_eq!(
                BigRational::from_float(x).as_ref(),
                Some(&exact),
                "{text}: to_f64 = 0x{:016x} but to_exact = {exact}",
                x.to_bits()
            );
        }
    } else {
        let non_finite = |x: Result<f64, _>| x.is_ok_and(|x: f64| !x.is_finite());
        assert!(
            non_finite(as_f32.clone().map(f64::from)) && non_finite(as_f64.clone()),
            "{text}: no exact reading, but to_f32 = {as_f32:?}, to_f64 = {as_f64:?}"
        );
    }
    if let Ok(x) = as_f32 {
        let widened = as_f64.clone().map(f64::to_bits);
        let expected = f64::from(x);
        assert!(
            as_f64.is_ok_and(|y| y == expected || (y.is_nan() && x.is_nan())),
            "{text}: to_f32 = 0x{:08x} but to_f64 = {widened:x?}",
            x.to_bits()
        );
    }
}
