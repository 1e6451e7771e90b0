//! `micromap-index`: the command-line front end. Parsing and printing only;
//! the work is in the library. Each command lives in its own module.

mod check_command;
mod eval_command;
mod locate_command;
mod prove_command;
mod tree_command;
mod vectors_command;

use std::process::ExitCode;

const USAGE: &str = "\
usage: micromap-index COMMAND [OPTIONS]
commands:
  eval --variant NAME     evaluate JSON lines {\"u\": U, \"v\": V, \"level\": L} from
                          stdin; one line {\"index\": N} or {\"error\": \"...\"} each.
                          U and V: \"0x\" + 8 hex digits (binary32 bits), \"0x\" + 16
                          hex digits (binary64 bits), or an exact decimal or
                          rational (\"0.375\", \"-3/8\").
  locate --level L --index I  print micro-triangle I's exact vertices as one JSON line.
  prove --levels A..=B    compare the walk with the reference on every face of each
                          level's lattice (a proof for all real points); per level
                          faces checked, mismatches, seconds. Exit 0 equal, 1 mismatch,
                          130 interrupted. Options: --spec-wide (64-bit reference,
                          levels to 32), --version1 (the talk's first walk, which
                          fails), --sample N [--seed S] (N random faces, walked step
                          by step), --json, --threads T, --examples K.
  vectors --out DIR       write the conformance vector files (spec-f32, spec-exact,
                          uv2index-exact .json) into DIR.
  vectors --answers-from NAME --vectors FILE  print {\"id\": N, \"index\": I} lines
                          for FILE's cases computed by NAME (a variant, or
                          uv2index-version1-exact / uv2index-version1-f32).
  check --vectors FILE --answers FILE  compare answer lines (FILE or - for stdin)
                          with the vectors; report by class, tag and level. Exit 0 all
                          match, 1 a mismatch or missing/unknown id, 2 usage error or
                          unreadable or malformed file. Options: --levels A..=B,
                          --tags T,.. / --exclude-tags T,.. (select cases), --json,
                          --examples K (per class, default 5).
  tree encode|lookup      the paper's succinct tree: encode a micromap given as
                          states, or look a state up from tree bits and data
                          (micromap-index tree --help).
  help                    this text";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    match args.split_first() {
        Some((&"eval", options)) => eval_command::run(options),
        Some((&"locate", options)) => locate_command::run(options),
        Some((&"prove", options)) => prove_command::run(options),
        Some((&"vectors", options)) => vectors_command::run(options),
        Some((&"check", options)) => check_command::run(options),
        Some((&"tree", options)) => tree_command::run(options),
        Some((&("help" | "--help" | "-h"), [])) => {
            println!("{USAGE}");
            println!("variants: {}", eval_command::variant_names());
            ExitCode::SUCCESS
        }
        _ => usage_error("expected a command"),
    }
}

/// Prints `message` and the usage to stderr; exit code 2.
pub(crate) fn usage_error(message: &str) -> ExitCode {
    eprintln!("micromap-index: {message}\n{USAGE}");
    ExitCode::from(2)
}
