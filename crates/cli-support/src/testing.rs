//! The spawn helpers of the command-line tests (feature `testing`): one
//! [`Cli`] per binary under test, which each test crate builds from the
//! paths cargo gives it at compile time:
//!
//! ```ignore
//! const CLI: Cli = Cli::new(env!("CARGO_BIN_EXE_micromap-index"), env!("CARGO_TARGET_TMPDIR"));
//! ```
//!
//! `crates/cli/tests` binds it to `micromap-index`, `crates/lab/tests` to
//! `micromap-lab`. Helpers panic on what a test cannot go on from (a binary
//! that does not start).
// Test helpers report a failed step by panicking, as the tests do.
#![allow(clippy::missing_panics_doc)]

use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// One binary under test and its tests' scratch space.
#[derive(Clone, Copy, Debug)]
pub struct Cli {
    /// The executable (`CARGO_BIN_EXE_<name>`).
    pub binary: &'static str,
    /// Cargo's per-test scratch space (`CARGO_TARGET_TMPDIR`).
    pub scratch_root: &'static str,
}

impl Cli {
    /// The binary at `binary`, with scratch directories under
    /// `scratch_root`.
    #[must_use]
    pub const fn new(binary: &'static str, scratch_root: &'static str) -> Cli {
        Cli {
            binary,
            scratch_root,
        }
    }

    /// A command running the binary.
    #[must_use]
    pub fn command(&self) -> Command {
        Command::new(self.binary)
    }

    /// Runs with stdin empty; stdout and stderr captured.
    #[must_use]
    pub fn run(&self, args: &[&str]) -> Output {
        self.command()
            .args(args)
            .stdin(Stdio::null())
            .output()
            .expect("the binary runs")
    }

    /// Runs with stdin empty, stdout and stderr captured, and fails the test
    /// if the command has not ended after `limit`: a hang guard (make the
    /// limit generous, minutes: it must fail only on a hang, never on a
    /// slow or busy machine).
    #[must_use]
    pub fn run_within(&self, args: &[&str], limit: std::time::Duration) -> Output {
        let mut child = self
            .command()
            .args(args)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the binary runs");
        let drain = |mut pipe: Box<dyn Read + Send>| {
            std::thread::spawn(move || {
                let mut bytes = Vec::new();
                let _ = pipe.read_to_end(&mut bytes);
                bytes
            })
        };
        let stdout = drain(Box::new(child.stdout.take().unwrap()));
        let stderr = drain(Box::new(child.stderr.take().unwrap()));
        let started = std::time::Instant::now();
        let status = loop {
            if let Some(status) = child.try_wait().unwrap() {
                break status;
            }
            if started.elapsed() > limit {
                let _ = child.kill();
                let _ = child.wait();
                panic!("{args:?} hung: still running after {limit:?}");
            }
            std::thread::sleep(std::time::Duration::from_millis(20));
        };
        Output {
            status,
            stdout: stdout.join().unwrap(),
            stderr: stderr.join().unwrap(),
        }
    }

    /// Runs with `stdin` as its input, written from a thread (the child may
    /// answer while it reads); stdout and stderr captured.
    #[must_use]
    pub fn run_with_stdin(&self, args: &[&str], stdin: &[u8]) -> Output {
        let mut child = self
            .command()
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
    #[must_use]
    pub fn close_stdout_after(
        &self,
        args: &[&str],
        lines: usize,
    ) -> (Option<i32>, Vec<String>, String) {
        let mut child = self
            .command()
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

    /// A fresh, empty directory `name` under the scratch space.
    #[must_use]
    pub fn scratch(&self, name: &str) -> PathBuf {
        let dir = Path::new(self.scratch_root).join(name);
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// Each of `commands`, with stdout on a full disk, exits 3 with exactly
    /// `PROGRAM: writing stdout: No space left on device (os error 28)` on
    /// stderr, once.
    #[cfg(target_os = "linux")]
    pub fn assert_full_stdout_is_exit_3(&self, program: &str, commands: &[&[&str]]) {
        for args in commands {
            let output = self
                .command()
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
    pub fn assert_lost_stderr_keeps_exit_codes(&self, cases: &[(&[&str], i32)]) {
        for &(args, code) in cases {
            for stderr in [dev_full(), Stdio::null()] {
                let output = self
                    .command()
                    .args(args)
                    .stdin(Stdio::null())
                    .stderr(stderr)
                    .output()
                    .unwrap();
                assert_eq!(output.status.code(), Some(code), "{args:?}");
            }
        }
    }

    /// Checks `docs/cli.md` against the flag tables: every command in
    /// `commands` has its usage there exactly as `program help COMMAND`
    /// prints it (rendered from its table), in a text block; and every usage
    /// line of `program` there is one of theirs.
    pub fn docs_show_the_usage(&self, program: &str, commands: &[&str]) {
        let docs = std::fs::read_to_string(root().join("docs/cli.md")).unwrap();
        for command in commands {
            let output = self.run(&["help", command]);
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
}

/// `/dev/full` opened for writing: a child's stdout or stderr on a full
/// disk.
#[cfg(target_os = "linux")]
#[must_use]
pub fn dev_full() -> Stdio {
    Stdio::from(
        std::fs::File::options()
            .write(true)
            .open("/dev/full")
            .unwrap(),
    )
}

/// Bytes as text, invalid UTF-8 replaced.
#[must_use]
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The repository's root.
#[must_use]
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A committed vector file's path, as a string.
#[must_use]
pub fn committed(name: &str) -> String {
    root()
        .join("reference/vectors")
        .join(name)
        .to_string_lossy()
        .into_owned()
}
