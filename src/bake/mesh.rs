//! Whole meshes: [`bake_meshes`] chooses a level per triangle, fits a byte
//! budget, bakes every triangle exactly ([`Baker::bake`](super::Baker::bake)), deduplicates the
//! micromaps into API buffers ([`MicromapBuffers`](crate::micromap::MicromapBuffers), one geometry per mesh)
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

use super::mips::bake_bounded;
use super::parallel::Runner;
use super::triangle::{BakedTriangle, TriangleStatus, UvTriangle};
use crate::micromap::BakedOpacity;
use crate::micromap::{MicromapBuffersBuilder, MicromapIndex};
use crate::succinct::packed_tree_sizes;
use alloc::vec;
use alloc::vec::Vec;
use distinct::{Distinct, Plan};
use levels::{levels_of, resolve_all};

mod distinct;
mod input;
// The levels bake_meshes chooses, and the output bound callers check first.
mod levels;
mod report;
mod verify;

pub use super::level::LevelRule;
pub use super::material::Material;
pub use super::mips::Mips;
pub use input::{Mesh, MeshBakeError, MeshOptions, MeshTriangles};
pub use levels::{chosen_levels, output_bytes_bound};
pub use report::{BakeReport, MeshBake, StatusCounts, TriangleBake};
pub use verify::{verify_mesh, MeshVerification, MeshVerifyError};

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
    let a = super::float::abs(a);
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
    let (levels, period_level_zero) = levels_of(meshes, &triangles, options)?;

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
            let a = texel_area(&mesh.material.placed(uv), size);
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
    let mut records = input::room(buffers.records().len())?;
    records.extend(0..buffers.records().len() as u32);
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
    let bake_one =
        |w: &distinct::Work, max_work: u64, split: bool| -> Result<BakedTriangle, MeshBakeError> {
            let (format, unknown) = (options.format, options.unknown);
            let baker = &plan.bakers[w.baker as usize];
            let mips = &plan.mips[w.baker as usize];
            match w.bound {
                None if mips.is_empty() => baker
                    .bake_split((&w.uv, w.alphas), w.level, format, unknown, max_work, split)
                    .map_err(MeshBakeError::Bake),
                None => {
                    let mut pairs = vec![(baker, baker)];
                    pairs.extend(mips.iter().map(|(low, high)| (low, high)));
                    bake_bounded(&pairs, &w.uv, w.level, format, unknown, max_work)
                        .map_err(MeshBakeError::Bake)
                }
                Some(b) => {
                    let (low, high) = (&plan.bounds[b.0 as usize], &plan.bounds[b.1 as usize]);
                    bake_bounded(&[(low, high)], &w.uv, w.level, format, unknown, max_work)
                        .map_err(MeshBakeError::Bake)
                }
            }
        };
    // A group of vertex-alpha variants is baked by its first, in one walk
    // (`distinct::Plan::group_variants`); the others' bakes wait in `held`
    // until their turn. `None`: a variant baked by its group's first.
    let bake = |w: &distinct::Work,
                max_work: u64,
                split: bool|
     -> Result<Option<Vec<BakedTriangle>>, MeshBakeError> {
        if w.leader.is_some() {
            return Ok(None);
        }
        if w.members.len() < 2 {
            return bake_one(w, max_work, split).map(|b| Some(vec![b]));
        }
        let baker = &plan.bakers[w.baker as usize];
        let mut alphas = input::room(w.members.len())?;
        for &m in &w.members {
            alphas.push(plan.work[m as usize].alphas.unwrap_or([1.0; 3]));
        }
        baker
            .bake_variants(
                baker.model,
                (&w.uv, &alphas),
                w.level,
                (options.format, options.unknown),
                max_work,
            )
            .map(Some)
            .map_err(MeshBakeError::Bake)
    };
    let mut held: alloc::collections::BTreeMap<u32, BakedTriangle> =
        alloc::collections::BTreeMap::new();
    let mut builder = MicromapBuffersBuilder::new(options.buffers);
    let mut distinct = input::room(plan.work.len())?;
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
        for ((id, w), b) in (start..).zip(chunk).zip(baked) {
            let allowance = options.triangle_work_budget.min(work_left);
            let mut b = match b? {
                Some(group) => {
                    let mut group = group.into_iter();
                    let first = group.next().expect("a bake per variant, the first first");
                    for (&m, b) in w.members.iter().skip(1).zip(group) {
                        held.insert(m, b);
                    }
                    first
                }
                None => held
                    .remove(&(id as u32))
                    .expect("a group's first comes before its other variants"),
            };
            if allowance < at_start && b.work >= allowance {
                b = bake_one(w, allowance, false)?;
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
    use crate::bake::material::vertex_range;
    use crate::bake::Unorm8Texture;
    use crate::micromap::{BakedOpacity, Format};
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
                    uv_transform: crate::bake::UvTransform::IDENTITY,
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

    /// Snapping never narrows a range, keeps at most `VERTEX_BOUNDS` values
    /// per side, and keeps every value where there are few.
    #[test]
    fn vertex_bounds_snap_outwards_to_few_values() {
        use crate::bake::material::{VertexBounds, VERTEX_BOUNDS};
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        for count in [1, 5, VERTEX_BOUNDS, VERTEX_BOUNDS + 1, 300] {
            let ranges: Vec<(u64, u64)> = (0..count)
                .map(|_| vertex_range([next(), next(), next()]))
                .collect();
            let bounds = VertexBounds::new(
                ranges.iter().map(|r| r.0).collect(),
                ranges.iter().map(|r| r.1).collect(),
            );
            let mut lows = alloc::collections::BTreeSet::new();
            let mut highs = alloc::collections::BTreeSet::new();
            for &r in &ranges {
                let (low, high) = bounds.snap(r);
                assert!(f64::from_bits(low) <= f64::from_bits(r.0), "{count}: {r:?}");
                assert!(
                    f64::from_bits(high) >= f64::from_bits(r.1),
                    "{count}: {r:?}"
                );
                lows.insert(low);
                highs.insert(high);
                if count <= VERTEX_BOUNDS {
                    assert_eq!((low, high), r, "few ranges snap to themselves");
                }
            }
            assert!(lows.len() <= VERTEX_BOUNDS && highs.len() <= VERTEX_BOUNDS);
        }
    }

    /// A smooth vertex alpha (every triangle a range of its own, far more
    /// than `VERTEX_BOUNDS`) bakes soundly: at every point of a known
    /// micro-triangle (corners, edges and inside) the exact `texel * v` is
    /// on the state's side of the cutoff; and a triangle knows no more than
    /// baked alone (where its range is exact).
    #[test]
    fn smooth_vertex_alpha_bakes_soundly_with_few_bounds() {
        let texels: Vec<u8> = (0..16u32).map(|i| (i * 37 % 256) as u8).collect();
        let texture = Unorm8Texture::new(16, 1, &texels).unwrap();
        let material = Material {
            sampler: crate::bake::Sampler {
                filter: crate::bake::Filter::Nearest,
                address_u: crate::bake::AddressMode::ClampToEdge,
                address_v: crate::bake::AddressMode::ClampToEdge,
                border_alpha: 0.0,
            },
            ..Material::default()
        };
        let count = 120usize;
        let triangles: Vec<UvTriangle> = (0..count)
            .map(|t| {
                let x = (t % 12) as f32 / 12.0;
                [[x, 0.0], [x + 0.3, 0.0], [x, 1.0]]
            })
            .collect();
        let alphas: Vec<[f32; 3]> = (0..count)
            .map(|t| {
                let a = 0.55 + 0.45 * (t as f32 / count as f32);
                [a, a * 0.97, (a * 1.01).min(1.0)]
            })
            .collect();
        let level = Level::new(3).unwrap();
        let options = MeshOptions {
            levels: LevelRule::Fixed(level),
            ..MeshOptions::default()
        };
        let mesh = |t: core::ops::Range<usize>| Mesh {
            triangles: MeshTriangles::Uv(&triangles[t.clone()]),
            texture: &texture,
            material,
            vertex_alpha: Some(&alphas[t]),
        };
        let baked = bake_mesh(&mesh(0..count), &options).unwrap();
        let mut known = 0;
        for (t, uv) in triangles.iter().enumerate() {
            let opacity = baked.opacity(0, t).unwrap();
            let alone = bake_mesh(&mesh(t..t + 1), &options).unwrap();
            let alone = alone.opacity(0, 0).unwrap();
            for i in 0..64u64 {
                let state = opacity.state(i).unwrap();
                if !state.is_known() {
                    continue;
                }
                known += 1;
                assert_eq!(alone.state(i), Some(state), "triangle {t} micro {i}");
                let micro = crate::inverse::micro_triangle(level, i).unwrap();
                let [p, q, r] = micro.vertices_f64();
                for j in 0..=6 {
                    for k in 0..=(6 - j) {
                        let (s, w) = (f64::from(j) / 6.0, f64::from(k) / 6.0);
                        let b1 = (1.0 - s - w) * p.0 + s * q.0 + w * r.0;
                        let b2 = (1.0 - s - w) * p.1 + s * q.1 + w * r.1;
                        let at = |c: usize| {
                            (1.0 - b1 - b2) * f64::from(uv[0][c])
                                + b1 * f64::from(uv[1][c])
                                + b2 * f64::from(uv[2][c])
                        };
                        let x = (at(0) * 16.0).floor().clamp(0.0, 15.0) as usize;
                        // Points on a texel edge may read either texel.
                        if (at(0) * 16.0 - (at(0) * 16.0).round()).abs() < 1e-9 {
                            continue;
                        }
                        let va = alphas[t];
                        let v = (1.0 - b1 - b2) * f64::from(va[0])
                            + b1 * f64::from(va[1])
                            + b2 * f64::from(va[2]);
                        let alpha = f64::from(texels[x]) / 255.0 * v;
                        let opaque = alpha >= 0.5;
                        assert_eq!(
                            opaque,
                            state == crate::micromap::State::Opaque,
                            "triangle {t} micro {i}: alpha {alpha} at ({b1}, {b2})"
                        );
                    }
                }
            }
        }
        assert!(known > 1000, "{known}");

        // Each triangle baked alone knows by its exact range; the verifier
        // judges them all together first by the mesh's grid, which is
        // coarser, so it finds contradictions that are not there, and
        // judges those triangles again by their exact ranges: sound. A
        // state made wrong is caught and reported.
        let maps: Vec<BakedOpacity> = (0..count)
            .map(|t| {
                bake_mesh(&mesh(t..t + 1), &options)
                    .unwrap()
                    .opacity(0, 0)
                    .unwrap()
            })
            .collect();
        let opacities: Vec<_> = maps.iter().map(BakedOpacity::as_opacity).collect();
        let mut seen = 0;
        let verdict = verify_mesh(
            &mesh(0..count),
            &opacities,
            &options,
            u64::MAX,
            &mut |_, _| seen += 1,
        )
        .unwrap();
        assert!(verdict.is_sound(count), "{verdict:?}");
        assert_eq!(seen, 0);
        // Triangle 3 all opaque: some of its micro-triangles read texels
        // under the cutoff at every vertex alpha.
        let all_opaque = crate::micromap::TriangleOpacity::Special(crate::micromap::State::Opaque);
        let mut wrong = opacities.clone();
        wrong[3] = all_opaque;
        let mut reported = Vec::new();
        let verdict = verify_mesh(&mesh(0..count), &wrong, &options, u64::MAX, &mut |t, _| {
            reported.push(t);
        })
        .unwrap();
        assert!(
            verdict.contradictions > 0 && reported.iter().all(|&t| t == 3),
            "{reported:?}"
        );
        assert_eq!(reported.len() as u64, verdict.contradictions);
    }

    /// Under linear filtering by value the walk reads the vertex alpha per
    /// part: at every point of a known micro-triangle the exact bilinear
    /// value times the exact interpolated alpha is on the state's side of
    /// the cutoff; triangles whose alpha crosses the cutoff's level are
    /// known on both sides of it; the verifier calls the bake sound and
    /// catches a state made wrong; equal UVs with equal alphas share a
    /// bake, equal UVs with other alphas do not.
    #[test]
    fn vertex_alpha_is_read_per_part_under_linear_filtering() {
        let (w, h) = (16usize, 16usize);
        let texels: Vec<u8> = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f64, (i / w) as f64);
                (127.5 + 127.5 * ((x * 0.7).sin() * (y * 0.45).cos())) as u8
            })
            .collect();
        let texture = Unorm8Texture::new(w as u32, h as u32, &texels).unwrap();
        let material = Material {
            sampler: crate::bake::Sampler {
                filter: crate::bake::Filter::Linear,
                address_u: crate::bake::AddressMode::ClampToEdge,
                address_v: crate::bake::AddressMode::ClampToEdge,
                border_alpha: 0.0,
            },
            ..Material::default()
        };
        let count = 40usize;
        let mut triangles: Vec<UvTriangle> = (0..count)
            .map(|t| {
                let (x, y) = ((t % 8) as f32 / 10.0, (t / 8) as f32 / 6.0);
                [[x, y], [x + 0.25, y + 0.05], [x + 0.02, y + 0.3]]
            })
            .collect();
        let mut alphas: Vec<[f32; 3]> = (0..count)
            .map(|t| {
                let a = 0.3 + 0.7 * (t as f32 / count as f32);
                [1.0, a, (1.3 - a).clamp(0.0, 1.0)]
            })
            .collect();
        // Two repeats: one with the same alphas (shares the bake), one
        // with others (does not).
        triangles.extend([triangles[5], triangles[5]]);
        alphas.extend([alphas[5], [0.5, 0.5, 0.5]]);
        let level = Level::new(4).unwrap();
        let options = MeshOptions {
            levels: LevelRule::Fixed(level),
            ..MeshOptions::default()
        };
        let mesh = Mesh {
            triangles: MeshTriangles::Uv(&triangles),
            texture: &texture,
            material,
            vertex_alpha: Some(&alphas),
        };
        let baked = bake_mesh(&mesh, &options).unwrap();
        assert_eq!(baked.report.distinct_triangles, count + 1);
        // The variants of one UV triangle are walked together; each bakes
        // as it does alone (and as a group of its own repeats).
        let mut grouped = triangles.clone();
        let mut grouped_alphas = alphas.clone();
        for &a in &alphas[..count] {
            grouped.push(triangles[0]);
            grouped_alphas.push(a);
        }
        let many = Mesh {
            triangles: MeshTriangles::Uv(&grouped),
            vertex_alpha: Some(&grouped_alphas),
            ..mesh
        };
        let many = bake_mesh(&many, &options).unwrap();
        for t in 0..triangles.len() {
            let alone = Mesh {
                triangles: MeshTriangles::Uv(&triangles[t..=t]),
                vertex_alpha: Some(&alphas[t..=t]),
                ..mesh
            };
            let alone = bake_mesh(&alone, &options).unwrap();
            let states =
                |x: Option<TriangleBake>| x.map(|x| (x.level, x.status, x.counts, x.widened));
            assert_eq!(
                states(alone.triangle(0, 0)),
                states(baked.triangle(0, t)),
                "triangle {t}"
            );
            assert_eq!(alone.opacity(0, 0), baked.opacity(0, t), "triangle {t}");
            assert_eq!(alone.opacity(0, 0), many.opacity(0, t), "triangle {t}");
        }
        for t in 0..count {
            let alone = Mesh {
                triangles: MeshTriangles::Uv(&triangles[0..1]),
                vertex_alpha: Some(&alphas[t..=t]),
                ..mesh
            };
            let alone = bake_mesh(&alone, &options).unwrap();
            let at = triangles.len() + t;
            assert_eq!(alone.opacity(0, 0), many.opacity(0, at), "variant {t}");
        }
        // The exact filtered value at texel coordinates (x, y), clamped.
        let texel = |x: isize, y: isize| {
            let (x, y) = (x.clamp(0, w as isize - 1), y.clamp(0, h as isize - 1));
            f64::from(texels[y as usize * w + x as usize]) / 255.0
        };
        let bilinear = |x: f64, y: f64| {
            let (fx, fy) = ((x - 0.5).floor(), (y - 0.5).floor());
            let (a, b) = (x - 0.5 - fx, y - 0.5 - fy);
            let (i, j) = (fx as isize, fy as isize);
            (1.0 - a) * (1.0 - b) * texel(i, j)
                + a * (1.0 - b) * texel(i + 1, j)
                + (1.0 - a) * b * texel(i, j + 1)
                + a * b * texel(i + 1, j + 1)
        };
        let (mut known, mut crossing_known) = (0u64, [0u64; 2]);
        for (t, uv) in triangles.iter().enumerate() {
            let opacity = baked.opacity(0, t).unwrap();
            let va = alphas[t];
            for i in 0..(1u64 << (2 * level.get())) {
                let state = opacity.state(i).unwrap();
                if !state.is_known() {
                    continue;
                }
                known += 1;
                let micro = crate::inverse::micro_triangle(level, i).unwrap();
                let [p, q, r] = micro.vertices_f64();
                let mut sides = [false; 2];
                for j in 0..=8 {
                    for k in 0..=(8 - j) {
                        let (s, z) = (f64::from(j) / 8.0, f64::from(k) / 8.0);
                        let b1 = (1.0 - s - z) * p.0 + s * q.0 + z * r.0;
                        let b2 = (1.0 - s - z) * p.1 + s * q.1 + z * r.1;
                        let at = |c: usize| {
                            (1.0 - b1 - b2) * f64::from(uv[0][c])
                                + b1 * f64::from(uv[1][c])
                                + b2 * f64::from(uv[2][c])
                        };
                        let v = (1.0 - b1 - b2) * f64::from(va[0])
                            + b1 * f64::from(va[1])
                            + b2 * f64::from(va[2]);
                        let texture_alpha = bilinear(at(0) * w as f64, at(1) * h as f64);
                        sides[usize::from(texture_alpha >= 0.5)] = true;
                        let alpha = texture_alpha * v;
                        if (alpha - 0.5).abs() < 1e-6 {
                            continue;
                        }
                        assert_eq!(
                            alpha >= 0.5,
                            state == crate::micromap::State::Opaque,
                            "triangle {t} micro {i}: alpha {alpha} at ({b1}, {b2})"
                        );
                    }
                }
                // Known where the texture alone would say otherwise: the
                // alpha, read per part, decided it.
                if sides[1] && state == crate::micromap::State::Transparent {
                    crossing_known[0] += 1;
                }
                if sides[1] && state == crate::micromap::State::Opaque {
                    crossing_known[1] += 1;
                }
            }
        }
        assert!(known > 4000, "{known}");
        assert!(
            crossing_known[0] > 20 && crossing_known[1] > 20,
            "{crossing_known:?}"
        );
        let opacities: Vec<_> = (0..triangles.len())
            .map(|t| baked.opacity(0, t).unwrap())
            .collect();
        let opacities: Vec<_> = opacities.iter().map(BakedOpacity::as_opacity).collect();
        let verdict = verify_mesh(&mesh, &opacities, &options, u64::MAX, &mut |_, _| {}).unwrap();
        assert!(verdict.is_sound(triangles.len()), "{verdict:?}");
        // Triangle 7 all opaque: its alpha is below the cutoff somewhere.
        let mut wrong = opacities.clone();
        wrong[7] = crate::micromap::TriangleOpacity::Special(crate::micromap::State::Opaque);
        let mut reported = Vec::new();
        let verdict = verify_mesh(&mesh, &wrong, &options, u64::MAX, &mut |t, _| {
            reported.push(t);
        })
        .unwrap();
        assert!(
            verdict.contradictions > 0 && reported.iter().all(|&t| t == 7),
            "{reported:?}"
        );
    }
}
