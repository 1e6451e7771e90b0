//! The usage texts, rendered from the commands' flag tables (`crate::args`):
//! one per command (`COMMAND --help`, `help COMMAND`, and after a usage
//! error), and the whole (`help`) with the variant list and the exit-code
//! table.

use crate::args::{usage_text, Command};
use crate::output::exit_code_table;
use crate::PROGRAM;
use micromap_index_conformance::eval::Variant;
use std::fmt::Write as _;

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
        Usage::Tables(&[&crate::bake_command::verify::VERIFY_BAKE], ""),
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
            Usage::Tables(tables, about) => usage_text(PROGRAM, tables, about),
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
        "usage: {PROGRAM} COMMAND [OPTIONS]
       {PROGRAM} COMMAND --help      one command's usage
       {PROGRAM} help [COMMAND]"
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
