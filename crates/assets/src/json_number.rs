//! JSON numbers read from their decimal text with one rounding to binary32
//! (`TRIS.json` coordinates, glTF's `alphaCutoff` and factors).

/// Reads a JSON number's text as binary32 with one rounding (Rust's
/// correctly rounded `f32` parser). `None` unless `text` is a JSON number:
/// an optional `-`, digits, an optional fraction and exponent. Values past
/// the binary32 range give `±inf`, tiny ones `±0` or a subnormal.
pub(crate) fn json_number_f32(text: &str) -> Option<f32> {
    let text = text.trim_matches(|c: char| c == ' ' || c == '\t' || c == '\n' || c == '\r');
    let digits = text.strip_prefix('-').unwrap_or(text);
    // A JSON number starts with a digit after its sign; this also rules out
    // what Rust's parser accepts beyond JSON ("inf", "NaN", "+1", ".5").
    if !digits.starts_with(|c: char| c.is_ascii_digit())
        || !digits
            .bytes()
            .all(|b| b.is_ascii_digit() || matches!(b, b'.' | b'e' | b'E' | b'+' | b'-'))
    {
        return None;
    }
    text.parse::<f32>().ok()
}
