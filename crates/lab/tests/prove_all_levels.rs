//! The all-levels construction (`micromap_index_lab::prove_all_levels`) checked
//! against the real functions: the transducers' indices on every face of
//! levels 0..=8 (9..=12 behind `--ignored`), random faces up to level 32,
//! binary32 points (the command: `crates/lab/tests/lab_prove_all_levels.rs`).
//!
//! The slow levels: `cargo test -p micromap-index-lab --test prove_all_levels -- --ignored`.

mod common;

use common::VERSION1_MISMATCHES;
use micromap_index::{internals, spec, uv2index, Level, SpecLevel};
use micromap_index_lab::lattice::Face;
use micromap_index_lab::prove::{for_each_face, WalkVersion};
use micromap_index_lab::prove_all_levels::{
    explore, face_containing, prove_all_levels, Machine, ProductState, Verdict,
};
use micromap_index_test_support::{window_partner, SplitMix64};
use std::collections::HashSet;

fn level(n: u32) -> Level {
    Level::new(n).unwrap()
}

/// The real reference (64-bit integer half, and the 32-bit one where it is
/// valid) at a face's representative.
fn real_reference(face: &Face) -> u64 {
    let cell = spec::cell_dyadic(face.x, face.y, face.scale_log2(), face.level).unwrap();
    let wide = spec::wide_index_from_cell(cell.iu, cell.iv, cell.diagonal, face.level.get());
    if face.level.get() <= spec::MAX_LEVEL {
        let narrow = spec::index_from_cell(
            cell.iu as u32,
            cell.iv as u32,
            cell.diagonal,
            face.level.get(),
        );
        assert_eq!(u64::from(narrow), wide, "{face:?}");
    }
    wide
}

/// Per face of the given levels: the transducers' walk index equals the
/// enumerated proof's (the descent of `prove::for_each_face`, itself
/// checked against the direct walk by `tests/prove.rs`) and their
/// reference index equals the real reference. Returns the product states
/// the runs visited and the mismatching faces per kind (vertex, horizontal,
/// vertical, diagonal edge, upright, upside-down) per level.
fn cross_check(
    version: WalkVersion,
    levels: std::ops::RangeInclusive<u32>,
) -> (HashSet<ProductState>, Vec<[u64; 6]>) {
    let machine = Machine::new(version).unwrap();
    let mut visited = HashSet::new();
    let mut mismatches = Vec::new();
    for n in levels {
        let level = level(n);
        let mut per_kind = [0u64; 6];
        let mut faces = 0u128;
        for_each_face(level, version, |face, descent_index| {
            let run = machine
                .run_on_point(
                    u128::from(face.x),
                    u128::from(face.y),
                    face.scale_log2(),
                    level,
                )
                .unwrap_or_else(|e| panic!("{face:?}: {e}"));
            assert_eq!(run.walk_index, descent_index, "walk, {version:?} {face:?}");
            assert_eq!(
                run.reference_index,
                real_reference(&face),
                "reference, {face:?}"
            );
            if run.walk_index != run.reference_index {
                per_kind[face.kind.index()] += 1;
            }
            visited.extend(run.states);
            faces += 1;
        })
        .unwrap();
        assert_eq!(faces, micromap_index_lab::lattice::face_count(level));
        mismatches.push(per_kind);
    }
    (visited, mismatches)
}

/// Levels 0..=8: the transducers agree with the real functions on every
/// face; version 2's runs stay inside the explored product and visit all
/// of it (so the search explored no state that no point reaches); version
/// 1's transducers differ from the reference on exactly the faces the
/// enumeration finds.
#[test]
fn transducers_equal_the_real_functions_on_every_face_of_levels_0_to_8() {
    let report = prove_all_levels(WalkVersion::Version2).unwrap();
    assert!(report.is_proof());
    let explored: HashSet<ProductState> = report.product_states.iter().copied().collect();
    let (visited, mismatches) = cross_check(WalkVersion::Version2, 0..=8);
    assert!(mismatches.iter().all(|m| *m == [0; 6]), "{mismatches:?}");
    let outside: Vec<_> = visited.difference(&explored).collect();
    assert!(
        outside.is_empty(),
        "runs leave the explored product: {outside:?}"
    );
    let unvisited: Vec<_> = explored.difference(&visited).collect();
    assert!(
        unvisited.is_empty(),
        "{} explored states no face of levels 0..=8 visits, e.g. {:?}",
        unvisited.len(),
        unvisited.first()
    );

    let (_, mismatches) = cross_check(WalkVersion::Version1, 0..=8);
    for (n, per_kind) in mismatches.iter().enumerate() {
        let (table_level, expected) = VERSION1_MISMATCHES[n];
        assert_eq!(table_level, n as u32);
        assert_eq!(per_kind[..4], expected, "level {n}");
        assert_eq!(
            per_kind[4..],
            [0, 0],
            "level {n}: version 1 inside a triangle"
        );
    }
}

#[test]
#[ignore = "every face of levels 9..=12: about 4.5 CPU minutes (25 min wall on a loaded 2-core machine)"]
fn transducers_equal_the_real_functions_on_every_face_of_levels_9_to_12() {
    let explored: HashSet<ProductState> = prove_all_levels(WalkVersion::Version2)
        .unwrap()
        .product_states
        .into_iter()
        .collect();
    let (visited, mismatches) = cross_check(WalkVersion::Version2, 9..=12);
    assert!(mismatches.iter().all(|m| *m == [0; 6]), "{mismatches:?}");
    assert!(visited.is_subset(&explored));
    let (_, mismatches) = cross_check(WalkVersion::Version1, 9..=10);
    for (i, per_kind) in mismatches.iter().enumerate() {
        assert_eq!(
            per_kind[..4],
            VERSION1_MISMATCHES[9 + i].1,
            "level {}",
            9 + i
        );
    }
}

/// Random faces of levels 13..=32: the transducers against the real walk
/// and the 64-bit reference (whose prefix XOR and interleave the small
/// levels do not exercise in full).
#[test]
fn transducers_equal_the_real_functions_on_random_faces_up_to_level_32() {
    let machine = Machine::new(WalkVersion::Version2).unwrap();
    let mut rng = SplitMix64::new(14);
    for n in 13..=32 {
        let level = level(n);
        let side = 1u64 << n;
        for _ in 0..3000 {
            let a = rng.up_to(side);
            let b = rng.up_to(side - a);
            let (dx, dy, kind) = micromap_index_lab::lattice::FACE_OFFSETS[rng.below(6) as usize];
            let (x, y) = (4 * a + dx, 4 * b + dy);
            if x + y > 4 * side {
                continue;
            }
            let face = Face { level, x, y, kind };
            let run = machine
                .run_on_point(u128::from(x), u128::from(y), face.scale_log2(), level)
                .unwrap();
            let (u, v) = face.to_fixed64();
            assert_eq!(
                run.walk_index,
                uv2index::index_unchecked(u, v, level),
                "{face:?}"
            );
            assert_eq!(run.reference_index, real_reference(&face), "{face:?}");
            assert_eq!(face_containing(x, y, face.scale_log2(), level), face);
        }
    }
}

/// The binary32 reference, levels 0..=16: wherever binary32 does not round
/// `uf + vf` across 1 (`spec::rounding_flips_diagonal`), it equals the
/// transducers' reference on the float's exact value, hence (all-levels
/// proof) the exact walk; inside the window it differs from both.
#[test]
fn binary32_reference_is_the_transducers_reference_outside_the_rounding_window() {
    let machine = Machine::new(WalkVersion::Version2).unwrap();
    let mut rng = SplitMix64::new(32);
    let (mut outside, mut inside) = (0, 0);
    for i in 0..40_000u32 {
        let n = i % 17;
        let level = level(n);
        // A random float in [2^-90, 1], half of them near a lattice line of
        // the level (a few ulps off, so the window is hit).
        let float = |rng: &mut SplitMix64| -> f32 {
            let x = if rng.below(2) == 0 {
                let e = rng.below(90) as i32;
                (1.0 + rng.below(1 << 23) as f32 / (1u32 << 23) as f32) * 2f32.powi(-e - 1)
            } else {
                let k = rng.up_to(1 << n) as f32 / (1u64 << n) as f32;
                let nudged = i64::from(k.to_bits()) + rng.below(7) as i64 - 3;
                f32::from_bits(nudged.clamp(0, i64::from(1.0f32.to_bits())) as u32)
            };
            x.max(2f32.powi(-90))
        };
        let u = float(&mut rng);
        let scale = (1u64 << n) as f32;
        let fraction = |x: f32| x * scale - (x * scale).trunc();
        let mut v = if i % 3 == 0 {
            // Aim at the window: vf just below 1 - uf, a few ulps down.
            let iv = rng.below(1 << n);
            let v = window_partner(fraction(u), iv, n)
                .to_bits()
                .saturating_sub(rng.below(4) as u32);
            f32::from_bits(v)
        } else {
            float(&mut rng)
        };
        let scaled = |x: f32| (f64::from(x) * 2f64.powi(120)) as u128;
        // `u + v <= 1` decided exactly (a binary64 sum could round).
        v = v.min((1.0 - f64::from(u)) as f32);
        while scaled(u) + scaled(v) > 1 << 120 {
            v = f32::from_bits(v.to_bits() - 1);
        }
        if v != 0.0 && v < 2f32.powi(-90) {
            continue;
        }
        let run = machine
            .run_on_point(scaled(u), scaled(v), 120, level)
            .unwrap();
        let by_f32 = u64::from(spec::index_f32(u, v, SpecLevel::new(n).unwrap()));
        let walk = uv2index::exact_index_f32(u, v, level).unwrap();
        if internals::rounding_flips_diagonal(fraction(u), fraction(v)) {
            inside += 1;
            let cell = spec::cell_f32(u, v, n);
            // In the window binary32 moves the point to the upside-down
            // half; the walk (and the exact reference) do not (unless the
            // cell is the last of its row, where the test is ignored).
            if cell.iu + cell.iv + 1 < 1 << n {
                assert_ne!(by_f32, run.reference_index, "({u:e}, {v:e}) level {n}");
            }
        } else {
            outside += 1;
            assert_eq!(by_f32, run.reference_index, "({u:e}, {v:e}) level {n}");
        }
        assert_eq!(walk, run.walk_index, "({u:e}, {v:e}) level {n}");
        assert_eq!(
            run.walk_index, run.reference_index,
            "({u:e}, {v:e}) level {n}"
        );
    }
    println!("binary32 points: {inside} in the rounding window, {outside} outside");
    assert!(
        inside > 100 && outside > 20_000,
        "inside {inside}, outside {outside}"
    );
}

/// The counterexample of version 1 is a face where the real functions
/// differ, with the indices the transducers gave.
#[test]
fn version1_counterexample_is_real() {
    let report = prove_all_levels(WalkVersion::Version1).unwrap();
    let Verdict::Counterexample(example) = report.verdict else {
        panic!("{:?}", report.verdict)
    };
    let face = example.face;
    let (u, v) = face.to_fixed64();
    let walk = internals::index_version1_unchecked(u, v, face.level);
    let reference = spec::wide_index_dyadic(face.x, face.y, face.scale_log2(), face.level).unwrap();
    assert_ne!(walk, reference);
    assert_eq!(
        (walk, reference),
        (example.walk_index, example.reference_index)
    );
    assert_eq!(example.real, Some((walk, reference)));
    // The search explores the same product for a machine built from parts.
    let machine = Machine::new(WalkVersion::Version1).unwrap();
    assert!(!explore(&machine).is_proof());
}

/// The listing in `docs/results/all_levels_product.txt` (which
/// `docs/verification.md` section 10.6 invites readers to check by hand)
/// is the search's current output, state for state and transition for
/// transition.
#[test]
fn documented_listing_is_the_current_product() {
    let documented = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/results/all_levels_product.txt"
    ))
    .unwrap();
    let documented: Vec<&str> = documented
        .lines()
        .filter(|line| line.starts_with('S'))
        .collect();
    let report = prove_all_levels(WalkVersion::Version2).unwrap();
    assert_eq!(report.listing(), documented);
    assert_eq!(documented.len(), 34 + 106);
}
