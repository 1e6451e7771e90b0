//! The conformance vectors (`reference/vectors/`, `src/vectors.rs`): the
//! committed files are exactly what the generator writes, every expected
//! index agrees with every implementation of its function (including the C
//! reference), the tags are true, and `check` and the readers behave.
//!
//! Regenerate the files after a deliberate change with
//! `cargo run --release -p micromap-index-lab --bin micromap-lab -- vectors --out reference/vectors`.

use micromap_index::{spec, uv2index, Level, SpecLevel};
use micromap_index_c_reference::spec_index;
use micromap_index_lab::value::Value;
use micromap_index_lab::vectors::{
    check, check_reader, compute_answers, exact_form, generate_sets, micro_triangle_contains,
    parse_answers, parse_vector_file, tag, Answer, AnswerSource, Answers, Case, MismatchClass,
    Selection, VectorError, VectorFile, VectorSet, LEVELS,
};
use num_rational::BigRational;
use std::collections::BTreeSet;
use std::path::PathBuf;

const REGENERATE: &str = "cargo run --release -p micromap-index-lab --bin micromap-lab -- vectors --out reference/vectors";

/// The committed files must stay reviewable.
const MAX_TOTAL_BYTES: u64 = 5_000_000;

fn vectors_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../reference/vectors")
}

fn committed(set: VectorSet) -> VectorFile {
    let path = vectors_dir().join(set.file_name());
    let bytes = std::fs::read(&path)
        .unwrap_or_else(|e| panic!("{}: {e}; regenerate with `{REGENERATE}`", path.display()));
    parse_vector_file(&bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn has(case: &Case, name: &str) -> bool {
    case.tags.iter().any(|t| t == name)
}

/// The case's inputs as exact bits or rationals, for failure messages.
fn shown(case: &Case) -> String {
    format!(
        "id {} level {}: u = {}, v = {} (expected {}) [{}]",
        case.id,
        case.level,
        exact_form(&case.u),
        exact_form(&case.v),
        case.index,
        case.tags.join(", ")
    )
}

fn f32_of(text: &str) -> f32 {
    Value::parse(text).unwrap().to_f32().unwrap()
}

fn exact_of(text: &str) -> BigRational {
    Value::parse(text).unwrap().to_exact().unwrap()
}

#[test]
fn committed_files_are_what_the_generator_writes() {
    let mut expected_names = BTreeSet::new();
    for set in generate_sets() {
        let name = format!("{}.json", set.function);
        let path = vectors_dir().join(&name);
        let generated = set.to_json_text();
        let committed = std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("{}: {e}; regenerate with `{REGENERATE}`", path.display()));
        if committed != generated {
            let first_difference = committed
                .lines()
                .zip(generated.lines())
                .enumerate()
                .find(|(_, (a, b))| a != b);
            match first_difference {
                Some((n, (old, new))) => panic!(
                    "{} differs from the generator at line {}:\n  committed: {old}\n  generated: {new}\n\
                     if the change is intended, regenerate with `{REGENERATE}`",
                    path.display(),
                    n + 1
                ),
                None => panic!(
                    "{} differs from the generator in length ({} vs {} lines); \
                     if intended, regenerate with `{REGENERATE}`",
                    path.display(),
                    committed.lines().count(),
                    generated.lines().count()
                ),
            }
        }
        expected_names.insert(name);
    }
    let mut names = BTreeSet::new();
    let mut total_bytes = 0;
    for entry in std::fs::read_dir(vectors_dir()).unwrap() {
        let entry = entry.unwrap();
        names.insert(entry.file_name().to_string_lossy().into_owned());
        total_bytes += entry.metadata().unwrap().len();
    }
    assert_eq!(
        names, expected_names,
        "reference/vectors/ holds files the generator does not write"
    );
    assert!(
        total_bytes < MAX_TOTAL_BYTES,
        "reference/vectors/ is {total_bytes} bytes, over {MAX_TOTAL_BYTES}"
    );
}

#[test]
fn generation_is_deterministic() {
    assert_eq!(generate_sets(), generate_sets());
}

#[test]
fn every_level_has_every_class() {
    let always = [
        tag::VERTEX,
        tag::EDGE_MIDPOINT,
        tag::HORIZONTAL_EDGE,
        tag::VERTICAL_EDGE,
        tag::DIAGONAL_EDGE,
        tag::CENTROID,
        tag::UPRIGHT,
        tag::ULP_NEIGHBOUR,
        tag::NEAR_VERTEX,
        tag::NEAR_HORIZONTAL_EDGE,
        tag::NEAR_VERTICAL_EDGE,
        tag::NEAR_DIAGONAL_EDGE,
        tag::ROUNDING_WINDOW_IGNORED,
        tag::ROUNDING_WINDOW_EDGE,
        tag::SUBNORMAL,
        tag::RANDOM,
    ];
    // Level 0 has one micro-triangle: no upside-down ones, and the diagonal
    // test is never used, so binary32 rounding cannot change an index.
    let from_level_1 = [tag::UPSIDE_DOWN, tag::ROUNDING_WINDOW];
    let clamping = [
        tag::CLAMP,
        tag::NEGATIVE,
        tag::ABOVE_ONE,
        tag::SUM_ABOVE_ONE,
    ];
    let binary32_only = [
        tag::NAN,
        tag::SIGNALLING_NAN,
        tag::INFINITY,
        tag::SIGNED_ZERO,
    ];
    for set in VectorSet::ALL {
        let file = committed(set);
        let mut required: Vec<&str> = always.to_vec();
        if set != VectorSet::Uv2indexExact {
            required.extend(clamping);
        }
        if set == VectorSet::SpecF32 {
            required.extend(binary32_only);
        }
        for level in LEVELS {
            let mut wanted = required.clone();
            if level >= 1 {
                wanted.extend(from_level_1);
            }
            for name in wanted {
                assert!(
                    file.cases.iter().any(|c| c.level == level && has(c, name)),
                    "{}: no case tagged {name} at level {level}",
                    file.function
                );
            }
        }
        let known: BTreeSet<&str> = tag::ALL.into_iter().collect();
        for case in &file.cases {
            assert!(
                case.tags.iter().all(|t| known.contains(t.as_str())),
                "{}: unknown tag in {}",
                file.function,
                shown(case)
            );
        }
        let ids: Vec<u64> = file.cases.iter().map(|c| c.id).collect();
        assert!(
            ids.iter().copied().eq(0..ids.len() as u64),
            "ids are 0, 1, ..."
        );
    }
}

#[test]
fn spec_f32_cases_agree_with_every_binary32_implementation() {
    let file = committed(VectorSet::SpecF32);
    assert_eq!(file.function, "spec-f32");
    for case in &file.cases {
        assert!(case.u.len() == 10 && case.v.len() == 10, "{}", shown(case));
        let (u, v) = (f32_of(&case.u), f32_of(&case.v));
        let level = case.level;
        let answers = [
            ("spec::index_f32", spec::reference_bits_f32(u, v, level)),
            (
                "spec::reference_bits_f32_by_integers",
                spec::reference_bits_f32_by_integers(u, v, level),
            ),
            ("C reference", spec_index(u, v, level)),
        ];
        for (name, index) in answers {
            assert_eq!(u64::from(index), case.index, "{name}: {}", shown(case));
        }
        // Flushing subnormal inputs to zero (as shaders may) changes nothing:
        // a subnormal scales to a fraction far below the rounding window.
        let flush = |x: f32| if x.is_subnormal() { 0.0 } else { x };
        assert_eq!(
            u64::from(spec::reference_bits_f32(flush(u), flush(v), level)),
            case.index,
            "flush to zero: {}",
            shown(case)
        );
        // The derived tags are true.
        let finite_in_triangle = u.is_finite()
            && v.is_finite()
            && u >= 0.0
            && v >= 0.0
            && exact_of(&case.u) + exact_of(&case.v) <= BigRational::from_integer(1.into());
        assert_eq!(
            has(case, tag::CLAMP),
            !finite_in_triangle,
            "{}",
            shown(case)
        );
        assert_eq!(
            has(case, tag::NAN),
            u.is_nan() || v.is_nan(),
            "{}",
            shown(case)
        );
        let signalling = |x: f32| x.is_nan() && x.to_bits() & 0x0040_0000 == 0;
        assert_eq!(
            has(case, tag::SIGNALLING_NAN),
            signalling(u) || signalling(v),
            "{}",
            shown(case)
        );
        assert_eq!(
            has(case, tag::SUBNORMAL),
            u.is_subnormal() || v.is_subnormal(),
            "{}",
            shown(case)
        );
        if u.is_finite() && v.is_finite() {
            let lv = Level::new(level).unwrap();
            let exact = u64::from(spec::index_real(
                &exact_of(&case.u),
                &exact_of(&case.v),
                SpecLevel::try_from(lv).unwrap(),
            ));
            assert_eq!(
                exact != case.index,
                has(case, tag::ROUNDING_WINDOW),
                "binary32 differs from exact exactly on rounding-window cases: {} (exact {exact})",
                shown(case)
            );
        }
    }
}

#[test]
fn spec_exact_cases_agree_with_the_exact_implementations() {
    let file = committed(VectorSet::SpecExact);
    assert_eq!(file.function, "spec-exact");
    for case in &file.cases {
        assert!(
            case.u.contains('/') && case.v.contains('/'),
            "{}",
            shown(case)
        );
        let (u, v) = (exact_of(&case.u), exact_of(&case.v));
        let level = Level::new(case.level).unwrap();
        let cell = micromap_index::internals::cell_real_ref(&u, &v, level);
        let by_big_rational =
            spec::index_from_cell(cell.iu as u32, cell.iv as u32, cell.diagonal, case.level);
        let answers = [
            (
                "spec::index_real",
                u64::from(spec::index_real(
                    &u,
                    &v,
                    SpecLevel::try_from(level).unwrap(),
                )),
            ),
            (
                "micromap_index::internals::cell_real_ref",
                u64::from(by_big_rational),
            ),
            (
                "spec::wide_index_real",
                spec::wide_index_real(&u, &v, level),
            ),
        ];
        for (name, index) in answers {
            assert_eq!(index, case.index, "{name}: {}", shown(case));
        }
        if !has(case, tag::CLAMP) {
            assert_eq!(
                uv2index::index_real(&u, &v, level),
                Ok(case.index),
                "the walk equals the spec over the reals: {}",
                shown(case)
            );
        }
    }
}

#[test]
fn uv2index_cases_agree_with_the_exact_walks() {
    let file = committed(VectorSet::Uv2indexExact);
    assert_eq!(file.function, "uv2index-exact");
    for case in &file.cases {
        let (u, v) = (exact_of(&case.u), exact_of(&case.v));
        let level = Level::new(case.level).unwrap();
        // Promised: every point is exactly a binary32 value.
        let (u32_, v32) = (f32_of(&case.u), f32_of(&case.v));
        let answers = [
            ("uv2index::index_real", uv2index::index_real(&u, &v, level)),
            (
                "internals::index_real_ref",
                micromap_index::internals::index_real_ref(&u, &v, level),
            ),
            (
                "uv2index::exact_index_f32",
                uv2index::exact_index_f32(u32_, v32, level),
            ),
            (
                "spec::index_real",
                Ok(u64::from(spec::index_real(
                    &u,
                    &v,
                    SpecLevel::try_from(level).unwrap(),
                ))),
            ),
        ];
        for (name, index) in answers {
            assert_eq!(index, Ok(case.index), "{name}: {}", shown(case));
        }
        assert!(!has(case, tag::CLAMP), "{}", shown(case));
    }
}

/// The correct answers for a file, as another implementation would print them.
fn correct_answers(file: &VectorFile) -> Answers {
    let mut answers = Answers::default();
    for case in &file.cases {
        answers.by_id.insert(case.id, Answer::Index(case.index));
    }
    answers
}

#[test]
fn check_passes_correct_answers_and_pins_down_wrong_ones() {
    for set in VectorSet::ALL {
        let file = committed(set);
        let right = correct_answers(&file);
        let report = check(&file, &right);
        assert!(report.passed(), "{report}");
        assert_eq!(report.matched, file.cases.len());
        // The crate's own function for the set answers it correctly too.
        let own = compute_answers(AnswerSource::Variant(set.variant()), &file);
        assert_eq!(own, right, "{}", file.function);

        // One perturbed answer: reported under exactly that case's tags.
        let victim = &file.cases[file.cases.len() / 2];
        let mut wrong = right.clone();
        wrong
            .by_id
            .insert(victim.id, Answer::Index(victim.index ^ 1));
        let report = check(&file, &wrong);
        assert!(!report.passed());
        assert_eq!(report.mismatches.len(), 1, "{report}");
        assert_eq!(report.mismatches[0].id, victim.id);
        assert_eq!(report.mismatches[0].got, Answer::Index(victim.index ^ 1));
        for (name, tally) in &report.by_tag {
            let expected = usize::from(victim.tags.contains(name));
            assert_eq!(tally.mismatched, expected, "tag {name}: {report}");
        }
        assert_eq!(report.by_class.values().sum::<usize>(), 1, "{report}");
        let text = report.render(3);
        assert!(
            text.contains(&format!("id {} level {}", victim.id, victim.level)),
            "{text}"
        );
        assert!(text.contains(&exact_form(&victim.u)), "{text}");

        // Missing, refused and unknown ids.
        let mut partial = right.clone();
        let first = file.cases[0].id;
        let last = file.cases[file.cases.len() - 1].id;
        partial.by_id.remove(&first);
        partial.by_id.insert(last, Answer::Refused("no".into()));
        partial.by_id.insert(u64::MAX, Answer::Index(0));
        let report = check(&file, &partial);
        assert_eq!(
            (report.missing, report.missing_ids.as_slice()),
            (1, &[first][..])
        );
        assert_eq!(report.unknown, [u64::MAX]);
        assert_eq!(report.mismatches.len(), 1);
        assert_eq!(report.mismatches[0].got, Answer::Refused("no".into()));
        let text = report.to_string();
        assert!(
            text.contains("missing ids (1)") && text.contains("unknown ids (1)"),
            "{text}"
        );
    }
}

#[test]
fn answers_round_trip_through_their_text() {
    let file = committed(VectorSet::Uv2indexExact);
    let source = AnswerSource::from_name("uv2index-version1-exact").unwrap();
    let answers = compute_answers(source, &file);
    assert_eq!(
        parse_answers(answers.to_json_lines().as_bytes()),
        Ok(answers)
    );
}

#[test]
fn malformed_files_are_errors_not_panics() {
    let valid_case =
        r#"{"id": 0, "u": "0x3e800000", "v": "1/4", "level": 2, "index": 5, "tags": []}"#;
    let file_with = |header: &str, cases: &str| format!("{{{header}, \"cases\": [{cases}]}}");
    let header = r#""format": "micromap-index-vectors", "version": 1, "function": "spec-f32""#;
    assert!(parse_vector_file(file_with(header, valid_case).as_bytes()).is_ok());
    let bad_files: Vec<Vec<u8>> = vec![
        vec![],
        b"\xff\xfe".to_vec(),
        b"null".to_vec(),
        b"[]".to_vec(),
        b"{}".to_vec(),
        file_with(r#""format": "other", "version": 1, "function": "f""#, "").into_bytes(),
        file_with(
            r#""format": "micromap-index-vectors", "version": 2, "function": "f""#,
            "",
        )
        .into_bytes(),
        file_with(header, &format!("{valid_case}, {valid_case}")).into_bytes(),
        // Vacuous, unknown function, expected index >= 4^level, ids not increasing.
        file_with(header, "").into_bytes(),
        file_with(
            r#""format": "micromap-index-vectors", "version": 1, "function": "f""#,
            valid_case,
        )
        .into_bytes(),
        file_with(header, &valid_case.replace("\"index\": 5", "\"index\": 16")).into_bytes(),
        file_with(
            header,
            &format!(
                "{}, {valid_case}",
                valid_case.replace("\"id\": 0", "\"id\": 1")
            ),
        )
        .into_bytes(),
        file_with(header, &valid_case.replace("0x3e800000", "0x3e8")).into_bytes(),
        file_with(header, &valid_case.replace("1/4", "1/0")).into_bytes(),
        file_with(header, &valid_case.replace("\"level\": 2", "\"level\": 33")).into_bytes(),
        file_with(header, &valid_case.replace("\"level\": 2", "\"level\": -1")).into_bytes(),
        file_with(
            header,
            &valid_case.replace("\"index\": 5", "\"index\": 1e3"),
        )
        .into_bytes(),
        file_with(
            header,
            &valid_case.replace("\"id\": 0", "\"id\": 18446744073709551616"),
        )
        .into_bytes(),
        "[".repeat(100_000).into_bytes(),
    ];
    for bytes in &bad_files {
        assert!(
            parse_vector_file(bytes).is_err(),
            "accepted {:?}",
            String::from_utf8_lossy(bytes)
        );
    }
    let duplicate = file_with(header, &format!("{valid_case}, {valid_case}"));
    assert_eq!(
        parse_vector_file(duplicate.as_bytes()),
        Err(VectorError::DuplicateId { id: 0, line: None })
    );

    let bad_answers: [&[u8]; 12] = [
        b"{\"id\": 1, \"index\": 1, \"unsupported\": true}",
        b"{\"id\": 1, \"unsupported\": 1}",
        b"{",
        b"{\"id\": 1}",
        b"{\"id\": 1, \"index\": -1}",
        b"{\"id\": 1, \"index\": 1, \"error\": \"x\"}",
        b"{\"index\": 1}",
        b"{\"id\": \"1\", \"index\": 1}",
        b"{\"id\": 1, \"index\": 1}\n{\"id\": 1, \"index\": 1}",
        b"{\"id\": 1, \"index\": 1}\n\xff",
        b"[1, 2]",
        b"{\"id\": 1, \"index\": 1} {\"id\": 2, \"index\": 2}",
    ];
    for bytes in bad_answers {
        assert!(
            parse_answers(bytes).is_err(),
            "accepted {:?}",
            String::from_utf8_lossy(bytes)
        );
    }
    assert_eq!(
        parse_answers(b"{\"id\": 1, \"index\": 1}\r\n\n{\"id\": 2}"),
        Err(VectorError::BadAnswer {
            line: 3,
            message: "needs \"index\" (a non-negative integer), \"error\" or \"unsupported\": true"
                .into()
        })
    );
    assert_eq!(parse_answers(b""), Ok(Answers::default()));
}

/// Every truncation and many single-byte edits of a real file and answers:
/// the readers return (Ok or Err) and never panic.
#[test]
fn readers_survive_edited_bytes() {
    let mut file = committed(VectorSet::SpecF32);
    file.cases.truncate(4);
    let text = file.to_json_text().into_bytes();
    let answers = correct_answers(&file).to_json_lines().into_bytes();
    for original in [&text, &answers] {
        for end in 0..original.len() {
            let _ = parse_vector_file(&original[..end]);
            let _ = parse_answers(&original[..end]);
        }
        for at in 0..original.len() {
            for byte in [b'"', b'{', b'9', b'-', b'/', b'x', b'\n', 0xff] {
                let mut edited = original.clone();
                edited[at] = byte;
                let _ = parse_vector_file(&edited);
                let _ = parse_answers(&edited);
            }
        }
    }
}

/// The `shared-edge` / `shared-vertex` tags, checked against a brute-force
/// count of the closed micro-triangles that contain the point (levels
/// `0..=3`, every index): 2 on a shared edge, 3 or more at a shared vertex,
/// 1 elsewhere in the triangle.
#[test]
fn shared_tags_match_the_count_of_containing_micro_triangles() {
    for set in VectorSet::ALL {
        let file = committed(set);
        let mut seen = [0usize; 3];
        for case in file.cases.iter().filter(|c| c.level <= 3) {
            let (Ok(u), Ok(v)) = (
                Value::parse(&case.u).unwrap().to_exact(),
                Value::parse(&case.v).unwrap().to_exact(),
            ) else {
                continue; // NaN or infinite
            };
            let level = Level::new(case.level).unwrap();
            let containing = (0..1u64 << (2 * case.level))
                .filter(|&index| micro_triangle_contains(level, index, &u, &v) == Some(true))
                .count();
            let expected = match containing {
                0 | 1 => None,
                2 => Some(tag::SHARED_EDGE),
                _ => Some(tag::SHARED_VERTEX),
            };
            for name in [tag::SHARED_EDGE, tag::SHARED_VERTEX] {
                assert_eq!(
                    has(case, name),
                    expected == Some(name),
                    "{name}: {containing} micro-triangles contain {}",
                    shown(case)
                );
            }
            seen[containing.min(2)] += 1;
        }
        // Some points of one micro-triangle and some shared ones (and, for
        // the clamping sets, some outside the triangle).
        assert!(seen[1] > 0 && seen[2] > 0, "{}: {seen:?}", file.function);
    }
}

/// The classes of known implementations: version 1 only breaks ties
/// differently (every mismatch on a shared edge or vertex, and the answered
/// micro-triangle contains the point); the float walk also names wrong
/// micro-triangles; the exact reading of the reference differs from the
/// binary32 set exactly by the rounding window and its refusals of NaN
/// and infinities. Every class agrees with the exact containment test.
#[test]
fn mismatch_classes_of_known_implementations() {
    let walk_set = committed(VectorSet::Uv2indexExact);
    let spec_f32 = committed(VectorSet::SpecF32);
    let runs = [
        ("uv2index-version1-exact", &walk_set),
        ("uv2index-f32", &walk_set),
        ("spec-exact", &spec_f32),
    ];
    for (source, file) in runs {
        let answers = compute_answers(AnswerSource::from_name(source).unwrap(), file);
        let report = check(file, &answers);
        assert_eq!(
            report.by_class.values().sum::<usize>(),
            report.mismatches.len(),
            "{source}: {report}"
        );
        assert_eq!(report.out_of_range(), 0, "{source}");
        for m in &report.mismatches {
            let context = format!("{source}: id {} ({:?}) got {}", m.id, m.class, m.got);
            let exact = |text: &str| Value::parse(text).unwrap().to_exact().ok();
            let level = Level::new(m.level).unwrap();
            let contains = match (&m.got, exact(&m.u), exact(&m.v)) {
                (Answer::Index(index), Some(u), Some(v)) => {
                    micro_triangle_contains(level, *index, &u, &v)
                }
                _ => None,
            };
            match m.class {
                MismatchClass::WrongTriangle => assert_eq!(contains, Some(false), "{context}"),
                MismatchClass::TieBreakEdge => {
                    assert_eq!(contains, Some(true), "{context}");
                    assert!(m.tags.iter().any(|t| t == tag::SHARED_EDGE), "{context}");
                }
                MismatchClass::TieBreakVertex => {
                    assert_eq!(contains, Some(true), "{context}");
                    assert!(m.tags.iter().any(|t| t == tag::SHARED_VERTEX), "{context}");
                }
                _ => {}
            }
        }
        let count = |class| report.by_class.get(&class).copied().unwrap_or(0);
        match source {
            "uv2index-version1-exact" => {
                let ties =
                    count(MismatchClass::TieBreakEdge) + count(MismatchClass::TieBreakVertex);
                assert!(ties > 0 && ties == report.mismatches.len(), "{report}");
            }
            "uv2index-f32" => {
                assert!(count(MismatchClass::WrongTriangle) > 0, "{report}");
                assert_eq!(
                    count(MismatchClass::RoundingWindow),
                    report.by_tag[tag::ROUNDING_WINDOW].mismatched,
                    "{report}"
                );
            }
            _ => {
                assert_eq!(
                    count(MismatchClass::RoundingWindow),
                    report.by_tag[tag::ROUNDING_WINDOW].cases,
                    "{report}"
                );
                let not_real = spec_f32
                    .cases
                    .iter()
                    .filter(|c| has(c, tag::NAN) || has(c, tag::INFINITY))
                    .count();
                assert_eq!(count(MismatchClass::Refused), not_real, "{report}");
                assert_eq!(
                    report.mismatches.len(),
                    count(MismatchClass::RoundingWindow) + not_real
                );
            }
        }
    }
}

/// An index `>= 4^level` is flagged first; `"unsupported"` answers are
/// counted apart and do not fail; a selection skips cases; the streaming
/// check equals the in-memory one.
#[test]
fn out_of_range_unsupported_and_selection() {
    let file = committed(VectorSet::SpecF32);
    let bytes = std::fs::read(vectors_dir().join(VectorSet::SpecF32.file_name())).unwrap();
    let mut answers = correct_answers(&file);
    let victim = file
        .cases
        .iter()
        .find(|c| c.level == 2 && has(c, tag::NAN))
        .unwrap();
    answers.by_id.insert(victim.id, Answer::Index(16));
    let capped: Vec<u64> = file
        .cases
        .iter()
        .filter(|c| c.level > 12)
        .map(|c| c.id)
        .collect();
    for id in &capped {
        answers.by_id.insert(*id, Answer::Unsupported);
    }
    let report = check(&file, &answers);
    assert_eq!(
        report,
        check_reader(&bytes[..], &answers, Selection::default()).unwrap()
    );
    assert_eq!(report.out_of_range(), 1, "{report}");
    assert_eq!(report.mismatches[0].class, MismatchClass::OutOfRange);
    assert_eq!(report.unsupported, capped.len());
    assert_eq!(report.matched + report.unsupported + 1, file.cases.len());
    let text = report.render(1);
    let danger = text
        .lines()
        .position(|l| l.starts_with("DANGER: 1 answers are >= 4^level"));
    assert_eq!(danger, Some(1), "{text}");
    assert!(text.contains("got 16 (>= 4^2 = 16)"), "{text}");
    assert!(text.lines().count() < 16, "{text}");

    // Leaving out the NaN cases: the unsupported levels alone still pass.
    let selection = Selection {
        exclude_tags: vec![tag::NAN.into()],
        ..Selection::default()
    };
    let report = check_reader(&bytes[..], &answers, selection).unwrap();
    assert!(report.passed(), "{report}");
    let nan_cases = file.cases.iter().filter(|c| has(c, tag::NAN)).count();
    assert_eq!(report.skipped, nan_cases);
    assert_eq!(report.checked + report.skipped, file.cases.len());
    let json = report.to_json(0);
    assert_eq!(json["skipped"], nan_cases);
    assert_eq!(json["mismatched"], 0);
    assert_eq!(json["unsupported"], report.unsupported);

    // Every answer unsupported: nothing matched, not a pass.
    let mut nothing = Answers::default();
    for case in &file.cases {
        nothing.by_id.insert(case.id, Answer::Unsupported);
    }
    assert!(!check(&file, &nothing).passed());
    // A selection that covers nothing is an error, not a vacuous pass.
    let none = Selection {
        levels: Some(17..=32),
        ..Selection::default()
    };
    assert!(check_reader(&bytes[..], &answers, none).is_err());
}
