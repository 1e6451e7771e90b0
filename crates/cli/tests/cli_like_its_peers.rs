//! Issue 38: the command behaves like its peers. `--version`/`-V` print the
//! version; a usage error is its message (with the closest flag or command
//! when one is a likely slip) and one line pointing at the usage, never the
//! usage itself; every command's help lists its flags in one column, wrapped
//! lines included; the flags several commands share read the same values.

mod common;

use common::{run, text};

const COMMANDS: [&str; 7] = [
    "eval",
    "locate",
    "check",
    "tree",
    "bake",
    "verify-bake",
    "render",
];

#[test]
fn version_and_short_version() {
    for flag in ["--version", "-V"] {
        let output = run(&[flag]);
        assert_eq!(output.status.code(), Some(0), "{flag}");
        assert_eq!(
            text(&output.stdout),
            format!("micromap-index {}\n", env!("CARGO_PKG_VERSION"))
        );
        assert!(output.stderr.is_empty());
    }
    // As a command's option it is unknown, as any other.
    let output = run(&["--version", "extra"]);
    assert_eq!(output.status.code(), Some(2));
}

/// `(args, the error line, the pointer line)` for usage errors of every
/// kind: an unknown option with and without a close flag, an unknown
/// command, a missing command, a missing value.
#[test]
fn a_usage_error_is_two_lines_with_the_closest_flag() {
    let cases: [(&[&str], &str, &str); 9] = [
        (
            &["bake", "--fromat", "4"],
            "micromap-index: bake: unknown option \"--fromat\" (did you mean --format?)",
            "see `micromap-index bake --help`",
        ),
        (
            &["verify-bake", "--gltf", "a.gltf", "--max-reprot", "3"],
            "micromap-index: verify-bake: unknown option \"--max-reprot\" (did you mean --max-report?)",
            "see `micromap-index verify-bake --help`",
        ),
        (
            &["render", "--out", "x", "--tracr", "query"],
            "micromap-index: render: unknown option \"--tracr\" (did you mean --tracer?)",
            "see `micromap-index render --help`",
        ),
        (
            &["locate", "--levle", "1", "--index", "0"],
            "micromap-index: locate: unknown option \"--levle\" (did you mean --level?)",
            "see `micromap-index locate --help`",
        ),
        (
            &["eval", "--varaint", "spec-f32"],
            "micromap-index: eval: unknown option \"--varaint\" (did you mean --variant?)",
            "see `micromap-index eval --help`",
        ),
        (
            &["bake", "--out", "x", "--zzz"],
            "micromap-index: bake: unknown option \"--zzz\"",
            "see `micromap-index bake --help`",
        ),
        (
            &["bkae"],
            "micromap-index: unknown command \"bkae\" (did you mean bake?)",
            "see `micromap-index help`",
        ),
        (
            &[],
            "micromap-index: expected a command: eval, locate, check, tree, bake, verify-bake, render",
            "see `micromap-index help`",
        ),
        (
            &["check", "--vectors"],
            "micromap-index: check: --vectors needs a value",
            "see `micromap-index check --help`",
        ),
    ];
    for (args, error, pointer) in cases {
        let output = run(args);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        assert!(output.stdout.is_empty(), "{args:?}");
        assert_eq!(
            text(&output.stderr),
            format!("{error}\n{pointer}\n"),
            "{args:?}"
        );
    }
}

/// In every command's help the flags' help starts in one column, and so
/// does every wrapped line of it; no options line is wider than 80
/// characters, save a flag itself too wide for the column (its help then
/// starts on the next line).
#[test]
fn help_is_aligned_in_one_column() {
    for command in COMMANDS {
        let output = run(&["help", command]);
        assert_eq!(output.status.code(), Some(0), "{command}");
        let help = text(&output.stdout);
        let options = help
            .split_once("\noptions:\n")
            .unwrap_or_else(|| panic!("{command}: no options"))
            .1;
        let mut column = None;
        // The options end at the first line not indented (eval's variants).
        for line in options.lines().take_while(|line| line.starts_with(' ')) {
            let flag_line = line.starts_with("  --");
            let starts = if flag_line {
                // The help after the flag and at least two spaces.
                line[2..]
                    .find("  ")
                    .map(|at| 2 + at + line[2 + at..].len() - line[2 + at..].trim_start().len())
            } else {
                Some(line.len() - line.trim_start().len())
            };
            let Some(starts) = starts else {
                // A switch without help, or a flag too wide for the column.
                continue;
            };
            let column = *column.get_or_insert(starts);
            assert_eq!(starts, column, "{command}: {line:?}");
            assert!(line.len() <= 80, "{command}: {line:?}");
        }
    }
}

/// `--index-width` reads 8, 16 and 32 in every command that has it
/// (`render` listed only 16 and 32 while `bake` writes 8 too), and refuses
/// anything else in the same words.
#[test]
fn the_index_width_takes_the_same_values_everywhere() {
    let lines: [&[&str]; 3] = [
        &["bake", "--out", "x", "--texture", "a", "--triangles", "b"],
        &[
            "verify-bake",
            "--texture",
            "a",
            "--triangles",
            "b",
            "--micromaps",
            "c",
        ],
        &["render", "--gltf", "a", "--micromaps", "c", "--out", "x"],
    ];
    for line in lines {
        let command = line[0];
        let help = text(&run(&["help", command]).stdout);
        assert!(
            help.contains("\n  --index-width 8|16|32 "),
            "{command}: {help}"
        );
        let output = run(&[line, &["--index-width", "64"]].concat());
        assert_eq!(output.status.code(), Some(2), "{command}");
        assert_eq!(
            text(&output.stderr),
            "micromap-index: --index-width \"64\": expected 8, 16 or 32 (Vulkan EXT takes 16 \
             and 32; Vulkan KHR, DXR and glTF also 8)\n",
            "{command}"
        );
        // 8 passes the options: the command goes on to read its input.
        let output = run(&[line, &["--index-width", "8"]].concat());
        assert_eq!(output.status.code(), Some(3), "{command}");
        assert!(text(&output.stderr).contains("cannot read"), "{command}");
    }
}
