//! `micromap-index check --vectors FILE --answers FILE [--levels A..=B]
//! [--tags T,..] [--exclude-tags T,..] [--examples K] [--json]`: compares
//! another implementation's answers with a vector file and prints the
//! report (`micromap_index_lab::vectors::CheckReport`) to stdout.
//!
//! The answers are read first (`--answers -` reads stdin), then the vector
//! file is streamed case by case: memory for the answers and one case.
//! `--levels`/`--tags`/`--exclude-tags` select cases (the others count as
//! skipped); answers `{"id": N, "unsupported": true}` are counted apart.
//! `--json` prints one JSON object instead of the text. Exit codes:
//!
//! * 0 — every selected case answered with its expected index (or
//!   unsupported), at least one matched, no other ids;
//! * 1 — a mismatch, a refused or missing case, an id not in the file, or
//!   nothing matched;
//! * 2 — usage error, or a file that cannot be parsed or is malformed (no
//!   cases, an expected index `>= 4^level`, an unknown `function`), or a
//!   selection that covers no case (nothing was checked; the message names
//!   the file and, for answers, the line);
//! * 3 — a file that cannot be read;
//! * 141 — stdout closed by its reader (the table in `micromap-index help`).

use crate::output::{print_then, report, Exit};
use crate::usage_error;
use micromap_index_lab::vectors::{
    check_reader, is_known_tag, parse_answers, parse_vector_file, tag, Selection, VectorFile,
};
use std::collections::BTreeMap;
use std::io::{self, BufReader, Read};
use std::process::ExitCode;

/// Examples per class when `--examples` is not given.
const DEFAULT_EXAMPLES: usize = 5;

pub(crate) fn run(options: &[&str]) -> ExitCode {
    let json = options.contains(&"--json");
    let options: Vec<&str> = options.iter().copied().filter(|o| *o != "--json").collect();
    let options = match named_options(
        "check",
        &options,
        &[
            "--vectors",
            "--answers",
            "--examples",
            "--levels",
            "--tags",
            "--exclude-tags",
        ],
    ) {
        Ok(options) => options,
        Err(message) => return usage_error(&message),
    };
    let (Some(&vectors_path), Some(&answers_path)) =
        (options.get("--vectors"), options.get("--answers"))
    else {
        return usage_error("check needs --vectors FILE and --answers FILE");
    };
    if vectors_path == "-" && answers_path == "-" {
        return usage_error("check: --vectors and --answers cannot both be stdin");
    }
    let examples = match options.get("--examples").map(|text| text.parse::<usize>()) {
        None => DEFAULT_EXAMPLES,
        Some(Ok(examples)) => examples,
        Some(Err(_)) => return usage_error("check: --examples needs a whole number"),
    };
    let selection = match selection(&options) {
        Ok(selection) => selection,
        Err(message) => return usage_error(&message),
    };
    let answers = match read_answers(answers_path) {
        Ok(Err(message)) => return cannot_check(&message),
        Ok(Ok(bytes)) => match parse_answers(&bytes) {
            Ok(answers) => answers,
            Err(e) => return cannot_check(&format!("{}: {e}", shown_path(answers_path))),
        },
        Err(message) => return unreadable(&message),
    };
    let report = match open(vectors_path) {
        Ok(reader) => match check_reader(reader, &answers, selection) {
            Ok(report) => report,
            Err(e) => return cannot_check(&format!("{}: {e}", shown_path(vectors_path))),
        },
        Err(message) => return unreadable(&message),
    };
    let text = if json {
        format!("{}\n", report.to_json(examples))
    } else {
        report.render(examples)
    };
    let verdict = if report.passed() {
        Exit::Success
    } else {
        Exit::Failed
    };
    print_then(&text, verdict).into()
}

/// `--levels A..=B` (or `N`), `--tags T,..`, `--exclude-tags T,..`.
fn selection(options: &BTreeMap<String, &str>) -> Result<Selection, String> {
    let mut selection = Selection::default();
    if let Some(text) = options.get("--levels") {
        let bad = || format!("check: --levels needs A..=B or N with levels 0..=32, not {text:?}");
        let (low, high) = match text.split_once("..=") {
            Some((low, high)) => (low, high),
            None => (*text, *text),
        };
        let parse = |t: &str| t.trim().parse::<u32>().ok().filter(|level| *level <= 32);
        match (parse(low), parse(high)) {
            (Some(low), Some(high)) if low <= high => selection.levels = Some(low..=high),
            _ => return Err(bad()),
        }
    }
    for (option, target) in [
        ("--tags", &mut selection.tags),
        ("--exclude-tags", &mut selection.exclude_tags),
    ] {
        if let Some(text) = options.get(option) {
            for name in text.split(',').map(str::trim) {
                if !is_known_tag(name) {
                    return Err(format!(
                        "check: {option}: unknown tag {name:?}; tags: {}",
                        tag::ALL.join(", ")
                    ));
                }
                target.push(name.to_owned());
            }
        }
    }
    Ok(selection)
}

/// The file (`-`: stdin) as a buffered reader, or a message naming it.
fn open(path: &str) -> Result<Box<dyn Read>, String> {
    if path == "-" {
        return Ok(Box::new(BufReader::new(io::stdin())));
    }
    match std::fs::File::open(path) {
        Ok(file) => Ok(Box::new(BufReader::new(file))),
        Err(e) => Err(format!("cannot read {path}: {e}")),
    }
}

/// A malformed file: exit 2, nothing checked.
fn cannot_check(message: &str) -> ExitCode {
    report(message);
    Exit::Usage.into()
}

/// A file that cannot be read: exit 3.
fn unreadable(message: &str) -> ExitCode {
    report(message);
    Exit::Io.into()
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

/// The most bytes `--answers` may hold (the 1 GiB the bake inputs allow:
/// answers to every published vector take a few megabytes).
const MAX_ANSWERS_BYTES: u64 = 1 << 30;

/// The answers file's bytes (`-`: stdin), read up to [`MAX_ANSWERS_BYTES`]
/// (an endless pipe stops there): `Err` unreadable (exit 3), `Ok(Err)` over
/// the limit (exit 2, the message names it).
fn read_answers(path: &str) -> Result<Result<Vec<u8>, String>, String> {
    let reader: Box<dyn Read> = if path == "-" {
        Box::new(io::stdin())
    } else {
        Box::new(std::fs::File::open(path).map_err(|e| format!("cannot read {path}: {e}"))?)
    };
    let mut bytes = Vec::new();
    reader
        .take(MAX_ANSWERS_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("reading {}: {e}", shown_path(path)))?;
    if bytes.len() as u64 > MAX_ANSWERS_BYTES {
        return Ok(Err(format!(
            "{}: over the limit of {MAX_ANSWERS_BYTES} bytes for --answers",
            shown_path(path)
        )));
    }
    Ok(Ok(bytes))
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
