//! `micromap-index eval --variant NAME`: JSON lines in, JSON lines out.
//!
//! Every input line gives one output line, in order; a line longer than
//! [`MAX_LINE_BYTES`] gives an error line without being held in memory.
//! Exit 0 at the end of the input (error lines included: they are answers),
//! 2 for a bad command line, 3 if stdin cannot be read or stdout written,
//! 141 if stdout is closed.

use crate::input::{BoundedLines, Line, MAX_LINE_BYTES};
use crate::output::{self, Exit, Stdout};
use crate::usage;
use micromap_index_lab::eval::{eval_line_bytes, Variant};
use std::io;

pub(crate) fn run(options: &[&str]) -> Exit {
    match variant_option(options) {
        Ok(variant) => evaluate_stdin(variant),
        Err(message) => usage(&message),
    }
}

/// `--variant NAME` or `--variant=NAME`, and nothing else.
fn variant_option(options: &[&str]) -> Result<Variant, String> {
    let name = match options {
        ["--variant", name] => *name,
        [option] if option.starts_with("--variant=") => &option["--variant=".len()..],
        _ => return Err("eval needs exactly --variant NAME".into()),
    };
    Variant::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = Variant::ALL.map(Variant::name).to_vec();
        format!(
            "unknown variant {name:?}; variants: {} (and their legacy names)",
            names.join(", ")
        )
    })
}

fn evaluate_stdin(variant: Variant) -> Exit {
    let mut lines = BoundedLines::new(
        io::BufReader::with_capacity(1 << 16, io::stdin().lock()),
        MAX_LINE_BYTES,
    );
    let mut out = Stdout::buffered();
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
                output::report(format_args!("reading stdin: {e}"));
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
