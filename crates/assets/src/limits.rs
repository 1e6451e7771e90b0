//! The bounds every reader keeps ([`Limits`]) and the one check of a size
//! against a bound ([`check_limit`]).

use crate::error::AssetError;

/// Bounds on what a reader may decode or hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Most pixels (`width * height`) of one image, checked from its header
    /// before any pixel is allocated.
    pub max_pixels: u64,
    /// Most bytes a reader holds: for an image its decoding buffers and
    /// texels; for a glTF everything it loads and builds together (buffers,
    /// decoded images, UV and triangle arrays), and every file it reads.
    pub max_bytes: u64,
}

impl Default for Limits {
    /// `2^26` pixels (an 8192 x 8192 image) and 1 GiB.
    fn default() -> Self {
        Limits {
            max_pixels: 1 << 26,
            max_bytes: 1 << 30,
        }
    }
}

/// `Err(LimitExceeded)` unless `size <= limit`.
pub(crate) fn check_limit(
    what: impl FnOnce() -> String,
    size: u64,
    limit: u64,
) -> Result<(), AssetError> {
    if size <= limit {
        Ok(())
    } else {
        Err(AssetError::LimitExceeded {
            what: what(),
            size,
            limit,
        })
    }
}
