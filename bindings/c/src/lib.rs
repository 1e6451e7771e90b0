//! The C ABI of `micromap-index`: thin `mmi_`-prefixed `extern "C"`
//! wrappers over the library, declared in `include/micromap_index.h`.
//!
//! Every answer comes from the library (`micromap_index::{spec, batch,
//! inverse, bake, bake::mesh, micromap, succinct}`); this crate only checks
//! what crosses the boundary and converts it:
//!
//! - every entry point is total: a null pointer, a wrong length, a value
//!   outside an enum or a level out of range returns its `MMI_ERROR_*` code
//!   (never undefined behaviour on the Rust side), and the message of the
//!   last failure on the calling thread is [`mmi_last_error_message`];
//! - no panic crosses the boundary: every body runs under
//!   [`std::panic::catch_unwind`] and a panic returns [`MMI_ERROR_PANIC`]
//!   (this needs `panic = "unwind"`, the default; a program built with
//!   `panic = "abort"` aborts instead);
//! - enums arrive as `uint32_t` and are checked before use, so an
//!   out-of-range value is [`MMI_ERROR_INVALID_ENUM`], not an invalid Rust
//!   enum;
//! - handles (`mmi_bake_result`, `mmi_tree`) are owned by the caller after
//!   they are returned and freed with their `*_free` function; the pointers
//!   their accessors return stay valid until then.
//!
//! `docs/c.md` explains building, linking, ownership and thread safety.

#![allow(non_camel_case_types)]

mod bake;
mod ffi;
mod index;
mod mesh;
mod tree;
mod verify;

pub use bake::{
    mmi_bake, mmi_bake_options, mmi_bake_options_default, mmi_bake_result, mmi_bake_result_data,
    mmi_bake_result_free, mmi_bake_result_geometry_count, mmi_bake_result_indices,
    mmi_bake_result_is_mixed, mmi_bake_result_stats, mmi_bake_result_triangle_records,
    mmi_bake_result_usage_counts, mmi_bake_stats,
};
pub use ffi::{
    mmi_last_error_message, mmi_result, mmi_version, mmi_version_string, MMI_ERROR_BAKE,
    MMI_ERROR_BUFFER_TOO_SMALL, MMI_ERROR_INVALID_ARGUMENT, MMI_ERROR_INVALID_ENUM,
    MMI_ERROR_INVALID_LEVEL, MMI_ERROR_LENGTH, MMI_ERROR_LIMIT, MMI_ERROR_MALFORMED,
    MMI_ERROR_NULL_POINTER, MMI_ERROR_OUT_OF_MEMORY, MMI_ERROR_PANIC, MMI_ERROR_UNSUPPORTED,
    MMI_OK,
};
pub use index::{
    mmi_index_f32, mmi_index_f32_batch, mmi_inverse_micro_triangle, mmi_micro_triangle,
    mmi_wide_index_f32, mmi_wide_index_f32_batch,
};
pub use mesh::{
    mmi_material, mmi_material_default, mmi_mesh, mmi_sampler, mmi_texture, mmi_uv_transform,
};
pub use tree::{
    mmi_tree, mmi_tree_decode, mmi_tree_encode, mmi_tree_free, mmi_tree_from_bytes, mmi_tree_get,
    mmi_tree_get_f32, mmi_tree_info, mmi_tree_info_get, mmi_tree_to_bytes,
};
pub use verify::{
    mmi_buffers_info, mmi_buffers_view, mmi_contradiction, mmi_read_options,
    mmi_read_options_default, mmi_validate_buffers, mmi_verify, mmi_verify_report,
    mmi_verify_with_model, mmi_verify_with_options,
};

/// The constants shared by the header's `#define`s and the Rust side (the
/// header test checks each against the header).
pub mod constants {
    /// Texel formats of `mmi_texture::format`.
    pub const MMI_TEXEL_U8: u32 = 0;
    /// 16-bit unorm texels (`alpha = c / 65535`), native endian.
    pub const MMI_TEXEL_U16: u32 = 1;
    /// `float` texels, as they are.
    pub const MMI_TEXEL_F32: u32 = 2;
    /// Nearest filtering.
    pub const MMI_FILTER_NEAREST: u32 = 0;
    /// Bilinear filtering.
    pub const MMI_FILTER_LINEAR: u32 = 1;
    /// Address mode: repeat.
    pub const MMI_ADDRESS_REPEAT: u32 = 0;
    /// Address mode: mirrored repeat.
    pub const MMI_ADDRESS_MIRRORED_REPEAT: u32 = 1;
    /// Address mode: clamp to edge.
    pub const MMI_ADDRESS_CLAMP_TO_EDGE: u32 = 2;
    /// Address mode: clamp to border.
    pub const MMI_ADDRESS_CLAMP_TO_BORDER: u32 = 3;
    /// Address mode: mirror clamp to edge.
    pub const MMI_ADDRESS_MIRROR_CLAMP_TO_EDGE: u32 = 4;
    /// Opaque when `alpha >= cutoff` (glTF MASK).
    pub const MMI_OPAQUE_AT_LEAST: u32 = 0;
    /// Opaque when `alpha > cutoff` (the OMM SDK's rule).
    pub const MMI_OPAQUE_ABOVE: u32 = 1;
    /// 2-state micromaps (the API value 1).
    pub const MMI_FORMAT_2_STATE: u32 = 1;
    /// 4-state micromaps (the API value 2).
    pub const MMI_FORMAT_4_STATE: u32 = 2;
    /// 2-state: unknowns become the state they fall back to.
    pub const MMI_UNKNOWN_FALLBACK: u32 = 0;
    /// 2-state: unknowns become opaque.
    pub const MMI_UNKNOWN_OPAQUE: u32 = 1;
    /// 2-state: unknowns become transparent.
    pub const MMI_UNKNOWN_TRANSPARENT: u32 = 2;
    /// `mmi_bake_options::level`: each triangle's useful level (the paper's
    /// eq. 1), capped at `max_level`.
    pub const MMI_LEVEL_AUTO: u32 = 0xFFFF_FFFF;
    /// The highest `mmi_bake_options::level` and `max_level`: the
    /// library's `bake::MAX_BAKE_LEVEL`, the highest DXR allows and Vulkan
    /// devices report.
    pub const MMI_MAX_BAKE_LEVEL: u32 = 12;
    /// `mmi_bake_options::max_bytes` 0 means this limit on a bake's
    /// estimated output: 1 GiB (`micromap-index bake --max-bytes`'s
    /// default).
    pub const MMI_DEFAULT_MAX_BYTES: u64 = 1_073_741_824;
    /// `mmi_bake_options::model`: known states hold for what a GPU computes
    /// in binary32 (the default; `docs/bake.md`).
    pub const MMI_MODEL_GPU_BINARY32: u32 = 0;
    /// Known states hold for the exact real texture coordinates only.
    pub const MMI_MODEL_EXACT: u32 = 1;
    /// `mmi_bake_options::interpolation`: the shader interpolates texture
    /// coordinates in binary32 (the default).
    pub const MMI_INTERPOLATION_F32: u32 = 0;
    /// The shader interpolates in 16-bit floats (`mediump`).
    pub const MMI_INTERPOLATION_F16: u32 = 1;
    /// `mmi_bake_options::linear_rule`: linear filtering judged by the
    /// filtered value (the default; `docs/bake.md`, "The texture unit").
    pub const MMI_LINEAR_VALUE: u32 = 0;
    /// Linear filtering judged by footprint (every texel of the 2x2
    /// footprint read, whatever its weight).
    pub const MMI_LINEAR_FOOTPRINT: u32 = 1;
    /// `mmi_bake_result_indices`' geometry: every geometry, concatenated.
    pub const MMI_ALL_GEOMETRIES: usize = usize::MAX;
    /// The paper's depth-first tree (`PaperTree`).
    pub const MMI_TREE_PAPER: u32 = 0;
    /// The level-order tree (`LevelOrderTree`).
    pub const MMI_TREE_LEVEL_ORDER: u32 = 1;
    /// State: transparent.
    pub const MMI_STATE_TRANSPARENT: u32 = 0;
    /// State: opaque.
    pub const MMI_STATE_OPAQUE: u32 = 1;
    /// State: unknown, transparent when any-hit is skipped.
    pub const MMI_STATE_UNKNOWN_TRANSPARENT: u32 = 2;
    /// State: unknown, opaque when any-hit is skipped.
    pub const MMI_STATE_UNKNOWN_OPAQUE: u32 = 3;
}
