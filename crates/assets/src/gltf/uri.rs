//! URIs: `data:` (base64 or percent-encoded), relative paths through the
//! caller's resolver, and the labels of URIs in messages.

use super::reader::Reader;
use crate::AssetError;

impl Reader<'_, '_> {
    /// The bytes of a `data:` URI, or of an external one through `resolve`.
    pub(super) fn load_uri(&mut self, uri: &str) -> Result<Vec<u8>, AssetError> {
        if let Some(data) = uri.strip_prefix("data:") {
            return decode_data_uri(data).map_err(|message| AssetError::Uri {
                uri: uri_label(uri),
                message,
            });
        }
        if has_scheme(uri) {
            return Err(AssetError::Uri {
                uri: uri_label(uri),
                message: "only relative paths and data: URIs are supported".to_string(),
            });
        }
        let path = percent_decode(uri.as_bytes())
            .and_then(|bytes| {
                String::from_utf8(bytes).map_err(|_| "percent-decodes to invalid UTF-8".to_string())
            })
            .map_err(|message| AssetError::Uri {
                uri: uri_label(uri),
                message,
            })?;
        (self.resolve)(&path)
    }
}

/// A URI for a message: `data:` URIs cut after their header, long ones
/// shortened.
pub(super) fn uri_label(uri: &str) -> String {
    if uri.starts_with("data:") {
        let header = uri.split(',').next().unwrap_or(uri);
        format!("{},...", header.chars().take(60).collect::<String>())
    } else if uri.chars().count() > 120 {
        format!("{}...", uri.chars().take(120).collect::<String>())
    } else {
        uri.to_string()
    }
}

/// Whether `uri` starts with a scheme (`http:`, `file:`, ...).
pub(super) fn has_scheme(uri: &str) -> bool {
    let Some(colon) = uri.find(':') else {
        return false;
    };
    let scheme = &uri[..colon];
    scheme.starts_with(|c: char| c.is_ascii_alphabetic())
        && scheme
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
}

/// `%XX` escapes decoded to bytes; a `%` not followed by two hex digits is
/// an error.
pub(super) fn percent_decode(text: &[u8]) -> Result<Vec<u8>, String> {
    let hex = |b: u8| (b as char).to_digit(16);
    let mut out = Vec::with_capacity(text.len());
    let mut i = 0;
    while i < text.len() {
        if text[i] == b'%' {
            let digits = text
                .get(i + 1)
                .copied()
                .and_then(hex)
                .zip(text.get(i + 2).copied().and_then(hex));
            let Some((high, low)) = digits else {
                return Err(format!("'%' at byte {i} is not followed by two hex digits"));
            };
            out.push((high * 16 + low) as u8);
            i += 3;
        } else {
            out.push(text[i]);
            i += 1;
        }
    }
    Ok(out)
}

/// The data of a `data:` URI (after `data:`): `[<media type>][;base64],<data>`.
pub(super) fn decode_data_uri(rest: &str) -> Result<Vec<u8>, String> {
    let (header, data) = rest
        .split_once(',')
        .ok_or_else(|| "data: URI without ','".to_string())?;
    if header.ends_with(";base64") {
        decode_base64(data.as_bytes())
    } else {
        percent_decode(data.as_bytes())
    }
}

/// Standard base64 (RFC 4648 alphabet `A-Z a-z 0-9 + /`), with or without
/// `=` padding.
pub(super) fn decode_base64(text: &[u8]) -> Result<Vec<u8>, String> {
    pub(super) fn value(c: u8) -> Option<u32> {
        match c {
            b'A'..=b'Z' => Some(u32::from(c - b'A')),
            b'a'..=b'z' => Some(u32::from(c - b'a') + 26),
            b'0'..=b'9' => Some(u32::from(c - b'0') + 52),
            b'+' => Some(62),
            b'/' => Some(63),
            _ => None,
        }
    }
    let padding = text.iter().rev().take_while(|&&c| c == b'=').count();
    if padding > 2 || (padding > 0 && text.len() % 4 != 0) {
        return Err("base64: bad '=' padding".to_string());
    }
    let text = &text[..text.len() - padding];
    if text.len() % 4 == 1 {
        return Err(format!(
            "base64: {} characters is not a valid length",
            text.len()
        ));
    }
    let mut out = Vec::with_capacity(text.len() / 4 * 3 + 2);
    for (chunk_index, chunk) in text.chunks(4).enumerate() {
        let mut word = 0u32;
        for (k, &c) in chunk.iter().enumerate() {
            let v = value(c).ok_or_else(|| {
                format!(
                    "base64: byte {} ({:?}) is not a base64 character",
                    chunk_index * 4 + k,
                    c as char
                )
            })?;
            word |= v << (18 - 6 * k);
        }
        let bytes = word.to_be_bytes();
        out.extend_from_slice(&bytes[1..chunk.len()]);
    }
    Ok(out)
}

#[cfg(test)]
mod unit {
    use super::{decode_base64, has_scheme, percent_decode};

    #[test]
    fn base64_matches_rfc_4648_vectors() {
        for (encoded, decoded) in [
            ("", ""),
            ("Zg==", "f"),
            ("Zm8=", "fo"),
            ("Zm9v", "foo"),
            ("Zm9vYg==", "foob"),
            ("Zm9vYmE=", "fooba"),
            ("Zm9vYmFy", "foobar"),
            ("Zm9vYg", "foob"),
        ] {
            assert_eq!(
                decode_base64(encoded.as_bytes()).unwrap(),
                decoded.as_bytes()
            );
        }
        assert!(decode_base64(b"Zm9vY").is_err());
        assert!(decode_base64(b"Zm9v====").is_err());
        assert!(decode_base64(b"Zm=v").is_err());
        assert!(decode_base64(b"Zm9v Yg==").is_err());
    }

    #[test]
    fn percent_and_scheme() {
        assert_eq!(percent_decode(b"a%20b%2Fc").unwrap(), b"a b/c");
        assert!(percent_decode(b"a%2").is_err());
        assert!(percent_decode(b"a%zz").is_err());
        assert!(has_scheme("http://x/y.png"));
        assert!(has_scheme("file:y.png"));
        assert!(!has_scheme("textures/y.png"));
        assert!(!has_scheme("a b:c/x.png"));
    }
}
