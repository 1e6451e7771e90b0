//! The usage texts, rendered from the commands' flag tables
//! (`cli_support::args`): one per command (`COMMAND --help`, `help
//! COMMAND`), and the whole (`help`) with the variant list and the
//! exit-code table; [`PROGRAM`], the program as its messages name it, whose
//! usage errors end in one line pointing at the usage ("see
//! `micromap-index bake --help`") rather than the usage itself; and
//! [`version`].

use cli_support::args::{usage_text, Command};
use cli_support::output::{exit_code_table, Program};
use micromap_index_conformance::eval::Variant;
use std::fmt::Write as _;
use std::sync::OnceLock;

/// The program's name, which every message on stderr starts with.
const NAME: &str = "micromap-index";

/// The running program, passed to every command for its messages.
pub(crate) static PROGRAM: Program = Program {
    name: NAME,
    usage: usage_after_error,
};

/// The command being run, for the usage text after a usage error.
static COMMAND: OnceLock<&'static str> = OnceLock::new();

/// `command` (one of [`COMMANDS`]) is the one being run: a usage error
/// shows its usage.
pub(crate) fn running(command: &'static str) {
    let _ = COMMAND.set(command);
}

/// What follows a usage error's message: one line saying where the usage
/// is (the command being run's `--help`, or `help`), so the message stays
/// on the screen.
fn usage_after_error() -> String {
    match COMMAND.get() {
        Some(command) => format!("see `{NAME} {command} --help`"),
        None => format!("see `{NAME} help`"),
    }
}

/// `--version` and `-V`: the program and its version.
#[must_use]
pub(crate) fn version() -> String {
    format!("{NAME} {}", env!("CARGO_PKG_VERSION"))
}

/// Why `command` is no command, with the closest command if one is close
/// (`unknown command "bkae" (did you mean bake?)`).
#[must_use]
pub(crate) fn unknown_command(command: &str) -> String {
    let names = COMMANDS.iter().map(|(name, _)| *name).chain(["help"]);
    match cli_support::args::closest(command, names) {
        Some(name) => format!("unknown command {command:?} (did you mean {name}?)"),
        None => format!("unknown command {command:?}"),
    }
}

/// The commands, for "expected a command".
#[must_use]
pub(crate) fn command_list() -> String {
    let names: Vec<&str> = COMMANDS.iter().map(|(name, _)| *name).collect();
    names.join(", ")
}

/// Where a command's usage comes from.
pub(crate) enum Usage {
    /// Rendered from the tables (one, or the subcommands of one word), with
    /// prose common to them.
    Tables(&'static [&'static Command], &'static str),
}

/// The commands and their usage, in the order `help` lists them.
pub(crate) static COMMANDS: [(&str, Usage); 7] = [
    ("eval", Usage::Tables(&[&crate::eval_command::EVAL], "")),
    (
        "locate",
        Usage::Tables(&[&crate::locate_command::LOCATE], ""),
    ),
    ("check", Usage::Tables(&[&crate::check_command::CHECK], "")),
    (
        "tree",
        Usage::Tables(
            &[&crate::tree_command::ENCODE, &crate::tree_command::LOOKUP],
            crate::tree_command::ABOUT,
        ),
    ),
    ("bake", Usage::Tables(&[&crate::bake_command::BAKE], "")),
    (
        "verify-bake",
        Usage::Tables(&[&crate::verify_bake::VERIFY_BAKE], ""),
    ),
    (
        "render",
        Usage::Tables(&[&crate::render_command::RENDER], ""),
    ),
];

/// The commands of earlier releases that moved to the lab's binary.
pub(crate) const MOVED: [&str; 2] = ["prove", "vectors"];

/// The usage text of `command`, if it is one.
#[must_use]
pub(crate) fn usage_of(command: &str) -> Option<String> {
    COMMANDS
        .iter()
        .find(|(name, _)| *name == command)
        .map(|(_, usage)| match usage {
            Usage::Tables(tables, about) => usage_text(NAME, tables, about),
        })
}

/// Where a moved command went, in one line.
#[must_use]
pub(crate) fn moved_note(command: &str) -> String {
    format!(
        "{command} moved to micromap-lab, the lab's binary: run `micromap-lab {command} ...` \
         (in the repository: cargo run -p micromap-index-lab --bin micromap-lab -- {command} ...)"
    )
}

/// The variants, one per line, with the legacy names they also accept.
#[must_use]
pub(crate) fn variant_list() -> String {
    let mut text = String::from(
        "variants (eval --variant; the names of earlier releases are accepted as aliases):",
    );
    for variant in Variant::ALL {
        text.push_str("\n  ");
        text.push_str(variant.name());
        if let Some(legacy) = variant.legacy_name() {
            let _ = write!(text, " (alias {legacy})");
        }
    }
    text
}

/// `COMMAND --help` / `help COMMAND`: the command's usage, plus the variant
/// list for `eval`; for a moved command, where it went.
#[must_use]
pub(crate) fn command_help(command: &str) -> Option<String> {
    if MOVED.contains(&command) {
        return Some(moved_note(command));
    }
    let usage = usage_of(command)?;
    Some(if command == "eval" {
        format!("{usage}\n{}", variant_list())
    } else {
        usage
    })
}

/// `help`: everything.
#[must_use]
pub(crate) fn full_help() -> String {
    let mut text = format!(
        "usage: {NAME} COMMAND [OPTIONS]
       {NAME} COMMAND --help      one command's usage
       {NAME} help [COMMAND]
       {NAME} --version           the version (also -V)"
    );
    for (name, _) in &COMMANDS {
        text.push_str("\n\n");
        text.push_str(&usage_of(name).unwrap_or_default());
    }
    text.push_str(
        "\n\nprove and vectors moved to micromap-lab, the lab's binary (in the repository:\n\
         cargo run -p micromap-index-lab --bin micromap-lab -- help); here they exit 2\n\
         with a note saying so.",
    );
    text.push_str("\n\n");
    text.push_str(&variant_list());
    text.push_str("\n\n");
    text.push_str(&exit_code_table());
    text
}
