//! `bake_gltf(..., gltf_out=PATH)`: the asset written back with its
//! micromaps, by the assets crate's `write_gltf_micromaps_file` (the code
//! `micromap-index bake --gltf-out` runs), for PATH's directory. Returns
//! the files' names and bytes; the Python layer writes them.

use crate::options::value_error;
use micromap_index::micromap::MicromapBuffers;
use micromap_index_assets::{write_gltf_micromaps_file, AssetError, GltfContainer, Limits};
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};

/// `gltf_out`, checked: its directory, file name and container.
pub(crate) struct GltfOut {
    dir: PathBuf,
    name: String,
    container: GltfContainer,
}

impl GltfOut {
    /// `path` ending in `NAME.gltf` or `NAME.glb`; the directory (which
    /// must exist: an `OSError` naming it otherwise) is the rest.
    pub(crate) fn new(path: &Path) -> PyResult<GltfOut> {
        let refused = || {
            value_error(format!(
                "gltf_out {:?}: expected a path ending in NAME.gltf or NAME.glb",
                path.display().to_string()
            ))
        };
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .ok_or_else(refused)?;
        let container = GltfContainer::from_file_name(name).ok_or_else(refused)?;
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        // The directory must exist: checked here, before anything is
        // baked (the written files stand alone, so the writer itself never
        // reads it).
        if !dir.is_dir() {
            return Err(PyOSError::new_err(format!(
                "gltf_out {name:?}: the directory {} does not exist",
                dir.display()
            )));
        }
        Ok(GltfOut {
            dir,
            name: name.to_string(),
            container,
        })
    }

    /// The directory the files go to.
    pub(crate) fn dir(&self) -> &Path {
        &self.dir
    }

    /// The files (name, bytes) of `asset` written back with `buffers`, one
    /// geometry per `(mesh, primitive)` of `primitives`: `OSError` for a
    /// file that cannot be read (or a missing directory), else
    /// `ValueError`. The GIL may be released around it.
    pub(crate) fn files(
        &self,
        asset: &Path,
        buffers: &MicromapBuffers,
        primitives: &[(usize, usize)],
    ) -> PyResult<Vec<(String, Vec<u8>)>> {
        let written = write_gltf_micromaps_file(
            asset,
            buffers,
            primitives,
            &self.container,
            &Limits::default(),
        )
        .map_err(|e| {
            let message = format!("gltf_out {:?}: {e}", self.name);
            if matches!(e.root(), AssetError::Io { .. }) {
                PyOSError::new_err(message)
            } else {
                value_error(message)
            }
        })?;
        let mut files = vec![(self.name.clone(), written.main)];
        files.extend(written.sidecars);
        Ok(files)
    }
}
