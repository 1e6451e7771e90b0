//! What [`bake_meshes`](super::bake_meshes) and
//! [`verify_mesh`](super::verify_mesh) take: meshes ([`Mesh`], their
//! triangles as [`MeshTriangles`]), how to bake them ([`MeshOptions`]),
//! and why a mesh is refused ([`MeshBakeError`]).

use crate::bake::baker::DEFAULT_BLOCK_BUDGET;
use crate::bake::gpu::Model;
use crate::bake::level::LevelRule;
use crate::bake::material::{vertex_range, Material};
use crate::bake::mips::Mips;
use crate::bake::parallel::Threads;
use crate::bake::texture::{AlphaTexture, TextureError};
use crate::bake::texture_unit::TextureUnit;
use crate::bake::triangle::{BakeError, UvTriangle};
use crate::bake::work::{DEFAULT_BAKE_WORK_BUDGET, DEFAULT_TRIANGLE_WORK_BUDGET};
use crate::micromap::{BufferError, BuildOptions, Format, MicromapError, UnknownPolicy};
use alloc::borrow::Cow;
use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;

/// A mesh's triangles in UV space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MeshTriangles<'a> {
    /// One [`UvTriangle`] per triangle.
    Uv(&'a [UvTriangle]),
    /// Triangle `t` is vertices `indices[3t]`, `indices[3t + 1]`,
    /// `indices[3t + 2]`; vertex `i`'s UV is `uvs[stride i]`,
    /// `uvs[stride i + 1]` (`stride` floats per vertex, at least 2, so UVs
    /// may sit inside interleaved vertex data). `indices.len()` must be a
    /// multiple of 3 and every index name a vertex in `uvs`.
    Indexed {
        /// Three vertex indices per triangle.
        indices: &'a [u32],
        /// The vertices' data, `stride` floats each, `(u, v)` first.
        uvs: &'a [f32],
        /// Floats from one vertex to the next.
        stride: usize,
    },
}

impl MeshTriangles<'_> {
    /// The number of triangles (for `Indexed`, `indices.len() / 3`).
    #[must_use]
    pub fn len(&self) -> usize {
        match self {
            MeshTriangles::Uv(triangles) => triangles.len(),
            MeshTriangles::Indexed { indices, .. } => indices.len() / 3,
        }
    }

    /// Whether there are no triangles.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The triangles as [`UvTriangle`]s (borrowed when they already are).
    pub(crate) fn resolve(&self, mesh: usize) -> Result<Cow<'_, [UvTriangle]>, MeshBakeError> {
        let (indices, uvs, stride) = match *self {
            MeshTriangles::Uv(triangles) => return Ok(Cow::Borrowed(triangles)),
            MeshTriangles::Indexed {
                indices,
                uvs,
                stride,
            } => (indices, uvs, stride),
        };
        if stride < 2 || indices.len() % 3 != 0 {
            return Err(MeshBakeError::Layout {
                mesh,
                indices: indices.len(),
                stride,
            });
        }
        let vertices = (uvs.len() + stride - 2) / stride;
        let vertex = |triangle: usize, index: u32| -> Result<[f32; 2], MeshBakeError> {
            let at = (index as usize)
                .checked_mul(stride)
                .filter(|&at| at < uvs.len().saturating_sub(1));
            match at {
                Some(at) => Ok([uvs[at], uvs[at + 1]]),
                None => Err(MeshBakeError::Index {
                    mesh,
                    triangle,
                    index,
                    vertices,
                }),
            }
        };
        let mut triangles = room(indices.len() / 3)?;
        for (t, corners) in indices.chunks_exact(3).enumerate() {
            triangles.push([
                vertex(t, corners[0])?,
                vertex(t, corners[1])?,
                vertex(t, corners[2])?,
            ]);
        }
        Ok(Cow::Owned(triangles))
    }
}

/// A mesh to bake: its triangles, the texture they are alpha-tested
/// against, its material, and optionally a vertex alpha (glTF's `COLOR_0`).
#[derive(Clone, Copy)]
pub struct Mesh<'a> {
    /// The triangles in UV space.
    pub triangles: MeshTriangles<'a>,
    /// The alpha texture.
    pub texture: &'a dyn AlphaTexture,
    /// Sampler, cutoff and alpha factor.
    pub material: Material,
    /// The alpha of each triangle's three vertices (glTF's `COLOR_0`
    /// alpha), in the order of the triangles, one entry per triangle;
    /// `None`: alpha 1. The renderer multiplies the sampled alpha by the
    /// alpha factor and by the vertex alpha interpolated at the hit (see
    /// [`bake_meshes`](crate::bake::mesh::bake_meshes) for how that is baked soundly). Each value must be
    /// in `[0, 1]`.
    pub vertex_alpha: Option<&'a [[f32; 3]]>,
}

/// How [`bake_meshes`](crate::bake::mesh::bake_meshes) bakes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshOptions {
    /// The level of each triangle.
    pub levels: LevelRule,
    /// 2-state or 4-state micromaps.
    pub format: Format,
    /// What unknown micro-triangles become in a 2-state format.
    pub unknown: UnknownPolicy,
    /// At most this many bytes of micromap data, before deduplication, for
    /// all meshes together: the highest levels are lowered first
    /// ([`levels_within_budget`](crate::bake::levels_within_budget)). `None`: no budget.
    pub budget_bytes: Option<u64>,
    /// Block tests a micro-triangle may use ([`Baker::with_block_budget`](crate::bake::Baker::with_block_budget)).
    pub block_budget: u32,
    /// Work units one triangle may spend ([`Baker::bake_within`](crate::bake::Baker::bake_within), units in
    /// [bounded work](crate::bake#bounded-work)).
    pub triangle_work_budget: u64,
    /// Work units all triangles together may spend: each triangle gets the
    /// smaller of [`triangle_work_budget`](Self::triangle_work_budget) and
    /// what the triangles before it (meshes in order) left.
    pub bake_work_budget: u64,
    /// The points known states hold for ([`Baker::with_model`](crate::bake::Baker::with_model); default
    /// [`Model::GpuBinary32`]).
    pub model: Model,
    /// The mip levels the known states hold for (default
    /// [`Mips::Level0`]; the filter model of the others is in
    /// `docs/bake.md`, "Every mip level").
    pub mips: Mips,
    /// The threads the bake may use (default [`Threads::All`]: every core
    /// with the `rayon` feature, one without). The output is the same
    /// bytes for every choice.
    pub threads: Threads,
    /// The texture unit the known states hold for (default
    /// [`TextureUnit::default`]: 8 sub-texel bits, binary32 interpolation,
    /// linear filtering judged by value; see `docs/bake.md`, "The texture
    /// unit").
    pub texture_unit: TextureUnit,
    /// How the API buffers are laid out (default: uniform maps become
    /// special indices, which may mix with records; set
    /// [`BuildOptions::no_mixed_special_indices`] for Vulkan KHR's
    /// no-mixed pipelines).
    pub buffers: BuildOptions,
}

impl Default for MeshOptions {
    /// Useful levels up to 12, 4-state, fallback for unknowns, no byte
    /// budget, [`DEFAULT_BLOCK_BUDGET`], [`DEFAULT_TRIANGLE_WORK_BUDGET`],
    /// [`DEFAULT_BAKE_WORK_BUDGET`], the GPU model.
    fn default() -> Self {
        MeshOptions {
            levels: LevelRule::default(),
            format: Format::FourState,
            unknown: UnknownPolicy::Fallback,
            budget_bytes: None,
            block_budget: DEFAULT_BLOCK_BUDGET,
            triangle_work_budget: DEFAULT_TRIANGLE_WORK_BUDGET,
            bake_work_budget: DEFAULT_BAKE_WORK_BUDGET,
            model: Model::default(),
            mips: Mips::default(),
            threads: Threads::default(),
            texture_unit: TextureUnit::default(),
            buffers: BuildOptions::default(),
        }
    }
}

/// An empty list with room for `len` items, allocated fallibly: every list
/// sized by the meshes (triangles, levels, the plan of distinct triangles)
/// is made by it, so input too large for memory is
/// [`MeshBakeError::AllocationFailed`], never an abort.
pub(super) fn room<T>(len: usize) -> Result<Vec<T>, MeshBakeError> {
    let mut list = Vec::new();
    make_room(&mut list, len)?;
    Ok(list)
}

/// Room in `list` for `more` items beyond its length, allocated fallibly
/// (see [`room`]).
pub(super) fn make_room<T>(list: &mut Vec<T>, more: usize) -> Result<(), MeshBakeError> {
    list.try_reserve(more)
        .map_err(|_| MeshBakeError::AllocationFailed {
            bytes: (list.len() as u64)
                .saturating_add(more as u64)
                .saturating_mul(core::mem::size_of::<T>() as u64),
        })
}

/// Appends the vertex-alpha range ([`vertex_range`]) of each triangle of
/// `alphas` to `lows` and `highs` (reserved fallibly): the lists
/// [`VertexBounds::new`](crate::bake::material::VertexBounds::new) takes.
pub(super) fn push_vertex_ranges(
    (lows, highs): &mut (Vec<u64>, Vec<u64>),
    alphas: &[[f32; 3]],
) -> Result<(), MeshBakeError> {
    make_room(lows, alphas.len())?;
    make_room(highs, alphas.len())?;
    for &a in alphas {
        let (low, high) = vertex_range(a);
        lows.push(low);
        highs.push(high);
    }
    Ok(())
}

/// Why [`bake_meshes`](crate::bake::mesh::bake_meshes) failed.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum MeshBakeError {
    /// Mesh `mesh`'s texture, sampler or cutoff was refused by
    /// [`Baker::new`](crate::bake::Baker::new).
    Texture {
        /// The mesh, by position.
        mesh: usize,
        /// Why.
        error: TextureError,
    },
    /// Mesh `mesh` is `Indexed` with a stride below 2 or a number of
    /// indices that is not a multiple of 3.
    Layout {
        /// The mesh, by position.
        mesh: usize,
        /// The number of indices.
        indices: usize,
        /// The stride.
        stride: usize,
    },
    /// An index of mesh `mesh` names no vertex.
    Index {
        /// The mesh, by position.
        mesh: usize,
        /// The triangle.
        triangle: usize,
        /// The index.
        index: u32,
        /// The vertices there are.
        vertices: usize,
    },
    /// Mesh `mesh` has a vertex alpha list whose length is not its number
    /// of triangles, or a vertex alpha outside `[0, 1]` (NaN included), or
    /// vertex alpha with an alpha factor that is negative or not finite,
    /// or with [`MeshOptions::mips`] other than [`Mips::Level0`] (not
    /// modelled).
    VertexAlpha {
        /// The mesh, by position.
        mesh: usize,
        /// What is wrong.
        message: String,
    },
    /// A triangle could not be baked (level above 16, allocation).
    Bake(BakeError),
    /// A list sized by the meshes (resolved triangles, their levels, the
    /// distinct triangles and their table) could not be allocated.
    AllocationFailed {
        /// The bytes the list needed.
        bytes: u64,
    },
    /// The buffers could not be built.
    Buffers(BufferError),
}

impl MeshBakeError {
    /// Whether the bake failed for memory the input asked for and the
    /// allocator refused (texel tables, a micromap, the per-triangle lists
    /// or the buffers), as against input that is wrong: front ends report
    /// it as out of memory (`MMI_ERROR_OUT_OF_MEMORY`, `MemoryError`).
    #[must_use]
    pub fn is_allocation_failure(&self) -> bool {
        matches!(
            self,
            MeshBakeError::Texture {
                error: TextureError::AllocationFailed { .. },
                ..
            } | MeshBakeError::Bake(BakeError::Micromap(MicromapError::AllocationFailed { .. }))
                | MeshBakeError::Buffers(BufferError::AllocationFailed)
                | MeshBakeError::AllocationFailed { .. }
        )
    }
}

impl fmt::Display for MeshBakeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshBakeError::Texture { mesh, error } => write!(f, "mesh {mesh}: {error}"),
            MeshBakeError::Layout {
                mesh,
                indices,
                stride,
            } => write!(
                f,
                "mesh {mesh}: {indices} indices with stride {stride}: expected a multiple of 3 indices and a stride of at least 2"
            ),
            MeshBakeError::Index {
                mesh,
                triangle,
                index,
                vertices,
            } => write!(
                f,
                "mesh {mesh}: triangle {triangle} has index {index}, past the {vertices} vertices"
            ),
            MeshBakeError::VertexAlpha { mesh, message } => {
                write!(f, "mesh {mesh}: vertex alpha: {message}")
            }
            MeshBakeError::Bake(e) => e.fmt(f),
            MeshBakeError::Buffers(e) => e.fmt(f),
            MeshBakeError::AllocationFailed { bytes } => write!(
                f,
                "out of memory: a list of {bytes} bytes for the meshes' triangles cannot be had"
            ),
        }
    }
}

impl core::error::Error for MeshBakeError {}

/// Checks a mesh's vertex alphas.
pub(crate) fn check_vertex_alpha<'a>(
    m: usize,
    mesh: &Mesh<'a>,
    triangles: usize,
) -> Result<Option<&'a [[f32; 3]]>, MeshBakeError> {
    let Some(alphas) = mesh.vertex_alpha else {
        return Ok(None);
    };
    let error = |message: String| MeshBakeError::VertexAlpha { mesh: m, message };
    if alphas.len() != triangles {
        return Err(error(format!(
            "{} entries for {triangles} triangles",
            alphas.len()
        )));
    }
    let factor = mesh.material.alpha_factor;
    if !(factor.is_finite() && factor >= 0.0) {
        return Err(error(format!(
            "the alpha factor {factor} is negative or not finite"
        )));
    }
    for (t, v) in alphas.iter().enumerate() {
        if let Some(bad) = v.iter().find(|a| !(0.0..=1.0).contains(*a)) {
            return Err(error(format!(
                "triangle {t} has vertex alpha {bad}, outside [0, 1]"
            )));
        }
    }
    Ok(Some(alphas))
}
