//! `uv2index::exact_index_f32` / `exact_index_f64` (the reference's exact
//! steps on the float bits) against the walk (`internals::exact_index_f32_ref`,
//! `exact_index_f64_ref`, the oracle) and `internals::cell_real_f32` /
//! `cell_real_f64` against the `BigRational` `spec::cell_real`: proptest over any bit pattern of the
//! closed triangle, dyadics `k / 2^m` a few ulps off lattice lines,
//! subnormals, and points outside (errors must agree too), at every level.

use micromap_index::internals::{
    cell_real_f32, cell_real_f64, exact_index_f32_ref, exact_index_f64_ref,
};
use micromap_index::num::WalkNumber;
use micromap_index::spec::{self, wide_index_from_cell};
use micromap_index::uv2index::{exact_index_f32, exact_index_f64};
use micromap_index::Level;
use micromap_index_test_support::{step_ulps, step_ulps_f64};
use num_rational::BigRational;
use proptest::prelude::*;

/// `x` moved by `steps` ulps, staying non-negative (bit patterns of
/// non-negative floats order like the floats).
/// A dyadic `k / 2^m` (`k <= 2^m`) moved by a few ulps: near a lattice line
/// of every level `>= m`.
fn near_line_f32() -> impl Strategy<Value = f32> {
    (0u32..=26, any::<u32>(), -3i32..=3).prop_map(|(m, k, steps)| {
        let k = k % ((1u32 << m.min(24)) + 1);
        step_ulps(k as f32 * 2f32.powi(-(m as i32)), steps)
    })
}

fn near_line_f64() -> impl Strategy<Value = f64> {
    (0u32..=55, any::<u64>(), -3i64..=3).prop_map(|(m, k, steps)| {
        let k = k % ((1u64 << m.min(53)) + 1);
        step_ulps_f64(k as f64 * 2f64.powi(-(m as i32)), steps)
    })
}

/// Any float: every bit pattern, a unit-interval value, a subnormal, or a
/// value near a lattice line.
fn any_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        any::<u32>().prop_map(f32::from_bits),
        (0u32..=0x3f80_0000u32).prop_map(f32::from_bits),
        (0u32..0x0080_0000u32).prop_map(f32::from_bits),
        near_line_f32(),
    ]
}

fn any_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        any::<u64>().prop_map(f64::from_bits),
        (0u64..=0x3ff0_0000_0000_0000u64).prop_map(f64::from_bits),
        (0u64..0x0010_0000_0000_0000u64).prop_map(f64::from_bits),
        near_line_f64(),
    ]
}

/// Points of the closed triangle only: `v` drawn below `1 - u` often enough
/// by reflecting pairs with `u + v > 1`.
fn in_triangle_f32() -> impl Strategy<Value = (f32, f32)> {
    (near_line_f32(), near_line_f32()).prop_map(|(u, v)| {
        let (u, v) = (u.min(1.0), v.min(1.0));
        // The exact test (an f64 sum can round down to 1).
        let outside = |u: f32, v: f32| f32::check_point(&u, &v).is_err();
        if outside(u, v) {
            // 1 - u rounded to binary32 may round up; step down until inside.
            let mut v = (1.0 - f64::from(u)) as f32;
            while outside(u, v) {
                v = step_ulps(v, -1);
            }
            (u, v)
        } else {
            (u, v)
        }
    })
}

fn exact_cell(u: f64, v: f64, level: Level) -> spec::Cell {
    let r = |x: f64| BigRational::from_float(x).unwrap_or_default();
    spec::cell_real(&r(u), &r(v), level)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4096))]

    #[test]
    fn f32_equals_the_walk(u in any_f32(), v in any_f32(), level in 0u32..=32) {
        let level = Level::new(level).unwrap();
        prop_assert_eq!(
            exact_index_f32(u, v, level),
            exact_index_f32_ref(u, v, level),
            "u = {:#010x}, v = {:#010x}, level {}", u.to_bits(), v.to_bits(), level
        );
    }

    #[test]
    fn f32_in_triangle_equals_the_walk((u, v) in in_triangle_f32(), level in 0u32..=32) {
        let level = Level::new(level).unwrap();
        let walk = exact_index_f32_ref(u, v, level);
        prop_assert!(walk.is_ok());
        prop_assert_eq!(exact_index_f32(u, v, level), walk.clone(),
            "u = {:#010x}, v = {:#010x}, level {}", u.to_bits(), v.to_bits(), level);
        // The closed form at every level (proved: docs/verification.md 10).
        let cell = cell_real_f32(u, v, level);
        prop_assert_eq!(Ok(wide_index_from_cell(cell.iu, cell.iv, cell.diagonal, level.get())), walk,
            "closed form: u = {:#010x}, v = {:#010x}, level {}", u.to_bits(), v.to_bits(), level);
    }

    #[test]
    fn f64_equals_the_walk(u in any_f64(), v in any_f64(), level in 0u32..=32) {
        let level = Level::new(level).unwrap();
        prop_assert_eq!(
            exact_index_f64(u, v, level),
            exact_index_f64_ref(u, v, level),
            "u = {:#018x}, v = {:#018x}, level {}", u.to_bits(), v.to_bits(), level
        );
    }

    #[test]
    fn f64_near_lines_equals_the_walk(u in near_line_f64(), v in near_line_f64(), level in 0u32..=32) {
        let (u, v) = (u.min(1.0), v.min(1.0));
        let v = if u + v > 1.0 { step_ulps_f64(1.0 - u, -1) } else { v };
        let level = Level::new(level).unwrap();
        let walk = exact_index_f64_ref(u, v, level);
        prop_assert_eq!(exact_index_f64(u, v, level), walk.clone(),
            "u = {:#018x}, v = {:#018x}, level {}", u.to_bits(), v.to_bits(), level);
        if let Ok(walk) = walk {
            let cell = cell_real_f64(u, v, level);
            prop_assert_eq!(wide_index_from_cell(cell.iu, cell.iv, cell.diagonal, level.get()), walk,
                "closed form: u = {:#018x}, v = {:#018x}, level {}", u.to_bits(), v.to_bits(), level);
        }
    }

    #[test]
    fn cells_equal_the_rational_reading(u in any_f64(), v in any_f64(), level in 0u32..=32) {
        let level = Level::new(level).unwrap();
        // Non-finite values have no rational; the clamp sends NaN to 0 and
        // +inf to 1, so compare those with what they clamp to.
        let finite = |x: f64| if x.is_nan() { 0.0 } else { x.clamp(-1.0, 2.0) };
        prop_assert_eq!(cell_real_f64(u, v, level), exact_cell(finite(u), finite(v), level),
            "u = {:#018x}, v = {:#018x}, level {}", u.to_bits(), v.to_bits(), level);
        let (u32_, v32) = (u as f32, v as f32);
        prop_assert_eq!(cell_real_f32(u32_, v32, level),
            exact_cell(finite(f64::from(u32_)), finite(f64::from(v32)), level));
    }
}

/// Every pair of a structured set, at every level: lattice lines of levels
/// up to 24 and their neighbours, subnormals, 0, 1 and values outside.
#[test]
fn structured_pairs_every_level() {
    let mut values = vec![
        0.0f32,
        -0.0,
        1.0,
        f32::from_bits(1),
        f32::from_bits(0x007f_ffff),
    ];
    for m in 0..=24 {
        for k in [1u32, 3, 1 << m.max(1) >> 1, (1 << m) - 1, 1 << m] {
            let x = k as f32 * 2f32.powi(-m);
            for steps in -2..=2 {
                values.push(step_ulps(x, steps));
            }
        }
    }
    values.extend([1.5, -0.25, f32::NAN, f32::INFINITY]);
    values.sort_unstable_by_key(|x| x.to_bits());
    values.dedup_by_key(|x| x.to_bits());
    let mut compared = 0u64;
    for level in 0..=32 {
        let level = Level::new(level).unwrap();
        for &u in &values {
            for &v in &values {
                let walk = exact_index_f32_ref(u, v, level);
                assert_eq!(
                    exact_index_f32(u, v, level),
                    walk,
                    "u = {:#010x}, v = {:#010x}, level {level}",
                    u.to_bits(),
                    v.to_bits()
                );
                let (u64_, v64) = (f64::from(u), f64::from(v));
                assert_eq!(exact_index_f64(u64_, v64, level), walk);
                assert_eq!(exact_index_f64_ref(u64_, v64, level), walk);
                compared += 1;
            }
        }
    }
    eprintln!("exact_index_f32/_f64: {compared} structured pairs compared with the walk");
}
