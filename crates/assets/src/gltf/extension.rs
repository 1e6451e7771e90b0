//! `EXT_mesh_opacity_micromap`'s name and highest level, for the reader
//! (`micromap_ext`) and the writer (`write`) alike.

use micromap_index::micromap::Api;

/// The extension's name, as it appears in `extensionsUsed` and in the
/// `extensions` of the root and of each primitive.
pub const EXTENSION: &str = "EXT_mesh_opacity_micromap";

/// The highest subdivision level the extension allows (records and
/// `usageLevels`, schema `maximum: 12`): [`Api::max_level`] of
/// [`Api::Gltf`].
pub const MAX_GLTF_LEVEL: u32 = match Api::Gltf.max_level() {
    Some(level) => level,
    None => 12,
};
