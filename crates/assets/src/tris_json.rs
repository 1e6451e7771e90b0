//! [`read_triangles_json`]: triangles in UV space from `TRIS.json`.

use crate::error::AssetError;
use crate::json_number::json_number_f32;
use serde::Deserialize;
use serde_json::value::RawValue;

/// The top level of a `TRIS.json`: only `"triangles"` is read.
#[derive(Deserialize)]
#[serde(expecting = "an object {\"triangles\": [...]}")]
struct TrisFile<'a> {
    #[serde(borrow)]
    triangles: &'a RawValue,
}

/// Reads a `TRIS.json` file: a JSON object whose member `"triangles"` is an
/// array of triangles, each an array of three vertices `[u, v]` of JSON
/// numbers:
///
/// ```json
/// {"triangles": [[[0, 0], [1, 0], [0, 1]], [[0.5, 0.5], [1, 0.5], [0.5, 1]]]}
/// ```
///
/// * Each number is rounded **once** from its decimal text to binary32
///   (Rust's correctly rounded `str::parse::<f32>`), never through `f64`,
///   which could round twice. Numbers beyond the binary32 range come out as
///   `±inf` (`1e39` is `inf`) and are let through for the caller to handle;
///   tiny ones round to subnormals or `±0`.
/// * Other top-level members are allowed and ignored (a `"name"` or
///   `"comment"`, say); `"triangles"` must be there, and only once.
/// * Anything else is an error naming the triangle: a triangle that is not
///   an array of three vertices, a vertex that is not an array of two
///   numbers, a string or `null` where a number should be.
///
/// The output holds 24 bytes per triangle, and each triangle takes at least
/// 19 bytes of input (`[[0,0],[0,0],[0,0]]`), so memory stays within a small
/// multiple of the input's length. Never panics.
///
/// ```
/// use micromap_index_assets::read_triangles_json;
/// // 0.1 rounds once to the nearest binary32 value; 1e39 overflows to inf.
/// let triangles = read_triangles_json(br#"{"triangles": [[[0.1, 0], [1, 0], [0, 1e39]]], "name": "x"}"#).unwrap();
/// assert_eq!(triangles[0][0][0], 0.1f32);
/// assert_eq!(triangles[0][2][1], f32::INFINITY);
///
/// let error = read_triangles_json(br#"{"triangles": [[[0, 0], [1, 0], [0, 1]], [[0, 0], [1, 0]]]}"#);
/// assert_eq!(error.unwrap_err().to_string(), "triangle 1: has 2 vertices, expected 3 ([[u, v], [u, v], [u, v]])");
/// ```
pub fn read_triangles_json(bytes: &[u8]) -> Result<Vec<[[f32; 2]; 3]>, AssetError> {
    // serde would read a struct from an array too.
    if bytes.trim_ascii_start().starts_with(b"[") {
        return Err(AssetError::Json {
            message: "the top level is an array, expected an object {\"triangles\": [...]}"
                .to_string(),
        });
    }
    let file: TrisFile<'_> = serde_json::from_slice(bytes).map_err(|e| AssetError::Json {
        message: e.to_string(),
    })?;
    let items: Vec<&RawValue> =
        serde_json::from_str(file.triangles.get()).map_err(|_| AssetError::Triangles {
            triangle: None,
            message: format!(
                "\"triangles\" is {}, expected an array",
                describe(file.triangles)
            ),
        })?;
    let mut triangles = Vec::with_capacity(items.len());
    for (i, item) in items.into_iter().enumerate() {
        let error = |message: String| AssetError::Triangles {
            triangle: Some(i),
            message,
        };
        let vertices: Vec<&RawValue> = serde_json::from_str(item.get()).map_err(|_| {
            error(format!(
                "is {}, expected an array of 3 vertices [u, v]",
                describe(item)
            ))
        })?;
        if vertices.len() != 3 {
            return Err(error(format!(
                "has {} vertices, expected 3 ([[u, v], [u, v], [u, v]])",
                vertices.len()
            )));
        }
        let mut triangle = [[0f32; 2]; 3];
        for (k, (vertex, slot)) in vertices.iter().zip(&mut triangle).enumerate() {
            let numbers: Vec<&RawValue> = serde_json::from_str(vertex.get()).map_err(|_| {
                error(format!(
                    "vertex {k} is {}, expected [u, v]",
                    describe(vertex)
                ))
            })?;
            if numbers.len() != 2 {
                return Err(error(format!(
                    "vertex {k} has {} numbers, expected 2 ([u, v])",
                    numbers.len()
                )));
            }
            for (number, (out, name)) in numbers.iter().zip(slot.iter_mut().zip(["u", "v"])) {
                *out = json_number_f32(number.get()).ok_or_else(|| {
                    error(format!(
                        "vertex {k}: {name} is {}, expected a number",
                        describe(number)
                    ))
                })?;
            }
        }
        triangles.push(triangle);
    }
    Ok(triangles)
}

/// A short description of a JSON value for error messages: its kind and,
/// for short scalars, its text.
fn describe(value: &RawValue) -> String {
    let text = value.get().trim();
    let kind = match text.as_bytes().first() {
        Some(b'[') => return "an array".to_string(),
        Some(b'{') => return "an object".to_string(),
        Some(b'"') => "a string",
        Some(b'n') => "null",
        Some(b't' | b'f') => "a boolean",
        _ => "a number",
    };
    if kind == "null" {
        return kind.to_string();
    }
    if text.len() <= 40 {
        format!("{kind} {text}")
    } else {
        kind.to_string()
    }
}
