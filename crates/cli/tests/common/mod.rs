//! The CLI tests' binding of the shared spawn helpers
//! (`micromap_index_cli_support::testing`) to `micromap-index`. Each test
//! file uses a part.
#![allow(dead_code, unused_imports)]

#[cfg(target_os = "linux")]
pub use cli_support::testing::dev_full;
use cli_support::testing::Cli;
pub use cli_support::testing::{committed, root, text};
use std::path::PathBuf;
use std::process::{Command, Output};

/// `micromap-index`, as cargo built it for these tests.
pub const CLI: Cli = Cli::new(
    env!("CARGO_BIN_EXE_micromap-index"),
    env!("CARGO_TARGET_TMPDIR"),
);

/// The binary under test.
pub fn binary() -> Command {
    CLI.command()
}

/// Runs with stdin empty; stdout and stderr captured.
pub fn run(args: &[&str]) -> Output {
    CLI.run(args)
}

/// Runs with stdin empty; fails the test on a hang (still running after
/// [`HANG`]).
pub fn run_within_hang_guard(args: &[&str]) -> Output {
    CLI.run_within(args, HANG)
}

/// The hang guard of the tests: generous, so that only a hang (never a
/// slow or busy machine) reaches it.
pub const HANG: std::time::Duration = std::time::Duration::from_secs(600);

/// Runs with `stdin` as its input.
pub fn run_with_stdin(args: &[&str], stdin: &[u8]) -> Output {
    CLI.run_with_stdin(args, stdin)
}

/// A fresh, empty directory under cargo's per-test scratch space.
pub fn scratch(name: &str) -> PathBuf {
    CLI.scratch(name)
}
