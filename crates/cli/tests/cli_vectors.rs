//! `micromap-index check`: the built binary's reports and exit codes (0 all
//! match, 1 mismatch / missing / unknown id, 2 usage error or malformed
//! file, 3 unreadable file). (`micromap-lab vectors`:
//! `crates/lab/tests/lab_vectors_out.rs`.)

mod common;

use common::{committed, text};
use micromap_index_conformance::eval::Variant;
use micromap_index_conformance::value::Value;
use micromap_index_conformance::vectors::{parse_vector_file, Answer, Answers};
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::Output;

fn run(args: &[&str], stdin: Option<&[u8]>) -> Output {
    common::run_with_stdin(args, stdin.unwrap_or_default())
}

/// A fresh directory under cargo's per-test scratch space.
fn scratch(name: &str) -> PathBuf {
    common::scratch(&format!("cli_vectors_{name}"))
}

/// The answer lines of `variant` to every case of the vector file
/// `vectors`, computed here by the conformance crate's engine (what
/// `micromap-lab vectors --answers-from VARIANT` prints).
fn answers_from(variant: &str, vectors: &str) -> Vec<u8> {
    let file = parse_vector_file(&std::fs::read(vectors).unwrap()).unwrap();
    let variant = Variant::from_name(variant).unwrap();
    let mut answers = Answers::default();
    for case in &file.cases {
        let index = Value::parse(&case.u)
            .and_then(|u| Ok((u, Value::parse(&case.v)?)))
            .map_err(|e| e.to_string())
            .and_then(|(u, v)| {
                variant
                    .evaluate(&u, &v, u64::from(case.level))
                    .map_err(|e| e.to_string())
            });
        let answer = match index {
            Ok(index) => Answer::Index(index),
            Err(message) => Answer::Refused(message),
        };
        answers.by_id.insert(case.id, answer);
    }
    answers.to_json_lines().into_bytes()
}

#[test]
fn check_exit_codes() {
    let spec_f32 = committed("spec-f32.json");
    let uv2index = committed("uv2index-exact.json");
    let dir = scratch("check");

    // The crate's own functions: 0 when right ...
    let right = answers_from("fixed-mirror", &spec_f32);
    let output = run(
        &["check", "--vectors", &spec_f32, "--answers", "-"],
        Some(&right),
    );
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stdout));
    assert!(text(&output.stdout).starts_with("spec-f32: "));
    assert!(text(&output.stdout)
        .lines()
        .next()
        .unwrap()
        .ends_with("PASS"));

    // ... 1 for the float walk, with the failures under their tags.
    let float_walk = dir.join("uv2index-f32.jsonl");
    std::fs::write(&float_walk, answers_from("uv2index-f32", &uv2index)).unwrap();
    let output = run(
        &[
            "check",
            "--vectors",
            &uv2index,
            "--answers",
            float_walk.to_str().unwrap(),
            "--examples=2",
        ],
        None,
    );
    assert_eq!(output.status.code(), Some(1));
    let report = text(&output.stdout);
    assert!(report.contains("FAIL"), "{report}");
    assert!(
        report.contains("\nrounding-window (287; first 2)"),
        "{report}"
    );

    // A missing answer alone fails; so does an id not in the file.
    let mut lines: Vec<&[u8]> = right.split(|&b| b == b'\n').collect();
    lines.remove(0);
    let missing_first = lines.join(&b'\n');
    let output = run(
        &["check", "--vectors", &spec_f32, "--answers", "-"],
        Some(&missing_first),
    );
    assert_eq!(output.status.code(), Some(1));
    assert!(text(&output.stdout).contains("missing ids (1): 0"));
    let mut extra = right.clone();
    extra.extend_from_slice(b"{\"id\": 99999999, \"index\": 0}\n");
    let output = run(
        &["check", "--vectors", &spec_f32, "--answers", "-"],
        Some(&extra),
    );
    assert_eq!(output.status.code(), Some(1));
    assert!(text(&output.stdout).contains("unknown ids (1): 99999999"));
}

#[test]
fn malformed_files_exit_2_and_unreadable_ones_3() {
    let spec_f32 = committed("spec-f32.json");
    let dir = scratch("malformed");
    let not_vectors = dir.join("not-vectors.json");
    std::fs::write(&not_vectors, b"{\"format\": \"something else\"}").unwrap();
    let missing = dir.join("does-not-exist.json");
    let header =
        r#"{"format": "micromap-index-vectors", "version": 1, "function": "spec-f32", "cases": ["#;
    let case =
        r#"{"id": 0, "u": "0x3e800000", "v": "0x3e800000", "level": 2, "index": 5, "tags": []}"#;
    let malformed = [
        ("empty.json", format!("{header}]}}"), "no cases"),
        (
            "too-big.json",
            format!(
                "{header}{}]}}",
                case.replace("\"index\": 5", "\"index\": 16")
            ),
            "not below 4^2",
        ),
        (
            "unknown-function.json",
            format!("{header}{case}]}}").replace("spec-f32", "my-function"),
            "\"my-function\" is not a function",
        ),
    ];
    for (name, content, message) in malformed {
        let path = dir.join(name);
        std::fs::write(&path, content).unwrap();
        let output = run(
            &[
                "check",
                "--vectors",
                path.to_str().unwrap(),
                "--answers",
                "-",
            ],
            Some(b"{\"id\": 0, \"index\": 5}\n"),
        );
        assert_eq!(
            output.status.code(),
            Some(2),
            "{name}: {}",
            text(&output.stdout)
        );
        assert!(
            text(&output.stderr).contains(message),
            "{name}: {}",
            text(&output.stderr)
        );
    }
    // A selection that covers nothing checks nothing: exit 2, not a pass.
    let output = run(
        &[
            "check",
            "--vectors",
            &spec_f32,
            "--answers",
            "-",
            "--levels",
            "17..=20",
        ],
        Some(b""),
    );
    assert_eq!(output.status.code(), Some(2));
    assert!(text(&output.stderr).contains("nothing was checked"));
    let cases: [(Vec<&str>, &[u8], &str); 4] = [
        (
            vec![
                "check",
                "--vectors",
                missing.to_str().unwrap(),
                "--answers",
                "-",
            ],
            b"",
            "cannot read",
        ),
        (
            vec![
                "check",
                "--vectors",
                not_vectors.to_str().unwrap(),
                "--answers",
                "-",
            ],
            b"",
            "not-vectors.json",
        ),
        (
            vec!["check", "--vectors", &spec_f32, "--answers", "-"],
            b"{\"id\": 0, \"index\": 0}\n{\"id\": 0, \"index\": 0}\n",
            "stdin: line 2: duplicate id 0",
        ),
        (
            vec!["check", "--vectors", &spec_f32, "--answers", "-"],
            b"not json\n",
            "stdin: line 1: bad JSON",
        ),
    ];
    for (args, stdin, message) in cases {
        let output = run(&args, Some(stdin));
        // A file that cannot be read is an I/O error (3); a malformed one is 2.
        let expected = if message.starts_with("cannot read") {
            3
        } else {
            2
        };
        assert_eq!(output.status.code(), Some(expected), "{args:?}");
        assert!(
            text(&output.stderr).contains(message),
            "{args:?}: {}",
            text(&output.stderr)
        );
        assert!(!text(&output.stderr).contains("panicked"));
    }
}

#[test]
fn usage_errors_exit_2() {
    for args in [
        vec!["check"],
        vec!["check", "--vectors", "x"],
        vec![
            "check",
            "--vectors",
            "x",
            "--answers",
            "y",
            "--levels",
            "3..=1",
        ],
        vec![
            "check",
            "--vectors",
            "x",
            "--answers",
            "y",
            "--levels",
            "0..=33",
        ],
        vec![
            "check",
            "--vectors",
            "x",
            "--answers",
            "y",
            "--tags",
            "no-such-tag",
        ],
        vec!["check", "--vectors", "-", "--answers", "-"],
        vec![
            "check",
            "--vectors",
            "x",
            "--answers",
            "y",
            "--examples",
            "many",
        ],
    ] {
        let output = run(&args, None);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        // The message and a pointer to the command's usage.
        let err = text(&output.stderr);
        assert!(err.ends_with("--help`\n"), "{args:?}: {err}");
        assert!(err.lines().count() <= 2, "{args:?}: {err}");
    }
}

/// A capped implementation (levels 0..=12, the rest `"unsupported"`), one
/// out-of-range answer: flagged first; `--levels` and `--json` scope and
/// summarise the run.
#[test]
fn check_scoping_classes_and_json() {
    let spec_f32 = committed("spec-f32.json");
    let right = text(&answers_from("spec-f32", &spec_f32));
    let vectors = std::fs::read_to_string(&spec_f32).unwrap();
    let level_of = |id: &str| {
        let key = format!("{{\"id\":{id},");
        let line = vectors
            .lines()
            .find(|l| l.trim_start().starts_with(&key))
            .unwrap();
        let level = line.split("\"level\":").nth(1).unwrap();
        level.split(',').next().unwrap().parse::<u32>().unwrap()
    };
    let mut capped = String::new();
    for line in right.lines() {
        let id = line.split(&[':', ','][..]).nth(1).unwrap();
        if level_of(id) > 12 {
            let _ = writeln!(capped, "{{\"id\": {id}, \"unsupported\": true}}");
        } else if id == "200" {
            capped.push_str("{\"id\": 200, \"index\": 4294967296}\n");
        } else {
            capped.push_str(line);
            capped.push('\n');
        }
    }
    let output = run(
        &[
            "check",
            "--vectors",
            &spec_f32,
            "--answers",
            "-",
            "--examples",
            "1",
        ],
        Some(capped.as_bytes()),
    );
    assert_eq!(output.status.code(), Some(1));
    let report = text(&output.stdout);
    let lines: Vec<&str> = report.lines().collect();
    assert!(lines[0].ends_with("FAIL"), "{report}");
    assert!(
        lines[1].starts_with("DANGER: 1 answers are >= 4^level"),
        "{report}"
    );
    assert!(report.contains("by class: out-of-range 1"), "{report}");
    assert!(report.contains("unsupported by level: 13: "), "{report}");

    let output = run(
        &[
            "check",
            "--vectors",
            &spec_f32,
            "--answers",
            "-",
            "--json",
            "--levels",
            "0..=12",
        ],
        Some(capped.as_bytes()),
    );
    assert_eq!(output.status.code(), Some(1));
    let json: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(json["out_of_range"], 1);
    assert_eq!(json["mismatched"], 1);
    assert_eq!(json["unsupported"], 0);
    assert_eq!(json["by_class"]["out-of-range"], 1);
    let skipped = json["skipped"].as_u64().unwrap();
    assert_eq!(json["checked"].as_u64().unwrap() + skipped, 9393);
    assert!(skipped > 0);
    let by_class: u64 = json["by_class"]
        .as_object()
        .unwrap()
        .values()
        .map(|v| v.as_u64().unwrap())
        .sum();
    assert_eq!(by_class, 1);

    // Without the bad answer, the capped implementation passes.
    let fixed = capped.replace(
        "{\"id\": 200, \"index\": 4294967296}",
        right
            .lines()
            .find(|l| l.starts_with("{\"id\":200,"))
            .unwrap(),
    );
    let output = run(
        &["check", "--vectors", &spec_f32, "--answers", "-", "--json"],
        Some(fixed.as_bytes()),
    );
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stdout));
    let json: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(json["passed"], true);
    assert!(json["unsupported"].as_u64().unwrap() > 0);
}
