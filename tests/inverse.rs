//! The inverse map against the forward maps, index by index.
//!
//! For every index of levels 0..=8 (9..=12 too in the ignored test
//! `exhaustive_up_to_level_12`: `cargo test --all-features --test inverse -- --ignored`):
//! points strictly inside the micro-triangle walk back to the index under
//! every forward implementation (the `BigRational` centroid only for levels
//! 0..=7, 8..=9 in the ignored test: it is slow), its vertices and edge midpoints
//! get the spec's tie-breaks, the vertex order is the walk's local frame,
//! and the micro-triangles tile the base triangle. A slow oracle that
//! assigns indices to the lattice's micro-triangles with the spec supplies
//! the expected vertex sets; another finds neighbours by shared edges
//! (levels 0..=6, 7..=9 in the ignored test). Sampled indices of every level
//! 0..=32 check the float conversions' rounding and the walk back.

// The tests build on the workspace toolchain (1.88+, what the dev-dependencies
// need); only the library itself keeps the older MSRV.
#![allow(clippy::incompatible_msrv)]

use micromap_index::inverse::{micro_triangle, MicroTriangle};
use micromap_index::num::Fixed64;
use micromap_index::uv2index::{self, Walk};
use micromap_index::{spec, Error, Level, SpecLevel};
use micromap_index_test_support::SplitMix64;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed};
use std::collections::HashMap;

const DEFAULT_LEVELS: std::ops::RangeInclusive<u32> = 0..=8;
const EXHAUSTIVE_LEVELS: std::ops::RangeInclusive<u32> = 9..=12;
/// The `BigRational` walk is slow; its default share stays small.
const DEFAULT_RATIONAL_LEVELS: std::ops::RangeInclusive<u32> = 0..=7;
const EXHAUSTIVE_RATIONAL_LEVELS: std::ops::RangeInclusive<u32> = 8..=9;

type Point = (u64, u64);

fn level(level: u32) -> Level {
    Level::new(level).unwrap()
}

fn every_triangle(level: Level) -> impl Iterator<Item = MicroTriangle> {
    let count = u64::try_from(level.micro_triangle_count()).unwrap();
    (0..count).map(move |index| micro_triangle(level, index).unwrap())
}

/// `(x, y) / 2^scale_log2` on Fixed64 (exact for `scale_log2 <= 60`).
fn fixed_point((x, y): Point, scale_log2: u32) -> (Fixed64, Fixed64) {
    let to_fixed = |n: u64| Fixed64::from_scaled(i64::try_from(n).unwrap(), scale_log2).unwrap();
    (to_fixed(x), to_fixed(y))
}

/// The exact walk and the exact spec on the dyadic point
/// `(x, y) / 2^scale_log2`; `None` for the spec above its level 16.
fn forward_dyadic(point: Point, scale_log2: u32, level: Level) -> (u64, Option<u64>) {
    let (u, v) = fixed_point(point, scale_log2);
    let walk = uv2index::index_unchecked(u, v, level);
    let spec = SpecLevel::try_from(level)
        .ok()
        .map(|level| u64::from(spec::index_dyadic(point.0, point.1, scale_log2, level).unwrap()));
    (walk, spec)
}

/// `weights[0] * p + weights[1] * q + weights[2] * r` (numerators).
fn combine(vertices: [Point; 3], weights: [u64; 3]) -> Point {
    vertices
        .iter()
        .zip(weights)
        .fold((0, 0), |(x, y), (&(u, v), weight)| {
            (x + weight * u, y + weight * v)
        })
}

/// Weights (out of 4) of three points strictly inside a triangle.
const INTERIOR_WEIGHTS: [[u64; 3]; 3] = [[2, 1, 1], [1, 2, 1], [1, 1, 2]];

fn what(triangle: &MicroTriangle) -> String {
    format!(
        "level {} index {} vertices {:?}",
        triangle.level(),
        triangle.index(),
        triangle.vertices_scaled()
    )
}

/// Points strictly inside walk back to the index under the exact walk and
/// the exact spec, and the walk's final state is the point's barycentrics
/// in the documented vertex order.
fn check_interior_points_walk_back(level: Level) {
    let scale_log2 = level.get() + 2;
    for triangle in every_triangle(level) {
        for weights in INTERIOR_WEIGHTS {
            let point = combine(triangle.vertices_scaled(), weights);
            let (walk, spec) = forward_dyadic(point, scale_log2, level);
            assert_eq!(walk, triangle.index(), "walk, {}", what(&triangle));
            assert_eq!(spec, Some(triangle.index()), "spec, {}", what(&triangle));

            let (u, v) = fixed_point(point, scale_log2);
            let mut state = Walk::new(u, v);
            for _ in 0..level.get() {
                state.step();
            }
            let quarters = |n: u64| Fixed64::from_scaled(n as i64, 2).unwrap();
            let expected = (
                quarters(weights[0]),
                quarters(weights[1]),
                quarters(weights[2]),
            );
            assert_eq!(
                (state.w, state.u, state.v),
                expected,
                "local frame, {}",
                what(&triangle)
            );
        }
    }
}

/// The exact centroid walks back under both exact implementations.
fn check_rational_centroid_walks_back(level: Level) {
    for triangle in every_triangle(level) {
        let (u, v) = triangle.centroid_rational();
        let index = triangle.index();
        assert_eq!(
            uv2index::index_real(&u, &v, level),
            Ok(index),
            "{}",
            what(&triangle)
        );
        assert_eq!(
            u64::from(spec::index_real(
                &u,
                &v,
                SpecLevel::try_from(level).unwrap()
            )),
            index,
            "{}",
            what(&triangle)
        );
        let [p, q, r] = triangle.vertices_rational();
        let three = BigRational::from_integer(3.into());
        assert_eq!((&p.0 + &q.0 + &r.0) / &three, u);
        assert_eq!((&p.1 + &q.1 + &r.1) / &three, v);
    }
}

/// The centroid rounded to binary32 walks back under every float variant.
fn check_f32_centroid_walks_back(level: Level) {
    for triangle in every_triangle(level) {
        let (u, v) = triangle.centroid_f32();
        let index = Ok(triangle.index());
        let what = what(&triangle);
        assert_eq!(
            Ok(u64::from(spec::index_f32(
                u,
                v,
                SpecLevel::try_from(level).unwrap()
            ))),
            index,
            "spec f32, {what}"
        );
        assert_eq!(
            uv2index::index_in_f32_arithmetic(u, v, level),
            index,
            "walk f32, {what}"
        );
        assert_eq!(
            uv2index::index_in_f64_arithmetic(f64::from(u), f64::from(v), level),
            index,
            "walk f64, {what}"
        );
        assert_eq!(
            uv2index::exact_index_f32(u, v, level),
            index,
            "fixed f32, {what}"
        );
        let (u, v) = triangle.centroid_f64();
        assert_eq!(
            uv2index::index_in_f64_arithmetic(u, v, level),
            index,
            "walk f64, {what}"
        );
        assert_eq!(
            uv2index::exact_index_f64(u, v, level),
            index,
            "fixed f64, {what}"
        );
    }
}

/// Vertices and edge midpoints are shared with neighbours: the walk must
/// give them the index the spec's tie rules give, whichever that is.
fn check_boundary_points_follow_the_spec(level: Level) {
    let scale_log2 = level.get() + 1;
    for triangle in every_triangle(level) {
        let [p, q, r] = triangle.vertices_scaled();
        let doubled = |(u, v): Point| (2 * u, 2 * v);
        let sum = |a: Point, b: Point| (a.0 + b.0, a.1 + b.1);
        let points = [
            doubled(p),
            doubled(q),
            doubled(r),
            sum(q, r),
            sum(r, p),
            sum(p, q),
        ];
        for point in points {
            let (walk, spec) = forward_dyadic(point, scale_log2, level);
            assert_eq!(Some(walk), spec, "point {point:?}, {}", what(&triangle));
        }
    }
}

/// Each vertex triple is a lattice micro-triangle of the orientation the
/// flag says, wound counter-clockwise exactly when upright, and no two
/// indices share one: with `4^level` of them they tile the base triangle.
fn check_tiling(level: Level) {
    let side = 1u64 << level.get();
    // One bit per lattice micro-triangle: (row, column, orientation).
    let mut seen = vec![false; 2 * (side * side) as usize];
    for triangle in every_triangle(level) {
        let [p, q, r] = triangle.vertices_scaled();
        let mut sorted = [p, q, r];
        sorted.sort_unstable();
        // Sorted by u then v: upright (a,b) (a,b+1) (a+1,b); upside down
        // (a,b+1) (a+1,b) (a+1,b+1).
        let (slot, upright) = match sorted {
            [(a, b), (a2, b2), (a3, b3)] if (a2, b2, a3, b3) == (a, b + 1, a + 1, b) => {
                assert!(a + b < side, "{}", what(&triangle));
                (2 * (b * side + a), true)
            }
            [(a, b2), (a1, b), (a3, b3)] if (a1, b2, a3, b3) == (a + 1, b + 1, a + 1, b + 1) => {
                assert!(a + b + 2 <= side, "{}", what(&triangle));
                (2 * (b * side + a) + 1, false)
            }
            _ => panic!("not a lattice micro-triangle: {}", what(&triangle)),
        };
        assert_eq!(triangle.upright(), upright, "{}", what(&triangle));
        let cross = |a: Point, b: Point, c: Point| {
            let (ax, ay) = (i128::from(a.0), i128::from(a.1));
            (i128::from(b.0) - ax) * (i128::from(c.1) - ay)
                - (i128::from(b.1) - ay) * (i128::from(c.0) - ax)
        };
        assert_eq!(cross(p, q, r) > 0, upright, "winding, {}", what(&triangle));
        let slot = slot as usize;
        assert!(!seen[slot], "vertex set used twice: {}", what(&triangle));
        seen[slot] = true;
    }
}

/// The slow oracle: every lattice micro-triangle of the level, located by
/// the exact spec (not the walk) at an interior point. Vertex sets sorted.
fn micro_triangles_ref(level: Level) -> Vec<[Point; 3]> {
    let side = 1u64 << level.get();
    let mut by_index = vec![None; (side * side) as usize];
    for b in 0..side {
        for a in 0..side - b {
            let upright = [(a, b), (a, b + 1), (a + 1, b)];
            let upside_down = [(a, b + 1), (a + 1, b), (a + 1, b + 1)];
            let mut candidates = vec![(upright, (4 * a + 1, 4 * b + 1))];
            if a + b + 2 <= side {
                candidates.push((upside_down, (4 * a + 3, 4 * b + 3)));
            }
            for (vertices, inside) in candidates {
                let index = spec::index_dyadic(
                    inside.0,
                    inside.1,
                    level.get() + 2,
                    SpecLevel::try_from(level).unwrap(),
                )
                .unwrap();
                let slot = &mut by_index[index as usize];
                assert!(slot.is_none(), "spec index {index} used twice");
                *slot = Some(vertices);
            }
        }
    }
    by_index.into_iter().map(Option::unwrap).collect()
}

fn sorted(mut vertices: [Point; 3]) -> [Point; 3] {
    vertices.sort_unstable();
    vertices
}

fn check_against_ref(level: Level) {
    let expected = micro_triangles_ref(level);
    for triangle in every_triangle(level) {
        assert_eq!(
            sorted(triangle.vertices_scaled()),
            expected[triangle.index() as usize],
            "{}",
            what(&triangle)
        );
    }
}

/// The neighbour oracle: the other micro-triangle holding both endpoints.
fn check_neighbours_against_shared_edges(level: Level) {
    let mut by_edge: HashMap<[Point; 2], Vec<u64>> = HashMap::new();
    let edge_key = |a: Point, b: Point| if a < b { [a, b] } else { [b, a] };
    for triangle in every_triangle(level) {
        let [p, q, r] = triangle.vertices_scaled();
        for (a, b) in [(q, r), (r, p), (p, q)] {
            by_edge
                .entry(edge_key(a, b))
                .or_default()
                .push(triangle.index());
        }
    }
    let mut boundary_edges = 0;
    for triangle in every_triangle(level) {
        let [p, q, r] = triangle.vertices_scaled();
        let neighbours = triangle.neighbours();
        for (i, (a, b)) in [(q, r), (r, p), (p, q)].into_iter().enumerate() {
            let expected = by_edge[&edge_key(a, b)]
                .iter()
                .copied()
                .find(|&other| other != triangle.index());
            assert_eq!(neighbours[i], expected, "edge {i}, {}", what(&triangle));
            boundary_edges += usize::from(expected.is_none());
        }
    }
    assert_eq!(boundary_edges, 3 << level.get());
}

#[test]
fn interior_points_walk_back() {
    for n in DEFAULT_LEVELS {
        check_interior_points_walk_back(level(n));
    }
}

#[test]
fn rational_centroid_walks_back() {
    for n in DEFAULT_RATIONAL_LEVELS {
        check_rational_centroid_walks_back(level(n));
    }
}

#[test]
fn f32_centroid_walks_back_under_every_float_variant() {
    for n in DEFAULT_LEVELS {
        check_f32_centroid_walks_back(level(n));
    }
}

#[test]
fn vertices_and_edge_midpoints_follow_the_spec() {
    for n in DEFAULT_LEVELS {
        check_boundary_points_follow_the_spec(level(n));
    }
}

#[test]
fn micro_triangles_tile_the_triangle() {
    for n in DEFAULT_LEVELS {
        check_tiling(level(n));
    }
}

#[test]
fn vertex_sets_match_the_spec_oracle() {
    for n in DEFAULT_LEVELS {
        check_against_ref(level(n));
    }
}

#[test]
fn neighbours_match_shared_edges() {
    for n in 0..=6 {
        check_neighbours_against_shared_edges(level(n));
    }
}

#[test]
fn consecutive_indices_share_a_vertex() {
    // The curve is continuous, though not through edges: at level 1 the
    // Right child (2) and the Top child (3) only touch at a corner.
    for n in DEFAULT_LEVELS {
        let mut previous: Option<MicroTriangle> = None;
        for triangle in every_triangle(level(n)) {
            if let Some(previous) = previous {
                let shared = previous
                    .vertices_scaled()
                    .into_iter()
                    .filter(|vertex| triangle.vertices_scaled().contains(vertex));
                assert!(
                    shared.count() >= 1,
                    "{} -> {}",
                    what(&previous),
                    what(&triangle)
                );
            }
            previous = Some(triangle);
        }
    }
}

#[test]
fn accessors_agree_with_each_other() {
    for n in [0, 1, 2, 5] {
        let level = level(n);
        let denominator = BigInt::one() << n;
        let rational = |x: u64| BigRational::new(x.into(), denominator.clone());
        for triangle in every_triangle(level) {
            let scaled = triangle.vertices_scaled();
            assert_eq!(triangle.level(), level);
            assert_eq!(
                triangle.vertices_rational(),
                scaled.map(|(u, v)| (rational(u), rational(v)))
            );
            let [p, q, r] = triangle.vertices_rational();
            let two = BigRational::from_integer(2.into());
            let mid = |a: &(BigRational, BigRational), b: &(BigRational, BigRational)| {
                ((&a.0 + &b.0) / &two, (&a.1 + &b.1) / &two)
            };
            assert_eq!(
                triangle.edge_midpoints_rational(),
                [mid(&q, &r), mid(&r, &p), mid(&p, &q)]
            );
        }
    }
}

/// A fixed spread of indices at one level: both ends, digit patterns and a
/// pseudo-random sample.
fn sample_indices(level: Level) -> Vec<u64> {
    let last = u64::try_from(level.micro_triangle_count() - 1).unwrap();
    let mut indices = vec![
        0,
        last,
        last / 3,
        last / 3 * 2,
        0x5555_5555_5555_5555 & last,
    ];
    let mut rng = SplitMix64::new(0x9e37_79b9_7f4a_7c15 ^ u64::from(level.get()));
    for _ in 0..200 {
        indices.push(rng.next_u64() & last);
    }
    indices
}

/// Whether `rounded` is a nearest binary32 value to `exact`.
fn is_nearest_f32(rounded: f32, exact: &BigRational) -> bool {
    let distance = |x: f32| (BigRational::from_float(x).unwrap() - exact).abs();
    let here = distance(rounded);
    here <= distance(rounded.next_up()) && here <= distance(rounded.next_down())
}

#[test]
fn sampled_indices_of_every_level_walk_back_and_round_correctly() {
    for n in 0..=32 {
        let level = level(n);
        for index in sample_indices(level) {
            let triangle = micro_triangle(level, index).unwrap();
            for weights in INTERIOR_WEIGHTS {
                let point = combine(triangle.vertices_scaled(), weights);
                let (walk, spec) = forward_dyadic(point, n + 2, level);
                assert_eq!(walk, index, "{}", what(&triangle));
                if let Some(spec) = spec {
                    assert_eq!(spec, index, "{}", what(&triangle));
                }
            }
            let exact = triangle.vertices_rational();
            for ((u, v), (exact_u, exact_v)) in triangle.vertices_f32().into_iter().zip(&exact) {
                if n <= 24 {
                    assert_eq!(BigRational::from_float(u).as_ref(), Some(exact_u));
                    assert_eq!(BigRational::from_float(v).as_ref(), Some(exact_v));
                } else {
                    assert!(is_nearest_f32(u, exact_u) && is_nearest_f32(v, exact_v));
                }
            }
            for ((u, v), (exact_u, exact_v)) in triangle.vertices_f64().into_iter().zip(&exact) {
                assert_eq!(BigRational::from_float(u).as_ref(), Some(exact_u));
                assert_eq!(BigRational::from_float(v).as_ref(), Some(exact_v));
            }
            let (u, v) = triangle.centroid_f32();
            let (exact_u, exact_v) = triangle.centroid_rational();
            assert!(is_nearest_f32(u, &exact_u), "{}", what(&triangle));
            assert!(is_nearest_f32(v, &exact_v), "{}", what(&triangle));
            let (u64_u, u64_v) = triangle.centroid_f64();
            let half_ulp = |x: f64| BigRational::from_float(x * f64::EPSILON / 2.0).unwrap();
            assert!((BigRational::from_float(u64_u).unwrap() - &exact_u).abs() <= half_ulp(u64_u));
            assert!((BigRational::from_float(u64_v).unwrap() - &exact_v).abs() <= half_ulp(u64_v));
            // The exact walk on the centroid itself.
            assert_eq!(uv2index::index_real(&exact_u, &exact_v, level), Ok(index));
        }
    }
}

#[test]
fn out_of_range_indices_are_errors() {
    for (n, index) in [(0, 1), (1, 4), (8, 1 << 16), (31, 1 << 62), (31, u64::MAX)] {
        assert_eq!(
            micro_triangle(level(n), index),
            Err(Error::IndexOutOfRange { index, level: n })
        );
    }
    // Every u64 is an index at level 32.
    let last = micro_triangle(level(32), u64::MAX).unwrap();
    assert_eq!(last.index(), u64::MAX);
    assert_eq!(
        Error::IndexOutOfRange { index: 4, level: 1 }.to_string(),
        "index 4 is out of range for level 1: valid indices are 0..=3"
    );
    assert_eq!(
        Error::IndexOutOfRange {
            index: 0,
            level: 70
        }
        .to_string(),
        "index 0 is out of range for level 70"
    );
}

#[test]
#[ignore = "exhaustive tier (minutes): run with --ignored"]
fn exhaustive_up_to_level_12() {
    for n in EXHAUSTIVE_RATIONAL_LEVELS {
        check_rational_centroid_walks_back(level(n));
    }
    for n in EXHAUSTIVE_LEVELS {
        let level = level(n);
        check_interior_points_walk_back(level);
        check_f32_centroid_walks_back(level);
        check_boundary_points_follow_the_spec(level);
        check_tiling(level);
        check_against_ref(level);
    }
    for n in 7..=9 {
        check_neighbours_against_shared_edges(level(n));
    }
}
