//! `micromap-index`: the command-line front end. Parsing and printing only;
//! the work is in the library and in `micromap-index-conformance`. Each
//! command lives in its own module with its flag table (`args`: one table
//! per command, which both parses and renders the usage); `help` renders
//! the usage texts, `output` is the one output layer (stdout and stderr
//! writers that never panic), the exit-code table and the one failure type;
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
//! | 4 | `render`: no Vulkan device with ray queries; nothing written |
//! | 130 | interrupted by Ctrl-C |
//! | 141 | stdout closed by its reader (`... \| head -1`): the command stops quietly, as shells report a GNU tool killed by SIGPIPE |
//!
//! A failed write to stderr is ignored (there is nowhere left to report it);
//! the exit code still tells.

mod args;
mod bake_command;
mod check_command;
mod eval_command;
mod geometry_usage;
mod gltf_out;
mod help;
mod input;
mod locate_command;
mod output;
mod preview;
mod progress;
mod render_command;
mod tree_command;
mod write_all_or_nothing;

use output::Exit;
use std::process::ExitCode;
use std::sync::OnceLock;

/// The program's name, which every message on stderr starts with.
pub(crate) const PROGRAM: &str = "micromap-index";

/// The command being run, for the usage text after a usage error.
static COMMAND: OnceLock<&'static str> = OnceLock::new();

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
        return usage("expected a command").into();
    };
    let asks_help = options
        .iter()
        .any(|&option| option == "--help" || option == "-h");
    if let Some((name, _)) = help::COMMANDS.iter().find(|(name, _)| *name == command) {
        let _ = COMMAND.set(name);
        if asks_help {
            return print_help(&help::command_help(command).unwrap_or_default()).into();
        }
    }
    if help::MOVED.contains(&command) && asks_help {
        return print_help(&help::moved_note(command)).into();
    }
    match (command, options) {
        ("eval", options) => eval_command::run(options).into(),
        ("locate", options) => locate_command::run(options).into(),
        ("check", options) => check_command::run(options).into(),
        ("tree", options) => tree_command::run(options).into(),
        ("bake", options) => bake_command::run_bake(options).into(),
        ("verify-bake", options) => bake_command::verify::run(options).into(),
        ("render", options) => render_command::run(options).into(),
        (moved, _) if help::MOVED.contains(&moved) => {
            output::report(help::moved_note(moved));
            Exit::Usage.into()
        }
        ("help" | "--help" | "-h", []) => print_help(&help::full_help()).into(),
        ("help", [topic]) => match help::command_help(topic) {
            Some(text) => print_help(&text).into(),
            None => usage(&format!("help: unknown command {topic:?}")).into(),
        },
        ("help", _) => usage("help takes at most one command").into(),
        _ => usage(&format!("unknown command {command:?}")).into(),
    }
}

fn print_help(text: &str) -> Exit {
    output::print_then(&format!("{text}\n"), Exit::Success)
}

/// Reports `message` and the usage (of the command being run, or of all) on
/// stderr; exit code 2.
pub(crate) fn usage(message: &str) -> Exit {
    let usage = match COMMAND.get() {
        Some(command) => format!(
            "{}\nrun `{PROGRAM} help` for every command and the exit codes",
            help::usage_of(command).unwrap_or_default()
        ),
        None => help::full_help(),
    };
    output::report(format_args!("{message}\n{usage}"));
    Exit::Usage
}
