//! Unit tests of the prover's tables, descent and sampler.

use super::sample::FaceSampler;
use super::*;

/// The tables `docs/verification.md` describes: 8 states for version
/// 2, 6 for version 1 (no flags); children of the root in digit order
/// as (digit, owned mask, corners among V0 V1 V2 M01 M12 M20).
#[test]
fn tables_are_the_documented_ones() {
    let row = |table: &Table, state: usize| {
        table.children[state].map(|child| (child.digit, child.owned, child.corners))
    };
    let version2 = Table::build(WalkVersion::Version2).unwrap();
    assert_eq!(version2.state_count(), 8);
    assert_eq!(
        row(&version2, 0),
        [
            (0, 0b11_0001, [0, 3, 5]),
            (1, 0b01_0000, [5, 4, 3]),
            (2, 0b11_1011, [3, 1, 4]),
            (3, 0b11_1111, [5, 4, 2]),
        ]
    );
    let version1 = Table::build(WalkVersion::Version1).unwrap();
    assert_eq!(version1.state_count(), 6);
    assert!(version1.states.iter().all(|s| !s.mid_flip && !s.top_flip));
    // Version 1 enters the top child rotated: M12 and M20 swap roles.
    assert_eq!(row(&version1, 0)[3], (3, 0b11_1111, [4, 5, 2]));
}

/// The twig lists give each leaf exactly the faces [`LeafFaces`] gives it.
#[test]
fn twig_lists_match_leaf_faces() {
    for version in [WalkVersion::Version2, WalkVersion::Version1] {
        let table = Table::build(version).unwrap();
        for state in 0..table.state_count() {
            let node = Node {
                state: state as u16,
                owned: table.states[state].owned,
                index: 0,
                corners: [[0, 0], [2, 0], [0, 2]],
            };
            let twig = Twig::new(&table, &node);
            for position in 0..4 {
                let leaf = twig.leaf(position);
                let mut from_twig = vec![twig.interior(position)];
                from_twig.extend(
                    twig.boundary_faces()
                        .filter(|&(p, _)| p == position)
                        .map(|(_, point)| point),
                );
                let from_leaf = LeafFaces::of(leaf.corners, leaf.owned);
                assert_eq!(from_twig, from_leaf.as_slice(), "{version:?} state {state}");
            }
        }
    }
}

#[test]
fn random_faces_are_faces() {
    let mut rng = SplitMix64::new(1);
    for level in [0, 1, 5, 32] {
        let level = Level::new(level).unwrap();
        let sampler = FaceSampler::new(level);
        for _ in 0..1000 {
            let face = sampler.draw(&mut rng);
            assert!(face.x + face.y <= 4 << level.get());
            assert_eq!(FaceKind::at(face.x, face.y), face.kind);
        }
    }
}
