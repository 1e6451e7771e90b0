//! The shipped C driver (`reference/drivers/c/`): built with the system C
//! compiler and run against the committed `spec-f32` vectors, it passes
//! `check`; capped with `--max-level 12` it passes with the levels above
//! counted as unsupported. Skipped, saying so, where no `cc` runs.

mod common;

use common::root;
use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};

/// `micromap-index check` on the spec-f32 vectors with `answers` on stdin:
/// exit code and stdout.
fn check(answers: &[u8]) -> (Option<i32>, String) {
    let vectors = common::committed("spec-f32.json");
    let output =
        common::run_with_stdin(&["check", "--vectors", &vectors, "--answers", "-"], answers);
    (output.status.code(), common::text(&output.stdout))
}

#[test]
fn c_driver_passes_the_spec_f32_vectors() {
    let Ok(version) = Command::new("cc").arg("--version").output() else {
        println!("skipped: no `cc` on this machine to build reference/drivers/c");
        return;
    };
    assert!(version.status.success(), "cc --version failed");
    let dir = root().join("reference/drivers/c");
    let driver = Path::new(env!("CARGO_TARGET_TMPDIR")).join("micromap-c-driver");
    // The build command docs/vectors.md gives.
    let build = Command::new("cc")
        .args(["-O2", "-std=c99", "-Wall", "-Wextra", "-Werror"])
        .args(["-ffp-contract=off", "-fno-fast-math"])
        .arg(dir.join("driver.c"))
        .arg(dir.join("implementation.c"))
        .arg("-o")
        .arg(&driver)
        .output()
        .unwrap();
    assert!(
        build.status.success(),
        "{}",
        String::from_utf8_lossy(&build.stderr)
    );
    let vectors = root().join("reference/vectors/spec-f32.json");
    for (args, unsupported) in [(vec![], false), (vec!["--max-level", "12"], true)] {
        let output = Command::new(&driver)
            .args(&args)
            .arg(&vectors)
            .output()
            .unwrap();
        assert_eq!(output.status.code(), Some(0), "{args:?}");
        let (code, report) = check(&output.stdout);
        assert_eq!(code, Some(0), "{args:?}: {report}");
        let first = report.lines().next().unwrap();
        assert!(first.ends_with("PASS"), "{first}");
        assert_eq!(first.contains(" 0 unsupported"), !unsupported, "{first}");
    }
    // The simple line format.
    let mut child = Command::new(&driver)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(b"7 3e800000 3e800000 2\n8 7fc00000 3f000000 1\n")
        .unwrap();
    let output = child.wait_with_output().unwrap();
    assert_eq!(
        String::from_utf8_lossy(&output.stdout),
        "{\"id\": 7, \"index\": 5}\n{\"id\": 8, \"index\": 3}\n"
    );
}
