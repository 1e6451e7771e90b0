//! `micromap-index check --vectors FILE --answers FILE [--examples K]`:
//! compares another implementation's answers with a vector file and prints
//! the report (`micromap_index_verify::vectors::CheckReport`) to stdout.
//!
//! `--answers -` reads the answers from stdin. Exit codes:
//!
//! * 0 — every case answered with its expected index, no other ids;
//! * 1 — a mismatch, a refused or missing case, or an id not in the file;
//! * 2 — usage error, or a file that cannot be read or parsed (nothing was
//!   checked; the message names the file and, for answers, the line).

use crate::usage_error;
use micromap_index_verify::vectors::{check, parse_answers, parse_vector_file, VectorFile};
use std::collections::BTreeMap;
use std::io::{self, Read, Write};
use std::process::ExitCode;

/// Examples per tag when `--examples` is not given.
const DEFAULT_EXAMPLES: usize = 5;

pub(crate) fn run(options: &[&str]) -> ExitCode {
    let options = match named_options("check", options, &["--vectors", "--answers", "--examples"]) {
        Ok(options) => options,
        Err(message) => return usage_error(&message),
    };
    let (Some(&vectors_path), Some(&answers_path)) =
        (options.get("--vectors"), options.get("--answers"))
    else {
        return usage_error("check needs --vectors FILE and --answers FILE");
    };
    let examples = match options.get("--examples").map(|text| text.parse::<usize>()) {
        None => DEFAULT_EXAMPLES,
        Some(Ok(examples)) => examples,
        Some(Err(_)) => return usage_error("check: --examples needs a whole number"),
    };
    let vectors = match read_vectors(vectors_path) {
        Ok(vectors) => vectors,
        Err(message) => return cannot_check(&message),
    };
    let answers = match read_bytes(answers_path).and_then(|bytes| {
        parse_answers(&bytes).map_err(|e| format!("{}: {e}", shown_path(answers_path)))
    }) {
        Ok(answers) => answers,
        Err(message) => return cannot_check(&message),
    };
    let report = check(&vectors, &answers);
    let mut out = io::stdout().lock();
    if out
        .write_all(report.render(examples).as_bytes())
        .and_then(|()| out.flush())
        .is_err()
    {
        return ExitCode::from(2);
    }
    if report.passed() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

fn cannot_check(message: &str) -> ExitCode {
    eprintln!("micromap-index: {message}");
    ExitCode::from(2)
}

fn shown_path(path: &str) -> &str {
    if path == "-" {
        "stdin"
    } else {
        path
    }
}

/// The file's bytes (`-`: stdin), or a message naming it.
fn read_bytes(path: &str) -> Result<Vec<u8>, String> {
    if path == "-" {
        let mut bytes = Vec::new();
        return io::stdin()
            .read_to_end(&mut bytes)
            .map(|_| bytes)
            .map_err(|e| format!("reading stdin: {e}"));
    }
    std::fs::read(path).map_err(|e| format!("cannot read {path}: {e}"))
}

/// Reads and parses a vector file, or a message naming it.
pub(crate) fn read_vectors(path: &str) -> Result<VectorFile, String> {
    let bytes = read_bytes(path)?;
    parse_vector_file(&bytes).map_err(|e| format!("{}: {e}", shown_path(path)))
}

/// `--name VALUE` or `--name=VALUE` options from `allowed`, each at most
/// once, and nothing else.
pub(crate) fn named_options<'a>(
    command: &str,
    options: &[&'a str],
    allowed: &[&str],
) -> Result<BTreeMap<String, &'a str>, String> {
    let mut found = BTreeMap::new();
    let mut rest = options;
    while let Some((&option, after)) = rest.split_first() {
        let (name, inline_value) = match option.split_once('=') {
            Some((name, value)) => (name, Some(value)),
            None => (option, None),
        };
        if !allowed.contains(&name) {
            return Err(format!("{command}: unknown option {option:?}"));
        }
        let (value, after) = match (inline_value, after.split_first()) {
            (Some(value), _) => (value, after),
            (None, Some((&value, after))) => (value, after),
            (None, None) => return Err(format!("{command}: {name} needs a value")),
        };
        if found.insert(name.to_owned(), value).is_some() {
            return Err(format!("{command}: {name} given twice"));
        }
        rest = after;
    }
    Ok(found)
}
