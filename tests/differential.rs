//! Differential properties between the variants.
//!
//! * proptest: the exact walk equals the spec's exact reading on random
//!   rationals biased toward lattice lines, and the fixed-point entry points
//!   equal the exact walk on random floats biased toward lattice lines and
//!   subnormals.
//! * quickcheck: the spec in binary32 against its exact reading on random
//!   `f32` pairs, with the precise statement of where they may differ.

use micromap_index::{fixed, spec, uv2index, Level};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Zero};
use proptest::prelude::*;
use quickcheck::{Arbitrary, Gen, QuickCheck};

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
        let level = Level::new(level).unwrap();
        let walk = uv2index::index_exact(&u, &v, level);
        let reference = spec::index_exact(&u, &v, level).map(u64::from);
        prop_assert_eq!(walk, reference, "u = {}, v = {}, level {}", u, v, level);
    }
}

/// An f64 near something interesting: a lattice line `k / 2^m` plus a few
/// ulps, a subnormal, or any value of the unit interval.
fn float_coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![
        (0u32..=33, 0u64..=(1 << 33), -3i64..=3).prop_map(|(m, k, ulps)| {
            let line = (k % ((1 << m) + 1)) as f64 / (1u64 << m) as f64;
            step_ulps(line, ulps).clamp(0.0, 1.0)
        }),
        (1u64..(1 << 52)).prop_map(f64::from_bits),
        (0u64..=0x3ff0_0000_0000_0000).prop_map(f64::from_bits),
    ]
}

fn step_ulps(x: f64, ulps: i64) -> f64 {
    let bits = x.to_bits() as i64 + ulps;
    if bits < 0 {
        0.0
    } else {
        f64::from_bits(bits as u64)
    }
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
        let exact = uv2index::index_exact(
            &BigRational::from_float(u).unwrap(),
            &BigRational::from_float(v).unwrap(),
            level,
        );
        prop_assert_eq!(fixed::index_f64(u, v, level), exact,
            "u = {:#018x}, v = {:#018x}, level {}", u.to_bits(), v.to_bits(), level);
    }

    #[test]
    fn fixed_f32_equals_exact_walk((u, v) in float_point(), level in 0u32..=32) {
        let (u, v) = (u as f32, v as f32);
        let level = Level::new(level).unwrap();
        let exact = uv2index::index_exact(
            &BigRational::from_float(u).unwrap(),
            &BigRational::from_float(v).unwrap(),
            level,
        );
        prop_assert_eq!(fixed::index_f32(u, v, level), exact,
            "u = {:#010x}, v = {:#010x}, level {}", u.to_bits(), v.to_bits(), level);
    }
}

/// A pair of f32 for the spec comparison: arbitrary bits (NaN, inf, huge,
/// negative), values in [0, 1], or a pair whose scaled fractions sum to
/// within a few ulps of 1 at some level (the only place binary32 rounding
/// matters).
#[derive(Clone, Debug)]
struct SpecInput {
    u: f32,
    v: f32,
    level: u32,
}

impl Arbitrary for SpecInput {
    fn arbitrary(g: &mut Gen) -> Self {
        let level = u32::arbitrary(g) % 17;
        let unit = |g: &mut Gen| f32::from_bits(u32::arbitrary(g) % 0x3f80_0001);
        let (u, v) = match u8::arbitrary(g) % 4 {
            0 => (
                f32::from_bits(u32::arbitrary(g)),
                f32::from_bits(u32::arbitrary(g)),
            ),
            1 => (unit(g), unit(g)),
            _ => {
                // Scaled fractions uf in [1/2, 1) and vf = (1 - uf) - k ulps,
                // so uf + vf = 1 - k ulp(vf): in the window for small k when
                // vf is fine enough. Small cells keep the points exact.
                let cells = 1u32 << level;
                let uf = f32::from_bits(0x3f00_0000 + u32::arbitrary(g) % 0x80_0000);
                let rest = 1.0 - uf; // exact (Sterbenz)
                let k = u32::arbitrary(g) % 6;
                let vf = f32::from_bits(rest.to_bits().saturating_sub(k));
                let small_cell = |g: &mut Gen| match u8::arbitrary(g) % 3 {
                    0 => 0,
                    1 => 1 % cells,
                    _ => u32::arbitrary(g) % cells,
                };
                let u = (small_cell(g) as f32 + uf) / cells as f32;
                let v = (small_cell(g) as f32 + vf) / cells as f32;
                if bool::arbitrary(g) {
                    (u, v)
                } else {
                    (v, u)
                }
            }
        };
        SpecInput { u, v, level }
    }
}

/// The reference's clamp, as exact rationals (NaN -> 0, ±inf -> 0/1).
#[allow(clippy::manual_clamp)] // `f32::clamp` keeps NaN; the reference maps it to 0
fn clamped_exact(x: f32) -> BigRational {
    BigRational::from_float(x.max(0.0).min(1.0)).unwrap()
}

/// Where spec-f32 and spec-exact may differ, stated exactly: only when the
/// real sum of the scaled fractions `uf + vf` lies in `[1 - 2^-25, 1)`, which
/// binary32 rounds up to 1, *and* the reference then uses that test
/// (`iu + iv < 2^level - 1`). In that window they always differ.
fn spec_difference_is_exactly_the_rounding_window(input: SpecInput) -> bool {
    classify_spec_difference(input).is_some()
}

/// `Some(differs)` when the property holds for `input`, `None` otherwise.
fn classify_spec_difference(input: SpecInput) -> Option<bool> {
    let SpecInput { u, v, level } = input;
    let f32_result = spec::index_f32(u, v, level);
    let (eu, ev) = (clamped_exact(u), clamped_exact(v));
    let level_checked = Level::new(level).unwrap();
    let exact_result = spec::index_exact(&eu, &ev, level_checked).unwrap();
    let cells = BigRational::from_integer(BigInt::from(1u32 << level));
    let (su, sv) = (eu * &cells, ev * &cells);
    let (iu, iv) = (su.floor(), sv.floor());
    let fraction_sum = (&su - &iu) + (&sv - &iv);
    let window_low = BigRational::one() - rational(1, 25);
    let in_window = fraction_sum >= window_low && fraction_sum < BigRational::one();
    let cells_int = BigInt::from(1u32 << level);
    let clamp_cell = |i: BigInt| if i >= cells_int { &cells_int - 1 } else { i };
    let test_used = clamp_cell(iu.to_integer()) + clamp_cell(iv.to_integer()) < &cells_int - 1;
    let should_differ = in_window && test_used;
    if (f32_result != exact_result) != should_differ {
        eprintln!(
            "u = {:#010x}, v = {:#010x}, level {level}: f32 {f32_result}, exact {exact_result}, window {in_window}, test used {test_used}",
            u.to_bits(),
            v.to_bits()
        );
        return None;
    }
    Some(should_differ)
}

/// The property above can only fail if its generator reaches the window:
/// make sure it does, often.
#[test]
fn spec_input_generator_reaches_the_rounding_window() {
    let mut g = Gen::new(100);
    let differing = (0..20_000)
        .filter(|_| classify_spec_difference(SpecInput::arbitrary(&mut g)) == Some(true))
        .count();
    assert!(
        differing >= 200,
        "only {differing} of 20000 inputs hit the window"
    );
}

#[test]
fn spec_f32_differs_from_spec_exact_only_in_the_rounding_window() {
    QuickCheck::new()
        .tests(20_000)
        .quickcheck(spec_difference_is_exactly_the_rounding_window as fn(SpecInput) -> bool);
}

/// Concrete binary32 inputs where the reference on a GPU and its exact
/// reading disagree (found by the property above; bits are exact).
#[test]
fn regression_spec_f32_rounding_cases() {
    // u = 0.5, v = 0.5 - 2^-26 at level 1: fu = 1 (cell 1, fraction 0),
    // fv = 1 - 2^-25 (cell 0, fraction 1 - 2^-25). The sum 1 - 2^-25 rounds
    // to 1.0 ... but iu + iv = 1 = 2^1 - 1, so the test is not used.
    let (u, v) = (0.5f32, f32::from_bits(0x3eff_ffff));
    assert!(spec_difference_is_exactly_the_rounding_window(SpecInput {
        u,
        v,
        level: 1
    }));
    assert_eq!(spec::index_f32(u, v, 1), 2);
    // Level 2: u = 0.125 (fraction 0.5 of cell 0), v = 0.125 - 2^-27
    // (fraction 0.5 - 2^-25 of cell 0). Exact sum 1 - 2^-25 < 1: the exact
    // reading stays in the upright triangle 0, binary32 rounds to 1.0 and
    // takes the upside-down one, 1.
    let (u, v) = (0.125f32, 0.125f32 - 2f32.powi(-27));
    assert_eq!(v.to_bits(), 0x3dff_ffff);
    let exact = spec::index_exact(
        &BigRational::from_float(u).unwrap(),
        &BigRational::from_float(v).unwrap(),
        Level::new(2).unwrap(),
    );
    assert_eq!((spec::index_f32(u, v, 2), exact), (1, Ok(0)));
    assert!(spec_difference_is_exactly_the_rounding_window(SpecInput {
        u,
        v,
        level: 2
    }));
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
        prop_assert_eq!(spec::cell_exact(&u, &v, level), spec::cell_exact_ref(&u, &v, level),
            "u = {}, v = {}, level {}", u, v, level);
        prop_assert_eq!(uv2index::index_exact(&u, &v, level), uv2index::index_exact_ref(&u, &v, level),
            "u = {}, v = {}, level {}", u, v, level);
        let (fu, fv) = into_triangle(u.clone().clamp(BigRational::zero(), BigRational::one()),
                                     v.clone().clamp(BigRational::zero(), BigRational::one()));
        prop_assert_eq!(uv2index::index_exact(&fu, &fv, level), uv2index::index_exact_ref(&fu, &fv, level),
            "u = {}, v = {}, level {}", fu, fv, level);
    }
}
