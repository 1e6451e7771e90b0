//! `micromap-index eval --variant NAME`: JSON lines in, JSON lines out.

use crate::usage_error;
use micromap_index_verify::eval::{eval_line_bytes, Variant};
use std::io::{self, BufRead, BufWriter, Write};
use std::process::ExitCode;

pub(crate) fn variant_names() -> String {
    Variant::ALL.map(Variant::name).join(", ")
}

pub(crate) fn run(options: &[&str]) -> ExitCode {
    match variant_option(options) {
        Ok(variant) => evaluate_stdin(variant),
        Err(message) => usage_error(&message),
    }
}

/// `--variant NAME` or `--variant=NAME`, and nothing else.
fn variant_option(options: &[&str]) -> Result<Variant, String> {
    let name = match options {
        ["--variant", name] => *name,
        [option] if option.starts_with("--variant=") => &option["--variant=".len()..],
        _ => return Err("eval needs exactly --variant NAME".into()),
    };
    Variant::from_name(name)
        .ok_or_else(|| format!("unknown variant {name:?}; variants: {}", variant_names()))
}

fn evaluate_stdin(variant: Variant) -> ExitCode {
    let stdin = io::stdin().lock();
    let mut out = BufWriter::new(io::stdout().lock());
    for line in stdin.split(b'\n') {
        let line = match line {
            Ok(bytes) => bytes,
            Err(e) => {
                eprintln!("micromap-index: reading stdin: {e}");
                return ExitCode::FAILURE;
            }
        };
        let line = line.strip_suffix(b"\r").unwrap_or(&line);
        if writeln!(out, "{}", eval_line_bytes(variant, line)).is_err() {
            return ExitCode::FAILURE;
        }
    }
    if out.flush().is_err() {
        return ExitCode::FAILURE;
    }
    ExitCode::SUCCESS
}
