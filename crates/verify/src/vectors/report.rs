//! The report as text ([`CheckReport::render`]) and the exact form of a
//! coordinate ([`exact_form`]).

use super::format::rational_text;
use super::{CheckReport, Tally};
use crate::value::Value;
use std::fmt;
use std::fmt::Write as _;

/// Ids listed in full before a report abbreviates.
const MAX_LISTED_IDS: usize = 20;

impl CheckReport {
    /// Every case answered with its expected index, and nothing else answered.
    pub fn passed(&self) -> bool {
        self.mismatches.is_empty() && self.missing.is_empty() && self.unknown.is_empty()
    }

    /// The report as text: a summary line, a table of cases and failures
    /// per tag and per failing level, then for every tag with mismatches
    /// its first `examples_per_tag` cases with the inputs in exact form,
    /// then the missing and unknown ids.
    pub fn render(&self, examples_per_tag: usize) -> String {
        let mut text = String::new();
        let _ = writeln!(
            text,
            "{}: {} cases, {} match, {} mismatch, {} missing, {} unknown ids: {}",
            self.function,
            self.cases,
            self.matched,
            self.mismatches.len(),
            self.missing.len(),
            self.unknown.len(),
            if self.passed() { "PASS" } else { "FAIL" }
        );
        let _ = writeln!(
            text,
            "\n{:<26} {:>7} {:>9} {:>8}",
            "tag", "cases", "mismatch", "missing"
        );
        for (name, tally) in &self.by_tag {
            let _ = writeln!(
                text,
                "{:<26} {:>7} {:>9} {:>8}",
                name, tally.cases, tally.mismatched, tally.missing
            );
        }
        let failing_levels: Vec<(&u32, &Tally)> = self
            .by_level
            .iter()
            .filter(|(_, t)| t.mismatched + t.missing > 0)
            .collect();
        if !failing_levels.is_empty() {
            let _ = writeln!(
                text,
                "\n{:<26} {:>7} {:>9} {:>8}",
                "failing level", "cases", "mismatch", "missing"
            );
            for (level, tally) in failing_levels {
                let _ = writeln!(
                    text,
                    "{:<26} {:>7} {:>9} {:>8}",
                    level, tally.cases, tally.mismatched, tally.missing
                );
            }
        }
        for (name, tally) in self.by_tag.iter().filter(|(_, t)| t.mismatched > 0) {
            let shown = examples_per_tag.min(tally.mismatched);
            let _ = writeln!(
                text,
                "\nmismatches tagged {name} ({} of {} cases; first {shown}):",
                tally.mismatched, tally.cases
            );
            let examples = self.mismatches.iter().filter(|m| m.tags.contains(name));
            for mismatch in examples.take(examples_per_tag) {
                let _ = writeln!(
                    text,
                    "  id {} level {}: u = {}, v = {}: expected {}, got {}  [{}]",
                    mismatch.id,
                    mismatch.level,
                    exact_form(&mismatch.u),
                    exact_form(&mismatch.v),
                    mismatch.expected,
                    mismatch.got,
                    mismatch.tags.join(", ")
                );
            }
        }
        for (what, ids) in [("missing", &self.missing), ("unknown", &self.unknown)] {
            if !ids.is_empty() {
                let listed: Vec<String> = ids
                    .iter()
                    .take(MAX_LISTED_IDS)
                    .map(u64::to_string)
                    .collect();
                let more = if ids.len() > MAX_LISTED_IDS {
                    ", …"
                } else {
                    ""
                };
                let _ = writeln!(
                    text,
                    "\n{what} ids ({}): {}{more}",
                    ids.len(),
                    listed.join(", ")
                );
            }
        }
        text
    }
}

impl fmt::Display for CheckReport {
    /// [`CheckReport::render`] with 5 examples per tag.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render(5))
    }
}

/// A coordinate as written plus its exact value: `0x3dffffff (16777215/134217728)`,
/// `0x7fc00000 (NaN)`, `0.375 (3/8)`; `p/q` text as is.
///
/// ```
/// use micromap_index_verify::vectors::exact_form;
/// assert_eq!(exact_form("0x3e000000"), "0x3e000000 (1/8)");
/// assert_eq!(exact_form("0xff800000"), "0xff800000 (-inf)");
/// assert_eq!(exact_form("0x80000000"), "0x80000000 (-0)");
/// assert_eq!(exact_form("3/8"), "3/8");
/// assert_eq!(exact_form("0.375"), "0.375 (3/8)");
/// ```
pub fn exact_form(text: &str) -> String {
    let value = match Value::parse(text) {
        Ok(value) => value,
        Err(_) => return text.to_owned(),
    };
    let float = match value {
        Value::F32Bits(bits) => Some(f64::from(f32::from_bits(bits))),
        Value::F64Bits(bits) => Some(f64::from_bits(bits)),
        Value::Exact(_) => None,
    };
    let exact = match (float, value.to_exact()) {
        (Some(x), _) if x.is_nan() => "NaN".to_owned(),
        (Some(x), _) if x.is_infinite() => if x > 0.0 { "+inf" } else { "-inf" }.to_owned(),
        (Some(x), _) if x == 0.0 && x.is_sign_negative() => "-0".to_owned(),
        (_, Ok(r)) if r.is_integer() => r.numer().to_string(),
        (_, Ok(r)) => rational_text(&r),
        (_, Err(_)) => return text.to_owned(),
    };
    if exact == text || (float.is_none() && text.contains('/')) {
        text.to_owned()
    } else {
        format!("{text} ({exact})")
    }
}
