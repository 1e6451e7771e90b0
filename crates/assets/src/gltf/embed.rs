//! A `.glb` that stands alone: every buffer and image the input names by a
//! URI is moved into the `BIN` chunk, so the written file can be moved or
//! sent without the files beside the input.
//!
//! Contract: called with `host` holding buffer 0's bytes (the chunk) and
//! `buffers[0]` without a URI. Afterwards there is one buffer; every buffer
//! view that named buffer `b > 0` names buffer 0 at `b`'s new offset (the
//! `EXT_meshopt_compression` view extension's `buffer` and `byteOffset`
//! too); every image that had a URI has a `bufferView` of its bytes and a
//! `mimeType` (its own, or read from the bytes: PNG, JPEG, WebP, KTX2).
//! Views are never renumbered: those of images are appended.

use super::raw::{field, parse_raw, to_raw, RawObject};
use super::uri::{decode_data_uri, has_scheme, percent_decode, uri_label};
use crate::AssetError;
use serde_json::json;
use serde_json::value::RawValue;

/// The `EXT_meshopt_compression` view extension, whose `buffer` names the
/// compressed bytes.
const MESHOPT: &str = "EXT_meshopt_compression";

/// Moves buffers `1..` and every image with a URI into `host` (see the
/// module's contract).
pub(super) fn embed_into_bin(
    host: &mut Vec<u8>,
    buffers: &mut Vec<RawObject>,
    views: &mut Vec<Box<RawValue>>,
    images: &mut [RawObject],
    resolve: &mut dyn FnMut(&str) -> Result<Vec<u8>, AssetError>,
) -> Result<(), AssetError> {
    // Step 1: each later buffer's bytes appended, 16-byte aligned (enough
    // for any accessor and for meshopt's streams), its offset kept.
    let mut bases = vec![0usize; buffers.len()];
    for (b, buffer) in buffers.iter().enumerate().skip(1) {
        let path = format!("buffers[{b}]");
        let uri = buffer.parse::<String>("uri", &path)?.ok_or_else(|| {
            AssetError::gltf(
                field(&path, "uri"),
                "missing: only buffer 0 may be a GLB's BIN chunk",
            )
        })?;
        let length = buffer
            .parse::<usize>("byteLength", &path)?
            .ok_or_else(|| AssetError::gltf(field(&path, "byteLength"), "missing"))?;
        let bytes = exactly(load_uri(&uri, resolve)?, length, &path)?;
        host.resize(host.len().next_multiple_of(16), 0);
        bases[b] = host.len();
        host.extend_from_slice(&bytes);
    }
    // Step 2: the views of those buffers point into the chunk.
    if buffers.len() > 1 {
        for (v, raw) in views.iter_mut().enumerate() {
            let path = format!("bufferViews[{v}]");
            let mut view: RawObject = parse_raw(raw, &path)?;
            let mut changed = rebase(&mut view, &path, &bases)?;
            if let Some(mut extensions) = view.parse::<RawObject>("extensions", &path)? {
                let at = field(&path, "extensions");
                if let Some(mut meshopt) = extensions.parse::<RawObject>(MESHOPT, &at)? {
                    if rebase(&mut meshopt, &field(&at, MESHOPT), &bases)? {
                        extensions.set(MESHOPT, to_raw(&meshopt)?);
                        view.set("extensions", to_raw(&extensions)?);
                        changed = true;
                    }
                }
            }
            if changed {
                *raw = to_raw(&view)?;
            }
        }
        buffers.truncate(1);
    }
    // Step 3: each image with a URI becomes a view of its bytes.
    for (i, image) in images.iter_mut().enumerate() {
        let path = format!("images[{i}]");
        let Some(uri) = image.parse::<String>("uri", &path)? else {
            continue;
        };
        let bytes = load_uri(&uri, resolve).map_err(|e| e.within(&path))?;
        let mime = match image.parse::<String>("mimeType", &path)? {
            Some(mime) => mime,
            None => sniff_mime(&bytes)
                .ok_or_else(|| {
                    AssetError::gltf(
                        field(&path, "uri"),
                        "neither PNG, JPEG, WebP nor KTX2, and no mimeType: cannot embed it",
                    )
                })?
                .to_string(),
        };
        host.resize(host.len().next_multiple_of(4), 0);
        views.push(to_raw(&json!({
            "buffer": 0,
            "byteOffset": host.len(),
            "byteLength": bytes.len(),
            "name": format!("{path} (was {})", uri_label(&uri)),
        }))?);
        host.extend_from_slice(&bytes);
        image.remove("uri");
        image.set("bufferView", to_raw(&(views.len() - 1))?);
        image.set("mimeType", to_raw(&mime)?);
    }
    Ok(())
}

/// The bytes of a buffer's URI: a `data:` URI decoded, a relative one
/// through `resolve`.
pub(super) fn load_uri(
    uri: &str,
    resolve: &mut dyn FnMut(&str) -> Result<Vec<u8>, AssetError>,
) -> Result<Vec<u8>, AssetError> {
    let error = |message: String| AssetError::Uri {
        uri: uri_label(uri),
        message,
    };
    if let Some(data) = uri.strip_prefix("data:") {
        return decode_data_uri(data).map_err(error);
    }
    if has_scheme(uri) {
        return Err(error(
            "only relative paths and data: URIs are supported".into(),
        ));
    }
    let path = percent_decode(uri.as_bytes())
        .and_then(|b| String::from_utf8(b).map_err(|_| "percent-decodes to invalid UTF-8".into()))
        .map_err(error)?;
    resolve(&path)
}

/// `bytes` cut to `length`, which they must reach.
pub(super) fn exactly(
    mut bytes: Vec<u8>,
    length: usize,
    path: &str,
) -> Result<Vec<u8>, AssetError> {
    if bytes.len() < length {
        return Err(AssetError::gltf(
            format!("{path}.byteLength"),
            format!("{length}, but the data has {} bytes", bytes.len()),
        ));
    }
    bytes.truncate(length);
    Ok(bytes)
}

/// Points `object`'s `buffer` (and `byteOffset`) at the chunk when it names
/// a moved buffer; whether it did.
fn rebase(object: &mut RawObject, path: &str, bases: &[usize]) -> Result<bool, AssetError> {
    let Some(buffer) = object.parse::<usize>("buffer", path)? else {
        return Ok(false);
    };
    // Buffer 0 stays; an index past the buffers is the reader's to refuse.
    if buffer == 0 || buffer >= bases.len() {
        return Ok(false);
    }
    let offset = object.parse::<usize>("byteOffset", path)?.unwrap_or(0);
    let moved = bases[buffer]
        .checked_add(offset)
        .ok_or_else(|| AssetError::gltf(field(path, "byteOffset"), "past the end of the GLB"))?;
    object.set("buffer", to_raw(&0)?);
    object.set("byteOffset", to_raw(&moved)?);
    Ok(true)
}

/// The image type of `bytes` by its signature.
fn sniff_mime(bytes: &[u8]) -> Option<&'static str> {
    if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        Some("image/png")
    } else if bytes.starts_with(&[0xff, 0xd8, 0xff]) {
        Some("image/jpeg")
    } else if bytes.len() >= 12 && &bytes[..4] == b"RIFF" && &bytes[8..12] == b"WEBP" {
        Some("image/webp")
    } else if bytes.starts_with(b"\xabKTX 20\xbb\r\n\x1a\n") {
        Some("image/ktx2")
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::sniff_mime;

    #[test]
    fn signatures_name_their_types() {
        assert_eq!(sniff_mime(b"\x89PNG\r\n\x1a\n...."), Some("image/png"));
        assert_eq!(sniff_mime(&[0xff, 0xd8, 0xff, 0xe0]), Some("image/jpeg"));
        assert_eq!(sniff_mime(b"RIFF\0\0\0\0WEBPVP8 "), Some("image/webp"));
        assert_eq!(sniff_mime(b"\xabKTX 20\xbb\r\n\x1a\n"), Some("image/ktx2"));
        assert_eq!(sniff_mime(b"GIF89a"), None);
        assert_eq!(sniff_mime(b""), None);
    }
}
