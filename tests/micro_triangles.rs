//! `inverse::micro_triangle` (the reference's integer half inverted,
//! constant time) and `inverse::micro_triangles` (the iterator) against
//! `internals::micro_triangle_ref`, which replays the walk digit by digit: every
//! index of levels 0..=10, random indices of every level up to 32, and the
//! iterator against `triangle` for every triangle of levels 0..=10 and a
//! prefix of levels 11..=32.

use micromap_index::internals::micro_triangle_ref;
use micromap_index::inverse::{micro_triangle, micro_triangles};
use micromap_index::{spec, Error, Level};
use proptest::prelude::*;

fn assert_matches_replay(level: Level, index: u64) {
    let fast = micro_triangle(level, index).unwrap();
    let replay = micro_triangle_ref(level, index).unwrap();
    assert_eq!(fast, replay, "level {level}, index {index:#x}");
    assert_eq!(fast.index(), index);
}

#[test]
fn every_index_of_levels_0_to_10_matches_the_replay() {
    let mut compared = 0u64;
    for level in 0..=10 {
        let level = Level::new(level).unwrap();
        for index in 0..(1u64 << (2 * level.get())) {
            assert_matches_replay(level, index);
            compared += 1;
        }
    }
    eprintln!("inverse::micro_triangle: {compared} indices compared with the replay");
}

#[test]
fn iterator_visits_every_triangle_of_levels_0_to_10_in_order() {
    let mut visited = 0u64;
    for level in 0..=10 {
        let level = Level::new(level).unwrap();
        let mut expected_index = 0u64;
        for t in micro_triangles(level) {
            assert_eq!(
                t,
                micro_triangle(level, expected_index).unwrap(),
                "level {level}"
            );
            expected_index += 1;
        }
        assert_eq!(u128::from(expected_index), level.micro_triangle_count());
        visited += expected_index;
    }
    eprintln!("inverse::micro_triangles: {visited} triangles checked");
}

#[test]
fn iterator_prefix_of_high_levels() {
    for level in 11..=32 {
        let level = Level::new(level).unwrap();
        for (i, t) in micro_triangles(level).take(70_000).enumerate() {
            assert_eq!(t, micro_triangle(level, i as u64).unwrap(), "level {level}");
        }
    }
}

#[test]
fn last_triangles_and_range() {
    for level in 0..=32 {
        let level = Level::new(level).unwrap();
        let last = ((1u128 << (2 * level.get())) - 1) as u64;
        assert_matches_replay(level, last);
        assert_matches_replay(level, 0);
        if level.get() < 32 {
            assert_eq!(
                micro_triangle(level, last + 1),
                Err(Error::IndexOutOfRange {
                    index: last + 1,
                    level: level.get()
                })
            );
        }
    }
}

/// The cell and orientation agree with the reference's forward map: a point
/// strictly inside the micro-triangle, the dyadic `(4a + 1, 4b + 1) /
/// 2^(level + 2)` of an upright one in cell `(a, b)` (`4a + 3`, `4b + 3` of
/// an upside-down one), maps back to its index.
#[test]
fn centroids_map_back_under_the_reference() {
    for level in 0..=8 {
        let level = Level::new(level).unwrap();
        for t in micro_triangles(level) {
            let [a, b, c] = t.vertices_scaled();
            let (iu, iv) = t.cell();
            let (u, v) = if t.upright() {
                (4 * iu + 1, 4 * iv + 1)
            } else {
                (4 * iu + 3, 4 * iv + 3)
            };
            assert!([a, b, c]
                .iter()
                .all(|&(x, y)| x <= 1 << level.get() && y <= 1 << level.get()));
            let index = spec::wide_index_dyadic(u, v, level.get() + 2, level);
            assert_eq!(index, Ok(t.index()), "level {level}, triangle {t:?}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]

    #[test]
    fn random_indices_match_the_replay(level in 0u32..=32, index in any::<u64>()) {
        let level = Level::new(level).unwrap();
        let index = if level.get() == 32 { index } else { index % (1u64 << (2 * level.get())) };
        let fast = micro_triangle(level, index).unwrap();
        let replay = micro_triangle_ref(level, index).unwrap();
        prop_assert_eq!(fast, replay, "level {}, index {:#x}", level, index);
    }
}
