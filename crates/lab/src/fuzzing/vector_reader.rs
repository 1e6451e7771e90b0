//! The body of the fuzz target `vector_reader`, replayed on stable by
//! `crates/lab/tests/fuzz_corpus.rs`.

#[allow(clippy::wildcard_imports)]
use super::*;

/// The conformance-vector readers on arbitrary bytes:
/// [`vectors::parse_vector_file`] and [`vectors::parse_answers`] never
/// panic, and what they accept survives a write-and-read round trip.
///
/// Decoding: the bytes before the first NUL byte are the vector file, the
/// bytes after it the answers; without a NUL, all the bytes are given to
/// both readers. Checks:
///
/// * an accepted vector file equals the result of reading its
///   [`to_json_text`](vectors::VectorFile::to_json_text) again, and so do
///   accepted answers and their
///   [`to_json_lines`](vectors::Answers::to_json_lines);
/// * on an accepted file, the answers of `spec-f32` and `fixed-mirror`
///   ([`vectors::compute_answers`]) are equal, read back equal, and
///   [`vectors::check`] of them (and of the accepted answers, if any) adds
///   up: every case is matched, mismatched or missing, the tallies by level
///   count every case once, and rendering the report does not panic.
///
/// ```
/// use micromap_index_lab::fuzzing::vector_reader;
/// let file = br#"{"format": "micromap-index-vectors", "version": 1, "function": "spec-f32",
///   "cases": [{"id": 7, "u": "0x3e800000", "v": "0x3e800000", "level": 2, "index": 5, "tags": ["vertex"]}]}"#;
/// let mut data = file.to_vec();
/// data.extend(b"\0{\"id\": 7, \"index\": 5}\n");
/// vector_reader(&data);
/// vector_reader(b"\xff{");
/// ```
///
/// # Panics
///
/// When a property fails.
pub fn vector_reader(data: &[u8]) {
    let (file_bytes, answer_bytes) = match data.iter().position(|&b| b == 0) {
        Some(nul) => (&data[..nul], &data[nul + 1..]),
        None => (data, data),
    };
    let file = vectors::parse_vector_file(file_bytes).ok();
    if let Some(file) = &file {
        let text = file.to_json_text();
        let again = vectors::parse_vector_file(text.as_bytes());
        assert_eq!(
            again.as_ref(),
            Ok(file),
            "vector file {file:?} writes as {text:?}, which reads back differently"
        );
    }
    let answers = vectors::parse_answers(answer_bytes).ok();
    if let Some(answers) = &answers {
        check_answers_round_trip(answers);
    }
    let Some(file) = file else {
        return;
    };
    let source = |name| vectors::AnswerSource::from_name(name);
    if let (Some(spec_f32), Some(mirror)) = (source("spec-f32"), source("fixed-mirror")) {
        let by_spec = vectors::compute_answers(spec_f32, &file);
        let by_mirror = vectors::compute_answers(mirror, &file);
        let neutral = |answers: &vectors::Answers, variant| -> Vec<(u64, String)> {
            answers
                .by_id
                .iter()
                .map(|(id, answer)| (*id, naming_no_variant(&answer.to_string(), variant)))
                .collect()
        };
        assert_eq!(
            neutral(&by_spec, Variant::SpecF32),
            neutral(&by_mirror, Variant::SpecF32ByIntegers),
            "spec-f32 and fixed-mirror answer {file:?} differently"
        );
        check_answers_round_trip(&by_spec);
        check_report_adds_up(&file, &by_spec);
    }
    if let Some(answers) = &answers {
        check_report_adds_up(&file, answers);
    }
}

/// Answers read back from their own JSON lines unchanged.
fn check_answers_round_trip(answers: &vectors::Answers) {
    let lines = answers.to_json_lines();
    let again = vectors::parse_answers(lines.as_bytes());
    assert_eq!(
        again.as_ref(),
        Ok(answers),
        "answers {answers:?} write as {lines:?}, which read back differently"
    );
}

/// The counts of [`vectors::check`] are consistent.
fn check_report_adds_up(file: &vectors::VectorFile, answers: &vectors::Answers) {
    let report = vectors::check(file, answers);
    let accounted = report.matched + report.unsupported + report.mismatches.len() + report.missing;
    let by_level: usize = report.by_level.values().map(|tally| tally.cases).sum();
    let by_class: usize = report.by_class.values().sum();
    assert!(
        report.cases == file.cases.len()
            && report.checked == report.cases
            && accounted == report.cases
            && by_level == report.cases
            && by_class == report.mismatches.len()
            && report.passed()
                == (report.matched > 0
                    && accounted == report.matched + report.unsupported
                    && report.unknown.is_empty()),
        "check of {file:?} against {answers:?} does not add up: {report:?}"
    );
    let _ = report.render(3);
    let _ = report.to_json(3);
}
