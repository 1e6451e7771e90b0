//! `micromap-index locate --level L --index I`: one micro-triangle's exact
//! vertices as a JSON line.
//!
//! Output: `{"level":L,"index":I,"upright":B,"vertices":[["p/q","p/q"],...]}`
//! with the vertices as `(u, v)` pairs in the walk's local order (see
//! `micromap_index::inverse`). Every coordinate is a reduced fraction written
//! `"p/q"` even when it is an integer (`"0/1"`, `"1/1"`); `q` is a power of
//! two. A command line of the wrong shape, or a level or index that is not a
//! number or out of range, is exit 2 (usage error or malformed input; the
//! message says what is wrong); exit 3 or 141 if stdout cannot be written.

use cli_support::args::{whole_number, Command, Flag};
use cli_support::output::{self, Exit, Failure, Program, Stdout};
use micromap_index::inverse::{micro_triangle, MicroTriangle};
use micromap_index::Level;
use num_rational::BigRational;
use serde::Serialize;

/// The flag table of `locate`.
pub(crate) static LOCATE: Command = Command {
    name: "locate",
    forms: &["--level L --index I"],
    about: "  Prints micro-triangle I's exact vertices at level L as one JSON line
  {\"level\":L,\"index\":I,\"upright\":B,\"vertices\":[[\"p/q\",\"p/q\"],...]}.
  L in 0..=32, I in 0..4^L; anything else is exit 2.",
    flags: &[
        Flag::value("--level", "L", "the subdivision level, 0..=32"),
        Flag::value("--index", "I", "the micro-triangle's index, 0..4^L"),
    ],
};

pub(crate) fn run(program: &Program, options: &[&str]) -> Exit {
    let parsed = match LOCATE.parse(options) {
        Ok(parsed) => parsed,
        Err(error) => return Failure::Usage(LOCATE.error_message(&error)).exit(program),
    };
    let (Some(level), Some(index)) = (parsed.get("--level"), parsed.get("--index")) else {
        return Failure::Usage("locate needs --level L and --index I".into()).exit(program);
    };
    match locate(level, index) {
        Ok(triangle) => print_line(program, &triangle),
        Err(message) => Failure::Malformed(message).exit(program),
    }
}

/// Parses and checks the values; the message says what is wrong.
fn locate(level_text: &str, index_text: &str) -> Result<MicroTriangle, String> {
    let too_high = || {
        format!(
            "level {level_text} is too high: levels are 0..={}",
            Level::MAX
        )
    };
    let level = number("--level", level_text)?
        .and_then(|level| u32::try_from(level).ok())
        .ok_or_else(too_high)?;
    let level = Level::new(level).map_err(|_| too_high())?;
    match number("--index", index_text)? {
        Some(index) => micro_triangle(level, index).map_err(|error| error.to_string()),
        // Above u64::MAX, so at least 4^32: out of range at every level.
        None => Err(format!(
            "index {index_text} is out of range for level {level}: valid indices are 0..={}",
            level.micro_triangle_count() - 1
        )),
    }
}

/// `Some(n)` for a whole number that fits a `u64`, `None` for a larger one.
fn number(option: &str, text: &str) -> Result<Option<u64>, String> {
    whole_number(text).map_err(|()| format!("{option} {text:?} is not a whole number"))
}

/// The JSON line, fields in this order.
#[derive(Serialize)]
struct LocateLine {
    level: u32,
    index: u64,
    upright: bool,
    vertices: [[String; 2]; 3],
}

/// `"p/q"`: `BigRational` is always reduced, with zero as `0/1`.
fn fraction(value: &BigRational) -> String {
    format!("{}/{}", value.numer(), value.denom())
}

fn print_line(program: &Program, triangle: &MicroTriangle) -> Exit {
    let line = LocateLine {
        level: triangle.level().get(),
        index: triangle.index(),
        upright: triangle.upright(),
        vertices: triangle
            .vertices_rational()
            .map(|(u, v)| [fraction(&u), fraction(&v)]),
    };
    let mut out = Stdout::buffered(program);
    let written = match serde_json::to_string(&line) {
        Ok(json) => out.line(json).map(|()| Exit::Success),
        Err(e) => {
            program.report(format_args!("cannot write JSON: {e}"));
            Err(Exit::Io)
        }
    };
    out.finish(output::either(written))
}
