//! The two inputs: an 8-bit PNG's alpha channel and a JSON list of UV triangles.

use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use serde::Deserialize;
use serde_json::value::RawValue;

/// One alpha byte per texel, row 0 = the image's top row, tightly packed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AlphaTexture {
    /// Texels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// `width * height` bytes, row-major from the top row.
    pub alpha: Vec<u8>,
}

impl AlphaTexture {
    /// A texture whose alpha is `f(x, y)` (x to the right, y down from the top row).
    pub fn from_fn(width: u32, height: u32, f: impl Fn(u32, u32) -> u8) -> Self {
        let alpha = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| f(x, y))
            .collect();
        Self {
            width,
            height,
            alpha,
        }
    }
}

/// A triangle's three texture coordinates `[u, v]`, in the input's vertex order.
pub type UvTriangle = [[f32; 2]; 3];

/// Reads the alpha channel of an 8-bit PNG (RGBA, grey + alpha, or a palette
/// with a `tRNS` chunk, which the decoder expands to RGBA).
pub fn read_png_alpha(path: &Path) -> Result<AlphaTexture, String> {
    let file = File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut decoder = png::Decoder::new(BufReader::new(file));
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder
        .read_info()
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| format!("{}: image too large", path.display()))?;
    let mut buffer = vec![0; size];
    let info = reader
        .next_frame(&mut buffer)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    if info.bit_depth != png::BitDepth::Eight {
        return Err(format!(
            "{}: {:?}-bit samples; only 8-bit PNGs are read",
            path.display(),
            info.bit_depth
        ));
    }
    let (channels, alpha_channel) = match info.color_type {
        png::ColorType::Rgba => (4, 3),
        png::ColorType::GrayscaleAlpha => (2, 1),
        other => {
            return Err(format!(
                "{}: colour type {other:?} has no alpha channel",
                path.display()
            ))
        }
    };
    let (width, height) = (info.width, info.height);
    let mut alpha = Vec::with_capacity(width as usize * height as usize);
    for row in buffer[..info.buffer_size()].chunks_exact(info.line_size) {
        alpha.extend(
            row[..width as usize * channels]
                .chunks_exact(channels)
                .map(|texel| texel[alpha_channel]),
        );
    }
    Ok(AlphaTexture {
        width,
        height,
        alpha,
    })
}

#[derive(Deserialize)]
struct TrianglesFile<'a> {
    #[serde(borrow)]
    triangles: Vec<[[&'a RawValue; 2]; 3]>,
}

/// Parses `{"triangles": [[[u0, v0], [u1, v1], [u2, v2]], ...]}`; every
/// number is read as `f32` from its own decimal text (`str::parse::<f32>`,
/// correctly rounded), never through an `f64`.
pub fn parse_triangles(text: &str) -> Result<Vec<UvTriangle>, String> {
    let file: TrianglesFile<'_> =
        serde_json::from_str(text).map_err(|e| format!("triangles file: {e}"))?;
    let number = |raw: &RawValue, t: usize| -> Result<f32, String> {
        let token = raw.get().trim();
        token
            .parse::<f32>()
            .map_err(|e| format!("triangle {t}: {token:?} is not a number ({e})"))
    };
    file.triangles
        .iter()
        .enumerate()
        .map(|(t, triangle)| {
            let mut out = [[0.0f32; 2]; 3];
            for (corner, raw) in out.iter_mut().zip(triangle) {
                *corner = [number(raw[0], t)?, number(raw[1], t)?];
            }
            Ok(out)
        })
        .collect()
}

/// The texture covered by an `n` x `n` grid of quads, two triangles each,
/// UVs in `[0, 1]` with v down (row 0 = the image's top row). Quad `(i, j)`
/// (column `i`, row `j`) spans `[i/n, (i+1)/n] x [j/n, (j+1)/n]` and is split
/// along its diagonal from top-left to bottom-right:
/// `(u0, v0), (u1, v0), (u1, v1)` then `(u0, v0), (u1, v1), (u0, v1)`.
pub fn grid_triangles(n: u32) -> Vec<UvTriangle> {
    let mut out = Vec::with_capacity(2 * (n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            let (u0, u1) = (i as f32 / n as f32, (i + 1) as f32 / n as f32);
            let (v0, v1) = (j as f32 / n as f32, (j + 1) as f32 / n as f32);
            out.push([[u0, v0], [u1, v0], [u1, v1]]);
            out.push([[u0, v0], [u1, v1], [u0, v1]]);
        }
    }
    out
}

/// `grid_triangles` as the JSON the tool reads, one triangle a line. Each
/// number is written with Rust's shortest round-trip text, so parsing it back
/// as `f32` gives the same bits.
pub fn triangles_json(triangles: &[UvTriangle]) -> String {
    let mut s = String::from("{\"triangles\": [\n");
    for (k, t) in triangles.iter().enumerate() {
        s.push_str(&format!(
            "  [[{:?}, {:?}], [{:?}, {:?}], [{:?}, {:?}]]{}\n",
            t[0][0],
            t[0][1],
            t[1][0],
            t[1][1],
            t[2][0],
            t[2][1],
            if k + 1 < triangles.len() { "," } else { "" }
        ));
    }
    s.push_str("]}\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_parsed_as_f32_from_their_text() {
        // 0.1 through f64 then f32 equals direct parsing here, but a value
        // near an f32 rounding tie would not; the parser must use the token.
        let t = parse_triangles(
            r#"{"triangles": [[[0.1, 1e-3], [1, 0], [0.30000001192092896, -0.0]]]}"#,
        )
        .unwrap();
        assert_eq!(t[0][0], [0.1f32, 1e-3f32]);
        assert_eq!(t[0][2][0], "0.30000001192092896".parse::<f32>().unwrap());
        assert!(t[0][2][1].is_sign_negative());
        // Double rounding: 1 + 2^-24 + 2^-60 rounds to 1 + 2^-23 directly,
        // but through f64 it becomes 1 + 2^-24, a tie, rounded to 1.
        let token = "1.000000059604644776257986737988403547205962240695953369140625";
        let t = parse_triangles(&format!(
            "{{\"triangles\": [[[{token}, 0], [0, 0], [0, 0]]]}}"
        ))
        .unwrap();
        assert_eq!(t[0][0][0], 1.0 + f32::EPSILON);
        assert_eq!(token.parse::<f64>().unwrap() as f32, 1.0);
    }

    /// The grid the runs bake (`assets/crytek-sponza/grid.tris.json`, shared
    /// with the repository's bake docs) is `--grid 8`.
    #[test]
    fn committed_grid_is_the_8_by_8_grid() {
        let committed = include_str!("../../../assets/crytek-sponza/grid.tris.json");
        assert_eq!(parse_triangles(committed).unwrap(), grid_triangles(8));
    }

    #[test]
    fn grid_round_trips_through_json() {
        let grid = grid_triangles(8);
        assert_eq!(grid.len(), 128);
        assert_eq!(parse_triangles(&triangles_json(&grid)).unwrap(), grid);
    }
}
