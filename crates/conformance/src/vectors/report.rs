//! The report as text ([`CheckReport::render`]: a compact summary by
//! class, tag and level, then examples per class), as JSON
//! ([`CheckReport::to_json`]), and the exact form of a coordinate
//! ([`exact_form`]).

use super::classify::MismatchClass;
use super::format::rational_text;
use super::{Answer, CheckReport, Mismatch, Tally};
use crate::value::Value;
use serde_json::json;
use std::fmt;
use std::fmt::Write as _;

/// Summary lines wrap before this many characters.
const LINE_WIDTH: usize = 100;

impl CheckReport {
    /// The report as text, a dozen lines before the examples: the verdict
    /// and counts; what the selection skipped; a warning if any answer is
    /// out of range or names a micro-triangle that does not contain the
    /// point; mismatches by class (most dangerous first), the NaN cases
    /// apart; failing tags and levels only (`failing/cases`); unsupported,
    /// missing and unknown ids; then up to `examples_per_class` examples of
    /// each class, inputs in exact form.
    #[must_use]
    pub fn render(&self, examples_per_class: usize) -> String {
        let mut text = String::new();
        let _ = writeln!(
            text,
            "{}: {} cases, {} checked, {} match, {} mismatch, {} unsupported, {} missing, {} unknown ids: {}",
            self.function,
            self.cases,
            self.checked,
            self.matched,
            self.mismatches.len(),
            self.unsupported,
            self.missing,
            self.unknown.len(),
            if self.passed() { "PASS" } else { "FAIL" }
        );
        if self.skipped > 0 {
            let _ = writeln!(
                text,
                "skipped: {} cases not selected by {}",
                self.skipped,
                selection_text(self)
            );
        }
        if self.checked > 0 && self.matched == 0 {
            let _ = writeln!(text, "FAIL: no case answered with an index that matches");
        }
        let out_of_range = self.out_of_range();
        let wrong = self
            .by_class
            .get(&MismatchClass::WrongTriangle)
            .copied()
            .unwrap_or(0);
        if out_of_range > 0 {
            let _ = writeln!(
                text,
                "DANGER: {out_of_range} answers are >= 4^level: a micromap lookup with them reads past the end of the buffer"
            );
        }
        if wrong > 0 {
            let _ = writeln!(
                text,
                "DANGER: {wrong} answers name a micro-triangle that does not contain the point"
            );
        }
        if !self.by_class.is_empty() {
            let items = self
                .by_class
                .iter()
                .map(|(class, count)| format!("{class} {count}"));
            wrapped(&mut text, "by class: ", items);
        }
        if let Some(nan) = self.by_class.get(&MismatchClass::Nan) {
            let _ = writeln!(
                text,
                "nan: {nan} of the mismatches have a NaN input; NaN -> 0 is this project's reading of clamp (docs/vectors.md)"
            );
        }
        let failing_tags = self
            .by_tag
            .iter()
            .filter(|(_, tally)| tally.failing() > 0)
            .map(|(name, tally)| format!("{name} {}/{}", tally.failing(), tally.cases));
        wrapped(&mut text, "failing tags (failing/cases): ", failing_tags);
        let failing_levels = self
            .by_level
            .iter()
            .filter(|(_, tally)| tally.failing() > 0)
            .map(|(level, tally)| format!("{level}: {}/{}", tally.failing(), tally.cases));
        wrapped(
            &mut text,
            "failing levels (failing/cases): ",
            failing_levels,
        );
        if self.unsupported > 0 {
            let levels = self
                .by_level
                .iter()
                .filter(|(_, tally)| tally.unsupported > 0)
                .map(|(level, tally): (&u32, &Tally)| format!("{level}: {}", tally.unsupported));
            wrapped(&mut text, "unsupported by level: ", levels);
        }
        if self.missing > 0 {
            let _ = writeln!(
                text,
                "missing ids ({}): {}",
                self.missing,
                listed(&self.missing_ids, self.missing)
            );
        }
        if !self.unknown.is_empty() {
            let _ = writeln!(
                text,
                "unknown ids ({}): {}",
                self.unknown.len(),
                listed(&self.unknown, self.unknown.len())
            );
        }
        if examples_per_class > 0 {
            for (class, count) in &self.by_class {
                let shown = examples_per_class.min(*count);
                let _ = writeln!(
                    text,
                    "\n{class} ({count}; first {shown}): {}",
                    class.meaning()
                );
                let examples = self.mismatches.iter().filter(|m| m.class == *class);
                for mismatch in examples.take(examples_per_class) {
                    let _ = writeln!(text, "  {}", example_line(mismatch));
                }
            }
        }
        text
    }

    /// The report as one JSON object, for CI: `function`, `passed`,
    /// `cases`, `checked`, `skipped`, `matched`, `mismatched`,
    /// `unsupported`, `missing`, `unknown`, `out_of_range`, `by_class`
    /// (every class, summing to `mismatched`), `by_tag` and `by_level`
    /// (`{"cases", "mismatched", "missing", "unsupported"}` each),
    /// `missing_ids` and `unknown_ids` (the first 20), `selection`, and
    /// `examples` (up to `examples_per_class` per class).
    ///
    /// ```
    /// use micromap_index_conformance::vectors::{check, parse_answers, parse_vector_file};
    /// let vectors = parse_vector_file(br#"{"format": "micromap-index-vectors", "version": 1,
    ///   "function": "spec-exact", "cases": [
    ///     {"id": 0, "u": "1/4", "v": "1/4", "level": 1, "index": 1, "tags": ["shared-edge"]}]}"#).unwrap();
    /// let report = check(&vectors, &parse_answers(br#"{"id":0,"index":4}"#).unwrap());
    /// let json = report.to_json(1);
    /// assert_eq!((json["mismatched"].as_u64(), json["out_of_range"].as_u64()), (Some(1), Some(1)));
    /// assert_eq!(json["by_class"]["out-of-range"], 1);
    /// assert_eq!(json["examples"][0]["class"], "out-of-range");
    /// ```
    #[must_use]
    pub fn to_json(&self, examples_per_class: usize) -> serde_json::Value {
        let tally = |t: &Tally| json!({"cases": t.cases, "mismatched": t.mismatched, "missing": t.missing, "unsupported": t.unsupported});
        let by_class: serde_json::Map<String, serde_json::Value> = MismatchClass::ALL
            .iter()
            .map(|class| {
                let count = self.by_class.get(class).copied().unwrap_or(0);
                (class.name().to_owned(), json!(count))
            })
            .collect();
        let by_tag: serde_json::Map<String, serde_json::Value> = self
            .by_tag
            .iter()
            .map(|(name, t)| (name.clone(), tally(t)))
            .collect();
        let by_level: serde_json::Map<String, serde_json::Value> = self
            .by_level
            .iter()
            .map(|(level, t)| (level.to_string(), tally(t)))
            .collect();
        let mut examples = vec![];
        for class in MismatchClass::ALL {
            let of_class = self.mismatches.iter().filter(|m| m.class == class);
            for m in of_class.take(examples_per_class) {
                let (got, error) = match &m.got {
                    Answer::Index(index) => (json!(index), serde_json::Value::Null),
                    Answer::Refused(message) => (serde_json::Value::Null, json!(message)),
                    Answer::Unsupported => (serde_json::Value::Null, serde_json::Value::Null),
                };
                examples.push(json!({
                    "id": m.id, "level": m.level, "u": m.u, "v": m.v,
                    "u_exact": exact_form(&m.u), "v_exact": exact_form(&m.v),
                    "expected": m.expected, "got": got, "error": error,
                    "class": class.name(), "tags": m.tags,
                }));
            }
        }
        let unknown_ids: Vec<u64> = self
            .unknown
            .iter()
            .take(super::check::MAX_LISTED_IDS)
            .copied()
            .collect();
        json!({
            "function": self.function,
            "passed": self.passed(),
            "cases": self.cases,
            "checked": self.checked,
            "skipped": self.skipped,
            "matched": self.matched,
            "mismatched": self.mismatches.len(),
            "unsupported": self.unsupported,
            "missing": self.missing,
            "unknown": self.unknown.len(),
            "out_of_range": self.out_of_range(),
            "by_class": by_class,
            "by_tag": by_tag,
            "by_level": by_level,
            "missing_ids": self.missing_ids,
            "unknown_ids": unknown_ids,
            "selection": selection_text(self),
            "examples": examples,
        })
    }
}

/// The selection as command-line options (`everything` if none).
fn selection_text(report: &CheckReport) -> String {
    let selection = &report.selection;
    let mut parts = vec![];
    if let Some(levels) = &selection.levels {
        parts.push(format!("--levels {}..={}", levels.start(), levels.end()));
    }
    if !selection.tags.is_empty() {
        parts.push(format!("--tags {}", selection.tags.join(",")));
    }
    if !selection.exclude_tags.is_empty() {
        parts.push(format!(
            "--exclude-tags {}",
            selection.exclude_tags.join(",")
        ));
    }
    if parts.is_empty() {
        "everything".to_owned()
    } else {
        parts.join(" ")
    }
}

/// `items` after `label`, comma-separated, wrapped before [`LINE_WIDTH`];
/// nothing if there are none.
fn wrapped(text: &mut String, label: &str, items: impl Iterator<Item = String>) {
    let mut line = String::from(label);
    let mut first = true;
    for item in items {
        if !first && line.len() + item.len() + 2 > LINE_WIDTH {
            line.push(',');
            let _ = writeln!(text, "{line}");
            line = " ".repeat(label.len());
            first = true;
        }
        if !first {
            line.push_str(", ");
        }
        line.push_str(&item);
        first = false;
    }
    if line.len() > label.len() {
        let _ = writeln!(text, "{line}");
    }
}

/// The first ids (those stored), with `…` if there are more.
fn listed(ids: &[u64], total: usize) -> String {
    let shown: Vec<String> = ids
        .iter()
        .take(super::check::MAX_LISTED_IDS)
        .map(u64::to_string)
        .collect();
    let more = if total > shown.len() { ", …" } else { "" };
    format!("{}{more}", shown.join(", "))
}

fn example_line(m: &Mismatch) -> String {
    let got = match (&m.got, m.class) {
        (Answer::Index(index), MismatchClass::OutOfRange) => {
            format!(
                "{index} (>= 4^{} = {})",
                m.level,
                1u128 << (2 * m.level.min(32))
            )
        }
        (got, _) => got.to_string(),
    };
    format!(
        "id {} level {}: u = {}, v = {}: expected {}, got {got}  [{}]",
        m.id,
        m.level,
        exact_form(&m.u),
        exact_form(&m.v),
        m.expected,
        m.tags.join(", ")
    )
}

impl fmt::Display for CheckReport {
    /// [`CheckReport::render`] with 5 examples per class.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render(5))
    }
}

/// A coordinate as written plus its exact value: `0x3dffffff (16777215/134217728)`,
/// `0x7fc00000 (NaN)`, `0.375 (3/8)`; `p/q` text as is.
///
/// ```
/// use micromap_index_conformance::vectors::exact_form;
/// assert_eq!(exact_form("0x3e000000"), "0x3e000000 (1/8)");
/// assert_eq!(exact_form("0xff800000"), "0xff800000 (-inf)");
/// assert_eq!(exact_form("0x80000000"), "0x80000000 (-0)");
/// assert_eq!(exact_form("3/8"), "3/8");
/// assert_eq!(exact_form("0.375"), "0.375 (3/8)");
/// // Subnormals: the shortest decimal and the bits beside the exact form.
/// assert_eq!(exact_form("0x00000001"), "0x00000001 (1e-45 = 1/2^149)");
/// assert_eq!(
///     exact_form("1/713623846352979940529142984724747568191373312"),
///     "1/713623846352979940529142984724747568191373312 (1/2^149 = 1e-45, binary32 0x00000001)"
/// );
/// ```
#[must_use]
pub fn exact_form(text: &str) -> String {
    let Ok(value) = Value::parse(text) else {
        return text.to_owned();
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
    if let Some(subnormal) = subnormal_f32(&value) {
        let short = power_of_two_form(&value).unwrap_or(exact);
        return match value {
            Value::Exact(_) => format!(
                "{text} ({short} = {subnormal:?}, binary32 0x{:08x})",
                subnormal.to_bits()
            ),
            _ => format!("{text} ({subnormal:?} = {short})"),
        };
    }
    if exact == text || (float.is_none() && text.contains('/')) {
        text.to_owned()
    } else {
        format!("{text} ({exact})")
    }
}

/// The value as a binary32 subnormal, if it is exactly one.
fn subnormal_f32(value: &Value) -> Option<f32> {
    value.to_f32().ok().filter(|x| x.is_subnormal())
}

/// `p/2^k` (or `-p/2^k`) when the denominator is a power of two above 2^24,
/// so the 45-digit denominators of subnormals read at a glance.
fn power_of_two_form(value: &Value) -> Option<String> {
    let exact = value.to_exact().ok()?;
    let denominator = exact.denom();
    let bits = denominator.bits();
    if bits <= 25 || denominator != &(num_bigint::BigInt::from(1) << (bits - 1)) {
        return None;
    }
    Some(format!("{}/2^{}", exact.numer(), bits - 1))
}
