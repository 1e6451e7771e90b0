//! `micromap-index`: evaluate the index functions from the command line.
//! Parsing and printing only; the work is in the library.

use micromap_index::eval::{eval_line_bytes, Variant};
use std::io::{self, BufRead, BufWriter, Write};
use std::process::ExitCode;

const USAGE: &str = "\
usage: micromap-index eval --variant NAME
           reads JSON lines {\"u\": U, \"v\": V, \"level\": L} on stdin and writes
           one line {\"index\": N} or {\"error\": \"...\"} per input line.
           U and V: \"0x\" + 8 hex digits (binary32 bits), \"0x\" + 16 hex digits
           (binary64 bits), or an exact decimal or rational (\"0.375\", \"-3/8\").
       micromap-index help";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    match args.as_slice() {
        ["eval", options @ ..] => match variant_option(options) {
            Ok(variant) => run_eval(variant),
            Err(message) => usage_error(&message),
        },
        ["help"] | ["--help"] | ["-h"] => {
            println!("{USAGE}");
            println!("variants: {}", variant_names());
            ExitCode::SUCCESS
        }
        _ => usage_error("expected a command"),
    }
}

fn variant_names() -> String {
    Variant::ALL.map(Variant::name).join(", ")
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

fn usage_error(message: &str) -> ExitCode {
    eprintln!("micromap-index: {message}\n{USAGE}");
    ExitCode::from(2)
}

fn run_eval(variant: Variant) -> ExitCode {
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
