//! What [`bake_meshes`](super::bake_meshes) returns: the buffers and the
//! statistics ([`MeshBake`], [`BakeReport`], [`StatusCounts`]), and how
//! each triangle baked ([`TriangleBake`]).

use super::distinct::Distinct;
use crate::bake::triangle::TriangleStatus;
use crate::micromap::{BakedOpacity, MicromapBuffers, MicromapIndex};
use alloc::vec::Vec;

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

/// What [`bake_meshes`](crate::bake::mesh::bake_meshes) found, over all meshes.
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
    /// widening cost ([`BakedTriangle::widened`](crate::bake::BakedTriangle::widened); 0 under the exact
    /// model). `(counts[0] + counts[1] + widened) / micro-triangles` is
    /// the known fraction the exact model would have.
    pub widened: u64,
    /// Work units spent, all triangles together ([bounded work](crate::bake#bounded-work)):
    /// what the serial bake spends, whatever the threads (the budgets
    /// count these).
    pub work: u64,
    /// Work units spent besides and thrown away by triangles split over
    /// several threads whose budget ran out
    /// ([`BakedTriangle::speculative_work`](crate::bake::BakedTriangle::speculative_work)); 0 on one thread. `work +
    /// speculative_work` is all the work done.
    pub speculative_work: u64,
    /// Triangles [`LevelRule::Useful`](crate::bake::mesh::LevelRule::Useful) baked at level 0 because their
    /// micro-triangles would each hold a whole texture period
    /// ([`level_within_periods`](crate::bake::level_within_periods)).
    pub period_level_zero: usize,
}

/// What [`bake_meshes`](crate::bake::mesh::bake_meshes) returns: the buffers, the report, and how each
/// triangle baked ([`triangle`](Self::triangle), for previews and checks).
#[derive(Clone, Debug)]
pub struct MeshBake {
    /// One geometry per mesh, micromaps deduplicated across all.
    pub buffers: MicromapBuffers,
    /// The statistics.
    pub report: BakeReport,
    /// Each distinct triangle's bake (its map is in the buffers).
    pub(super) distinct: Vec<Distinct>,
    /// Per mesh, per triangle: its distinct triangle.
    pub(super) of_triangle: Vec<Vec<u32>>,
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
    /// ([`BakedTriangle::widened`](crate::bake::BakedTriangle::widened)).
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
    /// use micromap_index::bake::Unorm8Texture;
    /// use micromap_index::micromap::BakedOpacity;
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
