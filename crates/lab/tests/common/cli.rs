//! The lab tests' binding of the shared spawn helpers
//! (`micromap_index_cli_support::testing`) to `micromap-lab`.
#![allow(dead_code, unused_imports)]

use cli_support::testing::Cli;
pub use cli_support::testing::{committed, root, text};
use std::path::PathBuf;
use std::process::{Command, Output};

/// `micromap-lab`, as cargo built it for these tests.
pub const CLI: Cli = Cli::new(
    env!("CARGO_BIN_EXE_micromap-lab"),
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

/// Runs, reads `lines` lines of stdout, then closes it.
pub fn close_stdout_after(args: &[&str], lines: usize) -> (Option<i32>, Vec<String>, String) {
    CLI.close_stdout_after(args, lines)
}

/// A fresh, empty directory under cargo's per-test scratch space.
pub fn scratch(name: &str) -> PathBuf {
    CLI.scratch(name)
}
