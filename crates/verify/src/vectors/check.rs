//! The check: every case's outcome against the answers, tallied per tag
//! and per level ([`check`], [`CheckReport`]).

use super::{Answer, Answers, VectorFile};
use std::collections::{BTreeMap, BTreeSet};

/// Cases and failures of one tag or level.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Tally {
    /// Cases with this tag (or level).
    pub cases: usize,
    /// Of those, answered with a different index or refused.
    pub mismatched: usize,
    /// Of those, not answered at all.
    pub missing: usize,
}

/// One case answered wrongly (or refused).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mismatch {
    /// The case's id.
    pub id: u64,
    /// The case's level.
    pub level: u32,
    /// `u` as written in the vector file.
    pub u: String,
    /// `v` as written in the vector file.
    pub v: String,
    /// The case's tags.
    pub tags: Vec<String>,
    /// The expected index.
    pub expected: u64,
    /// What the implementation answered.
    pub got: Answer,
}

/// The outcome of [`check`]; [`CheckReport::render`] (or `Display`) prints
/// it grouped by tag.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CheckReport {
    /// The vector file's function.
    pub function: String,
    /// Cases in the vector file.
    pub cases: usize,
    /// Cases answered with the expected index.
    pub matched: usize,
    /// Cases answered otherwise, in id order.
    pub mismatches: Vec<Mismatch>,
    /// Ids of cases without an answer, in order.
    pub missing: Vec<u64>,
    /// Ids answered that are not in the vector file, in order.
    pub unknown: Vec<u64>,
    /// Per tag (in name order).
    pub by_tag: BTreeMap<String, Tally>,
    /// Per level.
    pub by_level: BTreeMap<u32, Tally>,
}

/// Compares `answers` with the expected indices of `vectors`.
///
/// ```
/// use micromap_index_verify::vectors::{check, parse_answers, parse_vector_file};
/// let vectors = parse_vector_file(br#"{"format": "micromap-index-vectors", "version": 1,
///   "function": "spec-f32", "cases": [
///     {"id": 0, "u": "0x3e000000", "v": "0x3dffffff", "level": 2, "index": 1, "tags": ["rounding-window"]},
///     {"id": 1, "u": "0x3e800000", "v": "0x3e800000", "level": 2, "index": 5, "tags": ["vertex"]}]}"#).unwrap();
/// let report = check(&vectors, &parse_answers(b"{\"id\":0,\"index\":0}\n{\"id\":9,\"index\":0}").unwrap());
/// assert!(!report.passed());
/// assert_eq!(report.mismatches[0].id, 0);
/// assert_eq!((report.missing.as_slice(), report.unknown.as_slice()), (&[1][..], &[9][..]));
/// assert!(report.to_string().contains("u = 0x3e000000 (1/8)"));
/// ```
pub fn check(vectors: &VectorFile, answers: &Answers) -> CheckReport {
    let mut report = CheckReport {
        function: vectors.function.clone(),
        cases: vectors.cases.len(),
        matched: 0,
        mismatches: vec![],
        missing: vec![],
        unknown: vec![],
        by_tag: BTreeMap::new(),
        by_level: BTreeMap::new(),
    };
    for case in &vectors.cases {
        let outcome = match answers.by_id.get(&case.id) {
            Some(Answer::Index(index)) if *index == case.index => Outcome::Matched,
            Some(answer) => Outcome::Mismatched(answer.clone()),
            None => Outcome::Missing,
        };
        report
            .by_level
            .entry(case.level)
            .or_default()
            .count(&outcome);
        let distinct_tags: BTreeSet<&String> = case.tags.iter().collect();
        for name in distinct_tags {
            report
                .by_tag
                .entry(name.clone())
                .or_default()
                .count(&outcome);
        }
        match outcome {
            Outcome::Matched => report.matched += 1,
            Outcome::Mismatched(got) => report.mismatches.push(Mismatch {
                id: case.id,
                level: case.level,
                u: case.u.clone(),
                v: case.v.clone(),
                tags: case.tags.clone(),
                expected: case.index,
                got,
            }),
            Outcome::Missing => report.missing.push(case.id),
        }
    }
    let ids: BTreeSet<u64> = vectors.cases.iter().map(|c| c.id).collect();
    report.unknown = answers
        .by_id
        .keys()
        .filter(|id| !ids.contains(id))
        .copied()
        .collect();
    report
}

/// How one case fared.
enum Outcome {
    Matched,
    Mismatched(Answer),
    Missing,
}

impl Tally {
    fn count(&mut self, outcome: &Outcome) {
        self.cases += 1;
        match outcome {
            Outcome::Matched => {}
            Outcome::Mismatched(_) => self.mismatched += 1,
            Outcome::Missing => self.missing += 1,
        }
    }
}
