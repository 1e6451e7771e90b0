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

/// The reference's cell steps without the hypotenuse move (a mutant of
/// `internals::reference_cell`, for the derivation).
fn cell_without_move(
    iu: CellForm,
    iv: CellForm,
    diagonal: bool,
    level: u32,
) -> (CellForm, CellForm, CellForm) {
    use micromap_index::internals::ReferenceWord;
    let one = CellForm::constant(1);
    let cells = CellForm::power_of_two(level);
    let last = cells.wrapping_sub(one);
    let (mut iu, mut iv) = (iu, iv);
    if iu.at_least(cells) {
        iu = last;
    }
    if iv.at_least(cells) {
        iv = last;
    }
    let iuv = iu.wrapping_add(iv);
    let mut iw = iu.wrapping_add(iv).complement();
    if diagonal && !iuv.at_least(last) {
        iw = iw.wrapping_sub(one);
    }
    (iu, iv, iw)
}

#[test]
fn mutated_transducers_are_rejected() {
    let columns = machine().columns();
    for step in [step_without_tie_rule as SymbolicStep, step_without_top_flip] {
        let report = explore(&Machine::with_parts(step, columns, machine().rule()));
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
            let report = explore(&Machine::with_parts(step_version2, wrong, machine().rule()));
            assert!(
                !report.is_proof(),
                "entry ({parity}, {key:03b}) flipped still proved"
            );
        }
    }
    // The reference's cell code without the hypotenuse move: the
    // derivation refuses it (the hypotenuse vertex's cell reaches 2^level).
    let derived = derive_cell_rule(cell_without_move, REFERENCE_DIAGONAL);
    assert!(
        matches!(&derived, Err(e) if e.contains("not the point's integer part")),
        "{derived:?}"
    );
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
        machine().rule(),
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

/// A search that prunes too much (here: never follows a column whose bits
/// are all one, which only vertices and the corners need) still finds no
/// differing digit, but [`prove_all_levels`]'s certification refuses it:
/// some face of levels 0..=8 reads a transition it did not explore.
#[test]
fn an_over_pruning_search_is_refused() {
    let machine = machine();
    let pruned = explore_pruned(&machine, |_, column| column.bits == [true; 3]);
    assert_eq!(pruned.verdict, Verdict::Proved, "the pruned search alone");
    assert!(pruned.transitions.len() < 106);
    let certified = certify(&machine, pruned, COMMITTED_LISTING);
    assert!(
        matches!(&certified.verdict, Verdict::Failed(e) if e.0.contains("did not explore the whole product")),
        "{:?}",
        certified.verdict
    );
    // Pruning a single transition is caught too.
    let full = explore(&machine);
    let first = full.transitions[full.transitions.len() - 1];
    let from = full.product_states[first.from];
    let pruned = explore_pruned(&machine, |state, column| {
        *state == from && *column == first.column
    });
    assert_eq!(pruned.transitions.len(), 105);
    assert!(!certify(&machine, pruned, COMMITTED_LISTING).is_proof());
}

#[test]
fn the_committed_listing_is_checked() {
    let machine = machine();
    let report = certify(&machine, explore(&machine), COMMITTED_LISTING);
    assert_eq!(report.verdict, Verdict::Proved);
    // One changed digit in the committed text: refused, with the line.
    let altered =
        COMMITTED_LISTING.replacen("digits walk 0 reference 0", "digits walk 1 reference 1", 1);
    assert_ne!(altered, COMMITTED_LISTING);
    let report = certify(&machine, explore(&machine), &altered);
    assert!(
        matches!(&report.verdict, Verdict::Failed(e) if e.0.contains("differs from the committed")),
        "{:?}",
        report.verdict
    );
    // A missing line as well.
    let shorter = COMMITTED_LISTING
        .lines()
        .filter(|l| !l.starts_with("S33:"))
        .collect::<Vec<_>>()
        .join("\n");
    assert!(!certify(&machine, explore(&machine), &shorter).is_proof());
}

/// The cell rule derived from the code is the case analysis of
/// `docs/verification.md` section 10.3 (kept here as the test's oracle).
#[test]
fn derived_cell_rule_is_the_documented_case_analysis() {
    let rule = derive_cell_rule(REFERENCE_CELL, REFERENCE_DIAGONAL).unwrap();
    let documented = |zero: [bool; 3], u_zero: bool, w_zero: bool| {
        if !w_zero && zero[W] {
            Some(W)
        } else if w_zero && zero[U] && zero[V] {
            Some(if u_zero { V } else { U })
        } else {
            None
        }
    };
    let mut reachable = 0;
    for rest in search::completable() {
        for (u_zero, w_zero) in [(false, false), (false, true), (true, false), (true, true)] {
            match rule.outcome(rest, u_zero, w_zero) {
                CellOutcome::Decrement(d) => {
                    reachable += 1;
                    assert_eq!(
                        d,
                        documented(rest.zero, u_zero, w_zero),
                        "{rest:?} {u_zero} {w_zero}"
                    );
                }
                CellOutcome::Unreachable => {
                    // u == 0 needs u's rest zero, w == 0 needs w's; both
                    // mean v = 1, nothing left.
                    assert!(
                        (u_zero && !rest.zero[U])
                            || (w_zero && !rest.zero[W])
                            || (u_zero && w_zero && rest.sum > 0),
                        "{rest:?} {u_zero} {w_zero}"
                    );
                }
            }
        }
    }
    assert!(reachable >= 10, "{reachable}");
}

/// Mutants of the reference's cell code (copies of
/// `internals::reference_cell` with one change): each is refused by the
/// derivation or changes the derived rule.
fn cell_mutant(
    iu: CellForm,
    iv: CellForm,
    diagonal: bool,
    level: u32,
    mutant: u8,
) -> (CellForm, CellForm, CellForm) {
    use micromap_index::internals::ReferenceWord;
    let one = CellForm::constant(1);
    let cells = CellForm::power_of_two(level);
    let last = cells.wrapping_sub(one);
    let (mut iu, mut iv) = (iu, iv);
    if iu.at_least(cells) {
        iu = last;
    }
    if iv.at_least(cells) {
        iv = last;
    }
    let iuv = iu.wrapping_add(iv);
    let moves = match mutant {
        // `>` instead of `>=`.
        1 => !cells.at_least(iuv),
        // Switched off from level 20 on.
        2 => level < 20 && iuv.at_least(cells),
        _ => iuv.at_least(cells),
    };
    if moves {
        iu = iu.wrapping_sub(iuv.wrapping_sub(cells).wrapping_add(one));
    }
    let mut iw = iu.wrapping_add(iv).complement();
    // 3: the decrement on `<=` instead of `<`.
    let decrements = || {
        if mutant == 3 {
            last.at_least(iuv)
        } else {
            !iuv.at_least(last)
        }
    };
    if diagonal && decrements() {
        iw = iw.wrapping_sub(one);
    }
    (iu, iv, iw)
}

#[test]
fn mutants_of_the_reference_cell_are_caught() {
    let real = machine().rule();
    assert_eq!(cell_mutant_rule(0), Ok(real));
    for mutant in 1..=3 {
        let derived = cell_mutant_rule(mutant);
        assert!(
            derived.as_ref() != Ok(&real),
            "mutant {mutant} derives the real rule"
        );
        if let Ok(rule) = derived {
            let report = explore(&Machine::with_parts(
                step_version2,
                machine().columns(),
                rule,
            ));
            assert!(!report.is_proof(), "mutant {mutant} proved");
        }
    }
    // A diagonal test on `>=` (a mutant of `fractions_reach_one`).
    let derived = derive_cell_rule(REFERENCE_CELL, diagonal_at_least);
    assert!(derived.as_ref() != Ok(&real), "{derived:?}");
}

/// `uf + vf >= mask` instead of `>`: a mutant of `fractions_reach_one`.
fn diagonal_at_least(uf: FractionForm, vf: FractionForm, mask: FractionForm) -> bool {
    use micromap_index::internals::ReferenceWord;
    uf.wrapping_add(vf).at_least(mask)
}

fn cell_mutant_rule(mutant: u8) -> Result<CellRule, String> {
    let code: [CellCode; 4] = [
        |iu, iv, d, l| cell_mutant(iu, iv, d, l, 0),
        |iu, iv, d, l| cell_mutant(iu, iv, d, l, 1),
        |iu, iv, d, l| cell_mutant(iu, iv, d, l, 2),
        |iu, iv, d, l| cell_mutant(iu, iv, d, l, 3),
    ];
    derive_cell_rule(code[usize::from(mutant)], REFERENCE_DIAGONAL)
}

/// The column table holds for the 64-bit code at every level 0..=32 and
/// the 32-bit code at 0..=16; the 32-bit code is refuted at 17 (its 16-bit
/// prefix XOR and interleave), and so is a 64-bit code whose prefix XOR
/// stops at 16 bits.
#[test]
fn integer_half_verified_symbolically_with_negative_controls() {
    let columns = machine().columns();
    verify_columns(&columns).unwrap();
    let refuted = verify_columns_at(&columns, NARROW, 17);
    assert!(
        matches!(&refuted, Err(e) if e.contains("32-bit integer half at level 17")),
        "{refuted:?}"
    );
    let window16 = Width {
        prefix_xor: &[1, 2, 4, 8],
        ..WIDE
    };
    for level in 0..=16 {
        verify_columns_at(&columns, window16, level).unwrap();
    }
    assert!(verify_columns_at(&columns, window16, 17).is_err());
    // A wrong table entry is refused at level 1 already.
    let mut wrong = columns;
    wrong.digits[0][1] ^= 2;
    assert!(verify_columns_at(&wrong, WIDE, 1).is_err());
}
