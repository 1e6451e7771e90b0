//! `micromap-index`: the command-line front end. Parsing and printing only;
//! the work is in the library. Each command lives in its own module.

mod eval_command;

use std::process::ExitCode;

const USAGE: &str = "\
usage: micromap-index COMMAND [OPTIONS]
commands:
  eval --variant NAME     evaluate JSON lines {\"u\": U, \"v\": V, \"level\": L} from
                          stdin; one line {\"index\": N} or {\"error\": \"...\"} each.
                          U and V: \"0x\" + 8 hex digits (binary32 bits), \"0x\" + 16
                          hex digits (binary64 bits), or an exact decimal or
                          rational (\"0.375\", \"-3/8\").
  help                    this text";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    match args.split_first() {
        Some((&"eval", options)) => eval_command::run(options),
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
