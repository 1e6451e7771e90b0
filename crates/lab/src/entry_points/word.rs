//! Machine words of decision diagrams: bit `i` of a [`Bits<N>`] is the
//! Boolean function of the inputs' bits that the real word's bit `i` is.
//! They implement the library's `LaneWord` (the kernel's word: comparisons
//! give a [`Node`], selects are diagrams) and `ReferenceWord` (the
//! reference's word: comparisons give a Rust `bool`, so the reference's
//! `if`s branch: [`explore`] runs the code once per feasible branch
//! combination, each under its path condition).
//!
//! Contract: arithmetic is the machine's, bit for bit (two's complement,
//! wrapping unless the name says otherwise); shifts take counts below `N`,
//! as the library's code does.

use super::bdd::Node;
use micromap_index::internals::kernel::LaneWord;
use micromap_index::internals::ReferenceWord;
use std::cell::RefCell;
use std::ops::{BitAnd, BitOr, BitXor, Not, Shl, Shr};

/// An `N`-bit word whose bits are diagrams (bit 0 the least significant).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bits<const N: usize>(pub [Node; N]);

impl<const N: usize> Bits<N> {
    /// The word of `value` (truncated to `N` bits).
    #[must_use]
    pub fn of(value: u64) -> Self {
        Bits(std::array::from_fn(|i| {
            Node::constant(i < 64 && (value >> i) & 1 == 1)
        }))
    }

    /// An input word: bit `i < significant` is variable `variable(i)`, the
    /// bits above are zero (the input is below `2^significant`).
    #[must_use]
    pub fn input(significant: usize, variable: impl Fn(usize) -> u32) -> Self {
        Bits(std::array::from_fn(|i| {
            if i < significant {
                Node::variable(variable(i))
            } else {
                Node::FALSE
            }
        }))
    }

    /// The diagram "every bit of `self` equals the same bit of `other`".
    #[must_use]
    pub fn equals(&self, other: &Self) -> Node {
        self.0
            .iter()
            .zip(&other.0)
            .fold(Node::TRUE, |all, (&a, &b)| all & !(a ^ b))
    }

    /// The same bits in a wider (zero-extended) or narrower (truncated)
    /// word: `u32::from(u16)` and `as u16`.
    #[must_use]
    pub fn resize<const M: usize>(self) -> Bits<M> {
        Bits(std::array::from_fn(|i| {
            if i < N {
                self.0[i]
            } else {
                Node::FALSE
            }
        }))
    }

    /// The word's value under an assignment of the variables (missing
    /// variables read 0).
    #[must_use]
    pub fn value(&self, assignment: &[(u32, bool)]) -> u64 {
        let mut value = 0;
        for (i, &bit) in self.0.iter().enumerate().take(64) {
            if bit.evaluate(assignment) {
                value |= 1 << i;
            }
        }
        value
    }

    /// `self + other + carry`, and the carry out of the top bit.
    fn add_with_carry(self, other: Self, carry: Node) -> (Self, Node) {
        let mut carry = carry;
        let sum = std::array::from_fn(|i| {
            let (a, b) = (self.0[i], other.0[i]);
            let bit = a ^ b ^ carry;
            carry = (a & b) | (carry & (a ^ b));
            bit
        });
        (Bits(sum), carry)
    }

    /// `self < other`, unsigned: the borrow out of `self - other`.
    fn below(self, other: Self) -> Node {
        let (_, no_borrow) = self.add_with_carry(!other, Node::TRUE);
        !no_borrow
    }

    fn map(self, other: Self, op: impl Fn(Node, Node) -> Node) -> Self {
        Bits(std::array::from_fn(|i| op(self.0[i], other.0[i])))
    }
}

impl<const N: usize> BitAnd for Bits<N> {
    type Output = Self;
    fn bitand(self, other: Self) -> Self {
        self.map(other, |a, b| a & b)
    }
}

impl<const N: usize> BitOr for Bits<N> {
    type Output = Self;
    fn bitor(self, other: Self) -> Self {
        self.map(other, |a, b| a | b)
    }
}

impl<const N: usize> BitXor for Bits<N> {
    type Output = Self;
    fn bitxor(self, other: Self) -> Self {
        self.map(other, |a, b| a ^ b)
    }
}

impl<const N: usize> Not for Bits<N> {
    type Output = Self;
    fn not(self) -> Self {
        Bits(self.0.map(|a| !a))
    }
}

impl<const N: usize> Shl<u32> for Bits<N> {
    type Output = Self;
    fn shl(self, shift: u32) -> Self {
        let shift = shift as usize;
        assert!(shift < N, "shift by {shift} in a {N}-bit word");
        Bits(std::array::from_fn(|i| {
            if i >= shift {
                self.0[i - shift]
            } else {
                Node::FALSE
            }
        }))
    }
}

impl<const N: usize> Shr<u32> for Bits<N> {
    type Output = Self;
    fn shr(self, shift: u32) -> Self {
        let shift = shift as usize;
        assert!(shift < N, "shift by {shift} in a {N}-bit word");
        Bits(std::array::from_fn(|i| {
            if i + shift < N {
                self.0[i + shift]
            } else {
                Node::FALSE
            }
        }))
    }
}

impl<const N: usize> LaneWord for Bits<N> {
    type Bool = Node;
    fn constant(value: u64) -> Self {
        Bits::of(value)
    }
    fn from_bool(value: Node) -> Self {
        Bits(std::array::from_fn(|i| {
            if i == 0 {
                value
            } else {
                Node::FALSE
            }
        }))
    }
    fn wrapping_add(self, other: Self) -> Self {
        self.add_with_carry(other, Node::FALSE).0
    }
    fn wrapping_sub(self, other: Self) -> Self {
        self.add_with_carry(!other, Node::TRUE).0
    }
    fn saturating_add(self, other: Self) -> Self {
        let (sum, carry) = self.add_with_carry(other, Node::FALSE);
        Bits(sum.0.map(|bit| carry | bit))
    }
    fn min(self, other: Self) -> Self {
        Self::select(other.below(self), other, self)
    }
    fn less_than(self, other: Self) -> Node {
        self.below(other)
    }
    fn less_than_signed(self, other: Self) -> Node {
        // Two's complement order is the unsigned order with the sign bits
        // flipped.
        let flip = Bits::<N>::of(1 << (N - 1));
        (self ^ flip).below(other ^ flip)
    }
    fn select(condition: Node, if_true: Self, if_false: Self) -> Self {
        if_true.map(if_false, |a, b| condition.select(a, b))
    }
}

impl<const N: usize> ReferenceWord for Bits<N> {
    fn constant(value: u64) -> Self {
        Bits::of(value)
    }
    fn power_of_two(level: u32) -> Self {
        // `(1 as uN).wrapping_shl(level)`: the count taken modulo N.
        Bits::of(1u64 << (level as usize % N))
    }
    fn wrapping_add(self, other: Self) -> Self {
        LaneWord::wrapping_add(self, other)
    }
    fn wrapping_sub(self, other: Self) -> Self {
        LaneWord::wrapping_sub(self, other)
    }
    fn at_least(self, other: Self) -> bool {
        !decide(self.below(other))
    }
    fn complement(self) -> Self {
        !self
    }
    fn xor(self, other: Self) -> Self {
        self ^ other
    }
    fn and(self, other: Self) -> Self {
        self & other
    }
    fn or(self, other: Self) -> Self {
        self | other
    }
    fn shift_right(self, shift: u32) -> Self {
        self >> shift
    }
    fn shift_left(self, shift: u32) -> Self {
        self << shift
    }
}

/// The state of one run under [`explore`]: the branch choices to replay,
/// the position in them, the path condition, and the branches found open.
struct Run {
    script: Vec<bool>,
    position: usize,
    path: Node,
    open: Vec<Vec<bool>>,
}

thread_local! {
    static RUN: RefCell<Option<Run>> = const { RefCell::new(None) };
}

/// A branch of the reference's code on a symbolic condition: the outcome
/// forced by the path condition when it is, else the next scripted choice
/// (the first time: `true`, with the `false` side queued). The path
/// condition then records the choice.
///
/// # Panics
/// Outside [`explore`] on a condition that is not constant.
fn decide(condition: Node) -> bool {
    RUN.with(|run| {
        let mut run = run.borrow_mut();
        let Some(run) = run.as_mut() else {
            return condition
                .as_constant()
                .expect("a branch on a symbolic condition outside `explore`");
        };
        let if_true = run.path & condition;
        let if_false = run.path & !condition;
        if if_true == Node::FALSE {
            return false;
        }
        if if_false == Node::FALSE {
            return true;
        }
        let choice = if let Some(&choice) = run.script.get(run.position) {
            choice
        } else {
            let mut other = run.script.clone();
            other.push(false);
            run.open.push(other);
            run.script.push(true);
            true
        };
        run.position += 1;
        run.path = if choice { if_true } else { if_false };
        choice
    })
}

/// [`explore`] for a computation giving a pair of words: every path's
/// results merged into one pair (each bit selected by its path condition;
/// the paths are disjoint and cover every input).
pub fn explore_pair<const N: usize, const M: usize>(
    body: impl FnMut() -> (Bits<N>, Bits<M>),
) -> (Bits<N>, Bits<M>) {
    let (mut first, mut second) = (Bits::of(0), Bits::of(0));
    for (path, (path_first, path_second)) in explore(body) {
        first = Bits::select(path, path_first, first);
        second = Bits::select(path, path_second, second);
    }
    (first, second)
}

/// Runs `body` once for every feasible combination of the outcomes of its
/// symbolic branches (`ReferenceWord::at_least` on diagram words) and
/// returns each run's path condition and result. The path conditions are
/// disjoint and cover every input (every branch takes both sides where
/// both are feasible).
pub fn explore<R>(mut body: impl FnMut() -> R) -> Vec<(Node, R)> {
    let mut pending = vec![Vec::new()];
    let mut results = Vec::new();
    while let Some(script) = pending.pop() {
        RUN.with(|run| {
            *run.borrow_mut() = Some(Run {
                script,
                position: 0,
                path: Node::TRUE,
                open: Vec::new(),
            });
        });
        let result = body();
        let run = RUN
            .with(|run| run.borrow_mut().take())
            .expect("the run's state");
        pending.extend(run.open);
        results.push((run.path, result));
    }
    results
}

impl<const N: usize> micromap_index::internals::CoordinateWord for Bits<N> {
    /// # Panics
    /// When a low bit is not a constant: the proofs split the inputs into
    /// cases where the exponent is one (module `binary64`).
    fn low_u32(self) -> u32 {
        let mut value = 0;
        for (i, bit) in self.0.iter().enumerate().take(32) {
            let bit = bit
                .as_constant()
                .expect("low_u32 of a word whose low bits are symbolic");
            value |= u32::from(bit) << i;
        }
        value
    }
}
