//! The exhaustive proof (`micromap_index_lab::prove`) checked against slower,
//! independent computations, and the proof itself for levels 0..=10.
//! Higher levels are a command (`micromap-lab prove`), not a test.

mod common;

use common::VERSION1_MISMATCHES;
use micromap_index::{spec, uv2index, Level, SpecLevel};
use micromap_index_lab::lattice::{face_count, faces, FaceKind};
use micromap_index_lab::prove::{
    for_each_face, prove_level, sample_level, Method, Progress, Reference, Settings, WalkVersion,
    FACE_KINDS,
};
use std::collections::HashMap;

fn level(n: u32) -> Level {
    Level::new(n).unwrap()
}

/// The table-driven descent gives every face of the lattice exactly once,
/// with the index the step-by-step walk computes at its point: the
/// machinery the proof relies on, checked face by face.
#[test]
fn descent_assigns_every_face_the_direct_walks_index() {
    for version in [WalkVersion::Version2, WalkVersion::Version1] {
        for n in 0..=8 {
            let level = level(n);
            let mut by_descent: HashMap<(u64, u64), (u64, FaceKind)> = HashMap::new();
            for_each_face(level, version, |face, index| {
                let previous = by_descent.insert((face.x, face.y), (index, face.kind));
                assert!(previous.is_none(), "face {face:?} visited twice");
            })
            .unwrap();
            assert_eq!(by_descent.len() as u128, face_count(level));
            for face in faces(level) {
                let (u, v) = face.to_fixed64();
                let direct = match version {
                    WalkVersion::Version2 => uv2index::index_unchecked(u, v, level),
                    WalkVersion::Version1 => {
                        micromap_index::internals::index_version1_unchecked(u, v, level)
                    }
                };
                assert_eq!(
                    by_descent.get(&(face.x, face.y)),
                    Some(&(direct, face.kind)),
                    "{version:?} level {n}, face {face:?}"
                );
            }
        }
    }
}

#[test]
fn walk_equals_spec_on_every_face_of_levels_0_to_10() {
    for reference in [Reference::Spec, Reference::SpecWide] {
        let settings = Settings {
            reference,
            ..Settings::default()
        };
        for n in 0..=10 {
            let report = prove_level(level(n), &settings, &Progress::new()).unwrap();
            assert!(report.complete);
            assert_eq!(report.faces_checked, face_count(level(n)), "level {n}");
            assert_eq!(report.faces_expected, face_count(level(n)));
            assert_eq!(report.mismatches(), 0, "level {n}: {:?}", report.examples);
            assert!(report.is_proof());
        }
    }
}

/// The negative control: the same check finds version 1's boundary
/// mismatches, exactly as many as the direct walk does, and none inside a
/// micro-triangle.
#[test]
fn version1_fails_with_exactly_the_known_mismatches() {
    let settings = Settings {
        walk: WalkVersion::Version1,
        examples: 3,
        ..Settings::default()
    };
    for (n, expected) in VERSION1_MISMATCHES {
        let report = prove_level(level(n), &settings, &Progress::new()).unwrap();
        assert_eq!(report.faces_checked, face_count(level(n)));
        let [vertex, horizontal, vertical, diagonal, upright, upside_down] =
            report.mismatches_by_kind;
        assert_eq!(
            [vertex, horizontal, vertical, diagonal],
            expected.map(u128::from),
            "level {n}"
        );
        assert_eq!((upright, upside_down), (0, 0));
        assert_eq!(report.is_proof(), n < 2);
        for example in &report.examples {
            let (u, v) = example.face.to_fixed64();
            assert_eq!(
                example.walk,
                micromap_index::internals::index_version1_unchecked(u, v, level(n))
            );
            let by_spec = spec::index_dyadic(
                example.face.x,
                example.face.y,
                n + 2,
                SpecLevel::new(n).unwrap(),
            );
            assert_eq!(Ok(example.reference), by_spec.map(u64::from));
            assert_ne!(example.walk, example.reference);
        }
        assert_eq!(report.examples.len(), report.mismatches().min(3) as usize);
    }
}

/// Examples are the mismatches of smallest walk index, whatever the thread
/// count.
#[test]
fn examples_do_not_depend_on_threads() {
    let run = |threads| {
        let settings = Settings {
            walk: WalkVersion::Version1,
            threads,
            examples: 7,
            ..Settings::default()
        };
        prove_level(level(9), &settings, &Progress::new()).unwrap()
    };
    let one = run(1);
    let three = run(3);
    assert_eq!(one.examples, three.examples);
    assert_eq!(one.mismatches_by_kind, three.mismatches_by_kind);
    assert!(one.examples.windows(2).all(|w| w[0].walk <= w[1].walk));
}

#[test]
fn cancelled_run_is_marked_incomplete() {
    let progress = Progress::new();
    progress.cancel();
    let report = prove_level(level(12), &Settings::default(), &progress).unwrap();
    assert!(!report.complete);
    assert!(!report.is_proof());
    assert!(report.faces_checked < report.faces_expected);
}

#[test]
fn levels_beyond_the_reference_are_refused() {
    let err = prove_level(level(17), &Settings::default(), &Progress::new()).unwrap_err();
    assert_eq!(
        err.to_string(),
        "level 17 is too high: this function supports levels 0..=16"
    );
}

#[test]
fn samples_agree_and_repeat_with_the_seed() {
    let wide = Settings {
        reference: Reference::SpecWide,
        ..Settings::default()
    };
    for n in [0, 5, 17, 24, 32] {
        let report = sample_level(level(n), 20_000, 42, &wide, &Progress::new()).unwrap();
        assert_eq!(report.method, Method::Sampled { seed: 42 });
        assert_eq!(report.faces_checked, 20_000);
        assert_eq!(report.mismatches(), 0, "level {n}: {:?}", report.examples);
        assert!(!report.is_proof());
    }
    // Version 1 fails on random faces too, identically for the same seed.
    let version1 = Settings {
        walk: WalkVersion::Version1,
        ..Settings::default()
    };
    let first = sample_level(level(3), 10_000, 9, &version1, &Progress::new()).unwrap();
    let again = sample_level(level(3), 10_000, 9, &version1, &Progress::new()).unwrap();
    assert!(first.mismatches() > 0);
    assert_eq!(first.mismatches_by_kind, again.mismatches_by_kind);
    assert_eq!(first.examples, again.examples);
    // Version 1 agrees with the reference inside every micro-triangle: its
    // mismatches are all on edges and vertices.
    for (kind, &count) in FACE_KINDS.iter().zip(&first.mismatches_by_kind) {
        if kind.is_open_triangle() {
            assert_eq!(count, 0, "{} faces", kind.name());
        }
    }
}
