//! [`verify_with_progress`]: the library's `verify_mesh` over a mesh in
//! chunks of triangles, so that a progress bar follows a long verification
//! (minutes at level 8). The library's verifier is the only one: each chunk
//! is one `verify_mesh` call on a slice of the mesh, and together they give
//! what one call over the whole mesh gives (the counts summed, the
//! contradictions in order with the mesh's triangle numbers, `max_known`
//! counted across chunks); an error is the one call's error, its numbers
//! the mesh's.

use micromap_index::bake::mesh::{
    verify_mesh, Mesh, MeshOptions, MeshTriangles, MeshVerification, MeshVerifyError,
};
use micromap_index::bake::Contradiction;
use micromap_index::micromap::TriangleOpacity;

/// Triangles per `verify_mesh` call: enough that the per-call setup is
/// small next to the checks, few enough that the bar moves.
const CHUNK: usize = 64;

/// `verify_mesh(mesh, opacities, judge, max_known, visit)` (the module's
/// contracts), telling `progress` after each chunk how many of the mesh's
/// triangles are done.
pub(super) fn verify_with_progress(
    mesh: &Mesh<'_>,
    opacities: &[TriangleOpacity<'_>],
    judge: &MeshOptions,
    max_known: u64,
    visit: &mut dyn FnMut(usize, Contradiction),
    progress: &mut dyn FnMut(usize),
) -> Result<MeshVerification, MeshVerifyError> {
    let MeshTriangles::Uv(triangles) = mesh.triangles else {
        let v = verify_mesh(mesh, opacities, judge, max_known, visit)?;
        progress(opacities.len());
        return Ok(v);
    };
    if triangles.len() != opacities.len()
        || mesh
            .vertex_alpha
            .is_some_and(|alpha| alpha.len() != triangles.len())
    {
        // The one call's error, as it words it.
        return verify_mesh(mesh, opacities, judge, max_known, visit);
    }
    let mut sum = MeshVerification::default();
    for start in (0..triangles.len()).step_by(CHUNK) {
        let end = (start + CHUNK).min(triangles.len());
        let chunk = Mesh {
            triangles: MeshTriangles::Uv(&triangles[start..end]),
            vertex_alpha: mesh.vertex_alpha.map(|alpha| &alpha[start..end]),
            ..*mesh
        };
        let Ok(v) = verify_mesh(
            &chunk,
            &opacities[start..end],
            judge,
            max_known.saturating_sub(sum.known),
            &mut |t, c| visit(start + t, c),
        ) else {
            // Numbered within the chunk: the whole mesh's call says it
            // with the mesh's numbers.
            return verify_mesh(mesh, opacities, judge, max_known, &mut |_, _| {});
        };
        sum.triangles_checked += v.triangles_checked;
        sum.known += v.known;
        sum.unknown += v.unknown;
        sum.undecided += v.undecided;
        sum.unchecked += v.unchecked;
        sum.contradictions += v.contradictions;
        progress(end);
    }
    Ok(sum)
}

#[cfg(test)]
mod tests {
    use super::*;
    use micromap_index::bake::mesh::Material;
    use micromap_index::bake::Unorm8Texture;
    use micromap_index::micromap::State;

    /// Chunks give what one call gives: the same counts and the same
    /// contradictions, numbered as the mesh's triangles, with and without a
    /// cap on the known micro-triangles checked that ends inside a chunk.
    #[test]
    fn chunks_add_up_to_one_call() {
        let texels: Vec<u8> = (0..64).map(|i| if i % 3 == 0 { 255 } else { 0 }).collect();
        let texture = Unorm8Texture::new(8, 8, &texels).unwrap();
        let triangles: Vec<[[f32; 2]; 3]> = (0..200)
            .map(|t| {
                let o = (t % 8) as f32 / 8.0;
                [
                    [o, 0.0],
                    [o + 0.125, 0.0],
                    [o, 0.125 + (t % 5) as f32 / 8.0],
                ]
            })
            .collect();
        let alpha: Vec<[f32; 3]> = (0..200)
            .map(|t| [1.0, 0.5 + (t % 2) as f32 / 2.0, 1.0])
            .collect();
        let opacities: Vec<TriangleOpacity<'_>> = (0..200)
            .map(|t| {
                TriangleOpacity::Special(if t % 3 == 0 {
                    State::Opaque
                } else {
                    State::Transparent
                })
            })
            .collect();
        for vertex_alpha in [None, Some(alpha.as_slice())] {
            let mesh = Mesh {
                triangles: MeshTriangles::Uv(&triangles),
                texture: &texture,
                material: Material::default(),
                vertex_alpha,
            };
            for max_known in [u64::MAX, 70] {
                let mut one = Vec::new();
                let whole = verify_mesh(
                    &mesh,
                    &opacities,
                    &MeshOptions::default(),
                    max_known,
                    &mut |t, c| {
                        one.push((t, c));
                    },
                )
                .unwrap();
                let (mut chunked, mut told) = (Vec::new(), Vec::new());
                let sum = verify_with_progress(
                    &mesh,
                    &opacities,
                    &MeshOptions::default(),
                    max_known,
                    &mut |t, c| chunked.push((t, c)),
                    &mut |done| told.push(done),
                )
                .unwrap();
                assert_eq!(sum, whole, "{max_known}");
                assert_eq!(chunked, one, "{max_known}");
                assert!(whole.contradictions > 0);
                assert_eq!(told, [64, 128, 192, 200]);
            }
        }
        // An error is the one call's.
        let mesh = Mesh {
            triangles: MeshTriangles::Uv(&triangles),
            texture: &texture,
            material: Material::default(),
            vertex_alpha: None,
        };
        let short = &opacities[..199];
        assert_eq!(
            verify_with_progress(
                &mesh,
                short,
                &MeshOptions::default(),
                u64::MAX,
                &mut |_, _| {},
                &mut |_| {}
            ),
            verify_mesh(
                &mesh,
                short,
                &MeshOptions::default(),
                u64::MAX,
                &mut |_, _| {}
            )
        );
    }
}
