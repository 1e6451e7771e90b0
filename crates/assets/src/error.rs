//! [`AssetError`]: why an asset could not be read, printed as one line.

use crate::image_format::ImageFormat;
use std::fmt;

/// Why an asset could not be read. `Display` writes one line naming the
/// file, the part of it or the field at fault.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum AssetError {
    /// A file could not be read (`path` as given, `message` the system's).
    Io {
        /// The file.
        path: String,
        /// The operating system's message.
        message: String,
    },
    /// The image bytes start with neither the PNG nor the JPEG signature.
    UnknownImageFormat {
        /// Up to the first 8 bytes.
        start: Vec<u8>,
    },
    /// The image decoder rejected the image (truncated, corrupt, ...).
    Image {
        /// PNG or JPEG.
        format: ImageFormat,
        /// The decoder's message.
        message: String,
    },
    /// The image decoded, but its pixel format is not supported (CMYK JPEG).
    UnsupportedImage {
        /// PNG or JPEG.
        format: ImageFormat,
        /// What is not supported.
        message: String,
    },
    /// A size is over a [`Limits`](crate::Limits) bound.
    LimitExceeded {
        /// What was measured ("image of 9000 x 9000 pixels", ...).
        what: String,
        /// Its size, in the unit of the limit (pixels or bytes).
        size: u64,
        /// The bound it broke.
        limit: u64,
    },
    /// The bytes are not JSON text of the expected top-level shape (with
    /// `serde_json`'s line and column).
    Json {
        /// `serde_json`'s message.
        message: String,
    },
    /// A `TRIS.json` triangle is malformed.
    Triangles {
        /// The index of the triangle in `"triangles"`, if the fault is in one.
        triangle: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// The GLB container is malformed (header, chunk lengths).
    Glb {
        /// What is wrong.
        message: String,
    },
    /// A glTF field is missing, of the wrong type, out of range, or
    /// inconsistent with the data it describes.
    Gltf {
        /// The field as a JSON path, e.g. `accessors[3].count`.
        field: String,
        /// What is wrong.
        message: String,
    },
    /// A URI could not be decoded or resolved.
    Uri {
        /// The URI as written in the glTF (shortened if long).
        uri: String,
        /// What is wrong.
        message: String,
    },
    /// An error inside a named file or part of an asset.
    In {
        /// The file or part, e.g. `cards.gltf` or `images[1] ("chain.png")`.
        context: String,
        /// The error inside it.
        source: Box<AssetError>,
    },
}

impl AssetError {
    /// This error inside `context` (a file name or a part of an asset).
    #[must_use]
    pub fn within(self, context: impl Into<String>) -> AssetError {
        AssetError::In {
            context: context.into(),
            source: Box::new(self),
        }
    }

    /// The innermost error, below every [`AssetError::In`].
    #[must_use]
    pub fn root(&self) -> &AssetError {
        match self {
            AssetError::In { source, .. } => source.root(),
            other => other,
        }
    }

    pub(crate) fn gltf(field: impl Into<String>, message: impl Into<String>) -> AssetError {
        AssetError::Gltf {
            field: field.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for AssetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AssetError::Io { path, message } => {
                write!(f, "cannot read {}: {}", line(path), line(message))
            }
            AssetError::UnknownImageFormat { start } => {
                write!(f, "not a PNG or JPEG image (starts with")?;
                if start.is_empty() {
                    write!(f, " nothing: empty")?;
                }
                for byte in start {
                    write!(f, " {byte:02x}")?;
                }
                write!(f, ")")
            }
            AssetError::Image { format, message } => {
                write!(f, "{format} image: {}", line(message))
            }
            AssetError::UnsupportedImage { format, message } => {
                write!(f, "{format} image not supported: {}", line(message))
            }
            AssetError::LimitExceeded { what, size, limit } => {
                write!(f, "{}: {size} is over the limit of {limit}", line(what))
            }
            AssetError::Json { message } => write!(f, "invalid JSON: {}", line(message)),
            AssetError::Triangles {
                triangle: Some(i),
                message,
            } => write!(f, "triangle {i}: {}", line(message)),
            AssetError::Triangles {
                triangle: None,
                message,
            } => write!(f, "triangles: {}", line(message)),
            AssetError::Glb { message } => write!(f, "GLB container: {}", line(message)),
            AssetError::Gltf { field, message } => {
                write!(f, "{}: {}", line(field), line(message))
            }
            AssetError::Uri { uri, message } => write!(f, "URI {uri:?}: {}", line(message)),
            AssetError::In { context, source } => write!(f, "{}: {source}", line(context)),
        }
    }
}

/// `text` with control characters (line breaks included) escaped, so that
/// every message stays on one line.
fn line(text: &str) -> std::borrow::Cow<'_, str> {
    if text.chars().any(char::is_control) {
        text.chars()
            .map(|c| {
                if c.is_control() {
                    c.escape_default().to_string()
                } else {
                    c.to_string()
                }
            })
            .collect::<String>()
            .into()
    } else {
        text.into()
    }
}

impl std::error::Error for AssetError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            AssetError::In { source, .. } => Some(source.as_ref()),
            _ => None,
        }
    }
}
