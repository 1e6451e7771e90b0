//! [`verify_mesh`]: anyone's micromaps for a [`Mesh`] checked against its
//! texture and material as [`bake_meshes`](super::bake_meshes) models them
//! (alpha factor, vertex alpha), with [`Baker::verify_each`].

use super::input::{check_vertex_alpha, push_vertex_ranges, Mesh, MeshBakeError, MeshOptions};
use crate::bake::alpha_test::{judges_by_value, VertexScale};
use crate::bake::baker::Baker;
use crate::bake::material::{vertex_bound_baker, vertex_range, FactorTexture, VertexBounds};
use crate::bake::parallel::Runner;
use crate::bake::verify::Contradiction;
use crate::micromap::{State, TriangleOpacity};
use alloc::collections::BTreeMap;
use alloc::vec::Vec;
use core::fmt;

/// What [`verify_mesh`] found, summed over the mesh's triangles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct MeshVerification {
    /// Triangles checked (the others have coordinates that are not finite
    /// or off the exact grid: nothing of them was checked).
    pub triangles_checked: usize,
    /// Known micro-triangles checked.
    pub known: u64,
    /// Unknown micro-triangles (nothing to check).
    pub unknown: u64,
    /// Known micro-triangles the block budget could not decide (with
    /// vertex alpha, summed over the two bounds).
    pub undecided: u64,
    /// Known micro-triangles past `max_known`: not checked.
    pub unchecked: u64,
    /// Known micro-triangles the texture contradicts.
    pub contradictions: u64,
}

impl MeshVerification {
    /// No contradiction, and every known micro-triangle of every triangle
    /// was checked.
    #[must_use]
    pub fn is_sound(&self, triangles: usize) -> bool {
        self.contradictions == 0 && self.unchecked == 0 && self.triangles_checked == triangles
    }
}

/// Why [`verify_mesh`] could not run.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum MeshVerifyError {
    /// The mesh is malformed (as [`bake_meshes`](super::bake_meshes) would
    /// report it).
    Mesh(MeshBakeError),
    /// Not one opacity per triangle.
    Count {
        /// Opacities given.
        opacities: usize,
        /// Triangles of the mesh.
        triangles: usize,
    },
}

impl fmt::Display for MeshVerifyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshVerifyError::Mesh(e) => e.fmt(f),
            MeshVerifyError::Count {
                opacities,
                triangles,
            } => write!(f, "{opacities} opacities for {triangles} triangles"),
        }
    }
}

impl core::error::Error for MeshVerifyError {}

/// The most exact-range bound bakers [`verify_mesh`] keeps at once (each
/// holds tables the size of the texture).
const EXACT_BAKERS: usize = 32;

/// Checks `opacities` (one per triangle of `mesh`, any baker's) against the
/// mesh's texture under its material, as [`bake_meshes`](super::bake_meshes)
/// models it with `judge` (the same options a bake takes: its
/// [`model`](MeshOptions::model), [`texture_unit`](MeshOptions::texture_unit)
/// and [`block_budget`](MeshOptions::block_budget) judge): every known
/// micro-triangle whose state a point of it can contradict (by the texels
/// it reads, or under linear filtering by value the filtered value) is a
/// [`Contradiction`], passed to `visit` with its triangle. The texel's alpha is multiplied by the
/// material's alpha factor as a GPU does; with vertex alpha, an opaque
/// state must hold for the lowest alpha the GPU can compute over the
/// triangle, a transparent state for the highest (the bounds the bake
/// uses). At most `max_known` known micro-triangles are checked (the rest
/// are counted as unchecked).
///
/// ```
/// use micromap_index::bake::mesh::{verify_mesh, Material, Mesh, MeshOptions, MeshTriangles};
/// use micromap_index::bake::Unorm8Texture;
/// use micromap_index::micromap::{State, TriangleOpacity};
/// let texels = [255u8, 0, 0, 0];
/// let texture = Unorm8Texture::new(2, 2, &texels).unwrap();
/// let triangle = [[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]];
/// let mesh = Mesh { triangles: MeshTriangles::Uv(&triangle), texture: &texture, material: Material::default(), vertex_alpha: None };
/// let mut found = 0;
/// let opaque = [TriangleOpacity::Special(State::Opaque)];
/// let judge = MeshOptions::default();
/// let v = verify_mesh(&mesh, &opaque, &judge, u64::MAX, &mut |_, _| found += 1).unwrap();
/// assert_eq!((v.contradictions, found), (1, 1));
/// let unknown = [TriangleOpacity::Special(State::UnknownOpaque)];
/// assert!(verify_mesh(&mesh, &unknown, &judge, u64::MAX, &mut |_, _| {}).unwrap().is_sound(1));
/// ```
pub fn verify_mesh(
    mesh: &Mesh<'_>,
    opacities: &[TriangleOpacity<'_>],
    judge: &MeshOptions,
    max_known: u64,
    visit: &mut dyn FnMut(usize, Contradiction),
) -> Result<MeshVerification, MeshVerifyError> {
    let (model, unit) = (judge.model, judge.texture_unit);
    let triangles = mesh.triangles.resolve(0).map_err(MeshVerifyError::Mesh)?;
    if opacities.len() != triangles.len() {
        return Err(MeshVerifyError::Count {
            opacities: opacities.len(),
            triangles: triangles.len(),
        });
    }
    let vertex_alpha =
        check_vertex_alpha(0, mesh, triangles.len()).map_err(MeshVerifyError::Mesh)?;
    let material = &mesh.material;
    let texture_error = |error| MeshVerifyError::Mesh(MeshBakeError::Texture { mesh: 0, error });
    let factor = FactorTexture {
        inner: mesh.texture,
        factor: material.alpha_factor,
    };
    let scale = f64::from(material.alpha_factor);
    let test = (material.sampler, material.cutoff, unit, scale);
    let serial = Runner::serial();
    // Under linear filtering by value, vertex alpha is judged per
    // micro-triangle, as the bake reads it ([`VertexScale`]).
    let by_value = judges_by_value(material.sampler.filter, &unit);
    let per_part = vertex_alpha.filter(|_| by_value).map(VertexScale::over_all);
    let baker = if material.alpha_factor == 1.0 {
        Baker::new_on_vertex(mesh.texture, test, per_part, u64::MAX, &serial)
    } else {
        Baker::new_on_vertex(&factor, test, per_part, u64::MAX, &serial)
    }
    .map_err(texture_error)?
    .with_block_budget(judge.block_budget)
    .with_model(model)
    .with_uv_transform(material.uv_transform);
    // Otherwise vertex alpha in two passes per triangle. First against the bounds
    // the ranges snap to (at most VERTEX_BOUNDS bakers per side, as the
    // bake's): a snapped range is wider, so its bounds find every
    // contradiction the exact range's find, and maybe more. Only a
    // triangle with some is judged again, and reported, by the bounds of
    // its exact range (bakers made on demand; at most EXACT_BAKERS kept).
    let grid = match vertex_alpha {
        None => VertexBounds::default(),
        Some(_) if per_part.is_some() => VertexBounds::default(),
        Some(alphas) => {
            let mut ranges = (Vec::new(), Vec::new());
            push_vertex_ranges(&mut ranges, alphas).map_err(MeshVerifyError::Mesh)?;
            VertexBounds::new(ranges.0, ranges.1)
        }
    };
    let mut snapped: BTreeMap<(bool, u64), Baker> = BTreeMap::new();
    let mut exact: BTreeMap<(bool, u64), Baker> = BTreeMap::new();
    let bound_baker = |bakers: &mut BTreeMap<(bool, u64), Baker>,
                       upper: bool,
                       v: u64|
     -> Result<(), MeshVerifyError> {
        if let alloc::collections::btree_map::Entry::Vacant(slot) = bakers.entry((upper, v)) {
            slot.insert(
                vertex_bound_baker(mesh.texture, material, unit, (upper, v), &serial)
                    .map(|b| b.with_block_budget(judge.block_budget).with_model(model))
                    .map_err(texture_error)?,
            );
        }
        Ok(())
    };
    let mut out = MeshVerification::default();
    for (t, (uv, opacity)) in triangles.iter().zip(opacities).enumerate() {
        let remaining = max_known.saturating_sub(out.known);
        let counts = match vertex_alpha {
            None => baker.verify_each(uv, opacity, remaining, |c| visit(t, c)),
            Some(alphas) if per_part.is_some() => {
                baker.verify_each_alpha((uv, Some(alphas[t])), opacity, remaining, |c| visit(t, c))
            }
            Some(alphas) => {
                let range = vertex_range(alphas[t]);
                // Each bound decides the states it is the bound of.
                let judge_by = |low: &Baker, high: &Baker, visit: &mut dyn FnMut(Contradiction)| {
                    let mut kept = 0;
                    let mut a = low.verify_each(uv, opacity, remaining, |c| {
                        if c.state == State::Opaque {
                            kept += 1;
                            visit(c);
                        }
                    });
                    let b = high.verify_each(uv, opacity, remaining, |c| {
                        if c.state == State::Transparent {
                            kept += 1;
                            visit(c);
                        }
                    });
                    a.contradictions = kept;
                    a.undecided += b.undecided;
                    a
                };
                let (low, high) = grid.snap(range);
                bound_baker(&mut snapped, false, low)?;
                bound_baker(&mut snapped, true, high)?;
                let coarse = judge_by(
                    &snapped[&(false, low)],
                    &snapped[&(true, high)],
                    &mut |_| {},
                );
                if coarse.contradictions == 0 {
                    coarse
                } else {
                    // Judged again, and reported, by the exact range's
                    // bounds: the snapped ones where the range is its own.
                    let bakers = if (low, high) == range {
                        &snapped
                    } else {
                        if exact.len() + 2 > EXACT_BAKERS {
                            exact.clear();
                        }
                        bound_baker(&mut exact, false, range.0)?;
                        bound_baker(&mut exact, true, range.1)?;
                        &exact
                    };
                    judge_by(
                        &bakers[&(false, range.0)],
                        &bakers[&(true, range.1)],
                        &mut |c| visit(t, c),
                    )
                }
            }
        };
        out.triangles_checked += usize::from(counts.checked);
        out.known += counts.known;
        out.unknown += counts.unknown;
        out.undecided += counts.undecided;
        out.unchecked += counts.unchecked;
        out.contradictions += counts.contradictions;
    }
    Ok(out)
}
