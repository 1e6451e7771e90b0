//! `micromap-index locate`: the built binary's output, exit codes and
//! messages.

use micromap_index::inverse::micro_triangle;
use micromap_index::Level;
use num_rational::BigRational;
use std::process::Output;

mod common;

fn locate(args: &[&str]) -> Output {
    common::run(&[&["locate"], args].concat())
}

fn stdout(output: &Output) -> String {
    String::from_utf8(output.stdout.clone()).unwrap()
}

fn stderr(output: &Output) -> String {
    String::from_utf8(output.stderr.clone()).unwrap()
}

/// Runs a successful case and returns its single output line.
fn located_line(args: &[&str]) -> String {
    let output = locate(args);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{args:?}: {}",
        stderr(&output)
    );
    assert!(stderr(&output).is_empty(), "{args:?}");
    let out = stdout(&output);
    assert_eq!(out.matches('\n').count(), 1, "one line: {out:?}");
    out.trim_end().to_owned()
}

#[test]
fn prints_exact_vertices() {
    assert_eq!(
        located_line(&["--level", "0", "--index", "0"]),
        r#"{"level":0,"index":0,"upright":true,"vertices":[["0/1","0/1"],["1/1","0/1"],["0/1","1/1"]]}"#
    );
    assert_eq!(
        located_line(&["--level", "2", "--index", "5"]),
        r#"{"level":2,"index":5,"upright":true,"vertices":[["1/4","1/4"],["1/2","1/4"],["1/4","1/2"]]}"#
    );
    // `--name=value`, either order; the centre triangle is upside down.
    assert_eq!(
        located_line(&["--index=1", "--level=1"]),
        r#"{"level":1,"index":1,"upright":false,"vertices":[["0/1","1/2"],["1/2","1/2"],["1/2","0/1"]]}"#
    );
}

#[test]
fn agrees_with_the_library() {
    for (level, index) in [(3u32, 42u64), (16, 0xdead_beef), (32, u64::MAX)] {
        let line = located_line(&["--level", &level.to_string(), "--index", &index.to_string()]);
        let json: serde_json::Value = serde_json::from_str(&line).unwrap();
        let triangle = micro_triangle(Level::new(level).unwrap(), index).unwrap();
        assert_eq!(json["level"], level);
        assert_eq!(json["index"], index);
        assert_eq!(json["upright"], triangle.upright());
        for (i, (u, v)) in triangle.vertices_rational().into_iter().enumerate() {
            for (j, expected) in [u, v].into_iter().enumerate() {
                let text = json["vertices"][i][j].as_str().unwrap();
                let (numerator, denominator) = text.split_once('/').unwrap();
                let denominator: u64 = denominator.parse().unwrap();
                assert!(denominator.is_power_of_two(), "{text}");
                assert_eq!(text.parse::<BigRational>().unwrap(), expected, "{line}");
                // Reduced: an odd numerator unless the denominator is 1.
                let numerator: u64 = numerator.parse().unwrap();
                assert!(denominator == 1 || numerator % 2 == 1, "{text}");
            }
        }
    }
}

#[test]
fn bad_values_exit_2_with_a_message() {
    for (args, message) in [
        (
            ["--level", "33", "--index", "0"],
            "level 33 is too high: levels are 0..=32",
        ),
        (
            ["--level", "99999999999999999999999", "--index", "0"],
            "level 99999999999999999999999 is too high",
        ),
        (
            ["--level", "two", "--index", "0"],
            "--level \"two\" is not a whole number",
        ),
        (
            ["--level", "1", "--index", "4"],
            "index 4 is out of range for level 1: valid indices are 0..=3",
        ),
        (
            ["--level", "32", "--index", "18446744073709551616"],
            "index 18446744073709551616 is out of range for level 32",
        ),
        (
            ["--level", "1", "--index", "-1"],
            "--index \"-1\" is not a whole number",
        ),
    ] {
        let output = locate(&args);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        assert!(output.stdout.is_empty(), "{args:?}");
        assert!(
            stderr(&output).contains(message),
            "{args:?}: {}",
            stderr(&output)
        );
    }
}

#[test]
fn malformed_command_lines_are_usage_errors() {
    for (args, message) in [
        (&[][..], "locate needs --level L and --index I"),
        (
            &["--level", "1"][..],
            "locate needs --level L and --index I",
        ),
        (&["--level", "1", "--index"][..], "--index needs a value"),
        (
            &["--level", "1", "--index", "0", "--verbose"][..],
            "unknown option \"--verbose\"",
        ),
        (
            &["--level", "1", "--level", "2", "--index", "0"][..],
            "--level given twice",
        ),
        (&["--level", "1", "0"][..], "unknown option \"0\""),
    ] {
        let output = locate(args);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        assert!(output.stdout.is_empty(), "{args:?}");
        let err = stderr(&output);
        assert!(err.contains(message), "{args:?}: {err}");
        // The message and a pointer to the usage, not the usage itself.
        assert!(
            err.ends_with("\nsee `micromap-index locate --help`\n"),
            "{args:?}: {err}"
        );
        assert_eq!(err.lines().count(), 2, "{args:?}: {err}");
    }
}
