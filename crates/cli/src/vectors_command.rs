//! `micromap-index vectors`: writes the conformance vector files, or prints
//! one of this crate's functions' answers to a vector file (to demonstrate
//! `check`).
//!
//! * `vectors --out DIR` writes `spec-f32.json`, `spec-exact.json` and
//!   `uv2index-exact.json` into `DIR` (created if needed) and prints one line
//!   per file (cases, bytes). Exit 0, or 1 if a file cannot be written.
//! * `vectors --answers-from NAME --vectors FILE` prints answer lines
//!   `{"id":N,"index":I}` (or `{"id":N,"error":"..."}`) for every case of
//!   `FILE`, computed by `NAME`: an `eval` variant, `uv2index-version1-exact`
//!   or `uv2index-version1-f32`. Exit 0, or 2 if `FILE` cannot be read or
//!   parsed.
//!
//! A command line of the wrong shape is a usage error (exit 2).

use crate::usage_error;
use micromap_index_verify::vectors::{compute_answers, generate_sets, AnswerSource};
use std::io::{self, Write};
use std::path::Path;
use std::process::ExitCode;

pub(crate) fn run(options: &[&str]) -> ExitCode {
    let options = match crate::check_command::named_options(
        "vectors",
        options,
        &["--out", "--answers-from", "--vectors"],
    ) {
        Ok(options) => options,
        Err(message) => return usage_error(&message),
    };
    let get = |name: &str| options.get(name).copied();
    match (get("--out"), get("--answers-from"), get("--vectors")) {
        (Some(dir), None, None) => write_sets(Path::new(dir)),
        (None, Some(name), Some(file)) => match AnswerSource::from_name(name) {
            Some(source) => print_answers(source, file),
            None => usage_error(&format!(
                "unknown answer source {name:?}; sources: {}",
                source_names()
            )),
        },
        _ => usage_error("vectors needs --out DIR, or --answers-from NAME --vectors FILE"),
    }
}

fn source_names() -> String {
    AnswerSource::all()
        .into_iter()
        .map(AnswerSource::name)
        .collect::<Vec<_>>()
        .join(", ")
}

fn write_sets(dir: &Path) -> ExitCode {
    if let Err(e) = std::fs::create_dir_all(dir) {
        eprintln!("micromap-index: cannot create {}: {e}", dir.display());
        return ExitCode::FAILURE;
    }
    for set in generate_sets() {
        let path = dir.join(format!("{}.json", set.function));
        let text = set.to_json_text();
        if let Err(e) = std::fs::write(&path, &text) {
            eprintln!("micromap-index: cannot write {}: {e}", path.display());
            return ExitCode::FAILURE;
        }
        println!(
            "{}: {} cases, {} bytes",
            path.display(),
            set.cases.len(),
            text.len()
        );
    }
    ExitCode::SUCCESS
}

fn print_answers(source: AnswerSource, file: &str) -> ExitCode {
    let vectors = match crate::check_command::read_vectors(file) {
        Ok(vectors) => vectors,
        Err(message) => {
            eprintln!("micromap-index: {message}");
            return ExitCode::from(2);
        }
    };
    let text = compute_answers(source, &vectors).to_json_lines();
    let mut out = io::stdout().lock();
    if out
        .write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .is_err()
    {
        return ExitCode::FAILURE;
    }
    ExitCode::SUCCESS
}
