//! `KHR_texture_transform` in mesh bakes: the transform is part of what
//! makes triangles bake alike. (The oracle of transformed bakes is
//! `crates/lab/tests/bake_uv_transform.rs`.)

use micromap_index::bake::{Filter, Sampler, Unorm8Texture, UvTransform};
use micromap_index::Level;

/// Two meshes over one texture and the same stored triangle, with
/// different transforms, are two distinct bakes (the transform is part of
/// what makes triangles bake alike), and each equals its own bake alone.
#[test]
fn different_transforms_are_never_deduplicated() {
    use micromap_index::bake::mesh::{
        bake_mesh, bake_meshes, LevelRule, Material, Mesh, MeshOptions, MeshTriangles,
    };
    // 4 x 1: opaque in the left texel only.
    let texture = Unorm8Texture::new(4, 1, &[255, 0, 0, 0]).unwrap();
    let triangle = [[[0.0f32, 0.0], [1.0, 0.0], [0.0, 1.0]]];
    let mesh = |uv_transform| Mesh {
        triangles: MeshTriangles::Uv(&triangle),
        texture: &texture,
        material: Material {
            sampler: Sampler {
                filter: Filter::Nearest,
                ..Sampler::default()
            },
            uv_transform,
            ..Material::default()
        },
        vertex_alpha: None,
    };
    let moved = UvTransform::new([0.25, 0.0], 0.0, [0.5, 0.5]).unwrap();
    let turned = UvTransform::new([0.6, 0.0], 0.4, [0.3, 0.3]).unwrap();
    let meshes = [mesh(UvTransform::IDENTITY), mesh(moved), mesh(turned)];
    let options = MeshOptions {
        levels: LevelRule::Fixed(Level::new(3).unwrap()),
        ..MeshOptions::default()
    };
    let together = bake_meshes(&meshes, &options, &mut |_, _| {}).unwrap();
    assert_eq!(together.report.distinct_triangles, 3);
    let alone: Vec<[u64; 4]> = meshes
        .iter()
        .map(|m| bake_mesh(m, &options).unwrap().report.counts)
        .collect();
    assert_ne!(alone[0], alone[1]);
    assert_ne!(alone[1], alone[2]);
    let summed = alone.iter().fold([0u64; 4], |mut s, c| {
        for (s, c) in s.iter_mut().zip(c) {
            *s += c;
        }
        s
    });
    assert_eq!(together.report.counts, summed);
}
