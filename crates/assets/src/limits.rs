//! The bounds every reader keeps ([`Limits`]: sizes, and where the files a
//! glTF names may lie, [`UriScope`]) and the one check of a size against a
//! bound ([`check_limit`]).

use crate::error::AssetError;

/// Bounds on what a reader may decode, hold or read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Most pixels (`width * height`) of one image, checked from its header
    /// before any pixel is allocated.
    pub max_pixels: u64,
    /// Most bytes a reader holds: for an image its decoding buffers and
    /// texels; for a glTF everything it loads and builds together (buffers,
    /// decoded images, UV and triangle arrays), and every file it reads.
    pub max_bytes: u64,
    /// Where the files a glTF's relative URIs name may lie (the glTF file
    /// readers [`read_gltf_file`](crate::read_gltf_file),
    /// [`read_gltf_micromaps_file`](crate::read_gltf_micromaps_file) and
    /// the writer [`write_gltf_micromaps_file`](crate::write_gltf_micromaps_file)).
    pub uri_scope: UriScope,
}

/// Where the files a glTF's URIs name may lie. Absolute paths and URIs with
/// a scheme other than `data:` are refused under either scope, and so is a
/// file whose reading could block forever (a FIFO or a socket).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum UriScope {
    /// Any relative path, `../` included (`../textures/leaf.png`, as asset
    /// libraries share textures): for a desktop tool reading the user's own
    /// files. The default.
    #[default]
    Anywhere,
    /// Only regular files inside the asset's folder or below it: a URI
    /// whose `..` components climb above the folder is refused as written,
    /// and so is one that leaves it through a symbolic link (its canonical
    /// path must lie under the folder's canonical path); devices, FIFOs and
    /// sockets are refused. For a service baking uploaded assets.
    AssetFolder,
}

impl Default for Limits {
    /// `2^26` pixels (an 8192 x 8192 image), 1 GiB, URIs
    /// [`UriScope::Anywhere`].
    fn default() -> Self {
        Limits {
            max_pixels: 1 << 26,
            max_bytes: 1 << 30,
            uri_scope: UriScope::Anywhere,
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
