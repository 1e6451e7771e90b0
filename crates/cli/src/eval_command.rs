//! `micromap-index eval --variant NAME`: JSON lines in, JSON lines out.
//!
//! Every input line gives one output line, in order; a line longer than
//! [`MAX_LINE_BYTES`] gives an error line without being held in memory.
//! Exit 0 at the end of the input (error lines included: they are answers),
//! 2 for a bad command line, 3 if stdin cannot be read or stdout written,
//! 141 if stdout is closed.

use cli_support::args::{ArgError, Command, Flag};
use cli_support::input::{BoundedLines, Line, MAX_LINE_BYTES};
use cli_support::output::{self, Exit, Failure, Program, Stdout};
use micromap_index_conformance::eval::{eval_line_bytes, Variant};
use std::io;

/// The flag table of `eval`.
pub(crate) static EVAL: Command = Command {
    name: "eval",
    forms: &["--variant NAME"],
    about: "  Evaluates JSON lines {\"u\": U, \"v\": V, \"level\": L} from stdin; writes one
  line {\"index\": N} or {\"error\": \"...\"} per input line to stdout.
  U and V: \"0x\" + 8 hex digits (binary32 bits), \"0x\" + 16 hex digits
  (binary64 bits), or an exact decimal or rational (\"0.375\", \"-3/8\").
  Limits (each an error line naming the limit): a value of at most 20000
  characters, a decimal of at most 4096 digits with an exponent of at most
  4096 in magnitude, a numerator or denominator of at most 8200 digits, an
  input line of at most 1048576 bytes; L an integer in 0..=32 (0..=16 for
  spec-f32, spec-f32-by-integers, spec-real).",
    flags: &[Flag::value(
        "--variant",
        "NAME",
        "the library function to evaluate (the list below)",
    )],
};

pub(crate) fn run(program: &Program, options: &[&str]) -> Exit {
    match variant_option(options) {
        Ok(variant) => evaluate_stdin(program, variant),
        Err(failure) => failure.exit(program),
    }
}

/// `--variant NAME` or `--variant=NAME`, and nothing else.
fn variant_option(options: &[&str]) -> Result<Variant, Failure> {
    let parsed = EVAL.parse(options).map_err(|error| match error {
        ArgError::Unknown(_) => Failure::Usage(EVAL.error_message(&error)),
        _ => Failure::Usage("eval needs exactly --variant NAME".into()),
    })?;
    let name = parsed
        .get("--variant")
        .ok_or_else(|| Failure::Usage("eval needs exactly --variant NAME".into()))?;
    Variant::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = Variant::ALL.map(Variant::name).to_vec();
        Failure::Usage(format!(
            "unknown variant {name:?}; variants: {} (and their legacy names)",
            names.join(", ")
        ))
    })
}

fn evaluate_stdin(program: &Program, variant: Variant) -> Exit {
    let mut lines = BoundedLines::new(
        io::BufReader::with_capacity(1 << 16, io::stdin().lock()),
        MAX_LINE_BYTES,
    );
    let mut out = Stdout::buffered(program);
    let result = (|| loop {
        // Before waiting for more input, pass on the answers so far: a
        // program feeding eval line by line gets each answer back.
        if lines.reader().buffer().is_empty() {
            out.flush()?;
        }
        let line = match lines.next_line() {
            Ok(Some(line)) => line,
            Ok(None) => return Ok(Exit::Success),
            Err(e) => {
                program.report(format_args!("reading stdin: {e}"));
                return Err(Exit::Io);
            }
        };
        let answer = match line {
            Line::Text(bytes) => {
                let bytes = bytes.strip_suffix(b"\r").unwrap_or(bytes);
                eval_line_bytes(variant, bytes)
            }
            Line::TooLong { bytes } => format!(
                "{{\"error\":\"malformed input line: {bytes} bytes, over the limit of {MAX_LINE_BYTES} bytes per line; skipped\"}}"
            ),
        };
        out.line(answer)?;
    })();
    out.finish(output::either(result))
}
