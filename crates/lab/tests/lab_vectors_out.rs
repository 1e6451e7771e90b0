//! `micromap-lab vectors --out DIR` writes all three files or none, refuses
//! an empty or non-directory path and existing vector files (unless
//! `--force`), and leaves no temporary behind.

mod common;

use common::cli;

use std::path::{Path, PathBuf};
use std::process::Output;

const NAMES: [&str; 3] = ["spec-exact.json", "spec-f32.json", "uv2index-exact.json"];

fn vectors(args: &[&str]) -> Output {
    cli::run(&[&["vectors"], args].concat())
}

fn stderr(output: &Output) -> String {
    cli::text(&output.stderr)
}

fn scratch(name: &str) -> PathBuf {
    cli::scratch(&format!("cli_vectors_out_{name}"))
}

fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    names
}

fn committed(name: &str) -> Vec<u8> {
    std::fs::read(cli::committed(name)).unwrap()
}

/// Issue 9: `mkdir -p DIR/spec-exact.json; vectors --out DIR` wrote one file
/// and exited 1. Now nothing is written, exit 2, even with `--force`.
#[test]
fn a_directory_in_the_way_writes_nothing() {
    let dir = scratch("blocked");
    std::fs::create_dir(dir.join("spec-exact.json")).unwrap();
    for force in [false, true] {
        let mut args = vec!["--out", dir.to_str().unwrap()];
        if force {
            args.push("--force");
        }
        let output = vectors(&args);
        assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
        assert!(output.stdout.is_empty());
        assert!(
            stderr(&output).contains("spec-exact.json exists and is not a file; nothing written"),
            "{}",
            stderr(&output)
        );
        assert_eq!(listing(&dir), ["spec-exact.json"]);
    }
}

#[test]
fn existing_files_need_force() {
    let dir = scratch("force");
    std::fs::write(dir.join("spec-f32.json"), "old").unwrap();
    let out = dir.to_str().unwrap();
    let output = vectors(&["--out", out]);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).contains("spec-f32.json exists; nothing written (--force replaces it)"),
        "{}",
        stderr(&output)
    );
    assert_eq!(listing(&dir), ["spec-f32.json"]);
    assert_eq!(std::fs::read(dir.join("spec-f32.json")).unwrap(), b"old");

    let output = vectors(&["--out", out, "--force"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(listing(&dir), NAMES);
    for name in NAMES {
        assert!(
            std::fs::read(dir.join(name)).unwrap() == committed(name),
            "{name}"
        );
    }
    // A second run without --force refuses again; with it, succeeds again.
    assert_eq!(vectors(&["--out", out]).status.code(), Some(2));
    assert_eq!(vectors(&["--force", "--out", out]).status.code(), Some(0));
    assert_eq!(listing(&dir), NAMES);
}

#[test]
fn bad_out_paths_are_usage_errors() {
    let dir = scratch("paths");
    let file = dir.join("a-file");
    std::fs::write(&file, "x").unwrap();
    for (args, message) in [
        (
            vec!["--out", ""],
            "--out needs a directory path, got an empty one",
        ),
        (
            vec!["--out", file.to_str().unwrap()],
            "a-file exists and is not a directory",
        ),
        (
            vec!["--out", dir.to_str().unwrap(), "--force", "--force"],
            "--force given twice",
        ),
        (
            vec!["--answers-from", "spec-f32", "--vectors", "x", "--force"],
            "vectors needs --out DIR",
        ),
    ] {
        let output = vectors(&args);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        assert!(
            stderr(&output).contains(message),
            "{args:?}: {}",
            stderr(&output)
        );
    }
    assert_eq!(listing(&dir), ["a-file"]);
}

/// A new directory (with parents) is created; the summary names each file.
#[test]
fn writes_into_a_new_directory() {
    let dir = scratch("new").join("a").join("b");
    let output = vectors(&["--out", dir.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(listing(&dir), NAMES);
    let summary = String::from_utf8(output.stdout).unwrap();
    assert_eq!(summary.lines().count(), 3);
    for name in NAMES {
        assert!(summary.contains(name), "{summary}");
    }
}

#[test]
fn vectors_writes_the_committed_files() {
    let out = scratch("out").join("sets");
    let output = vectors(&["--out", out.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    for name in ["spec-f32.json", "spec-exact.json", "uv2index-exact.json"] {
        let written = std::fs::read(out.join(name)).unwrap();
        let committed = committed(name);
        assert!(
            written == committed,
            "{name} differs from reference/vectors/"
        );
        assert!(cli::text(&output.stdout).contains(name));
    }
}

#[test]
fn usage_errors_exit_2() {
    for args in [
        vec![],
        vec!["--out"],
        vec!["--out", "a", "--out", "b"],
        vec!["--out", "a", "--answers-from", "spec-f32"],
        vec!["--answers-from", "no-such-variant", "--vectors", "x"],
        vec!["--bogus", "1"],
    ] {
        let output = vectors(&args);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        assert!(stderr(&output).contains("usage:"), "{args:?}");
    }
}
