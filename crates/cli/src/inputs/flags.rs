//! The flags more than one command has, each defined once: a command's
//! table lists them by name (`cli_support::args::concat` joins the groups).

use cli_support::args::Flag;

/// `bake`'s and `render`'s glTF input.
pub(crate) const GLTF: Flag = Flag::value(
    "--gltf",
    "ASSET",
    "a glTF 2.0 asset (.gltf or .glb): its MASK primitives",
);
/// `bake`'s, `verify-bake`'s and `render`'s confinement of `--gltf`'s
/// URIs to the asset's folder (`Limits::uri_scope`, read by
/// [`asset_limits`](super::files::asset_limits)).
pub(crate) const CONFINE_URIS: Flag = Flag::switch(
    "--confine-uris",
    "read only regular files inside the --gltf asset's folder: refuse URIs that leave it (../, symbolic links) and devices (for untrusted uploads)",
);
/// `bake`'s and `render`'s texture input.
pub(crate) const TEXTURE: Flag =
    Flag::value("--texture", "T.png", "an alpha texture (PNG or JPEG)");
/// `bake`'s and `render`'s UV triangles over [`TEXTURE`].
pub(crate) const TRIANGLES: Flag =
    Flag::value("--triangles", "TRIS.json", "UV triangles over --texture");
/// `bake`'s and `render`'s output directory.
pub(crate) const OUT: Flag = Flag::value("--out", "DIR", "the output directory");
/// `bake`'s and `render`'s replacing of existing outputs.
pub(crate) const FORCE: Flag = Flag::switch("--force", "replace existing files in DIR");
/// The width of micromap-indices.bin `bake` writes and `verify-bake` and
/// `render --micromaps` read: the same three widths everywhere.
pub(crate) const INDEX_WIDTH: Flag = Flag::value(
    "--index-width",
    "8|16|32",
    "micromap-indices.bin width (default 32; 8 is for Vulkan KHR, DXR and glTF, not Vulkan EXT)",
);

/// The sampler, cutoff and model flags `bake`, `verify-bake` and
/// `render` share; all but `--model` are the asset's own with
/// `--gltf-out` and `verify-bake --gltf`.
pub(crate) const SAMPLER: [Flag; 8] = [
    Flag::value(
        "--filter",
        "F",
        "nearest or linear (default nearest; glTF: the sampler's magFilter)",
    ),
    Flag::value(
        "--address",
        "MODE",
        "both axes: repeat (default; glTF: wrapS/wrapT), mirrored-repeat,
                         clamp-to-edge, clamp-to-border or mirror-clamp-to-edge",
    ),
    Flag::value("--address-u", "MODE", "the u axis only"),
    Flag::value("--address-v", "MODE", "the v axis only"),
    Flag::value("--border", "ALPHA", "clamp-to-border alpha (default 0)"),
    Flag::value(
        "--cutoff",
        "C",
        "alpha cutoff (default 0.5; glTF: alphaCutoff); opaque when alpha >= C",
    ),
    Flag::switch(
        "--opaque-above",
        "opaque when alpha > C (the OMM SDK's rule)",
    ),
    Flag::value(
        "--model",
        "M",
        "the points known states hold for: gpu-binary32 (default: every binary32
                         hit a GPU assigns to the micro-triangle and the texel its binary32
                         arithmetic reads) or exact (the exact real points only; docs/bake.md)",
    ),
];

/// The texture-unit flags `bake`, `verify-bake` and `render` share: what
/// a GPU's texture unit may do between a hit and the alpha test
/// (`docs/bake.md`, "The texture unit"); never the asset's own.
pub(crate) const TEXTURE_UNIT: [Flag; 4] = [
    Flag::value(
        "--subtexel-bits",
        "K",
        "texel coordinates snap to 1/2^K texel: 4..=16 (default 8; Vulkan's minimum is 4)",
    ),
    Flag::value(
        "--interpolation",
        "P",
        "the shader's texture-coordinate precision: f32 (default) or f16 (mediump)",
    ),
    Flag::value(
        "--filter-error",
        "E",
        "the largest error of a linear filter's result, in alpha units (default 2^-7)",
    ),
    Flag::value(
        "--linear",
        "RULE",
        "linear filtering judged by value (default: the filtered alpha) or footprint
                         (every texel of the 2x2 footprint, whatever its weight)",
    ),
];
