//! The levels [`bake_meshes`](super::bake_meshes) chooses per triangle, and an upper bound on
//! its output computed from them before anything is baked.

use super::input::{room, Mesh, MeshBakeError, MeshOptions};
use crate::bake::level::levels_within_budget;
use crate::bake::triangle::UvTriangle;
use crate::micromap::{IndexWidth, Micromap};
use crate::Level;
use alloc::borrow::Cow;
use alloc::vec::Vec;

/// Each triangle's level, mesh by mesh, as [`bake_meshes`](super::bake_meshes) chooses them:
/// the [`LevelRule`](super::LevelRule), then the byte budget over all meshes
/// ([`levels_within_budget`]).
pub fn chosen_levels(
    meshes: &[Mesh<'_>],
    options: &MeshOptions,
) -> Result<Vec<Vec<Level>>, MeshBakeError> {
    let triangles = resolve_all(meshes)?;
    Ok(levels_of(meshes, &triangles, options)?.0)
}

/// An upper bound, before any micro-triangle is baked, on the bytes of
/// [`bake_meshes`](super::bake_meshes)'s buffers with indices of `width`: the data of every
/// triangle's micromap at its [`chosen_levels`] level before deduplication
/// (maps that deduplicate or become special indices only shrink it), the
/// 8-byte records, the indices and the usage counts (at most 34 of 12
/// bytes). A caller refuses a bake over its memory limit with it.
///
/// ```
/// use micromap_index::bake::mesh::{output_bytes_bound, LevelRule, Material, Mesh, MeshOptions, MeshTriangles};
/// use micromap_index::bake::Unorm8Texture;
/// use micromap_index::micromap::IndexWidth;
/// use micromap_index::Level;
///
/// let texels = [0u8, 255, 255, 0];
/// let texture = Unorm8Texture::new(2, 2, &texels).unwrap();
/// let triangle = [[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]];
/// let mesh = Mesh { triangles: MeshTriangles::Uv(&triangle), texture: &texture, material: Material::default(), vertex_alpha: None };
/// let options = MeshOptions { levels: LevelRule::Fixed(Level::new(4).unwrap()), ..MeshOptions::default() };
/// // One level-4 4-state map (64 bytes), a record, a 32-bit index, the usage counts.
/// assert_eq!(output_bytes_bound(&[mesh], &options, IndexWidth::U32)?, 64 + 8 + 4 + 34 * 12);
/// # Ok::<(), micromap_index::bake::mesh::MeshBakeError>(())
/// ```
pub fn output_bytes_bound(
    meshes: &[Mesh<'_>],
    options: &MeshOptions,
    width: IndexWidth,
) -> Result<u64, MeshBakeError> {
    let per_triangle = 8 + width.bytes() as u64;
    let levels = chosen_levels(meshes, options)?;
    Ok(levels.iter().flatten().fold(34 * 12, |sum: u64, &level| {
        sum.saturating_add(Micromap::byte_len(level, options.format) as u64)
            .saturating_add(per_triangle)
    }))
}

pub(super) fn resolve_all<'a>(
    meshes: &'a [Mesh<'_>],
) -> Result<Vec<Cow<'a, [UvTriangle]>>, MeshBakeError> {
    let mut all = room(meshes.len())?;
    for (m, mesh) in meshes.iter().enumerate() {
        all.push(mesh.triangles.resolve(m)?);
    }
    Ok(all)
}

/// Each triangle's level ([`LevelRule::level_of`](super::LevelRule::level_of), then the byte budget),
/// and how many triangles the period rule lowered to level 0.
pub(super) fn levels_of(
    meshes: &[Mesh<'_>],
    triangles: &[Cow<'_, [UvTriangle]>],
    options: &MeshOptions,
) -> Result<(Vec<Vec<Level>>, usize), MeshBakeError> {
    let mut period_level_zero = 0;
    let mut levels: Vec<Vec<Level>> = room(meshes.len())?;
    for (mesh, triangles) in meshes.iter().zip(triangles) {
        let size = (mesh.texture.width(), mesh.texture.height());
        let mut mesh_levels = room(triangles.len())?;
        for uv in triangles.iter() {
            // The level of the triangle the shader samples (its placed image).
            let placed = mesh.material.placed(uv);
            let (level, lowered) = options
                .levels
                .level_of(&placed, size, mesh.material.sampler);
            period_level_zero += usize::from(lowered);
            mesh_levels.push(level);
        }
        levels.push(mesh_levels);
    }
    if let Some(budget) = options.budget_bytes {
        let mut flat = room(levels.iter().map(Vec::len).sum())?;
        flat.extend(levels.iter().flatten().copied());
        let mut capped = levels_within_budget(&flat, options.format, budget).into_iter();
        for mesh_levels in &mut levels {
            for level in mesh_levels.iter_mut() {
                *level = capped.next().unwrap_or(*level);
            }
        }
    }
    Ok((levels, period_level_zero))
}
