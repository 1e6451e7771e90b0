//! A proof for **every** level at once: the walk ([`Walk::step`], version 2)
//! equals the reference's steps (the integer half read with unbounded
//! words, i.e. [`spec::wide_index_from_cell`] for levels `0..=32` and
//! [`spec::index_from_cell`] for `0..=16`, after the exact first half) at
//! every real point of the closed triangle, for every subdivision level `n`.
//!
//! [`crate::prove`] checks one level at a time by enumerating faces. Here
//! both algorithms become finite-state transducers that read the binary
//! digits of the point, most significant first, and emit one index digit
//! per digit column; their product has finitely many reachable states, and
//! exploring it covers every level and every point in one finite search.
//! `docs/verification.md` (section 10) gives the argument step by step.
//!
//! # The input
//!
//! A dyadic point `u = X / 2^m`, `v = Y / 2^m` of the closed triangle, with
//! `Z = 2^m - X - Y >= 0` (so `w = Z / 2^m`), is written as `m + 1`
//! [`Column`]s `k = 0..=m`: the bits of `X`, `Y`, `Z` at position `m - k`
//! (column 0 is the integer part), each annotated with what the rest of
//! the number below it is: which of the three remainders
//! `R_c(k) = frac(2^k c)` are zero, and their sum `D(k)` (an integer, since
//! `2^k (u + v + w)` is one; at most 2). The annotations are a function of
//! the point; read top down they are a guess that the [`Rest`] automaton
//! checks column by column (`2 D(k-1) = bits + D(k)`) and at the end
//! (`D(m) = 0`, all remainders zero). So every accepted annotated word is
//! exactly one point and every point has exactly one accepted word.
//!
//! Every face of the level-`n` lattice contains a dyadic point with `m =
//! n + 2` (its representative, [`crate::lattice`]) and both algorithms are
//! constant on faces, so words of every length cover every real point.
//!
//! # The walk: the real step on symbolic numbers
//!
//! Before step `d + 1` each of the walk's local `u`, `v`, `w` is an affine
//! function of the remainders `R_u(d)`, `R_v(d)` with small integer
//! coefficients (a [`Form`]). [`Symbolic`] implements [`WalkNumber`] on
//! forms: `twice`, `plus`, `minus` are exact on the coefficients, and
//! `cmp_half` decides `form <=> 1/2` from the next column's bits and the
//! zero flags (a form in one remainder `s R + k`, `s = +-1`, compared with a
//! half integer: `2 R(d) = bit + R(d+1)` and `R(d+1)` is 0 or in `(0, 1)`).
//! The transition of the walk transducer *is* [`Walk::step`] (or
//! the talk's version 1, `internals::step_version1`) run on these numbers, followed by the change
//! of variables `R(d) = (bit + R(d+1)) / 2`. Nothing of the step is
//! restated.
//!
//! # The reference: learnt column table and one restated rule
//!
//! The reference's integer half turns its cell `(iu, iv, iw)` into digits
//! column by column from the top, carrying the parity of the Top digits
//! above (its prefix XOR). The table `(parity, u bit, v bit, w bit) ->
//! digit` is *learnt* from [`spec::wide_index_from_cell`] on every cell of
//! levels 1..=5 ([`ReferenceColumns::learn`]), and fails unless it is a
//! function. What is restated is how the reference's cell relates to the
//! point's digits: `(iu, iv, iw)` is the point's integer parts `(U, V, W)`
//! at level `n` with at most one of them decremented by one
//! ([`decremented_coordinate`], derived by hand from the clamps, the
//! hypotenuse move and the diagonal test in `docs/verification.md`).
//! Read from the top, "minus one" flips exactly the bits below which the
//! number's rest is zero, so the transducer guesses the decremented
//! coordinate at the start and the guess is checked where the level ends.
//! Both restatements are cross-checked against the real functions on every
//! face of levels 0..=12 (`tests/prove_all_levels.rs`).
//!
//! ```
//! use micromap_index_lab::prove::WalkVersion;
//! use micromap_index_lab::prove_all_levels::{prove_all_levels, Verdict};
//!
//! let report = prove_all_levels(WalkVersion::Version2).unwrap();
//! assert!(matches!(report.verdict, Verdict::Proved));
//!
//! // The talk's version 1 is refuted, with a concrete face.
//! let report = prove_all_levels(WalkVersion::Version1).unwrap();
//! let Verdict::Counterexample(example) = report.verdict else { panic!() };
//! assert_ne!(example.walk_index, example.reference_index);
//! ```

use crate::lattice::{Face, FaceKind};
use crate::prove::WalkVersion;
use core::cmp::Ordering;
use micromap_index::uv2index::{self, Walk, WalkNumber};
use micromap_index::{internals, spec, Error, Level, Outside};
use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet, VecDeque};
use std::fmt;

/// Index of `u` in the coordinate triples of this module.
pub const U: usize = 0;
/// Index of `v`.
pub const V: usize = 1;
/// Index of `w = 1 - u - v`.
pub const W: usize = 2;

/// The checker's state after column `k`: which remainders `R_c(k)` are zero
/// and their sum `D(k)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Rest {
    /// `D(k) = R_u(k) + R_v(k) + R_w(k)`, an integer in `0..=2`.
    pub sum: u8,
    /// `R_c(k) == 0` for `c` = `u`, `v`, `w`.
    pub zero: [bool; 3],
}

impl Rest {
    /// All 24 candidate values (`sum` in `0..=2`, any zero flags).
    fn all() -> impl Iterator<Item = Rest> {
        (0..=2u8).flat_map(|sum| {
            (0..8u8).map(move |z| Rest {
                sum,
                zero: [z & 1 != 0, z & 2 != 0, z & 4 != 0],
            })
        })
    }

    /// The accepting state: nothing left.
    const DONE: Rest = Rest {
        sum: 0,
        zero: [true; 3],
    };

    /// Whether `self` (after column `k - 1`) may be followed by the column
    /// with these bits and the rest `next` (after column `k`):
    /// `R(k-1) = (bit + R(k)) / 2` summed and tested for zero.
    ///
    /// ```
    /// use micromap_index_lab::prove_all_levels::Rest;
    /// // u = v = 1/4, w = 1/2: after the integer column the remainders are
    /// // (1/4, 1/4, 1/2), none zero, sum 1; after the next column (bits
    /// // 0, 0, 1) they are (1/2, 1/2, 0).
    /// let before = Rest { sum: 1, zero: [false; 3] };
    /// let after = Rest { sum: 1, zero: [false, false, true] };
    /// assert!(before.admits([false, false, true], after));
    /// assert!(!before.admits([true, false, false], after));
    /// ```
    #[must_use]
    pub fn admits(self, bits: [bool; 3], next: Rest) -> bool {
        let ones = bits.iter().filter(|&&b| b).count() as u8;
        2 * self.sum == ones + next.sum
            && (0..3).all(|c| self.zero[c] == (!bits[c] && next.zero[c]))
    }
}

/// One input column as the transducers see it: the bits of `X`, `Y`, `Z`
/// at this position and the checker's state after it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Column {
    /// Bits of `X`, `Y`, `Z`.
    pub bits: [bool; 3],
    /// The remainders below this column.
    pub rest: Rest,
}

/// Eight bit triples in a fixed order.
fn bit_triples() -> impl Iterator<Item = [bool; 3]> {
    (0..8u8).map(|b| [b & 1 != 0, b & 2 != 0, b & 4 != 0])
}

// ---------------------------------------------------------------------------
// Symbolic numbers: the walk's arithmetic on affine forms.

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
    static UNDECIDED: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
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
const CONSTANT_BOUND: i32 = 8;

/// One step of the walk on symbolic numbers.
pub type SymbolicStep = fn(&mut Walk<Symbolic>) -> u8;

fn step_version2(walk: &mut Walk<Symbolic>) -> u8 {
    walk.step()
}

fn step_version1(walk: &mut Walk<Symbolic>) -> u8 {
    internals::step_version1(walk)
}

// ---------------------------------------------------------------------------
// The reference transducer.

/// The reference's digit per column, learnt from the real integer half:
/// `digits[parity][u + 2 v + 4 w]`, `parity` the parity of the Top digits
/// (3) above the column.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReferenceColumns {
    /// The digit for each (parity of Top digits above, column bits).
    pub digits: [[u8; 8]; 2],
}

impl ReferenceColumns {
    /// Runs [`spec::wide_index_from_cell`] on every cell `(iu, iv)` with
    /// `iu + iv < 2^level` and both diagonal bits, levels 1..=5, and reads
    /// off, for every digit position, the digit against the parity of the
    /// Top digits above it and the column's bits of `(iu, iv, iw)`, where
    /// `iw = 2^level - 1 - iu - iv - [diagonal and iu + iv < 2^level - 1]`
    /// (the code's `~(iu + iv)` and decrement, restated for cells inside
    /// the grid, where no clamp applies). Fails unless every key is seen
    /// and always with one digit.
    ///
    /// ```
    /// use micromap_index_lab::prove_all_levels::ReferenceColumns;
    /// let columns = ReferenceColumns::learn().unwrap();
    /// // Column (u, v, w) bits 0, 0, 1 is Left: digit 0, or 2 below an odd
    /// // number of Top digits; 0, 1, 0 is Top (3) and flips the parity.
    /// assert_eq!(columns.digit(false, [false, false, true]), (0, false));
    /// assert_eq!(columns.digit(true, [false, false, true]), (2, true));
    /// assert_eq!(columns.digit(false, [false, true, false]), (3, true));
    /// ```
    pub fn learn() -> Result<ReferenceColumns, String> {
        let mut digits: [[Option<u8>; 8]; 2] = [[None; 8]; 2];
        for level in 1..=5u32 {
            let cells = 1u64 << level;
            for iu in 0..cells {
                for iv in 0..cells - iu {
                    for diagonal in [false, true] {
                        let decrement = u64::from(diagonal && iu + iv < cells - 1);
                        let iw = cells - 1 - iu - iv - decrement;
                        let index = spec::wide_index_from_cell(iu, iv, diagonal, level);
                        let mut parity = false;
                        for position in (0..level).rev() {
                            let digit = ((index >> (2 * position)) & 3) as u8;
                            let bit = |x: u64| ((x >> position) & 1) as usize;
                            let key = bit(iu) | bit(iv) << 1 | bit(iw) << 2;
                            let slot = &mut digits[usize::from(parity)][key];
                            if slot.is_some_and(|known| known != digit) {
                                return Err(format!(
                                    "reference digit is not a function of (parity, column): \
                                     cell ({iu}, {iv}, {diagonal}) level {level} position {position}"
                                ));
                            }
                            *slot = Some(digit);
                            parity ^= digit == 3;
                        }
                    }
                }
            }
        }
        let mut table = [[0; 8]; 2];
        for parity in 0..2 {
            for key in 0..8 {
                table[parity][key] = digits[parity][key].ok_or_else(|| {
                    format!("column (parity {parity}, bits {key:03b}) never seen")
                })?;
            }
        }
        Ok(ReferenceColumns { digits: table })
    }

    /// The digit for the column and the new parity.
    #[must_use]
    pub fn digit(&self, parity: bool, bits: [bool; 3]) -> (u8, bool) {
        let key = usize::from(bits[U]) | usize::from(bits[V]) << 1 | usize::from(bits[W]) << 2;
        let digit = self.digits[usize::from(parity)][key];
        (digit, parity ^ (digit == 3))
    }
}

/// The reference transducer's state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ReferenceState {
    /// Parity of the Top digits emitted so far (the prefix XOR).
    pub parity: bool,
    /// The guessed coordinate the reference's cell decrements (see
    /// [`decremented_coordinate`]).
    pub decremented: Option<usize>,
    /// `u == 0` (known from the first column and its rest).
    pub u_zero: bool,
    /// `w == 0`.
    pub w_zero: bool,
}

/// Which of the point's integer parts `(U, V, W) = floor(2^n (u, v, w))`
/// the reference's cell `(iu, iv, iw)` has one less of, from the rest
/// below level `n` and whether `u` or `w` is zero (restated by hand from
/// [`spec::wide_index_from_cell`]'s clamps, hypotenuse move and diagonal
/// test; `docs/verification.md` section 10.3 has the case analysis):
///
/// * `w`'s rest is zero and `w > 0` (vertices, and points on a line
///   `u + v = k/2^n` below the hypotenuse): `iw = W - 1`;
/// * `w = 0` and the point is a lattice vertex: `iu = U - 1` (the
///   hypotenuse move, and the clamp of `u = 1`), or `iv = V - 1` when
///   `u = 0` (the clamp of `v = 1`);
/// * otherwise the cell is `(U, V, W)`.
///
/// ```
/// use micromap_index_lab::prove_all_levels::{decremented_coordinate, U, V, W};
/// // A vertex below the hypotenuse: iw = W - 1.
/// assert_eq!(decremented_coordinate([true; 3], false, false), Some(W));
/// // The vertex u = 1 (w = 0): iu clamped to U - 1; v = 1 (u = 0 too): iv.
/// assert_eq!(decremented_coordinate([true; 3], false, true), Some(U));
/// assert_eq!(decremented_coordinate([true; 3], true, true), Some(V));
/// // Inside an upright micro-triangle: the cell is (U, V, W).
/// assert_eq!(decremented_coordinate([false; 3], false, false), None);
/// ```
#[must_use]
pub fn decremented_coordinate(rest_zero: [bool; 3], u_zero: bool, w_zero: bool) -> Option<usize> {
    if !w_zero && rest_zero[W] {
        Some(W)
    } else if w_zero && rest_zero[U] && rest_zero[V] {
        Some(if u_zero { V } else { U })
    } else {
        None
    }
}

/// The rule [`Machine`] uses for [`decremented_coordinate`].
pub type DecrementRule = fn([bool; 3], bool, bool) -> Option<usize>;

/// The reference's cell bits in one column: the point's bits with those
/// of the decremented coordinate flipped wherever its rest is zero (the
/// borrow of "minus one" runs up through the trailing zeros).
fn effective_bits(state: &ReferenceState, column: Column) -> [bool; 3] {
    std::array::from_fn(|c| column.bits[c] ^ (state.decremented == Some(c) && column.rest.zero[c]))
}

// ---------------------------------------------------------------------------
// The two transducers together.

/// Why the construction could not be carried out (a bug in a transducer
/// or an assumption of the method that does not hold).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ModelError(pub String);

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ModelError {}

/// A state of the product: checker, walk and reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ProductState {
    /// The remainders after the columns read so far.
    pub rest: Rest,
    /// The walk transducer.
    pub walk: WalkState,
    /// The reference transducer.
    pub reference: ReferenceState,
}

/// The first column (the integer bits) with its rest, and the reference's
/// guess: what a run starts from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Start {
    /// Integer bits of `u`, `v`, `w` and the rest after them.
    pub column: Column,
    /// The guessed decremented coordinate.
    pub decremented: Option<usize>,
}

/// The two transducers: the walk's step (the crate's, or a mutated one in
/// tests), the learnt reference columns and the decrement rule.
#[derive(Clone, Copy)]
pub struct Machine {
    step: SymbolicStep,
    columns: ReferenceColumns,
    rule: DecrementRule,
    version: Option<WalkVersion>,
}

impl fmt::Debug for Machine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Machine")
            .field("version", &self.version)
            .field("columns", &self.columns)
            .finish_non_exhaustive()
    }
}

impl Machine {
    /// The machine for one of the crate's walks.
    pub fn new(version: WalkVersion) -> Result<Machine, ModelError> {
        let step = match version {
            WalkVersion::Version2 => step_version2 as SymbolicStep,
            WalkVersion::Version1 => step_version1 as SymbolicStep,
        };
        let columns = ReferenceColumns::learn().map_err(ModelError)?;
        Ok(Machine {
            step,
            columns,
            rule: decremented_coordinate,
            version: Some(version),
        })
    }

    /// A machine with parts replaced (to show that the search rejects a
    /// wrong transducer); it has no real walk to check counterexamples with.
    #[must_use]
    pub fn with_parts(
        step: SymbolicStep,
        columns: ReferenceColumns,
        rule: DecrementRule,
    ) -> Machine {
        Machine {
            step,
            columns,
            rule,
            version: None,
        }
    }

    /// The learnt reference columns.
    #[must_use]
    pub fn columns(&self) -> ReferenceColumns {
        self.columns
    }

    /// The state a run starts in, or an error if the reference's cell
    /// would not fit the grid (its top column must be all zero).
    pub fn start(&self, start: Start) -> Result<ProductState, ModelError> {
        let Column { bits, rest } = start.column;
        let u_zero = !bits[U] && rest.zero[U];
        let w_zero = !bits[W] && rest.zero[W];
        let reference = ReferenceState {
            parity: false,
            decremented: start.decremented,
            u_zero,
            w_zero,
        };
        if effective_bits(&reference, start.column).iter().any(|&b| b) {
            return Err(ModelError(format!(
                "start {start:?}: the reference's cell has a bit at 2^level"
            )));
        }
        let root = |ru, rv, bit: bool| Symbolic {
            form: Form {
                ru,
                rv,
                constant: i32::from(bit),
            },
            // Not compared before the first step sets the input.
            input: StepInput {
                sum: rest.sum,
                next: start.column,
            },
        };
        let walk = Walk::new(root(1, 0, bits[U]), root(0, 1, bits[V]));
        Ok(ProductState {
            rest,
            walk: WalkState {
                u: walk.u.form,
                v: walk.v.form,
                w: walk.w.form,
                mid_flip: walk.mid_flip,
                top_flip: walk.top_flip,
            },
            reference,
        })
    }

    /// Whether a run in `state` may end its level here: the reference's
    /// guess is the right one for this rest.
    #[must_use]
    pub fn level_may_end(&self, state: &ReferenceState, rest: Rest) -> bool {
        (self.rule)(rest.zero, state.u_zero, state.w_zero) == state.decremented
    }

    /// One column: the walk's digit, the reference's digit and the next
    /// state. The column must be admitted by `state.rest` (not checked
    /// here).
    pub fn transition(
        &self,
        state: &ProductState,
        column: Column,
    ) -> Result<(u8, u8, ProductState), ModelError> {
        let input = StepInput {
            sum: state.rest.sum,
            next: column,
        };
        let fail = |why: &str| ModelError(format!("{state:?} column {column:?}: {why}"));
        let s = &state.walk;
        let symbolic = |form| Symbolic { form, input };
        let mut walk = Walk {
            u: symbolic(s.u),
            v: symbolic(s.v),
            w: symbolic(s.w),
            mid_flip: s.mid_flip,
            top_flip: s.top_flip,
        };
        UNDECIDED.with(|flag| flag.set(false));
        let walk_digit = (self.step)(&mut walk);
        if UNDECIDED.with(std::cell::Cell::get) {
            return Err(fail(
                "the step compared a form that is not a single remainder",
            ));
        }
        let advance = |x: Symbolic| {
            x.form
                .advance(column.bits)
                .filter(|f| {
                    f.ru.abs() <= 1 && f.rv.abs() <= 1 && f.constant.abs() <= CONSTANT_BOUND
                })
                .ok_or_else(|| fail(&format!("step result {:?} leaves the finite set", x.form)))
        };
        let walk_state = WalkState {
            u: advance(walk.u)?,
            v: advance(walk.v)?,
            w: advance(walk.w)?,
            mid_flip: walk.mid_flip,
            top_flip: walk.top_flip,
        };
        let effective = effective_bits(&state.reference, column);
        let (reference_digit, parity) = self.columns.digit(state.reference.parity, effective);
        Ok((
            walk_digit,
            reference_digit,
            ProductState {
                rest: column.rest,
                walk: walk_state,
                reference: ReferenceState {
                    parity,
                    ..state.reference
                },
            },
        ))
    }

    /// Runs both transducers on the dyadic point `(x, y) / 2^scale_log2`
    /// at `level`, with the annotations computed from the point: the
    /// automaton's answer for that point. Returns the two indices and the
    /// product states visited (after the start and after each column).
    ///
    /// ```
    /// use micromap_index_lab::prove::WalkVersion;
    /// use micromap_index_lab::prove_all_levels::Machine;
    /// use micromap_index::Level;
    /// let machine = Machine::new(WalkVersion::Version2).unwrap();
    /// // The vertex (1/4, 1/4) at level 2 (scale 4): index 5 by both.
    /// let run = machine.run_on_point(1, 1, 2, Level::new(2).unwrap()).unwrap();
    /// assert_eq!((run.walk_index, run.reference_index), (5, 5));
    /// ```
    pub fn run_on_point(
        &self,
        x: u128,
        y: u128,
        scale_log2: u32,
        level: Level,
    ) -> Result<PointRun, ModelError> {
        let columns = point_columns(x, y, scale_log2, level.get())?;
        let n = level.get() as usize;
        let at_level = columns[n].rest;
        let first = columns[0];
        // The guess a correct run makes: the rule at the level's rest.
        let u_zero = !first.bits[U] && first.rest.zero[U];
        let w_zero = !first.bits[W] && first.rest.zero[W];
        let decremented = (self.rule)(at_level.zero, u_zero, w_zero);
        let mut state = self.start(Start {
            column: first,
            decremented,
        })?;
        let mut states = vec![state];
        let (mut walk_index, mut reference_index) = (0u64, 0u64);
        for &column in &columns[1..=n] {
            if !state.rest.admits(column.bits, column.rest) {
                return Err(ModelError(format!(
                    "checker rejects the point's own column {column:?}"
                )));
            }
            let (walk_digit, reference_digit, next) = self.transition(&state, column)?;
            walk_index = walk_index << 2 | u64::from(walk_digit);
            reference_index = reference_index << 2 | u64::from(reference_digit);
            state = next;
            states.push(state);
        }
        if !self.level_may_end(&state.reference, state.rest) {
            return Err(ModelError(
                "the rule's own guess fails at the level end".into(),
            ));
        }
        Ok(PointRun {
            walk_index,
            reference_index,
            states,
        })
    }
}

/// What [`Machine::run_on_point`] computes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PointRun {
    /// The index from the walk transducer's digits.
    pub walk_index: u64,
    /// The index from the reference transducer's digits.
    pub reference_index: u64,
    /// The product states of the run, start first.
    pub states: Vec<ProductState>,
}

/// The annotated columns `0..=m` of `(x, y) / 2^scale_log2`, `m` raised to
/// `level` if smaller; the point must be in the closed triangle and `m <=
/// 120`.
fn point_columns(x: u128, y: u128, scale_log2: u32, level: u32) -> Result<Vec<Column>, ModelError> {
    let m = scale_log2.max(level);
    if m > 120 {
        return Err(ModelError(format!("scale 2^{m} is above 2^120")));
    }
    let shift = m - scale_log2;
    let (x, y) = (x << shift, y << shift);
    let one = 1u128 << m;
    if !matches!(x.checked_add(y), Some(sum) if sum <= one) {
        return Err(ModelError(format!(
            "({x}, {y}) / 2^{m} is outside the triangle"
        )));
    }
    let z = one - x - y;
    let values = [x, y, z];
    Ok((0..=m)
        .map(|k| {
            let below = m - k;
            let mask = (1u128 << below) - 1;
            let rem = values.map(|value| value & mask);
            Column {
                bits: values.map(|value| (value >> below) & 1 == 1),
                rest: Rest {
                    sum: ((rem[0] + rem[1] + rem[2]) >> below) as u8,
                    zero: rem.map(|r| r == 0),
                },
            }
        })
        .collect())
}

// ---------------------------------------------------------------------------
// The search.

/// The verdict of [`prove_all_levels`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// No reachable state of the product emits two different digits: the
    /// walk equals the reference at every point of every level.
    Proved,
    /// A reachable column where the digits differ, completed to a point and
    /// a level.
    Counterexample(Box<Counterexample>),
    /// A reachable state where a transducer cannot go on (see the message).
    Failed(ModelError),
}

/// A point and level where the walk and the reference differ, found by the
/// search and recomputed with the real functions.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Counterexample {
    /// The level.
    pub level: Level,
    /// The face of the level's lattice the point lies in (its
    /// representative point, kind).
    pub face: Face,
    /// The point found: `(x, y) / 2^scale_log2`.
    pub point: (u128, u128, u32),
    /// The walk transducer's index.
    pub walk_index: u64,
    /// The reference transducer's index.
    pub reference_index: u64,
    /// The real functions at the face's representative: the walk
    /// ([`uv2index::index_unchecked`] or `internals::index_version1_unchecked` on
    /// [`micromap_index::num::Fixed64`]) and [`spec::wide_index_dyadic`]. `None` for a mutated
    /// machine (no real walk to run).
    pub real: Option<(u64, u64)>,
}

/// Counts of what the search reached.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StateCounts {
    /// Checker states (remainder sum and zero flags) that can still end
    /// in a valid word.
    pub checker: usize,
    /// Checker x reference-guess states from which a level can end.
    pub live_guesses: usize,
    /// Distinct walk transducer states reached.
    pub walk: usize,
    /// Distinct reference transducer states reached.
    pub reference: usize,
    /// Product states reached.
    pub product: usize,
    /// Product transitions explored (each compares two digits).
    pub transitions: usize,
    /// Start states (first column and guess).
    pub starts: usize,
}

/// The outcome of [`prove_all_levels`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AllLevelsReport {
    /// The walk checked (`None` for a mutated machine).
    pub walk: Option<WalkVersion>,
    /// What was reached.
    pub counts: StateCounts,
    /// The verdict.
    pub verdict: Verdict,
    /// The walk transducer's reachable states, sorted (for the docs).
    pub walk_states: Vec<WalkState>,
    /// Every product state reached, in the order the search found them.
    pub product_states: Vec<ProductState>,
    /// Every transition compared, between indices of `product_states`.
    pub transitions: Vec<Transition>,
    /// The start of each state reached from a start (`None` for the others).
    pub starts: Vec<Option<Start>>,
}

/// One transition of the product: both transducers read `column` in state
/// `from` and emit `digit` (the same digit, or the search would have
/// stopped).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Transition {
    /// Index of the source state.
    pub from: usize,
    /// The column read.
    pub column: Column,
    /// The walk's digit.
    pub walk_digit: u8,
    /// The reference's digit.
    pub reference_digit: u8,
    /// Index of the target state.
    pub to: usize,
}

impl AllLevelsReport {
    /// Whether the walk is proved equal to the reference at every level.
    #[must_use]
    pub fn is_proof(&self) -> bool {
        self.verdict == Verdict::Proved
    }
}

/// The reference's guess state without the parity (which does not affect
/// whether a level can end).
type Guess = (Rest, Option<usize>, bool, bool);

/// Checker states from which the accepting state is reachable.
fn completable() -> BTreeSet<Rest> {
    let mut done: BTreeSet<Rest> = [Rest::DONE].into();
    loop {
        let before = done.len();
        for rest in Rest::all() {
            if !done.contains(&rest)
                && bit_triples().any(|bits| {
                    Rest::all().any(|next| done.contains(&next) && rest.admits(bits, next))
                })
            {
                done.insert(rest);
            }
        }
        if done.len() == before {
            return done;
        }
    }
}

/// The columns a state may read next whose rest can still be completed.
fn columns_after(rest: Rest, completable: &BTreeSet<Rest>) -> Vec<Column> {
    bit_triples()
        .flat_map(|bits| Rest::all().map(move |next| Column { bits, rest: next }))
        .filter(|column| {
            completable.contains(&column.rest) && rest.admits(column.bits, column.rest)
        })
        .collect()
}

/// The guess states from which a level end (the rule holds and the rest is
/// completable) is reachable, and a shortest continuation for each.
struct Liveness {
    /// For each live guess state: the columns to a level end (empty if it
    /// may end now).
    to_end: BTreeMap<Guess, Vec<Column>>,
}

impl Liveness {
    fn build(machine: &Machine, completable: &BTreeSet<Rest>) -> Liveness {
        let guesses: Vec<Guess> = completable
            .iter()
            .flat_map(|&rest| {
                [None, Some(U), Some(V), Some(W)]
                    .into_iter()
                    .flat_map(move |g| {
                        [(false, false), (false, true), (true, false), (true, true)]
                            .map(|(uz, wz)| (rest, g, uz, wz))
                    })
            })
            .collect();
        let may_end = |&(rest, g, u_zero, w_zero): &Guess| {
            let state = ReferenceState {
                parity: false,
                decremented: g,
                u_zero,
                w_zero,
            };
            machine.level_may_end(&state, rest)
        };
        let mut to_end: BTreeMap<Guess, Vec<Column>> = guesses
            .iter()
            .filter(|g| may_end(g))
            .map(|&g| (g, Vec::new()))
            .collect();
        // Backward breadth-first: each round adds the states one column
        // further from an end, so the recorded continuations are shortest.
        loop {
            let mut added = Vec::new();
            for &guess in &guesses {
                if to_end.contains_key(&guess) {
                    continue;
                }
                let (rest, g, uz, wz) = guess;
                if let Some((column, tail)) = columns_after(rest, completable)
                    .into_iter()
                    .find_map(|c| to_end.get(&(c.rest, g, uz, wz)).map(|t| (c, t)))
                {
                    let mut path = vec![column];
                    path.extend_from_slice(tail);
                    added.push((guess, path));
                }
            }
            if added.is_empty() {
                return Liveness { to_end };
            }
            to_end.extend(added);
        }
    }

    fn is_live(&self, state: &ProductState) -> bool {
        let r = &state.reference;
        self.to_end
            .contains_key(&(state.rest, r.decremented, r.u_zero, r.w_zero))
    }
}

/// How a product state was first reached.
#[derive(Clone, Copy)]
enum Parent {
    Start(Start),
    Column(usize, Column),
}

/// Explores the product of the walk and reference transducers for one of
/// the crate's walks. `Verdict::Proved` means: for every level `n` and
/// every real point of the closed triangle, the walk equals the reference
/// (see the module docs for what is restated and how it is checked).
pub fn prove_all_levels(version: WalkVersion) -> Result<AllLevelsReport, ModelError> {
    Ok(explore(&Machine::new(version)?))
}

/// Explores the product for any machine (also a mutated one).
#[must_use]
pub fn explore(machine: &Machine) -> AllLevelsReport {
    let completable = completable();
    let liveness = Liveness::build(machine, &completable);
    let mut ids: HashMap<ProductState, usize> = HashMap::new();
    let mut states: Vec<ProductState> = Vec::new();
    let mut parents: Vec<Parent> = Vec::new();
    let mut queue = VecDeque::new();
    let mut counts = StateCounts {
        checker: completable.len(),
        live_guesses: liveness.to_end.len(),
        ..StateCounts::default()
    };
    let mut transitions: Vec<Transition> = Vec::new();
    let finish = |counts: StateCounts,
                  states: &[ProductState],
                  parents: &[Parent],
                  transitions: Vec<Transition>,
                  verdict| {
        let walks: HashSet<WalkState> = states.iter().map(|s| s.walk).collect();
        let references: HashSet<ReferenceState> = states.iter().map(|s| s.reference).collect();
        let mut walk_states: Vec<WalkState> = walks.into_iter().collect();
        walk_states.sort();
        AllLevelsReport {
            walk: machine.version,
            counts: StateCounts {
                walk: walk_states.len(),
                reference: references.len(),
                product: states.len(),
                ..counts
            },
            verdict,
            walk_states,
            product_states: states.to_vec(),
            transitions,
            starts: parents
                .iter()
                .map(|p| match p {
                    Parent::Start(start) => Some(*start),
                    Parent::Column(..) => None,
                })
                .collect(),
        }
    };
    for bits in bit_triples() {
        for rest in Rest::all() {
            let ones = bits.iter().filter(|&&b| b).count() as u8;
            if ones + rest.sum != 1 || !completable.contains(&rest) {
                continue;
            }
            for decremented in [None, Some(U), Some(V), Some(W)] {
                let start = Start {
                    column: Column { bits, rest },
                    decremented,
                };
                let u_zero = !bits[U] && rest.zero[U];
                let w_zero = !bits[W] && rest.zero[W];
                if !liveness
                    .to_end
                    .contains_key(&(rest, decremented, u_zero, w_zero))
                {
                    continue;
                }
                counts.starts += 1;
                let state = match machine.start(start) {
                    Ok(state) => state,
                    Err(e) => {
                        return finish(counts, &states, &parents, transitions, Verdict::Failed(e))
                    }
                };
                if let std::collections::hash_map::Entry::Vacant(slot) = ids.entry(state) {
                    slot.insert(states.len());
                    queue.push_back(states.len());
                    states.push(state);
                    parents.push(Parent::Start(start));
                }
            }
        }
    }
    while let Some(id) = queue.pop_front() {
        let state = states[id];
        for column in columns_after(state.rest, &completable) {
            let probe = ProductState {
                rest: column.rest,
                ..state
            };
            if !liveness.is_live(&probe) {
                continue; // no valid word goes on from here to a level end
            }
            counts.transitions += 1;
            let (walk_digit, reference_digit, next) = match machine.transition(&state, column) {
                Ok(step) => step,
                Err(e) => {
                    let path = path_to(&parents, id);
                    let why = format!("{e}; reached by {}", describe_path(&path, column));
                    let verdict = Verdict::Failed(ModelError(why));
                    return finish(counts, &states, &parents, transitions, verdict);
                }
            };
            if walk_digit != reference_digit {
                let verdict = counterexample(
                    machine,
                    &liveness,
                    &completable,
                    &parents,
                    id,
                    column,
                    &next,
                );
                return finish(counts, &states, &parents, transitions, verdict);
            }
            let to = *ids.entry(next).or_insert_with(|| {
                queue.push_back(states.len());
                states.push(next);
                parents.push(Parent::Column(id, column));
                states.len() - 1
            });
            transitions.push(Transition {
                from: id,
                column,
                walk_digit,
                reference_digit,
                to,
            });
        }
    }
    finish(counts, &states, &parents, transitions, Verdict::Proved)
}

/// The start and the columns that first reached state `id`.
fn path_to(parents: &[Parent], mut id: usize) -> (Start, Vec<Column>) {
    let mut columns = Vec::new();
    loop {
        match parents[id] {
            Parent::Start(start) => {
                columns.reverse();
                return (start, columns);
            }
            Parent::Column(parent, column) => {
                columns.push(column);
                id = parent;
            }
        }
    }
}

fn describe_path((start, columns): &(Start, Vec<Column>), last: Column) -> String {
    let bits = |b: [bool; 3]| {
        b.map(|x| char::from(b'0' + u8::from(x)))
            .iter()
            .collect::<String>()
    };
    let mut text = format!(
        "start {} guess {:?}",
        bits(start.column.bits),
        start.decremented
    );
    for column in columns.iter().chain([&last]) {
        text.push(' ');
        text.push_str(&bits(column.bits));
    }
    text
}

/// Completes the differing column to a point and a level, and recomputes
/// it with the transducers and the real functions.
fn counterexample(
    machine: &Machine,
    liveness: &Liveness,
    completable: &BTreeSet<Rest>,
    parents: &[Parent],
    id: usize,
    column: Column,
    next: &ProductState,
) -> Verdict {
    let (start, mut columns) = path_to(parents, id);
    columns.push(column);
    let r = &next.reference;
    let Some(to_end) = liveness
        .to_end
        .get(&(next.rest, r.decremented, r.u_zero, r.w_zero))
    else {
        return Verdict::Failed(ModelError("a live state has no way to a level end".into()));
    };
    columns.extend_from_slice(to_end);
    let level = columns.len() as u32;
    // Then finish the digits of the point: a shortest way to nothing left.
    let mut rest = columns.last().map_or(start.column.rest, |c| c.rest);
    while rest != Rest::DONE {
        let Some(step) = columns_after(rest, completable)
            .into_iter()
            .min_by_key(|c| distance_to_done(c.rest, completable))
        else {
            return Verdict::Failed(ModelError("a completable rest cannot be completed".into()));
        };
        columns.push(step);
        rest = step.rest;
    }
    let m = columns.len() as u32;
    let value = |c: usize| {
        std::iter::once(start.column)
            .chain(columns.iter().copied())
            .fold(0u128, |acc, col| acc << 1 | u128::from(col.bits[c]))
    };
    let (x, y, z) = (value(U), value(V), value(W));
    let Ok(level) = Level::new(level) else {
        return Verdict::Failed(ModelError(format!("counterexample at level {level} > 32")));
    };
    if m > 60 || x + y + z != 1u128 << m {
        return Verdict::Failed(ModelError(format!(
            "counterexample ({x}, {y}, {z}) / 2^{m} does not check"
        )));
    }
    let run = match machine.run_on_point(x, y, m, level) {
        Ok(run) => run,
        Err(e) => return Verdict::Failed(e),
    };
    if run.walk_index == run.reference_index {
        return Verdict::Failed(ModelError(format!(
            "the search's counterexample ({x}, {y}) / 2^{m} at level {} agrees when rerun",
            level.get()
        )));
    }
    let face = face_containing(x as u64, y as u64, m, level);
    let real = match machine.version.map(|version| real_indices(version, &face)) {
        Some(Err(e)) => return Verdict::Failed(ModelError(format!("real functions: {e}"))),
        Some(Ok(real)) => Some(real),
        None => None,
    };
    Verdict::Counterexample(Box::new(Counterexample {
        level,
        face,
        point: (x, y, m),
        walk_index: run.walk_index,
        reference_index: run.reference_index,
        real,
    }))
}

/// Columns needed to reach [`Rest::DONE`] (for the shortest completion).
fn distance_to_done(from: Rest, completable: &BTreeSet<Rest>) -> usize {
    let mut frontier = vec![from];
    let mut seen: HashSet<Rest> = [from].into();
    for distance in 0..=completable.len() {
        if frontier.contains(&Rest::DONE) {
            return distance;
        }
        frontier = frontier
            .iter()
            .flat_map(|&rest| columns_after(rest, completable))
            .map(|c| c.rest)
            .filter(|rest| seen.insert(*rest))
            .collect();
    }
    usize::MAX
}

/// The real walk and the real reference at the face's representative
/// (an error only for a face finer than `spec::MAX_SCALE_LOG2`, above
/// level 60).
pub fn real_indices(version: WalkVersion, face: &Face) -> Result<(u64, u64), Error> {
    let (u, v) = face.to_fixed64();
    let walk = match version {
        WalkVersion::Version2 => uv2index::index_unchecked(u, v, face.level),
        WalkVersion::Version1 => internals::index_version1_unchecked(u, v, face.level),
    };
    let reference = spec::wide_index_dyadic(face.x, face.y, face.scale_log2(), face.level)?;
    Ok((walk, reference))
}

/// The face of the level's lattice holding the point `(x, y) /
/// 2^scale_log2` of the closed triangle (`scale_log2 <= 62`), as
/// [`crate::lattice::faces`] names it.
///
/// ```
/// use micromap_index_lab::lattice::FaceKind;
/// use micromap_index_lab::prove_all_levels::face_containing;
/// use micromap_index::Level;
/// let level = Level::new(2).unwrap();
/// // (1/16, 1/16): inside the upright micro-triangle of cell (0, 0) ...
/// let face = face_containing(1, 1, 4, level);
/// assert_eq!((face.x, face.y, face.kind), (1, 1, FaceKind::Upright));
/// // ... (3/16, 1/16): on its diagonal edge u + v = 1/4.
/// let face = face_containing(3, 1, 4, level);
/// assert_eq!((face.x, face.y, face.kind), (2, 2, FaceKind::DiagonalEdge));
/// ```
#[must_use]
pub fn face_containing(x: u64, y: u64, scale_log2: u32, level: Level) -> Face {
    let n = level.get();
    let (x, y, m) = if scale_log2 < n {
        (x << (n - scale_log2), y << (n - scale_log2), n)
    } else {
        (x, y, scale_log2)
    };
    let below = m - n;
    let unit = 1u64 << below;
    let (a, b) = (x >> below, y >> below);
    let (ru, rv) = (x & (unit - 1), y & (unit - 1));
    let kind = match (ru == 0, rv == 0) {
        (true, true) => FaceKind::Vertex,
        (true, false) => FaceKind::VerticalEdge,
        (false, true) => FaceKind::HorizontalEdge,
        _ => match (ru + rv).cmp(&unit) {
            Ordering::Equal => FaceKind::DiagonalEdge,
            Ordering::Less => FaceKind::Upright,
            Ordering::Greater => FaceKind::UpsideDown,
        },
    };
    let (dx, dy) = kind.offset();
    Face {
        level,
        x: 4 * a + dx,
        y: 4 * b + dy,
        kind,
    }
}

/// The point's value as `x / 2^scale_log2` (for messages).
fn fraction(numerator: u128, scale_log2: u32) -> String {
    let shift = numerator.trailing_zeros().min(scale_log2);
    let (numerator, scale) = (numerator >> shift, scale_log2 - shift);
    if scale == 0 {
        numerator.to_string()
    } else {
        format!("{numerator}/{}", 1u128 << scale)
    }
}

impl Counterexample {
    /// `u`, `v` of the face's representative as exact fractions.
    #[must_use]
    pub fn representative(&self) -> (String, String) {
        let scale = self.face.scale_log2();
        (
            fraction(u128::from(self.face.x), scale),
            fraction(u128::from(self.face.y), scale),
        )
    }
}

// ---------------------------------------------------------------------------
// Printing (for `micromap-index prove --all-levels --list` and the docs).

impl fmt::Display for Rest {
    /// `D1 z=u-v` lists the sum and the coordinates whose rest is zero.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "D{} z={}", self.sum, coordinate_list(self.zero))
    }
}

/// The names of the coordinates with a flag set, `-` for none.
fn coordinate_list(flags: [bool; 3]) -> String {
    let names: String = ["u", "v", "w"]
        .iter()
        .zip(flags)
        .filter(|(_, set)| *set)
        .map(|(name, _)| *name)
        .collect();
    if names.is_empty() {
        "-".into()
    } else {
        names
    }
}

impl fmt::Display for Column {
    /// `bits uvw=010 then D1 z=u`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let bits: String = self
            .bits
            .iter()
            .map(|&b| if b { '1' } else { '0' })
            .collect();
        write!(f, "bits {bits} then {}", self.rest)
    }
}

impl fmt::Display for Form {
    /// `1 - Ru - Rv` style.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut text = String::new();
        for (coefficient, name) in [(self.constant, ""), (self.ru, "Ru"), (self.rv, "Rv")] {
            if coefficient == 0 {
                continue;
            }
            let sign = if coefficient < 0 { "-" } else { "+" };
            let magnitude = coefficient.abs();
            let term = match (magnitude, name) {
                (m, "") => m.to_string(),
                (1, n) => n.to_string(),
                (m, n) => format!("{m}{n}"),
            };
            if text.is_empty() {
                text = if coefficient < 0 {
                    format!("-{term}")
                } else {
                    term
                };
            } else {
                text.push(' ');
                text.push_str(sign);
                text.push(' ');
                text.push_str(&term);
            }
        }
        if text.is_empty() {
            text.push('0');
        }
        f.write_str(&text)
    }
}

impl fmt::Display for WalkState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "u={}, v={}, w={}", self.u, self.v, self.w)?;
        match (self.mid_flip, self.top_flip) {
            (false, false) => Ok(()),
            (true, false) => f.write_str(", mid_flip"),
            (false, true) => f.write_str(", top_flip"),
            (true, true) => f.write_str(", mid_flip, top_flip"),
        }
    }
}

impl fmt::Display for ReferenceState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let guess = self.decremented.map_or("-", |c| ["u", "v", "w"][c]);
        write!(
            f,
            "parity {}, minus one on {guess}, zero: {}",
            u8::from(self.parity),
            coordinate_list([self.u_zero, false, self.w_zero])
        )
    }
}

impl AllLevelsReport {
    /// Every state and transition of the product, one per line (what
    /// `micromap-index prove --all-levels --list` prints).
    #[must_use]
    pub fn listing(&self) -> Vec<String> {
        let mut lines = Vec::new();
        for (id, state) in self.product_states.iter().enumerate() {
            let start = match self.starts.get(id).copied().flatten() {
                Some(start) => format!("  <- start: integer {}", start.column),
                None => String::new(),
            };
            lines.push(format!(
                "S{id}: {} | {} | {}{start}",
                state.rest, state.walk, state.reference
            ));
        }
        for t in &self.transitions {
            lines.push(format!(
                "S{} --[{}]--> S{}  digits walk {} reference {}",
                t.from, t.column, t.to, t.walk_digit, t.reference_digit
            ));
        }
        lines
    }
}

#[cfg(test)]
mod tests {
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
}
