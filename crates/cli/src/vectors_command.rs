//! `micromap-index vectors`: writes the conformance vector files, or prints
//! one of this crate's functions' answers to a vector file (to demonstrate
//! `check`).
//!
//! * `vectors --out DIR [--force]` writes `spec-f32.json`, `spec-exact.json`
//!   and `uv2index-exact.json` into `DIR` (created if needed), all or nothing
//!   (see [`crate::write_all_or_nothing`]), then prints one line per file
//!   (cases, bytes). Exit 0; 2 if `DIR` is empty or not a directory, or a
//!   vector file is already there (or something else under its name) and
//!   `--force` is not given; 3 if a file cannot be written (nothing is then
//!   left behind).
//! * `vectors --answers-from NAME --vectors FILE` prints answer lines
//!   `{"id":N,"index":I}` (or `{"id":N,"error":"..."}`) for every case of
//!   `FILE`, computed by `NAME`: an `eval` variant, `uv2index-version1-exact`
//!   or `uv2index-version1-f32`. Exit 0; 3 if `FILE` cannot be read; 2 if it
//!   cannot be parsed.
//!
//! A command line of the wrong shape is a usage error (exit 2).

use crate::output::{self, Exit, Stdout};
use crate::usage;
use crate::write_all_or_nothing::{check_destination, write_files};
use micromap_index_lab::vectors::{compute_answers, generate_sets, AnswerSource};
use std::fs::File;
use std::io;
use std::path::Path;

pub(crate) fn run(options: &[&str]) -> Exit {
    // `--force` is the one flag without a value.
    let force = options.contains(&"--force");
    if options.iter().filter(|&&o| o == "--force").count() > 1 {
        return usage("vectors: --force given twice");
    }
    let options: Vec<&str> = options
        .iter()
        .copied()
        .filter(|&o| o != "--force")
        .collect();
    let options = match crate::check_command::named_options(
        "vectors",
        &options,
        &["--out", "--answers-from", "--vectors"],
    ) {
        Ok(options) => options,
        Err(message) => return usage(&message),
    };
    let get = |name: &str| options.get(name).copied();
    match (get("--out"), get("--answers-from"), get("--vectors")) {
        (Some(dir), None, None) => write_sets(Path::new(dir), force),
        (None, Some(name), Some(file)) if !force => match AnswerSource::from_name(name) {
            Some(source) => print_answers(source, file),
            None => usage(&format!(
                "unknown answer source {name:?}; sources: {}",
                source_names()
            )),
        },
        _ => usage("vectors needs --out DIR [--force], or --answers-from NAME --vectors FILE"),
    }
}

fn source_names() -> String {
    AnswerSource::all()
        .into_iter()
        .map(AnswerSource::name)
        .collect::<Vec<_>>()
        .join(", ")
}

fn write_sets(dir: &Path, force: bool) -> Exit {
    let files: Vec<(String, Vec<u8>, usize)> = generate_sets()
        .into_iter()
        .map(|set| {
            (
                format!("{}.json", set.function),
                set.to_json_text().into_bytes(),
                set.cases.len(),
            )
        })
        .collect();
    let names: Vec<&str> = files.iter().map(|(name, _, _)| name.as_str()).collect();
    if let Err(message) = check_destination(dir, &names, force) {
        output::report(format_args!("vectors: {message}"));
        return Exit::Usage;
    }
    let contents: Vec<(String, Vec<u8>)> = files
        .iter()
        .map(|(name, bytes, _)| (name.clone(), bytes.clone()))
        .collect();
    if let Err(message) = write_files(dir, &contents) {
        output::report(format_args!("vectors: {message}; nothing written"));
        return Exit::Io;
    }
    // The files are complete before anything is printed: a closed stdout
    // (`| head -1`) can cut the summary short, not the files.
    let mut out = Stdout::line_by_line();
    let printed = files.iter().try_for_each(|(name, bytes, cases)| {
        out.line(format_args!(
            "{}: {cases} cases, {} bytes",
            dir.join(name).display(),
            bytes.len()
        ))
    });
    out.finish(output::either(printed.map(|()| Exit::Success)))
}

fn print_answers(source: AnswerSource, file: &str) -> Exit {
    // Unreadable (exit 3) is told apart from malformed (exit 2) here.
    if file != "-" {
        let readable = File::open(file).and_then(|f| f.metadata()).and_then(|m| {
            if m.is_dir() {
                Err(io::Error::other("is a directory"))
            } else {
                Ok(())
            }
        });
        if let Err(e) = readable {
            output::report(format_args!("cannot read {file}: {e}"));
            return Exit::Io;
        }
    }
    let vectors = match crate::check_command::read_vectors(file) {
        Ok(vectors) => vectors,
        Err(message) => {
            output::report(message);
            return Exit::Usage;
        }
    };
    let text = compute_answers(source, &vectors).to_json_lines();
    let mut out = Stdout::buffered();
    let written = out.text(&text).map(|()| Exit::Success);
    out.finish(output::either(written))
}
