//! The prover proves the real kernels and refuses changed ones: each
//! mutant below is a kernel of the library's shape with one planted
//! change, run through the same prover.

use super::word::Bits;
use super::*;
use micromap_index::internals::kernel::{interleave_16, interleave_32, LaneWord};

#[test]
fn the_real_kernels_are_proved() {
    let proof = prove_kernel_integer_halves().unwrap();
    assert_eq!(proof.forms.len(), 4);
    // 17 narrow and 33 wide levels, two forms each, two diagonal outcomes.
    assert_eq!(proof.cases, 2 * 2 * (17 + 33));
    assert!(proof.reference_paths >= proof.cases);
}

/// The point kernel's integer half with planted changes: `mutant` picks
/// which (0: none).
fn point_half<W: LaneWord>(
    iu: W,
    iv: W,
    diagonal: W::Bool,
    last: W,
    wide: bool,
    level: u32,
    mutant: u8,
) -> (W, W) {
    let room = last.wrapping_sub(iv);
    let mut below_room = if wide {
        iu.less_than(room)
    } else {
        iu.less_than_signed(room)
    };
    if mutant == 1 && (13..=16).contains(&level) {
        // `<` becomes `<=` at levels 13..=16 (the first mutation):
        // `iu < room + 1`, no overflow since `room < 2^16`.
        below_room = iu.less_than_signed(room.wrapping_add(W::constant(1)));
    }
    let d = W::from_bool(diagonal & below_room);
    let iu = W::select(below_room, iu, room);
    let b0 = (iu ^ iu.wrapping_add(iv).wrapping_add(d)) & last;
    let t = (iu ^ iv) & b0;
    let mut f = t;
    for shift in [1, 2, 4, 8, 16] {
        let skip =
            !wide && shift == 16 || mutant == 2 && shift == 16 && level > 16 && level % 2 == 1;
        if !skip {
            f = f ^ (f >> shift);
        }
    }
    (b0, ((f ^ iu) & !b0) | t)
}

fn mutated(
    form: KernelForm,
    iu: Bits<32>,
    iv: Bits<32>,
    diagonal: bool,
    last: u64,
    mutant: u8,
) -> Bits<64> {
    use super::bdd::Node;
    let level = (last + 1).trailing_zeros();
    let wide = matches!(form, KernelForm::PointWide | KernelForm::LanesWide);
    let (b0, b1) = point_half(
        iu,
        iv,
        Node::constant(diagonal),
        Bits::of(last),
        wide,
        level,
        mutant,
    );
    if wide {
        let (low, high) = interleave_32(b0, b1);
        Bits(std::array::from_fn(|i| {
            if i < 32 {
                low.0[i]
            } else {
                high.0[i - 32]
            }
        }))
    } else {
        interleave_16(b0, b1).resize()
    }
}

fn mutated_concrete(
    form: KernelForm,
    iu: u32,
    iv: u32,
    diagonal: bool,
    level: u32,
    mutant: u8,
) -> u64 {
    let last = ((1u64 << level) - 1) as u32;
    let wide = matches!(form, KernelForm::PointWide | KernelForm::LanesWide);
    let (b0, b1) = point_half(iu, iv, diagonal, last, wide, level, mutant);
    if wide {
        let (low, high) = interleave_32(b0, b1);
        u64::from(low) | (u64::from(high) << 32)
    } else {
        u64::from(interleave_16(b0, b1))
    }
}

fn refuted(form: KernelForm, mutant: u8) -> KernelCounterexample {
    let result = prove_forms_with(
        &[form],
        |form, iu, iv, diagonal, last| mutated(form, iu, iv, diagonal, last, mutant),
        |form, iu, iv, diagonal, level| mutated_concrete(form, iu, iv, diagonal, level, mutant),
    );
    match result {
        Err(KernelProofError::Differs(example)) => example,
        other => panic!("mutant {mutant} of {form:?} not refuted: {other:?}"),
    }
}

#[test]
fn the_unmutated_copy_proves() {
    prove_forms_with(
        &[KernelForm::PointNarrow, KernelForm::PointWide],
        |form, iu, iv, diagonal, last| mutated(form, iu, iv, diagonal, last, 0),
        |form, iu, iv, diagonal, level| mutated_concrete(form, iu, iv, diagonal, level, 0),
    )
    .unwrap();
}

#[test]
fn the_narrow_fold_off_by_one_is_refuted() {
    let example = refuted(KernelForm::PointNarrow, 1);
    assert_eq!(example.level, 13);
    assert_ne!(example.kernel, example.reference);
}

#[test]
fn the_skipped_wide_prefix_step_is_refuted() {
    let example = refuted(KernelForm::PointWide, 2);
    assert_eq!(example.level, 17);
}

#[test]
fn the_machine_words_agree_with_the_reference_on_small_levels() {
    // The concrete path of the counterexamples: every cell of levels 0..=6.
    for form in KernelForm::ALL {
        for level in 0..=6 {
            let last = (1u32 << level) - 1;
            for iu in 0..=last {
                for iv in 0..=last {
                    for diagonal in [false, true] {
                        assert_eq!(
                            form.concrete(iu, iv, diagonal, level),
                            form.reference(iu, iv, diagonal, level),
                            "{form:?} level {level} cell ({iu}, {iv}) {diagonal}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn cell_dyadic_is_proved() {
    let proof = prove_cell_dyadic().unwrap();
    assert_eq!(proof.cases, 63 * 33);
}

/// `dyadic_cell` with the planted change: at levels 21 and up the
/// diagonal test is also true on the diagonal itself (`uf + vf >= mask`).
fn dyadic_mutant<W: micromap_index::internals::ReferenceWord>(
    u: W,
    v: W,
    scale_log2: u32,
    level: u32,
) -> (W, W, bool) {
    let (iu, iv, diagonal) = micromap_index::internals::dyadic_cell(u, v, scale_log2, level);
    if level < 21 || scale_log2 < level {
        return (iu, iv, diagonal);
    }
    let one = W::power_of_two(scale_log2);
    let clamp = |x: W| if x.at_least(one) { one } else { x };
    let mask = W::power_of_two(scale_log2 - level).wrapping_sub(W::constant(1));
    let sum = clamp(u).and(mask).wrapping_add(clamp(v).and(mask));
    (iu, iv, sum.at_least(mask))
}

#[test]
fn the_dyadic_diagonal_mutant_is_refuted() {
    let example = prove_dyadic_steps(dyadic_mutant, dyadic_mutant).unwrap_err();
    assert_eq!(example.level, 21);
    // The machine words show the change: the definition's diagonal is
    // false there (the fractions sum to less than 1).
    let (iu, iv, diagonal) = example.computed;
    let cell = micromap_index::spec::cell_dyadic(
        example.u_scaled,
        example.v_scaled,
        example.scale_log2,
        micromap_index::Level::new(example.level).unwrap(),
    )
    .unwrap();
    assert_eq!((iu, iv), (cell.iu, cell.iv));
    assert_ne!(diagonal, cell.diagonal);
}

#[test]
fn the_binary64_first_half_is_proved() {
    let proof = prove_binary64_first_half().unwrap();
    assert_eq!(proof.cases, 33 * (2 + 1024));
}

#[test]
fn a_binary64_diagonal_on_greater_is_refuted() {
    use micromap_index::internals::{binary64_clamped_coordinate, ReferenceWord};
    // The mutation of closed_form_f64: `>` instead of `>=`.
    let example = prove_binary64_steps(binary64_clamped_coordinate, |uf: Bits<64>, vf| {
        let sum = ReferenceWord::wrapping_add(uf, vf);
        !Bits::of(1 << 62).at_least(sum)
    })
    .unwrap_err();
    assert_eq!(example.inputs.0 + example.inputs.1, 1 << 62);
}

#[test]
fn a_binary64_fraction_off_by_one_bit_is_refuted() {
    use micromap_index::internals::{
        binary64_clamped_coordinate, binary64_diagonal, ReferenceWord,
    };
    // The fraction kept to 61 bits at levels 17..=19.
    let example = prove_binary64_steps(
        |bits: Bits<64>, level| {
            let (cell, fraction) = binary64_clamped_coordinate(bits, level);
            if (17..=19).contains(&level) {
                (cell, fraction.and(Bits::of(!1)))
            } else {
                (cell, fraction)
            }
        },
        binary64_diagonal,
    )
    .unwrap_err();
    assert_eq!(example.level, 17);
}

#[test]
fn a_binary64_cell_without_the_clamp_is_refuted() {
    use micromap_index::internals::{binary64_coordinate, binary64_diagonal};
    // closed_form_f64's old glue, `iu.min(last)`, left out: `x >= 1` keeps
    // the cell `2^level` one past the last.
    let example = prove_binary64_steps(binary64_coordinate, binary64_diagonal).unwrap_err();
    assert_eq!(example.level, 0);
    assert!(example.claim.contains("2^level - 1"), "{example}");
    assert!(f64::from_bits(example.inputs.0) >= 1.0, "{example}");
}

#[test]
fn the_binary32_first_half_is_proved() {
    let proof = prove_binary32_first_half().unwrap();
    assert_eq!(proof.cases, (33 + 17) * (1 + 256));
}

#[test]
fn binary32_first_halves_with_changed_steps_are_refuted() {
    use micromap_index::internals::kernel::{binary32_coordinate, binary32_unit_coordinate};
    use micromap_index::internals::ReferenceWord;
    let last = |level: u32| ((1u64 << level) - 1) as u32;
    // The wide form's fraction kept to 30 bits at level 20.
    let short_fraction = |bits: Bits<32>, level: u32| {
        let (cell, fraction) = binary32_coordinate::<_, true>(bits, 150 - level, last(level));
        let fraction = if level == 20 {
            fraction.and(Bits::of(!1))
        } else {
            fraction
        };
        (cell.resize(), fraction.resize())
    };
    let example = prove_binary32_forms(&[("wide", 32, &short_fraction)]).unwrap_err();
    assert_eq!((example.form, example.level), ("wide", 20), "{example}");
    // The unit form after a clamp that sends +inf to 0 like NaN.
    let unclamped = |bits: Bits<32>, level: u32| {
        use micromap_index::internals::kernel::clamp_binary32;
        let clamped = if bits.at_least(Bits::of(0x7f80_0000)) {
            Bits::of(0)
        } else {
            clamp_binary32(bits)
        };
        binary32_unit_coordinate(clamped.resize::<64>(), 150 - level, last(level))
    };
    let example = prove_binary32_forms(&[("unit", 16, &unclamped)]).unwrap_err();
    assert_eq!(example.form, "unit", "{example}");
    assert_eq!(example.bits, 0x7f80_0000, "{example}");
}

#[test]
fn a_float_truncation_on_at_least_is_refuted() {
    use micromap_index::internals::kernel::clamp_flushed;
    // `r - 1` taken when `r >= fu`: every integer fu loses one.
    let truncate = |fu: f32| {
        let sum = fu + 8_388_608.0;
        let rounded = sum - 8_388_608.0;
        let above = rounded >= fu;
        let truncated = rounded - if above { 1.0 } else { 0.0 };
        (
            (sum.to_bits() & 0x7f_ffff).wrapping_sub(u32::from(above)),
            fu - truncated,
        )
    };
    let example = prove_float_steps(clamp_flushed, truncate).unwrap_err();
    assert_eq!(example.step, "truncate_float");
    assert_eq!(f32::from_bits(example.bits), 1.0, "{example}");
}

#[test]
fn the_float_clamp_is_proved() {
    let proof = prove_float_clamp().unwrap();
    assert_eq!(proof.levels, 0..=16);
    assert_eq!(proof.forms.len(), 2);
    assert_eq!(TINY_FRACTION.to_bits(), (127 - 110) << 23);
}

#[test]
fn changed_float_clamps_are_refuted() {
    use super::bdd::Node;
    use micromap_index::internals::kernel::{truncate_float, BELOW_ONE};
    let real = |form: KernelForm, iu, iv, d, last| form.symbolic(iu, iv, d, last);
    // The stop at 1/2 instead of below 1: a cell short of the last from
    // level 2 (1/2 * 4 = 2, not 3).
    let example = prove_clamp_with(0.5, truncate_float, &FLOAT_FORMS, real).unwrap_err();
    assert_eq!(example, ClampCounterexample::StopCell { level: 2, cell: 2 });
    // A truncation that leaves the flush value a fraction of 2^-100.
    let example = prove_clamp_with(
        BELOW_ONE,
        |fu| {
            let (cell, fraction) = truncate_float(fu);
            if fu < 1e-20 {
                (cell, fraction + 2f32.powi(-100))
            } else {
                (cell, fraction)
            }
        },
        &FLOAT_FORMS,
        real,
    )
    .unwrap_err();
    assert!(
        matches!(
            example,
            ClampCounterexample::Flush {
                level: 0,
                cell: 0,
                ..
            }
        ),
        "{example}"
    );
    // An integer half that reads the diagonal with a cell at the last:
    // there the outcome flips the index's lowest bit.
    let example = prove_clamp_with(
        BELOW_ONE,
        truncate_float,
        &[KernelForm::PointNarrow],
        |form, iu: Bits<32>, iv: Bits<32>, d, last| {
            let mut index = form.symbolic(iu, iv, d, last);
            let on_edge = iu.equals(&Bits::of(last)) | iv.equals(&Bits::of(last));
            index.0[0] = index.0[0] ^ (on_edge & Node::constant(d && last > 0));
            index
        },
    )
    .unwrap_err();
    assert!(
        matches!(
            example,
            ClampCounterexample::DiagonalRead {
                form: KernelForm::PointNarrow,
                level: 1,
                ..
            }
        ),
        "{example}"
    );
}

#[test]
fn the_literal_first_half_is_proved() {
    let proof = prove_literal_first_half().unwrap();
    assert_eq!(proof.inputs, (1 << 32) + 0x4f80_0001 + 1);
}

#[test]
fn changed_literal_steps_are_refuted() {
    use micromap_index::internals::{clamp_unit, truncate_scaled};
    // The clamp's two steps swapped: NaN becomes 1.
    #[allow(clippy::manual_clamp)] // the mutant: `clamp` would keep NaN
    let example = prove_literal_steps(|x| x.min(1.0).max(0.0), truncate_scaled).unwrap_err();
    assert_eq!(example.step, "clamp_unit");
    assert!(f32::from_bits(example.bits).is_nan(), "{example}");
    // Rounding instead of truncating.
    let example = prove_literal_steps(clamp_unit, |fu| {
        let cell = fu.round() as i64 as u64;
        (cell, fu - cell as i64 as f32)
    })
    .unwrap_err();
    assert_eq!(example.step, "truncate_scaled");
    assert_eq!(f32::from_bits(example.bits), 0.5);
}
