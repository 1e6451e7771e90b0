//! The output layer (the user CLI's, `crates/cli-support/src/output.rs`) on
//! `micromap-lab`: a closed stdout ends `prove` quietly with 141, a full
//! disk is a message and 3, a full or closed stderr changes no exit code,
//! Ctrl-C is 130, and never a panic (101). The other rows of the exit-code
//! table are produced by `crates/cli/tests/cli_output.rs`.

mod common;

use common::cli;

use cli::{binary, close_stdout_after, run, text};
use std::io::{BufRead, BufReader, Read};
use std::process::{Command, Stdio};

fn assert_no_panic(args: &[&str], stderr: &str) {
    assert!(
        !stderr.contains("panicked") && !stderr.contains("failed printing"),
        "{args:?}: {stderr}"
    );
}

/// Issue 9: `prove --levels 0..=16 | head -3` and `prove --json ... | head -1`
/// panicked with "failed printing to stdout" (exit 101).
#[test]
fn a_closed_stdout_ends_quietly_with_141() {
    for (args, lines) in [
        (&["prove", "--levels", "0..=16"][..], 3),
        (&["prove", "--levels", "0..=16", "--json"][..], 1),
        (&["prove", "--levels", "0..=16", "--sample", "1000"][..], 3),
    ] {
        let (code, read, stderr) = close_stdout_after(args, lines);
        assert_eq!(code, Some(141), "{args:?}: {stderr}");
        assert_eq!(read.len(), lines);
        assert!(stderr.is_empty(), "quiet: {args:?}: {stderr}");
    }
}

/// `vectors --out DIR | head -1` panicked after writing one or two files;
/// now the files are complete before the summary, which a closed pipe cuts.
#[test]
fn vectors_out_into_a_closed_pipe_writes_every_file() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_output_vectors_pipe");
    let _ = std::fs::remove_dir_all(&dir);
    let (code, _, stderr) = close_stdout_after(&["vectors", "--out", dir.to_str().unwrap()], 0);
    // 0 if all three summary lines fit the pipe before it was closed.
    assert!(matches!(code, Some(0 | 141)), "{code:?}: {stderr}");
    assert_no_panic(&[], &stderr);
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["spec-exact.json", "spec-f32.json", "uv2index-exact.json"]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `prove ... >/dev/full` and `help >/dev/full` panicked; now exit 3 with
/// the reason on stderr, once.
#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_is_exit_3_with_a_message() {
    cli::CLI.assert_full_stdout_is_exit_3(
        "micromap-lab",
        &[
            &["prove", "--levels", "0..=3"][..],
            &["prove", "--levels", "0..=3", "--json"][..],
            &["help"][..],
            &["help", "prove"][..],
            &["vectors", "--help"][..],
        ],
    );
}

/// `bogus 2>/dev/full` panicked; a full (or closed) stderr now changes
/// nothing but the missing message.
#[cfg(target_os = "linux")]
#[test]
fn a_full_or_closed_stderr_keeps_the_exit_code() {
    cli::CLI.assert_lost_stderr_keeps_exit_codes(&[
        (&["bogus"][..], 2),
        (&["prove", "--sample", "0", "--levels", "1"][..], 2),
        (&["prove", "--levels", "0..=4", "--version1"][..], 1),
    ]);
}

/// The codes of the table that `micromap-lab` alone produces (1 and 3 too);
/// and its table is the user CLI's.
#[test]
fn prove_and_vectors_produce_their_exit_codes() {
    let help = text(&run(&["help"]).stdout);
    let table = help
        .split_once("exit codes (all commands):\n")
        .expect("help has the table")
        .1;
    let codes: Vec<i32> = table
        .lines()
        .map(|line| line.split_whitespace().next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(codes, [0, 1, 2, 3, 4, 5, 130, 141]);
    assert_eq!(
        run(&["prove", "--levels", "0..=4", "--version1"])
            .status
            .code(),
        Some(1)
    );
    // 3: a vectors file that cannot be read.
    let missing = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("no-such-vectors.json");
    let output = run(&[
        "vectors",
        "--answers-from",
        "spec-f32",
        "--vectors",
        missing.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(3));
    assert!(text(&output.stderr).contains("cannot read"));
    // 141: above. 130: Ctrl-C.
    #[cfg(unix)]
    {
        let mut child = binary()
            .args(["prove", "--levels", "0..=16"])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut reader = BufReader::new(child.stdout.take().unwrap());
        let mut line = String::new();
        reader.read_line(&mut line).unwrap(); // the header: the handler is set
        let killed = Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status()
            .unwrap();
        assert!(killed.success());
        let mut rest = String::new();
        reader.read_to_string(&mut rest).unwrap();
        let output = child.wait_with_output().unwrap();
        assert_eq!(output.status.code(), Some(130), "{}", text(&output.stderr));
        assert!(text(&output.stderr).contains("interrupted"));
    }
}

/// `prove --help`, `prove -h` and `help prove` print the same usage.
#[test]
fn every_command_has_help() {
    for command in ["prove", "vectors"] {
        let usage = format!("usage: micromap-lab {command}");
        let mut texts = Vec::new();
        for args in [
            vec![command, "--help"],
            vec![command, "-h"],
            vec!["help", command],
        ] {
            let output = run(&args);
            assert_eq!(output.status.code(), Some(0), "{args:?}");
            assert!(output.stderr.is_empty(), "{args:?}");
            let out = text(&output.stdout);
            assert!(out.starts_with(&usage), "{args:?}: {out}");
            texts.push(out);
        }
        assert!(texts.windows(2).all(|w| w[0] == w[1]), "{command}");
    }
    assert_eq!(run(&["help", "bogus"]).status.code(), Some(2));
    assert_eq!(run(&["eval"]).status.code(), Some(2));
}

/// Issue 9: `prove --sample 0` reported success after checking nothing.
#[test]
fn a_check_of_nothing_is_a_usage_error() {
    for (args, message) in [
        (
            &["prove", "--levels", "1", "--sample", "0"][..],
            "--sample 0 checks nothing",
        ),
        (
            &["prove", "--levels", "3..3"][..],
            "empty --levels \"3..3\"",
        ),
        (
            &["prove", "--levels", "0..0"][..],
            "empty --levels \"0..0\"",
        ),
        (
            &["prove", "--levels", "4..=3"][..],
            "empty --levels \"4..=3\"",
        ),
    ] {
        let output = run(args);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        assert!(output.stdout.is_empty(), "{args:?}");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(stderr.contains(message), "{args:?}: {stderr}");
    }
    let output = run(&["prove", "--levels", "1", "--sample", "1"]);
    assert_eq!(output.status.code(), Some(0));
}
