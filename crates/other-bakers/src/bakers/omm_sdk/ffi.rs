//! The few types and entry points of the OMM SDK's C API (`omm.h`, SDK
//! 1.7.1) that a CPU bake needs, declared by hand from the header's
//! documented layout: C enums are 4-byte integers here (GCC and Clang on
//! x86-64 and AArch64), structs follow the C layout (`#[repr(C)]`). No SDK
//! code is copied; the layout test below pins every size and offset this
//! crate relies on (values printed with `offsetof` against the header).

use std::ffi::{c_char, c_void};

/// `ommResult`.
pub type OmmResult = u32;
/// `ommResult_SUCCESS`.
pub const SUCCESS: OmmResult = 0;

/// `ommResult` as its name in the header.
pub fn result_name(r: OmmResult) -> &'static str {
    match r {
        0 => "SUCCESS",
        1 => "FAILURE",
        2 => "INVALID_ARGUMENT",
        3 => "INSUFFICIENT_SCRATCH_MEMORY",
        4 => "NOT_IMPLEMENTED",
        5 => "WORKLOAD_TOO_BIG",
        _ => "unknown ommResult",
    }
}

/// `ommBakerType_CPU`.
pub const BAKER_TYPE_CPU: u32 = 1;
/// `ommCpuTextureFormat_UNORM8`.
pub const TEXTURE_FORMAT_UNORM8: u32 = 0;
/// `ommCpuBakeFlags_EnableInternalThreads`.
pub const BAKE_FLAG_INTERNAL_THREADS: u32 = 1 << 0;
/// `ommCpuBakeFlags_Force32BitIndices`.
pub const BAKE_FLAG_FORCE_32BIT_INDICES: u32 = 1 << 2;
/// `ommTexCoordFormat_UV32_FLOAT`.
pub const TEX_COORD_UV32_FLOAT: u32 = 2;
/// `ommIndexFormat_UINT_32`.
pub const INDEX_FORMAT_UINT_32: u32 = 1;
/// `ommAlphaMode_Test`.
pub const ALPHA_MODE_TEST: u32 = 0;
/// `ommOpacityState_Transparent`.
pub const STATE_TRANSPARENT: u32 = 0;
/// `ommOpacityState_Opaque`.
pub const STATE_OPAQUE: u32 = 1;
/// `ommUnknownStatePromotion_ForceOpaque` (the header's default).
pub const PROMOTION_FORCE_OPAQUE: u32 = 1;
/// `ommSpecialIndex_FullyUnknownOpaque` (the header's default for
/// unresolvable UV triangles).
pub const SPECIAL_FULLY_UNKNOWN_OPAQUE: i32 = -4;

/// `ommTextureAddressMode`: Wrap 0, Mirror 1, Clamp 2, Border 3, MirrorOnce 4.
pub mod address {
    /// `ommTextureAddressMode_Wrap`.
    pub const WRAP: u32 = 0;
    /// `ommTextureAddressMode_Mirror`.
    pub const MIRROR: u32 = 1;
    /// `ommTextureAddressMode_Clamp`.
    pub const CLAMP: u32 = 2;
    /// `ommTextureAddressMode_Border`.
    pub const BORDER: u32 = 3;
    /// `ommTextureAddressMode_MirrorOnce`.
    pub const MIRROR_ONCE: u32 = 4;
}

/// `ommTextureFilterMode`: Nearest 0, Linear 1.
pub mod filter {
    /// `ommTextureFilterMode_Nearest`.
    pub const NEAREST: u32 = 0;
    /// `ommTextureFilterMode_Linear`.
    pub const LINEAR: u32 = 1;
}

/// Opaque handles (`ommBaker`, `ommCpuTexture`, `ommCpuBakeResult`).
pub type Handle = *mut c_void;

/// `ommLibraryDesc`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct LibraryDesc {
    pub major: u8,
    pub minor: u8,
    pub build: u8,
}

/// `ommMemoryAllocatorInterface` (all null: the SDK's default allocator).
#[repr(C)]
pub struct MemoryAllocatorInterface {
    pub allocate: *const c_void,
    pub reallocate: *const c_void,
    pub free: *const c_void,
    pub user_arg: *mut c_void,
}

/// `ommMessageCallback`.
pub type MessageCallback =
    unsafe extern "C" fn(severity: u32, message: *const c_char, user: *mut c_void);

/// `ommMessageInterface`.
#[repr(C)]
pub struct MessageInterface {
    pub callback: Option<MessageCallback>,
    pub user_arg: *mut c_void,
}

/// `ommBakerCreationDesc`.
#[repr(C)]
pub struct BakerCreationDesc {
    pub baker_type: u32,
    pub allocator: MemoryAllocatorInterface,
    pub messages: MessageInterface,
}

/// `ommCpuTextureMipDesc`.
#[repr(C)]
pub struct TextureMipDesc {
    pub width: u32,
    pub height: u32,
    /// Bytes per row; 0 = tightly packed.
    pub row_pitch: u32,
    pub data: *const c_void,
}

/// `ommCpuTextureDesc`.
#[repr(C)]
pub struct TextureDesc {
    pub format: u32,
    pub flags: u32,
    pub mips: *const TextureMipDesc,
    pub mip_count: u32,
    /// Embedded cutoff (`< 0`: none); must equal the bake's when set.
    pub alpha_cutoff: f32,
}

/// `ommSamplerDesc`.
#[repr(C)]
pub struct SamplerDesc {
    pub address_mode: u32,
    pub filter: u32,
    pub border_alpha: f32,
}

/// `ommCpuBakeInputDesc` (deprecated union aliases omitted: same storage).
#[repr(C)]
pub struct BakeInputDesc {
    pub bake_flags: u32,
    pub texture: Handle,
    pub runtime_sampler: SamplerDesc,
    pub alpha_mode: u32,
    pub tex_coord_format: u32,
    pub tex_coords: *const c_void,
    pub tex_coord_stride: u32,
    pub index_format: u32,
    pub index_buffer: *const c_void,
    pub index_count: u32,
    /// `<= 0`: every triangle at `max_subdivision_level`.
    pub dynamic_subdivision_scale: f32,
    pub rejection_threshold: f32,
    pub alpha_cutoff: f32,
    pub near_duplicate_deduplication_factor: f32,
    pub alpha_cutoff_less_equal: u32,
    pub alpha_cutoff_greater: u32,
    pub format: u32,
    pub formats: *const u32,
    pub unknown_state_promotion: u32,
    pub unresolved_tri_state: i32,
    pub max_subdivision_level: u8,
    pub max_array_data_size: u32,
    pub subdivision_levels: *const u8,
    pub max_workload_size: u64,
}

/// `ommCpuOpacityMicromapDesc`: `VkMicromapTriangleEXT`'s layout.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct MicromapDesc {
    pub offset: u32,
    pub subdivision_level: u16,
    pub format: u16,
}

/// `ommCpuBakeResultDesc`.
#[repr(C)]
pub struct BakeResultDesc {
    pub array_data: *const c_void,
    pub array_data_size: u32,
    pub desc_array: *const MicromapDesc,
    pub desc_array_count: u32,
    pub desc_array_histogram: *const c_void,
    pub desc_array_histogram_count: u32,
    pub index_buffer: *const c_void,
    pub index_count: u32,
    pub index_format: u32,
    pub index_histogram: *const c_void,
    pub index_histogram_count: u32,
}

/// `ommGetLibraryDesc`.
pub type GetLibraryDesc = unsafe extern "C" fn() -> LibraryDesc;
/// `ommCreateBaker`.
pub type CreateBaker = unsafe extern "C" fn(*const BakerCreationDesc, *mut Handle) -> OmmResult;
/// `ommDestroyBaker`.
pub type DestroyBaker = unsafe extern "C" fn(Handle) -> OmmResult;
/// `ommCpuCreateTexture`.
pub type CreateTexture = unsafe extern "C" fn(Handle, *const TextureDesc, *mut Handle) -> OmmResult;
/// `ommCpuDestroyTexture`.
pub type DestroyTexture = unsafe extern "C" fn(Handle, Handle) -> OmmResult;
/// `ommCpuBake`.
pub type Bake = unsafe extern "C" fn(Handle, *const BakeInputDesc, *mut Handle) -> OmmResult;
/// `ommCpuDestroyBakeResult`.
pub type DestroyBakeResult = unsafe extern "C" fn(Handle) -> OmmResult;
/// `ommCpuGetBakeResultDesc`.
pub type GetBakeResultDesc = unsafe extern "C" fn(Handle, *mut *const BakeResultDesc) -> OmmResult;

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{offset_of, size_of};

    /// Sizes and offsets as `offsetof` prints them for omm.h 1.7.1 with g++
    /// on x86-64: a declaration out of step with the header fails here.
    #[test]
    fn layouts_match_the_header() {
        assert_eq!(size_of::<BakerCreationDesc>(), 56);
        assert_eq!(offset_of!(BakerCreationDesc, allocator), 8);
        assert_eq!(offset_of!(BakerCreationDesc, messages), 40);
        assert_eq!(size_of::<TextureMipDesc>(), 24);
        assert_eq!(size_of::<TextureDesc>(), 24);
        assert_eq!(offset_of!(TextureDesc, mips), 8);
        assert_eq!(offset_of!(TextureDesc, mip_count), 16);
        assert_eq!(offset_of!(TextureDesc, alpha_cutoff), 20);
        assert_eq!(size_of::<BakeInputDesc>(), 136);
        assert_eq!(offset_of!(BakeInputDesc, texture), 8);
        assert_eq!(offset_of!(BakeInputDesc, runtime_sampler), 16);
        assert_eq!(offset_of!(BakeInputDesc, alpha_mode), 28);
        assert_eq!(offset_of!(BakeInputDesc, tex_coords), 40);
        assert_eq!(offset_of!(BakeInputDesc, index_buffer), 56);
        assert_eq!(offset_of!(BakeInputDesc, index_count), 64);
        assert_eq!(offset_of!(BakeInputDesc, alpha_cutoff), 76);
        assert_eq!(offset_of!(BakeInputDesc, alpha_cutoff_less_equal), 84);
        assert_eq!(offset_of!(BakeInputDesc, format), 92);
        assert_eq!(offset_of!(BakeInputDesc, formats), 96);
        assert_eq!(offset_of!(BakeInputDesc, unknown_state_promotion), 104);
        assert_eq!(offset_of!(BakeInputDesc, unresolved_tri_state), 108);
        assert_eq!(offset_of!(BakeInputDesc, max_subdivision_level), 112);
        assert_eq!(offset_of!(BakeInputDesc, max_array_data_size), 116);
        assert_eq!(offset_of!(BakeInputDesc, subdivision_levels), 120);
        assert_eq!(offset_of!(BakeInputDesc, max_workload_size), 128);
        assert_eq!(size_of::<BakeResultDesc>(), 80);
        assert_eq!(offset_of!(BakeResultDesc, array_data_size), 8);
        assert_eq!(offset_of!(BakeResultDesc, desc_array), 16);
        assert_eq!(offset_of!(BakeResultDesc, desc_array_count), 24);
        assert_eq!(offset_of!(BakeResultDesc, desc_array_histogram), 32);
        assert_eq!(offset_of!(BakeResultDesc, index_buffer), 48);
        assert_eq!(offset_of!(BakeResultDesc, index_count), 56);
        assert_eq!(offset_of!(BakeResultDesc, index_format), 60);
        assert_eq!(offset_of!(BakeResultDesc, index_histogram), 64);
        assert_eq!(offset_of!(BakeResultDesc, index_histogram_count), 72);
        assert_eq!(size_of::<LibraryDesc>(), 3);
        assert_eq!(size_of::<MicromapDesc>(), 8);
    }
}
