//! proptest: the spec in binary32 against its exact reading on random
//! `f32` pairs, with the precise statement of where they may differ.

use micromap_index::{spec, SpecLevel};
use micromap_index_test_support::window_fractions;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::One;
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;

/// `numerator / 2^denominator_log2`.
fn rational(numerator: i64, denominator_log2: u32) -> BigRational {
    BigRational::new(numerator.into(), BigInt::one() << denominator_log2)
}
/// A pair of f32 for the spec comparison.
#[derive(Clone, Copy, Debug)]
struct SpecInput {
    u: f32,
    v: f32,
    level: u32,
}

/// Arbitrary bits (NaN, inf, huge, negative), values in [0, 1], or (half
/// of the cases) a pair whose scaled fractions sum to within a few ulps of
/// 1 at some level (the only place binary32 rounding matters).
fn spec_input() -> impl Strategy<Value = SpecInput> {
    let unit = || (0u32..=0x3f80_0000).prop_map(f32::from_bits);
    let pair = prop_oneof![
        1 => (any::<u32>(), any::<u32>())
            .prop_map(|(u, v)| (f32::from_bits(u), f32::from_bits(v)))
            .boxed(),
        1 => (unit(), unit()).boxed(),
    ];
    (0u32..17).prop_flat_map(move |level| {
        let cells = 1u32 << level;
        // Small cells keep the points exact.
        let small_cell = prop_oneof![Just(0), Just(1 % cells), 0..cells];
        // Scaled fractions uf in [1/2, 1) and vf = (1 - uf) - k ulps, so
        // uf + vf = 1 - k ulp(vf): in the window for small k when vf is
        // fine enough.
        let window = (
            any::<u32>(),
            0u32..6,
            small_cell.clone(),
            small_cell,
            any::<bool>(),
        )
            .prop_map(move |(bits, k, cu, cv, swap)| {
                let (uf, vf) = window_fractions(bits, k);
                let u = (cu as f32 + uf) / cells as f32;
                let v = (cv as f32 + vf) / cells as f32;
                if swap {
                    (v, u)
                } else {
                    (u, v)
                }
            });
        prop_oneof![1 => pair.clone(), 1 => window].prop_map(move |(u, v)| SpecInput {
            u,
            v,
            level,
        })
    })
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
    let spec_level = SpecLevel::new(level).unwrap();
    let f32_result = spec::index_f32(u, v, spec_level);
    let (eu, ev) = (clamped_exact(u), clamped_exact(v));
    let exact_result = spec::index_real(&eu, &ev, spec_level);
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
    let mut runner = TestRunner::deterministic();
    let strategy = spec_input();
    let differing = (0..20_000)
        .filter(|_| {
            let input = strategy.new_tree(&mut runner).unwrap().current();
            classify_spec_difference(input) == Some(true)
        })
        .count();
    assert!(
        differing >= 200,
        "only {differing} of 20000 inputs hit the window"
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]

    #[test]
    fn spec_f32_differs_from_spec_exact_only_in_the_rounding_window(input in spec_input()) {
        prop_assert!(spec_difference_is_exactly_the_rounding_window(input));
    }
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
    assert_eq!(spec::index_f32(u, v, SpecLevel::new(1).unwrap()), 2);
    // Level 2: u = 0.125 (fraction 0.5 of cell 0), v = 0.125 - 2^-27
    // (fraction 0.5 - 2^-25 of cell 0). Exact sum 1 - 2^-25 < 1: the exact
    // reading stays in the upright triangle 0, binary32 rounds to 1.0 and
    // takes the upside-down one, 1.
    let (u, v) = (0.125f32, 0.125f32 - 2f32.powi(-27));
    assert_eq!(v.to_bits(), 0x3dff_ffff);
    let exact = spec::index_real(
        &BigRational::from_float(u).unwrap(),
        &BigRational::from_float(v).unwrap(),
        SpecLevel::new(2).unwrap(),
    );
    assert_eq!(
        (spec::index_f32(u, v, SpecLevel::new(2).unwrap()), exact),
        (1, 0)
    );
    assert!(spec_difference_is_exactly_the_rounding_window(SpecInput {
        u,
        v,
        level: 2
    }));
}
