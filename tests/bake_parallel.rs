//! `bake::mesh` on many generated scenes: the parallel bake gives the
//! serial bake's buffers, report and per-triangle results on every thread
//! count, and the deduplicated bake gives what baking every triangle in
//! turn gives (`Baker::bake` per triangle into
//! `MicromapBuffersBuilder::add_geometry`, the pipeline before
//! deduplication).

use micromap_index::bake::mesh::{
    bake_meshes, LevelRule, Material, Mesh, MeshBake, MeshOptions, MeshTriangles,
};
use micromap_index::bake::{
    AddressMode, Baker, Comparison, Cutoff, Filter, Sampler, Threads, Unorm8Texture, UvTriangle,
};
use micromap_index::micromap::{BuildOptions, Format, MicromapBuffersBuilder, UnknownPolicy};
use micromap_index::Level;
use micromap_index_test_support::SplitMix64;

/// A random scene: textures, and meshes whose triangles are drawn from a
/// small pool (so that many repeat), some not finite or far outside.
/// A mesh: its texture (by position), material, triangles, vertex alpha.
type MeshSpec = (usize, Material, Vec<UvTriangle>, Option<Vec<[f32; 3]>>);

struct Scene {
    textures: Vec<(u32, u32, Vec<u8>)>,
    meshes: Vec<MeshSpec>,
    options: MeshOptions,
}

fn coordinate(rng: &mut SplitMix64) -> f32 {
    match rng.below(20) {
        0 => f32::NAN,
        1 => 1e30,
        2 => -3.25,
        3 => (rng.below(9) as f32) / 8.0,
        _ => (rng.below(1 << 20) as f32) / (1 << 20) as f32 * 1.5 - 0.25,
    }
}

fn scene(seed: u64) -> Scene {
    let mut rng = SplitMix64::new(seed);
    let textures = (0..=rng.below(2))
        .map(|_| {
            let (w, h) = (1 + rng.below(24) as u32, 1 + rng.below(24) as u32);
            let texels = (0..w * h)
                .map(|_| rng.pick(&[0u8, 0, 255, 255, 127, 128, 200]))
                .collect();
            (w, h, texels)
        })
        .collect::<Vec<_>>();
    let pool: Vec<UvTriangle> = (0..=rng.below(12))
        .map(|_| {
            [0; 3].map(|_| {
                let u = coordinate(&mut rng);
                [u, coordinate(&mut rng)]
            })
        })
        .collect();
    let materials = [
        Material::default(),
        Material {
            sampler: Sampler {
                filter: Filter::Linear,
                address_u: AddressMode::ClampToEdge,
                address_v: AddressMode::MirroredRepeat,
                border_alpha: 0.0,
            },
            cutoff: Cutoff::new(0.5, Comparison::Above).unwrap(),
            alpha_factor: 1.0,
            uv_transform: micromap_index::bake::UvTransform::IDENTITY,
        },
        Material {
            alpha_factor: 0.75,
            uv_transform: micromap_index::bake::UvTransform::IDENTITY,
            ..Material::default()
        },
    ];
    let meshes = (0..=rng.below(4))
        .map(|_| {
            let n = 1 + rng.below(40) as usize;
            let triangles: Vec<UvTriangle> = (0..n).map(|_| rng.pick(&pool)).collect();
            let alpha = (rng.below(4) == 0).then(|| {
                (0..n)
                    .map(|_| [0; 3].map(|_| rng.pick(&[1.0f32, 0.5, 0.25, 0.0])))
                    .collect()
            });
            (
                rng.below(textures.len() as u64) as usize,
                rng.pick(&materials),
                triangles,
                alpha,
            )
        })
        .collect();
    let level = Level::new(rng.below(5) as u32).unwrap();
    let options = MeshOptions {
        levels: if rng.below(2) == 0 {
            LevelRule::Fixed(level)
        } else {
            LevelRule::Useful { max: level }
        },
        format: rng.pick(&[Format::FourState, Format::TwoState]),
        unknown: rng.pick(&[
            UnknownPolicy::Fallback,
            UnknownPolicy::Opaque,
            UnknownPolicy::Transparent,
        ]),
        budget_bytes: (rng.below(4) == 0).then(|| rng.below(200)),
        ..MeshOptions::default()
    };
    Scene {
        textures,
        meshes,
        options,
    }
}

fn bake(scene: &Scene, threads: Threads) -> MeshBake {
    let textures: Vec<Unorm8Texture<'_>> = scene
        .textures
        .iter()
        .map(|(w, h, t)| Unorm8Texture::new(*w, *h, t).unwrap())
        .collect();
    let meshes: Vec<Mesh<'_>> = scene
        .meshes
        .iter()
        .map(|(texture, material, triangles, alpha)| Mesh {
            triangles: MeshTriangles::Uv(triangles),
            texture: &textures[*texture],
            material: *material,
            vertex_alpha: alpha.as_deref(),
        })
        .collect();
    let options = MeshOptions {
        threads,
        ..scene.options
    };
    let mut last = (0, 0);
    let baked = bake_meshes(&meshes, &options, &mut |done, total| last = (done, total)).unwrap();
    let total: usize = scene.meshes.iter().map(|m| m.2.len()).sum();
    assert_eq!(last, (total, total));
    baked
}

/// The pipeline before deduplication, for scenes without vertex alpha or
/// budget: one baker per mesh, every triangle baked, all maps handed to
/// the builder.
fn bake_each_triangle(scene: &Scene) -> Option<MicromapBuffersBuilder> {
    if scene.options.budget_bytes.is_some() || scene.meshes.iter().any(|m| m.3.is_some()) {
        return None;
    }
    let mut builder = MicromapBuffersBuilder::new(BuildOptions::default());
    for (texture, material, triangles, _) in &scene.meshes {
        let (w, h, texels) = &scene.textures[*texture];
        let texels: Vec<u8> = if material.alpha_factor == 1.0 {
            texels.clone()
        } else {
            // Only factor 0.75 is generated: 8-bit alphas times 0.75
            // against 0.5 (the default cutoff) in binary32.
            texels
                .iter()
                .map(|&c| {
                    if (f32::from(c) / 255.0) * 0.75 >= 0.5 {
                        255
                    } else {
                        0
                    }
                })
                .collect()
        };
        let texture = Unorm8Texture::new(*w, *h, &texels).unwrap();
        let baker = Baker::new(&texture, material.sampler, material.cutoff)
            .unwrap()
            .with_model(scene.options.model);
        let maps: Vec<_> = triangles
            .iter()
            .map(|uv| {
                let level = match scene.options.levels {
                    LevelRule::Fixed(l) => l,
                    LevelRule::Useful { max } => {
                        micromap_index::bake::useful_level(uv, (*w, *h), max)
                    }
                };
                baker
                    .bake(uv, level, scene.options.format, scene.options.unknown)
                    .unwrap()
            })
            .collect();
        builder
            .add_geometry(maps.iter().map(|b| b.opacity.as_opacity()))
            .unwrap();
    }
    Some(builder)
}

#[test]
fn every_thread_count_and_the_undeduplicated_bake_give_the_same_bytes() {
    let mut compared = 0;
    let mut merged = 0;
    for seed in 0..150 {
        let scene = scene(seed);
        let serial = bake(&scene, Threads::Exactly(1));
        for threads in [Threads::Exactly(2), Threads::Exactly(7), Threads::All] {
            let parallel = bake(&scene, threads);
            assert_eq!(parallel.buffers, serial.buffers, "seed {seed} {threads:?}");
            assert_eq!(parallel.report, serial.report, "seed {seed} {threads:?}");
            for (m, mesh) in scene.meshes.iter().enumerate() {
                for t in 0..mesh.2.len() {
                    assert_eq!(parallel.triangle(m, t), serial.triangle(m, t));
                }
            }
        }
        if let Some(each) = bake_each_triangle(&scene) {
            assert_eq!(each.finish().unwrap(), serial.buffers, "seed {seed}");
            compared += 1;
        }
        merged += serial.report.triangles - serial.report.distinct_triangles;
    }
    // The generator must exercise both comparisons and the merging.
    assert!(compared > 40, "{compared}");
    assert!(merged > 1000, "{merged}");
}
