//! [`decode_alpha_image`] and [`decode_image_alpha`]: the alpha channel of
//! a PNG or JPEG, and what stands for it when the image has none.

use crate::alpha_image::{AlphaImage, AlphaTexels};
use crate::error::AssetError;
use crate::image_format::ImageFormat;
use crate::limits::{check_limit, Limits};
use std::io::Cursor;

/// What an image without an alpha channel stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MissingAlpha {
    /// Its grey value is the alpha: for a standalone alpha mask (a grey or
    /// black-and-white picture given as `--texture`), where the user names
    /// the image as the mask.
    Luminance,
    /// Alpha 1 everywhere: how glTF reads a base-colour image without an
    /// alpha channel (glTF 2.0, `pbrMetallicRoughness.baseColorTexture`: the
    /// fourth component, if present, is the alpha coverage; otherwise the
    /// coverage is 1).
    One,
}

/// Where the alpha of a decoded image came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AlphaSource {
    /// The image's own alpha channel (RGBA, grey + alpha, PNG `tRNS`).
    Channel,
    /// The image has no alpha channel; its grey value (or luma) was read
    /// as alpha ([`MissingAlpha::Luminance`]).
    Luminance,
    /// The image has no alpha channel; alpha is 1 everywhere
    /// ([`MissingAlpha::One`]).
    One,
}

/// Decodes a PNG or JPEG (told apart by signature, not by name) into one
/// channel: [`decode_image_alpha`] with [`MissingAlpha::Luminance`] (the
/// rule for a standalone alpha mask), without the [`AlphaSource`]:
///
/// * the **alpha** channel if the image has one: RGBA, grey + alpha, and
///   PNG `tRNS` transparency (expanded: a palette entry's alpha, or 0 for
///   the colour key and 255 elsewhere);
/// * otherwise its **grey value**: the grey channel of a grey image, and for
///   RGB (JPEG included) the luma `round(0.2126 R + 0.7152 G + 0.0722 B)`
///   (Rec. 709 weights on the stored, gamma-encoded values), computed
///   exactly in integers as `(2126 R + 7152 G + 722 B + 5000) / 10000`, so
///   halves round up.
///
/// glTF base-colour images are read with [`MissingAlpha::One`] instead.
///
/// 8-bit samples (and PNG's 1, 2 and 4-bit grey and palettes, scaled to 8
/// bits) give [`AlphaTexels::Unorm8`]; 16-bit samples (PNG, 16-bit lossless
/// JPEG) give [`AlphaTexels::Unorm16`], exactly as stored.
/// Palette PNGs are expanded. Of an animated PNG, the default image is
/// read. Row 0 is the image's top row.
///
/// `width * height` is checked against [`Limits::max_pixels`] from the
/// header, before pixel buffers are allocated, and the decoder's buffers
/// against [`Limits::max_bytes`]. Never panics.
///
/// ```
/// use micromap_index_assets::{decode_alpha_image, AlphaTexels, Limits};
/// // A 1 x 1 grey PNG of value 0x80.
/// let png = b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\0\0\x01\0\0\0\x01\x08\0\0\0\0\x3a\x7e\x9b\x55\
///     \0\0\0\x0aIDAT\x78\x9c\x63\x68\0\0\0\x82\0\x81\x77\xcd\x72\xb6\0\0\0\0IEND\xae\x42\x60\x82";
/// let image = decode_alpha_image(png, &Limits::default()).unwrap();
/// assert_eq!((image.width, image.height), (1, 1));
/// assert_eq!(image.texels, AlphaTexels::Unorm8(vec![0x80]));
/// assert!(decode_alpha_image(b"GIF89a", &Limits::default()).is_err());
/// ```
pub fn decode_alpha_image(bytes: &[u8], limits: &Limits) -> Result<AlphaImage, AssetError> {
    decode_image_alpha(bytes, limits, MissingAlpha::Luminance).map(|(image, _)| image)
}

/// Decodes a PNG or JPEG as [`decode_alpha_image`] does, except that an
/// image without an alpha channel (grey, RGB, every JPEG) is read as
/// `missing` says; returns where the alpha came from.
///
/// ```
/// use micromap_index_assets::{decode_image_alpha, AlphaSource, AlphaTexels, Limits, MissingAlpha};
/// // A 1 x 1 grey PNG of value 0x80: no alpha channel.
/// let png = b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\0\0\x01\0\0\0\x01\x08\0\0\0\0\x3a\x7e\x9b\x55\
///     \0\0\0\x0aIDAT\x78\x9c\x63\x68\0\0\0\x82\0\x81\x77\xcd\x72\xb6\0\0\0\0IEND\xae\x42\x60\x82";
/// let (image, source) = decode_image_alpha(png, &Limits::default(), MissingAlpha::One).unwrap();
/// assert_eq!((image.texels, source), (AlphaTexels::Unorm8(vec![255]), AlphaSource::One));
/// let (image, source) = decode_image_alpha(png, &Limits::default(), MissingAlpha::Luminance).unwrap();
/// assert_eq!((image.texels, source), (AlphaTexels::Unorm8(vec![0x80]), AlphaSource::Luminance));
/// ```
pub fn decode_image_alpha(
    bytes: &[u8],
    limits: &Limits,
    missing: MissingAlpha,
) -> Result<(AlphaImage, AlphaSource), AssetError> {
    match ImageFormat::detect(bytes) {
        Some(ImageFormat::Png) => decode_png(bytes, limits, missing),
        Some(ImageFormat::Jpeg) => decode_jpeg(bytes, limits, missing),
        None => Err(AssetError::UnknownImageFormat {
            start: bytes.iter().copied().take(8).collect(),
        }),
    }
}

/// `Err` unless `width * height` is within the limit and not zero.
fn check_pixels(
    format: ImageFormat,
    width: u32,
    height: u32,
    limits: &Limits,
) -> Result<(), AssetError> {
    if width == 0 || height == 0 {
        return Err(AssetError::Image {
            format,
            message: format!("empty image of {width} x {height} pixels"),
        });
    }
    check_limit(
        || format!("{format} image of {width} x {height} pixels"),
        u64::from(width) * u64::from(height),
        limits.max_pixels,
    )
}

fn usize_limit(bytes: u64) -> usize {
    usize::try_from(bytes).unwrap_or(usize::MAX)
}

fn png_error(error: &png::DecodingError) -> AssetError {
    match error {
        png::DecodingError::LimitsExceeded => AssetError::Image {
            format: ImageFormat::Png,
            message: "the decoder's buffers would exceed the byte limit".to_string(),
        },
        other => AssetError::Image {
            format: ImageFormat::Png,
            message: other.to_string(),
        },
    }
}

/// The Rec. 709 luma, rounded half up, exactly.
fn luma(r: u64, g: u64, b: u64) -> u64 {
    (2126 * r + 7152 * g + 722 * b + 5000) / 10000
}

/// Rejects a `PLTE` chunk whose length is not a multiple of 3 (invalid:
/// palette entries are RGB triples), on which png 0.18.1 panics while
/// expanding the palette (image-rs/image-png#694, fixed upstream after
/// 0.18.1; finding A1 in `docs/fuzzing.md`). Walks the chunk headers only;
/// the decoder checks the rest.
fn check_png_palette(bytes: &[u8]) -> Result<(), AssetError> {
    let mut at = 8usize;
    while let Some(header) = bytes.get(at..at + 8) {
        let length = u32::from_be_bytes([header[0], header[1], header[2], header[3]]) as usize;
        let kind = &header[4..8];
        if kind == b"PLTE" && length % 3 != 0 {
            return Err(AssetError::Image {
                format: ImageFormat::Png,
                message: format!("PLTE chunk of {length} bytes, not a multiple of 3"),
            });
        }
        if kind == b"IDAT" || kind == b"IEND" {
            break;
        }
        // Length, type, data, CRC.
        at = match at.checked_add(12).and_then(|n| n.checked_add(length)) {
            Some(next) => next,
            None => break,
        };
    }
    Ok(())
}

/// The result for an image without an alpha channel under
/// [`MissingAlpha::One`]: every texel 255.
fn all_opaque(width: u32, height: u32) -> (AlphaImage, AlphaSource) {
    let pixels = (width as usize) * (height as usize);
    (
        AlphaImage {
            width,
            height,
            texels: AlphaTexels::Unorm8(vec![255; pixels]),
        },
        AlphaSource::One,
    )
}

fn decode_png(
    bytes: &[u8],
    limits: &Limits,
    missing: MissingAlpha,
) -> Result<(AlphaImage, AlphaSource), AssetError> {
    const FORMAT: ImageFormat = ImageFormat::Png;
    check_png_palette(bytes)?;
    let mut decoder = png::Decoder::new_with_limits(
        Cursor::new(bytes),
        png::Limits {
            bytes: usize_limit(limits.max_bytes),
        },
    );
    // Palette -> RGB(A), tRNS -> alpha, 1/2/4-bit grey -> 8 bits; 16 bits kept.
    decoder.set_transformations(png::Transformations::EXPAND);
    let header = decoder.read_header_info().map_err(|e| png_error(&e))?;
    let (width, height) = (header.width, header.height);
    check_pixels(FORMAT, width, height, limits)?;
    let mut reader = decoder.read_info().map_err(|e| png_error(&e))?;
    let size = reader
        .output_buffer_size()
        .ok_or(AssetError::LimitExceeded {
            what: format!("PNG image of {width} x {height} pixels, decoded bytes"),
            size: u64::MAX,
            limit: limits.max_bytes,
        })?;
    check_limit(
        || format!("PNG image of {width} x {height} pixels, decoded bytes"),
        size as u64,
        limits.max_bytes,
    )?;
    let mut buffer = vec![0u8; size];
    let info = reader.next_frame(&mut buffer).map_err(|e| png_error(&e))?;
    if (info.width, info.height) != (width, height) {
        return Err(AssetError::Image {
            format: FORMAT,
            message: format!(
                "first frame is {} x {} pixels, the image {width} x {height}",
                info.width, info.height
            ),
        });
    }
    let pixels = (width as usize) * (height as usize);
    let (samples, alpha) = match info.color_type {
        png::ColorType::Grayscale => (1, None),
        png::ColorType::GrayscaleAlpha => (2, Some(1)),
        png::ColorType::Rgb => (3, None),
        png::ColorType::Rgba => (4, Some(3)),
        png::ColorType::Indexed => {
            return Err(AssetError::Image {
                format: FORMAT,
                message: "palette was not expanded".to_string(),
            })
        }
    };
    let depth_bytes = match info.bit_depth {
        png::BitDepth::Eight => 1,
        png::BitDepth::Sixteen => 2,
        other => {
            return Err(AssetError::Image {
                format: FORMAT,
                message: format!("{other:?} samples were not expanded to 8 bits"),
            })
        }
    };
    if alpha.is_none() && missing == MissingAlpha::One {
        return Ok(all_opaque(width, height));
    }
    let source = if alpha.is_some() {
        AlphaSource::Channel
    } else {
        AlphaSource::Luminance
    };
    let pixel_bytes = samples * depth_bytes;
    let row_bytes = width as usize * pixel_bytes;
    if info.line_size < row_bytes || buffer.len() < info.line_size * (height as usize) {
        return Err(AssetError::Image {
            format: FORMAT,
            message: format!(
                "decoded rows of {} bytes, expected {row_bytes}",
                info.line_size
            ),
        });
    }
    let pixel_iter = buffer
        .chunks_exact(info.line_size)
        .take(height as usize)
        .flat_map(|row| row[..row_bytes].chunks_exact(pixel_bytes));
    let texels = if depth_bytes == 1 {
        let mut texels = Vec::with_capacity(pixels);
        texels.extend(pixel_iter.map(|p| match alpha {
            Some(a) => p[a],
            None if samples == 1 => p[0],
            None => luma(p[0].into(), p[1].into(), p[2].into()) as u8,
        }));
        AlphaTexels::Unorm8(texels)
    } else {
        let sample = |p: &[u8], i: usize| u64::from(u16::from_be_bytes([p[2 * i], p[2 * i + 1]]));
        let mut texels = Vec::with_capacity(pixels);
        texels.extend(pixel_iter.map(|p| match alpha {
            Some(a) => sample(p, a) as u16,
            None if samples == 1 => sample(p, 0) as u16,
            // The luma of 16-bit samples is at most 65535.
            None => luma(sample(p, 0), sample(p, 1), sample(p, 2)) as u16,
        }));
        AlphaTexels::Unorm16(texels)
    };
    Ok((
        AlphaImage {
            width,
            height,
            texels,
        },
        source,
    ))
}

fn jpeg_error(error: &jpeg_decoder::Error) -> AssetError {
    AssetError::Image {
        format: ImageFormat::Jpeg,
        message: error.to_string(),
    }
}

fn decode_jpeg(
    bytes: &[u8],
    limits: &Limits,
    missing: MissingAlpha,
) -> Result<(AlphaImage, AlphaSource), AssetError> {
    const FORMAT: ImageFormat = ImageFormat::Jpeg;
    let mut decoder = jpeg_decoder::Decoder::new(bytes);
    decoder.set_max_decoding_buffer_size(usize_limit(limits.max_bytes));
    decoder.read_info().map_err(|e| jpeg_error(&e))?;
    let info = decoder.info().ok_or_else(|| AssetError::Image {
        format: FORMAT,
        message: "no frame header".to_string(),
    })?;
    let (width, height) = (u32::from(info.width), u32::from(info.height));
    check_pixels(FORMAT, width, height, limits)?;
    let pixel_bytes = info.pixel_format.pixel_bytes();
    check_limit(
        || format!("JPEG image of {width} x {height} pixels, decoded bytes"),
        u64::from(width) * u64::from(height) * pixel_bytes as u64,
        limits.max_bytes,
    )?;
    let cmyk = || AssetError::UnsupportedImage {
        format: FORMAT,
        message: "CMYK (4 components)".to_string(),
    };
    if info.pixel_format == jpeg_decoder::PixelFormat::CMYK32 {
        return Err(cmyk());
    }
    let data = decoder.decode().map_err(|e| jpeg_error(&e))?;
    // JPEG has no alpha channel.
    if missing == MissingAlpha::One {
        return Ok(all_opaque(width, height));
    }
    let pixels = (width as usize) * (height as usize);
    if data.len() != pixels * pixel_bytes {
        return Err(AssetError::Image {
            format: FORMAT,
            message: format!(
                "decoded {} bytes for {width} x {height} pixels of {pixel_bytes} bytes",
                data.len()
            ),
        });
    }
    let texels = match info.pixel_format {
        jpeg_decoder::PixelFormat::L8 => AlphaTexels::Unorm8(data),
        jpeg_decoder::PixelFormat::RGB24 => AlphaTexels::Unorm8(
            data.chunks_exact(3)
                .map(|p| luma(p[0].into(), p[1].into(), p[2].into()) as u8)
                .collect(),
        ),
        // 16-bit lossless JPEG: samples in native byte order.
        jpeg_decoder::PixelFormat::L16 => AlphaTexels::Unorm16(
            data.chunks_exact(2)
                .map(|p| u16::from_ne_bytes([p[0], p[1]]))
                .collect(),
        ),
        jpeg_decoder::PixelFormat::CMYK32 => return Err(cmyk()),
    };
    Ok((
        AlphaImage {
            width,
            height,
            texels,
        },
        AlphaSource::Luminance,
    ))
}
