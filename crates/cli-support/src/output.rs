//! The one output layer of every command: the exit-code table, and writers
//! for stdout and stderr that never panic.
//!
//! `println!` and `eprintln!` panic when the write fails ("failed printing to
//! stdout", exit 101), which `micromap-lab prove | head -3` or
//! `micromap-index help >/dev/full` trigger. Here a write to stdout that
//! fails because the reader went away (`EPIPE`; Rust ignores `SIGPIPE`, so the
//! write returns the error) ends the command quietly with [`Exit::BrokenPipe`];
//! any other failure (`ENOSPC` on a full disk, `EIO`) is reported on stderr
//! and ends it with [`Exit::Io`]. Messages to stderr are best effort: when
//! stderr itself is closed or full there is nowhere left to report, so the
//! error is dropped and the exit code alone tells.
//!
//! Every command returns an [`Exit`]; what ends one early is a [`Failure`],
//! which says how it is reported and with which code. Messages start with
//! the running program's name, from the [`Program`] each binary passes in.

use std::fmt;
use std::fmt::Write as _;
use std::io::{self, Write};
use std::process::ExitCode;

/// The running program, as its messages need it: passed in by each binary
/// (`micromap-index`, `micromap-lab`), so nothing here refers back to it.
#[derive(Clone, Copy, Debug)]
pub struct Program {
    /// The program's name, which every message on stderr starts with.
    pub name: &'static str,
    /// What follows a usage error's message on stderr: `micromap-index`
    /// points at the usage ("see `micromap-index bake --help`"), so the
    /// message stays on the screen; `micromap-lab` prints the command's
    /// usage.
    pub usage: fn() -> String,
}

impl Program {
    /// Writes `NAME: MESSAGE` and a newline to stderr; best effort (see the
    /// module docs).
    pub fn report(&self, message: impl fmt::Display) {
        let _ = writeln!(io::stderr().lock(), "{}: {message}", self.name);
    }

    /// Reports `message` and what follows it ([`Program::usage`]) on
    /// stderr; exit code 2.
    #[must_use]
    pub fn usage_error(&self, message: &str) -> Exit {
        self.report(format_args!("{message}\n{}", (self.usage)()));
        Exit::Usage
    }
}

/// The exit codes of every command (documented in `micromap-index help`,
/// the crate docs and `docs/cli.md`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Exit {
    /// 0: the command did what was asked (for `prove` and `check`: no
    /// mismatch).
    Success,
    /// 1: the command ran and found a difference: `prove` a mismatch (or a
    /// transition table that does not hold), `check` a mismatch, a missing or
    /// an unknown id.
    Failed,
    /// 2: usage error or malformed input: a command line of the wrong shape,
    /// a value out of range (`locate --level 33`), a malformed vectors file,
    /// or a destination `vectors --out` refuses (an existing file without
    /// `--force`, a path that is not a directory). Nothing was checked and
    /// nothing was written.
    Usage,
    /// 3: an I/O error: an input that cannot be read (a missing file, a
    /// directory as stdin) or an output that cannot be written (a full disk).
    /// Nothing is left half-written by `vectors --out`.
    Io,
    /// 4: `render` found no Vulkan device with what it needs (nothing traced).
    NoDevice,
    /// 5: `bake --gltf` refused some primitives (listed in `summary.json`
    /// and on stderr, each with its reason), baked the rest and wrote it;
    /// `--strict` makes a refusal exit 2 with nothing written.
    Partial,
    /// 130: interrupted by Ctrl-C (`prove`), as shells report a SIGINT death.
    Interrupted,
    /// 141: stdout was closed by its reader (`... | head -1`); the command
    /// stops quietly, as shells report a SIGPIPE death of a GNU tool. Not 0:
    /// the command did not finish what it was asked to do.
    BrokenPipe,
}

impl Exit {
    /// Every code, in the order of the table.
    pub const TABLE: [Exit; 8] = [
        Exit::Success,
        Exit::Failed,
        Exit::Usage,
        Exit::Io,
        Exit::NoDevice,
        Exit::Partial,
        Exit::Interrupted,
        Exit::BrokenPipe,
    ];

    /// The process exit status.
    #[must_use]
    pub fn code(self) -> u8 {
        match self {
            Exit::Success => 0,
            Exit::Failed => 1,
            Exit::Usage => 2,
            Exit::Io => 3,
            Exit::NoDevice => 4,
            Exit::Partial => 5,
            Exit::Interrupted => 130,
            Exit::BrokenPipe => 141,
        }
    }

    /// One line of the table as `help` prints it.
    #[must_use]
    pub fn meaning(self) -> &'static str {
        match self {
            Exit::Success => "success (prove, check: no mismatch)",
            Exit::Failed => {
                "the check failed: a mismatch (prove, check), a missing or unknown id (check)"
            }
            Exit::Usage => {
                "usage error or malformed input (bad option or value, malformed file, \
                 vectors --out refusing an existing file); nothing done"
            }
            Exit::Io => "I/O error: unreadable input, unwritable output (full disk)",
            Exit::NoDevice => "no Vulkan device with what render needs; nothing traced",
            Exit::Partial => {
                "bake --gltf refused some primitives (summary.json says why) and wrote the rest"
            }
            Exit::Interrupted => "interrupted (Ctrl-C)",
            Exit::BrokenPipe => "stdout closed by its reader (| head); stopped quietly",
        }
    }
}

impl From<Exit> for ExitCode {
    fn from(exit: Exit) -> Self {
        ExitCode::from(exit.code())
    }
}

/// The exit-code table as `help` prints it.
#[must_use]
pub fn exit_code_table() -> String {
    let mut text = String::from("exit codes (all commands):\n");
    for exit in Exit::TABLE {
        let _ = writeln!(text, "  {:>3}  {}", exit.code(), exit.meaning());
    }
    text.pop();
    text
}

/// What ended a command before it finished, by exit code.
#[derive(Debug)]
pub enum Failure {
    /// Exit 2, the message followed by the command's usage: a command line
    /// of the wrong shape.
    Usage(String),
    /// Exit 2: malformed input, a value out of range, a destination
    /// refused; nothing was done.
    Malformed(String),
    /// Exit 1: the check failed, or an internal error was found.
    Failed(String),
    /// Exit 3: an input that cannot be read, an output that cannot be
    /// written.
    Io(String),
    /// This exit, already reported (or quiet: a closed stdout).
    Exit(Exit),
}

impl Failure {
    /// Reports the failure on stderr as `program`'s and returns its exit.
    #[must_use]
    pub fn exit(self, program: &Program) -> Exit {
        let (message, exit) = match self {
            Failure::Usage(message) => return program.usage_error(&message),
            Failure::Malformed(message) => (message, Exit::Usage),
            Failure::Failed(message) => (message, Exit::Failed),
            Failure::Io(message) => (message, Exit::Io),
            Failure::Exit(exit) => return exit,
        };
        program.report(message);
        exit
    }
}

impl From<Exit> for Failure {
    fn from(exit: Exit) -> Self {
        Failure::Exit(exit)
    }
}

/// The exit of a command's outcome: its verdict, or its failure reported
/// as `program`'s.
#[must_use]
pub fn finish(program: &Program, outcome: Result<Exit, Failure>) -> Exit {
    outcome.unwrap_or_else(|failure| failure.exit(program))
}

/// Writes `text` to stderr as it is (no prefix, no newline); best effort.
pub fn to_stderr(text: impl fmt::Display) {
    let mut err = io::stderr().lock();
    let _ = write!(err, "{text}");
    let _ = err.flush();
}

/// What a failed write to stdout means: [`Exit::BrokenPipe`] (quiet) for a
/// closed pipe, otherwise the error reported on stderr (as `program`'s) and
/// [`Exit::Io`].
#[must_use]
pub fn stdout_failure(program: &Program, error: &io::Error) -> Exit {
    if error.kind() == io::ErrorKind::BrokenPipe {
        Exit::BrokenPipe
    } else {
        program.report(format_args!("writing stdout: {error}"));
        Exit::Io
    }
}

/// Stdout for one command: buffered, every failure mapped by
/// [`stdout_failure`]. Call [`Stdout::finish`] at the end: a failure of the
/// final flush is an error too (dropping without it loses nothing silently
/// only because Rust's exit flush would then ignore the error).
pub struct Stdout {
    program: Program,
    out: io::BufWriter<io::StdoutLock<'static>>,
    /// Flush after each line (for output a person or `head` reads as it
    /// comes, like `prove`'s rows), not only when the buffer fills.
    flush_each_line: bool,
    /// A write failed (and was reported): nothing more is written, so the
    /// failure is reported once.
    failed: bool,
}

impl Stdout {
    /// Buffered stdout, flushed when the buffer fills and at the end (for
    /// many short lines: `eval`); failures reported as `program`'s.
    #[must_use]
    pub fn buffered(program: &Program) -> Stdout {
        Stdout {
            program: *program,
            out: io::BufWriter::new(io::stdout().lock()),
            flush_each_line: false,
            failed: false,
        }
    }

    /// Stdout flushed after each line.
    #[must_use]
    pub fn line_by_line(program: &Program) -> Stdout {
        Stdout {
            flush_each_line: true,
            ..Stdout::buffered(program)
        }
    }

    /// Writes `text` and a newline.
    pub fn line(&mut self, text: impl fmt::Display) -> Result<(), Exit> {
        let written = writeln!(self.out, "{text}");
        self.check(written)?;
        if self.flush_each_line {
            self.flush()?;
        }
        Ok(())
    }

    /// Writes `text` as it is.
    pub fn text(&mut self, text: &str) -> Result<(), Exit> {
        let written = self.out.write_all(text.as_bytes());
        self.check(written)?;
        if self.flush_each_line {
            self.flush()?;
        }
        Ok(())
    }

    /// Flushes what is buffered.
    pub fn flush(&mut self) -> Result<(), Exit> {
        let flushed = self.out.flush();
        self.check(flushed)
    }

    /// Maps a failed write, once.
    fn check(&mut self, result: io::Result<()>) -> Result<(), Exit> {
        result.map_err(|e| {
            self.failed = true;
            stdout_failure(&self.program, &e)
        })
    }

    /// Flushes and returns `exit`, or the failure of the flush. After an
    /// earlier failure, returns `exit` (that failure) without writing again.
    #[must_use]
    pub fn finish(mut self, exit: Exit) -> Exit {
        if self.failed {
            return exit;
        }
        match self.flush() {
            Ok(()) => exit,
            Err(failure) => failure,
        }
    }
}

/// Writes `text` to stdout and returns `verdict`, or the failure of the
/// write (reported as `program`'s; for commands that print one finished
/// report).
#[must_use]
pub fn print_then(program: &Program, text: &str, verdict: Exit) -> Exit {
    let mut out = Stdout::buffered(program);
    let exit = match out.text(text) {
        Ok(()) => verdict,
        Err(failure) => failure,
    };
    out.finish(exit)
}

/// `Ok(exit)` or `Err(exit)` as one exit.
#[must_use]
pub fn either(result: Result<Exit, Exit>) -> Exit {
    match result {
        Ok(exit) | Err(exit) => exit,
    }
}
