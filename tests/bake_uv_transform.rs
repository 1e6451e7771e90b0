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

/// Transforms whose images overflow binary32 or lie far off the texture
/// bake (levels chosen by the rule, auto) without a panic: the triangle is
/// unknown-opaque, as any coordinates the exact grid cannot hold.
#[test]
fn extreme_transforms_bake_unknown_without_panicking() {
    use micromap_index::bake::mesh::{
        bake_mesh, LevelRule, Material, Mesh, MeshOptions, MeshTriangles,
    };
    use micromap_index::bake::{Interpolation, Model, TextureUnit};
    let texture = Unorm8Texture::new(4, 1, &[255, 0, 0, 0]).unwrap();
    let triangle = [[[0.0f32, 0.0], [1.0, 0.0], [0.0, 1.0]]];
    for (offset, rotation, scale) in [
        ([0.0, 0.0], 0.0, [3e38f32, 3e38]),
        ([3e38, -3e38], 1.0, [1.0, 1.0]),
        ([0.5, 0.5], 65536.0, [1e-30, 1e30]),
        ([1e20, 0.0], -3.0, [0.0, 0.0]),
    ] {
        let transform = UvTransform::new(offset, rotation, scale).unwrap();
        for model in Model::ALL {
            for interpolation in [Interpolation::F32, Interpolation::F16] {
                let mesh = Mesh {
                    triangles: MeshTriangles::Uv(&triangle),
                    texture: &texture,
                    material: Material {
                        uv_transform: transform,
                        ..Material::default()
                    },
                    vertex_alpha: None,
                };
                let options = MeshOptions {
                    levels: LevelRule::Useful {
                        max: Level::new(6).unwrap(),
                    },
                    model,
                    texture_unit: TextureUnit::default().with_interpolation(interpolation),
                    ..MeshOptions::default()
                };
                let report = bake_mesh(&mesh, &options).unwrap().report;
                assert_eq!(report.triangles, 1);
                let known = report.counts[0] + report.counts[1];
                assert_eq!(
                    known, 0,
                    "{offset:?} {rotation} {scale:?} {model:?} {interpolation:?}: {:?}",
                    report.status
                );
            }
        }
    }
}
