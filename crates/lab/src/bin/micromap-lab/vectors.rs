//! `micromap-lab vectors`: writes the conformance vector files, or prints
//! one of this crate's functions' answers to a vector file (to demonstrate
//! `check`).
//!
//! * `vectors --out DIR [--force]` writes `spec-f32.json`, `spec-exact.json`
//!   and `uv2index-exact.json` into `DIR` (created if needed), all or nothing
//!   (see `write_all_or_nothing`), then prints one line per file
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

use cli_support::args::{Command, Flag};
use cli_support::input::{read_bytes, shown_path};
use cli_support::output::{self, Exit, Program, Stdout};
use cli_support::write_all_or_nothing::{check_destination, write_files};
use micromap_index_lab::vectors::{
    compute_answers, generate_sets, parse_vector_file, AnswerSource, VectorFile,
};
use std::fs::File;
use std::io;
use std::path::Path;

/// The flag table of `vectors`.
pub(crate) static VECTORS: Command = Command {
    name: "vectors",
    forms: &["--out DIR [--force]", "--answers-from NAME --vectors FILE"],
    about: "  --out DIR writes the conformance vector files spec-f32.json,
  spec-exact.json and uv2index-exact.json into DIR (created if needed), all
  or nothing: each goes to a temporary file in DIR, is synced, and the three
  are renamed into place only when all are written. An existing vector file
  is refused (exit 2, nothing written) unless --force is given.
  --answers-from NAME --vectors FILE prints {\"id\": N, \"index\": I} lines for
  FILE's cases computed by NAME (a variant, or uv2index-version1-exact /
  uv2index-version1-f32).",
    flags: &[
        Flag::value("--out", "DIR", "write the vector files into DIR"),
        Flag::switch("--force", "replace existing vector files"),
        Flag::value(
            "--answers-from",
            "NAME",
            "the function whose answers to print",
        ),
        Flag::value(
            "--vectors",
            "FILE",
            "the vector file to answer (- for stdin)",
        ),
    ],
};

pub(crate) fn run(program: &Program, options: &[&str]) -> Exit {
    let options = match VECTORS.parse(options) {
        Ok(options) => options,
        Err(error) => return program.usage_error(&error.message("vectors")),
    };
    let force = options.flag("--force");
    match (
        options.get("--out"),
        options.get("--answers-from"),
        options.get("--vectors"),
    ) {
        (Some(dir), None, None) => write_sets(program, Path::new(dir), force),
        (None, Some(name), Some(file)) if !force => match AnswerSource::from_name(name) {
            Some(source) => print_answers(program, source, file),
            None => program.usage_error(&format!(
                "unknown answer source {name:?}; sources: {}",
                source_names()
            )),
        },
        _ => program.usage_error(
            "vectors needs --out DIR [--force], or --answers-from NAME --vectors FILE",
        ),
    }
}

/// Reads and parses a vector file, or a message naming it.
fn read_vectors(path: &str) -> Result<VectorFile, String> {
    let bytes = read_bytes(path)?;
    parse_vector_file(&bytes).map_err(|e| format!("{}: {e}", shown_path(path)))
}

fn source_names() -> String {
    AnswerSource::all()
        .into_iter()
        .map(AnswerSource::name)
        .collect::<Vec<_>>()
        .join(", ")
}

fn write_sets(program: &Program, dir: &Path, force: bool) -> Exit {
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
        program.report(format_args!("vectors: {message}"));
        return Exit::Usage;
    }
    let contents: Vec<(String, Vec<u8>)> = files
        .iter()
        .map(|(name, bytes, _)| (name.clone(), bytes.clone()))
        .collect();
    if let Err(message) = write_files(dir, &contents) {
        program.report(format_args!("vectors: {message}; nothing written"));
        return Exit::Io;
    }
    // The files are complete before anything is printed: a closed stdout
    // (`| head -1`) can cut the summary short, not the files.
    let mut out = Stdout::line_by_line(program);
    let printed = files.iter().try_for_each(|(name, bytes, cases)| {
        out.line(format_args!(
            "{}: {cases} cases, {} bytes",
            dir.join(name).display(),
            bytes.len()
        ))
    });
    out.finish(output::either(printed.map(|()| Exit::Success)))
}

fn print_answers(program: &Program, source: AnswerSource, file: &str) -> Exit {
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
            program.report(format_args!("cannot read {file}: {e}"));
            return Exit::Io;
        }
    }
    let vectors = match read_vectors(file) {
        Ok(vectors) => vectors,
        Err(message) => {
            program.report(message);
            return Exit::Usage;
        }
    };
    let text = compute_answers(source, &vectors).to_json_lines();
    let mut out = Stdout::buffered(program);
    let written = out.text(&text).map(|()| Exit::Success);
    out.finish(output::either(written))
}
