//! The output layer and the exit-code table, on the built binary: a closed
//! stdout ends a command quietly with 141, a full disk is a message and 3, a
//! full or closed stderr changes no exit code, and never a panic (101).
//! Each row of the table in `micromap-index help` and `docs/cli.md` is
//! produced here.

mod common;

#[cfg(target_os = "linux")]
use common::dev_full;
use common::{binary, run, run_with_stdin, text};
use std::fs::File;
use std::process::Stdio;

/// `prove ... >/dev/full` and `help >/dev/full` panicked; now exit 3 with
/// the reason on stderr, once (`prove`: `crates/lab/tests/lab_output.rs`).
#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_is_exit_3_with_a_message() {
    common::CLI.assert_full_stdout_is_exit_3(
        "micromap-index",
        &[
            &["help"][..],
            &["eval", "--help"][..],
            &["help", "check"][..],
            &["help", "prove"][..],
            &["locate", "--level", "3", "--index", "5"][..],
        ],
    );
    let output = binary()
        .args(["eval", "--variant", "spec-f32"])
        .stdin(Stdio::piped())
        .stdout(dev_full())
        .stderr(Stdio::piped())
        .spawn()
        .and_then(|mut child| {
            use std::io::Write;
            let mut stdin = child.stdin.take().unwrap();
            stdin.write_all(b"{\"u\": \"0\", \"v\": \"0\", \"level\": 1}\n")?;
            drop(stdin);
            child.wait_with_output()
        })
        .unwrap();
    assert_eq!(output.status.code(), Some(3), "{}", text(&output.stderr));
    assert!(text(&output.stderr).contains("No space left on device"));
}

/// `bogus 2>/dev/full` panicked; a full (or closed) stderr now changes
/// nothing but the missing message.
#[cfg(target_os = "linux")]
#[test]
fn a_full_or_closed_stderr_keeps_the_exit_code() {
    let spec_f32 = common::committed("spec-f32.json");
    common::CLI.assert_lost_stderr_keeps_exit_codes(&[
        (&["bogus"][..], 2),
        (&["prove", "--sample", "0", "--levels", "1"][..], 2),
        (&["locate", "--level", "33", "--index", "0"][..], 2),
        (
            &["check", "--vectors", &spec_f32, "--answers", "/dev/null"][..],
            1,
        ),
    ]);
}

/// Every code of the table, produced by a command (141 and 130 by
/// `micromap-lab prove`, `crates/lab/tests/lab_output.rs`; 4 by `render`
/// without a device, `crates/cli/tests/cli_render.rs`); and the table is
/// the same in `help` and `docs/cli.md`.
#[test]
fn every_exit_code_of_the_table_is_produced() {
    let help = run(&["help"]);
    assert_eq!(help.status.code(), Some(0));
    let help = text(&help.stdout);
    let table = help
        .split_once("exit codes (all commands):\n")
        .expect("help has the table")
        .1;
    let codes: Vec<i32> = table
        .lines()
        .map(|line| line.split_whitespace().next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(codes, [0, 1, 2, 3, 4, 5, 130, 141]);
    let docs = std::fs::read_to_string(common::root().join("docs/cli.md")).unwrap();
    for code in &codes {
        assert!(
            docs.contains(&format!("\n| {code} |")),
            "docs/cli.md has no row for exit code {code}"
        );
    }

    // 0, 1, 2.
    assert_eq!(
        run(&["locate", "--level", "1", "--index", "0"])
            .status
            .code(),
        Some(0)
    );
    let spec_f32 = common::committed("spec-f32.json");
    let wrong = run_with_stdin(
        &["check", "--vectors", &spec_f32, "--answers", "-"],
        b"{\"id\": 0, \"index\": 99}\n",
    );
    assert_eq!(wrong.status.code(), Some(1));
    assert_eq!(run(&["bogus"]).status.code(), Some(2));
    // 3: stdin that cannot be read (a directory).
    let output = binary()
        .args(["eval", "--variant", "walk-real"])
        .stdin(Stdio::from(File::open(env!("CARGO_MANIFEST_DIR")).unwrap()))
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(3));
    assert!(text(&output.stderr).starts_with("micromap-index: reading stdin: "));
    // 3: a vectors file that cannot be read.
    let missing = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("no-such-vectors.json");
    let output = run(&[
        "check",
        "--vectors",
        missing.to_str().unwrap(),
        "--answers",
        "/dev/null",
    ]);
    assert_eq!(output.status.code(), Some(3));
    assert!(text(&output.stderr).contains("cannot read"));
}

/// `eval --help` and `help eval` were usage errors.
#[test]
fn every_command_has_help() {
    for command in ["eval", "locate", "check", "tree", "bake", "verify-bake"] {
        let usage = format!("usage: micromap-index {command}");
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
    let output = run(&["help", "bogus"]);
    assert_eq!(output.status.code(), Some(2));
    for args in [&["help"][..], &["--help"][..], &["-h"][..]] {
        let output = run(args);
        assert_eq!(output.status.code(), Some(0));
        let out = text(&output.stdout);
        for command in ["eval", "locate", "check", "tree", "bake", "verify-bake"] {
            assert!(out.contains(&format!("usage: micromap-index {command}")));
        }
        assert!(
            out.contains("prove and vectors moved to micromap-lab"),
            "{out}"
        );
    }
}

/// `prove` and `vectors` moved to `micromap-lab`: here any use is exit 2
/// with one line on stderr saying where they went; asking for their help
/// prints that line on stdout, exit 0.
#[test]
fn moved_commands_say_where_they_went() {
    for command in ["prove", "vectors"] {
        let note = format!(
            "{command} moved to micromap-lab, the lab's binary: run `micromap-lab {command} ...` \
             (in the repository: cargo run -p micromap-index-lab --bin micromap-lab -- {command} ...)\n"
        );
        for args in [
            vec![command],
            vec![command, "--levels", "0..=3"],
            vec![command, "--out", "/nonexistent/dir"],
        ] {
            let output = run(&args);
            assert_eq!(output.status.code(), Some(2), "{args:?}");
            assert!(output.stdout.is_empty(), "{args:?}");
            assert_eq!(
                text(&output.stderr),
                format!("micromap-index: {note}"),
                "{args:?}"
            );
        }
        for args in [vec![command, "--help"], vec!["help", command]] {
            let output = run(&args);
            assert_eq!(output.status.code(), Some(0), "{args:?}");
            assert_eq!(text(&output.stdout), note, "{args:?}");
        }
    }
}

/// The variant list uses the new names and says the old ones still work;
/// the README's first command (a legacy name) still answers.
#[test]
fn help_lists_the_variants_with_their_aliases() {
    let help = text(&run(&["help", "eval"]).stdout);
    for (name, alias) in [
        ("spec-f32", None),
        ("spec-f32-by-integers", Some("fixed-mirror")),
        ("spec-real", Some("spec-exact")),
        ("spec-wide-f32", None),
        ("spec-wide-real", Some("spec-wide")),
        ("walk-real", Some("uv2index-exact")),
        ("walk-exact-float", Some("fixed-exact")),
        ("walk-f32-arithmetic", Some("uv2index-f32")),
        ("walk-f64-arithmetic", Some("uv2index-f64")),
    ] {
        let line = match alias {
            Some(alias) => format!("\n  {name} (alias {alias})\n"),
            None => format!("\n  {name}\n"),
        };
        assert!(format!("{help}\n").contains(&line), "{line:?} in {help}");
    }
    assert!(help.contains("names of earlier releases are accepted as aliases"));
    for variant in ["spec-exact", "spec-real"] {
        let output = run_with_stdin(
            &["eval", "--variant", variant],
            b"{\"u\": \"0.28\", \"v\": \"0.4\", \"level\": 3}\n",
        );
        assert_eq!(text(&output.stdout), "{\"index\":23}\n", "{variant}");
    }
}
