//! `micromap-index`: the command-line front end. Parsing and printing only;
//! the work is in the library and in `micromap-index-conformance`. Each
//! command lives in its own module with its flag table
//! (`micromap-index-cli-support`'s `args`: one table per command, which both
//! parses and renders the usage); `help` renders the usage texts and holds
//! [`help::PROGRAM`], which every command gets passed in for its messages
//! (a usage error is its message and one line pointing at the usage;
//! `--version`/`-V` prints the version);
//! `cli_support::output` is the one output layer (stdout and stderr writers
//! that never panic), the exit-code table and the one failure type;
//! `progress` draws a long step's progress bar (on a terminal only).
//!
//! `prove` and `vectors` moved to the lab's binary, `micromap-lab`
//! (`crates/lab`); here they exit 2 with a one-line note saying so
//! (`help prove` and `prove --help` print the note, exit 0).
//!
//! # Exit codes (the same for every command; also in `micromap-index help`
//! and `docs/cli.md`)
//!
//! | code | meaning |
//! |------|---------|
//! | 0 | success (`prove`, `check`: no mismatch) |
//! | 1 | the check failed: a mismatch (`prove`, `check`), a missing or unknown id (`check`) |
//! | 2 | usage error or malformed input: a bad option or value (`locate --level 33`, `prove --sample 0`), a malformed file, `vectors --out` refusing an existing file; nothing was done |
//! | 3 | I/O error: unreadable input (a missing file, a directory as stdin), unwritable output (a full disk) |
//! | 4 | `render`: no Vulkan device with what it needs; nothing written |
//! | 130 | interrupted by Ctrl-C |
//! | 141 | stdout closed by its reader (`... \| head -1`): the command stops quietly, as shells report a GNU tool killed by SIGPIPE |
//!
//! A failed write to stderr is ignored (there is nowhere left to report it);
//! the exit code still tells.

mod bake_args;
mod bake_command;
mod check_command;
mod eval_command;
mod geometry_usage;
mod gltf_out;
mod help;
mod inputs;
mod locate_command;
mod preview;
mod progress;
mod render_command;
mod tree_command;
mod verify_bake;

use cli_support::output::{self, Exit};
use help::PROGRAM;
use std::process::ExitCode;

fn main() -> ExitCode {
    let mut args = Vec::new();
    for arg in std::env::args_os().skip(1) {
        match arg.into_string() {
            Ok(arg) => args.push(arg),
            Err(arg) => return usage(&format!("argument {arg:?} is not UTF-8")).into(),
        }
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let Some((&command, options)) = args.split_first() else {
        return usage(&format!("expected a command: {}", help::command_list())).into();
    };
    if matches!(command, "--version" | "-V") && options.is_empty() {
        return print_help(&help::version()).into();
    }
    let asks_help = options
        .iter()
        .any(|&option| option == "--help" || option == "-h");
    if let Some((name, _)) = help::COMMANDS.iter().find(|(name, _)| *name == command) {
        help::running(name);
        if asks_help {
            return print_help(&help::command_help(command).unwrap_or_default()).into();
        }
    }
    if help::MOVED.contains(&command) && asks_help {
        return print_help(&help::moved_note(command)).into();
    }
    match (command, options) {
        ("eval", options) => eval_command::run(&PROGRAM, options).into(),
        ("locate", options) => locate_command::run(&PROGRAM, options).into(),
        ("check", options) => check_command::run(&PROGRAM, options).into(),
        ("tree", options) => tree_command::run(&PROGRAM, options).into(),
        ("bake", options) => bake_command::run_bake(&PROGRAM, options).into(),
        ("verify-bake", options) => verify_bake::run(&PROGRAM, options).into(),
        ("render", options) => render_command::run(&PROGRAM, options).into(),
        (moved, _) if help::MOVED.contains(&moved) => {
            PROGRAM.report(help::moved_note(moved));
            Exit::Usage.into()
        }
        ("help" | "--help" | "-h", []) => print_help(&help::full_help()).into(),
        ("help", [topic]) => match help::command_help(topic) {
            Some(text) => print_help(&text).into(),
            None => usage(&format!("help: {}", help::unknown_command(topic))).into(),
        },
        ("help", _) => usage("help takes at most one command").into(),
        _ => usage(&help::unknown_command(command)).into(),
    }
}

fn print_help(text: &str) -> Exit {
    output::print_then(&PROGRAM, &format!("{text}\n"), Exit::Success)
}

/// Reports `message` and where the usage is (the command being run's
/// `--help`, or `help`) on stderr; exit code 2.
fn usage(message: &str) -> Exit {
    PROGRAM.usage_error(message)
}
