//! Edge-case flip tests: one point on every face of the level-n lattice
//! (every vertex, every open edge, every open micro-triangle), levels 0..=10.
//!
//! Because both algorithms only compare against lattice lines (see
//! `docs/verification.md`), agreement on these points is agreement on every
//! real point of the closed triangle at that level.

mod common;

use common::VERSION1_MISMATCHES;
use micromap_index::num::Fixed64;
use micromap_index::{spec, uv2index, Level, SpecLevel};
use micromap_index_lab::lattice::{face_count, faces, Face, FaceKind};
use micromap_index_test_support::SplitMix64;
use std::collections::BTreeMap;

const LEVELS: std::ops::RangeInclusive<u32> = 0..=10;

fn spec_exact(face: &Face) -> u64 {
    u64::from(
        spec::index_dyadic(
            face.x,
            face.y,
            face.scale_log2(),
            SpecLevel::try_from(face.level).unwrap(),
        )
        .unwrap(),
    )
}

fn describe(face: &Face) -> String {
    let (u, v) = face.to_rational();
    format!(
        "level {} {} face at (u, v) = ({u}, {v})",
        face.level,
        face.kind.name()
    )
}

#[test]
fn walk_equals_spec_exact_on_every_face() {
    for level in LEVELS {
        let level = Level::new(level).unwrap();
        let mut checked = 0u128;
        for face in faces(level) {
            let (u, v) = face.to_fixed64();
            let walk = uv2index::index_unchecked(u, v, level);
            assert_eq!(walk, spec_exact(&face), "{}", describe(&face));
            checked += 1;
        }
        assert_eq!(checked, face_count(level));
    }
}

#[test]
fn bigrational_walk_and_spec_agree_on_every_face_up_to_level_6() {
    for level in 0..=6 {
        let level = Level::new(level).unwrap();
        for face in faces(level) {
            let (u, v) = face.to_rational();
            let expected = spec_exact(&face);
            assert_eq!(
                u64::from(spec::index_real(
                    &u,
                    &v,
                    SpecLevel::try_from(level).unwrap()
                )),
                expected,
                "{}",
                describe(&face)
            );
            assert_eq!(
                uv2index::index_real(&u, &v, level),
                Ok(expected),
                "{}",
                describe(&face)
            );
        }
    }
}

/// Face points are multiples of 2^-(level+2): every step of the walk on
/// them is exact in binary32 up to level 20, so the float walks, the
/// reference in binary32 and the fixed-point entry points must all agree
/// with the exact answer here. (Off the lattice they need not: docs/float.md.)
#[test]
fn float_variants_are_exact_on_lattice_points() {
    for level in LEVELS {
        let level = Level::new(level).unwrap();
        let denominator = (1u64 << (level.get() + 2)) as f32;
        for face in faces(level) {
            let (u, v) = (face.x as f32 / denominator, face.y as f32 / denominator);
            let expected = spec_exact(&face);
            let what = describe(&face);
            assert_eq!(
                uv2index::index_in_f32_arithmetic(u, v, level),
                Ok(expected),
                "{what}"
            );
            assert_eq!(
                uv2index::index_in_f64_arithmetic(u.into(), v.into(), level),
                Ok(expected),
                "{what}"
            );
            assert_eq!(
                u64::from(spec::reference_bits_f32(u, v, level.get())),
                expected,
                "{what}"
            );
            assert_eq!(
                uv2index::exact_index_f32(u, v, level),
                Ok(expected),
                "{what}"
            );
        }
    }
}

#[test]
fn version1_differs_exactly_on_these_boundary_faces() {
    for (level, expected) in VERSION1_MISMATCHES {
        let level = Level::new(level).unwrap();
        let mut mismatches: BTreeMap<FaceKind, u64> = BTreeMap::new();
        for face in faces(level) {
            let (u, v) = face.to_fixed64();
            if micromap_index::internals::index_version1_unchecked(u, v, level) != spec_exact(&face)
            {
                assert!(
                    !face.kind.is_open_triangle(),
                    "version 1 differs inside a micro-triangle: {}",
                    describe(&face)
                );
                *mismatches.entry(face.kind).or_default() += 1;
            }
        }
        let count = |kind| mismatches.get(&kind).copied().unwrap_or(0);
        let found = [
            count(FaceKind::Vertex),
            count(FaceKind::HorizontalEdge),
            count(FaceKind::VerticalEdge),
            count(FaceKind::DiagonalEdge),
        ];
        assert_eq!(
            found, expected,
            "version 1 mismatches per kind at level {level}"
        );
    }
}

/// A point as a fixed-point pair `(x / 2^s, y / 2^s)`.
fn point(x: i64, y: i64, scale_log2: u32) -> (Fixed64, Fixed64) {
    (
        Fixed64::from_scaled(x, scale_log2).unwrap(),
        Fixed64::from_scaled(y, scale_log2).unwrap(),
    )
}

fn both_versions(x: i64, y: i64, scale_log2: u32, level: u32) -> (u64, u64, u64) {
    let level = Level::new(level).unwrap();
    let (u, v) = point(x, y, scale_log2);
    let reference = u64::from(
        spec::index_dyadic(
            x as u64,
            y as u64,
            scale_log2,
            SpecLevel::try_from(level).unwrap(),
        )
        .unwrap(),
    );
    (
        reference,
        uv2index::index_unchecked(u, v, level),
        micromap_index::internals::index_version1_unchecked(u, v, level),
    )
}

// Named regressions: the level-2 faces where version 1 goes wrong, one per
// kind, each showing which flag the reference's tie-breaking needs.

#[test]
fn regression_vertex_quarter_quarter_needs_mid_flip() {
    // (1/4, 1/4): centre of the level-1 middle child. After the middle step
    // the point sits on v = 1/2 of the flipped child; the reference sends it
    // to the middle grandchild (5), version 1 to the top one (7).
    assert_eq!(both_versions(1, 1, 2, 2), (5, 5, 7));
}

#[test]
fn regression_horizontal_edge_three_eighths_quarter() {
    // (3/8, 1/4) on the line v = 1/4.
    assert_eq!(both_versions(3, 2, 3, 2), (5, 5, 7));
}

#[test]
fn regression_vertical_edge_quarter_five_eighths_needs_top_flip() {
    // (1/4, 5/8) on u = 1/4. Version 2 enters the level-1 top child keeping
    // its frame (u' = 1/2: Right, whose digit the top flip turns into 0);
    // version 1 rotates the frame, the point lands on w' = 1/2 and the tie
    // goes to the middle child instead.
    assert_eq!(both_versions(2, 5, 3, 2), (12, 12, 13));
}

#[test]
fn regression_diagonal_edge_eighth_five_eighths() {
    // (1/8, 5/8) on u + v = 3/4.
    assert_eq!(both_versions(1, 5, 3, 2), (13, 13, 14));
}

#[test]
fn regression_vertex_quarter_half() {
    assert_eq!(both_versions(1, 2, 2, 2), (12, 12, 14));
}

#[test]
fn wide_spec_equals_the_reference_up_to_level_16() {
    for level in LEVELS {
        let level = Level::new(level).unwrap();
        for face in faces(level) {
            let wide = spec::wide_index_dyadic(face.x, face.y, face.scale_log2(), level).unwrap();
            assert_eq!(wide, spec_exact(&face), "{}", describe(&face));
        }
    }
}

/// A face of `level` drawn uniformly among cells, then among the six kinds
/// anchored at the cell (kinds outside the triangle are redrawn).
fn random_face(level: Level, rng: &mut SplitMix64) -> (u64, u64) {
    let cells = 1u64 << level.get();
    loop {
        let a = rng.below(cells + 1);
        let b = rng.below(cells + 1);
        let (dx, dy) = [(0, 0), (2, 0), (0, 2), (2, 2), (1, 1), (3, 3)][rng.below(6) as usize];
        let (x, y) = (4 * a + dx, 4 * b + dy);
        if x + y <= 4 * cells {
            return (x, y);
        }
    }
}

/// Above 16 the reference's words are too narrow; the 64-bit steps must
/// still equal the exact walk. Every face is checked by `micromap-index
/// prove --spec-wide`; here, 20,000 random faces per level 17..=32.
#[test]
fn wide_spec_equals_the_walk_on_random_faces_above_16() {
    let mut rng = SplitMix64::new(0x5eed);
    for level in 17..=32 {
        let level = Level::new(level).unwrap();
        let scale_log2 = level.get() + 2;
        for _ in 0..20_000 {
            let (x, y) = random_face(level, &mut rng);
            let u = Fixed64::from_scaled(x as i64, scale_log2).unwrap();
            let v = Fixed64::from_scaled(y as i64, scale_log2).unwrap();
            assert_eq!(
                spec::wide_index_dyadic(x, y, scale_log2, level),
                Ok(uv2index::index_unchecked(u, v, level)),
                "level {level} face ({x}, {y}) / 2^{scale_log2}"
            );
        }
    }
}

/// The narrow reference really is wrong above 16 (the reason for the wide
/// variant): on random faces at level 17 it disagrees with the walk.
#[test]
fn narrow_reference_fails_above_16() {
    let mut rng = SplitMix64::new(17);
    let level = Level::new(17).unwrap();
    let wrong = (0..1000)
        .filter(|_| {
            let (x, y) = random_face(level, &mut rng);
            let cell = spec::cell_dyadic(x, y, 19, level).unwrap();
            let narrow = spec::index_from_cell(cell.iu as u32, cell.iv as u32, cell.diagonal, 17);
            Ok(u64::from(narrow)) != spec::wide_index_dyadic(x, y, 19, level)
        })
        .count();
    assert!(wrong > 100, "only {wrong} of 1000 level-17 faces differ");
}
