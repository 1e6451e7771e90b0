//! The rationals' first half (`spec::cell_real`'s fast path,
//! `cell_over_denominator`, and `num::over_common_denominator`) must be,
//! token for token, the lines `crates/lab/certificates/rationals.py`
//! models and proves with z3 (lemmas 9a and 9b, `docs/verification.md`
//! 10.12). The model is read from that script (the one copy of it; this
//! lab embeds it with `include_str!`), the functions are cut from the
//! sources the lab was built with, and both are split into tokens by the
//! fold check's tokenizer ([`super::fold`]): a changed, inserted, deleted
//! or reordered token is refused with its source line, so a mutation of
//! these functions makes `prove --all-levels` fail as well as the SMT
//! tier.

use super::fold::{cut_function, first_difference, tokenize, Token};
use std::fmt;

/// The z3 script whose `MODELLED` lines are the model.
const SCRIPT: &str = include_str!("../../certificates/rationals.py");

/// The sources the model names, as the lab was built with them.
const SOURCES: [(&str, &str); 2] = [
    (
        "src/spec/real.rs",
        include_str!("../../../../src/spec/real.rs"),
    ),
    (
        "src/num/rational.rs",
        include_str!("../../../../src/num/rational.rs"),
    ),
];

/// Where a source departs from the model (or the model cannot be read).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RationalsMismatch {
    /// The file and function.
    pub function: String,
    /// The source line of the first differing token (0: none).
    pub line: usize,
    /// What differs.
    pub detail: String,
}

impl fmt::Display for RationalsMismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} is not the code rationals.py proves (line {}): {}",
            self.function, self.line, self.detail
        )
    }
}

/// What was checked.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RationalsProof {
    /// `file: fn name` of each function checked.
    pub functions: Vec<String>,
    /// Their tokens in all.
    pub tokens: usize,
}

/// Checks the sources this lab was built with against the script's model.
///
/// # Errors
/// The first function whose tokens differ from the model's.
pub fn prove_rationals_source() -> Result<RationalsProof, RationalsMismatch> {
    check_rationals_source(SCRIPT, &SOURCES)
}

/// [`prove_rationals_source`] on a given script and sources: how the tests
/// check that changed functions are refused.
///
/// # Errors
/// As [`prove_rationals_source`].
pub fn check_rationals_source(
    script: &str,
    sources: &[(&str, &str)],
) -> Result<RationalsProof, RationalsMismatch> {
    let model = modelled(script);
    if model.is_empty() {
        return Err(RationalsMismatch {
            function: "rationals.py".into(),
            line: 0,
            detail: "no MODELLED functions found in the script".into(),
        });
    }
    let mut proof = RationalsProof {
        functions: Vec::new(),
        tokens: 0,
    };
    for (file, name, lines) in model {
        let function = format!("{file}: fn {name}");
        let mismatch = |line: usize, detail: String| RationalsMismatch {
            function: function.clone(),
            line,
            detail,
        };
        let source = sources
            .iter()
            .find(|(path, _)| *path == file)
            .ok_or_else(|| mismatch(0, "the lab does not embed this file".into()))?
            .1;
        let tokens = tokenize(source)
            .map_err(|(line, why)| mismatch(line, format!("cannot be split into tokens: {why}")))?;
        let found = cut_function(&tokens, &name).map_err(|why| mismatch(0, why))?;
        // The script's lines are the header and the body without the
        // function's closing brace.
        let mut expected = tokenize(&lines.join("\n"))
            .map_err(|(_, why)| mismatch(0, format!("the model cannot be split: {why}")))?;
        expected.push(Token {
            text: "}".into(),
            line: 0,
        });
        if let Some((line, detail)) = first_difference(&expected, found) {
            return Err(mismatch(line, detail));
        }
        proof.functions.push(function);
        proof.tokens += found.len();
    }
    Ok(proof)
}

/// The script's `MODELLED` entries: `(file, function name, lines)`, read
/// from its literal layout (a file key `"src/...": {`, a function key
/// `"fn NAME": [`, one string per line, `],` closing).
fn modelled(script: &str) -> Vec<(String, String, Vec<String>)> {
    let mut out = Vec::new();
    let mut file = None;
    let mut current: Option<(String, Vec<String>)> = None;
    for line in script.lines().map(str::trim) {
        let quoted = line
            .strip_prefix('"')
            .and_then(|rest| rest.rsplit_once('"'))
            .map(|(text, tail)| (text.to_owned(), tail));
        match (&mut current, quoted) {
            (None, Some((key, ": {"))) if key.starts_with("src/") => file = Some(key),
            (None, Some((key, ": ["))) if key.starts_with("fn ") => {
                current = Some((key["fn ".len()..].to_owned(), Vec::new()));
            }
            (Some((_, lines)), Some((text, ","))) => lines.push(text),
            (Some(_), None) if line == "]," => {
                if let (Some(file), Some((name, lines))) = (&file, current.take()) {
                    out.push((file.clone(), name, lines));
                }
            }
            _ => {}
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sources_are_the_model() {
        let proof = prove_rationals_source().unwrap();
        assert_eq!(proof.functions.len(), 3);
        assert!(proof.tokens > 100, "{proof:?}");
    }

    #[test]
    fn changed_functions_are_refused() {
        let real = SOURCES[0].1;
        for (from, to) in [
            ("su % d + sv % d >= d", "su % d + sv % d > d"),
            ("unwrap_or(0).min(d) << level", "unwrap_or(0) << level"),
            ("iu: (su / d) as u64,", "iu: (su / d) as u64 + 1,"),
        ] {
            let mutated = real.replace(from, to);
            assert_ne!(mutated, real, "{from}");
            let sources = [("src/spec/real.rs", mutated.as_str()), SOURCES[1]];
            let error = check_rationals_source(SCRIPT, &sources).unwrap_err();
            assert!(error.function.contains("cell_over_denominator"), "{error}");
            assert!(error.line > 0, "{error}");
        }
        // A model the script does not hold is an error, not a pass.
        assert!(check_rationals_source("", &SOURCES).is_err());
    }
}
