//! `bake --gltf-out NAME`: the asset written back into DIR with
//! `EXT_mesh_opacity_micromap`, by `micromap_index_assets`'s writer.

use crate::inputs::files::{read_asset_file, read_limited};
use crate::inputs::sampler::refuse_overrides;
use cli_support::args::Parsed;
use cli_support::output::Failure;
use micromap_index::micromap::MicromapBuffers;
use micromap_index_assets::{
    relative_uri_prefix, write_gltf_micromaps, AssetError, GltfContainer, GltfMicromapWrite, Limits,
};
use std::path::{Component, Path};

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
        let bare = !name.contains(['/', '\\'])
            && !matches!(
                Path::new(name).components().next(),
                Some(Component::ParentDir)
            );
        let container = match (bare, name.rsplit_once('.')) {
            (true, Some((stem, "gltf"))) if !stem.is_empty() => GltfContainer::Json {
                stem: stem.to_string(),
            },
            (true, Some((stem, "glb"))) if !stem.is_empty() => GltfContainer::Glb,
            _ => {
                return Err(Failure::Usage(format!(
                    "--gltf-out {name:?}: expected a file name NAME.gltf or NAME.glb (written into --out DIR)"
                )))
            }
        };
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
        let mut names = vec![self.name.clone()];
        if let GltfContainer::Json { stem } = &self.container {
            names.push(format!("{stem}.micromap.bin"));
            names.push(format!("{stem}.bin"));
        }
        names
    }

    /// The files of the asset at `asset` written back with `buffers` (one
    /// geometry per `(mesh, primitive)` of `primitives`), for DIR `out`.
    pub(crate) fn files(
        &self,
        asset: &Path,
        out: &Path,
        buffers: &MicromapBuffers,
        primitives: &[(usize, usize)],
    ) -> Result<Vec<(String, Vec<u8>)>, Failure> {
        // The fault is the input asset's (a duplicate member, a malformed
        // buffer): the message names it, and what was being written.
        let malformed = |e: AssetError| {
            Failure::Malformed(format!(
                "{}: {e} (writing --gltf-out {})",
                asset.display(),
                self.name
            ))
        };
        let limits = Limits::default();
        let input = read_limited(asset, &limits)?;
        let from = asset.parent().unwrap_or(Path::new(""));
        let prefix = relative_uri_prefix(out, from).map_err(|e| match e {
            AssetError::Io { .. } => Failure::Io(format!("cannot resolve {e}")),
            other => Failure::Malformed(other.to_string()),
        })?;
        let mut resolve = |uri: &str| read_asset_file(&from.join(uri), &limits);
        let written = write_gltf_micromaps(
            &input,
            &mut resolve,
            &GltfMicromapWrite {
                buffers,
                primitives,
                uri_prefix: &prefix,
            },
            &self.container,
        )
        .map_err(malformed)?;
        let mut files = vec![(self.name.clone(), written.main)];
        files.extend(written.sidecars);
        Ok(files)
    }
}
