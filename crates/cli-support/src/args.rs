//! The flag tables: each command's flags defined once ([`Flag`]), in one
//! table per command ([`Command`]) from which both the parser
//! ([`Command::parse`]) and the usage text ([`usage_text`]) are derived, as
//! ripgrep's `flags/defs.rs` does; and the level syntax every command shares
//! ([`level_range`], [`whole_number`]).
//!
//! The rules of a command line, the same for every table:
//!
//! * a switch (a flag without a value) is the exact word `--name`; it is
//!   never taken as another flag's value (`--out --force` is `--out` without
//!   its value), and `--name=VALUE` is refused;
//! * a valued flag is `--name VALUE` or `--name=VALUE`; the value may start
//!   with `-` (`--u -0.5`);
//! * a flag is given at most once unless its table entry is
//!   [`Flag::repeatable`] (the last value counts);
//! * anything else is an unknown option.
//!
//! Every error message names the command: `locate: unknown option "-x"`,
//! `check: --vectors needs a value`, `vectors: --force given twice`
//! ([`ArgError::message`]).
//!
//! Both binaries (`micromap-index`, `micromap-lab`) use these, so they share
//! one parser and one usage layout.
//!
//! Every command of both binaries has its table; `tests/cli_docs.rs` and
//! `crates/lab/tests/lab_docs.rs` check that `docs/cli.md` shows each
//! rendered usage verbatim.

use std::fmt::Write as _;
use std::ops::RangeInclusive;

/// One flag of a command's table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[must_use]
pub struct Flag {
    /// `--name`.
    pub name: &'static str,
    /// The value's placeholder in the usage (`L`, `FILE`); `None` for a
    /// switch.
    pub value: Option<&'static str>,
    /// What a missing value is called in `needs ...` (`a value` unless the
    /// command says better: `A..=B`, `a number of faces`).
    pub wants: &'static str,
    /// One line of help, shown after the flag in the usage.
    pub help: &'static str,
    /// Whether the flag may be given again (the last value counts), rather
    /// than being `given twice`.
    pub repeatable: bool,
}

impl Flag {
    /// `--name VALUE`.
    pub const fn value(name: &'static str, value: &'static str, help: &'static str) -> Flag {
        Flag {
            name,
            value: Some(value),
            wants: "a value",
            help,
            repeatable: false,
        }
    }

    /// A switch `--name`.
    pub const fn switch(name: &'static str, help: &'static str) -> Flag {
        Flag {
            name,
            value: None,
            wants: "a value",
            help,
            repeatable: false,
        }
    }

    /// The same flag, its missing value called `wants` (`needs A..=B`).
    pub const fn wants(self, wants: &'static str) -> Flag {
        Flag { wants, ..self }
    }

    /// The same flag, which may be repeated (the last value counts).
    pub const fn repeatable(self) -> Flag {
        Flag {
            repeatable: true,
            ..self
        }
    }

    /// `--name VALUE` or `--name`, as the usage lists it.
    fn shown(&self) -> String {
        match self.value {
            Some(value) => format!("{} {value}", self.name),
            None => self.name.to_owned(),
        }
    }
}

/// One command's table: its name, its synopsis, its prose and its flags.
#[derive(Debug)]
pub struct Command {
    /// The command's words after the program name (`locate`, `tree encode`).
    pub name: &'static str,
    /// The synopsis forms after `PROGRAM NAME ` (one line each; a form may
    /// continue on indented lines).
    pub forms: &'static [&'static str],
    /// The description, each line indented by two spaces (may be empty).
    pub about: &'static str,
    /// The flags.
    pub flags: &'static [Flag],
}

/// How many flags `groups` hold together: the length of their [`concat()`].
#[must_use]
pub const fn total(groups: &[&[Flag]]) -> usize {
    let (mut total, mut g) = (0, 0);
    while g < groups.len() {
        total += groups[g].len();
        g += 1;
    }
    total
}

/// The flags of `groups`, in order, as one table: a command's table made of
/// groups of flags it shares with other commands (each flag still defined
/// once): `flags: &concat::<{ total(GROUPS) }>(GROUPS)`. `N` must be
/// [`total`]`(groups)` (checked when the table is evaluated, at compile
/// time for a `static`).
///
/// # Panics
///
/// If `N` is not the groups' total (at compile time in a `static`).
pub const fn concat<const N: usize>(groups: &[&[Flag]]) -> [Flag; N] {
    assert!(total(groups) == N, "N is the groups' total");
    let mut table = [Flag::switch("", ""); N];
    let (mut n, mut g) = (0, 0);
    while g < groups.len() {
        let mut i = 0;
        while i < groups[g].len() {
            table[n] = groups[g][i];
            n += 1;
            i += 1;
        }
        g += 1;
    }
    table
}

/// Why a command line does not fit its table.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ArgError<'a> {
    /// A word that is no flag of the table (the word as given).
    Unknown(&'a str),
    /// A valued flag at the end of the line.
    NeedsValue(&'static Flag),
    /// A flag given twice.
    Twice(&'static str),
    /// A switch given as `--name=VALUE` (the word as given).
    TakesNoValue(&'static str, &'a str),
}

impl ArgError<'_> {
    /// The message, prefixed with the command's name: `locate: unknown
    /// option "-x"`.
    #[must_use]
    pub fn message(&self, command: &str) -> String {
        format!("{command}: {}", self.describe())
    }

    /// The message without the command's name: `unknown option "-x"`,
    /// `--level needs a value`, `--force given twice`.
    #[must_use]
    pub fn describe(&self) -> String {
        match self {
            ArgError::Unknown(word) | ArgError::TakesNoValue(_, word) => {
                format!("unknown option {word:?}")
            }
            ArgError::NeedsValue(flag) => format!("{} needs {}", flag.name, flag.wants),
            ArgError::Twice(name) => format!("{name} given twice"),
        }
    }
}

/// The name of `names` closest to `word` by edit distance (insertions,
/// deletions, substitutions and swaps of two neighbours, each 1), if one is
/// close enough to be a slip: at most 2 edits and at most a quarter of the
/// name's length (`--fromat` -> `--format`, `format` -> `--format`;
/// `-x` -> nothing). The first of equally close names.
#[must_use]
pub fn closest<'n>(word: &str, names: impl IntoIterator<Item = &'n str>) -> Option<&'n str> {
    names
        .into_iter()
        .map(|name| (edit_distance(word, name), name))
        .filter(|&(distance, name)| distance <= 2 && distance * 4 <= name.chars().count())
        .min_by_key(|&(distance, _)| distance)
        .map(|(_, name)| name)
}

/// The optimal string alignment distance of `a` and `b` (Damerau's edits,
/// no substring edited twice), in characters.
fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    // Rows i - 2, i - 1 and i of the table.
    let mut before: Vec<usize> = Vec::new();
    let mut above: Vec<usize> = (0..=b.len()).collect();
    for i in 1..=a.len() {
        let mut row = vec![i; b.len() + 1];
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            row[j] = (above[j] + 1).min(row[j - 1] + 1).min(above[j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                row[j] = row[j].min(before[j - 2] + 1);
            }
        }
        before = std::mem::replace(&mut above, row);
    }
    above[b.len()]
}

/// The flags found on a command line.
#[derive(Debug, Default)]
pub struct Parsed<'a> {
    values: Vec<(&'static str, &'a str)>,
    switches: Vec<&'static str>,
}

impl<'a> Parsed<'a> {
    /// The value of `name`, if given (the last one for a repeatable flag).
    #[must_use]
    pub fn get(&self, name: &str) -> Option<&'a str> {
        self.values
            .iter()
            .rev()
            .find(|&&(n, _)| n == name)
            .map(|&(_, v)| v)
    }

    /// Whether the switch `name` was given.
    #[must_use]
    pub fn flag(&self, name: &str) -> bool {
        self.switches.contains(&name)
    }
}

impl Command {
    /// `error`'s message, prefixed with the command's name
    /// ([`ArgError::message`]); for an unknown option, the table's closest
    /// flag too ([`closest`]): `bake: unknown option "--fromat" (did you
    /// mean --format?)`.
    #[must_use]
    pub fn error_message(&self, error: &ArgError<'_>) -> String {
        let mut message = error.message(self.name);
        if let ArgError::Unknown(word) = error {
            let name = word.split_once('=').map_or(*word, |(name, _)| name);
            if let Some(flag) = closest(name, self.flags.iter().map(|flag| flag.name)) {
                let _ = write!(message, " (did you mean {flag}?)");
            }
        }
        message
    }

    /// The table's flag called `name`.
    fn find(&'static self, name: &str) -> Option<&'static Flag> {
        self.flags.iter().find(|flag| flag.name == name)
    }

    /// Parses `given` by the table (the rules in the module docs).
    pub fn parse<'a>(&'static self, given: &[&'a str]) -> Result<Parsed<'a>, ArgError<'a>> {
        let mut parsed = Parsed::default();
        // Switches first: a switch is never another flag's value.
        let mut rest = Vec::with_capacity(given.len());
        for &word in given {
            match self.find(word) {
                Some(flag) if flag.value.is_none() => {
                    if parsed.switches.contains(&flag.name) && !flag.repeatable {
                        return Err(ArgError::Twice(flag.name));
                    }
                    parsed.switches.push(flag.name);
                }
                _ => rest.push(word),
            }
        }
        let mut rest = rest.into_iter();
        while let Some(word) = rest.next() {
            let (name, inline_value) = match word.split_once('=') {
                Some((name, value)) => (name, Some(value)),
                None => (word, None),
            };
            let Some(flag) = self.find(name) else {
                return Err(ArgError::Unknown(word));
            };
            if flag.value.is_none() {
                return Err(ArgError::TakesNoValue(flag.name, word));
            }
            let Some(value) = inline_value.or_else(|| rest.next()) else {
                return Err(ArgError::NeedsValue(flag));
            };
            if parsed.values.iter().any(|&(n, _)| n == flag.name) && !flag.repeatable {
                return Err(ArgError::Twice(flag.name));
            }
            parsed.values.push((flag.name, value));
        }
        Ok(parsed)
    }
}

/// The usage text of `commands` (one command, or the subcommands of one
/// word: `tree encode` and `tree lookup`) run as `program`: every synopsis
/// form, then `about`, then `options:` and every flag once with its help, in
/// table order.
#[must_use]
pub fn usage_text(program: &str, commands: &[&Command], about: &str) -> String {
    let mut text = String::new();
    let mut first = true;
    for command in commands {
        for form in command.forms {
            let lead = if first { "usage:" } else { "      " };
            first = false;
            let _ = writeln!(text, "{lead} {program} {} {form}", command.name);
        }
    }
    for part in std::iter::once(about).chain(commands.iter().map(|c| c.about)) {
        if !part.is_empty() {
            let _ = writeln!(text, "{part}");
        }
    }
    let mut listed: Vec<&Flag> = Vec::new();
    for flag in commands.iter().flat_map(|c| c.flags) {
        if !listed.iter().any(|shown| shown.name == flag.name) {
            listed.push(flag);
        }
    }
    let widest = listed
        .iter()
        .map(|flag| flag.shown().len())
        .max()
        .unwrap_or(0);
    let column = 2 + widest.clamp(16, MAX_FLAG_WIDTH) + 2;
    if !listed.is_empty() {
        text.push_str("options:\n");
    }
    for flag in listed {
        push_flag(&mut text, &flag.shown(), flag.help, column);
    }
    text.pop();
    text
}

/// The widest flag (`--name VALUE`) whose help starts on its own line; a
/// wider one has its help on the next line, in the same column.
const MAX_FLAG_WIDTH: usize = 22;

/// The width the usage's flag help is wrapped to.
const USAGE_WIDTH: usize = 80;

/// `  SHOWN  HELP` and a newline: the help's words (the table's line breaks
/// and indentation are not kept) wrapped at [`USAGE_WIDTH`], every line of
/// it starting at `column` (the first on the next line when `shown` does
/// not leave room).
fn push_flag(text: &mut String, shown: &str, help: &str, column: usize) {
    let indent = " ".repeat(column);
    let mut line = format!("  {shown}");
    if line.len() + 2 > column {
        // Too wide for the column: the help starts on the next line.
        text.push_str(&line);
        text.push('\n');
        line.clone_from(&indent);
    } else {
        line = format!("{line:<column$}");
    }
    let mut empty = true;
    for word in help.split_whitespace() {
        if !empty && line.len() + 1 + word.len() > USAGE_WIDTH {
            text.push_str(&line);
            text.push('\n');
            line.clone_from(&indent);
            empty = true;
        }
        if !empty {
            line.push(' ');
        }
        line.push_str(word);
        empty = false;
    }
    text.push_str(line.trim_end());
    text.push('\n');
}

/// Why a level range does not parse.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RangeError<'a> {
    /// A part that is not a level (as written).
    BadLevel(&'a str),
    /// The range holds no level (`3..3`, `4..=3`, `0..0`).
    Empty,
}

/// A level range, the one syntax of every `--levels`: `A..=B`, `A..B` (`B`
/// excluded) or a single level `N`, each level a whole number (spaces
/// around it allowed). Not empty; the caller checks the highest level.
pub fn level_range(text: &str) -> Result<RangeInclusive<u32>, RangeError<'_>> {
    fn level(s: &str) -> Result<u32, RangeError<'_>> {
        s.trim().parse::<u32>().map_err(|_| RangeError::BadLevel(s))
    }
    let range = if let Some((a, b)) = text.split_once("..=") {
        level(a)?..=level(b)?
    } else if let Some((a, b)) = text.split_once("..") {
        let end = level(b)?.checked_sub(1).ok_or(RangeError::Empty)?;
        level(a)?..=end
    } else {
        let n = level(text)?;
        n..=n
    };
    if range.is_empty() {
        return Err(RangeError::Empty);
    }
    Ok(range)
}

/// A whole number (as `u64` parses it: digits, an optional `+`):
/// `Ok(Some(n))`, `Ok(None)` when it is above `u64::MAX` (so above every
/// level and index), `Err(())` when it is no whole number.
// The callers word the error themselves (it names their flag).
#[allow(clippy::result_unit_err)]
pub fn whole_number(text: &str) -> Result<Option<u64>, ()> {
    match text.parse::<u64>() {
        Ok(number) => Ok(Some(number)),
        Err(e) if *e.kind() == std::num::IntErrorKind::PosOverflow => Ok(None),
        Err(_) => Err(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    static DEMO: Command = Command {
        name: "demo",
        forms: &["--level L [--json]"],
        about: "  A demonstration.",
        flags: &[
            Flag::value("--level", "L", "the level"),
            Flag::switch("--json", "JSON"),
            Flag::value("--seed", "S", "a seed").repeatable(),
        ],
    };

    #[test]
    fn parses_by_the_table() {
        let p = DEMO
            .parse(&["--json", "--level=3", "--seed", "1", "--seed", "2"])
            .unwrap();
        assert_eq!(
            (p.get("--level"), p.get("--seed"), p.flag("--json")),
            (Some("3"), Some("2"), true)
        );
        // A switch is never a value.
        assert_eq!(
            DEMO.parse(&["--level", "--json"])
                .unwrap_err()
                .message("demo"),
            "demo: --level needs a value"
        );
        assert_eq!(
            DEMO.parse(&["--json", "--json"]).unwrap_err(),
            ArgError::Twice("--json")
        );
        assert_eq!(
            DEMO.parse(&["--level", "1", "--level=2"]).unwrap_err(),
            ArgError::Twice("--level")
        );
        assert_eq!(
            DEMO.parse(&["-x"]).unwrap_err().message("demo"),
            "demo: unknown option \"-x\""
        );
        assert_eq!(
            DEMO.parse(&["--json=1"]).unwrap_err().message("demo"),
            "demo: unknown option \"--json=1\""
        );
        assert_eq!(
            DEMO.parse(&["--level", "-1"]).unwrap().get("--level"),
            Some("-1")
        );
    }

    #[test]
    fn concatenates_groups_in_order() {
        const SHARED: [Flag; 2] = [Flag::switch("--a", "a"), Flag::switch("--b", "b")];
        const LEVEL: Flag = Flag::value("--level", "L", "the level");
        const GROUPS: &[&[Flag]] = &[&[Flag::switch("--x", "x")], &SHARED, &[], &[LEVEL]];
        let table: [Flag; total(GROUPS)] = concat(GROUPS);
        let names: Vec<&str> = table.iter().map(|flag| flag.name).collect();
        assert_eq!(names, ["--x", "--a", "--b", "--level"]);
        assert_eq!(table[3], LEVEL);
    }

    #[test]
    fn renders_the_usage_from_the_table() {
        assert_eq!(
            usage_text("prog", &[&DEMO], ""),
            "usage: prog demo --level L [--json]\n  A demonstration.\noptions:\n  --level L         the level\n  --json            JSON\n  --seed S          a seed"
        );
    }

    /// Help text is re-wrapped into the flags' column (the table's own line
    /// breaks and indentation dropped); a flag wider than the column has
    /// its help on the next line, in the same column.
    #[test]
    fn help_wraps_into_one_column() {
        static WIDE: Command = Command {
            name: "wide",
            forms: &["[options]"],
            about: "",
            flags: &[
                Flag::value(
                    "--mode",
                    "M",
                    "one two three four five six seven eight nine ten eleven twelve
                         thirteen fourteen fifteen",
                ),
                Flag::value("--camera", "EX,EY,EZ,TX,TY,TZ[,FOV]", "eye and target"),
                Flag::switch("--quiet", ""),
            ],
        };
        let usage = usage_text("prog", &[&WIDE], "");
        assert_eq!(
            usage,
            "usage: prog wide [options]
options:
  --mode M                one two three four five six seven eight nine ten
                          eleven twelve thirteen fourteen fifteen
  --camera EX,EY,EZ,TX,TY,TZ[,FOV]
                          eye and target
  --quiet"
        );
        for line in usage.lines() {
            assert!(line.len() <= USAGE_WIDTH, "{line}");
        }
    }

    #[test]
    fn an_unknown_option_names_the_closest_flag() {
        static FORMAT: Command = Command {
            name: "bake",
            forms: &[""],
            about: "",
            flags: &[
                Flag::value("--format", "2|4", "format"),
                Flag::value("--out", "DIR", "out"),
                Flag::switch("--force", "force"),
            ],
        };
        let message = |args: &[&str]| FORMAT.error_message(&FORMAT.parse(args).unwrap_err());
        assert_eq!(
            message(&["--fromat", "4"]),
            "bake: unknown option \"--fromat\" (did you mean --format?)"
        );
        assert_eq!(
            message(&["--fromat=4"]),
            "bake: unknown option \"--fromat=4\" (did you mean --format?)"
        );
        assert_eq!(
            message(&["format"]),
            "bake: unknown option \"format\" (did you mean --format?)"
        );
        assert_eq!(
            message(&["--ot"]),
            "bake: unknown option \"--ot\" (did you mean --out?)"
        );
        // Nothing close: no guess.
        assert_eq!(message(&["-x"]), "bake: unknown option \"-x\"");
        assert_eq!(message(&["--level"]), "bake: unknown option \"--level\"");
        // Other errors are as they were.
        assert_eq!(message(&["--out"]), "bake: --out needs a value");
        assert_eq!(
            closest("--forcee", ["--format", "--force"]),
            Some("--force")
        );
        assert_eq!(edit_distance("abcd", "acbd"), 1);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }

    #[test]
    fn one_level_syntax() {
        assert_eq!(level_range("2..=4"), Ok(2..=4));
        assert_eq!(level_range("2..4"), Ok(2..=3));
        assert_eq!(level_range("7"), Ok(7..=7));
        assert_eq!(level_range("3..3"), Err(RangeError::Empty));
        assert_eq!(level_range("0..0"), Err(RangeError::Empty));
        assert_eq!(level_range("4..=3"), Err(RangeError::Empty));
        assert_eq!(level_range("x..=3"), Err(RangeError::BadLevel("x")));
        assert_eq!(whole_number("18446744073709551616"), Ok(None));
        assert_eq!(whole_number("+3"), Ok(Some(3)));
        assert_eq!(whole_number("3.0"), Err(()));
    }
}
