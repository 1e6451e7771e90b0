//! `micromap-index tree encode|lookup`: the paper's succinct tree from the
//! command line (library: `micromap_index::succinct`).
//!
//! Exit codes: 0 success; 1 an internal error (the paper's Algorithm 3 and
//! the level-order layout disagree: a bug, please report it); 2 a malformed
//! command line or input (unknown option, bad format, states, tree bits or
//! leaf data) or a value out of range (level above 16, index not below
//! `4^level`); 3 standard input unreadable.

use cli_support::args::{whole_number, Command, Flag, Parsed};
use cli_support::output::{self, print_then, Exit, Failure, Program};
use micromap_index::micromap::{Format, State};
use micromap_index::succinct::{LevelOrderTree, PaperTree, TreeError, MAX_TREE_LEVEL};
use micromap_index::Level;
use micromap_index_conformance::value::Value;
use serde::Serialize;
use std::io::{self, Read};

const FORMAT: Flag = Flag::value("--format", "2|4", "2-state or 4-state micromap");
const LEVEL: Flag = Flag::value("--level", "L", "the subdivision level, 0..=16");

/// The flag table of `tree encode`.
pub(crate) static ENCODE: Command = Command {
    name: "tree encode",
    forms: &["--format 2|4 --level L [--states S]"],
    about: "",
    flags: &[
        FORMAT,
        LEVEL,
        Flag::value(
            "--states",
            "S",
            "the micromap's states (absent or -: stdin)",
        ),
    ],
};

/// The flag table of `tree lookup`.
pub(crate) static LOOKUP: Command = Command {
    name: "tree lookup",
    forms: &["--format 2|4 --level L --tree BITS --data STATES
                                  (--index I | --u X --v Y)"],
    about: "",
    flags: &[
        FORMAT,
        LEVEL,
        Flag::value(
            "--tree",
            "BITS",
            "the depth-first tree bits that encode printed",
        ),
        Flag::value("--data", "STATES", "the leaf states that encode printed"),
        Flag::value("--index", "I", "the micro-triangle, 0..4^L"),
        Flag::value("--u", "X", "or the binary32 hit's u"),
        Flag::value("--v", "Y", "and v"),
    ],
};

/// The prose of `tree`'s usage, after both synopses.
pub(crate) const ABOUT: &str = "\
encode: S is the micromap, 4^L characters 0..3 (0 transparent, 1 opaque,
        2 unknown-transparent, 3 unknown-opaque; a 2-state map only 0 and 1),
        one per micro-triangle in index order; from standard input when
        --states is absent or -. Prints one JSON object: \"tree\" (the paper's
        depth-first tree bits, 1 internal, 0 leaf), \"data\" (the leaf states),
        \"tree_bits\", \"data_bits\", \"flat_bits\" (4^L states at 1 or 2 bits),
        \"paper_bits\" (tree + data), \"level_order_bits\" (the level-order
        layout: internal bits + rank directory + data), and its parts
        \"level_order_internal_bits\", \"level_order_directory_bits\".
lookup: the state of micro-triangle I, or of the binary32 hit (X, Y) through
        the Vulkan reference index (X, Y: \"0x\" + 8 hex digits, or an exact
        decimal or p/q that is a binary32 value), read from the tree by the
        paper's Algorithm 3 and by the level-order layout. Prints
        {\"state\": s}.
levels: 0..=16. Exit 0 ok, 1 the two lookups disagree (a bug: please report
        it), 2 malformed command line, states, bits or data, or a value out
        of range, 3 standard input unreadable.";

pub(crate) fn run(program: &Program, options: &[&str]) -> Exit {
    // `tree --help`, `tree encode --help` and `help tree` are handled by
    // main through `help::command_help("tree")`.
    let outcome = match options.split_first() {
        Some((&"encode", rest)) => encode(rest),
        Some((&"lookup", rest)) => lookup(rest),
        _ => Err(Failure::Usage(
            "tree needs a subcommand: encode or lookup".into(),
        )),
    };
    output::finish(
        program,
        outcome.map(|line| print_then(program, &format!("{line}\n"), Exit::Success)),
    )
}

/// `given` parsed by `table`.
fn options<'a>(table: &'static Command, given: &[&'a str]) -> Result<Parsed<'a>, Failure> {
    table
        .parse(given)
        .map_err(|e| Failure::Usage(table.error_message(&e)))
}

fn required<'a>(table: &Command, found: &Parsed<'a>, name: &str) -> Result<&'a str, Failure> {
    found
        .get(name)
        .ok_or_else(|| Failure::Usage(format!("{} needs {name}", table.name)))
}

/// An internal error: a bug (exit 1).
fn internal(message: impl std::fmt::Display) -> Failure {
    Failure::Failed(format!("internal error: {message}"))
}

fn parse_format(text: &str) -> Result<Format, Failure> {
    match text {
        "2" => Ok(Format::TwoState),
        "4" => Ok(Format::FourState),
        _ => Err(Failure::Malformed(format!(
            "--format {text:?}: expected 2 (2-state) or 4 (4-state)"
        ))),
    }
}

/// A level: digits only (no sign), at most [`MAX_TREE_LEVEL`].
fn parse_level(text: &str) -> Result<Level, Failure> {
    let number = if text.bytes().all(|b| b.is_ascii_digit()) {
        whole_number(text).ok()
    } else {
        None
    };
    match number {
        None => Err(Failure::Malformed(format!(
            "--level {text:?}: expected a whole number"
        ))),
        Some(Some(level)) if level <= u64::from(MAX_TREE_LEVEL) => {
            Level::new(level as u32).map_err(|e| Failure::Malformed(e.to_string()))
        }
        Some(_) => Err(Failure::Malformed(format!(
            "level {text} is too high: trees take levels 0..={MAX_TREE_LEVEL}"
        ))),
    }
}

/// States written as characters `0`..`3`.
fn parse_states(what: &str, text: &str, format: Format) -> Result<Vec<State>, Failure> {
    text.bytes()
        .enumerate()
        .map(|(i, b)| {
            let state = match b {
                b'0'..=b'3' => State::from_bits(b - b'0'),
                _ => None,
            };
            match state {
                Some(state) if format.holds(state) => Ok(state),
                Some(state) => Err(Failure::Malformed(format!(
                    "{what}: character {i} is {state} ({}), which a 2-state map cannot hold",
                    char::from(b)
                ))),
                None => Err(Failure::Malformed(format!(
                    "{what}: character {i} is {:?}, expected 0, 1, 2 or 3",
                    char::from(b)
                ))),
            }
        })
        .collect()
}

fn state_chars(states: &[State]) -> String {
    states.iter().map(|s| char::from(b'0' + s.bits())).collect()
}

#[allow(clippy::needless_pass_by_value)] // used as `map_err(tree_error)`
fn tree_error(error: TreeError) -> Failure {
    Failure::Malformed(error.to_string())
}

#[derive(Serialize)]
struct Encoded {
    level: u32,
    format: u32,
    tree: String,
    data: String,
    tree_bits: u64,
    data_bits: u64,
    flat_bits: u64,
    paper_bits: u64,
    level_order_bits: u64,
    level_order_internal_bits: u64,
    level_order_directory_bits: u64,
}

fn encode(given: &[&str]) -> Result<String, Failure> {
    let found = options(&ENCODE, given)?;
    let format = parse_format(required(&ENCODE, &found, "--format")?)?;
    let level = parse_level(required(&ENCODE, &found, "--level")?)?;
    let stdin_text;
    let text = match found.get("--states") {
        Some(text) if text != "-" => text,
        _ => {
            // A level-L string has 4^L characters; stdin is read up to that
            // and 4096 bytes of trailing whitespace, never endlessly.
            let limit = (1u64 << (2 * level.get())) + 4096;
            let mut buffer = String::new();
            io::stdin()
                .take(limit + 1)
                .read_to_string(&mut buffer)
                .map_err(|e| Failure::Io(format!("reading the states from stdin: {e}")))?;
            if buffer.len() as u64 > limit {
                return Err(Failure::Malformed(format!(
                    "stdin: over the limit of {limit} bytes for a level-{level} state string \
                     (4^{level} characters and 4096 bytes of whitespace)"
                )));
            }
            stdin_text = buffer;
            stdin_text.trim_end()
        }
    };
    let states = parse_states("--states", text, format)?;
    let expected = 1usize << (2 * level.get());
    if states.len() != expected {
        return Err(Failure::Malformed(format!(
            "--states has {} characters; a level-{level} micromap has 4^{level} = {expected}",
            states.len()
        )));
    }
    let paper = PaperTree::encode(level, format, &states).map_err(tree_error)?;
    let fast = LevelOrderTree::from_paper(&paper);
    let encoded = Encoded {
        level: level.get(),
        format: 2 * format.bits_per_state(),
        tree: paper.tree_bit_string(),
        data: state_chars(&paper.leaf_states()),
        tree_bits: paper.tree_bits(),
        data_bits: paper.data_bits(),
        flat_bits: expected as u64 * u64::from(format.bits_per_state()),
        paper_bits: paper.total_bits(),
        level_order_bits: fast.total_bits(),
        level_order_internal_bits: fast.internal_bits(),
        level_order_directory_bits: fast.directory_bits(),
    };
    serde_json::to_string(&encoded).map_err(internal)
}

fn lookup(given: &[&str]) -> Result<String, Failure> {
    let found = options(&LOOKUP, given)?;
    let format = parse_format(required(&LOOKUP, &found, "--format")?)?;
    let level = parse_level(required(&LOOKUP, &found, "--level")?)?;
    let bits_text = required(&LOOKUP, &found, "--tree")?;
    let bits = bits_text
        .bytes()
        .enumerate()
        .map(|(i, b)| match b {
            b'0' => Ok(false),
            b'1' => Ok(true),
            _ => Err(Failure::Malformed(format!(
                "--tree: character {i} is {:?}, expected 0 or 1",
                char::from(b)
            ))),
        })
        .collect::<Result<Vec<bool>, Failure>>()?;
    let leaves = parse_states("--data", required(&LOOKUP, &found, "--data")?, format)?;
    let index = match (found.get("--index"), found.get("--u"), found.get("--v")) {
        (Some(index), None, None) => {
            let count = 1u64 << (2 * level.get());
            match index.parse::<u64>() {
                Ok(i) if i < count => i,
                _ if !index.is_empty() && index.bytes().all(|b| b.is_ascii_digit()) => {
                    return Err(Failure::Malformed(format!(
                        "index {index} is out of range for level {level}: valid indices are 0..={}",
                        count - 1
                    )))
                }
                _ => {
                    return Err(Failure::Malformed(format!(
                        "--index {index:?}: expected a whole number"
                    )))
                }
            }
        }
        (None, Some(u), Some(v)) => {
            let coordinate = |name: &str, text: &str| {
                Value::parse(text)
                    .and_then(|value| value.to_f32())
                    .map_err(|e| Failure::Malformed(format!("{name}: {e}")))
            };
            let (u, v) = (coordinate("--u", u)?, coordinate("--v", v)?);
            let level = micromap_index::SpecLevel::try_from(level)
                .map_err(|e| Failure::Malformed(e.to_string()))?;
            u64::from(micromap_index::spec::index_f32(u, v, level))
        }
        _ => {
            return Err(Failure::Usage(
                "tree lookup needs --index I, or --u X and --v Y".into(),
            ))
        }
    };
    let paper = PaperTree::from_parts(level, format, bits, &leaves).map_err(tree_error)?;
    let fast = LevelOrderTree::from_paper(&paper);
    match (paper.get(index), fast.get(index)) {
        (Some(by_paper), Some(by_level_order)) if by_paper == by_level_order => {
            Ok(format!("{{\"state\":{}}}", by_paper.bits()))
        }
        (by_paper, by_level_order) => Err(internal(format_args!(
            "index {index}: Algorithm 3 reads {by_paper:?}, the level-order layout {by_level_order:?}"
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn states_parse_with_their_position_in_errors() {
        assert!(parse_states("s", "0123", Format::FourState).is_ok());
        match parse_states("s", "0120", Format::TwoState) {
            Err(Failure::Malformed(m)) => assert!(m.contains("character 2"), "{m}"),
            _ => panic!("a 2-state map took state 2"),
        }
        assert!(matches!(
            parse_states("s", "01x", Format::FourState),
            Err(Failure::Malformed(_))
        ));
    }
}
