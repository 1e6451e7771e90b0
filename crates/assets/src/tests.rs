//! Tests of the asset readers: every image kind, the `TRIS.json` rules, and
//! each error path of the glTF reader on small hand-made assets.

use super::gltf::{CLAMP_TO_EDGE, MIRRORED_REPEAT, NEAREST};
use super::{
    decode_alpha_image, read_gltf_bytes, read_gltf_file, read_triangles_json, AlphaImage,
    AlphaTexels, AssetError, GltfAsset, ImageFormat, Limits, IDENTITY_TRANSFORM,
};
use micromap_index::bake::{AddressMode, Filter, Sampler};
use serde_json::{json, Value};
use std::path::Path;

// ---------------------------------------------------------------- images

/// A PNG from the `png` crate's encoder.
fn png(
    width: u32,
    height: u32,
    color: png::ColorType,
    depth: png::BitDepth,
    data: &[u8],
    palette: Option<(&[u8], Option<&[u8]>)>,
    trns: Option<&[u8]>,
) -> Vec<u8> {
    let mut out = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut out, width, height);
        encoder.set_color(color);
        encoder.set_depth(depth);
        if let Some((plte, alpha)) = palette {
            encoder.set_palette(plte.to_vec());
            if let Some(alpha) = alpha {
                encoder.set_trns(alpha.to_vec());
            }
        }
        if let Some(trns) = trns {
            encoder.set_trns(trns.to_vec());
        }
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(data).unwrap();
    }
    out
}

fn decode(bytes: &[u8]) -> AlphaImage {
    decode_alpha_image(bytes, &Limits::default()).unwrap()
}

fn unorm8(image: &AlphaImage) -> &[u8] {
    match &image.texels {
        AlphaTexels::Unorm8(texels) => texels,
        _ => panic!("expected 8-bit texels"),
    }
}

fn unorm16(image: &AlphaImage) -> &[u16] {
    match &image.texels {
        AlphaTexels::Unorm16(texels) => texels,
        _ => panic!("expected 16-bit texels"),
    }
}

use png::{BitDepth, ColorType};

#[test]
fn png_grey_and_alpha_channels() {
    // Grey: the grey value, rows top first.
    let image = decode(&png(
        2,
        2,
        ColorType::Grayscale,
        BitDepth::Eight,
        &[0, 1, 2, 3],
        None,
        None,
    ));
    assert_eq!((image.width, image.height), (2, 2));
    assert_eq!(unorm8(&image), [0, 1, 2, 3]);
    assert_eq!(image.get(1, 0), Some(1.0 / 255.0));
    assert_eq!(image.get(2, 0), None);
    // Grey + alpha: the alpha.
    let image = decode(&png(
        2,
        1,
        ColorType::GrayscaleAlpha,
        BitDepth::Eight,
        &[9, 10, 9, 200],
        None,
        None,
    ));
    assert_eq!(unorm8(&image), [10, 200]);
    // RGBA: the alpha.
    let image = decode(&png(
        1,
        2,
        ColorType::Rgba,
        BitDepth::Eight,
        &[1, 2, 3, 4, 5, 6, 7, 8],
        None,
        None,
    ));
    assert_eq!(unorm8(&image), [4, 8]);
    // RGB: the luma, rounded half up.
    let rgb = [255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30, 255, 255, 255];
    let image = decode(&png(
        5,
        1,
        ColorType::Rgb,
        BitDepth::Eight,
        &rgb,
        None,
        None,
    ));
    // 0.2126 * 255 = 54.213, 0.7152 * 255 = 182.376, 0.0722 * 255 = 18.411,
    // 2.126 + 14.304 + 2.166 = 18.596.
    assert_eq!(unorm8(&image), [54, 182, 18, 19, 255]);
}

#[test]
fn png_16_bit_is_exact() {
    let image = decode(&png(
        3,
        1,
        ColorType::Grayscale,
        BitDepth::Sixteen,
        &[0, 0, 0x80, 0x00, 0xff, 0xff],
        None,
        None,
    ));
    assert_eq!(unorm16(&image), [0, 0x8000, 0xffff]);
    assert_eq!(image.get(1, 0), Some(32768.0 / 65535.0));
    let rgba = [0, 1, 0, 2, 0, 3, 0x12, 0x34];
    let image = decode(&png(
        1,
        1,
        ColorType::Rgba,
        BitDepth::Sixteen,
        &rgba,
        None,
        None,
    ));
    assert_eq!(unorm16(&image), [0x1234]);
    let rgb = [0xff, 0xff, 0, 0, 0, 0];
    let image = decode(&png(
        1,
        1,
        ColorType::Rgb,
        BitDepth::Sixteen,
        &rgb,
        None,
        None,
    ));
    // round(0.2126 * 65535) = 13933.
    assert_eq!(unorm16(&image), [13933]);
}

#[test]
fn png_palettes_low_depths_and_trns() {
    let plte = [0, 0, 0, 255, 255, 255, 255, 0, 0];
    // Palette with tRNS: each entry's alpha; entries past tRNS are opaque.
    let image = decode(&png(
        3,
        1,
        ColorType::Indexed,
        BitDepth::Eight,
        &[0, 1, 2],
        Some((&plte, Some(&[7, 200]))),
        None,
    ));
    assert_eq!(unorm8(&image), [7, 200, 255]);
    // Palette without tRNS: the luma of the colours.
    let image = decode(&png(
        3,
        1,
        ColorType::Indexed,
        BitDepth::Eight,
        &[0, 1, 2],
        Some((&plte, None)),
        None,
    ));
    assert_eq!(unorm8(&image), [0, 255, 54]);
    // 1-bit grey: scaled to 0 and 255.
    let image = decode(&png(
        8,
        1,
        ColorType::Grayscale,
        BitDepth::One,
        &[0b1010_0000],
        None,
        None,
    ));
    assert_eq!(unorm8(&image), [255, 0, 255, 0, 0, 0, 0, 0]);
    // Grey with a tRNS colour key: alpha 0 on the key, 255 elsewhere.
    let image = decode(&png(
        3,
        1,
        ColorType::Grayscale,
        BitDepth::Eight,
        &[5, 6, 5],
        None,
        Some(&[0, 5]),
    ));
    assert_eq!(unorm8(&image), [0, 255, 0]);
    // RGB with a colour key.
    let image = decode(&png(
        2,
        1,
        ColorType::Rgb,
        BitDepth::Eight,
        &[1, 2, 3, 1, 2, 4],
        None,
        Some(&[0, 1, 0, 2, 0, 3]),
    ));
    assert_eq!(unorm8(&image), [0, 255]);
}

/// The hand-made JPEGs of the fuzz seeds (`fuzz/seeds/make_asset_seeds.py`).
fn seed(target: &str, name: &str) -> Vec<u8> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz/seeds")
        .join(target)
        .join(name);
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn jpeg_grey_and_rgb() {
    let grey = seed("alpha_image", "grey-16x8.jpg");
    assert_eq!(ImageFormat::detect(&grey), Some(ImageFormat::Jpeg));
    let image = decode(&grey);
    assert_eq!((image.width, image.height), (16, 8));
    // Two flat blocks: 64 on the left, 200 on the right.
    let texels = unorm8(&image);
    for (i, &t) in texels.iter().enumerate() {
        assert_eq!(t, if i % 16 < 8 { 64 } else { 200 }, "texel {i}");
    }
    let image = decode(&seed("alpha_image", "rgb-8x8.jpg"));
    assert_eq!((image.width, image.height), (8, 8));
    // A flat colour of luma about 100 (YCbCr to RGB rounds each channel).
    let texels = unorm8(&image);
    assert!(
        texels
            .iter()
            .all(|&t| t == texels[0] && t.abs_diff(100) <= 2),
        "{texels:?}"
    );
}

#[test]
fn image_errors() {
    let limits = Limits::default();
    let error = decode_alpha_image(b"GIF89a....", &limits).unwrap_err();
    assert_eq!(
        error.to_string(),
        "not a PNG or JPEG image (starts with 47 49 46 38 39 61 2e 2e)"
    );
    let error = decode_alpha_image(b"", &limits).unwrap_err();
    assert_eq!(
        error.to_string(),
        "not a PNG or JPEG image (starts with nothing: empty)"
    );
    // Truncated and corrupted PNGs.
    let good = png(4, 4, ColorType::Rgba, BitDepth::Eight, &[7; 64], None, None);
    for cut in [8, 20, 33, 41] {
        let error = decode_alpha_image(&good[..cut], &limits).unwrap_err();
        assert!(
            matches!(
                error,
                AssetError::Image {
                    format: ImageFormat::Png,
                    ..
                }
            ),
            "{cut}: {error}"
        );
    }
    let mut bad_crc = good.clone();
    bad_crc[29] ^= 1;
    assert!(decode_alpha_image(&bad_crc, &limits).is_err());
    // A header claiming 100000 x 100000 pixels is refused before any pixel
    // buffer: the limit error, not an allocation.
    let mut huge = good.clone();
    huge[16..20].copy_from_slice(&100_000u32.to_be_bytes());
    huge[20..24].copy_from_slice(&100_000u32.to_be_bytes());
    let crc = crc32(&huge[12..29]);
    huge[29..33].copy_from_slice(&crc.to_be_bytes());
    let error = decode_alpha_image(&huge, &limits).unwrap_err();
    assert_eq!(
        error.to_string(),
        "PNG image of 100000 x 100000 pixels: 10000000000 is over the limit of 67108864"
    );
    // The byte limit.
    let error = decode_alpha_image(
        &good,
        &Limits {
            max_pixels: 16,
            max_bytes: 63,
            ..Limits::default()
        },
    )
    .unwrap_err();
    assert!(error.to_string().starts_with("PNG image"), "{error}");
    assert!(decode_alpha_image(
        &good,
        &Limits {
            max_pixels: 16,
            max_bytes: 64,
            ..Limits::default()
        }
    )
    .is_ok());
    // JPEG: truncated, and a header claiming 65535 x 65535 pixels.
    let grey = seed("alpha_image", "grey-16x8.jpg");
    for cut in [3, 20, grey.len() / 2] {
        let error = decode_alpha_image(&grey[..cut], &limits).unwrap_err();
        assert!(
            matches!(
                error,
                AssetError::Image {
                    format: ImageFormat::Jpeg,
                    ..
                }
            ),
            "{cut}: {error}"
        );
    }
    let sof = grey.windows(2).position(|w| w == [0xff, 0xc0]).unwrap();
    let mut huge = grey.clone();
    huge[sof + 5..sof + 9].copy_from_slice(&[0xff, 0xff, 0xff, 0xff]);
    let error = decode_alpha_image(&huge, &limits).unwrap_err();
    assert_eq!(
        error.to_string(),
        "JPEG image of 65535 x 65535 pixels: 4294836225 is over the limit of 67108864"
    );
}

/// A PNG chunk with its CRC.
fn chunk(kind: [u8; 4], data: &[u8]) -> Vec<u8> {
    let mut out = (data.len() as u32).to_be_bytes().to_vec();
    out.extend_from_slice(&kind);
    out.extend_from_slice(data);
    out.extend_from_slice(&crc32(&out[4..]).to_be_bytes());
    out
}

#[test]
fn png_palette_of_a_length_not_a_multiple_of_3_is_an_error() {
    // png 0.18.1 panics on this one (finding A1 in docs/fuzzing.md); the
    // reader rejects it first.
    let good = png(
        1,
        1,
        ColorType::Indexed,
        BitDepth::Eight,
        &[0],
        Some((&[1, 2, 3], None)),
        None,
    );
    assert_eq!(unorm8(&decode(&good)), [2]);
    // Replace the 3-byte PLTE (after the 33 bytes of signature and IHDR).
    let mut bad = good[..33].to_vec();
    bad.extend(chunk(*b"PLTE", &[1, 2, 3, 4]));
    bad.extend_from_slice(&good[33 + 15..]);
    let error = decode_alpha_image(&bad, &Limits::default()).unwrap_err();
    assert_eq!(
        error.to_string(),
        "PNG image: PLTE chunk of 4 bytes, not a multiple of 3"
    );
    let regression = std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../fuzz/regressions/alpha_image/a1-png-plte-length-not-multiple-of-3"),
    )
    .unwrap();
    assert!(decode_alpha_image(&regression, &Limits::default()).is_err());
}

/// CRC-32 (PNG's), to patch a chunk.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

// ---------------------------------------------------------------- TRIS.json

#[test]
fn triangles_round_once() {
    // 1 + 2^-24 is halfway between 1 and the next binary32 value; the
    // decimal just above it rounds up. Through f64 it would first round to
    // the halfway point, then to even: 1.0.
    let text = "1.00000005960464477539062500001";
    assert_eq!(text.parse::<f64>().unwrap() as f32, 1.0);
    let json =
        format!(r#"{{"triangles": [[[{text}, 0], [1e39, -1e39], [1e-50, -0.0]]], "name": "t"}}"#);
    let triangles = read_triangles_json(json.as_bytes()).unwrap();
    let [[a, b], [c, d], [e, f]] = triangles[0];
    assert_eq!(a, 1.0 + f32::EPSILON);
    assert_eq!(b, 0.0);
    assert_eq!((c, d), (f32::INFINITY, f32::NEG_INFINITY));
    assert_eq!(e.to_bits(), 0);
    assert_eq!(f.to_bits(), (-0.0f32).to_bits());
    assert_eq!(
        read_triangles_json(br#"{"triangles": []}"#).unwrap(),
        Vec::<[[f32; 2]; 3]>::new()
    );
    assert_eq!(
        read_triangles_json(b" {\"triangles\":[[[1E2,2e-1],[ 3 , 4 ],[5,6]]]}\n").unwrap(),
        vec![[[100.0, 0.2], [3.0, 4.0], [5.0, 6.0]]]
    );
}

#[test]
fn triangles_errors_name_the_triangle() {
    let ok = "[[0, 0], [1, 0], [0, 1]]";
    for (text, message) in [
        (
            "",
            "invalid JSON: EOF while parsing a value at line 1 column 0",
        ),
        (
            "[]",
            "invalid JSON: the top level is an array, expected an object {\"triangles\": [...]}",
        ),
        (
            "{}",
            "invalid JSON: missing field `triangles` at line 1 column 2",
        ),
        (
            r#"{"triangles": [], "triangles": []}"#,
            "invalid JSON: duplicate field `triangles` at line 1 column 29",
        ),
        (
            r#"{"triangles": {}}"#,
            "triangles: \"triangles\" is an object, expected an array",
        ),
        (
            &format!(r#"{{"triangles": [{ok}, 3]}}"#),
            "triangle 1: is a number 3, expected an array of 3 vertices [u, v]",
        ),
        (
            &format!(r#"{{"triangles": [{ok}, {ok}, [[0, 0], [1, 0]]]}}"#),
            "triangle 2: has 2 vertices, expected 3 ([[u, v], [u, v], [u, v]])",
        ),
        (
            r#"{"triangles": [[[0, 0], [1, 0], [0, 1], [1, 1]]]}"#,
            "triangle 0: has 4 vertices, expected 3 ([[u, v], [u, v], [u, v]])",
        ),
        (
            r#"{"triangles": [[[0, 0, 0], [1, 0], [0, 1]]]}"#,
            "triangle 0: vertex 0 has 3 numbers, expected 2 ([u, v])",
        ),
        (
            r#"{"triangles": [[[0, 0], {"u": 1}, [0, 1]]]}"#,
            "triangle 0: vertex 1 is an object, expected [u, v]",
        ),
        (
            r#"{"triangles": [[[0, 0], [1, 0], [0, "1"]]]}"#,
            "triangle 0: vertex 2: v is a string \"1\", expected a number",
        ),
        (
            r#"{"triangles": [[[null, 0], [1, 0], [0, 1]]]}"#,
            "triangle 0: vertex 0: u is null, expected a number",
        ),
        (
            r#"{"triangles": [[[[0], 0], [1, 0], [0, 1]]]}"#,
            "triangle 0: vertex 0: u is an array, expected a number",
        ),
        (
            "{\"triangles\": [[[0, 0], [1, 0], [0, 1]]]} x",
            "invalid JSON: trailing characters at line 1 column 43",
        ),
        ("\u{ff}", "invalid JSON: expected value at line 1 column 1"),
    ] {
        let error = read_triangles_json(text.as_bytes()).unwrap_err();
        assert_eq!(error.to_string(), message, "{text}");
    }
    assert!(read_triangles_json(&[0xff, 0xfe]).is_err());
}

// ---------------------------------------------------------------- glTF

/// Base64 (standard, padded), for `data:` URIs.
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let word = chunk
            .iter()
            .enumerate()
            .fold(0u32, |w, (k, &b)| w | u32::from(b) << (16 - 8 * k));
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(word >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// A 2 x 2 grey + alpha PNG, served for every image URI.
fn tiny_png() -> Vec<u8> {
    png(
        2,
        2,
        ColorType::GrayscaleAlpha,
        BitDepth::Eight,
        &[0, 0, 0, 85, 0, 170, 0, 255],
        None,
        None,
    )
}

/// A small valid asset: one MASK quad (4 float UVs, 6 `u16` indices) with
/// texture 0 -> image 0 (`a.png`), sampler-less; and the binary buffer
/// (UVs at 0, indices at 32).
fn fixture() -> (Value, Vec<u8>) {
    let mut bin = Vec::new();
    for x in [0f32, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0] {
        bin.extend_from_slice(&x.to_le_bytes());
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    bin.extend_from_slice(&[0; 4]);
    let json = json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 32},
            {"buffer": 0, "byteOffset": 32, "byteLength": 12},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
        ],
        "images": [{"uri": "a.png"}],
        "textures": [{"source": 0}],
        "materials": [{"alphaMode": "MASK", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "meshes": [{"primitives": [{"attributes": {"TEXCOORD_0": 0}, "indices": 1, "material": 0}]}],
    });
    (json, bin)
}

/// Reads `json` with `bin` as buffer 0's `data:` URI (unless it has a
/// URI); the image URI `a.png` resolves to [`tiny_png`], others fail.
fn read_with(json: &Value, bin: &[u8], limits: &Limits) -> Result<GltfAsset, AssetError> {
    let mut json = json.clone();
    if let Some(buffer) = json.pointer_mut("/buffers/0") {
        if buffer.get("uri").is_none() {
            buffer["uri"] = json!(format!(
                "data:application/octet-stream;base64,{}",
                base64(bin)
            ));
        }
    }
    let text = serde_json::to_vec(&json).unwrap();
    let mut resolve = |uri: &str| -> Result<Vec<u8>, AssetError> {
        if uri == "a.png" {
            Ok(tiny_png())
        } else {
            Err(AssetError::Io {
                path: uri.to_string(),
                message: "no such file".to_string(),
            })
        }
    };
    read_gltf_bytes(&text, &mut resolve, limits)
}

fn push(array: &mut Value, value: Value) {
    array.as_array_mut().expect("an array").push(value);
}

fn read(json: &Value, bin: &[u8]) -> Result<GltfAsset, AssetError> {
    read_with(json, bin, &Limits::default())
}

fn error(json: &Value, bin: &[u8]) -> String {
    match read(json, bin) {
        Ok(asset) => panic!("accepted: {asset:?}"),
        Err(error) => error.to_string(),
    }
}

const QUAD: [[[f32; 2]; 3]; 2] = [
    [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]],
    [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
];

#[test]
fn gltf_fixture_reads() {
    let (json, bin) = fixture();
    let asset = read(&json, &bin).unwrap();
    assert_eq!(asset.warnings, Vec::<String>::new());
    assert_eq!(asset.primitives.len(), 1);
    let p = &asset.primitives[0];
    assert_eq!(
        (
            p.mesh,
            p.primitive,
            p.material,
            p.texture,
            p.image,
            p.tex_coord
        ),
        (0, 0, 0, 0, 0, 0)
    );
    assert_eq!((p.cutoff.alpha(), p.alpha_factor), (0.5, 1.0));
    // glTF's defaults: REPEAT both ways, no magFilter (read as linear).
    assert_eq!(
        p.sampler,
        Sampler {
            filter: Filter::Linear,
            ..Sampler::default()
        }
    );
    assert_eq!(p.triangles, QUAD);
    assert_eq!(asset.images, [decode(&tiny_png())]);
    assert_eq!(asset.image_info[0].uri.as_deref(), Some("a.png"));
}

#[test]
fn gltf_glb_container() {
    let (mut json, bin) = fixture();
    json["buffers"][0] = json!({"byteLength": bin.len()});
    let glb = |json: &Value, bin: &[u8], pad_json: u8| {
        let mut text = serde_json::to_vec(json).unwrap();
        while text.len() % 4 != 0 {
            text.push(pad_json);
        }
        let mut out = b"glTF".to_vec();
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&((28 + text.len() + bin.len()) as u32).to_le_bytes());
        out.extend_from_slice(&(text.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&text);
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(bin);
        out
    };
    let mut resolve = |_: &str| Ok(tiny_png());
    let limits = Limits::default();
    let bytes = glb(&json, &bin, b' ');
    let asset = read_gltf_bytes(&bytes, &mut resolve, &limits).unwrap();
    assert_eq!(asset.primitives[0].triangles, QUAD);
    assert_eq!(asset.warnings, Vec::<String>::new());
    // NUL padding of the JSON chunk is accepted.
    assert!(read_gltf_bytes(&glb(&json, &bin, 0), &mut resolve, &limits).is_ok());
    let mut errors = Vec::new();
    let mut try_bytes = |bytes: &[u8]| match read_gltf_bytes(bytes, &mut resolve, &limits) {
        Ok(asset) => format!("ok {:?}", asset.warnings),
        Err(e) => e.to_string(),
    };
    errors.push(try_bytes(&bytes[..10]));
    let mut v1 = bytes.clone();
    v1[4] = 1;
    errors.push(try_bytes(&v1));
    errors.push(try_bytes(&bytes[..bytes.len() - 4]));
    let mut longer = bytes.clone();
    longer.extend_from_slice(&[0; 4]);
    errors.push(try_bytes(&longer));
    let mut not_json = bytes.clone();
    not_json[16..20].copy_from_slice(b"JSOX");
    errors.push(try_bytes(&not_json));
    let mut overrun = bytes.clone();
    overrun[12..16].copy_from_slice(&10_000u32.to_le_bytes());
    errors.push(try_bytes(&overrun));
    // Without its BIN chunk, buffer 0 has no data.
    let json_len = u32::from_le_bytes([bytes[12], bytes[13], bytes[14], bytes[15]]) as usize;
    let mut no_bin = bytes[..20 + json_len].to_vec();
    no_bin[8..12].copy_from_slice(&((20 + json_len) as u32).to_le_bytes());
    errors.push(try_bytes(&no_bin));
    let total = bytes.len();
    assert_eq!(
        errors,
        [
            "GLB container: 10 bytes, shorter than the 12-byte header".to_string(),
            "GLB container: version 1, expected 2".to_string(),
            format!("GLB container: header says {total} bytes, the data has {} (truncated?)", total - 4),
            format!("ok [\"GLB: 4 bytes after the length of {total} in the header ignored\"]"),
            "GLB container: the first chunk has type 0x584f534a, expected JSON (0x4e4f534a)".to_string(),
            format!("GLB container: chunk 0 at offset 12: length 10000 runs past the end ({total} bytes)"),
            "buffers[0].uri: missing, and there is no GLB BIN chunk to stand for buffer 0".to_string(),
        ]
    );
}

#[test]
fn gltf_quantized_sparse_and_unindexed_uvs() {
    let (mut json, mut bin) = fixture();
    // UNSIGNED_BYTE normalized UVs at byte 44: c / 255.
    let start = bin.len();
    bin.extend_from_slice(&[0, 0, 255, 0, 255, 51, 1, 255]);
    push(
        &mut json["bufferViews"],
        json!({"buffer": 0, "byteOffset": start, "byteLength": 8}),
    );
    json["buffers"][0]["byteLength"] = json!(bin.len());
    json["accessors"][0] = json!({"bufferView": 2, "componentType": 5121, "normalized": true, "count": 4, "type": "VEC2"});
    let asset = read(&json, &bin).unwrap();
    let expected_v = 51.0f32 / 255.0;
    assert_eq!(asset.primitives[0].triangles[0][2], [1.0, expected_v]);
    assert_eq!(asset.primitives[0].triangles[1][2], [1.0 / 255.0, 1.0]);
    // UNSIGNED_SHORT normalized through a stride of 8 (4 UV pairs of u16 in
    // the first 32 bytes, every other one used: 4 elements need 3 * 8 + 4).
    json["bufferViews"][0]["byteStride"] = json!(8);
    json["accessors"][0] = json!({"bufferView": 0, "componentType": 5123, "normalized": true, "count": 4, "type": "VEC2"});
    let asset = read(&json, &bin).unwrap();
    // Float 1.0 is 0x3f800000: low u16 0, high u16 0x3f80.
    assert_eq!(
        asset.primitives[0].triangles[0][1],
        [0.0, f32::from(0x3f80u16) / 65535.0]
    );
    // Non-normalized SHORT (KHR_mesh_quantization): the integers.
    json["accessors"][0]["componentType"] = json!(5122);
    json["accessors"][0]["normalized"] = json!(false);
    let asset = read(&json, &bin).unwrap();
    assert_eq!(
        asset.primitives[0].triangles[0][1],
        [0.0, f32::from(0x3f80u16)]
    );
    // Sparse: no buffer view (zeros), two substituted vertices.
    let (mut json, mut bin) = fixture();
    let start = bin.len();
    bin.extend_from_slice(&[1, 2, 0, 0]);
    for x in [0.25f32, 0.5, 0.75, 1.0] {
        bin.extend_from_slice(&x.to_le_bytes());
    }
    json["buffers"][0]["byteLength"] = json!(bin.len());
    push(
        &mut json["bufferViews"],
        json!({"buffer": 0, "byteOffset": start, "byteLength": 4}),
    );
    push(
        &mut json["bufferViews"],
        json!({"buffer": 0, "byteOffset": start + 4, "byteLength": 16}),
    );
    json["accessors"][0] = json!({"componentType": 5126, "count": 4, "type": "VEC2", "sparse": {
        "count": 2, "indices": {"bufferView": 2, "componentType": 5121}, "values": {"bufferView": 3}}});
    let asset = read(&json, &bin).unwrap();
    assert_eq!(
        asset.primitives[0].triangles,
        [
            [[0.0, 0.0], [0.25, 0.5], [0.75, 1.0]],
            [[0.0, 0.0], [0.75, 1.0], [0.0, 0.0]]
        ]
    );
    json["accessors"][0]["sparse"]["count"] = json!(5);
    assert_eq!(
        error(&json, &bin),
        "accessors[0].sparse.count: 5, expected 1..=4 (the accessor's count)"
    );
    json["accessors"][0]["sparse"]["count"] = json!(2);
    bin[start] = 4;
    assert_eq!(
        error(&json, &bin),
        "accessors[0].sparse.indices.bufferView: sparse index 0 is 4, past the accessor's count 4"
    );
    // No indices: vertices in order; 4 vertices make one triangle and a
    // warning.
    let (mut json, bin) = fixture();
    json["meshes"][0]["primitives"][0]
        .as_object_mut()
        .unwrap()
        .remove("indices");
    let asset = read(&json, &bin).unwrap();
    assert_eq!(
        asset.primitives[0].triangles,
        [[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]]
    );
    assert_eq!(
        asset.warnings,
        ["meshes[0].primitives[0]: 4 vertices, not a multiple of 3: the last 1 ignored"]
    );
}

#[test]
fn gltf_materials_samplers_and_warnings() {
    let (mut json, bin) = fixture();
    json["samplers"] = json!([{"wrapS": CLAMP_TO_EDGE, "wrapT": MIRRORED_REPEAT, "magFilter": NEAREST, "minFilter": 9987}]);
    json["textures"][0]["sampler"] = json!(0);
    push(&mut json["textures"], json!({"source": 0}));
    // alphaCutoff and baseColorFactor are rounded once from their text.
    json["materials"][0] = serde_json::from_str(
        r#"{"alphaMode": "MASK", "alphaCutoff": 1.00000005960464477539062500001,
            "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.25], "baseColorTexture": {"index": 0,
            "extensions": {"KHR_texture_transform": {"scale": [2, 2]}}}}}"#,
    )
    .unwrap();
    push(
        &mut json["materials"],
        json!({"alphaMode": "MASK", "alphaCutoff": 0.3, "pbrMetallicRoughness": {"baseColorTexture": {"index": 1}}}),
    );
    push(&mut json["materials"], json!({"alphaMode": "BLEND"}));
    push(&mut json["materials"], json!({"alphaMode": "MASK"}));
    let primitive = json["meshes"][0]["primitives"][0].clone();
    let with = |material: Option<u64>, mode: Option<u64>| {
        let mut p = primitive.clone();
        match material {
            Some(m) => p["material"] = json!(m),
            None => {
                p.as_object_mut().unwrap().remove("material");
            }
        }
        if let Some(mode) = mode {
            p["mode"] = json!(mode);
        }
        p
    };
    let mut colored = with(Some(1), None);
    // COLOR_0 without a buffer view: zeros, alpha 0.
    push(
        &mut json["accessors"],
        json!({"componentType": 5126, "count": 4, "type": "VEC4"}),
    );
    colored["attributes"]["COLOR_0"] = json!(2);
    json["meshes"][0]["primitives"] = json!([
        with(Some(0), Some(4)),
        colored,
        with(Some(2), None),
        with(None, None),
        with(Some(3), None),
        with(Some(0), Some(5))
    ]);
    push(
        &mut json["meshes"],
        json!({"primitives": [with(Some(1), None)]}),
    );
    // serde_json's `json!` writes 1.0000000596046448 for the cutoff above;
    // keep the decimal text.
    let mut text = serde_json::to_string(&json).unwrap();
    text = text.replace("1.0000000596046448", "1.00000005960464477539062500001");
    let json: Value = serde_json::from_str(&text).unwrap();
    let mut with_data = json.clone();
    with_data["buffers"][0]["uri"] = json!(format!(
        "data:application/octet-stream;base64,{}",
        base64(&bin)
    ));
    let text = serde_json::to_string(&with_data)
        .unwrap()
        .replace("1.0000000596046448", "1.00000005960464477539062500001");
    let mut resolve = |_: &str| Ok(tiny_png());
    let asset = read_gltf_bytes(text.as_bytes(), &mut resolve, &Limits::default()).unwrap();
    let summary: Vec<(usize, usize, usize, f32, f32)> = asset
        .primitives
        .iter()
        .map(|p| {
            (
                p.mesh,
                p.primitive,
                p.material,
                p.cutoff.alpha(),
                p.alpha_factor,
            )
        })
        .collect();
    assert_eq!(
        summary,
        [
            (0, 0, 0, 1.0 + f32::EPSILON, 0.25),
            (0, 1, 1, 0.3, 1.0),
            (1, 0, 1, 0.3, 1.0)
        ]
    );
    assert_eq!(
        asset.primitives[0].sampler,
        Sampler {
            filter: Filter::Nearest,
            address_u: AddressMode::ClampToEdge,
            address_v: AddressMode::MirroredRepeat,
            border_alpha: 0.0
        }
    );
    assert_eq!(
        asset.primitives[1].sampler,
        Sampler {
            filter: Filter::Linear,
            ..Sampler::default()
        }
    );
    // One image, decoded once, for two textures.
    assert_eq!(asset.images.len(), 1);
    assert!(asset.primitives.iter().all(|p| p.image == 0));
    assert_eq!(
        asset.warnings,
        [
            "meshes[0].primitives[5]: mode 5 (TRIANGLE_STRIP) is not TRIANGLES (4), skipped",
            "skipped 2 primitives whose material is not alphaMode MASK (1 OPAQUE, 1 BLEND)",
            "materials[3] is alphaMode MASK without pbrMetallicRoughness.baseColorTexture: 1 primitive skipped",
            "1 primitive has COLOR_0 alpha, multiplied in with bounds per triangle (texels near the cutoff may bake unknown): meshes[0].primitives[1]",
            "materials[0].pbrMetallicRoughness.baseColorTexture has KHR_texture_transform: modelled as the shader applies it to the interpolated UV (binary32)",
        ]
    );
}

#[test]
fn gltf_uris() {
    let (mut json, bin) = fixture();
    // Percent-decoded before the resolver; an unknown file is the
    // resolver's error, in context.
    json["images"][0]["uri"] = json!("leaf%20a.png");
    let text = serde_json::to_vec(&{
        let mut j = json.clone();
        j["buffers"][0]["uri"] = json!(format!(
            "data:application/octet-stream;base64,{}",
            base64(&bin)
        ));
        j
    })
    .unwrap();
    let mut asked = Vec::new();
    let mut resolve = |uri: &str| {
        asked.push(uri.to_string());
        Ok(tiny_png())
    };
    read_gltf_bytes(&text, &mut resolve, &Limits::default()).unwrap();
    assert_eq!(asked, ["leaf a.png"]);
    // The image as a data: URI.
    json["images"][0]["uri"] = json!(format!("data:image/png;base64,{}", base64(&tiny_png())));
    assert_eq!(read(&json, &bin).unwrap().images[0], decode(&tiny_png()));
    for (uri, message) in [
        ("a.jpg", "images[0] (uri \"a.jpg\"): cannot read a.jpg: no such file"),
        ("http://example.com/a.png", "images[0] (uri \"http://example.com/a.png\"): URI \"http://example.com/a.png\": only relative paths and data: URIs are supported"),
        ("a%2.png", "images[0] (uri \"a%2.png\"): URI \"a%2.png\": '%' at byte 1 is not followed by two hex digits"),
        ("data:image/png;base64,iVBO!A==", "images[0] (uri \"data:image/png;base64,...\"): URI \"data:image/png;base64,...\": base64: byte 4 ('!') is not a base64 character"),
        ("data:image/png;base64", "images[0] (uri \"data:image/png;base64,...\"): URI \"data:image/png;base64,...\": data: URI without ','"),
        ("data:,GIF89a", "images[0] (uri \"data:,...\"): not a PNG or JPEG image (starts with 47 49 46 38 39 61)"),
    ] {
        json["images"][0]["uri"] = json!(uri);
        assert_eq!(error(&json, &bin), message, "{uri}");
    }
    let (mut json, bin) = fixture();
    json["buffers"][0]["uri"] = json!("geometry.bin");
    assert_eq!(
        error(&json, &bin),
        "buffers[0] (uri \"geometry.bin\"): cannot read geometry.bin: no such file"
    );
}

#[test]
fn gltf_structure_errors() {
    let (base, bin) = fixture();
    let cases: Vec<(&str, Value, &str)> = vec![
        ("/asset", json!(null), "asset: null, expected an object"),
        ("/asset/version", json!("1.0"), "asset.version: \"1.0\": only glTF 2.x is supported"),
        ("/extensionsRequired", json!(["KHR_mesh_quantization", "KHR_draco_mesh_compression"]), "extensionsRequired[1]: the asset requires extension KHR_draco_mesh_compression, which is not supported"),
        ("/meshes", json!({}), "meshes: an object {}, expected an array"),
        ("/meshes/0/primitives/0/material", json!(7), "meshes[0].primitives[0].material: materials[7] does not exist (1 materials)"),
        ("/meshes/0/primitives/0/material", json!(-1), "meshes[0].primitives[0].material: a number -1, expected a non-negative integer"),
        ("/materials/0/alphaMode", json!("CUTOUT"), "materials[0].alphaMode: \"CUTOUT\" is not OPAQUE, MASK or BLEND"),
        ("/materials/0/alphaCutoff", json!(-0.5), "materials[0].alphaCutoff: a number -0.5, expected a number >= 0"),
        ("/materials/0/alphaCutoff", json!("0.5"), "materials[0].alphaCutoff: a string \"0.5\", expected a number >= 0"),
        ("/materials/0/pbrMetallicRoughness/baseColorFactor", json!([1, 1, 1]), "materials[0].pbrMetallicRoughness.baseColorFactor: an array [1,1,1], expected an array of 4 numbers"),
        ("/materials/0/pbrMetallicRoughness/baseColorTexture/texCoord", json!(1), "meshes[0].primitives[0].attributes.TEXCOORD_1: missing, but materials[0].pbrMetallicRoughness.baseColorTexture.texCoord = 1"),
        ("/materials/0/pbrMetallicRoughness/baseColorTexture/index", json!(3), "materials[0].pbrMetallicRoughness.baseColorTexture.index: textures[3] does not exist (1 textures)"),
        ("/textures/0", json!({"sampler": 0}), "textures[0].sampler: samplers[0] does not exist (0 samplers)"),
        ("/textures/0", json!({}), "textures[0].source: missing (images only in an extension, such as KHR_texture_basisu, are not supported)"),
        ("/images/0", json!({}), "images[0].uri: missing, and no bufferView either"),
        ("/images/0", json!({"uri": "a.png", "bufferView": 0}), "images[0].uri: given together with bufferView"),
        ("/images/0", json!({"bufferView": 0}), "images[0] (bufferViews[0]): not a PNG or JPEG image (starts with 00 00 00 00 00 00 00 00)"),
        ("/accessors/0/count", json!(5), "accessors[0].count: 5 elements of 8 bytes, stride 8, from byte 0 run past the end of bufferViews[0] (32 bytes)"),
        ("/accessors/0/byteOffset", json!(4), "accessors[0].count: 4 elements of 8 bytes, stride 8, from byte 4 run past the end of bufferViews[0] (32 bytes)"),
        ("/accessors/0/count", json!(18446744073709551615u64), "accessors[0] (18446744073709551615 elements) (bytes, with what is already loaded): 18446744073709551615 is over the limit of 1073741824"),
        ("/accessors/0/type", json!("VEC3"), "accessors[0].type: \"VEC3\", expected \"VEC2\" for meshes[0].primitives[0].attributes.TEXCOORD_0"),
        ("/accessors/0/componentType", json!(5125), "accessors[0].componentType: 5125 (UNSIGNED_INT) is not a texture coordinate type (FLOAT, or UNSIGNED_BYTE, UNSIGNED_SHORT, BYTE, SHORT)"),
        ("/accessors/0/componentType", json!(1), "accessors[0].componentType: 1 is not a glTF component type"),
        ("/accessors/1/componentType", json!(5126), "accessors[1].componentType: 5126 (FLOAT), expected UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT for indices"),
        ("/accessors/0/bufferView", json!(9), "accessors[0].bufferView: bufferViews[9] does not exist (2 bufferViews)"),
        ("/bufferViews/0/byteStride", json!(6), "bufferViews[0].byteStride: 6, expected a multiple of 4 in 4..=252"),
        ("/bufferViews/0/byteStride", json!(4), "accessors[0].bufferView: bufferViews[0].byteStride 4 is less than the element size 8"),
        ("/bufferViews/1/byteOffset", json!(40), "bufferViews[1].byteLength: bytes 40..40+12 run past the end of buffers[0] (48 bytes)"),
        ("/bufferViews/1/buffer", json!(1), "bufferViews[1].buffer: buffers[1] does not exist (1 buffers)"),
        ("/buffers/0/byteLength", json!(49), "buffers[0].byteLength: 49, but the data has 48 bytes"),
        ("/meshes/0/primitives/0/attributes/TEXCOORD_0", json!("0"), "meshes[0].primitives[0].attributes.TEXCOORD_0: a string \"0\", expected a non-negative integer"),
        ("/meshes/0/primitives/0/attributes", json!([]), "meshes[0].primitives[0].attributes: an array [], expected an object"),
        ("/meshes/0/primitives/0/indices", json!(0), "accessors[0].type: \"VEC2\", expected \"SCALAR\" for meshes[0].primitives[0].indices"),
    ];
    for (pointer, value, message) in cases {
        let mut json = base.clone();
        let (parent, key) = pointer.rsplit_once('/').unwrap();
        let target = json
            .pointer_mut(parent)
            .unwrap_or_else(|| panic!("{pointer}"));
        match target {
            Value::Object(map) => {
                map.insert(key.to_string(), value);
            }
            Value::Array(items) => {
                let i: usize = key.parse().unwrap();
                items[i] = value;
            }
            _ => panic!("{pointer}"),
        }
        assert_eq!(error(&json, &bin), message, "{pointer}");
    }
    // Samplers: a bad code, once a texture uses the sampler.
    let mut json = base.clone();
    json["samplers"] = json!([{"wrapS": 1234}]);
    json["textures"][0]["sampler"] = json!(0);
    assert_eq!(
        error(&json, &bin),
        "samplers[0].wrapS: 1234 is not one of the glTF codes [10497, 33071, 33648]"
    );
    // An index past the UVs.
    let mut bin2 = bin.clone();
    bin2[32 + 4] = 4;
    assert_eq!(
        error(&base, &bin2),
        "meshes[0].primitives[0].indices: index 2 is 4, past the 4 texture coordinates"
    );
    // Not JSON, not an object.
    let mut resolve = |_: &str| Ok(tiny_png());
    let limits = Limits::default();
    let text_error =
        |bytes: &[u8], resolve: &mut dyn FnMut(&str) -> Result<Vec<u8>, AssetError>| {
            read_gltf_bytes(bytes, resolve, &limits)
                .unwrap_err()
                .to_string()
        };
    assert_eq!(
        text_error(b"{", &mut resolve),
        "invalid JSON: EOF while parsing an object at line 1 column 1"
    );
    assert_eq!(
        text_error(b"[]", &mut resolve),
        "(top level): is not a JSON object"
    );
    assert_eq!(text_error(b"{}", &mut resolve), "asset: missing");
}

#[test]
fn gltf_limits() {
    let (json, bin) = fixture();
    // Pixels: the 2 x 2 image.
    let error = read_with(
        &json,
        &bin,
        &Limits {
            max_pixels: 3,
            max_bytes: 1 << 20,
            ..Limits::default()
        },
    )
    .unwrap_err();
    assert_eq!(
        error.to_string(),
        "images[0] (uri \"a.png\"): PNG image of 2 x 2 pixels: 4 is over the limit of 3"
    );
    // Bytes: the buffer (48) + UVs (32) + indices (24) + triangles (48) =
    // 152 before the image.
    assert!(read_with(
        &json,
        &bin,
        &Limits {
            max_pixels: 4,
            max_bytes: 1 << 20,
            ..Limits::default()
        }
    )
    .is_ok());
    let error = read_with(
        &json,
        &bin,
        &Limits {
            max_pixels: 4,
            max_bytes: 151,
            ..Limits::default()
        },
    )
    .unwrap_err();
    assert_eq!(
        error.to_string(),
        "meshes[0].primitives[0] (2 triangles) (bytes, with what is already loaded): 152 is over the limit of 151"
    );
    // Many primitives on one big accessor hit the budget, not the memory.
    let mut json = json.clone();
    push(
        &mut json["accessors"],
        json!({"componentType": 5126, "count": 300_000, "type": "VEC2"}),
    );
    let primitive = json!({"attributes": {"TEXCOORD_0": 2}, "material": 0});
    json["meshes"][0]["primitives"] = json!(vec![primitive; 100]);
    let limits = Limits {
        max_pixels: 4,
        max_bytes: 10_000_000,
        ..Limits::default()
    };
    let Err(error) = read_with(&json, &bin, &limits) else {
        panic!("accepted");
    };
    // UVs 2.4 MB once, triangles 2.4 MB per primitive, the image 4 bytes.
    assert_eq!(
        error.root(),
        &AssetError::LimitExceeded {
            what: "meshes[0].primitives[3] (100000 triangles) (bytes, with what is already loaded)"
                .to_string(),
            size: 12_000_004,
            limit: 10_000_000,
        }
    );
}

#[test]
fn errors_display_on_one_line_and_chain() {
    let error = AssetError::Gltf {
        field: "accessors[3].count".into(),
        message: "missing".into(),
    }
    .within("scene.gltf");
    assert_eq!(error.to_string(), "scene.gltf: accessors[3].count: missing");
    assert!(std::error::Error::source(&error).is_some());
    assert_eq!(
        error.root(),
        &AssetError::Gltf {
            field: "accessors[3].count".into(),
            message: "missing".into()
        }
    );
    let error =
        super::read_gltf_file(Path::new("/nonexistent/x.gltf"), &Limits::default()).unwrap_err();
    assert!(
        error
            .to_string()
            .starts_with("cannot read /nonexistent/x.gltf: "),
        "{error}"
    );
    assert!(!error.to_string().contains('\n'));
}

/// The fixture's mesh placed by `nodes` (and `scenes`, if given).
fn placed(nodes: Value, scenes: Option<Value>) -> GltfAsset {
    let (mut json, bin) = fixture();
    json["nodes"] = nodes;
    if let Some(scenes) = scenes {
        json["scenes"] = scenes;
    }
    read(&json, &bin).unwrap()
}

#[test]
fn gltf_node_transforms_place_the_mesh() {
    // No nodes: the mesh once, in its own space.
    let (json, bin) = fixture();
    assert_eq!(
        read(&json, &bin).unwrap().primitives[0].instances,
        [IDENTITY_TRANSFORM]
    );
    // A parent's translation and scale, a child's matrix (column-major:
    // x -> y, y -> -x, translate z by 3), composed root first.
    let asset = placed(
        json!([
            {"translation": [1, 2, 3], "scale": [2, 2, 2], "children": [1]},
            {"matrix": [0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 3, 1], "mesh": 0},
            {"mesh": 0, "rotation": [0, 0, 0, 2]},
        ]),
        None,
    );
    assert_eq!(asset.warnings, Vec::<String>::new());
    assert_eq!(
        asset.primitives[0].instances,
        [
            [0.0, -2.0, 0.0, 1.0, 2.0, 0.0, 0.0, 2.0, 0.0, 0.0, 2.0, 9.0],
            // Not a child of another node: a root too (no scenes). Its
            // quaternion is normalised.
            IDENTITY_TRANSFORM,
        ]
    );
    // The default scene holds only node 2; a node outside it places
    // nothing, a scene without the mesh's node leaves it unplaced.
    let nodes = json!([{"mesh": 0, "translation": [5, 0, 0]}, {}, {"mesh": 0}]);
    let asset = placed(nodes.clone(), Some(json!([{"nodes": [0]}, {"nodes": [1]}])));
    assert_eq!(
        asset.primitives[0].instances,
        [[1.0, 0.0, 0.0, 5.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0]]
    );
    let (mut json, bin) = fixture();
    json["nodes"] = nodes;
    json["scenes"] = json!([{"nodes": [0]}, {"nodes": [1]}]);
    json["scene"] = json!(1);
    assert!(read(&json, &bin).unwrap().primitives[0]
        .instances
        .is_empty());
}

#[test]
fn gltf_malformed_node_trees_are_warnings_not_errors() {
    for (nodes, why) in [
        (
            json!([{"children": [1]}, {"children": [0], "mesh": 0}]),
            "reached twice",
        ),
        (json!([{"children": [7]}]), "nodes[7] does not exist"),
        (json!([{"mesh": 3}]), "meshes[3] does not exist"),
        (
            json!([{"mesh": 0, "scale": [1, 1]}]),
            "expected 3 finite numbers",
        ),
        (
            json!([{"mesh": 0, "rotation": [0, 0, 0, 0]}]),
            "a zero quaternion",
        ),
        (
            json!([{"mesh": 0, "translation": [1e39, 0, 0]}]),
            "not finite in binary32",
        ),
    ] {
        let asset = placed(nodes, Some(json!([{"nodes": [0]}])));
        // The bake's input is unchanged; the mesh is drawn once, unplaced.
        assert_eq!(asset.primitives[0].triangles, QUAD);
        assert_eq!(asset.primitives[0].instances, [IDENTITY_TRANSFORM]);
        assert_eq!(asset.warnings.len(), 1, "{why}");
        assert!(
            asset.warnings[0].contains(why),
            "{why}: {:?}",
            asset.warnings
        );
    }
}

#[test]
fn gltf_committed_assets_are_placed_by_their_nodes() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/");
    let fern = read_gltf_file(
        format!("{root}polyhaven-fern02/fern_02.gltf").as_ref(),
        &Limits::default(),
    )
    .unwrap();
    // Four meshes, one node each; three translated by about 1 in x or z.
    let offsets: Vec<[f32; 3]> = fern
        .primitives
        .iter()
        .map(|p| {
            assert_eq!(p.instances.len(), 1);
            let t = p.instances[0];
            [t[3], t[7], t[11]]
        })
        .collect();
    assert_eq!(offsets[0], [0.0, 0.0, 0.0]);
    assert!(offsets[1][0] > 0.99 && offsets[2][2] > 0.99 && offsets[3][0] > 0.99);
}

/// `KHR_materials_variants` is not modelled: the primitive's default
/// material is read, and a warning says so (issue 34: variants were
/// ignored without a word).
#[test]
fn material_variants_are_named_in_a_warning() {
    let (mut json, bin) = fixture();
    json["extensionsUsed"] = json!(["KHR_materials_variants"]);
    json["meshes"][0]["primitives"][0]["extensions"] = json!({
        "KHR_materials_variants": {"mappings": [
            {"material": 0, "variants": [0]},
            {"material": 0, "variants": [1]},
        ]}
    });
    let asset = read(&json, &bin).unwrap();
    assert_eq!(asset.primitives.len(), 1);
    assert_eq!(
        asset.warnings,
        [
            "meshes[0].primitives[0]: KHR_materials_variants maps 2 variant material(s); only the \
          primitive's default material (materials[0]) is read, so a variant's look needs a bake \
          of its own"
        ]
    );
}

// ------------------------------------------------- EXT_mesh_gpu_instancing

/// Little-endian `f32`s.
fn f32_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// Appends `bytes` to `bin` (from a multiple of 4) as a buffer view of its
/// own and `accessor` (its `bufferView` set) to `json`; the accessor's
/// index.
fn add_accessor(json: &mut Value, bin: &mut Vec<u8>, mut accessor: Value, bytes: &[u8]) -> usize {
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    push(
        &mut json["bufferViews"],
        json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len()}),
    );
    bin.extend_from_slice(bytes);
    json["buffers"][0]["byteLength"] = json!(bin.len());
    accessor["bufferView"] = json!(json["bufferViews"].as_array().unwrap().len() - 1);
    push(&mut json["accessors"], accessor);
    json["accessors"].as_array().unwrap().len() - 1
}

/// A `FLOAT` accessor of `type` (`VEC3`, `VEC4`) holding `values`.
fn float_accessor(json: &mut Value, bin: &mut Vec<u8>, ty: &str, values: &[f32]) -> usize {
    let components = if ty == "VEC3" { 3 } else { 4 };
    add_accessor(
        json,
        bin,
        json!({"componentType": 5126, "count": values.len() / components, "type": ty}),
        &f32_bytes(values),
    )
}

/// The fixture with `nodes` (scene 0 holds node 0) after `build` added its
/// accessors; read.
fn instanced(build: impl FnOnce(&mut Value, &mut Vec<u8>) -> Value) -> GltfAsset {
    instanced_with(build, &Limits::default())
}

fn instanced_with(
    build: impl FnOnce(&mut Value, &mut Vec<u8>) -> Value,
    limits: &Limits,
) -> GltfAsset {
    let (mut json, mut bin) = fixture();
    let nodes = build(&mut json, &mut bin);
    json["nodes"] = nodes;
    json["scenes"] = json!([{"nodes": [0]}]);
    read_with(&json, &bin, limits).unwrap()
}

/// Three instances (a translation; a translation, a quarter turn about z
/// and a non-uniform scale; a non-uniform scale with a translation) under
/// a node translated by 10 in x: each
/// instance is drawn at `node * T * R * S`, and the node itself is not
/// drawn; its child is placed by the node's own transform. The expected
/// matrices are worked out by hand (row-major 3x4).
#[test]
fn gltf_gpu_instancing_places_each_instance() {
    // Rz(90°): x -> y, y -> -x.
    let expected = [
        // T(10, 0, 0) * T(1, 2, 3)
        [1.0, 0.0, 0.0, 11.0, 0.0, 1.0, 0.0, 2.0, 0.0, 0.0, 1.0, 3.0],
        // T(10, 0, 0) * T(1, 0, 0) * Rz(90°) * S(1, 2, 1): the columns of
        // Rz scaled (S * Rz would scale its rows), the instance's
        // translation not rotated (Rz * T would make it (0, 1, 0)), the
        // node's neither (instance * node would put it at (0, 10, 0)).
        [0.0, -2.0, 0.0, 11.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0],
        // T(10, 0, 0) * T(0, -1, 0) * S(2, 3, 4)
        [2.0, 0.0, 0.0, 10.0, 0.0, 3.0, 0.0, -1.0, 0.0, 0.0, 4.0, 0.0],
        // The child: T(10, 0, 0) * T(0, 0, 5), once.
        [1.0, 0.0, 0.0, 10.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 5.0],
    ];
    let half = std::f32::consts::FRAC_1_SQRT_2;
    // ROTATION as FLOAT (the quarter turn rounded to binary32, normalised
    // by the reader), and as normalized BYTE and SHORT (127 and 32767 are
    // 1: the quaternion (0, 0, 1, 1), normalised).
    let byte_rotation = [0i8, 0, 0, 127, 0, 0, 127, 127, 0, 0, 0, 127];
    let short_rotation: Vec<u8> = [0i16, 0, 0, 32767, 0, 0, 32767, 32767, 0, 0, 0, 32767]
        .iter()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    for (name, rotation, required) in [
        ("float", 5126, "EXT_mesh_gpu_instancing"),
        ("byte", 5120, "EXT_mesh_gpu_instancing"),
        ("short", 5122, "KHR_mesh_gpu_instancing"),
    ] {
        let asset = instanced(|json, bin| {
            json["extensionsUsed"] = json!([required]);
            json["extensionsRequired"] = json!([required]);
            let t = float_accessor(
                json,
                bin,
                "VEC3",
                &[1.0, 2.0, 3.0, 1.0, 0.0, 0.0, 0.0, -1.0, 0.0],
            );
            let r = match rotation {
                5126 => float_accessor(
                    json,
                    bin,
                    "VEC4",
                    &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, half, half, 0.0, 0.0, 0.0, 1.0],
                ),
                5120 => add_accessor(
                    json,
                    bin,
                    json!({"componentType": 5120, "normalized": true, "count": 3, "type": "VEC4"}),
                    &byte_rotation.map(|c| c as u8),
                ),
                _ => add_accessor(
                    json,
                    bin,
                    json!({"componentType": 5122, "normalized": true, "count": 3, "type": "VEC4"}),
                    &short_rotation,
                ),
            };
            let s = float_accessor(
                json,
                bin,
                "VEC3",
                &[1.0, 1.0, 1.0, 1.0, 2.0, 1.0, 2.0, 3.0, 4.0],
            );
            json!([
                {
                    "mesh": 0,
                    "translation": [10, 0, 0],
                    "children": [1],
                    "extensions": {required: {"attributes": {"TRANSLATION": t, "ROTATION": r, "SCALE": s}}}
                },
                {"mesh": 0, "translation": [0, 0, 5]},
            ])
        });
        assert_eq!(asset.warnings, Vec::<String>::new(), "{name}");
        assert_eq!(asset.primitives[0].instances, expected, "{name}");
        // The bake's input is what it was.
        assert_eq!(asset.primitives[0].triangles, QUAD, "{name}");
    }
    // Only a custom attribute: as many instances, each the node's own
    // transform (a missing TRANSLATION, ROTATION or SCALE is the identity);
    // the extension on a node without a mesh is ignored.
    let asset = instanced(|json, bin| {
        let ids = add_accessor(
            json,
            bin,
            json!({"componentType": 5125, "count": 2, "type": "SCALAR"}),
            &[0, 0, 0, 0, 1, 0, 0, 0],
        );
        json!([
            {"mesh": 0, "translation": [0, 7, 0], "children": [1],
             "extensions": {"EXT_mesh_gpu_instancing": {"attributes": {"_ID": ids}}}},
            {"extensions": {"EXT_mesh_gpu_instancing": {}}},
        ])
    });
    assert_eq!(asset.warnings, Vec::<String>::new());
    let seven = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 7.0, 0.0, 0.0, 1.0, 0.0];
    assert_eq!(asset.primitives[0].instances, [seven, seven]);
}

/// A malformed `EXT_mesh_gpu_instancing` is a malformed node tree: a
/// warning saying why, the mesh drawn once unplaced, the bake's input
/// unchanged; never an error or a panic. An extension without attributes
/// (or with none in them) is malformed: the schema asks for at least one,
/// and without one the instance count is not defined.
#[test]
fn gltf_malformed_gpu_instancing_is_a_warning() {
    type Build = Box<dyn Fn(&mut Value, &mut Vec<u8>) -> Value>;
    let node = |ext: Value| json!([{"mesh": 0, "extensions": {"EXT_mesh_gpu_instancing": ext}}]);
    let three = [0.0f32; 9];
    let cases: Vec<(Build, &str)> = vec![
        (
            Box::new(move |json, bin| {
                let t = float_accessor(json, bin, "VEC3", &three);
                let s = float_accessor(json, bin, "VEC3", &three[..6]);
                node(json!({"attributes": {"TRANSLATION": t, "SCALE": s}}))
            }),
            "TRANSLATION has 3 instances but SCALE has 2 (all attributes must have the same count)",
        ),
        (
            Box::new(move |_, _| node(json!({}))),
            "no attributes, so no instance count",
        ),
        (
            Box::new(move |_, _| node(json!({"attributes": {}}))),
            "no attributes, so no instance count",
        ),
        (
            Box::new(move |_, _| node(json!({"attributes": {"TRANSLATION": 99}}))),
            "accessors[99] does not exist",
        ),
        (
            Box::new(move |_, _| node(json!({"attributes": {"TRANSLATION": "zero"}}))),
            "expected a non-negative integer",
        ),
        (
            Box::new(move |json, bin| {
                let t = float_accessor(json, bin, "VEC4", &[0.0; 8]);
                node(json!({"attributes": {"TRANSLATION": t}}))
            }),
            "expected \"VEC3\"",
        ),
        (
            Box::new(move |json, bin| {
                let r = add_accessor(
                    json,
                    bin,
                    json!({"componentType": 5120, "count": 1, "type": "VEC4"}),
                    &[0, 0, 0, 127],
                );
                node(json!({"attributes": {"ROTATION": r}}))
            }),
            "expected FLOAT or normalized BYTE or SHORT for ROTATION",
        ),
        (
            Box::new(move |json, bin| {
                let s = add_accessor(
                    json,
                    bin,
                    json!({"componentType": 5123, "normalized": true, "count": 1, "type": "VEC3"}),
                    &[0; 6],
                );
                node(json!({"attributes": {"SCALE": s}}))
            }),
            "expected FLOAT for SCALE",
        ),
        (
            Box::new(move |json, bin| {
                let t = float_accessor(json, bin, "VEC3", &[0.0, f32::NAN, 0.0]);
                node(json!({"attributes": {"TRANSLATION": t}}))
            }),
            "element 0 is [0.0, NaN, 0.0], not finite",
        ),
        (
            Box::new(move |json, bin| {
                let r =
                    float_accessor(json, bin, "VEC4", &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0]);
                node(json!({"attributes": {"ROTATION": r}}))
            }),
            "ROTATION: element 1 is a zero quaternion",
        ),
        (
            Box::new(move |json, bin| {
                let s = float_accessor(json, bin, "VEC3", &[1.0, 1.0, 1.0, 3e38, 1.0, 1.0]);
                let mut nodes = node(json!({"attributes": {"SCALE": s}}));
                nodes[0]["scale"] = json!([2, 2, 2]);
                nodes
            }),
            "nodes[0]: instance 1's world transform is not finite in binary32",
        ),
        (
            Box::new(move |json, bin| {
                let t = add_accessor(
                    json,
                    bin,
                    json!({"componentType": 5126, "count": 0, "type": "VEC3"}),
                    &[],
                );
                node(json!({"attributes": {"TRANSLATION": t}}))
            }),
            "a count of 0 instances",
        ),
        (
            Box::new(move |json, bin| {
                let t = float_accessor(json, bin, "VEC3", &three);
                json!([{"mesh": 0, "extensions": {
                    "EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": t}},
                    "KHR_mesh_gpu_instancing": {"attributes": {"TRANSLATION": t}},
                }}])
            }),
            "both EXT_mesh_gpu_instancing and KHR_mesh_gpu_instancing",
        ),
        // A count from the input, past the data: refused by the accessor
        // reader.
        (
            Box::new(move |json, bin| {
                let t = float_accessor(json, bin, "VEC3", &three);
                json["accessors"][t]["count"] = json!(4);
                node(json!({"attributes": {"TRANSLATION": t}}))
            }),
            "run past the end of bufferViews",
        ),
        // Without a buffer view, the count is zeros: the byte budget
        // refuses it before any allocation.
        (
            Box::new(move |json, _| {
                push(
                    &mut json["accessors"],
                    json!({"componentType": 5126, "count": 1u64 << 40, "type": "VEC3"}),
                );
                node(json!({"attributes": {"TRANSLATION": 2}}))
            }),
            "is over the limit",
        ),
    ];
    for (build, why) in cases {
        let asset = instanced(build);
        assert_eq!(asset.primitives[0].triangles, QUAD, "{why}");
        assert_eq!(asset.primitives[0].instances, [IDENTITY_TRANSFORM], "{why}");
        assert_eq!(asset.warnings.len(), 1, "{why}: {:?}", asset.warnings);
        assert!(
            asset.warnings[0].starts_with("node transforms not applied (")
                && asset.warnings[0].contains(why),
            "{why}: {:?}",
            asset.warnings
        );
    }
}

/// Instance transforms count against [`Limits::max_bytes`] (the decoded
/// attributes, the transforms, and each primitive's copy): over it, a
/// warning, never an allocation past the budget.
#[test]
fn gltf_gpu_instances_stay_within_the_byte_budget() {
    let build = |json: &mut Value, bin: &mut Vec<u8>| {
        let t = float_accessor(json, bin, "VEC3", &vec![0.0; 3 * 1000]);
        json!([{"mesh": 0, "extensions": {"EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": t}}}}])
    };
    let asset = instanced(build);
    assert_eq!(asset.warnings, Vec::<String>::new());
    assert_eq!(asset.primitives[0].instances.len(), 1000);
    // What the asset needs without the instances, plus a little: the
    // 1000 transforms (96 + 48 bytes each, and 48 for the primitive's
    // copy) do not fit.
    let (mut json, mut bin) = fixture();
    let needed = {
        let nodes = build(&mut json, &mut bin);
        json["nodes"] = nodes;
        let mut low = 0u64;
        let mut high = Limits::default().max_bytes;
        // The smallest budget that reads the asset with its instances.
        while low + 1 < high {
            let mid = (low + high) / 2;
            let limits = Limits {
                max_bytes: mid,
                ..Limits::default()
            };
            match read_with(&json, &bin, &limits) {
                Ok(a) if a.warnings.is_empty() => high = mid,
                _ => low = mid,
            }
        }
        high
    };
    let limits = Limits {
        max_bytes: needed - 1000 * 48,
        ..Limits::default()
    };
    let asset = read_with(&json, &bin, &limits).unwrap();
    assert_eq!(asset.primitives[0].instances, [IDENTITY_TRANSFORM]);
    assert_eq!(asset.warnings.len(), 1, "{:?}", asset.warnings);
    assert!(
        asset.warnings[0].contains("the primitives' instance transforms")
            && asset.warnings[0].contains("is over the limit"),
        "{:?}",
        asset.warnings
    );
}
