//! Named regressions: inputs where the paper's walk evaluated in binary32 /
//! binary64 (as the talk's Python reads) differs from the exact walk.
//! Found by `cargo run --release --example float_study` (docs/float.md);
//! every expected exact index is confirmed here by `BigRational` arithmetic.

use micromap_index::{spec, uv2index, Level};
use num_rational::BigRational;

/// The exact walk's index of the real point `(u, v)`, by `BigRational`
/// (f32 values widen to f64 exactly).
fn exact_by_bigrational(u: f64, v: f64, level: Level) -> u64 {
    let exact = |x: f64| BigRational::from_float(x).unwrap();
    uv2index::index_real(&exact(u), &exact(v), level).unwrap()
}

fn exact_f32(u: u32, v: u32, level: u32) -> u64 {
    let (u, v) = (f32::from_bits(u), f32::from_bits(v));
    let level = Level::new(level).unwrap();
    let exact = exact_by_bigrational(u.into(), v.into(), level);
    assert_eq!(uv2index::exact_index_f32(u, v, level), Ok(exact));
    exact
}

fn float_f32(u: u32, v: u32, level: u32) -> u64 {
    uv2index::index_in_f32_arithmetic(
        f32::from_bits(u),
        f32::from_bits(v),
        Level::new(level).unwrap(),
    )
    .unwrap()
}

fn exact_f64(u: u64, v: u64, level: u32) -> u64 {
    let (u, v) = (f64::from_bits(u), f64::from_bits(v));
    let level = Level::new(level).unwrap();
    let exact = exact_by_bigrational(u, v, level);
    assert_eq!(uv2index::exact_index_f64(u, v, level), Ok(exact));
    exact
}

fn float_f64(u: u64, v: u64, level: u32) -> u64 {
    uv2index::index_in_f64_arithmetic(
        f64::from_bits(u),
        f64::from_bits(v),
        Level::new(level).unwrap(),
    )
    .unwrap()
}

#[test]
fn f32_w_rounds_onto_one_half_at_level_1() {
    // u = 0.5 - 2^-25, v = 0: w = 1 - u = 0.5 + 2^-25 is a tie in binary32
    // and rounds to the even 0.5, so `w > 0.5` fails: Middle instead of Left.
    let (u, v) = (0x3eff_ffff, 0x0000_0000);
    assert_eq!((float_f32(u, v, 1), exact_f32(u, v, 1)), (1, 0));
    // The reference itself, in binary32, gets this one right.
    assert_eq!(spec::reference_bits_f32(f32::from_bits(u), 0.0, 1), 0);
}

#[test]
fn f32_sum_rounds_onto_one_half_at_level_1() {
    // u + v is just below 1/2 but rounds up to it in binary32.
    let (u, v) = (0x3ecb_0d5a, 0x3dd3_ca95);
    assert_eq!((float_f32(u, v, 1), exact_f32(u, v, 1)), (1, 0));
}

#[test]
fn f32_near_horizontal_line_at_level_2() {
    let (u, v) = (0x3ec2_f2fa, 0x3e7f_ffff); // v = 1/4 - 2^-26
    assert_eq!((float_f32(u, v, 2), exact_f32(u, v, 2)), (5, 7));
}

#[test]
fn f32_near_vertex_at_level_3() {
    let (u, v) = (0x3e7f_ffff, 0x3e7f_ffff); // both 1/4 - 2^-26
    assert_eq!((float_f32(u, v, 3), exact_f32(u, v, 3)), (20, 6));
}

#[test]
fn f32_uniform_point_at_level_16() {
    // Far from any line at coarse levels: binary32 runs out of bits.
    let (u, v) = (0x3f6d_8900, 0x3bd2_391a);
    assert_eq!(
        (float_f32(u, v, 16), exact_f32(u, v, 16)),
        (2_829_471_281, 2_829_471_282)
    );
}

#[test]
fn f64_sum_rounds_onto_one_half_at_level_1() {
    let (u, v) = (0x3fcf_d33f_e659_b028, 0x3fd0_1660_0cd3_27eb);
    assert_eq!((float_f64(u, v, 1), exact_f64(u, v, 1)), (1, 0));
}

#[test]
fn f64_near_vertex_at_level_1() {
    // v = 1/2 - 2^-54, u = 2^-1073: w = 1 - (u + v) rounds onto 1/2.
    let (u, v) = (0x0000_0000_0000_0002, 0x3fdf_ffff_ffff_ffff);
    assert_eq!((float_f64(u, v, 1), exact_f64(u, v, 1)), (1, 0));
}

#[test]
fn f64_near_horizontal_line_at_level_4() {
    let (u, v) = (0x3fd6_bcbd_f253_45fc, 0x3fcf_ffff_ffff_ffff); // v = 1/4 - 2^-55
    assert_eq!((float_f64(u, v, 4), exact_f64(u, v, 4)), (82, 120));
}

#[test]
fn f64_near_diagonal_at_level_8() {
    let (u, v) = (0x3fd1_0217_24c8_fff6, 0x3fcd_fbd1_b66e_0012);
    assert_eq!((float_f64(u, v, 8), exact_f64(u, v, 8)), (31408, 12239));
}
