//! `micromap-lab`: the lab's commands, which generate rather than check and
//! so need the lab (`micromap-index-lab`): `prove` (the face-by-face proof,
//! `--all-levels` the transducer product) and `vectors` (`--out`: write the
//! conformance vector files; `--answers-from`: the lab's functions' answers
//! to a vector file). Flags, outputs and exit codes are those these
//! commands had in `micromap-index`; messages on stderr start with
//! `micromap-lab:`.
//!
//! The flag tables, the output layer and the exit codes are the user CLI's
//! (`micromap-index-cli-support`), so both binaries parse, render usage and
//! fail the same way: the table in `micromap-lab help` and `docs/cli.md`.
//! Each command gets [`PROGRAM`] passed in, for its messages.

mod prove;
mod prove_all_levels;
mod vectors;

use cli_support::args::{usage_text, Command};
use cli_support::output::{self, exit_code_table, Exit, Program};
use std::process::ExitCode;
use std::sync::OnceLock;

/// The program's name, which every message on stderr starts with.
const NAME: &str = "micromap-lab";

/// The running program, as the commands report it.
static PROGRAM: Program = Program {
    name: NAME,
    usage: usage_after_error,
};

/// The commands and their tables, in the order `help` lists them.
static COMMANDS: [(&str, &[&Command]); 2] = [
    ("prove", &[&prove::PROVE, &prove_all_levels::ALL_LEVELS]),
    ("vectors", &[&vectors::VECTORS]),
];

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
    if let Some((name, _)) = COMMANDS.iter().find(|(name, _)| *name == command) {
        let _ = COMMAND.set(name);
        if options
            .iter()
            .any(|&option| option == "--help" || option == "-h")
        {
            return print_help(&usage_of(command).unwrap_or_default()).into();
        }
    }
    let exit = match (command, options) {
        ("prove", options) => prove::run(&PROGRAM, options),
        ("vectors", options) => vectors::run(&PROGRAM, options),
        ("help" | "--help" | "-h", []) => print_help(&full_help()),
        ("help", [topic]) => match usage_of(topic) {
            Some(text) => print_help(&text),
            None => usage(&format!("help: unknown command {topic:?}")),
        },
        ("help", _) => usage("help takes at most one command"),
        _ => usage(&format!("unknown command {command:?}")),
    };
    exit.into()
}

/// The usage text of `command`, if it is one.
fn usage_of(command: &str) -> Option<String> {
    COMMANDS
        .iter()
        .find(|(name, _)| *name == command)
        .map(|(_, tables)| usage_text(NAME, tables, ""))
}

/// `help`: everything.
fn full_help() -> String {
    let mut text = format!(
        "usage: {NAME} COMMAND [OPTIONS]
       {NAME} COMMAND --help      one command's usage
       {NAME} help [COMMAND]"
    );
    for (name, _) in &COMMANDS {
        text.push_str("\n\n");
        text.push_str(&usage_of(name).unwrap_or_default());
    }
    text.push_str("\n\n");
    text.push_str(&exit_code_table());
    text
}

fn print_help(text: &str) -> Exit {
    output::print_then(&PROGRAM, &format!("{text}\n"), Exit::Success)
}

/// Reports `message` and the usage (of the command being run, or of all) on
/// stderr; exit code 2.
fn usage(message: &str) -> Exit {
    PROGRAM.usage_error(message)
}

/// The usage after a usage error: the command being run's, or all.
fn usage_after_error() -> String {
    match COMMAND.get() {
        Some(command) => format!(
            "{}\nrun `{NAME} help` for every command and the exit codes",
            usage_of(command).unwrap_or_default()
        ),
        None => full_help(),
    }
}
