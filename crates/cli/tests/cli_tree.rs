//! `micromap-index tree encode|lookup`: the built binary's output, exit
//! codes and messages, checked against the library.

use micromap_index::micromap::{Format, State};
use micromap_index::succinct::{LevelOrderTree, PaperTree};
use micromap_index::{spec, Level};
use micromap_index_test_support::SplitMix64;
use std::process::Output;

mod common;

fn tree(args: &[&str], stdin: Option<&str>) -> Output {
    common::run_with_stdin(&[&["tree"], args].concat(), stdin.unwrap_or("").as_bytes())
}

fn stderr(output: &Output) -> String {
    String::from_utf8(output.stderr.clone()).unwrap()
}

/// A successful run's one JSON line.
fn json(args: &[&str], stdin: Option<&str>) -> serde_json::Value {
    let output = tree(args, stdin);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{args:?}: {}",
        stderr(&output)
    );
    let out = String::from_utf8(output.stdout).unwrap();
    assert_eq!(out.matches('\n').count(), 1, "one line: {out:?}");
    serde_json::from_str(&out).unwrap()
}

/// A failing run's exit code and message.
fn failure(args: &[&str]) -> (i32, String) {
    let output = tree(args, None);
    assert!(output.stdout.is_empty(), "{args:?}");
    (output.status.code().unwrap(), stderr(&output))
}

fn chars(states: &[State]) -> String {
    states.iter().map(|s| char::from(b'0' + s.bits())).collect()
}

#[test]
fn encode_prints_the_paper_bits_and_the_sizes() {
    let out = json(
        &[
            "encode", "--format", "2", "--level", "1", "--states", "1101",
        ],
        None,
    );
    assert_eq!(
        out,
        serde_json::json!({
            "level": 1, "format": 2, "tree": "10000", "data": "1101",
            "tree_bits": 5, "data_bits": 4, "flat_bits": 4, "paper_bits": 9,
            "level_order_bits": 5, "level_order_internal_bits": 1,
            "level_order_directory_bits": 0
        })
    );
}

/// A level-5 4-state map through the CLI equals the library's encoding,
/// from `--states`, `--states -` and stdin alike.
#[test]
fn encode_agrees_with_the_library() {
    let mut rng = SplitMix64::new(5);
    let states: Vec<State> = (0..1024)
        .map(|i| {
            if i % 64 < 40 {
                State::Opaque
            } else {
                State::ALL[rng.below(4) as usize]
            }
        })
        .collect();
    let text = chars(&states);
    let level = Level::new(5).unwrap();
    let paper = PaperTree::encode(level, Format::FourState, &states).unwrap();
    let fast = LevelOrderTree::encode(level, Format::FourState, &states).unwrap();
    let by_option = json(
        &["encode", "--format=4", "--level=5", "--states", &text],
        None,
    );
    assert_eq!(by_option["tree"], paper.tree_bit_string());
    assert_eq!(by_option["data"], chars(&paper.leaf_states()));
    assert_eq!(by_option["tree_bits"], paper.tree_bits());
    assert_eq!(by_option["data_bits"], paper.data_bits());
    assert_eq!(by_option["flat_bits"], 2048);
    assert_eq!(by_option["level_order_bits"], fast.total_bits());
    let piped = format!("{text}\n");
    assert_eq!(
        json(
            &["encode", "--format", "4", "--level", "5", "--states", "-"],
            Some(&piped)
        ),
        by_option
    );
    assert_eq!(
        json(&["encode", "--format", "4", "--level", "5"], Some(&piped)),
        by_option
    );
}

/// Lookups by index and by binary32 hit on the tree that encode printed
/// equal the flat map at the spec index.
#[test]
fn lookup_reads_the_encoded_map() {
    let states: Vec<State> = (0..256)
        .map(|i| State::ALL[usize::from(i % 7 == 0 || i > 200)])
        .collect();
    let text = chars(&states);
    let out = json(
        &["encode", "--format", "2", "--level", "4", "--states", &text],
        None,
    );
    let (bits, data) = (out["tree"].as_str().unwrap(), out["data"].as_str().unwrap());
    let base = [
        "lookup", "--format", "2", "--level", "4", "--tree", bits, "--data", data,
    ];
    for index in [0usize, 1, 7, 100, 201, 255] {
        let mut args = base.to_vec();
        let index_text = index.to_string();
        args.extend(["--index", &index_text]);
        assert_eq!(
            json(&args, None),
            serde_json::json!({"state": states[index].bits()}),
            "{index}"
        );
    }
    for (u, v) in [
        ("0.25", "0.5"),
        ("0x3e800000", "0x3f000000"),
        ("3/4", "1/8"),
        ("0", "1"),
    ] {
        let level = Level::new(4).unwrap();
        let value = |t: &str| {
            micromap_index_conformance::value::Value::parse(t)
                .unwrap()
                .to_f32()
                .unwrap()
        };
        let index = spec::index_f32(
            value(u),
            value(v),
            micromap_index::SpecLevel::try_from(level).unwrap(),
        ) as usize;
        let mut args = base.to_vec();
        args.extend(["--u", u, "--v", v]);
        assert_eq!(
            json(&args, None),
            serde_json::json!({"state": states[index].bits()}),
            "{u} {v}"
        );
    }
}

#[test]
fn malformed_input_exits_2_with_a_clear_message() {
    let cases: [(&[&str], &str); 9] = [
        (
            &[
                "encode", "--format", "3", "--level", "1", "--states", "0000",
            ],
            "expected 2 (2-state) or 4",
        ),
        (
            &["encode", "--format", "2", "--level", "1", "--states", "000"],
            "4^1 = 4",
        ),
        (
            &[
                "encode", "--format", "2", "--level", "1", "--states", "0020",
            ],
            "2-state map cannot hold",
        ),
        (
            &[
                "encode", "--format", "4", "--level", "1", "--states", "00a0",
            ],
            "character 2",
        ),
        (
            &[
                "lookup", "--format", "2", "--level", "1", "--tree", "1000", "--data", "1101",
                "--index", "0",
            ],
            "end before the tree is complete",
        ),
        (
            &[
                "lookup", "--format", "2", "--level", "1", "--tree", "10000", "--data", "11",
                "--index", "0",
            ],
            "4 leaves but 2 leaf states",
        ),
        (
            &[
                "lookup", "--format", "2", "--level", "1", "--tree", "10200", "--data", "1101",
                "--index", "0",
            ],
            "expected 0 or 1",
        ),
        (
            &[
                "lookup", "--format", "2", "--level", "1", "--tree", "10000", "--data", "1111",
                "--index", "0",
            ],
            "Algorithm 1 merges",
        ),
        (
            &[
                "lookup", "--format", "2", "--level", "1", "--tree", "10000", "--data", "1101",
                "--u", "0.1", "--v", "0.5",
            ],
            "not exactly representable",
        ),
    ];
    for (args, message) in cases {
        let (code, err) = failure(args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(message), "{args:?}: {err}");
    }
}

#[test]
fn usage_errors_and_out_of_range_values_exit_2() {
    for args in [
        &["encode", "--level", "1", "--states", "0000"][..],
        &["encode", "--format", "2", "--level", "1", "--bogus", "x"],
        &["encode", "--format", "2", "--format", "2", "--level", "1"],
        &[
            "lookup", "--format", "2", "--level", "0", "--tree", "0", "--data", "1",
        ],
        &[
            "lookup", "--format", "2", "--level", "0", "--tree", "0", "--data", "1", "--index",
            "0", "--u", "0",
        ],
        &["frobnicate"],
        &[],
    ] {
        let (code, err) = failure(args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(
            err.ends_with("\nsee `micromap-index tree --help`\n"),
            "{args:?}: {err}"
        );
        assert!(!err.contains("usage:"), "{args:?}: {err}");
    }
    let (code, err) = failure(&[
        "lookup", "--format", "2", "--level", "1", "--tree", "10000", "--data", "1101", "--index",
        "4",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("valid indices are 0..=3"), "{err}");
    let (code, err) = failure(&["encode", "--format", "2", "--level", "17", "--states", "0"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("levels 0..=16"), "{err}");
}

#[test]
fn every_command_has_help() {
    for args in [
        &["tree", "--help"][..],
        &["help", "tree"],
        &["tree", "encode", "--help"],
        &["tree", "lookup", "-h"],
    ] {
        let output = common::run(args);
        assert_eq!(output.status.code(), Some(0), "{args:?}");
        let out = String::from_utf8(output.stdout).unwrap();
        assert!(out.contains("tree lookup --format 2|4"), "{args:?}: {out}");
    }
}

/// A uniform level-16 tree is two characters: lookups need no flat map.
#[test]
fn a_uniform_level_16_tree_answers_at_once() {
    let out = json(
        &[
            "lookup",
            "--format",
            "4",
            "--level",
            "16",
            "--tree",
            "0",
            "--data",
            "3",
            "--index",
            "4294967295",
        ],
        None,
    );
    assert_eq!(out, serde_json::json!({"state": 3}));
}
