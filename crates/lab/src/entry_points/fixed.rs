//! The fixed-point walk's arithmetic (`num::Fixed64`, `num::Fixed128`:
//! what `uv2index::index` and `index_unchecked` run for fixed-point points,
//! and the exact walk oracles) must be, token for token, the modelled
//! integer steps on the raw values (`x 2^P`):
//!
//! * `one_minus_sum`: `ONE - (u + v)`; `plus`, `minus`: the raw sum and
//!   difference; `twice`: the raw value shifted left once; `cmp_half`: the
//!   raw value against `2^(P - 1)`; each exact as long as no raw value
//!   leaves the integer type;
//! * `check_point`: the signs of `u`, `v` and `u + v - 1`, with the sum's
//!   overflow decided by the sign of `u`;
//! * `ONE` is `1 << P`, and a compile-time assertion holds `P < BITS - 1`.
//!
//! `crates/lab/certificates/product.py` proves by induction over the
//! walk's step ("walk range", z3) that every value a walk of a point of
//! the closed triangle forms lies in `[0, 1]`, i.e. every raw value in
//! `[0, 2^P]`, inside the type: so these steps are the exact steps over
//! the reals, and the walk on them is the walk section 10 proves. The
//! source is cut from `src/num/fixed.rs` as the lab was built with it and
//! compared with the model by the fold check's tokenizer
//! ([`super::fold`]).

use super::fold::{first_difference, occurrences, tokenize, Token};
use std::fmt;

/// The source of `src/num/fixed.rs` this lab was built with.
const FIXED_SOURCE: &str = include_str!("../../../../src/num/fixed.rs");

/// The `impl WalkNumber for $name` block of `fixed_point_type!`.
const MODELLED_IMPL: &str = "impl WalkNumber for $name {
    fn one_minus_sum(u: &Self, v: &Self) -> Self {
        Self::ONE.minus(&u.plus(v))
    }
    fn twice(&self) -> Self {
        $name(self.0.wrapping_shl(1))
    }
    fn plus(&self, other: &Self) -> Self {
        $name(self.0.wrapping_add(other.0))
    }
    fn minus(&self, other: &Self) -> Self {
        $name(self.0.wrapping_sub(other.0))
    }
    fn cmp_half(&self) -> Ordering {
        self.0.cmp(&(1 << ($one_log2 - 1)))
    }
    fn check_point(u: &Self, v: &Self) -> Result<(), Error> {
        let sum_minus_one = match u.0.checked_add(v.0) {
            Some(sum) => sum.cmp(&Self::ONE.0),
            None if u.0 > 0 => Ordering::Greater,
            None => Ordering::Less,
        };
        check_signs(u.0.cmp(&0), v.0.cmp(&0), sum_minus_one)
    }
}";

/// Statements that must occur exactly once, token for token.
const MODELLED_LINES: [&str; 2] = [
    "pub const ONE: $name = $name(1 << $one_log2);",
    "const _: () = assert!($one_log2 < <$int>::BITS - 1);",
];

/// Where the source departs from the model.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FixedMismatch {
    /// The source line of the first differing token (0: none found).
    pub line: usize,
    /// What differs.
    pub detail: String,
}

impl fmt::Display for FixedMismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the fixed-point walk's arithmetic is not the modelled exact integer steps \
             (src/num/fixed.rs line {}): {}",
            self.line, self.detail
        )
    }
}

/// What was checked.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FixedProof {
    /// Tokens compared.
    pub tokens: usize,
}

/// Checks the source this lab was built with (module comment).
///
/// # Errors
/// The first token where the source departs from the model.
pub fn prove_fixed_arithmetic() -> Result<FixedProof, FixedMismatch> {
    check_fixed_arithmetic(FIXED_SOURCE)
}

/// [`prove_fixed_arithmetic`] on a given source: how the tests check that
/// changed arithmetic is refused.
///
/// # Errors
/// As [`prove_fixed_arithmetic`].
pub fn check_fixed_arithmetic(source: &str) -> Result<FixedProof, FixedMismatch> {
    let split = |text: &str| {
        tokenize(text).map_err(|(line, why)| FixedMismatch {
            line,
            detail: format!("cannot be split into tokens: {why}"),
        })
    };
    let tokens = split(source)?;
    let occurrences = |needle: &[Token]| {
        let needle: Vec<&str> = needle.iter().map(|t| t.text.as_str()).collect();
        occurrences(&tokens, &needle)
    };
    let model = split(MODELLED_IMPL)?;
    // The block: from its header to the brace that closes it.
    let header = &model[..6];
    let &[start] = occurrences(header).as_slice() else {
        return Err(FixedMismatch {
            line: 0,
            detail: "`impl WalkNumber for $name {` does not occur exactly once".into(),
        });
    };
    let mut depth = 0usize;
    let end = (start + header.len() - 1..tokens.len()).find(|&i| {
        match tokens[i].text.as_str() {
            "{" => depth += 1,
            "}" => depth -= 1,
            _ => {}
        }
        depth == 0
    });
    let Some(end) = end else {
        return Err(FixedMismatch {
            line: tokens[start].line,
            detail: "the block is not closed".into(),
        });
    };
    let found = &tokens[start..=end];
    if let Some((line, detail)) = first_difference(&model, found) {
        return Err(FixedMismatch { line, detail });
    }
    let mut compared = found.len();
    for line in MODELLED_LINES {
        let needle = split(line)?;
        let count = occurrences(&needle).len();
        if count != 1 {
            return Err(FixedMismatch {
                line: 0,
                detail: format!("`{line}` occurs {count} times, not once"),
            });
        }
        compared += needle.len();
    }
    Ok(FixedProof { tokens: compared })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_source_is_the_model() {
        assert!(prove_fixed_arithmetic().unwrap().tokens > 150);
    }

    #[test]
    fn changed_arithmetic_is_refused() {
        for (from, to) in [
            ("self.0.wrapping_shl(1)", "self.0.wrapping_shl(2)"),
            ("(1 << ($one_log2 - 1))", "(1 << $one_log2)"),
            (
                "None if u.0 > 0 => Ordering::Greater",
                "None if u.0 >= 0 => Ordering::Greater",
            ),
            ("Self::ONE.minus(&u.plus(v))", "Self::ONE.minus(u)"),
            (
                "assert!($one_log2 < <$int>::BITS - 1)",
                "assert!($one_log2 < <$int>::BITS)",
            ),
            (
                "pub const ONE: $name = $name(1 << $one_log2);",
                "pub const ONE: $name = $name(1 << 59);",
            ),
        ] {
            let mutated = FIXED_SOURCE.replace(from, to);
            assert_ne!(mutated, FIXED_SOURCE, "{from}");
            let error = check_fixed_arithmetic(&mutated).unwrap_err();
            assert!(!error.detail.is_empty(), "{from}: {error}");
        }
    }
}
