//! Input checks of `eval` on the built binary: the line cap, the size
//! limits and level messages. (`prove`'s checks of nothing are in
//! `crates/lab/tests/lab_output.rs`.)

mod common;

use common::run_with_stdin as run;

fn eval(variant: &str, stdin: &[u8]) -> Vec<String> {
    let output = run(&["eval", "--variant", variant], stdin);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8(output.stdout)
        .unwrap()
        .lines()
        .map(str::to_owned)
        .collect()
}

/// Issue 9: a 200 MB line was held in memory whole. Now a line over
/// 1 MiB is one error line; the lines around it are answered.
#[test]
fn an_over_long_line_is_an_error_line() {
    let good = b"{\"u\": \"0.28\", \"v\": \"0.4\", \"level\": 3}\n";
    let mut input = good.to_vec();
    let padded_at_limit = {
        let mut line = b"{\"u\": \"0.28\", \"v\": \"0.4\", \"level\": 3".to_vec();
        line.resize((1 << 20) - 1, b' ');
        line.push(b'}');
        line
    };
    assert_eq!(padded_at_limit.len(), 1 << 20);
    input.extend_from_slice(&padded_at_limit);
    input.push(b'\n');
    input.extend(vec![b' '; (1 << 20) + 1]);
    input.push(b'\n');
    input.extend(vec![b'x'; 5 << 20]);
    input.push(b'\n');
    input.extend_from_slice(good);
    let lines = eval("spec-real", &input);
    assert_eq!(
        lines,
        [
            "{\"index\":23}",
            "{\"index\":23}",
            "{\"error\":\"malformed input line: 1048577 bytes, over the limit of 1048576 bytes per line; skipped\"}",
            "{\"error\":\"malformed input line: 5242880 bytes, over the limit of 1048576 bytes per line; skipped\"}",
            "{\"index\":23}",
        ]
    );
}

/// Issue 9: "1e999999999" said "expected a decimal"; a 10,000-digit
/// denominator did not name the limit; levels out of range said "invalid
/// type: floating point" or named the wrong range.
#[test]
fn limits_and_levels_are_named() {
    let line =
        |u: &str, level: &str| format!("{{\"u\": \"{u}\", \"v\": \"0\", \"level\": {level}}}\n");
    let denominator = "9".repeat(10_000);
    let input = [
        line("1e999999999", "1"),
        line(&format!("1/{denominator}"), "1"),
        line("0", "33"),
        line("0", "18446744073709551616"),
        line("0", "-1"),
        line("0", "1.5"),
    ]
    .concat();
    let lines = eval("spec-f32", input.as_bytes());
    let expected_starts = [
        "{\"error\":\"exponent 999999999 is over the limit of 4096 in magnitude",
        "{\"error\":\"denominator of 10000 digits is over the limit of 8200 digits",
        "{\"error\":\"level 33 is too high: spec-f32 supports levels 0..=16\"}",
        "{\"error\":\"level 18446744073709551616 is not an integer in 0..=16, the levels spec-f32 supports\"}",
        "{\"error\":\"level -1 is not an integer in 0..=16, the levels spec-f32 supports\"}",
        "{\"error\":\"level 1.5 is not an integer in 0..=16, the levels spec-f32 supports\"}",
    ];
    assert_eq!(lines.len(), expected_starts.len(), "{lines:?}");
    for (line, start) in lines.iter().zip(expected_starts) {
        assert!(line.starts_with(start), "{line} should start with {start}");
    }
}
