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

/// The real source with the first occurrence of `from` (after `macro_rules!
/// simd_lanes`, where the model starts) replaced.
fn lanes_changed(from: &str, to: &str) -> String {
    let start = lanes::SOURCE.find("macro_rules! simd_lanes").unwrap();
    let (before, after) = lanes::SOURCE.split_at(start);
    assert!(after.contains(from), "{from}");
    format!("{before}{}", after.replacen(from, to, 1))
}

/// The source line of the first occurrence of `text` after the model's start.
fn lanes_line(text: &str) -> usize {
    let start = lanes::SOURCE.find("macro_rules! simd_lanes").unwrap();
    let at = start + lanes::SOURCE[start..].find(text).unwrap();
    lanes::SOURCE[..at].lines().count() + usize::from(lanes::SOURCE[..at].ends_with('\n'))
}

#[test]
fn the_simd_lanes_source_is_the_model() {
    let tokens = check_lanes_source(lanes::SOURCE).unwrap();
    assert!(tokens > 3000, "{tokens}");
    // Layout and comments are free.
    for source in [
        lanes_changed(
            "let fu = mul_ps(min_ps(max_ps(x, floor), below_one), scale);",
            "let fu = mul_ps(\n  min_ps(max_ps(x, /* { */ floor), below_one), // )\n  scale);",
        ),
        lanes_changed("0, 1, 4, 5, 16, 17,", "0, 1, 4, 5, // the table\n 16, 17,"),
    ] {
        assert_eq!(check_lanes_source(&source), Ok(tokens));
    }
}

#[test]
fn changed_simd_lanes_are_refused_at_their_line() {
    let cases = [
        // The clamp's operands swapped: NaN would pass through `max`.
        ("max_ps(x, floor)", "max_ps(floor, x)"),
        // A wrong byte of the nibble table.
        ("80, 81, 84, 85,", "80, 81, 86, 85,"),
        // SSE2's pack bias changed.
        ("x86::_mm_set1_epi32(0x8000)", "x86::_mm_set1_epi32(0x7fff)"),
        // AVX2's `max_ps` bound to another intrinsic.
        ("_mm256_max_ps as max_ps", "_mm256_min_ps as max_ps"),
        // AVX2's 64-bit group order.
        ("<0b11_01_10_00>", "<0b11_10_01_00>"),
        // The diagonal truncated by a rounding conversion.
        ("(iu, iv, cvttps_epi32(sum))", "(iu, iv, cvtps_epi32(sum))"),
        // SSE2 stamped with the shuffle interleave.
        (
            "simd_lanes!(Sse2Lanes, sse2_ops, interleave: unpack);",
            "simd_lanes!(Sse2Lanes, sse2_ops, interleave: shuffle);",
        ),
        // The AVX2 probe dispatched to the SSE2 lanes.
        (
            "Backend::Avx2 => unsafe { avx2::$f($($arg),*) },",
            "Backend::Avx2 => unsafe { sse2::$f($($arg),*) },",
        ),
    ];
    for (from, to) in cases {
        let error = check_lanes_source(&lanes_changed(from, to)).unwrap_err();
        assert_eq!(error.line, lanes_line(from), "{from}: {error}");
    }
    // An inserted statement and a deleted one.
    let inserted = lanes_changed("k += 2 * LANES;", "k += 2 * LANES;\nk += 0;");
    assert!(check_lanes_source(&inserted).unwrap_err().line > 0);
    let deleted = lanes_changed("    x = xor_si(x, xor_si(t, slli_epi16::<2>(t)));\n", "");
    assert!(check_lanes_source(&deleted).unwrap_err().line > 0);
    // A second `simd_lanes!` definition: which one runs is not known.
    let twice = format!(
        "{}\nmacro_rules! simd_lanes {{ () => {{}} }}\n",
        lanes::SOURCE
    );
    assert!(check_lanes_source(&twice)
        .unwrap_err()
        .detail
        .contains("2 occurrences"));
}

#[cfg(target_arch = "x86_64")]
mod simd_semantics {
    use super::*;
    use micromap_index::batch::Backend;
    use micromap_index::internals::kernel::{Cells, Halves, CHUNK};
    use micromap_index::internals::lanes::{LaneProbe, Step, BLOCK};

    /// A few blocks of each range, the two interleaves whole.
    fn small(clamp: u64, scale: u64, truncate: u64) -> Coverage {
        Coverage {
            clamp: clamp..clamp + 4 * BLOCK as u64,
            scale: scale..scale + 4 * BLOCK as u64,
            levels: 0..17,
            truncate: truncate..truncate + 4 * BLOCK as u64,
            interleave: Coverage::FULL.interleave,
        }
    }

    fn probes() -> Vec<LaneProbe> {
        Backend::ALL
            .into_iter()
            .filter_map(LaneProbe::new)
            .collect()
    }

    #[test]
    fn the_real_lanes_hold_the_readings() {
        let probes = probes();
        assert_eq!(probes[0].name(), "SSE2", "SSE2 is the x86-64 baseline");
        let backends: Vec<&dyn LaneBackend> =
            probes.iter().map(|p| p as &dyn LaneBackend).collect();
        // NaNs and infinities, the smallest normals, the products near 1
        // and the diagonal sums near 1.
        for coverage in [
            small(0x7f7f_f000, 0x0080_0000, 0x3f7f_f000),
            small(0xff80_0000, 0x3f7f_c000, 0x0),
        ] {
            check_semantics(&backends, &coverage).unwrap();
        }
    }

    /// Every backend run is named by one of the names the proof lists
    /// (the others are listed as skipped), each backend under its own.
    #[test]
    fn every_backend_is_run_or_named() {
        let names: Vec<&str> = probes().iter().map(LaneProbe::name).collect();
        assert_eq!(names.len(), Backend::available().count());
        for (i, name) in names.iter().enumerate() {
            assert!(lanes::INSTRUCTION_SETS.contains(name), "{name}");
            assert!(!names[..i].contains(name), "{name} twice");
        }
    }

    #[test]
    fn the_pack_order_is_undone_by_the_interleave() {
        for lanes in [4, 8, 16] {
            let mut seen = vec![false; CHUNK];
            for at in 0..CHUNK {
                seen[point_at(lanes, at)] = true;
            }
            assert!(seen.iter().all(|&s| s), "a permutation for {lanes} lanes");
        }
        assert_eq!(
            (0..8).map(|at| point_at(4, at)).collect::<Vec<_>>(),
            [0, 1, 2, 3, 4, 5, 6, 7]
        );
        assert_eq!(
            (0..16).map(|at| point_at(8, at)).collect::<Vec<_>>(),
            [0, 1, 2, 3, 8, 9, 10, 11, 4, 5, 6, 7, 12, 13, 14, 15]
        );
    }

    /// The SSE2 lanes with one planted change (`mutant`).
    struct Changed {
        real: LaneProbe,
        mutant: u8,
    }

    impl LaneBackend for Changed {
        fn name(&self) -> &'static str {
            "changed SSE2"
        }
        fn lanes(&self) -> usize {
            self.real.lanes()
        }
        fn step(&self, step: Step, x: &[u32; BLOCK], out: &mut [u32; BLOCK]) {
            self.real.step(step, x, out);
            for (out, &x) in out.iter_mut().zip(x) {
                let fx = f32::from_bits(x);
                match (self.mutant, step) {
                    // `max_ps(floor, x)`: a NaN passes `max` and `min`
                    // returns its second operand.
                    (1, Step::Clamp) if fx.is_nan() => {
                        *out = micromap_index::internals::kernel::BELOW_ONE.to_bits();
                    }
                    // A rounding conversion for the truncating one.
                    (2, Step::Truncate) => *out = fx.round_ties_even() as u32,
                    // The scale of one level too high at level 16.
                    (3, Step::Scale(16)) => *out = (fx * 131_072.0).to_bits(),
                    _ => {}
                }
            }
        }
        fn pack(&self, a: &[u32; 16], b: &[u32; 16], out: &mut [u16; 32]) {
            self.real.pack(a, b, out);
            if self.mutant == 4 {
                // The bias 0x7fff for 0x8000: every value one too high,
                // saturated at 0xffff.
                for out in out.iter_mut() {
                    *out = out.saturating_add(1);
                }
            }
        }
        fn cells(&self, u: &[f32; CHUNK], v: &[f32; CHUNK], level: u32, cells: &mut Cells<u16>) {
            self.real.cells(u, v, level, cells);
        }
        fn interleave(&self, halves: &Halves<u16>, out: &mut [u32; CHUNK]) {
            self.real.interleave(halves, out);
            if self.mutant == 5 {
                // The nibble table's entry 14 is 86 instead of 84: one more
                // bit in the byte of every b0 nibble 14.
                for (out, &b0) in out.iter_mut().zip(&halves.b0) {
                    for nibble in 0..4 {
                        if (b0 >> (4 * nibble)) & 0xf == 14 {
                            *out ^= 2 << (8 * nibble);
                        }
                    }
                }
            }
        }
        fn wide_interleave(&self, halves: &Halves<u32>, out: &mut [u64; CHUNK]) {
            self.real.wide_interleave(halves, out);
            if self.mutant == 6 {
                // Two points swapped (a wrong group order).
                out.swap(2, 4);
            }
        }
    }

    #[test]
    fn changed_lanes_are_refuted() {
        let coverage = small(0x7fc0_0000, 0x3f00_0000, 0x3f00_0000);
        for (mutant, check) in [
            (1, "the clamp"),
            (2, "cvttps_epi32"),
            (3, "mul_ps(x, 2^16)"),
            (4, "pack_u16"),
            // Caught first by the pipeline's order check, which runs
            // through the same interleave.
            (5, "cells then interleave"),
            (6, "wide_interleave"),
        ] {
            let changed = Changed {
                real: LaneProbe::new(Backend::Portable).unwrap(),
                mutant,
            };
            let error = check_semantics(&[&changed], &coverage).unwrap_err();
            assert!(error.check.starts_with(check), "mutant {mutant}: {error}");
            assert_eq!(error.backend, "changed SSE2");
        }
    }
}
