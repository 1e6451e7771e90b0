//! `bake --gltf-out NAME`: the asset written back into DIR with
//! `EXT_mesh_opacity_micromap`, by `micromap_index_assets`'s
//! [`write_gltf_micromaps_file`] (the container from the name,
//! [`GltfContainer::from_file_name`]; the files it may make,
//! [`GltfContainer::file_names`]), under the limits the asset was read
//! with (`--confine-uris` included). Like the reader, the writer refuses
//! absolute URIs.

use crate::inputs::files::{asset_failure, asset_limits};
use crate::inputs::sampler::refuse_overrides;
use cli_support::args::Parsed;
use cli_support::output::Failure;
use micromap_index::micromap::MicromapBuffers;
use micromap_index_assets::{write_gltf_micromaps_file, GltfContainer};
use std::path::Path;

/// `--gltf-out NAME`: the file name and its container, checked.
pub(crate) struct GltfOut {
    name: String,
    container: GltfContainer,
}

impl GltfOut {
    /// `--gltf-out`, if given: a bare file name ending in `.gltf` or
    /// `.glb`, with `--gltf` and without sampler overrides, none of whose
    /// files is one of `reserved` (bake's other outputs).
    pub(crate) fn from_options(
        p: &Parsed<'_>,
        reserved: &[&str],
    ) -> Result<Option<GltfOut>, Failure> {
        let Some(name) = p.get("--gltf-out") else {
            return Ok(None);
        };
        if p.get("--gltf").is_none() {
            return Err(Failure::Usage(
                "--gltf-out writes the --gltf asset back: give --gltf ASSET".into(),
            ));
        }
        refuse_overrides(p, "--gltf-out")?;
        let container = GltfContainer::from_file_name(name).ok_or_else(|| {
            Failure::Usage(format!(
                "--gltf-out {name:?}: expected a file name NAME.gltf or NAME.glb (written into --out DIR)"
            ))
        })?;
        let out = GltfOut {
            name: name.to_string(),
            container,
        };
        if let Some(clash) = out.names().iter().find(|n| reserved.contains(&n.as_str())) {
            return Err(Failure::Usage(format!(
                "--gltf-out {name:?} would write {clash}, which bake writes too: choose another name"
            )));
        }
        Ok(Some(out))
    }

    /// Every file this may write into DIR (for the existence check).
    pub(crate) fn names(&self) -> Vec<String> {
        self.container.file_names(&self.name)
    }

    /// The files of the asset at `asset` written back with `buffers` (one
    /// geometry per `(mesh, primitive)` of `primitives`), under the asset's
    /// limits of `p`.
    pub(crate) fn files(
        &self,
        p: &Parsed<'_>,
        asset: &Path,
        buffers: &MicromapBuffers,
        primitives: &[(usize, usize)],
    ) -> Result<Vec<(String, Vec<u8>)>, Failure> {
        let limits = asset_limits(p)?;
        // The fault is the input asset's (a duplicate member, a malformed
        // buffer): the message names it, and what was being written.
        let written =
            write_gltf_micromaps_file(asset, buffers, primitives, &self.container, &limits)
                .map_err(|e| {
                    asset_failure(
                        &e.within(asset.display().to_string()),
                        &format!(" (writing --gltf-out {})", self.name),
                    )
                })?;
        let mut files = vec![(self.name.clone(), written.main)];
        files.extend(written.sidecars);
        Ok(files)
    }
}
