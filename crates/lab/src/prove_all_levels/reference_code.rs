//! The reference transducer derived from the reference's code: the
//! crate's own generic steps ([`internals::reference_cell`],
//! [`internals::fractions_reach_one`], [`internals::reference_digits`]) run
//! on symbolic words (the module docs, "The reference";
//! `docs/verification.md`, section 10.3).
//!
//! * [`CellForm`]: the cell's coordinates as affine forms in the point's
//!   integer parts `U`, `V`, `W` at the level and `N = 2^level`, with the
//!   comparisons decided from what a level end knows ([`CellCase`]).
//!   [`derive_cell_rule`] runs the clamps, the hypotenuse move, `~(iu +
//!   iv)` and the diagonal decrement on them, for every case and every level
//!   `0..=32`, and reads off which coordinate the cell has one less of.
//! * [`FractionForm`]: the fractions below the level, for the dyadic
//!   diagonal test.
//! * [`AnfWord`]: words whose bits are polynomials over GF(2) in the cell's
//!   bits; [`verify_columns`] runs the integer half's bit steps on them at
//!   every level `0..=32` (64-bit code) and `0..=16` (32-bit code) and checks
//!   every digit against the column table.
//!
//! One file, past 800 lines on purpose: the three symbolic word types share
//! the thread-local failure and case state below and are run through the
//! same generic reference code; split apart, each file would import the
//! others' state (an import circle) for no reader's gain.

#[allow(clippy::wildcard_imports)]
use super::*;
use micromap_index::internals::{self as code, ReferenceWord};
use std::cell::RefCell;
use std::rc::Rc;

thread_local! {
    /// The first operation a symbolic word could not carry out.
    static FAILURE: RefCell<Option<String>> = const { RefCell::new(None) };
    /// The case the cell forms are decided in.
    static CASE: std::cell::Cell<Option<CellCase>> = const { std::cell::Cell::new(None) };
}

fn fail(why: &str) {
    FAILURE.with(|f| {
        f.borrow_mut().get_or_insert_with(|| why.to_string());
    });
}

fn take_failure() -> Option<String> {
    FAILURE.with(|f| f.borrow_mut().take())
}

// ---------------------------------------------------------------------
// The cell: affine forms in U, V, W, N.

/// What a level end knows about the point, refined: the rest below the
/// level and which of the integer parts `(U, V, W) = floor(2^n (u, v, w))`
/// are zero. With `N = 2^n`, `U + V + W + D = N`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CellCase {
    /// The rest at the level.
    pub rest: Rest,
    /// `U == 0`, `V == 0`, `W == 0`.
    pub integer_zero: [bool; 3],
}

impl CellCase {
    /// Whether the coordinate itself is zero (its integer part and its rest).
    #[must_use]
    pub fn value_zero(&self, c: usize) -> bool {
        self.integer_zero[c] && self.rest.zero[c]
    }
}

fn case() -> CellCase {
    CASE.with(std::cell::Cell::get)
        .expect("a cell form is only used inside derive_cell_rule")
}

/// `coefficient . (U, V, W) + n N + constant`, an integer; `modular` if
/// the value is only known modulo `N` (after a complement, `~x = -1 - x`
/// on the word).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CellForm {
    /// Coefficients of `U`, `V`, `W`.
    pub coefficient: [i64; 3],
    /// Coefficient of `N`.
    pub n: i64,
    /// The constant term.
    pub constant: i64,
    /// Known only modulo `N`.
    pub modular: bool,
}

impl CellForm {
    fn variable(c: usize) -> CellForm {
        let mut coefficient = [0; 3];
        coefficient[c] = 1;
        CellForm {
            coefficient,
            n: 0,
            constant: 0,
            modular: false,
        }
    }

    fn combine(self, other: CellForm, sign: i64) -> CellForm {
        CellForm {
            coefficient: std::array::from_fn(|c| self.coefficient[c] + sign * other.coefficient[c]),
            n: self.n + sign * other.n,
            constant: self.constant + sign * other.constant,
            modular: self.modular || other.modular,
        }
    }

    /// The form with `N = U + V + W + D` substituted and the zero integer
    /// parts dropped: coefficients of the nonzero parts (`0` for the zero
    /// ones) and the constant.
    fn reduced(self, case: CellCase) -> ([i64; 3], i64) {
        let coefficient = std::array::from_fn(|c| {
            if case.integer_zero[c] {
                0
            } else {
                self.coefficient[c] + self.n
            }
        });
        (
            coefficient,
            self.constant + self.n * i64::from(case.rest.sum),
        )
    }
}

/// `sum a_c X_c + constant >= 0` for integers `X_c >= 1` (the nonzero
/// parts; zero ones have coefficient 0), or `None` when the sign depends
/// on the values.
fn nonnegative(coefficient: [i64; 3], constant: i64) -> Option<bool> {
    let total: i64 = coefficient.iter().sum::<i64>() + constant;
    if coefficient.iter().all(|&a| a >= 0) && total >= 0 {
        Some(true)
    } else if coefficient.iter().all(|&a| a <= 0) && total < 0 {
        Some(false)
    } else {
        None
    }
}

impl ReferenceWord for CellForm {
    fn constant(value: u64) -> Self {
        CellForm {
            coefficient: [0; 3],
            n: 0,
            constant: value as i64,
            modular: false,
        }
    }
    /// `N`, for every level (the derivation runs each level separately).
    fn power_of_two(_level: u32) -> Self {
        CellForm {
            coefficient: [0; 3],
            n: 1,
            constant: 0,
            modular: false,
        }
    }
    fn wrapping_add(self, other: Self) -> Self {
        self.combine(other, 1)
    }
    fn wrapping_sub(self, other: Self) -> Self {
        self.combine(other, -1)
    }
    fn at_least(self, other: Self) -> bool {
        let difference = self.combine(other, -1);
        if difference.modular {
            fail("compared a value known only modulo 2^level");
            return false;
        }
        let (coefficient, constant) = difference.reduced(case());
        nonnegative(coefficient, constant).unwrap_or_else(|| {
            fail(&format!(
                "cannot decide {self:?} >= {other:?} in {:?}",
                case()
            ));
            false
        })
    }
    fn complement(self) -> Self {
        CellForm {
            modular: true,
            ..CellForm::constant(u64::MAX).combine(self, -1)
        }
    }
    fn xor(self, _: Self) -> Self {
        fail("a bit operation in the cell's arithmetic");
        self
    }
    fn and(self, _: Self) -> Self {
        fail("a bit operation in the cell's arithmetic");
        self
    }
    fn or(self, _: Self) -> Self {
        fail("a bit operation in the cell's arithmetic");
        self
    }
    fn shift_right(self, _: u32) -> Self {
        fail("a shift in the cell's arithmetic");
        self
    }
    fn shift_left(self, _: u32) -> Self {
        fail("a shift in the cell's arithmetic");
        self
    }
}

/// `r . (R_u, R_v, R_w) + one + ulp * e`: a fraction below the level in
/// units of 1, where `e = 2^-(scale - level)` is the unit of the dyadic
/// numerators (`mask = 1 - e`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FractionForm {
    /// Coefficients of the remainders `R_u`, `R_v`, `R_w` at the level.
    pub r: [i64; 3],
    /// The constant, in units of 1.
    pub one: i64,
    /// The constant, in units of `e`.
    pub ulp: i64,
}

impl FractionForm {
    fn combine(self, other: FractionForm, sign: i64) -> FractionForm {
        FractionForm {
            r: std::array::from_fn(|c| self.r[c] + sign * other.r[c]),
            one: self.one + sign * other.one,
            ulp: self.ulp + sign * other.ulp,
        }
    }

    /// The sign of the form in the case, for every admissible `e` and
    /// remainders: `R_c = 0` where the rest is zero, else in `[e, 1 - e]`,
    /// `R_u + R_v + R_w = D`; `e <= 1/2` unless every rest is zero (then `e
    /// <= 1`). `None` if it depends on them.
    fn nonnegative(self, rest: Rest) -> Option<bool> {
        // Eliminate two remainders with R_u + R_v + R_w = D: the form must
        // have equal coefficients on two of them.
        let d = i64::from(rest.sum);
        let (c, s, one) = (0..3).find_map(|c| {
            let (a, b) = ((c + 1) % 3, (c + 2) % 3);
            (self.r[a] == self.r[b]).then(|| (c, self.r[c] - self.r[a], self.one + self.r[a] * d))
        })?;
        // Endpoints of s R_c: (constant, e-coefficient).
        let ends: Vec<(i64, i64)> = if rest.zero[c] || s == 0 {
            vec![(0, 0)]
        } else {
            vec![(0, s), (s, -s)]
        };
        let e_max_halves = if rest.zero.iter().all(|&z| z) { 2 } else { 1 };
        // value(e) = one + k + (ulp + j) e, linear in e in (0, e_max]: its
        // sign at e -> 0+ (lexicographic) and at e_max.
        let signs: Vec<(bool, bool)> = ends
            .iter()
            .flat_map(|&(k, j)| {
                let (constant, slope) = (one + k, self.ulp + j);
                let at_zero = constant > 0 || (constant == 0 && slope >= 0);
                let at_max = 2 * constant + slope * e_max_halves >= 0;
                [(at_zero, at_zero), (at_max, at_max)]
            })
            .collect();
        if signs.iter().all(|s| s.0) {
            Some(true)
        } else if signs.iter().all(|s| !s.0) {
            // All strictly negative at every end.
            Some(false)
        } else {
            None
        }
    }
}

impl ReferenceWord for FractionForm {
    fn constant(value: u64) -> Self {
        FractionForm {
            r: [0; 3],
            one: 0,
            ulp: value as i64,
        }
    }
    fn power_of_two(_: u32) -> Self {
        fail("a power of two among the fractions");
        FractionForm::constant(0)
    }
    fn wrapping_add(self, other: Self) -> Self {
        self.combine(other, 1)
    }
    fn wrapping_sub(self, other: Self) -> Self {
        self.combine(other, -1)
    }
    fn at_least(self, other: Self) -> bool {
        self.combine(other, -1)
            .nonnegative(case().rest)
            .unwrap_or_else(|| {
                fail(&format!(
                    "cannot decide {self:?} >= {other:?} in {:?}",
                    case()
                ));
                false
            })
    }
    fn complement(self) -> Self {
        fail("a complement among the fractions");
        self
    }
    fn xor(self, _: Self) -> Self {
        fail("a bit operation among the fractions");
        self
    }
    fn and(self, _: Self) -> Self {
        fail("a bit operation among the fractions");
        self
    }
    fn or(self, _: Self) -> Self {
        fail("a bit operation among the fractions");
        self
    }
    fn shift_right(self, _: u32) -> Self {
        fail("a shift among the fractions");
        self
    }
    fn shift_left(self, _: u32) -> Self {
        fail("a shift among the fractions");
        self
    }
}

/// The reference's first half as the derivation runs it: the cell's
/// integer steps (the crate's [`internals::reference_cell`]) ...
pub type CellCode = fn(CellForm, CellForm, bool, u32) -> (CellForm, CellForm, CellForm);
/// ... and the dyadic diagonal test ([`internals::fractions_reach_one`]).
pub type DiagonalCode = fn(FractionForm, FractionForm, FractionForm) -> bool;

/// The crate's code, instantiated on the symbolic words.
pub const REFERENCE_CELL: CellCode = code::reference_cell::<CellForm>;
/// The crate's dyadic diagonal test on symbolic fractions.
pub const REFERENCE_DIAGONAL: DiagonalCode = code::fractions_reach_one::<FractionForm>;

/// What the reference's cell is at a level end the transducer can see
/// (the rest and whether `u`, `w` are zero).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CellOutcome {
    /// No point ends a level with this knowledge.
    Unreachable,
    /// The cell is the point's integer parts with one less of this
    /// coordinate (or none).
    Decrement(Option<usize>),
}

/// The derived rule: the [`CellOutcome`] per (rest, `u == 0`, `w == 0`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CellRule {
    outcomes: [CellOutcome; 96],
}

fn rule_slot(rest: Rest, u_zero: bool, w_zero: bool) -> usize {
    let z =
        usize::from(rest.zero[U]) | usize::from(rest.zero[V]) << 1 | usize::from(rest.zero[W]) << 2;
    ((usize::from(rest.sum) * 8 + z) * 2 + usize::from(u_zero)) * 2 + usize::from(w_zero)
}

impl CellRule {
    /// The outcome for a level end.
    #[must_use]
    pub fn outcome(&self, rest: Rest, u_zero: bool, w_zero: bool) -> CellOutcome {
        self.outcomes[rule_slot(rest, u_zero, w_zero)]
    }
}

/// The highest level the cell rule is derived at (the 64-bit code's).
pub const CELL_RULE_LEVELS: u32 = 32;

/// Runs `diagonal` and `cell` on symbolic numbers for every completable
/// rest, every pattern of zero integer parts consistent with it and every
/// level `0..=32`, and reads each result as "the integer part of the same
/// coordinate, minus 0 or 1": that is the reference's cell in the digit
/// columns (the borrow of "minus one" read from the top, which needs the
/// coordinate's rest below the level to be zero: checked). Fails unless
/// every case is decided, every result has that shape, at most one
/// coordinate is decremented, and the outcome depends only on what the
/// transducer knows (the rest, `u == 0`, `w == 0`) and not on the level.
pub fn derive_cell_rule(cell: CellCode, diagonal: DiagonalCode) -> Result<CellRule, String> {
    let mut outcomes = [CellOutcome::Unreachable; 96];
    let mut seen = [None::<(CellCase, u32)>; 96];
    for level in 0..=CELL_RULE_LEVELS {
        let n_cells = 1u64 << level;
        for rest in search::completable() {
            for pattern in 0..8u8 {
                let integer_zero = [pattern & 1 != 0, pattern & 2 != 0, pattern & 4 != 0];
                let nonzero = integer_zero.iter().filter(|&&z| !z).count() as u64;
                // U + V + W + D = 2^level with each nonzero part >= 1.
                if nonzero + u64::from(rest.sum) > n_cells || (nonzero == 0 && rest.sum == 0) {
                    continue;
                }
                let case = CellCase { rest, integer_zero };
                let decremented = run_cell(cell, diagonal, case, level)?;
                let slot = rule_slot(rest, case.value_zero(U), case.value_zero(W));
                match (outcomes[slot], seen[slot]) {
                    (CellOutcome::Decrement(known), Some((other, at))) if known != decremented => {
                        return Err(format!(
                            "the reference's cell is not a function of what a level end knows: \
                             {other:?} at level {at} decrements {known:?}, {case:?} at level \
                             {level} decrements {decremented:?}"
                        ));
                    }
                    _ => {
                        outcomes[slot] = CellOutcome::Decrement(decremented);
                        seen[slot] = Some((case, level));
                    }
                }
            }
        }
    }
    Ok(CellRule { outcomes })
}

/// One case at one level: the decremented coordinate, if any.
fn run_cell(
    cell: CellCode,
    diagonal: DiagonalCode,
    case: CellCase,
    level: u32,
) -> Result<Option<usize>, String> {
    CASE.with(|c| c.set(Some(case)));
    let _ = take_failure();
    let fraction = |c: usize| {
        let mut r = [0; 3];
        r[c] = 1;
        FractionForm { r, one: 0, ulp: 0 }
    };
    let mask = FractionForm {
        r: [0; 3],
        one: 1,
        ulp: -1,
    };
    let diagonal = diagonal(fraction(U), fraction(V), mask);
    let (iu, iv, iw) = cell(
        CellForm::variable(U),
        CellForm::variable(V),
        diagonal,
        level,
    );
    let why = |what: String| format!("reference cell at level {level}, {case:?}: {what}");
    if let Some(failure) = take_failure() {
        return Err(why(failure));
    }
    let mut decremented = None;
    for (c, form) in [(U, iu), (V, iv), (W, iw)] {
        let minus = coordinate_minus(form, c, case).ok_or_else(|| {
            why(format!(
                "{} = {form:?} is not the point's integer part minus 0 or 1",
                ["iu", "iv", "iw"][c]
            ))
        })?;
        if minus {
            if !case.rest.zero[c] {
                return Err(why(format!(
                    "decrements {} whose rest below the level is not zero (the top-down borrow \
                     needs it)",
                    ["u", "v", "w"][c]
                )));
            }
            if decremented.replace(c).is_some() {
                return Err(why("decrements two coordinates".into()));
            }
        }
    }
    Ok(decremented)
}

/// Whether `form` is `X_c - 1` (`Some(true)`) or `X_c` (`Some(false)`),
/// a value in `0..N` (modulo `N` if the form is modular), in the case.
fn coordinate_minus(form: CellForm, c: usize, case: CellCase) -> Option<bool> {
    let shifts: &[i64] = if form.modular {
        &[-2, -1, 0, 1, 2]
    } else {
        &[0]
    };
    shifts.iter().find_map(|&k| {
        let shifted = CellForm {
            n: form.n + k,
            ..form
        };
        let (coefficient, constant) = shifted.reduced(case);
        let others_vanish = (0..3).all(|d| d == c || coefficient[d] == 0);
        let own = if case.integer_zero[c] {
            1
        } else {
            coefficient[c]
        };
        if !others_vanish || own != 1 || !(constant == 0 || constant == -1) {
            return None;
        }
        let minus = constant == -1;
        // In range: X_c - 1 >= 0, and X_c < N unless decremented (X_c = N
        // only when the other parts and D are zero).
        let others_zero = (0..3).all(|d| d == c || case.integer_zero[d]) && case.rest.sum == 0;
        let in_range = if minus {
            !case.integer_zero[c]
        } else {
            !others_zero
        };
        in_range.then_some(minus)
    })
}

// ---------------------------------------------------------------------
// The digits: words of GF(2) polynomials.

/// A monomial: a set of variables (bit `i`: variable `i`), `0` is `1`.
type Monomial = u128;

/// A polynomial over GF(2): sorted distinct monomials.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Polynomial(Vec<Monomial>);

impl Polynomial {
    fn one() -> Polynomial {
        Polynomial(vec![0])
    }
    fn variable(i: u32) -> Polynomial {
        Polynomial(vec![1 << i])
    }
    fn is_zero(&self) -> bool {
        self.0.is_empty()
    }
    fn is_one(&self) -> bool {
        self.0 == [0]
    }
    fn add(&self, other: &Polynomial) -> Polynomial {
        let (a, b) = (&self.0, &other.0);
        let mut out = Vec::with_capacity(a.len() + b.len());
        let (mut i, mut j) = (0, 0);
        while i < a.len() && j < b.len() {
            match a[i].cmp(&b[j]) {
                Ordering::Less => {
                    out.push(a[i]);
                    i += 1;
                }
                Ordering::Greater => {
                    out.push(b[j]);
                    j += 1;
                }
                Ordering::Equal => {
                    i += 1;
                    j += 1;
                }
            }
        }
        out.extend_from_slice(&a[i..]);
        out.extend_from_slice(&b[j..]);
        Polynomial(out)
    }
    fn mul(&self, other: &Polynomial) -> Polynomial {
        let mut all: Vec<Monomial> = self
            .0
            .iter()
            .flat_map(|&a| other.0.iter().map(move |&b| a | b))
            .collect();
        all.sort_unstable();
        let mut out = Vec::with_capacity(all.len());
        let mut i = 0;
        while i < all.len() {
            let mut j = i;
            while j < all.len() && all[j] == all[i] {
                j += 1;
            }
            if (j - i) % 2 == 1 {
                out.push(all[i]);
            }
            i = j;
        }
        Polynomial(out)
    }
}

/// One bit of a symbolic word; an `|` is kept unexpanded until an
/// operation needs it (the interleave's masks drop most of them).
#[derive(Clone, Debug)]
enum Bit {
    Value(Rc<Polynomial>),
    Or(Rc<Polynomial>, Rc<Polynomial>),
}

impl Bit {
    fn zero() -> Bit {
        Bit::Value(Rc::new(Polynomial::default()))
    }
    fn value(&self) -> Rc<Polynomial> {
        match self {
            Bit::Value(p) => p.clone(),
            Bit::Or(a, b) => Rc::new(a.add(b).add(&a.mul(b))),
        }
    }
    fn known(&self) -> Option<bool> {
        match self {
            Bit::Value(p) if p.is_zero() => Some(false),
            Bit::Value(p) if p.is_one() => Some(true),
            _ => None,
        }
    }
}

thread_local! {
    static WORDS: RefCell<Vec<Rc<Vec<Bit>>>> = const { RefCell::new(Vec::new()) };
}

/// A `BITS`-bit word whose bits are polynomials in the cell's bits (a
/// handle into a per-thread arena, so that it is `Copy` like `u32`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AnfWord<const BITS: u32>(usize);

impl<const BITS: u32> AnfWord<BITS> {
    fn new(bits: Vec<Bit>) -> Self {
        debug_assert_eq!(bits.len(), BITS as usize);
        WORDS.with(|w| {
            let mut words = w.borrow_mut();
            words.push(Rc::new(bits));
            AnfWord(words.len() - 1)
        })
    }
    fn bits(self) -> Rc<Vec<Bit>> {
        WORDS.with(|w| w.borrow()[self.0].clone())
    }
    fn map2(self, other: Self, f: impl Fn(&Bit, &Bit) -> Bit) -> Self {
        let (a, b) = (self.bits(), other.bits());
        Self::new(a.iter().zip(b.iter()).map(|(x, y)| f(x, y)).collect())
    }
    fn known(self) -> Option<u64> {
        self.bits()
            .iter()
            .enumerate()
            .try_fold(0u64, |acc, (i, bit)| {
                Some(acc | u64::from(bit.known()?) << i)
            })
    }
    fn width_mask() -> u64 {
        if BITS == 64 {
            u64::MAX
        } else {
            (1u64 << BITS) - 1
        }
    }
    fn arithmetic(self, other: Self, f: impl Fn(u64, u64) -> u64) -> Self {
        if let (Some(a), Some(b)) = (self.known(), other.known()) {
            Self::constant(f(a, b) & Self::width_mask())
        } else {
            fail("integer arithmetic on a word with symbolic bits");
            self
        }
    }
    /// The polynomial of bit `i`.
    #[must_use]
    pub fn bit(self, i: usize) -> Polynomial {
        (*self.bits()[i].value()).clone()
    }
}

impl<const BITS: u32> ReferenceWord for AnfWord<BITS> {
    fn constant(value: u64) -> Self {
        Self::new(
            (0..BITS)
                .map(|i| {
                    if (value >> i) & 1 == 1 {
                        Bit::Value(Rc::new(Polynomial::one()))
                    } else {
                        Bit::zero()
                    }
                })
                .collect(),
        )
    }
    fn power_of_two(level: u32) -> Self {
        Self::constant(1u64 << (level % BITS))
    }
    fn wrapping_add(self, other: Self) -> Self {
        self.arithmetic(other, u64::wrapping_add)
    }
    fn wrapping_sub(self, other: Self) -> Self {
        self.arithmetic(other, u64::wrapping_sub)
    }
    fn at_least(self, other: Self) -> bool {
        if let (Some(a), Some(b)) = (self.known(), other.known()) {
            a >= b
        } else {
            fail("a comparison of words with symbolic bits");
            false
        }
    }
    fn complement(self) -> Self {
        let one = Polynomial::one();
        Self::new(
            self.bits()
                .iter()
                .map(|b| Bit::Value(Rc::new(b.value().add(&one))))
                .collect(),
        )
    }
    fn xor(self, other: Self) -> Self {
        self.map2(other, |a, b| Bit::Value(Rc::new(a.value().add(&b.value()))))
    }
    fn and(self, other: Self) -> Self {
        self.map2(other, |a, b| match (a.known(), b.known()) {
            (Some(false), _) | (_, Some(false)) => Bit::zero(),
            (Some(true), _) => b.clone(),
            (_, Some(true)) => a.clone(),
            _ => Bit::Value(Rc::new(a.value().mul(&b.value()))),
        })
    }
    fn or(self, other: Self) -> Self {
        self.map2(other, |a, b| match (a.known(), b.known()) {
            (Some(false), _) => b.clone(),
            (_, Some(false)) => a.clone(),
            (Some(true), _) | (_, Some(true)) => Bit::Value(Rc::new(Polynomial::one())),
            _ => Bit::Or(a.value(), b.value()),
        })
    }
    fn shift_right(self, shift: u32) -> Self {
        let bits = self.bits();
        Self::new(
            (0..BITS as usize)
                .map(|i| {
                    bits.get(i + shift as usize)
                        .cloned()
                        .unwrap_or_else(Bit::zero)
                })
                .collect(),
        )
    }
    fn shift_left(self, shift: u32) -> Self {
        let bits = self.bits();
        Self::new(
            (0..BITS as usize)
                .map(|i| {
                    i.checked_sub(shift as usize)
                        .map_or_else(Bit::zero, |j| bits[j].clone())
                })
                .collect(),
        )
    }
}

/// The algebraic normal form of a function of (parity, u, v, w): for each
/// subset of the four variables (bit 0: parity, 1..=3: u, v, w) whether
/// its monomial occurs.
fn algebraic_normal_form(f: impl Fn(bool, [bool; 3]) -> bool) -> [bool; 16] {
    let mut table: [bool; 16] =
        std::array::from_fn(|x| f(x & 1 != 0, [x & 2 != 0, x & 4 != 0, x & 8 != 0]));
    for i in 0..4 {
        for x in 0..16 {
            if x & (1 << i) != 0 {
                table[x] ^= table[x ^ (1 << i)];
            }
        }
    }
    table
}

/// The ANF `anf` with the parity and the column's bits replaced by
/// polynomials.
fn substitute(anf: &[bool; 16], parity: &Polynomial, column: &[Polynomial; 3]) -> Polynomial {
    let mut out = Polynomial::default();
    for (subset, _) in anf.iter().enumerate().filter(|(_, &present)| present) {
        let mut term = Polynomial::one();
        if subset & 1 != 0 {
            term = term.mul(parity);
        }
        for (c, bit) in column.iter().enumerate() {
            if subset & (2 << c) != 0 {
                term = term.mul(bit);
            }
        }
        out = out.add(&term);
    }
    out
}

/// One width of the reference's integer half: its word size and its
/// prefix-XOR and interleave steps.
#[derive(Clone, Copy, Debug)]
pub struct Width {
    /// Bits of the word (32 or 64).
    pub bits: u32,
    /// The prefix-XOR shifts.
    pub prefix_xor: &'static [u32],
    /// The interleave steps.
    pub interleave: &'static [(u32, u64)],
}

/// The Vulkan code's 32-bit integer half.
pub const NARROW: Width = Width {
    bits: 32,
    prefix_xor: &code::NARROW_PREFIX_XOR,
    interleave: &code::NARROW_INTERLEAVE,
};
/// The 64-bit widening.
pub const WIDE: Width = Width {
    bits: 64,
    prefix_xor: &code::WIDE_PREFIX_XOR,
    interleave: &code::WIDE_INTERLEAVE,
};

/// Runs the integer half's bit steps ([`internals::reference_digits`]) at
/// `level` on a cell whose bits below the level are variables (`iw`'s bits
/// above it too: free) and checks that digit `j` is the column table's
/// digit for column `j` and the parity of the Top digits above it, as
/// polynomials, for every `j`, with nothing above digit `level - 1`.
pub fn verify_columns_at(
    columns: &ReferenceColumns,
    width: Width,
    level: u32,
) -> Result<(), String> {
    if 2 * level + width.bits > 128 {
        return Err(format!("level {level} needs more than 128 variables"));
    }
    let result = match width.bits {
        32 => digits_on_polynomials::<32>(width, level),
        64 => digits_on_polynomials::<64>(width, level),
        other => return Err(format!("no {other}-bit words")),
    }?;
    let n = level as usize;
    let variable = |p: usize, c: usize| Polynomial::variable((3 * p + c) as u32);
    let digit_anf = |b: u32| {
        algebraic_normal_form(|parity, bits| (columns.digit(parity, bits).0 >> b) & 1 == 1)
    };
    let (low, high) = (digit_anf(0), digit_anf(1));
    let toggle = algebraic_normal_form(|parity, bits| columns.digit(parity, bits).1 != parity);
    let mut parity = Polynomial::default();
    for j in (0..n).rev() {
        let column = [variable(j, U), variable(j, V), variable(j, W)];
        for (b, anf) in [(0, &low), (1, &high)] {
            let zero = Polynomial::default();
            if *result.get(2 * j + b).unwrap_or(&zero) != substitute(anf, &parity, &column) {
                return Err(format!(
                    "the {}-bit integer half at level {level}: bit {b} of digit {j} is not the \
                     column table's",
                    width.bits
                ));
            }
        }
        parity = parity.add(&substitute(&toggle, &parity, &column));
    }
    if let Some(p) = (2 * n..width.bits as usize).find(|&p| !result[p].is_zero()) {
        return Err(format!(
            "the {}-bit integer half at level {level}: index bit {p} is not zero",
            width.bits
        ));
    }
    Ok(())
}

fn digits_on_polynomials<const BITS: u32>(
    width: Width,
    level: u32,
) -> Result<Vec<Polynomial>, String> {
    WORDS.with(|w| w.borrow_mut().clear());
    let _ = take_failure();
    let n = level as usize;
    let word = |c: usize| {
        AnfWord::<BITS>::new(
            (0..BITS as usize)
                .map(|p| {
                    if p < n {
                        Bit::Value(Rc::new(Polynomial::variable((3 * p + c) as u32)))
                    } else if c == W {
                        // iw = ~(iu + iv) above the level: left free.
                        Bit::Value(Rc::new(Polynomial::variable((3 * n + p - n) as u32)))
                    } else {
                        Bit::zero()
                    }
                })
                .collect(),
        )
    };
    let index = code::reference_digits(
        word(U),
        word(V),
        word(W),
        level,
        width.prefix_xor,
        width.interleave,
    );
    let bits = (0..BITS as usize).map(|i| index.bit(i)).collect();
    WORDS.with(|w| w.borrow_mut().clear());
    match take_failure() {
        Some(why) => Err(format!(
            "the {BITS}-bit integer half at level {level}: {why}"
        )),
        None => Ok(bits),
    }
}

/// [`verify_columns_at`] for the 64-bit code at every level `0..=32` and the
/// 32-bit code at every level `0..=16`.
pub fn verify_columns(columns: &ReferenceColumns) -> Result<(), String> {
    for level in 0..=32 {
        verify_columns_at(columns, WIDE, level)?;
    }
    for level in 0..=spec::MAX_LEVEL {
        verify_columns_at(columns, NARROW, level)?;
    }
    Ok(())
}
