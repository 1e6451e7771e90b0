//! Whole meshes: [`bake_meshes`] chooses a level per triangle, fits a byte
//! budget, bakes every triangle exactly ([`Baker::bake`](super::Baker::bake)), deduplicates the
//! micromaps into API buffers ([`MicromapBuffers`], one geometry per mesh)
//! and reports what it found ([`BakeReport`]).
//!
//! A [`Mesh`] is its triangles in UV space ([`MeshTriangles`]: one
//! [`UvTriangle`] each, or indices into a strided UV array), the texture it
//! is alpha-tested against and its [`Material`] (sampler, cutoff and the
//! alpha factor, glTF's `baseColorFactor[3]`). [`MeshOptions`] says how to
//! bake all of them: the level rule ([`LevelRule`]), format, what unknowns
//! become in a 2-state format, and an optional byte budget for the
//! micromap data of all meshes together.
//!
//! ```
//! use micromap_index::bake::mesh::{bake_mesh, Material, Mesh, MeshOptions, MeshTriangles};
//! use micromap_index::bake::Unorm8Texture;
//! use micromap_index::micromap::State;
//!
//! // An 8 x 8 texture, opaque in its left three columns.
//! let texels: Vec<u8> = (0..64).map(|i| if (i % 8) < 3 { 255 } else { 0 }).collect();
//! let texture = Unorm8Texture::new(8, 8, &texels).unwrap();
//! // A quad over the whole texture: four corners, two triangles.
//! let uvs = [0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0];
//! let indices = [0, 1, 2, 0, 2, 3];
//! let mesh = Mesh {
//!     triangles: MeshTriangles::Indexed { indices: &indices, uvs: &uvs, stride: 2 },
//!     texture: &texture,
//!     material: Material::default(),
//!     vertex_alpha: None,
//! };
//! let baked = bake_mesh(&mesh, &MeshOptions::default()).unwrap();
//! assert_eq!(baked.report.triangles, 2);
//! assert_eq!(baked.buffers.geometry_indices(0).unwrap().len(), 2);
//! // Edges of 8 and 11.3 texels: level 4 (the paper's eq. 1).
//! assert_eq!(baked.report.levels, [0, 0, 0, 0, 2]);
//! assert!(baked.report.counts[State::Opaque.bits() as usize] > 0);
//! assert!(baked.report.known_fraction > 0.5 && baked.report.known_fraction < 1.0);
//! ```

use super::baker::DEFAULT_BLOCK_BUDGET;
use super::gpu::Model;
use super::level::levels_within_budget;
pub use super::level::LevelRule;
use super::mips::bake_bounded;
pub use super::mips::Mips;
use super::parallel::{Runner, Threads};
use super::texture::{AlphaTexture, Cutoff, Sampler, TextureError};
use super::triangle::{BakeError, BakedTriangle, TriangleStatus, UvTriangle};
use super::work::{DEFAULT_BAKE_WORK_BUDGET, DEFAULT_TRIANGLE_WORK_BUDGET};
use crate::micromap::BakedOpacity;
use crate::micromap::{
    BufferError, BuildOptions, Format, MicromapBuffers, MicromapBuffersBuilder, MicromapIndex,
    UnknownPolicy,
};
use crate::succinct::packed_tree_sizes;
use alloc::borrow::Cow;
use alloc::format;
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;
use core::fmt;
use distinct::{Distinct, Plan};

mod distinct;

// The levels bake_meshes chooses, and the output bound callers check first.
mod levels;
pub use levels::{chosen_levels, output_bytes_bound};
use levels::{levels_of, resolve_all};
mod verify;
pub use verify::{verify_mesh, MeshVerification, MeshVerifyError};

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
    fn resolve(&self, mesh: usize) -> Result<Cow<'_, [UvTriangle]>, MeshBakeError> {
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
        let mut triangles = Vec::with_capacity(indices.len() / 3);
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

/// How a mesh's texture is alpha-tested: the sampler, the cutoff, and a
/// factor on every texel's alpha.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// The sampler the runtime reads the texture with.
    pub sampler: Sampler,
    /// The alpha test.
    pub cutoff: Cutoff,
    /// Multiplies every texel's alpha before the cutoff (glTF's
    /// `pbrMetallicRoughness.baseColorFactor[3]`), as a GPU does: the
    /// texel's alpha as binary32 (`c / 255` rounded once, for 8-bit
    /// texels) times the factor, one binary32 product, compared with the
    /// cutoff; at `1.0` the texel's alpha as it is. Under linear filtering
    /// the filtered alpha lies between its texels' alphas, and the rounded
    /// product is monotone in it, so classifying each texel this way stays
    /// sound.
    pub alpha_factor: f32,
}

impl Default for Material {
    /// The default sampler and cutoff (glTF's `alpha >= 0.5`), factor 1.
    fn default() -> Self {
        Material {
            sampler: Sampler::default(),
            cutoff: Cutoff::default(),
            alpha_factor: 1.0,
        }
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
    /// [`bake_meshes`] for how that is baked soundly). Each value must be
    /// in `[0, 1]`.
    pub vertex_alpha: Option<&'a [[f32; 3]]>,
}

/// How [`bake_meshes`] bakes.
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
    /// ([`levels_within_budget`]). `None`: no budget.
    pub budget_bytes: Option<u64>,
    /// Block tests a micro-triangle may use ([`Baker::with_block_budget`](super::Baker::with_block_budget)).
    pub block_budget: u32,
    /// Work units one triangle may spend ([`Baker::bake_within`](super::Baker::bake_within), units in
    /// [bounded work](crate::bake#bounded-work)).
    pub triangle_work_budget: u64,
    /// Work units all triangles together may spend: each triangle gets the
    /// smaller of [`triangle_work_budget`](Self::triangle_work_budget) and
    /// what the triangles before it (meshes in order) left.
    pub bake_work_budget: u64,
    /// The points known states hold for ([`Baker::with_model`](super::Baker::with_model); default
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
            buffers: BuildOptions::default(),
        }
    }
}

/// Triangles by how they were baked ([`TriangleStatus`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct StatusCounts {
    /// [`TriangleStatus::Exact`].
    pub exact: usize,
    /// [`TriangleStatus::NotFinite`].
    pub not_finite: usize,
    /// [`TriangleStatus::OutOfExactRange`].
    pub out_of_exact_range: usize,
    /// [`TriangleStatus::BlockBudgetExceeded`].
    pub block_budget_exceeded: usize,
    /// [`TriangleStatus::WorkBudgetExceeded`].
    pub work_budget_exceeded: usize,
}

/// What [`bake_meshes`] found, over all meshes.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct BakeReport {
    /// Triangles baked.
    pub triangles: usize,
    /// Distinct triangles classified: triangles with bit-for-bit equal UVs,
    /// the same level, texture, sampler, cutoff, alpha factor and vertex
    /// alpha range are classified once (they bake to the same states).
    pub distinct_triangles: usize,
    /// Triangles per chosen level (`levels[n]` at level `n`), up to the
    /// highest level used (at least one entry). A triangle baked as a
    /// special index counts at the level it was given.
    pub levels: Vec<u64>,
    /// Micro-triangles per state, indexed by
    /// [`State::bits`](crate::micromap::State::bits), counted before a
    /// 2-state format resolves the unknowns.
    pub counts: [u64; 4],
    /// Triangles by how they were baked.
    pub status: StatusCounts,
    /// Known (opaque or transparent) micro-triangles over all
    /// micro-triangles (0 when there are none).
    pub known_fraction: f64,
    /// The known fraction of each triangle weighted by its area in texels
    /// (0 when the triangles have no area).
    pub known_area_fraction: f64,
    /// Distinct micromaps in the buffers, after deduplication.
    pub micromaps: usize,
    /// Triangles whose index is a special index (one state for the whole
    /// triangle: uniform, or not placeable on the exact grid).
    pub special_index_triangles: usize,
    /// Bytes of packed micromap data ([`MicromapBuffers::data`]).
    pub bytes_flat: usize,
    /// Bytes the distinct micromaps take as the paper's succinct trees
    /// ([`PaperTree`](crate::succinct::PaperTree)).
    pub bytes_paper_tree: u64,
    /// Bytes they take as level-order trees
    /// ([`LevelOrderTree`](crate::succinct::LevelOrderTree)).
    pub bytes_level_order_tree: u64,
    /// Unknown micro-triangles the exact model knows: the GPU model's
    /// widening cost ([`BakedTriangle::widened`]; 0 under the exact
    /// model). `(counts[0] + counts[1] + widened) / micro-triangles` is
    /// the known fraction the exact model would have.
    pub widened: u64,
    /// Work units spent, all triangles together ([bounded work](crate::bake#bounded-work)):
    /// what the serial bake spends, whatever the threads (the budgets
    /// count these).
    pub work: u64,
    /// Work units spent besides and thrown away by triangles split over
    /// several threads whose budget ran out
    /// ([`BakedTriangle::speculative_work`]); 0 on one thread. `work +
    /// speculative_work` is all the work done.
    pub speculative_work: u64,
    /// Triangles [`LevelRule::Useful`] baked at level 0 because their
    /// micro-triangles would each hold a whole texture period
    /// ([`level_within_periods`](super::level_within_periods)).
    pub period_level_zero: usize,
}

/// What [`bake_meshes`] returns: the buffers, the report, and how each
/// triangle baked ([`triangle`](Self::triangle), for previews and checks).
#[derive(Clone, Debug)]
pub struct MeshBake {
    /// One geometry per mesh, micromaps deduplicated across all.
    pub buffers: MicromapBuffers,
    /// The statistics.
    pub report: BakeReport,
    /// Each distinct triangle's bake (its map is in the buffers).
    distinct: Vec<Distinct>,
    /// Per mesh, per triangle: its distinct triangle.
    of_triangle: Vec<Vec<u32>>,
}

/// How one triangle baked ([`MeshBake::triangle`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct TriangleBake {
    /// The level its micromap was baked at; 0 for a triangle baked as a
    /// special index from its coordinates ([`TriangleStatus::NotFinite`],
    /// [`TriangleStatus::OutOfExactRange`]).
    pub level: crate::Level,
    /// How it went.
    pub status: TriangleStatus,
    /// Micro-triangles per state, indexed by [`State::bits`](crate::micromap::State::bits), before a
    /// 2-state format resolves the unknowns.
    pub counts: [u64; 4],
    /// Of the unknown ones, those the exact model knows
    /// ([`BakedTriangle::widened`]).
    pub widened: u64,
    /// Work units the bake of its distinct triangle spent (triangles that
    /// bake alike share one bake, and this figure).
    pub work: u64,
    /// Its index in the buffers: a record, or a special index (one state,
    /// also for a map that came out uniform).
    pub index: MicromapIndex,
}

impl MeshBake {
    /// How triangle `triangle` of mesh `mesh` baked; `None` past the end.
    ///
    /// ```
    /// use micromap_index::bake::mesh::{bake_mesh, Material, Mesh, MeshOptions, MeshTriangles};
    /// use micromap_index::bake::{BakedOpacity, Unorm8Texture};
    /// let texels: Vec<u8> = (0..64).map(|i| if (i % 8) < 3 { 255 } else { 0 }).collect();
    /// let texture = Unorm8Texture::new(8, 8, &texels).unwrap();
    /// let triangles = [[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]; 2];
    /// let mesh = Mesh { triangles: MeshTriangles::Uv(&triangles), texture: &texture, material: Material::default(), vertex_alpha: None };
    /// let baked = bake_mesh(&mesh, &MeshOptions::default()).unwrap();
    /// // Equal UVs: classified once.
    /// assert_eq!((baked.report.triangles, baked.report.distinct_triangles), (2, 1));
    /// assert_eq!(baked.triangle(0, 0), baked.triangle(0, 1));
    /// // Edges of 8 and 11.3 texels: level 4 (the paper's eq. 1).
    /// assert_eq!(baked.triangle(0, 1).unwrap().level.get(), 4);
    /// // A copy of the one map both use.
    /// assert_eq!(baked.opacity(0, 1), baked.opacity(0, 0));
    /// assert!(matches!(baked.opacity(0, 1), Some(BakedOpacity::Map(_))));
    /// assert!(baked.triangle(0, 2).is_none());
    /// ```
    #[must_use]
    pub fn triangle(&self, mesh: usize, triangle: usize) -> Option<TriangleBake> {
        let d = &self.distinct[*self.of_triangle.get(mesh)?.get(triangle)? as usize];
        Some(TriangleBake {
            level: d.level,
            status: d.status,
            counts: d.counts,
            widened: d.widened,
            work: d.work,
            index: *self.buffers.geometry_indices(mesh).ok()?.get(triangle)?,
        })
    }

    /// What triangle `triangle` of mesh `mesh` reads: a copy of its
    /// micromap from the buffers, or its special index's state (also for a
    /// map that came out uniform); `None` past the end.
    #[must_use]
    pub fn opacity(&self, mesh: usize, triangle: usize) -> Option<BakedOpacity> {
        self.buffers.resolve(mesh, triangle)
    }
}

/// Why [`bake_meshes`] failed.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum MeshBakeError {
    /// Mesh `mesh`'s texture, sampler or cutoff was refused by
    /// [`Baker::new`](super::Baker::new).
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
    /// The buffers could not be built.
    Buffers(BufferError),
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
        }
    }
}

impl core::error::Error for MeshBakeError {}

/// A texture whose every alpha is multiplied by `factor` as a GPU does:
/// the texel's alpha rounded to binary32, times `factor`, one binary32
/// product (exact in `f64`).
struct FactorTexture<'a> {
    inner: &'a dyn AlphaTexture,
    factor: f32,
}

impl AlphaTexture for FactorTexture<'_> {
    fn width(&self) -> u32 {
        self.inner.width()
    }
    fn height(&self) -> u32 {
        self.inner.height()
    }
    fn alpha(&self, x: u32, y: u32) -> f64 {
        // `as f32` rounds once to nearest (for `c / 255` and `c / 65535`,
        // correctly: see `texel_f32`).
        f64::from(texel_f32(self.inner.alpha(x, y)) * self.factor)
    }
}

/// A texel's alpha as the binary32 value a GPU reads. The `f64` quotient
/// `c / 255` (or `c / 65535`) rounds to the same binary32 value as the
/// exact quotient: double rounding could differ only if the `f64` value
/// were a binary32 midpoint, whose bits past the 25th are zero, while the
/// binary expansion of `c / (2^k - 1)`, `0 < c < 2^k - 1`, repeats the
/// `k`-bit pattern of `c` forever.
fn texel_f32(alpha: f64) -> f32 {
    alpha as f32
}

/// Relative widening that covers a GPU's binary32 rounding of
/// `texel * factor * vertex` (two products, at most `(1 + 2^-24)^2 - 1`
/// relative), and of the vertex alpha's interpolation (at most about
/// `6 * 2^-24` of the largest vertex alpha, see `docs/bake.md`), with room
/// for the `f64` arithmetic of the bounds.
const VERTEX_MARGIN: f64 = 1.0 / (1u64 << 20) as f64;

/// Absolute widening for products in binary32's subnormal range (each
/// rounding there errs by at most `2^-150`).
const TINY: f64 = 1.0 / (1u64 << 62) as f64 / (1u64 << 62) as f64 / (1u64 << 16) as f64;

/// Vertex alphas are grouped on this grid (bounds rounded outwards), so
/// that a mesh needs few texel classifications.
const VERTEX_GRID: f64 = 1024.0;

/// A texture whose alpha is a bound on `texel * factor * v` for every `v`
/// in `[low, high]`, as a GPU computes it: the lower bound (`upper:
/// false`), to find what is opaque for sure, or the upper (`upper: true`),
/// to find what is transparent for sure.
struct VertexBoundTexture<'a> {
    inner: &'a dyn AlphaTexture,
    factor: f64,
    low: f64,
    high: f64,
    upper: bool,
}

impl AlphaTexture for VertexBoundTexture<'_> {
    fn width(&self) -> u32 {
        self.inner.width()
    }
    fn height(&self) -> u32 {
        self.inner.height()
    }
    fn alpha(&self, x: u32, y: u32) -> f64 {
        let t = f64::from(texel_f32(self.inner.alpha(x, y))) * self.factor;
        // NaN stays NaN: it passes no cutoff, on the GPU either.
        let (a, b) = (t * self.low, t * self.high);
        let (min, max) = if a <= b { (a, b) } else { (b, a) };
        let abs = |x: f64| f64::from_bits(x.to_bits() & !(1 << 63));
        if self.upper {
            max + abs(max) * VERTEX_MARGIN + TINY
        } else {
            min - abs(min) * VERTEX_MARGIN - TINY
        }
    }
}

/// The range `[low, high]` a GPU's interpolated vertex alpha can take over
/// a triangle with vertex alphas `v`, widened by the interpolation's
/// rounding and rounded outwards to [`VERTEX_GRID`]; as bits, to group by.
fn vertex_range(v: [f32; 3]) -> (u64, u64) {
    let min = f64::from(v[0].min(v[1]).min(v[2]));
    let max = f64::from(v[0].max(v[1]).max(v[2]));
    // Floor and ceiling without `std`: the values are small (alphas in
    // [0, 1], times the grid), so the casts are exact.
    let scaled_low = (min - max * VERTEX_MARGIN) * VERTEX_GRID;
    let scaled_high = (max + max * VERTEX_MARGIN) * VERTEX_GRID;
    let floor = |x: f64| {
        let t = x as i64 as f64;
        if t > x {
            t - 1.0
        } else {
            t
        }
    };
    let ceil = |x: f64| {
        let t = x as i64 as f64;
        if t < x {
            t + 1.0
        } else {
            t
        }
    };
    let low = floor(scaled_low) / VERTEX_GRID;
    let high = ceil(scaled_high) / VERTEX_GRID;
    (low.max(0.0).to_bits(), high.to_bits())
}

/// Checks a mesh's vertex alphas.
fn check_vertex_alpha<'a>(
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

/// Twice the triangle's area in texels squared (for the area-weighted
/// known fraction); 0 if not finite.
fn texel_area(uv: &UvTriangle, (w, h): (u32, u32)) -> f64 {
    let p = uv.map(|c| {
        (
            f64::from(c[0]) * f64::from(w),
            f64::from(c[1]) * f64::from(h),
        )
    });
    let a = (p[1].0 - p[0].0) * (p[2].1 - p[0].1) - (p[1].1 - p[0].1) * (p[2].0 - p[0].0);
    // |a| without std.
    let a = f64::from_bits(a.to_bits() & !(1 << 63));
    if a.is_finite() {
        a
    } else {
        0.0
    }
}

/// [`bake_meshes`] for one mesh, without progress.
pub fn bake_mesh(mesh: &Mesh<'_>, options: &MeshOptions) -> Result<MeshBake, MeshBakeError> {
    bake_meshes(core::slice::from_ref(mesh), options, &mut |_, _| {})
}

/// Bakes every mesh: levels per triangle (the rule, then the budget over
/// all meshes), each triangle exactly ([`Baker::bake`](super::Baker::bake): sound, see
/// [`crate::bake`]), then the buffers, one geometry per mesh in order,
/// micromaps deduplicated across all, and the report.
///
/// Triangles that must bake alike (bit-for-bit equal UVs, the same level,
/// texture object, sampler, cutoff, alpha factor and vertex-alpha range)
/// are classified once ([`BakeReport::distinct_triangles`]); each map goes
/// into the buffers' builder as it is made, so memory follows the distinct
/// output. With the `rayon` feature the distinct triangles are baked on
/// [`MeshOptions::threads`] threads, in chunks balanced by their
/// micro-triangle counts.
///
/// `progress(done, total)` is called as triangles are done (`done` counts
/// input triangles, `total` over all meshes; the last call is
/// `(total, total)`). The output depends only on the inputs: the same
/// meshes and options give the same bytes, whatever the threads.
///
/// ```
/// use micromap_index::bake::mesh::{bake_meshes, LevelRule, Material, Mesh, MeshOptions, MeshTriangles};
/// use micromap_index::bake::Unorm8Texture;
/// use micromap_index::micromap::Format;
/// use micromap_index::Level;
///
/// let opaque = [255u8; 4];
/// let texture = Unorm8Texture::new(2, 2, &opaque).unwrap();
/// let triangle = [[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]];
/// let mesh = Mesh { triangles: MeshTriangles::Uv(&triangle), texture: &texture, material: Material::default(), vertex_alpha: None };
/// let options = MeshOptions { levels: LevelRule::Fixed(Level::new(3).unwrap()), format: Format::TwoState, ..MeshOptions::default() };
/// let mut last = (0, 0);
/// let baked = bake_meshes(&[mesh, mesh], &options, &mut |done, total| last = (done, total)).unwrap();
/// assert_eq!(last, (2, 2));
/// // The same triangle, texture and material: classified once.
/// assert_eq!(baked.report.distinct_triangles, 1);
/// // All opaque: each triangle is the special index "opaque", no micromap.
/// assert_eq!(baked.report.special_index_triangles, 2);
/// assert_eq!((baked.report.micromaps, baked.buffers.geometry_count()), (0, 2));
/// assert_eq!(baked.report.known_fraction, 1.0);
/// ```
pub fn bake_meshes(
    meshes: &[Mesh<'_>],
    options: &MeshOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<MeshBake, MeshBakeError> {
    let triangles = resolve_all(meshes)?;
    let (levels, period_level_zero) = levels_of(meshes, &triangles, options);

    let total: usize = triangles.iter().map(|t| t.len()).sum();
    // One pool for the whole bake: the texel tables, then the triangles.
    let runner = Runner::new(options.threads);
    let plan = Plan::new(meshes, &triangles, &levels, options, &runner)?;
    let progress = &mut builder_progress(progress, total);
    let distinct = bake_distinct(&plan, options, &runner, progress)?;
    let (mut builder, distinct) = distinct;

    // The statistics, triangle by triangle in input order (the sums are
    // the same floating-point operations in the same order as without
    // deduplication).
    let mut counts = [0u64; 4];
    let mut widened = 0u64;
    let mut status = StatusCounts::default();
    let mut known_area = 0.0;
    let mut area = 0.0;
    for ((mesh, triangles), of_triangle) in meshes.iter().zip(&triangles).zip(&plan.of_triangle) {
        let size = (mesh.texture.width(), mesh.texture.height());
        for (uv, &d) in triangles.iter().zip(of_triangle) {
            let b = &distinct[d as usize];
            for (sum, count) in counts.iter_mut().zip(b.counts) {
                *sum += count;
            }
            widened += b.widened;
            let n = b.counts.iter().sum::<u64>().max(1) as f64;
            let a = texel_area(uv, size);
            area += a;
            known_area += a * (b.counts[0] + b.counts[1]) as f64 / n;
            match b.status {
                TriangleStatus::Exact => status.exact += 1,
                TriangleStatus::NotFinite => status.not_finite += 1,
                TriangleStatus::OutOfExactRange => status.out_of_exact_range += 1,
                TriangleStatus::BlockBudgetExceeded => status.block_budget_exceeded += 1,
                TriangleStatus::WorkBudgetExceeded => status.work_budget_exceeded += 1,
            }
        }
    }

    // Buffers: one geometry per mesh, deduplicated across all.
    for of_triangle in &plan.of_triangle {
        builder
            .add_geometry_entries(of_triangle.iter().map(|&d| distinct[d as usize].entry))
            .map_err(MeshBakeError::Buffers)?;
    }
    let buffers = builder.finish().map_err(MeshBakeError::Buffers)?;
    let mut special = 0;
    for g in 0..buffers.geometry_count() {
        special += buffers
            .geometry_indices(g)
            .map_err(MeshBakeError::Buffers)?
            .iter()
            .filter(|i| matches!(i, MicromapIndex::Special(_)))
            .count();
    }
    let records: Vec<u32> = (0..buffers.records().len() as u32).collect();
    let sizes = runner.map_in_order(&records, 64, |&record| {
        buffers
            .record_bytes(record)
            .and_then(|(level, format, bytes)| packed_tree_sizes(level, format, bytes).ok())
    });
    let (mut paper_bits, mut level_order_bits) = (0u64, 0u64);
    for sizes in sizes.into_iter().flatten() {
        paper_bits += sizes.paper_bits;
        level_order_bits += sizes.level_order_bits;
    }
    // Levels 0..=12 (those DXR allows), more if used.
    let mut level_histogram = vec![0u64; 13];
    for level in levels.iter().flatten() {
        let slot = level.get() as usize;
        if slot >= level_histogram.len() {
            level_histogram.resize(slot + 1, 0);
        }
        level_histogram[slot] += 1;
    }
    while level_histogram.len() > 1 && level_histogram.last() == Some(&0) {
        level_histogram.pop();
    }
    let micro: u64 = counts.iter().sum();
    let work = distinct
        .iter()
        .fold(0u64, |sum, d| sum.saturating_add(d.work));
    let speculative_work = distinct
        .iter()
        .fold(0u64, |sum, d| sum.saturating_add(d.speculative_work));
    let report = BakeReport {
        triangles: total,
        distinct_triangles: distinct.len(),
        levels: level_histogram,
        counts,
        status,
        known_fraction: (counts[1] + counts[0]) as f64 / micro.max(1) as f64,
        known_area_fraction: if area > 0.0 { known_area / area } else { 0.0 },
        micromaps: buffers.records().len(),
        special_index_triangles: special,
        bytes_flat: buffers.data().len(),
        bytes_paper_tree: paper_bits.div_ceil(8),
        bytes_level_order_tree: level_order_bits.div_ceil(8),
        widened,
        work,
        speculative_work,
        period_level_zero,
    };
    Ok(MeshBake {
        buffers,
        report,
        distinct,
        of_triangle: plan.of_triangle,
    })
}

/// Micro-triangles (the cost model: [`distinct::Work::cost`]) baked
/// between two hand-overs to the builder, per thread: enough work per
/// thread to balance uneven triangles (64 level-8 triangles), little enough
/// that the maps in flight stay small next to the output (1 MiB of 4-state
/// data per thread). A chunk has at least one triangle per thread.
const CHUNK_COST_PER_THREAD: u64 = 1 << 22;

/// Work items one task takes at least: small triangles are batched until a
/// task classifies about this many micro-triangles.
const TASK_COST: u64 = 1 << 14;

/// `progress(done, total)` in triangles, from the distinct triangles baked.
fn builder_progress(
    progress: &mut dyn FnMut(usize, usize),
    total: usize,
) -> impl FnMut(usize) + '_ {
    let mut done = 0usize;
    move |triangles| {
        done += triangles;
        progress(done, total);
    }
}

/// Bakes every distinct triangle of `plan`, in chunks of about
/// [`CHUNK_COST_PER_THREAD`] micro-triangles per thread, each chunk on
/// every thread and then handed to the builder in order (so the maps are
/// added in first-appearance order, whatever the threads, and only one
/// chunk's maps exist outside the builder). `progress` gets the triangles
/// each chunk stands for.
///
/// The work budgets are those of the serial bake, whatever the threads:
/// distinct triangle `i` (in first-appearance order) may spend
/// `min(triangle_work_budget, what 0..i left of bake_work_budget)`. A
/// chunk is baked in parallel with what was left at its start (at least
/// that); a bake that spent less than its serial allowance took every
/// budget check the serial bake takes, so it is that bake, and any other
/// is baked again with its serial allowance (only at the chunk where the
/// bake budget runs out).
fn bake_distinct(
    plan: &Plan,
    options: &MeshOptions,
    runner: &Runner,
    progress: &mut dyn FnMut(usize),
) -> Result<(MicromapBuffersBuilder, Vec<Distinct>), MeshBakeError> {
    let threads = runner.threads().max(1);
    let chunk_cost = CHUNK_COST_PER_THREAD.saturating_mul(threads as u64);
    // A large triangle is split over the pool's threads when there are
    // several (`Baker::walk`; the same result either way).
    let bake =
        |w: &distinct::Work, max_work: u64, split: bool| -> Result<BakedTriangle, MeshBakeError> {
            let (format, unknown) = (options.format, options.unknown);
            let baker = &plan.bakers[w.baker as usize];
            let mips = &plan.mips[w.baker as usize];
            match w.bound {
                None if mips.is_empty() => baker
                    .bake_split(&w.uv, w.level, format, unknown, max_work, split)
                    .map_err(MeshBakeError::Bake),
                None => {
                    let mut pairs = vec![(baker, baker)];
                    pairs.extend(mips.iter().map(|(low, high)| (low, high)));
                    bake_bounded(&pairs, &w.uv, w.level, format, unknown, max_work)
                        .map_err(MeshBakeError::Bake)
                }
                Some(b) => {
                    let (low, high) = &plan.bounds[b as usize];
                    bake_bounded(&[(low, high)], &w.uv, w.level, format, unknown, max_work)
                        .map_err(MeshBakeError::Bake)
                }
            }
        };
    let mut builder = MicromapBuffersBuilder::new(options.buffers);
    let mut distinct = Vec::new();
    distinct
        .try_reserve_exact(plan.work.len())
        .map_err(|_| MeshBakeError::Buffers(BufferError::AllocationFailed))?;
    let mut work_left = options.bake_work_budget;
    let mut start = 0;
    while start < plan.work.len() {
        let (mut end, mut cost) = (start, 0u64);
        while end < plan.work.len() && (end - start < threads || cost < chunk_cost) {
            cost = cost.saturating_add(plan.work[end].cost());
            end += 1;
        }
        let chunk = &plan.work[start..end];
        let min_len = (TASK_COST / (cost / chunk.len() as u64).max(1)).max(1) as usize;
        let at_start = options.triangle_work_budget.min(work_left);
        let baked = runner.map_in_order(chunk, min_len, |w| bake(w, at_start, threads > 1));
        let mut triangles = 0;
        for (w, b) in chunk.iter().zip(baked) {
            let allowance = options.triangle_work_budget.min(work_left);
            let mut b = b?;
            if allowance < at_start && b.work >= allowance {
                b = bake(w, allowance, false)?;
            }
            work_left = work_left.saturating_sub(b.work);
            let level = b.opacity.level();
            let entry = match b.opacity {
                BakedOpacity::Map(map) => {
                    builder.add_micromap(&map).map_err(MeshBakeError::Buffers)?
                }
                BakedOpacity::Special(state) => MicromapBuffersBuilder::special(state),
            };
            distinct.push(Distinct {
                level,
                status: b.status,
                counts: b.counts,
                widened: b.widened,
                work: b.work,
                speculative_work: b.speculative_work,
                entry,
            });
            triangles += w.triangles;
        }
        progress(triangles);
        start = end;
    }
    Ok((builder, distinct))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::Unorm8Texture;
    use crate::micromap::BakedOpacity;
    use crate::Level;

    #[test]
    fn indexed_and_uv_triangles_bake_alike() {
        let texels: Vec<u8> = (0..64).map(|i| if (i % 8) < 3 { 255 } else { 0 }).collect();
        let texture = Unorm8Texture::new(8, 8, &texels).unwrap();
        // Interleaved: (u, v, extra) per vertex.
        let data = [0.0, 0.0, 9.0, 1.0, 0.0, 9.0, 1.0, 1.0, 9.0, 0.0, 1.0, 9.0];
        let indices = [0, 1, 2, 0, 2, 3];
        let triangles = [
            [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]],
            [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        ];
        let mesh = |triangles| Mesh {
            triangles,
            texture: &texture,
            material: Material::default(),
            vertex_alpha: None,
        };
        let options = MeshOptions::default();
        let a = bake_mesh(
            &mesh(MeshTriangles::Indexed {
                indices: &indices,
                uvs: &data,
                stride: 3,
            }),
            &options,
        )
        .unwrap();
        let b = bake_mesh(&mesh(MeshTriangles::Uv(&triangles)), &options).unwrap();
        assert_eq!(a.report, b.report);
        assert_eq!(a.buffers, b.buffers);
        for t in 0..2 {
            assert_eq!(a.triangle(0, t), b.triangle(0, t));
        }
        // Out of range, and a bad layout.
        let bad = bake_mesh(
            &mesh(MeshTriangles::Indexed {
                indices: &[0, 1, 4],
                uvs: &data,
                stride: 3,
            }),
            &options,
        );
        assert_eq!(
            bad.unwrap_err(),
            MeshBakeError::Index {
                mesh: 0,
                triangle: 0,
                index: 4,
                vertices: 4
            }
        );
        let bad = bake_mesh(
            &mesh(MeshTriangles::Indexed {
                indices: &[0, 1],
                uvs: &data,
                stride: 3,
            }),
            &options,
        );
        assert!(matches!(bad, Err(MeshBakeError::Layout { .. })));
    }

    #[test]
    fn the_alpha_factor_scales_the_texture() {
        let texels = [128u8; 4];
        let texture = Unorm8Texture::new(2, 2, &texels).unwrap();
        let triangle = [[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]];
        let bake = |alpha_factor| {
            let mesh = Mesh {
                triangles: MeshTriangles::Uv(&triangle),
                texture: &texture,
                material: Material {
                    alpha_factor,
                    ..Material::default()
                },
                vertex_alpha: None,
            };
            bake_mesh(&mesh, &MeshOptions::default()).unwrap().report
        };
        // 128/255 passes 0.5; times 0.5 it does not. Edges of 2 and 2.8
        // texels: level 2, 16 micro-triangles.
        assert_eq!(bake(1.0).counts, [0, 16, 0, 0]);
        assert_eq!(bake(0.5).counts, [16, 0, 0, 0]);
    }

    #[test]
    fn vertex_ranges_cover_the_interpolation_error() {
        let (low, high) = vertex_range([1.0, 1.0, 1.0]);
        let (low, high) = (f64::from_bits(low), f64::from_bits(high));
        let u = 1.0 / (1u64 << 24) as f64;
        assert!(low <= 1.0 - 8.0 * u && high >= 1.0 + 8.0 * u);
        assert!(low >= 1.0 - 1.0 / 512.0 && high <= 1.0 + 1.0 / 512.0);
        let (low, high) = vertex_range([0.0, 0.25, 0.5]);
        assert_eq!(f64::from_bits(low), 0.0);
        assert!(f64::from_bits(high) >= 0.5 * (1.0 + 8.0 * u));
    }

    /// Vertex alpha 1 on a texture far from the cutoff bakes as without
    /// it, in both formats (the two bounds agree, and the combination
    /// keeps the known states and resolves unknowns as the baker does).
    #[test]
    fn vertex_alpha_one_far_from_the_cutoff_changes_nothing() {
        let texels: Vec<u8> = (0..64).map(|i| if (i % 8) < 3 { 255 } else { 0 }).collect();
        let texture = Unorm8Texture::new(8, 8, &texels).unwrap();
        let triangles = [
            [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]],
            [[0.1, 0.0], [1.0, 0.3], [0.0, 1.0]],
        ];
        let ones = [[1.0f32; 3]; 2];
        for format in [Format::FourState, Format::TwoState] {
            let options = MeshOptions {
                levels: LevelRule::Fixed(Level::new(4).unwrap()),
                format,
                ..MeshOptions::default()
            };
            let bake = |vertex_alpha| {
                let mesh = Mesh {
                    triangles: MeshTriangles::Uv(&triangles),
                    texture: &texture,
                    material: Material::default(),
                    vertex_alpha,
                };
                bake_mesh(&mesh, &options).unwrap()
            };
            let (a, b) = (bake(None), bake(Some(&ones)));
            assert_eq!(a.report.counts, b.report.counts);
            assert_eq!(a.buffers, b.buffers);
            for t in 0..triangles.len() {
                // The same bake but for the work: two bounds cost more.
                let without_work =
                    |x: Option<TriangleBake>| x.map(|x| TriangleBake { work: 0, ..x });
                assert_eq!(
                    without_work(a.triangle(0, t)),
                    without_work(b.triangle(0, t))
                );
                assert!(matches!(a.opacity(0, t), Some(BakedOpacity::Map(_))));
            }
        }
    }
}
