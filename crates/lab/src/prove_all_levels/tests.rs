//! Unit tests of the construction.

#[allow(clippy::wildcard_imports)]
use super::*;

fn machine() -> Machine {
    Machine::new(WalkVersion::Version2).unwrap()
}

/// The comparison rule against exact arithmetic: every single-remainder
/// form, every dyadic remainder triple with denominator 16 and sum in
/// `0..=2`, thresholds 0 and 1/2.
#[test]
fn comparisons_are_exact() {
    let den = 16i64;
    for ru in 0..den {
        for rv in 0..den {
            for rw in 0..den {
                let total = ru + rv + rw;
                if total % den != 0 {
                    continue;
                }
                let rems = [ru, rv, rw];
                // Column d+1 of each remainder: first bit and the rest.
                let next = Column {
                    bits: rems.map(|r| 2 * r >= den),
                    rest: Rest {
                        sum: (rems.iter().map(|r| (2 * r) % den).sum::<i64>() / den) as u8,
                        zero: rems.map(|r| (2 * r) % den == 0),
                    },
                };
                let input = StepInput {
                    sum: (total / den) as u8,
                    next,
                };
                for (a, b) in [(1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, -1), (0, 0)] {
                    for constant in -3..=3 {
                        let form = Form {
                            ru: a,
                            rv: b,
                            constant,
                        };
                        // value * den, exactly.
                        let value =
                            i64::from(a) * ru + i64::from(b) * rv + i64::from(constant) * den;
                        for half_units in [0, 1] {
                            let exact = (2 * value).cmp(&(i64::from(half_units) * den));
                            assert_eq!(
                                form.compare_with_half_units(half_units, input),
                                Some(exact),
                                "{form:?} at ({ru}, {rv}, {rw})/{den} vs {half_units}/2"
                            );
                        }
                    }
                }
                assert_eq!(
                    Form {
                        ru: 1,
                        rv: -1,
                        constant: 0
                    }
                    .compare_with_half_units(1, input),
                    None
                );
            }
        }
    }
}

#[test]
fn learnt_columns_are_the_codes_bit_formula() {
    // b0 = ~(u ^ w), t = (u ^ v) & b0, f = parity ^ t,
    // b1 = ((f ^ u) & ~b0) | t: the lines of `integer_half!`.
    let columns = ReferenceColumns::learn().unwrap();
    for parity in [false, true] {
        for bits in bit_triples() {
            let [u, v, w] = bits;
            let b0 = !(u ^ w);
            let t = (u ^ v) & b0;
            let f = parity ^ t;
            #[allow(clippy::needless_bitwise_bool)] // the code's bit formula, verbatim
            let b1 = ((f ^ u) & !b0) | t;
            let digit = u8::from(b0) | u8::from(b1) << 1;
            assert_eq!(
                columns.digit(parity, bits),
                (digit, parity ^ t),
                "{parity} {bits:?}"
            );
        }
    }
}

#[test]
fn checker_completes_exactly_the_satisfiable_rests() {
    // A rest is completable iff some remainders in [0, 1) with these
    // zeros sum to D: none nonzero and D = 0, two and D = 1, three and
    // D in 1..=2.
    let done = completable();
    for rest in Rest::all() {
        let nonzero = rest.zero.iter().filter(|&&z| !z).count();
        let satisfiable = match nonzero {
            0 => rest.sum == 0,
            2 => rest.sum == 1,
            3 => rest.sum == 1 || rest.sum == 2,
            _ => false,
        };
        assert_eq!(done.contains(&rest), satisfiable, "{rest:?}");
    }
}

#[test]
fn version2_is_proved_and_version1_refuted() {
    let report = prove_all_levels(WalkVersion::Version2).unwrap();
    assert_eq!(report.verdict, Verdict::Proved, "{:?}", report.counts);
    let report = prove_all_levels(WalkVersion::Version1).unwrap();
    let Verdict::Counterexample(example) = report.verdict else {
        panic!("version 1 not refuted: {:?}", report.verdict);
    };
    let (walk, reference) = example.real.unwrap();
    assert_ne!(walk, reference);
    assert_eq!(
        (walk, reference),
        (example.walk_index, example.reference_index)
    );
}

/// Version 2 with the tie rule on `v = 1/2` dropped: must be rejected.
fn step_without_tie_rule(walk: &mut Walk<Symbolic>) -> u8 {
    walk.mid_flip = false;
    walk.step()
}

/// Version 2 with the Left/Right swap inside Top children dropped.
fn step_without_top_flip(walk: &mut Walk<Symbolic>) -> u8 {
    walk.top_flip = false;
    walk.step()
}

/// The decrement rule without the hypotenuse move (and the clamps).
fn no_move(zero: [bool; 3], _u_zero: bool, w_zero: bool) -> Option<usize> {
    (!w_zero && zero[W]).then_some(W)
}

#[test]
fn mutated_transducers_are_rejected() {
    let columns = machine().columns();
    for step in [step_without_tie_rule as SymbolicStep, step_without_top_flip] {
        let report = explore(&Machine::with_parts(step, columns, decremented_coordinate));
        assert!(
            matches!(report.verdict, Verdict::Counterexample(_)),
            "{:?}",
            report.verdict
        );
    }
    // One wrong entry in the reference's column table.
    for parity in 0..2 {
        for key in 0..8 {
            let mut wrong = columns;
            wrong.digits[parity][key] ^= 1;
            let report = explore(&Machine::with_parts(
                step_version2,
                wrong,
                decremented_coordinate,
            ));
            assert!(
                !report.is_proof(),
                "entry ({parity}, {key:03b}) flipped still proved"
            );
        }
    }
    // A decrement rule that forgets the hypotenuse move.
    let report = explore(&Machine::with_parts(step_version2, columns, no_move));
    assert!(!report.is_proof(), "{:?}", report.verdict);
}

/// A step that compares `u - v` (not a single remainder) with 1/2: the
/// transition must fail instead of trusting the fallback answer.
fn step_comparing_a_difference(walk: &mut Walk<Symbolic>) -> u8 {
    let _ = walk.u.minus(&walk.v).cmp_half();
    walk.step()
}

#[test]
fn undecided_comparisons_fail_the_construction() {
    let machine = Machine::with_parts(
        step_comparing_a_difference,
        machine().columns(),
        decremented_coordinate,
    );
    let report = explore(&machine);
    assert!(
        matches!(&report.verdict, Verdict::Failed(e) if e.0.contains("not a single remainder")),
        "{:?}",
        report.verdict
    );
}

#[test]
fn faces_of_points_match_the_lattice() {
    for level in 0..=4 {
        let level = Level::new(level).unwrap();
        for face in crate::lattice::faces(level) {
            assert_eq!(
                face_containing(face.x, face.y, level.get() + 2, level),
                face
            );
            // The same point at a finer scale.
            assert_eq!(
                face_containing(face.x * 8, face.y * 8, level.get() + 5, level),
                face
            );
        }
    }
}
