//! `micromap-index check --vectors FILE --answers FILE [--levels A..=B]
//! [--tags T,..] [--exclude-tags T,..] [--examples K] [--json]`: compares
//! another implementation's answers with a vector file and prints the
//! report (`micromap_index_conformance::vectors::CheckReport`) to stdout.
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

use cli_support::args::{level_range, Command, Flag, Parsed};
use cli_support::input::{open, refuse_blocking, shown_path};
use cli_support::output::{self, print_then, Exit, Failure, Program};
use micromap_index_conformance::vectors::{
    check_reader, is_known_tag, parse_answers, tag, Selection,
};
use std::io::{self, Read};

/// Examples per class when `--examples` is not given.
const DEFAULT_EXAMPLES: usize = 5;

/// The flag table of `check`.
pub(crate) static CHECK: Command = Command {
    name: "check",
    forms: &["--vectors FILE --answers FILE [--levels A..=B]
         [--tags T,..] [--exclude-tags T,..] [--json] [--examples K]"],
    about: "  Compares answer lines {\"id\": N, \"index\": I} (or {\"id\": N,
  \"unsupported\": true}) from FILE, or - for stdin, with the vectors; reports
  by mismatch class (out-of-range answers first), tag and level, then K
  examples per class (default 5). --levels/--tags/--exclude-tags select the
  cases checked (the rest count as skipped); --json prints one JSON object.
  Exit 0 all match, 1 a mismatch or a missing/unknown id, 2 usage error,
  malformed file or a selection with no case.",
    flags: &[
        Flag::value("--vectors", "FILE", "the vector file (- for stdin)"),
        Flag::value("--answers", "FILE", "the answer lines (- for stdin)"),
        Flag::value("--levels", "A..=B", "check only these levels (A..B, N)"),
        Flag::value("--tags", "T,..", "check only cases with one of these tags"),
        Flag::value(
            "--exclude-tags",
            "T,..",
            "skip cases with one of these tags",
        ),
        Flag::switch("--json", "one JSON object instead of the text").repeatable(),
        Flag::value("--examples", "K", "examples shown per class (default 5)"),
    ],
};

pub(crate) fn run(program: &Program, options: &[&str]) -> Exit {
    output::finish(program, check(program, options))
}

fn check(program: &Program, options: &[&str]) -> Result<Exit, Failure> {
    let options = CHECK
        .parse(options)
        .map_err(|e| Failure::Usage(CHECK.error_message(&e)))?;
    let json = options.flag("--json");
    let (Some(vectors_path), Some(answers_path)) =
        (options.get("--vectors"), options.get("--answers"))
    else {
        return Err(Failure::Usage(
            "check needs --vectors FILE and --answers FILE".into(),
        ));
    };
    if vectors_path == "-" && answers_path == "-" {
        return Err(Failure::Usage(
            "check: --vectors and --answers cannot both be stdin".into(),
        ));
    }
    let examples = match options.get("--examples").map(str::parse::<usize>) {
        None => DEFAULT_EXAMPLES,
        Some(Ok(examples)) => examples,
        Some(Err(_)) => {
            return Err(Failure::Usage(
                "check: --examples needs a whole number".into(),
            ))
        }
    };
    let selection = selection(&options).map_err(Failure::Usage)?;
    let answers = read_answers(answers_path)
        .map_err(Failure::Io)?
        .map_err(Failure::Malformed)?;
    let answers = parse_answers(&answers)
        .map_err(|e| Failure::Malformed(format!("{}: {e}", shown_path(answers_path))))?;
    let reader = open(vectors_path).map_err(Failure::Io)?;
    let report = check_reader(reader, &answers, selection)
        .map_err(|e| Failure::Malformed(format!("{}: {e}", shown_path(vectors_path))))?;
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
    Ok(print_then(program, &text, verdict))
}

/// `--levels A..=B` (or `A..B`, `N`), `--tags T,..`, `--exclude-tags T,..`.
fn selection(options: &Parsed<'_>) -> Result<Selection, String> {
    let mut selection = Selection::default();
    if let Some(text) = options.get("--levels") {
        match level_range(text) {
            Ok(levels) if *levels.end() <= 32 => selection.levels = Some(levels),
            _ => {
                return Err(format!(
                    "check: --levels needs A..=B or N with levels 0..=32, not {text:?}"
                ))
            }
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
        refuse_blocking(path.as_ref()).map_err(|e| format!("cannot read {path}: {e}"))?;
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
