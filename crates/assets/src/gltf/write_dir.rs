//! [`write_gltf_micromaps_file`]: a glTF file on disk written back with
//! micromaps for an output directory (what `micromap-index bake --gltf-out
//! NAME` writes into `--out DIR`, and Python's `bake_gltf(gltf_out=...)`):
//! the output's container from its file name
//! ([`GltfContainer::from_file_name`]), the files it makes
//! ([`GltfContainer::file_names`]), and the bytes (everything the asset
//! names gathered into the output's own files, so its folder can move).

use super::files::{read_file, resolve_beside};
use super::write::{write_gltf_micromaps, GltfContainer, GltfFiles, GltfMicromapWrite};
use crate::{AssetError, Limits};
use micromap_index::micromap::MicromapBuffers;
use std::path::{Component, Path};

impl GltfContainer {
    /// The container the file name `name` asks for: `NAME.glb` a GLB,
    /// `NAME.gltf` JSON with stem `NAME`; `None` for anything else (an
    /// empty `NAME`, another extension, or a name with a directory part:
    /// `/`, `\` or a leading `..`).
    ///
    /// ```
    /// use micromap_index_assets::GltfContainer;
    /// assert_eq!(GltfContainer::from_file_name("a.glb"), Some(GltfContainer::Glb));
    /// assert_eq!(GltfContainer::from_file_name("a.gltf"), Some(GltfContainer::Json { stem: "a".into() }));
    /// assert_eq!(GltfContainer::from_file_name("d/a.glb"), None);
    /// assert_eq!(GltfContainer::from_file_name(".glb"), None);
    /// ```
    #[must_use]
    pub fn from_file_name(name: &str) -> Option<GltfContainer> {
        let bare = !name.contains(['/', '\\'])
            && !matches!(
                Path::new(name).components().next(),
                Some(Component::ParentDir)
            );
        match (bare, name.rsplit_once('.')) {
            (true, Some((stem, "gltf"))) if !stem.is_empty() => Some(GltfContainer::Json {
                stem: stem.to_string(),
            }),
            (true, Some((stem, "glb"))) if !stem.is_empty() => Some(GltfContainer::Glb),
            _ => None,
        }
    }

    /// Every file an output named `name` in this container may make, `name`
    /// first: for JSON also `<stem>.micromap.bin` and `<stem>.bin` (the
    /// latter only when the input names a buffer or an image).
    ///
    /// ```
    /// use micromap_index_assets::GltfContainer;
    /// let json = GltfContainer::Json { stem: "a".into() };
    /// assert_eq!(json.file_names("a.gltf"), ["a.gltf", "a.micromap.bin", "a.bin"]);
    /// assert_eq!(GltfContainer::Glb.file_names("a.glb"), ["a.glb"]);
    /// ```
    #[must_use]
    pub fn file_names(&self, name: &str) -> Vec<String> {
        let mut names = vec![name.to_string()];
        if let GltfContainer::Json { stem } = self {
            names.push(format!("{stem}.micromap.bin"));
            names.push(format!("{stem}.bin"));
        }
        names
    }
}

/// The glTF file `asset` written back as `container` with `buffers` (one
/// geometry per `(mesh, primitive)` of `primitives`), by
/// [`write_gltf_micromaps`]: everything the asset names is gathered into
/// the output's own files, so no URI leads out of the output's folder. The
/// asset and every file it names are read within [`Limits::max_bytes`],
/// relative to the asset's directory (absolute paths refused, as
/// [`read_gltf_file`](super::read_gltf_file) does). Writes nothing: the
/// caller writes [`GltfFiles::main`] under its name and the sidecars under
/// theirs into one folder.
pub fn write_gltf_micromaps_file(
    asset: &Path,
    buffers: &MicromapBuffers,
    primitives: &[(usize, usize)],
    container: &GltfContainer,
    limits: &Limits,
) -> Result<GltfFiles, AssetError> {
    let input = read_file(asset, limits.max_bytes)?;
    let from = asset.parent().unwrap_or(Path::new(""));
    let mut resolve = resolve_beside(from, limits);
    write_gltf_micromaps(
        &input,
        &mut resolve,
        &GltfMicromapWrite {
            buffers,
            primitives,
        },
        container,
    )
}
