//! `spec::cell_dyadic` equals the definition of the reference's first half
//! over the reals, at every input: its steps (`internals::dyadic_cell`,
//! which `cell_dyadic`, `index_dyadic` and `wide_index_dyadic` run) on words
//! of decision diagrams over the 128 bits of the two numerators, for every
//! scale `0..=62` and level `0..=32`, against the definition stated as
//! properties, not as the code's shifts and masks:
//!
//! * `c = min(x, 2^m)` (a coordinate above 1 clamps to 1);
//! * for `m >= level`, with `k = m - level`: the cell `i` satisfies
//!   `i * 2^k <= c < (i + 1) * 2^k` (it is `floor(2^level c / 2^m)`), the
//!   fraction is `r = c - i * 2^k`, and the diagonal holds exactly when
//!   `r_u + r_v >= 2^k` (the fractions sum to at least 1);
//! * for `m < level`: the cell is `c * 2^(level - m)` (read back: shifted
//!   down it is `c`, its low bits are zero) and there is no diagonal (both
//!   fractions are zero).
//!
//! This is what the transducer proof (section 10.2) reads from a point's
//! digits, so `cell_dyadic` feeds the proved reference exactly the cell and
//! diagonal the proof assumes.

use super::bdd::{self, Node};
use super::word::{explore, Bits};
use micromap_index::internals::dyadic_cell;
use micromap_index::internals::kernel::LaneWord;
use micromap_index::spec::MAX_SCALE_LOG2;
use micromap_index::{spec, Level};
use std::fmt;

/// An input where `cell_dyadic` and the definition differ.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DyadicCounterexample {
    /// `u * 2^scale_log2`.
    pub u_scaled: u64,
    /// `v * 2^scale_log2`.
    pub v_scaled: u64,
    /// The scale.
    pub scale_log2: u32,
    /// The level.
    pub level: u32,
    /// `spec::cell_dyadic`'s `(iu, iv, diagonal)` there (machine words).
    pub computed: (u64, u64, bool),
}

impl fmt::Display for DyadicCounterexample {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "spec::cell_dyadic({}, {}, {}, level {}) = {:?} is not the definition's cell",
            self.u_scaled, self.v_scaled, self.scale_log2, self.level, self.computed
        )
    }
}

/// What the proof covered.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DyadicProof {
    /// `(scale, level)` pairs proved.
    pub cases: usize,
    /// Paths of the code's branches, over all cases.
    pub paths: usize,
    /// The most diagram nodes one case needed.
    pub peak_nodes: usize,
}

/// Store size beyond which a case starts with a fresh store.
const RESET_ABOVE_NODES: usize = 4_000_000;

/// The variable of bit `i` of `u` (`v = false`) or `v`: interleaved from
/// the top.
fn variable(i: usize, v: bool) -> u32 {
    2 * (63 - i as u32) + u32::from(v)
}

/// Proves `spec::cell_dyadic` equal to the definition at every input, scale
/// and level.
///
/// # Errors
/// The first input where they differ.
pub fn prove_cell_dyadic() -> Result<DyadicProof, DyadicCounterexample> {
    prove_dyadic_steps(dyadic_cell, |u, v, scale_log2, level| {
        let level = Level::new(level).expect("levels 0..=32");
        let cell = spec::cell_dyadic(u, v, scale_log2, level).expect("scale within 62");
        (cell.iu, cell.iv, cell.diagonal)
    })
}

/// [`prove_cell_dyadic`] with the steps given (symbolic and on machine
/// words): how the tests check that changed steps are refused.
///
/// # Errors
/// As [`prove_cell_dyadic`].
pub fn prove_dyadic_steps(
    symbolic: impl Fn(Bits<64>, Bits<64>, u32, u32) -> (Bits<64>, Bits<64>, bool),
    concrete: impl Fn(u64, u64, u32, u32) -> (u64, u64, bool),
) -> Result<DyadicProof, DyadicCounterexample> {
    let mut proof = DyadicProof {
        cases: 0,
        paths: 0,
        peak_nodes: 0,
    };
    for scale_log2 in 0..=MAX_SCALE_LOG2 {
        for level in 0..=32 {
            // The inputs are the same variables in every case: the cases
            // share diagrams until the store grows large.
            bdd::reset_above(RESET_ABOVE_NODES);
            let u = Bits::<64>::input(64, |i| variable(i, false));
            let v = Bits::<64>::input(64, |i| variable(i, true));
            let paths = explore(|| symbolic(u, v, scale_log2, level));
            proof.paths += paths.len();
            // The paths are disjoint and cover every input: their results
            // merge into one symbolic result, checked once.
            let (mut iu, mut iv, mut diagonal) = (Bits::of(0), Bits::of(0), Node::FALSE);
            for (path, (path_iu, path_iv, path_diagonal)) in paths {
                iu = Bits::select(path, path_iu, iu);
                iv = Bits::select(path, path_iv, iv);
                diagonal = path.select(Node::constant(path_diagonal), diagonal);
            }
            {
                let wrong = !definition_holds(&[u, v], &[iu, iv], diagonal, scale_log2, level);
                if let Some(assignment) = wrong.satisfying_assignment() {
                    let (u, v) = (u.value(&assignment), v.value(&assignment));
                    return Err(DyadicCounterexample {
                        u_scaled: u,
                        v_scaled: v,
                        scale_log2,
                        level,
                        computed: concrete(u, v, scale_log2, level),
                    });
                }
            }
            proof.cases += 1;
            proof.peak_nodes = proof.peak_nodes.max(bdd::node_count());
        }
    }
    Ok(proof)
}

/// Whether `cells` and `diagonal` are the definition's for the inputs
/// `numerators` at this scale and level (module comment), as a diagram.
fn definition_holds(
    numerators: &[Bits<64>; 2],
    cells: &[Bits<64>; 2],
    diagonal: Node,
    scale_log2: u32,
    level: u32,
) -> Node {
    let one = Bits::<64>::of(1 << scale_log2);
    let clamped = numerators.map(|x| Bits::select(one.less_than(x), one, x));
    if scale_log2 >= level {
        let k = scale_log2 - level;
        let unit = Bits::<64>::of(1 << k);
        let mut holds = Node::TRUE;
        let mut fractions = [Bits::<64>::of(0); 2];
        for c in 0..2 {
            // i * 2^k <= x < (i + 1) * 2^k, no overflow: i <= 2^level.
            let low = cells[c] << k;
            let high = cells[c].wrapping_add(Bits::of(1)) << k;
            holds = holds
                & !clamped[c].less_than(low)
                & clamped[c].less_than(high)
                & cells[c].less_than(Bits::of((1 << level) + 1));
            fractions[c] = clamped[c].wrapping_sub(low);
        }
        let reaches_one = !fractions[0].wrapping_add(fractions[1]).less_than(unit);
        holds & !(reaches_one ^ diagonal)
    } else {
        let k = level - scale_log2;
        let mut holds = !diagonal;
        for c in 0..2 {
            let low_bits = cells[c] & Bits::of((1 << k) - 1);
            holds = holds & (cells[c] >> k).equals(&clamped[c]) & low_bits.equals(&Bits::of(0));
        }
        holds
    }
}
