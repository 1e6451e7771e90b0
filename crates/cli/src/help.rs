//! The usage texts: one per command (`COMMAND --help`, `help COMMAND`, and
//! after a usage error), and the whole (`help`) with the variant list and the
//! exit-code table.

use crate::output::exit_code_table;
use micromap_index_lab::eval::Variant;
use std::fmt::Write as _;

const HEADER: &str = "\
usage: micromap-index COMMAND [OPTIONS]
       micromap-index COMMAND --help      one command's usage
       micromap-index help [COMMAND]";

const EVAL: &str = "\
usage: micromap-index eval --variant NAME
  Evaluates JSON lines {\"u\": U, \"v\": V, \"level\": L} from stdin; writes one
  line {\"index\": N} or {\"error\": \"...\"} per input line to stdout.
  U and V: \"0x\" + 8 hex digits (binary32 bits), \"0x\" + 16 hex digits
  (binary64 bits), or an exact decimal or rational (\"0.375\", \"-3/8\").
  Limits (each an error line naming the limit): a value of at most 20000
  characters, a decimal of at most 4096 digits with an exponent of at most
  4096 in magnitude, a numerator or denominator of at most 8200 digits, an
  input line of at most 1048576 bytes; L an integer in 0..=32 (0..=16 for
  spec-f32, spec-f32-by-integers, spec-real).";

const LOCATE: &str = "\
usage: micromap-index locate --level L --index I
  Prints micro-triangle I's exact vertices at level L as one JSON line
  {\"level\":L,\"index\":I,\"upright\":B,\"vertices\":[[\"p/q\",\"p/q\"],...]}.
  L in 0..=32, I in 0..4^L; anything else is exit 2.";

const PROVE: &str = "\
usage: micromap-index prove --levels A..=B [OPTIONS]
       micromap-index prove --all-levels [--version1] [--json] [--list]
  Compares the walk with the reference on every face of each level's lattice
  (a proof for all real points); per level: faces checked, mismatches,
  seconds. A..B excludes B; a single level N is N..=N; an empty range is a
  usage error. Exit 0 equal, 1 mismatch, 130 interrupted.
  --spec-wide       the 64-bit reference (levels to 32; default 32-bit, to 16)
  --version1        the talk's first walk (which fails)
  --sample N        N >= 1 random faces per level, walked step by step
  --seed S          the sample's seed (default 1)
  --json            one JSON line per level instead of the table
  --threads T       worker threads (default: all cores)
  --examples K      mismatches shown per level
  --all-levels proves the walk equal to the reference at every level at once
  by exploring the finite product of two digit transducers (milliseconds);
  exit 0 proved, 1 not; with --version1 it must fail and prints a face; --list
  prints every product state and transition (docs/verification.md section 10).";

const VECTORS: &str = "\
usage: micromap-index vectors --out DIR [--force]
       micromap-index vectors --answers-from NAME --vectors FILE
  --out DIR writes the conformance vector files spec-f32.json,
  spec-exact.json and uv2index-exact.json into DIR (created if needed), all
  or nothing: each goes to a temporary file in DIR, is synced, and the three
  are renamed into place only when all are written. An existing vector file
  is refused (exit 2, nothing written) unless --force is given.
  --answers-from NAME --vectors FILE prints {\"id\": N, \"index\": I} lines for
  FILE's cases computed by NAME (a variant, or uv2index-version1-exact /
  uv2index-version1-f32).";

const CHECK: &str = "\
usage: micromap-index check --vectors FILE --answers FILE [--levels A..=B]
         [--tags T,..] [--exclude-tags T,..] [--json] [--examples K]
  Compares answer lines {\"id\": N, \"index\": I} (or {\"id\": N,
  \"unsupported\": true}) from FILE, or - for stdin, with the vectors; reports
  by mismatch class (out-of-range answers first), tag and level, then K
  examples per class (default 5). --levels/--tags/--exclude-tags select the
  cases checked (the rest count as skipped); --json prints one JSON object.
  Exit 0 all match, 1 a mismatch or a missing/unknown id, 2 usage error,
  malformed file or a selection with no case.";

/// The commands and their usage texts, in the order `help` lists them.
pub(crate) const COMMANDS: [(&str, &str); 8] = [
    ("eval", EVAL),
    ("locate", LOCATE),
    ("prove", PROVE),
    ("vectors", VECTORS),
    ("check", CHECK),
    ("tree", crate::tree_command::USAGE),
    ("bake", crate::bake_command::BAKE_USAGE),
    ("verify-bake", crate::bake_command::VERIFY_USAGE),
];

/// The usage text of `command`, if it is one.
#[must_use]
pub(crate) fn usage_of(command: &str) -> Option<&'static str> {
    COMMANDS
        .iter()
        .find(|(name, _)| *name == command)
        .map(|(_, usage)| *usage)
}

/// The variants, one per line, with the legacy names they also accept.
#[must_use]
pub(crate) fn variant_list() -> String {
    let mut text = String::from(
        "variants (eval --variant; the names of earlier releases are accepted as aliases):",
    );
    for variant in Variant::ALL {
        text.push_str("\n  ");
        text.push_str(variant.name());
        if let Some(legacy) = variant.legacy_name() {
            let _ = write!(text, " (alias {legacy})");
        }
    }
    text
}

/// `COMMAND --help` / `help COMMAND`: the command's usage, plus the variant
/// list for `eval`.
#[must_use]
pub(crate) fn command_help(command: &str) -> Option<String> {
    let usage = usage_of(command)?;
    Some(if command == "eval" {
        format!("{usage}\n{}", variant_list())
    } else {
        usage.to_owned()
    })
}

/// `help`: everything.
#[must_use]
pub(crate) fn full_help() -> String {
    let mut text = String::from(HEADER);
    for (_, usage) in COMMANDS {
        text.push_str("\n\n");
        text.push_str(usage);
    }
    text.push_str("\n\n");
    text.push_str(&variant_list());
    text.push_str("\n\n");
    text.push_str(&exit_code_table());
    text
}
