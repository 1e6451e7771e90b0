//! Symbolic numbers: the walk's arithmetic on affine forms, and the walk
//! transducer's state (the module docs, "The walk").

#[allow(clippy::wildcard_imports)]
use super::*;

/// `ru * R_u + rv * R_v + constant`, where `R_u`, `R_v` are the remainders
/// `frac(2^d u)`, `frac(2^d v)` at the walk's current depth `d`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Form {
    /// Coefficient of `R_u`.
    pub ru: i32,
    /// Coefficient of `R_v`.
    pub rv: i32,
    /// The constant term.
    pub constant: i32,
}

/// What one step's comparisons may look at: the remainders' sum at the
/// current depth and the next column (its bits and which remainders are
/// zero after it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct StepInput {
    /// `D(d)`.
    pub sum: u8,
    /// Column `d + 1`.
    pub next: Column,
}

/// A number of the walk as a [`Form`] plus the [`StepInput`] that decides
/// its comparisons. Implements [`WalkNumber`], so [`Walk::step`] runs on
/// it unchanged.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Symbolic {
    /// The value.
    pub form: Form,
    /// The information comparisons use.
    pub input: StepInput,
}

impl Form {
    fn combine(self, other: Form, sign: i32) -> Form {
        Form {
            ru: self.ru + sign * other.ru,
            rv: self.rv + sign * other.rv,
            constant: self.constant + sign * other.constant,
        }
    }

    /// The form as `sign * R_c + constant` for one coordinate `c` (using
    /// `R_u + R_v = D - R_w`), `None` if it is not of that shape. A
    /// constant form gives `(None, 0, constant)`.
    #[must_use]
    pub fn single_remainder(self, sum: u8) -> Option<(Option<usize>, i32, i32)> {
        match (self.ru, self.rv) {
            (0, 0) => Some((None, 0, self.constant)),
            (s @ (1 | -1), 0) => Some((Some(U), s, self.constant)),
            (0, s @ (1 | -1)) => Some((Some(V), s, self.constant)),
            (s @ (1 | -1), t) if s == t => Some((Some(W), -s, self.constant + s * i32::from(sum))),
            _ => None,
        }
    }

    /// `self` compared with `half_units / 2`, decided from the step input,
    /// or `None` if the form is not a single remainder (never the case for
    /// the walk's coordinates: they are barycentrics of a lattice triangle).
    ///
    /// With `self = s R(d) + k` and `2 R(d) = bit + R(d+1)`: `2 self` vs
    /// `half_units` is `s R(d+1)` vs `T = half_units - 2k - s bit`, and
    /// `R(d+1)` is 0 (zero flag) or strictly between 0 and 1.
    ///
    /// ```
    /// use micromap_index_lab::prove_all_levels::{Column, Form, Rest, StepInput};
    /// use std::cmp::Ordering;
    /// // w = 1 - R_u - R_v with R = (1/4, 1/4, 1/2) at depth 0: w = 1/2
    /// // exactly (w's next bit is 1 and nothing follows it).
    /// let input = StepInput {
    ///     sum: 1,
    ///     next: Column { bits: [false, false, true], rest: Rest { sum: 1, zero: [false, false, true] } },
    /// };
    /// let w = Form { ru: -1, rv: -1, constant: 1 };
    /// assert_eq!(w.compare_with_half_units(1, input), Some(Ordering::Equal));
    /// let u = Form { ru: 1, rv: 0, constant: 0 };
    /// assert_eq!(u.compare_with_half_units(1, input), Some(Ordering::Less));
    /// ```
    #[must_use]
    pub fn compare_with_half_units(self, half_units: i32, input: StepInput) -> Option<Ordering> {
        let (coordinate, sign, constant) = self.single_remainder(input.sum)?;
        let Some(c) = coordinate else {
            return Some((2 * constant).cmp(&half_units));
        };
        let bit = i32::from(input.next.bits[c]);
        let threshold = half_units - 2 * constant - sign * bit;
        if input.next.rest.zero[c] {
            return Some(0.cmp(&threshold));
        }
        // sign * R(d+1) lies strictly between 0 and sign.
        let (low, high) = if sign > 0 { (0, 1) } else { (-1, 0) };
        if threshold <= low {
            Some(Ordering::Greater)
        } else if threshold >= high {
            Some(Ordering::Less)
        } else {
            None
        }
    }

    /// The form at depth `d + 1`: substitutes `R(d) = (bit + R(d+1)) / 2`.
    /// `None` if a coefficient is odd (the value would not be affine in
    /// the next remainders with integer coefficients).
    #[must_use]
    pub fn advance(self, bits: [bool; 3]) -> Option<Form> {
        if self.ru % 2 != 0 || self.rv % 2 != 0 {
            return None;
        }
        let (ru, rv) = (self.ru / 2, self.rv / 2);
        Some(Form {
            ru,
            rv,
            constant: self.constant + ru * i32::from(bits[U]) + rv * i32::from(bits[V]),
        })
    }
}

impl Symbolic {
    fn with(self, form: Form) -> Symbolic {
        Symbolic {
            form,
            input: self.input,
        }
    }
}

thread_local! {
    /// Set by [`Symbolic::cmp_half`] when a comparison cannot be decided.
    pub(super) static UNDECIDED: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

impl WalkNumber for Symbolic {
    fn one_minus_sum(u: &Self, v: &Self) -> Self {
        let one = Form {
            ru: 0,
            rv: 0,
            constant: 1,
        };
        u.with(one.combine(u.form, -1).combine(v.form, -1))
    }
    fn twice(&self) -> Self {
        self.with(self.form.combine(self.form, 1))
    }
    fn plus(&self, other: &Self) -> Self {
        self.with(self.form.combine(other.form, 1))
    }
    fn minus(&self, other: &Self) -> Self {
        self.with(self.form.combine(other.form, -1))
    }
    /// Exact when the form is a single remainder. Otherwise it answers
    /// `Less` and records that a comparison was undecided, which makes
    /// [`Machine::transition`] fail: no step's outcome rests on a guess.
    fn cmp_half(&self) -> Ordering {
        self.form
            .compare_with_half_units(1, self.input)
            .unwrap_or_else(|| {
                UNDECIDED.with(|flag| flag.set(true));
                Ordering::Less
            })
    }
    /// Decided exactly for single-remainder forms (the root's `u`, `v`,
    /// `1 - u - v` are); a form that cannot be decided is reported outside.
    fn check_point(u: &Self, v: &Self) -> Result<(), Error> {
        let w = Symbolic::one_minus_sum(u, v);
        let sign = |x: &Symbolic| x.form.compare_with_half_units(0, x.input);
        let outside = |reason| Err(Error::OutsideTriangle { reason });
        match (sign(u), sign(v), sign(&w)) {
            (Some(Ordering::Less) | None, _, _) => outside(Outside::NegativeU),
            (_, Some(Ordering::Less) | None, _) => outside(Outside::NegativeV),
            (_, _, Some(Ordering::Less) | None) => outside(Outside::SumAboveOne),
            _ => Ok(()),
        }
    }
}

/// The walk transducer's state: the local coordinates as forms in the
/// current remainders, and the flags.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct WalkState {
    /// Local `u`.
    pub u: Form,
    /// Local `v`.
    pub v: Form,
    /// Local `w`.
    pub w: Form,
    /// [`Walk::mid_flip`].
    pub mid_flip: bool,
    /// [`Walk::top_flip`].
    pub top_flip: bool,
}

/// The bound on a form's constant beyond which the construction reports
/// an error instead of exploring an unbounded state space (the walk's
/// coordinates are barycentrics in `[0, 1]`, so their constants stay
/// small: the reached forms have constants in `-1..=1`).
pub(super) const CONSTANT_BOUND: i32 = 8;

/// One step of the walk on symbolic numbers.
pub type SymbolicStep = fn(&mut Walk<Symbolic>) -> u8;

pub(super) fn step_version2(walk: &mut Walk<Symbolic>) -> u8 {
    walk.step()
}

pub(super) fn step_version1(walk: &mut Walk<Symbolic>) -> u8 {
    internals::step_version1(walk)
}
