//! [`ImageFormat`]: the image formats the readers decode, by signature.

use std::fmt;

/// The image formats [`decode_alpha_image`](crate::decode_alpha_image) reads, told apart by their
/// signatures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ImageFormat {
    /// PNG (signature `89 50 4e 47 0d 0a 1a 0a`).
    Png,
    /// JPEG (signature `ff d8 ff`).
    Jpeg,
}

impl ImageFormat {
    /// The format whose signature `bytes` start with.
    ///
    /// ```
    /// use micromap_index_assets::ImageFormat;
    /// assert_eq!(ImageFormat::detect(b"\x89PNG\r\n\x1a\n..."), Some(ImageFormat::Png));
    /// assert_eq!(ImageFormat::detect(b"\xff\xd8\xff\xe0"), Some(ImageFormat::Jpeg));
    /// assert_eq!(ImageFormat::detect(b"GIF89a"), None);
    /// ```
    #[must_use]
    pub fn detect(bytes: &[u8]) -> Option<ImageFormat> {
        if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
            Some(ImageFormat::Png)
        } else if bytes.starts_with(&[0xff, 0xd8, 0xff]) {
            Some(ImageFormat::Jpeg)
        } else {
            None
        }
    }
}

impl fmt::Display for ImageFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ImageFormat::Png => "PNG",
            ImageFormat::Jpeg => "JPEG",
        })
    }
}
