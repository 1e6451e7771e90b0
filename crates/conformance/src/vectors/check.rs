//! The check: every selected case's outcome against the answers, tallied
//! per tag, per level and per mismatch class ([`check`], [`Checker`],
//! [`CheckReport`]). [`Checker`] takes one case at a time, so a file can be
//! checked while it is read ([`check_reader`]): the memory is the answers,
//! the mismatches and one case.

use super::classify::{classify, MismatchClass};
use super::read::{read_vector_file, VectorError};
use super::{tag, Answer, Answers, Case, VectorFile};
use std::collections::{BTreeMap, BTreeSet};
use std::io::Read;
use std::ops::RangeInclusive;

/// Cases and failures of one tag or level (selected cases only).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Tally {
    /// Selected cases with this tag (or level).
    pub cases: usize,
    /// Of those, answered with a different index or refused.
    pub mismatched: usize,
    /// Of those, not answered at all.
    pub missing: usize,
    /// Of those, answered `"unsupported": true`.
    pub unsupported: usize,
}

impl Tally {
    /// Mismatched or missing: the cases that fail the check.
    #[must_use]
    pub fn failing(&self) -> usize {
        self.mismatched + self.missing
    }
}

/// One case answered wrongly (or refused), with the class of the difference.
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
    /// Why it differs ([`classify`]).
    pub class: MismatchClass,
}

/// Which cases of a file a check covers: a level range and tag filters.
/// The default selects every case.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Selection {
    /// Only cases whose level is in this range (`None`: every level).
    pub levels: Option<RangeInclusive<u32>>,
    /// If not empty, only cases carrying at least one of these tags.
    pub tags: Vec<String>,
    /// No case carrying any of these tags.
    pub exclude_tags: Vec<String>,
}

impl Selection {
    /// Whether the selection covers `case`.
    ///
    /// ```
    /// use micromap_index_conformance::vectors::{Case, Selection};
    /// let case = Case { id: 0, u: "1/4".into(), v: "1/4".into(), level: 13, index: 0,
    ///     tags: vec!["vertex".into(), "nan".into()], u_decimal: None, v_decimal: None };
    /// assert!(Selection::default().selects(&case));
    /// assert!(!Selection { levels: Some(0..=12), ..Selection::default() }.selects(&case));
    /// assert!(Selection { tags: vec!["vertex".into()], ..Selection::default() }.selects(&case));
    /// assert!(!Selection { exclude_tags: vec!["nan".into()], ..Selection::default() }.selects(&case));
    /// ```
    #[must_use]
    pub fn selects(&self, case: &Case) -> bool {
        let has = |names: &[String]| names.iter().any(|name| case.tags.contains(name));
        self.levels
            .as_ref()
            .map_or(true, |levels| levels.contains(&case.level))
            && (self.tags.is_empty() || has(&self.tags))
            && !has(&self.exclude_tags)
    }

    /// Whether it selects every case.
    #[must_use]
    pub fn is_everything(&self) -> bool {
        self.levels.is_none() && self.tags.is_empty() && self.exclude_tags.is_empty()
    }
}

/// Ids listed in a report before it abbreviates.
pub const MAX_LISTED_IDS: usize = 20;

/// The outcome of a check; [`CheckReport::render`] (or `Display`) prints
/// it, [`CheckReport::to_json`] gives it as one JSON object.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CheckReport {
    /// The vector file's function.
    pub function: String,
    /// Cases in the vector file.
    pub cases: usize,
    /// Cases the selection covers (`checked + skipped == cases`).
    pub checked: usize,
    /// Cases the selection leaves out.
    pub skipped: usize,
    /// Selected cases answered with the expected index.
    pub matched: usize,
    /// Selected cases answered `"unsupported": true` (not failures).
    pub unsupported: usize,
    /// Selected cases answered otherwise, in id order.
    pub mismatches: Vec<Mismatch>,
    /// Selected cases without an answer.
    pub missing: usize,
    /// The first [`MAX_LISTED_IDS`] of their ids, in order.
    pub missing_ids: Vec<u64>,
    /// Ids answered that are not in the vector file, in order.
    pub unknown: Vec<u64>,
    /// Per tag (in name order).
    pub by_tag: BTreeMap<String, Tally>,
    /// Per level.
    pub by_level: BTreeMap<u32, Tally>,
    /// Mismatches per class (summing to `mismatches.len()`).
    pub by_class: BTreeMap<MismatchClass, usize>,
    /// The selection the check ran with.
    pub selection: Selection,
}

impl CheckReport {
    /// Every selected case answered with its expected index or
    /// `"unsupported"`, at least one matched, and no id outside the file.
    #[must_use]
    pub fn passed(&self) -> bool {
        self.mismatches.is_empty()
            && self.missing == 0
            && self.unknown.is_empty()
            && self.matched > 0
    }

    /// Mismatches whose answer is `>= 4^level`.
    #[must_use]
    pub fn out_of_range(&self) -> usize {
        self.by_class
            .get(&MismatchClass::OutOfRange)
            .copied()
            .unwrap_or(0)
    }
}

/// Checks one case at a time: [`Checker::case`] for each case of the file,
/// then [`Checker::finish`]. Holds the answers, the mismatches so far and
/// the tallies; never the file.
#[derive(Debug)]
pub struct Checker<'a> {
    answers: &'a Answers,
    report: CheckReport,
    /// Ids of the file's cases that have an answer (to find unknown ids).
    answered_in_file: BTreeSet<u64>,
}

impl<'a> Checker<'a> {
    /// A checker of `answers` over the cases `selection` covers.
    #[must_use]
    pub fn new(answers: &'a Answers, selection: Selection) -> Checker<'a> {
        Checker {
            answers,
            report: CheckReport {
                function: String::new(),
                cases: 0,
                checked: 0,
                skipped: 0,
                matched: 0,
                unsupported: 0,
                mismatches: vec![],
                missing: 0,
                missing_ids: vec![],
                unknown: vec![],
                by_tag: BTreeMap::new(),
                by_level: BTreeMap::new(),
                by_class: BTreeMap::new(),
                selection,
            },
            answered_in_file: BTreeSet::new(),
        }
    }

    /// Counts one case of the file.
    pub fn case(&mut self, case: Case) {
        let report = &mut self.report;
        report.cases += 1;
        let answer = self.answers.by_id.get(&case.id);
        if answer.is_some() {
            self.answered_in_file.insert(case.id);
        }
        if !report.selection.selects(&case) {
            report.skipped += 1;
            return;
        }
        report.checked += 1;
        let outcome = match answer {
            Some(Answer::Index(index)) if *index == case.index => Outcome::Matched,
            Some(Answer::Unsupported) => Outcome::Unsupported,
            Some(_) => Outcome::Mismatched,
            None => Outcome::Missing,
        };
        report
            .by_level
            .entry(case.level)
            .or_default()
            .count(outcome);
        let distinct_tags: BTreeSet<&String> = case.tags.iter().collect();
        for name in distinct_tags {
            report
                .by_tag
                .entry(name.clone())
                .or_default()
                .count(outcome);
        }
        match (outcome, answer) {
            (Outcome::Matched, _) => report.matched += 1,
            (Outcome::Unsupported, _) => report.unsupported += 1,
            (Outcome::Mismatched, Some(got)) => report.mismatches.push(Mismatch {
                id: case.id,
                level: case.level,
                u: case.u,
                v: case.v,
                tags: case.tags,
                expected: case.index,
                got: got.clone(),
                // Classified in `finish`, once the function is known.
                class: MismatchClass::Refused,
            }),
            (Outcome::Missing | Outcome::Mismatched, _) => {
                report.missing += 1;
                if report.missing_ids.len() < MAX_LISTED_IDS {
                    report.missing_ids.push(case.id);
                }
            }
        }
    }

    /// The report for a file of `function`: the mismatches classified, the
    /// unknown ids found.
    #[must_use]
    pub fn finish(mut self, function: &str) -> CheckReport {
        let report = &mut self.report;
        function.clone_into(&mut report.function);
        for mismatch in &mut report.mismatches {
            mismatch.class = classify(
                function,
                &mismatch.u,
                &mismatch.v,
                mismatch.level,
                mismatch.expected,
                &mismatch.got,
            );
            *report.by_class.entry(mismatch.class).or_default() += 1;
        }
        report.unknown = self
            .answers
            .by_id
            .keys()
            .filter(|id| !self.answered_in_file.contains(id))
            .copied()
            .collect();
        self.report
    }
}

/// Compares `answers` with the expected indices of every case of `vectors`.
///
/// ```
/// use micromap_index_conformance::vectors::{check, parse_answers, parse_vector_file, MismatchClass};
/// let vectors = parse_vector_file(br#"{"format": "micromap-index-vectors", "version": 1,
///   "function": "spec-f32", "cases": [
///     {"id": 0, "u": "0x3e000000", "v": "0x3dffffff", "level": 2, "index": 1, "tags": ["rounding-window"]},
///     {"id": 1, "u": "0x3e800000", "v": "0x3e800000", "level": 2, "index": 5, "tags": ["vertex"]}]}"#).unwrap();
/// let report = check(&vectors, &parse_answers(b"{\"id\":0,\"index\":0}\n{\"id\":9,\"index\":0}").unwrap());
/// assert!(!report.passed());
/// assert_eq!(report.mismatches[0].id, 0);
/// // Index 0 is the exact reading's answer; the binary32 reference says 1.
/// assert_eq!(report.mismatches[0].class, MismatchClass::RoundingWindow);
/// assert_eq!((report.missing_ids.as_slice(), report.unknown.as_slice()), (&[1][..], &[9][..]));
/// assert!(report.to_string().contains("u = 0x3e000000 (1/8)"));
/// ```
#[must_use]
pub fn check(vectors: &VectorFile, answers: &Answers) -> CheckReport {
    check_selected(vectors, answers, Selection::default())
}

/// [`check`] over the cases `selection` covers; the others count as
/// skipped.
#[must_use]
pub fn check_selected(
    vectors: &VectorFile,
    answers: &Answers,
    selection: Selection,
) -> CheckReport {
    let mut checker = Checker::new(answers, selection);
    for case in &vectors.cases {
        checker.case(case.clone());
    }
    checker.finish(&vectors.function)
}

/// [`check_selected`] on a vector file read from `reader` one case at a
/// time ([`read_vector_file`]): memory for the answers, the mismatches and
/// one case, whatever the file's size. A malformed file is an error, and so
/// is a file of which `selection` covers no case (nothing was checked).
///
/// ```
/// use micromap_index_conformance::vectors::{check_reader, parse_answers, Selection};
/// let file = br#"{"format": "micromap-index-vectors", "version": 1, "function": "spec-f32", "cases": [
///     {"id": 0, "u": "0x3e800000", "v": "0x3e800000", "level": 2, "index": 5, "tags": ["vertex"]},
///     {"id": 1, "u": "0x3e800000", "v": "0x3e800000", "level": 13, "index": 21845, "tags": ["vertex"]}]}"#;
/// let answers = parse_answers(b"{\"id\":0,\"index\":5}\n{\"id\":1,\"unsupported\":true}").unwrap();
/// let report = check_reader(&file[..], &answers, Selection::default()).unwrap();
/// assert!(report.passed());
/// assert_eq!((report.matched, report.unsupported), (1, 1));
/// let capped = Selection { levels: Some(0..=12), ..Selection::default() };
/// let report = check_reader(&file[..], &answers, capped).unwrap();
/// assert_eq!((report.checked, report.skipped, report.unsupported), (1, 1, 0));
/// let none = Selection { levels: Some(20..=30), ..Selection::default() };
/// assert!(check_reader(&file[..], &answers, none).is_err());
/// ```
pub fn check_reader<R: Read>(
    reader: R,
    answers: &Answers,
    selection: Selection,
) -> Result<CheckReport, VectorError> {
    let mut checker = Checker::new(answers, selection);
    let header = read_vector_file(reader, |case| checker.case(case))?;
    let report = checker.finish(&header.function);
    if report.checked == 0 {
        return Err(VectorError::Schema(format!(
            "the selection covers none of the file's {} cases: nothing was checked",
            report.cases
        )));
    }
    Ok(report)
}

/// Whether `name` is a tag this crate writes ([`tag::ALL`]).
#[must_use]
pub fn is_known_tag(name: &str) -> bool {
    tag::ALL.contains(&name)
}

/// How one selected case fared.
#[derive(Clone, Copy)]
enum Outcome {
    Matched,
    Unsupported,
    Mismatched,
    Missing,
}

impl Tally {
    fn count(&mut self, outcome: Outcome) {
        self.cases += 1;
        match outcome {
            Outcome::Matched => {}
            Outcome::Unsupported => self.unsupported += 1,
            Outcome::Mismatched => self.mismatched += 1,
            Outcome::Missing => self.missing += 1,
        }
    }
}
