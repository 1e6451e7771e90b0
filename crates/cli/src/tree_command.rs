//! `micromap-index tree encode|lookup`: the paper's succinct tree from the
//! command line (library: `micromap_index::succinct`).
//!
//! Exit codes: 0 success; 1 a value out of range (level above 16, index not
//! below `4^level`); 2 a malformed command line or input (unknown option,
//! bad format, states, tree bits or leaf data); 3 an internal error (the
//! paper's Algorithm 3 and the level-order layout disagree: a bug, please
//! report it).

use crate::output::{print_then, report, Exit};
use micromap_index::micromap::{Format, State};
use micromap_index::succinct::{LevelOrderTree, PaperTree, TreeError, MAX_TREE_LEVEL};
use micromap_index::Level;
use micromap_index_lab::value::Value;
use serde::Serialize;
use std::io::{self, Read};
use std::process::ExitCode;

pub(crate) const USAGE: &str = "\
usage: micromap-index tree encode --format 2|4 --level L [--states S]
       micromap-index tree lookup --format 2|4 --level L --tree BITS --data STATES
                                  (--index I | --u X --v Y)
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

pub(crate) fn run(options: &[&str]) -> ExitCode {
    // `tree --help`, `tree encode --help` and `help tree` are handled by
    // main through `help::command_help("tree")`.
    match options.split_first() {
        Some((&"encode", rest)) => finish(encode(rest)),
        Some((&"lookup", rest)) => finish(lookup(rest)),
        _ => crate::usage_error("tree needs a subcommand: encode or lookup"),
    }
}

/// What went wrong, by exit code (the table in `micromap-index help`).
enum Failure {
    /// Exit 2, with the usage.
    Usage(String),
    /// Exit 2: the states, bits, data or a value are malformed.
    Malformed(String),
    /// Exit 2: a value is out of range (a level, an index).
    OutOfRange(String),
    /// Exit 1: Algorithm 3 and the level-order lookup disagree (a bug).
    Disagree(String),
    /// Exit 3: standard input could not be read.
    Io(String),
}

fn finish(outcome: Result<String, Failure>) -> ExitCode {
    let exit = match outcome {
        Ok(line) => print_then(&format!("{line}\n"), Exit::Success),
        Err(Failure::Usage(message)) => crate::usage(&message),
        Err(Failure::Malformed(message) | Failure::OutOfRange(message)) => {
            report(message);
            Exit::Usage
        }
        Err(Failure::Io(message)) => {
            report(message);
            Exit::Io
        }
        Err(Failure::Disagree(message)) => {
            report(format_args!("internal error: {message}"));
            Exit::Failed
        }
    };
    exit.into()
}

/// The values of `--name VALUE` / `--name=VALUE` options, each at most
/// once, names from `known`.
fn options<'a>(
    command: &str,
    given: &[&'a str],
    known: &[&'static str],
) -> Result<Vec<(&'static str, &'a str)>, Failure> {
    let mut found: Vec<(&'static str, &'a str)> = Vec::new();
    let mut rest = given;
    while let Some((&option, after)) = rest.split_first() {
        let (name, inline_value) = match option.split_once('=') {
            Some((name, value)) => (name, Some(value)),
            None => (option, None),
        };
        let Some(&name) = known.iter().find(|&&k| k == name) else {
            return Err(Failure::Usage(format!(
                "tree {command}: unknown option {option:?}"
            )));
        };
        let (value, after) = match (inline_value, after.split_first()) {
            (Some(value), _) => (value, after),
            (None, Some((&value, after))) => (value, after),
            (None, None) => {
                return Err(Failure::Usage(format!(
                    "tree {command}: {name} needs a value"
                )))
            }
        };
        if found.iter().any(|&(n, _)| n == name) {
            return Err(Failure::Usage(format!(
                "tree {command}: {name} given twice"
            )));
        }
        found.push((name, value));
        rest = after;
    }
    Ok(found)
}

fn get<'a>(found: &[(&'static str, &'a str)], name: &str) -> Option<&'a str> {
    found.iter().find(|&&(n, _)| n == name).map(|&(_, v)| v)
}

fn required<'a>(
    command: &str,
    found: &[(&'static str, &'a str)],
    name: &str,
) -> Result<&'a str, Failure> {
    get(found, name).ok_or_else(|| Failure::Usage(format!("tree {command} needs {name}")))
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

fn parse_level(text: &str) -> Result<Level, Failure> {
    if text.is_empty() || !text.bytes().all(|b| b.is_ascii_digit()) {
        return Err(Failure::Malformed(format!(
            "--level {text:?}: expected a whole number"
        )));
    }
    match text.parse::<u32>() {
        Ok(level) if level <= MAX_TREE_LEVEL => {
            Level::new(level).map_err(|e| Failure::OutOfRange(e.to_string()))
        }
        _ => Err(Failure::OutOfRange(format!(
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
    match error {
        TreeError::LevelTooHigh { .. } => Failure::OutOfRange(error.to_string()),
        _ => Failure::Malformed(error.to_string()),
    }
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
    let found = options("encode", given, &["--format", "--level", "--states"])?;
    let format = parse_format(required("encode", &found, "--format")?)?;
    let level = parse_level(required("encode", &found, "--level")?)?;
    let stdin_text;
    let text = match get(&found, "--states") {
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
    serde_json::to_string(&encoded).map_err(|e| Failure::Disagree(e.to_string()))
}

fn lookup(given: &[&str]) -> Result<String, Failure> {
    let found = options(
        "lookup",
        given,
        &[
            "--format", "--level", "--tree", "--data", "--index", "--u", "--v",
        ],
    )?;
    let format = parse_format(required("lookup", &found, "--format")?)?;
    let level = parse_level(required("lookup", &found, "--level")?)?;
    let bits_text = required("lookup", &found, "--tree")?;
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
    let leaves = parse_states("--data", required("lookup", &found, "--data")?, format)?;
    let index = match (
        get(&found, "--index"),
        get(&found, "--u"),
        get(&found, "--v"),
    ) {
        (Some(index), None, None) => {
            let count = 1u64 << (2 * level.get());
            match index.parse::<u64>() {
                Ok(i) if i < count => i,
                _ if !index.is_empty() && index.bytes().all(|b| b.is_ascii_digit()) => {
                    return Err(Failure::OutOfRange(format!(
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
                .map_err(|e| Failure::OutOfRange(e.to_string()))?;
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
        (by_paper, by_level_order) => Err(Failure::Disagree(format!(
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
