//! The host's exact classification of contradicted candidates, on a scene
//! small enough to work out by hand (no device needed): a 2x1 texture,
//! transparent texel 0 and opaque texel 1, under one triangle whose `u` is
//! `b1`; its micromap says opaque everywhere (level 0, 4-state).

use micromap_index::bake::mesh::Material;
use micromap_index::bake::{Filter, Sampler};
use micromap_index::micromap::{IndexWidth, State};
use micromap_index_render::{
    classify, Contradiction, ContradictionClass, Micromaps, Scene, SceneMesh, SceneTexture,
};

fn setup(filter: Filter) -> (Scene, Micromaps) {
    let mut scene = Scene::new(vec![SceneTexture {
        width: 2,
        height: 1,
        alphas: vec![0.0, 1.0],
    }]);
    let material = Material {
        sampler: Sampler {
            filter,
            ..Sampler::default()
        },
        ..Material::default()
    };
    scene
        .add_mesh(
            SceneMesh {
                texture: 0,
                material,
            },
            &[[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]],
            &[[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]],
        )
        .unwrap();
    // One record: offset 0, level 0, format 2 (4-state); data: opaque.
    let records = vec![0, 0, 0, 0, 0, 0, 2, 0];
    let data = vec![State::Opaque.bits()];
    let indices = 0u32.to_le_bytes().to_vec();
    let maps = Micromaps::from_bytes(data, records, indices, IndexWidth::U32).unwrap();
    (scene, maps)
}

fn contradiction(b1: f32, b2: f32) -> Contradiction {
    Contradiction {
        x: 0,
        y: 0,
        triangle: 0,
        micro_triangle: 0,
        b1_bits: b1.to_bits(),
        b2_bits: b2.to_bits(),
        state: 1,
        alpha_bits: 0,
    }
}

#[test]
fn an_exact_point_in_the_opaque_texel_is_a_rounding_contradiction() {
    let (scene, maps) = setup(Filter::Nearest);
    // u = 0.5 exactly: x = 1, texel 1 (opaque), as the map says.
    let c = classify(&scene, &maps, &contradiction(0.5, 0.25)).unwrap();
    assert_eq!(c.class, ContradictionClass::Binary32Rounding);
    assert!(c.exact_opaque);
    assert_eq!(c.exact_texel_point, ["1".to_string(), "1/4".to_string()]);
    assert_eq!(c.texels, [(1, 0, 1.0)]);
    assert_eq!(c.library_state, Some(State::Opaque));
    assert_eq!(c.level, Some(0));
}

#[test]
fn an_exact_point_in_the_transparent_texel_means_the_map_is_wrong() {
    let (scene, maps) = setup(Filter::Nearest);
    // u = 0.25: x = 1/2, texel 0 (transparent); the map says opaque.
    let c = classify(&scene, &maps, &contradiction(0.25, 0.5)).unwrap();
    assert_eq!(c.class, ContradictionClass::MicromapWrong);
    assert!(!c.exact_opaque);
    assert_eq!(c.texels, [(0, 0, 0.0)]);
    assert_eq!(c.binary32_uv, [0.25, 0.5]);
}

#[test]
fn linear_weights_are_exact() {
    let (scene, maps) = setup(Filter::Linear);
    // x = 1: half of texel 0, half of texel 1: 0.5 >= 0.5, opaque. The
    // one row is read twice (y = 0 lies between rows -1 and 0, and repeat
    // wraps -1 to 0), each with weight 1/2.
    let c = classify(&scene, &maps, &contradiction(0.5, 0.0)).unwrap();
    assert_eq!(
        c.texels,
        [(0, 0, 0.0), (1, 0, 1.0), (0, 0, 0.0), (1, 0, 1.0)]
    );
    assert!(c.exact_opaque);
    assert_eq!(c.class, ContradictionClass::Binary32Rounding);
    // One ulp less: the filtered alpha is just below 0.5, transparent.
    let below = f32::from_bits(0.5f32.to_bits() - 1);
    let c = classify(&scene, &maps, &contradiction(below, 0.0)).unwrap();
    assert!(!c.exact_opaque);
    assert_eq!(c.class, ContradictionClass::MicromapWrong);
    // A triangle the scene does not have.
    let mut missing = contradiction(0.5, 0.0);
    missing.triangle = 1;
    assert!(classify(&scene, &maps, &missing).is_none());
}
