//! Differential properties between the variants.
//!
//! * proptest: the exact walk equals the spec's exact reading on random
//!   rationals biased toward lattice lines, and the fixed-point entry points
//!   equal the exact walk on random floats biased toward lattice lines and
//!   subnormals.
//!
//! (The property of spec-f32 against spec-real is in
//! `spec_rounding_window.rs`.)

use micromap_index::{spec, uv2index, Level, SpecLevel};
use micromap_index_test_support::step_ulps_f64;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Zero};
use proptest::prelude::*;

fn rational(numerator: i64, denominator_log2: u32) -> BigRational {
    BigRational::new(numerator.into(), BigInt::one() << denominator_log2)
}

/// Folds a point of the unit square into the closed triangle, keeping its
/// position relative to lattice lines: `(u, v) -> (1 - v, 1 - u)` mirrors
/// across the hypotenuse.
fn into_triangle(u: BigRational, v: BigRational) -> (BigRational, BigRational) {
    if &u + &v > BigRational::one() {
        (BigRational::one() - v, BigRational::one() - u)
    } else {
        (u, v)
    }
}

/// A coordinate in `[0, 1]`: on a lattice line `k / 2^m`, a tiny rational
/// offset from one, or an arbitrary rational.
fn coordinate() -> impl Strategy<Value = BigRational> {
    prop_oneof![
        (0u32..=18).prop_flat_map(|m| (0i64..=(1 << m)).prop_map(move |k| rational(k, m))),
        (0u32..=18, 0i64..=(1 << 18), -3i64..=3, 20u32..=80).prop_map(|(m, k, ulps, fine)| {
            let line = rational(k % ((1 << m) + 1), m);
            let x = line + rational(ulps, fine);
            x.clamp(BigRational::zero(), BigRational::one())
        }),
        (0i64..=1000, 1i64..=1000).prop_map(|(p, q)| BigRational::new(p.min(q).into(), q.into())),
    ]
}

/// A diagonal-biased point: `u + v` on a lattice line `k / 2^m`, possibly
/// nudged off it.
fn diagonal_point() -> impl Strategy<Value = (BigRational, BigRational)> {
    (
        0u32..=18,
        0i64..=(1 << 18),
        coordinate(),
        -2i64..=2,
        20u32..=70,
    )
        .prop_map(|(m, k, u, nudge, fine)| {
            let sum = rational(k % ((1 << m) + 1), m) + rational(nudge, fine);
            let sum = sum.clamp(BigRational::zero(), BigRational::one());
            let u = if u > sum { sum.clone() } else { u };
            let v = sum - &u;
            (u, v)
        })
}

fn point() -> impl Strategy<Value = (BigRational, BigRational)> {
    prop_oneof![
        (coordinate(), coordinate()).prop_map(|(u, v)| into_triangle(u, v)),
        diagonal_point(),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn exact_walk_equals_exact_spec((u, v) in point(), level in 0u32..=16) {
        let level = SpecLevel::new(level).unwrap();
        let walk = uv2index::index_real(&u, &v, level.into());
        let reference = Ok(u64::from(spec::index_real(&u, &v, level)));
        prop_assert_eq!(walk, reference, "u = {}, v = {}, level {}", u, v, level);
    }
}

/// An f64 near something interesting: a lattice line `k / 2^m` plus a few
/// ulps, a subnormal, or any value of the unit interval.
fn float_coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![
        (0u32..=33, 0u64..=(1 << 33), -3i64..=3).prop_map(|(m, k, ulps)| {
            let line = (k % ((1 << m) + 1)) as f64 / (1u64 << m) as f64;
            step_ulps_f64(line, ulps).clamp(0.0, 1.0)
        }),
        (1u64..(1 << 52)).prop_map(f64::from_bits),
        (0u64..=0x3ff0_0000_0000_0000).prop_map(f64::from_bits),
    ]
}

/// Float points folded into the triangle (exactly: `1 - x` is exact for
/// `x` in `[1/2, 1]`; otherwise the point is left out by the caller).
fn float_point() -> impl Strategy<Value = (f64, f64)> {
    (float_coordinate(), float_coordinate()).prop_filter_map("outside", |(u, v)| {
        let exact = |x: f64| BigRational::from_float(x).unwrap();
        if exact(u) + exact(v) <= BigRational::one() {
            Some((u, v))
        } else {
            // Mirror across the hypotenuse when that is exact in binary64.
            let (mu, mv) = (1.0 - v, 1.0 - u);
            (exact(mu) == BigRational::one() - exact(v)
                && exact(mv) == BigRational::one() - exact(u))
            .then_some((mu, mv))
        }
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn fixed_f64_equals_exact_walk((u, v) in float_point(), level in 0u32..=32) {
        let level = Level::new(level).unwrap();
        let exact = uv2index::index_real(
            &BigRational::from_float(u).unwrap(),
            &BigRational::from_float(v).unwrap(),
            level,
        );
        prop_assert_eq!(uv2index::exact_index_f64(u, v, level), exact,
            "u = {:#018x}, v = {:#018x}, level {}", u.to_bits(), v.to_bits(), level);
    }

    #[test]
    fn fixed_f32_equals_exact_walk((u, v) in float_point(), level in 0u32..=32) {
        let (u, v) = (u as f32, v as f32);
        let level = Level::new(level).unwrap();
        let exact = uv2index::index_real(
            &BigRational::from_float(u).unwrap(),
            &BigRational::from_float(v).unwrap(),
            level,
        );
        prop_assert_eq!(uv2index::exact_index_f32(u, v, level), exact,
            "u = {:#010x}, v = {:#010x}, level {}", u.to_bits(), v.to_bits(), level);
    }
}

/// Any rational, including negative ones, ones above 1 and denominators
/// whose common multiple overflows 64 bits (to reach both code paths).
fn any_rational() -> impl Strategy<Value = BigRational> {
    prop_oneof![
        coordinate(),
        (-(1i64 << 40)..(1i64 << 40), 1i64..=1_000_000_000_007)
            .prop_map(|(p, q)| BigRational::new(p.into(), q.into())),
        (-3i64..=3, 1i64..=7).prop_map(|(p, q)| BigRational::new(p.into(), q.into())),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn fast_exact_paths_equal_their_bigrational_twins(
        u in any_rational(), v in any_rational(), level in 0u32..=32,
    ) {
        let level = Level::new(level).unwrap();
        prop_assert_eq!(spec::cell_real(&u, &v, level), micromap_index::internals::cell_real_ref(&u, &v, level),
            "u = {}, v = {}, level {}", u, v, level);
        prop_assert_eq!(uv2index::index_real(&u, &v, level), micromap_index::internals::index_real_ref(&u, &v, level),
            "u = {}, v = {}, level {}", u, v, level);
        let (fu, fv) = into_triangle(u.clone().clamp(BigRational::zero(), BigRational::one()),
                                     v.clone().clamp(BigRational::zero(), BigRational::one()));
        prop_assert_eq!(uv2index::index_real(&fu, &fv, level), micromap_index::internals::index_real_ref(&fu, &fv, level),
            "u = {}, v = {}, level {}", fu, fv, level);
    }
}
