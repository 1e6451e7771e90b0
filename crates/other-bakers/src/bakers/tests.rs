//! Conversion checks on tiny cases: uniform textures give special indices,
//! a half-opaque texture gives the micro-triangle pattern that
//! micromap-index's curve predicts (linear and nearest), and the two
//! meshoptimizer builds agree. The OMM SDK's baker runs in every test when
//! `OMM_SDK_LIB` names a build of it.

use micromap_index::bake::Filter;
use micromap_index::inverse::micro_triangle;
use micromap_index::Level;

use super::all;
use super::baker::{Baker, Request, SamplerRequest};
use super::meshopt_common::meshopt_sample;
use crate::input::{AlphaTexture, UvTriangle};
use crate::output::{Format, FULLY_OPAQUE, FULLY_TRANSPARENT};

const FORMATS: [Format; 2] = [Format::TwoState, Format::FourState];

fn bake(
    baker: &dyn Baker,
    texture: &AlphaTexture,
    tris: &[UvTriangle],
    level: u8,
    format: Format,
) -> crate::output::Micromaps {
    bake_with(
        baker,
        texture,
        tris,
        level,
        format,
        SamplerRequest::default(),
    )
    .unwrap_or_else(|e| panic!("{}: {e}", baker.name()))
}

fn bake_with(
    baker: &dyn Baker,
    texture: &AlphaTexture,
    tris: &[UvTriangle],
    level: u8,
    format: Format,
    sampler: SamplerRequest,
) -> Result<crate::output::Micromaps, String> {
    let baked = baker.bake(&Request {
        texture,
        triangles: tris,
        level,
        format,
        sampler,
    })?;
    baked.maps.validate(tris.len()).unwrap();
    Ok(baked.maps)
}

/// Every baker that can run here: the OMM SDK only when `OMM_SDK_LIB`
/// names the user's build of it (a note on stderr says when it is skipped).
fn working_bakers() -> Vec<Box<dyn Baker>> {
    let omm = super::omm_sdk::library::configured();
    if !omm {
        eprintln!("OMM_SDK_LIB not set: the omm-sdk baker is not tested");
    }
    all()
        .into_iter()
        .filter(|b| omm || b.name() != "omm-sdk")
        .collect()
}

#[test]
fn uniform_textures_give_special_indices() {
    let tris = crate::input::grid_triangles(2);
    for (value, special) in [(255u8, FULLY_OPAQUE), (0, FULLY_TRANSPARENT)] {
        let texture = AlphaTexture::from_fn(16, 8, |_, _| value);
        for baker in working_bakers() {
            for format in FORMATS {
                for level in [0, 1, 3] {
                    let maps = bake(&*baker, &texture, &tris, level, format);
                    assert!(
                        maps.records.is_empty(),
                        "{} {format:?} L{level}",
                        baker.name()
                    );
                    assert!(maps.data.is_empty());
                    assert_eq!(maps.indices, vec![special; tris.len()], "{}", baker.name());
                }
            }
        }
    }
}

/// UV of micro-triangle `index`'s vertices at `level` for the triangle
/// `tri`: barycentric `(u, v)` weighs vertex 1 and 2, `w = 1 - u - v` vertex 0.
fn micro_uvs(tri: &UvTriangle, level: u8, index: u64) -> [[f64; 2]; 3] {
    let m = micro_triangle(Level::new(level.into()).unwrap(), index).unwrap();
    m.vertices_f64().map(|(u, v)| {
        let w = 1.0 - u - v;
        [0, 1]
            .map(|k| w * f64::from(tri[0][k]) + u * f64::from(tri[1][k]) + v * f64::from(tri[2][k]))
    })
}

/// Left half opaque (texels x < W/2): the bilinear field is 1 for
/// u <= (W/2 - 0.5)/W and 0 for u >= (W/2 + 0.5)/W; nearest reads opaque
/// texels for u < 1/2 and transparent ones above. Every micro-triangle
/// wholly on one side, by a margin of 1/16 texel, must have that state (the
/// margin covers every baker's widening: meshoptimizer's 1/256-texel sample
/// positions, micromap-index's GPU model with its sub-texel snapping, the
/// OMM SDK's float corners); which index that is comes from
/// micromap-index's curve, so this checks the bakers' order and vertex
/// mapping as well as the bit packing. meshoptimizer has no nearest filter
/// and must refuse it.
#[test]
fn half_opaque_texture_matches_the_vulkan_curve() {
    let (w, h) = (64u32, 32u32);
    let texture = AlphaTexture::from_fn(w, h, |x, _| if x < w / 2 { 255 } else { 0 });
    let tris: Vec<UvTriangle> = vec![
        [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
        [[0.9, 0.1], [0.1, 0.2], [0.6, 0.95]],
        [[0.05, 0.9], [0.95, 0.85], [0.3, 0.05]],
    ];
    for filter in [Filter::Linear, Filter::Nearest] {
        let sampler = SamplerRequest {
            filter,
            ..SamplerRequest::default()
        };
        let band = match filter {
            Filter::Linear => 0.5,
            Filter::Nearest => 0.0,
        } + 1.0 / 16.0;
        let (opaque_below, transparent_above) = (
            (f64::from(w / 2) - band) / f64::from(w),
            (f64::from(w / 2) + band) / f64::from(w),
        );
        for baker in working_bakers() {
            for format in FORMATS {
                let mut checked = [0usize; 2];
                for level in [1u8, 2, 3, 5] {
                    let maps = match bake_with(&*baker, &texture, &tris, level, format, sampler) {
                        Ok(maps) => maps,
                        Err(e) if baker.name().starts_with("meshopt") => {
                            assert_eq!(filter, Filter::Nearest, "{e}");
                            continue;
                        }
                        Err(e) => panic!("{}: {e}", baker.name()),
                    };
                    for (t, tri) in tris.iter().enumerate() {
                        for i in 0..1u64 << (2 * level) {
                            let uvs = micro_uvs(tri, level, i);
                            let got = maps.state(t, i as usize);
                            let expected = if uvs.iter().all(|p| p[0] < opaque_below) {
                                1
                            } else if uvs.iter().all(|p| p[0] > transparent_above) {
                                0
                            } else {
                                continue;
                            };
                            checked[expected as usize] += 1;
                            assert_eq!(
                                got,
                                expected,
                                "{} {filter} {format:?} L{level} triangle {t} micro-triangle {i} at {uvs:?}",
                                baker.name()
                            );
                        }
                    }
                }
                let refused = filter == Filter::Nearest && baker.name().starts_with("meshopt");
                assert!(
                    refused || (checked[0] > 100 && checked[1] > 100),
                    "{} {filter}: {checked:?}",
                    baker.name()
                );
            }
        }
    }
}

/// A triangle straddling the edge: in 4-state some micro-triangles must be
/// unknown, and the known ones lie on their side.
#[test]
fn four_state_marks_the_edge_unknown() {
    let texture = AlphaTexture::from_fn(64, 64, |x, _| if x < 32 { 255 } else { 0 });
    let tris: Vec<UvTriangle> = vec![[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]];
    for baker in working_bakers() {
        let maps = bake(&*baker, &texture, &tris, 3, Format::FourState);
        let counts = maps.state_counts(3);
        assert!(counts[2] + counts[3] > 0, "{}: {counts:?}", baker.name());
    }
}

/// The C++ meshoptimizer and the Rust port give the same bytes on a
/// non-trivial texture, including wrapped and out-of-range UVs.
#[test]
fn meshopt_cpp_and_rust_port_agree() {
    let texture = AlphaTexture::from_fn(37, 23, |x, y| {
        let (dx, dy) = (x as f32 - 15.3, y as f32 - 11.7);
        (255.0 * (0.5 + 0.5 * ((dx * dx + dy * dy).sqrt() * 0.7).sin())) as u8
    });
    let mut tris = crate::input::grid_triangles(3);
    tris.push([[-0.3, 0.2], [1.4, -0.1], [0.5, 2.2]]);
    tris.push([[0.01, 0.99], [0.02, 0.98], [0.5, 0.5]]);
    let cpp = super::meshopt_cpp::MeshoptCpp;
    let rs = super::meshopt_rs::MeshoptRs;
    for format in FORMATS {
        for level in 0..=6u8 {
            let a = bake(&cpp, &texture, &tris, level, format);
            let b = bake(&rs, &texture, &tris, level, format);
            assert_eq!(a, b, "{format:?} L{level}");
        }
    }
}

/// End to end on the real chain texture (its micromaps are deduplicated
/// and compacted): every known 4-state micro-triangle must agree with
/// meshoptimizer's own samples at its corners and centroid, located through
/// micromap-index's curve. The grid's UVs are multiples of 1/8, so every
/// micro-vertex up to level 4 is exact in f32 and the centroid is the one
/// meshoptimizer computes.
#[test]
fn chain_known_states_agree_with_meshopt_samples() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/crytek-sponza/chain.png"
    );
    let texture = crate::input::read_png_alpha(std::path::Path::new(path)).unwrap();
    assert_eq!((texture.width, texture.height), (256, 1024));
    let tris = crate::input::grid_triangles(8);
    let level = 4u8;
    for baker in working_bakers() {
        let maps = bake(&*baker, &texture, &tris, level, Format::FourState);
        assert!(maps.records.len() < tris.len(), "expected deduplication");
        let mut known = 0;
        for (t, tri) in tris.iter().enumerate() {
            for i in 0..1u64 << (2 * level) {
                let state = maps.state(t, i as usize);
                if state >= 2 {
                    continue;
                }
                known += 1;
                let p = micro_uvs(tri, level, i).map(|q| q.map(|c| c as f32));
                let c = [0, 1].map(|k| (p[0][k] + p[1][k] + p[2][k]) * (1.0 / 3.0));
                for q in [p[0], p[1], p[2], c] {
                    let a = meshopt_sample(&texture, q[0], q[1]);
                    let ok = if state == 1 { a > 0.5 } else { a < 0.5 };
                    assert!(
                        ok,
                        "{} triangle {t} micro {i} state {state}: alpha {a} at {q:?}",
                        baker.name()
                    );
                }
            }
        }
        assert!(known > 20_000, "{known}");
    }
}
