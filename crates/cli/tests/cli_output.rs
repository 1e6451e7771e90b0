//! The output layer and the exit-code table, on the built binary: a closed
//! stdout ends a command quietly with 141, a full disk is a message and 3, a
//! full or closed stderr changes no exit code, and never a panic (101).
//! Each row of the table in `micromap-index help` and `docs/cli.md` is
//! produced here.

use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;
use std::process::{Child, Command, Output, Stdio};

fn binary() -> Command {
    Command::new(env!("CARGO_BIN_EXE_micromap-index"))
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Runs with stdin empty and stdout, stderr captured.
fn run(args: &[&str]) -> Output {
    binary()
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("the binary runs")
}

#[cfg(target_os = "linux")]
fn dev_full() -> Stdio {
    Stdio::from(File::options().write(true).open("/dev/full").unwrap())
}

fn assert_no_panic(args: &[&str], stderr: &str) {
    assert!(
        !stderr.contains("panicked") && !stderr.contains("failed printing"),
        "{args:?}: {stderr}"
    );
}

/// Reads `lines` lines of the child's stdout, then closes it (as
/// `| head -N` does) and waits: the exit code and stderr.
fn close_stdout_after(args: &[&str], lines: usize) -> (Option<i32>, Vec<String>, String) {
    let mut child: Child = binary()
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let mut reader = BufReader::new(child.stdout.take().unwrap());
    let mut read = Vec::new();
    for _ in 0..lines {
        let mut line = String::new();
        reader.read_line(&mut line).unwrap();
        read.push(line);
    }
    drop(reader);
    let mut stderr = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut stderr)
        .unwrap();
    let status = child.wait().unwrap();
    (status.code(), read, stderr)
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
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_output_vectors_pipe");
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
    for args in [
        &["prove", "--levels", "0..=3"][..],
        &["prove", "--levels", "0..=3", "--json"][..],
        &["help"][..],
        &["eval", "--help"][..],
        &["help", "prove"][..],
        &["locate", "--level", "3", "--index", "5"][..],
    ] {
        let output = binary()
            .args(args)
            .stdin(Stdio::null())
            .stdout(dev_full())
            .output()
            .unwrap();
        let stderr = text(&output.stderr);
        assert_eq!(output.status.code(), Some(3), "{args:?}: {stderr}");
        assert_eq!(
            stderr, "micromap-index: writing stdout: No space left on device (os error 28)\n",
            "{args:?}"
        );
    }
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
    for (args, code) in [
        (&["bogus"][..], 2),
        (&["prove", "--sample", "0", "--levels", "1"][..], 2),
        (&["locate", "--level", "33", "--index", "0"][..], 2),
        (&["prove", "--levels", "0..=4", "--version1"][..], 1),
    ] {
        for stderr in [dev_full(), Stdio::null()] {
            let output = binary()
                .args(args)
                .stdin(Stdio::null())
                .stderr(stderr)
                .output()
                .unwrap();
            assert_eq!(output.status.code(), Some(code), "{args:?}");
        }
    }
}

/// Every code of the table, produced by a command; and the table is the
/// same in `help` and `docs/cli.md`.
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
    assert_eq!(codes, [0, 1, 2, 3, 130, 141]);
    let docs =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/cli.md"))
            .unwrap();
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
    assert_eq!(
        run(&["prove", "--levels", "0..=4", "--version1"])
            .status
            .code(),
        Some(1)
    );
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
    let missing = Path::new(env!("CARGO_TARGET_TMPDIR")).join("no-such-vectors.json");
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

/// `eval --help` and `help eval` were usage errors.
#[test]
fn every_command_has_help() {
    for command in ["eval", "locate", "prove", "vectors", "check"] {
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
        for command in ["eval", "locate", "prove", "vectors", "check"] {
            assert!(out.contains(&format!("usage: micromap-index {command}")));
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
        let output = binary()
            .args(["eval", "--variant", variant])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .and_then(|mut child| {
                use std::io::Write;
                child
                    .stdin
                    .take()
                    .unwrap()
                    .write_all(b"{\"u\": \"0.28\", \"v\": \"0.4\", \"level\": 3}\n")?;
                child.wait_with_output()
            })
            .unwrap();
        assert_eq!(text(&output.stdout), "{\"index\":23}\n", "{variant}");
    }
}
