//! One `mmi_mesh` as the library takes it: the C input types (texture,
//! sampler, material, mesh), their checked conversions (texels, triangles,
//! per-vertex alpha, sampler, cutoff, model, format) and the enum errors.
//! Read by `mmi_bake` and `mmi_verify`; nothing here calls the bake.

use crate::constants::{
    MMI_MODEL_EXACT, MMI_MODEL_GPU_BINARY32, MMI_OPAQUE_ABOVE, MMI_OPAQUE_AT_LEAST, MMI_TEXEL_F32,
    MMI_TEXEL_U16, MMI_TEXEL_U8,
};
use crate::ffi::{
    guard, mmi_result, slice, try_vec, write, Error, Result, MMI_ERROR_BAKE,
    MMI_ERROR_INVALID_ARGUMENT, MMI_ERROR_INVALID_ENUM, MMI_ERROR_LENGTH, MMI_ERROR_OUT_OF_MEMORY,
};
use micromap_index::bake::mesh::{Material, Mesh, MeshBakeError, MeshTriangles};
use micromap_index::bake::{
    AddressMode, AlphaTexture, Comparison, Cutoff, F32Texture, Filter, Model, Sampler, Texel,
    Unorm16Texture, Unorm8Texture, UvTransform, UvTriangle,
};
use micromap_index::micromap::Format;
use std::borrow::Cow;

/// An alpha texture in the caller's memory.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct mmi_texture {
    /// Row 0 (the image's top row, `v = 0`) first.
    pub texels: *const core::ffi::c_void,
    /// Texels per row, at least 1.
    pub width: u32,
    /// Rows, at least 1.
    pub height: u32,
    /// Bytes from one row to the next (at least `width` texels); 0 means
    /// tightly packed.
    pub row_pitch: usize,
    /// `MMI_TEXEL_U8`, `MMI_TEXEL_U16` (native endian) or `MMI_TEXEL_F32`.
    pub format: u32,
}

/// How the runtime samples the texture.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct mmi_sampler {
    /// `MMI_FILTER_NEAREST` or `MMI_FILTER_LINEAR`.
    pub filter: u32,
    /// `MMI_ADDRESS_*` along u.
    pub address_u: u32,
    /// `MMI_ADDRESS_*` along v.
    pub address_v: u32,
    /// The alpha read outside the texture under clamp-to-border.
    pub border_alpha: f32,
}

/// How a texture is alpha-tested.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct mmi_material {
    /// The sampler.
    pub sampler: mmi_sampler,
    /// The alpha cutoff (not NaN).
    pub cutoff: f32,
    /// `MMI_OPAQUE_AT_LEAST` (`alpha >= cutoff`) or `MMI_OPAQUE_ABOVE`.
    pub comparison: u32,
    /// Multiplies every texel's alpha before the cutoff (glTF's
    /// `baseColorFactor[3]`; 1 for none).
    pub alpha_factor: f32,
}

/// One mesh: a texture, its material, and triangles in UV space.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct mmi_mesh {
    /// The alpha texture.
    pub texture: mmi_texture,
    /// Sampler, cutoff and alpha factor.
    pub material: mmi_material,
    /// Vertex `i`'s `(u, v)` are the two floats at byte
    /// `i * uv_stride` (4-byte aligned).
    pub uvs: *const f32,
    /// The number of vertices at `uvs`.
    pub vertex_count: usize,
    /// Bytes from one vertex to the next: a multiple of 4, at least 8; 0
    /// means 8 (tightly packed pairs).
    pub uv_stride: usize,
    /// Three vertex indices per triangle, or NULL: then vertices `3t`,
    /// `3t + 1`, `3t + 2` are triangle `t`.
    pub indices: *const u32,
    /// The number of indices (a multiple of 3); ignored when `indices` is
    /// NULL.
    pub index_count: usize,
    /// Vertex `i`'s alpha (glTF's `COLOR_0` alpha, in `[0, 1]`) is the
    /// float at byte `i * vertex_alpha_stride` (4-byte aligned), multiplied
    /// into the sampled alpha as glTF renderers do; NULL: alpha 1.
    pub vertex_alpha: *const f32,
    /// Bytes from one vertex alpha to the next: a multiple of 4; 0 means 4.
    pub vertex_alpha_stride: usize,
    /// The texture-coordinate transform the runtime's shader applies to
    /// the interpolated coordinate before sampling (glTF's
    /// `KHR_texture_transform`), or NULL: none.
    pub uv_transform: *const mmi_uv_transform,
}

/// glTF's `KHR_texture_transform`: `uv' = offset + R(rotation) (scale *
/// uv)`, `R` counter-clockwise by `rotation` radians (the extension's
/// `translation * rotation * scale`). The baker models it as the shader
/// computes it, in binary32 on the interpolated coordinate
/// (`docs/bake.md`, "Texture transforms").
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct mmi_uv_transform {
    /// Added after the rotation (the extension's `offset`).
    pub offset: [f32; 2],
    /// Radians, counter-clockwise; at most 65536 in magnitude.
    pub rotation: f32,
    /// Multiplies the coordinate first (the extension's `scale`).
    pub scale: [f32; 2],
}

/// The texels as a slice of `T`: borrowed when tightly packed and aligned,
/// else copied row by row.
trait FromBytes: Texel + Clone {
    fn from_ne(bytes: &[u8]) -> Self;
}

impl FromBytes for u8 {
    fn from_ne(bytes: &[u8]) -> Self {
        bytes[0]
    }
}

impl FromBytes for u16 {
    fn from_ne(bytes: &[u8]) -> Self {
        u16::from_ne_bytes([bytes[0], bytes[1]])
    }
}

impl FromBytes for f32 {
    fn from_ne(bytes: &[u8]) -> Self {
        f32::from_ne_bytes([bytes[0], bytes[1], bytes[2], bytes[3]])
    }
}

/// The copy, when there is one, is the only memory this takes
/// (`MMI_ERROR_OUT_OF_MEMORY` when it cannot be had).
///
/// # Safety
/// `t.texels` must be NULL or point to `row_pitch * (height - 1) + width *
/// size_of::<T>()` readable bytes, unchanged during the call.
unsafe fn texels<'a, T: FromBytes>(t: &mmi_texture) -> Result<Cow<'a, [T]>> {
    let size = size_of::<T>();
    let (width, height) = (t.width as usize, t.height as usize);
    if width == 0 || height == 0 {
        return Err(Error::new(
            MMI_ERROR_INVALID_ARGUMENT,
            "the texture has no texels",
        ));
    }
    let row = width
        .checked_mul(size)
        .ok_or_else(|| Error::new(MMI_ERROR_LENGTH, "the texture's row does not fit in memory"))?;
    let pitch = if t.row_pitch == 0 { row } else { t.row_pitch };
    if pitch < row {
        return Err(Error::new(
            MMI_ERROR_LENGTH,
            format!("row pitch {pitch} is below the row's {row} bytes"),
        ));
    }
    let total = pitch
        .checked_mul(height - 1)
        .and_then(|b| b.checked_add(row))
        .ok_or_else(|| Error::new(MMI_ERROR_LENGTH, "the texture does not fit in memory"))?;
    // No overflow: `total` covers at least `height` rows of `width` texels.
    let count = width * height;
    let ptr = t.texels.cast::<u8>();
    if pitch == row && ptr.cast::<T>().is_aligned() {
        // SAFETY: tightly packed and aligned: `width * height` texels of
        // `T` (every bit pattern is a valid u8, u16 or f32), the caller's
        // promise about the memory.
        return Ok(Cow::Borrowed(unsafe {
            slice(ptr.cast::<T>(), count, "texture.texels")
        }?));
    }
    // SAFETY: the caller promises `total` readable bytes.
    let bytes = unsafe { slice(ptr, total, "texture.texels") }?;
    let mut out = try_vec(count, "a copy of the texture's rows")?;
    for y in 0..height {
        let start = y * pitch;
        out.extend(bytes[start..start + row].chunks_exact(size).map(T::from_ne));
    }
    Ok(Cow::Owned(out))
}

/// A texture's texels, owned or borrowed, by format.
enum Texels<'a> {
    U8(Cow<'a, [u8]>),
    U16(Cow<'a, [u16]>),
    F32(Cow<'a, [f32]>),
}

impl<'a> Texels<'a> {
    /// # Safety
    /// As `texels`.
    unsafe fn new(t: &mmi_texture) -> Result<Texels<'a>> {
        // SAFETY: forwarded from the caller.
        unsafe {
            Ok(match t.format {
                MMI_TEXEL_U8 => Texels::U8(texels(t)?),
                MMI_TEXEL_U16 => Texels::U16(texels(t)?),
                MMI_TEXEL_F32 => Texels::F32(texels(t)?),
                other => {
                    return Err(Error::new(
                        MMI_ERROR_INVALID_ENUM,
                        format!("texel format {other}: expected MMI_TEXEL_U8, _U16 or _F32"),
                    ))
                }
            })
        }
    }

    /// The library's view of the texels.
    fn texture(&self, width: u32, height: u32) -> Result<Box<dyn AlphaTexture + '_>> {
        let refused = |e: micromap_index::bake::TextureError| {
            Error::new(MMI_ERROR_INVALID_ARGUMENT, e.to_string())
        };
        Ok(match self {
            Texels::U8(t) => Box::new(Unorm8Texture::new(width, height, t).map_err(refused)?),
            Texels::U16(t) => Box::new(Unorm16Texture::new(width, height, t).map_err(refused)?),
            Texels::F32(t) => Box::new(F32Texture::new(width, height, t).map_err(refused)?),
        })
    }
}

pub(crate) fn enum_error(what: &str, value: u32, expected: &str) -> Error {
    Error::new(
        MMI_ERROR_INVALID_ENUM,
        format!("{what} {value}: expected {expected}"),
    )
}

fn address(value: u32, what: &str) -> Result<AddressMode> {
    AddressMode::ALL
        .get(value as usize)
        .copied()
        .ok_or_else(|| enum_error(what, value, "an MMI_ADDRESS_* value (0..=4)"))
}

fn sampler(s: &mmi_sampler) -> Result<Sampler> {
    Ok(Sampler {
        filter: match s.filter {
            0 => Filter::Nearest,
            1 => Filter::Linear,
            other => return Err(enum_error("filter", other, "MMI_FILTER_NEAREST or _LINEAR")),
        },
        address_u: address(s.address_u, "address_u")?,
        address_v: address(s.address_v, "address_v")?,
        border_alpha: s.border_alpha,
    })
}

fn cutoff(m: &mmi_material) -> Result<Cutoff> {
    let comparison = match m.comparison {
        MMI_OPAQUE_AT_LEAST => Comparison::AtLeast,
        MMI_OPAQUE_ABOVE => Comparison::Above,
        other => {
            return Err(enum_error(
                "comparison",
                other,
                "MMI_OPAQUE_AT_LEAST or MMI_OPAQUE_ABOVE",
            ))
        }
    };
    Cutoff::new(m.cutoff, comparison)
        .map_err(|e| Error::new(MMI_ERROR_INVALID_ARGUMENT, e.to_string()))
}

pub(crate) fn format(value: u32) -> Result<Format> {
    u16::try_from(value)
        .ok()
        .and_then(Format::from_raw)
        .ok_or_else(|| enum_error("format", value, "MMI_FORMAT_2_STATE or _4_STATE"))
}

/// The model named by an `MMI_MODEL_*` value.
pub(crate) fn model(value: u32) -> Result<Model> {
    match value {
        MMI_MODEL_GPU_BINARY32 => Ok(Model::GpuBinary32),
        MMI_MODEL_EXACT => Ok(Model::Exact),
        other => Err(enum_error(
            "model",
            other,
            "MMI_MODEL_GPU_BINARY32 or MMI_MODEL_EXACT",
        )),
    }
}

/// A mesh's triangles as the library takes them.
enum Triangles<'a> {
    /// Gathered from consecutive vertices.
    Uv(Vec<UvTriangle>),
    /// Indexed, handed to the library as they are.
    Indexed {
        indices: &'a [u32],
        uvs: &'a [f32],
        stride: usize,
    },
}

impl<'a> Triangles<'a> {
    /// # Safety
    /// `m.uvs` must point to `vertex_count` vertices of `uv_stride` bytes
    /// (the last one at least 8), `m.indices` to `index_count` `uint32_t`.
    unsafe fn new(m: &mmi_mesh) -> Result<Triangles<'a>> {
        let stride_bytes = if m.uv_stride == 0 { 8 } else { m.uv_stride };
        if stride_bytes < 8 || stride_bytes % 4 != 0 {
            return Err(Error::new(
                MMI_ERROR_INVALID_ARGUMENT,
                format!("uv_stride {stride_bytes}: expected a multiple of 4, at least 8"),
            ));
        }
        let stride = stride_bytes / 4;
        let floats = match m.vertex_count {
            0 => 0,
            n => (n - 1)
                .checked_mul(stride)
                .and_then(|f| f.checked_add(2))
                .ok_or_else(|| Error::new(MMI_ERROR_LENGTH, "the UVs do not fit in memory"))?,
        };
        // SAFETY: the caller's promise about `uvs`.
        let uvs = unsafe { slice(m.uvs, floats, "uvs") }?;
        if m.indices.is_null() {
            if m.vertex_count % 3 != 0 {
                return Err(Error::new(
                    MMI_ERROR_LENGTH,
                    format!(
                        "{} vertices without indices: expected a multiple of 3",
                        m.vertex_count
                    ),
                ));
            }
            let vertex = |i: usize| [uvs[i * stride], uvs[i * stride + 1]];
            let count = m.vertex_count / 3;
            let mut triangles = try_vec(count, "the triangles gathered from the UVs")?;
            triangles
                .extend((0..count).map(|t| [vertex(3 * t), vertex(3 * t + 1), vertex(3 * t + 2)]));
            return Ok(Triangles::Uv(triangles));
        }
        if m.index_count % 3 != 0 {
            return Err(Error::new(
                MMI_ERROR_LENGTH,
                format!("{} indices: expected a multiple of 3", m.index_count),
            ));
        }
        // SAFETY: the caller's promise about `indices`.
        let indices = unsafe { slice(m.indices, m.index_count, "indices") }?;
        Ok(Triangles::Indexed {
            indices,
            uvs,
            stride,
        })
    }

    fn mesh_triangles(&self) -> MeshTriangles<'_> {
        match self {
            Triangles::Uv(t) => MeshTriangles::Uv(t),
            Triangles::Indexed {
                indices,
                uvs,
                stride,
            } => MeshTriangles::Indexed {
                indices,
                uvs,
                stride: *stride,
            },
        }
    }
}

/// One `mmi_mesh` read and checked, in this order: texels, triangles,
/// vertex alpha, sampler, cutoff. What had to be copied (texels at a
/// pitch or misaligned, triangles without indices, the vertex alphas
/// gathered per triangle) is owned here, each copy allocated fallibly; the
/// rest is borrowed from the caller.
pub(crate) struct MeshInput<'a> {
    texels: Texels<'a>,
    size: (u32, u32),
    triangles: Triangles<'a>,
    vertex_alpha: Option<Vec<[f32; 3]>>,
    /// The sampler, cutoff and alpha factor.
    pub(crate) material: Material,
}

impl<'a> MeshInput<'a> {
    /// # Safety
    /// `m`'s pointers must satisfy `mmi_mesh`'s description and stay
    /// unchanged for `'a`.
    pub(crate) unsafe fn read(m: &mmi_mesh) -> Result<MeshInput<'a>> {
        // SAFETY: forwarded from the caller.
        let (texels, triangles, vertex_alpha) = unsafe {
            (
                Texels::new(&m.texture)?,
                Triangles::new(m)?,
                vertex_alphas(m)?,
            )
        };
        let material = Material {
            sampler: sampler(&m.material.sampler)?,
            cutoff: cutoff(&m.material)?,
            alpha_factor: m.material.alpha_factor,
            // SAFETY: forwarded from the caller.
            uv_transform: unsafe { uv_transform(m.uv_transform) }?,
        };
        Ok(MeshInput {
            texels,
            size: (m.texture.width, m.texture.height),
            triangles,
            vertex_alpha,
            material,
        })
    }

    /// The library's view of the texels (`MMI_ERROR_INVALID_ARGUMENT` for
    /// a texture it refuses, e.g. of `2^32` texels or more).
    pub(crate) fn texture(&self) -> Result<Box<dyn AlphaTexture + '_>> {
        self.texels.texture(self.size.0, self.size.1)
    }

    /// The library's mesh over `texture` (from [`MeshInput::texture`]).
    pub(crate) fn mesh<'b>(&'b self, texture: &'b dyn AlphaTexture) -> Mesh<'b> {
        Mesh {
            triangles: self.triangles.mesh_triangles(),
            texture,
            material: self.material,
            vertex_alpha: self.vertex_alpha.as_deref(),
        }
    }
}

/// The transform at `t`, the identity for NULL; non-finite parameters and
/// rotations beyond `bake::MAX_ROTATION` are `MMI_ERROR_INVALID_ARGUMENT`.
///
/// # Safety
/// `t` must be NULL or point to a readable `mmi_uv_transform`.
unsafe fn uv_transform(t: *const mmi_uv_transform) -> Result<UvTransform> {
    // SAFETY: the caller's promise about `t`.
    let Some(t) = (unsafe { t.as_ref() }) else {
        return Ok(UvTransform::IDENTITY);
    };
    UvTransform::new(t.offset, t.rotation, t.scale).map_err(|e| {
        Error::new(
            MMI_ERROR_INVALID_ARGUMENT,
            format!("mmi_mesh.uv_transform: {e}"),
        )
    })
}

/// The code of the library's refusal of a mesh or of its bake, shared by
/// `mmi_bake` and `mmi_verify`: memory that could not be had is
/// `MMI_ERROR_OUT_OF_MEMORY`, a texture, cutoff or border alpha the baker
/// refuses (NaN) `MMI_ERROR_INVALID_ARGUMENT`, everything else (an index
/// naming no vertex, a vertex alpha outside `[0, 1]`, buffers past the
/// API's limits) `MMI_ERROR_BAKE`.
pub(crate) fn mesh_error(e: &MeshBakeError) -> Error {
    let code = match e {
        e if e.is_allocation_failure() => MMI_ERROR_OUT_OF_MEMORY,
        MeshBakeError::Texture { .. } => MMI_ERROR_INVALID_ARGUMENT,
        _ => MMI_ERROR_BAKE,
    };
    Error::new(code, e.to_string())
}

/// The default material: nearest filtering, repeat on both axes, border
/// alpha 0, opaque when `alpha >= 0.5` (glTF's default), factor 1.
///
/// # Safety
/// `material` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_material_default(material: *mut mmi_material) -> mmi_result {
    guard(|| {
        let value = mmi_material {
            sampler: mmi_sampler::default(),
            cutoff: 0.5,
            comparison: MMI_OPAQUE_AT_LEAST,
            alpha_factor: 1.0,
        };
        // SAFETY: the caller's promise about `material`.
        unsafe { write(material, value, "material") }
    })
}

/// The alphas of each triangle's three vertices, or `None` when
/// `vertex_alpha` is NULL (alpha 1). Vertex `i`'s alpha is the float at
/// byte `i * vertex_alpha_stride` (0 means 4); the corners are those of
/// the triangles (`indices`, or `3t..3t + 3` without them). Values outside
/// `[0, 1]` are left to the library, which refuses them.
///
/// # Safety
/// `m.vertex_alpha` must be NULL or point to `vertex_count` vertices of
/// `vertex_alpha_stride` bytes (the last one at least 4); `m.indices` to
/// `index_count` `uint32_t`.
unsafe fn vertex_alphas(m: &mmi_mesh) -> Result<Option<Vec<[f32; 3]>>> {
    if m.vertex_alpha.is_null() {
        return Ok(None);
    }
    let stride_bytes = match m.vertex_alpha_stride {
        0 => 4,
        s => s,
    };
    if stride_bytes % 4 != 0 {
        return Err(Error::new(
            MMI_ERROR_INVALID_ARGUMENT,
            format!("vertex_alpha_stride {stride_bytes}: expected a multiple of 4"),
        ));
    }
    let stride = stride_bytes / 4;
    let floats = match m.vertex_count {
        0 => 0,
        n => (n - 1)
            .checked_mul(stride)
            .and_then(|f| f.checked_add(1))
            .ok_or_else(|| {
                Error::new(MMI_ERROR_LENGTH, "the vertex alphas do not fit in memory")
            })?,
    };
    // SAFETY: the caller's promise about `vertex_alpha`.
    let alphas = unsafe { slice(m.vertex_alpha, floats, "vertex_alpha") }?;
    let alpha = |i: usize| -> Result<f32> {
        if i >= m.vertex_count {
            return Err(Error::new(
                MMI_ERROR_INVALID_ARGUMENT,
                format!("index {i} names no vertex"),
            ));
        }
        Ok(alphas[i * stride])
    };
    let indices = if m.indices.is_null() {
        None
    } else {
        // SAFETY: the caller's promise about `indices`.
        Some(unsafe { slice(m.indices, m.index_count, "indices") }?)
    };
    // Corner `k`'s vertex: `indices[k]`, or `k` without indices.
    let corner = |k: usize| indices.map_or(k, |i| i[k] as usize);
    let count = indices.map_or(m.vertex_count / 3, |i| i.len() / 3);
    let mut out = try_vec(count, "the vertex alphas of the triangles")?;
    for t in 0..count {
        out.push([
            alpha(corner(3 * t))?,
            alpha(corner(3 * t + 1))?,
            alpha(corner(3 * t + 2))?,
        ]);
    }
    Ok(Some(out))
}
