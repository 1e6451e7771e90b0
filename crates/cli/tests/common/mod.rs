//! The one spawn helper of the command-line tests: `micromap-index` for
//! `crates/cli/tests`, `micromap-lab` for `crates/lab/tests/cli_lab.rs`
//! (which includes this file by `#[path]`). Each test file uses a part.
#![allow(dead_code)]

use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// The binary under test: cargo sets `CARGO_BIN_EXE_<name>` for the tests
/// of the package that builds `<name>`.
pub fn binary() -> Command {
    let path = option_env!("CARGO_BIN_EXE_micromap-index")
        .or(option_env!("CARGO_BIN_EXE_micromap-lab"))
        .expect("a test of crates/cli or crates/lab");
    Command::new(path)
}

/// Runs with stdin empty; stdout and stderr captured.
pub fn run(args: &[&str]) -> Output {
    binary()
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("the binary runs")
}

/// Runs with `stdin` as its input, written from a thread (the child may
/// answer while it reads); stdout and stderr captured.
pub fn run_with_stdin(args: &[&str], stdin: &[u8]) -> Output {
    let mut child = binary()
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let mut input = child.stdin.take().unwrap();
    let bytes = stdin.to_vec();
    let writer = std::thread::spawn(move || {
        // The child may exit without reading it all (a usage error).
        let _ = input.write_all(&bytes);
    });
    let output = child.wait_with_output().unwrap();
    writer.join().unwrap();
    output
}

/// Runs, reads `lines` lines of stdout, then closes it (as `| head -N`
/// does) and waits: the exit code, the lines read and stderr.
pub fn close_stdout_after(args: &[&str], lines: usize) -> (Option<i32>, Vec<String>, String) {
    let mut child = binary()
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

/// `/dev/full` opened for writing: a child's stdout or stderr on a full
/// disk.
#[cfg(target_os = "linux")]
pub fn dev_full() -> Stdio {
    Stdio::from(
        std::fs::File::options()
            .write(true)
            .open("/dev/full")
            .unwrap(),
    )
}

/// Each of `commands`, with stdout on a full disk, exits 3 with exactly
/// `PROGRAM: writing stdout: No space left on device (os error 28)` on
/// stderr, once.
#[cfg(target_os = "linux")]
pub fn assert_full_stdout_is_exit_3(program: &str, commands: &[&[&str]]) {
    for args in commands {
        let output = binary()
            .args(*args)
            .stdin(Stdio::null())
            .stdout(dev_full())
            .output()
            .unwrap();
        let stderr = text(&output.stderr);
        assert_eq!(output.status.code(), Some(3), "{args:?}: {stderr}");
        assert_eq!(
            stderr,
            format!("{program}: writing stdout: No space left on device (os error 28)\n"),
            "{args:?}"
        );
    }
}

/// Each command exits with its code whether stderr is a full disk or
/// closed: a lost message changes nothing else.
#[cfg(target_os = "linux")]
pub fn assert_lost_stderr_keeps_exit_codes(cases: &[(&[&str], i32)]) {
    for &(args, code) in cases {
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

/// Bytes as text, invalid UTF-8 replaced.
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The repository's root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A committed vector file's path, as a string.
pub fn committed(name: &str) -> String {
    root()
        .join("reference/vectors")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

/// A fresh, empty directory under cargo's per-test scratch space.
pub fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Checks `docs/cli.md` against the flag tables: every command in
/// `commands` has its usage there exactly as `program help COMMAND` prints
/// it (rendered from its table), in a text block; and every usage line of
/// `program` there is one of theirs.
pub fn docs_show_the_usage(program: &str, commands: &[&str]) {
    let docs = std::fs::read_to_string(root().join("docs/cli.md")).unwrap();
    for command in commands {
        let output = run(&["help", command]);
        assert_eq!(output.status.code(), Some(0), "help {command}");
        let usage = text(&output.stdout);
        let block = format!("```text\n{usage}```\n");
        assert!(
            docs.contains(&block),
            "docs/cli.md lacks `{program} help {command}` as the binary prints it:\n{usage}"
        );
    }
    let prefix = format!("usage: {program} ");
    for line in docs.lines().filter(|line| line.starts_with(&prefix)) {
        let command = line[prefix.len()..].split(' ').next().unwrap();
        assert!(
            commands.contains(&command),
            "docs/cli.md shows a usage of {program} {command}, which is not rendered from a table"
        );
    }
}
