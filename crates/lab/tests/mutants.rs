//! The full mutation run of the proof tiers (`crates/lab/mutants/run.sh`
//! on every mutant of `mutants.txt`), behind the project's one exhaustive
//! switch: `cargo test --release --all-features -- --ignored` (about 20
//! minutes on 2 cores, more from a cold build). `.ci/run` runs the subset
//! `run.sh --subset` by default.

use std::path::Path;
use std::process::Command;

#[test]
#[ignore = "exhaustive: every mutant, about 20 minutes on 2 cores"]
fn every_listed_mutant_is_killed_or_documented_equivalent() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    // Its own target folder: the cargo running this test holds the lock
    // of the usual one.
    let target = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mutants");
    let output = Command::new("bash")
        .arg("crates/lab/mutants/run.sh")
        .current_dir(&root)
        .env("CARGO_TARGET_DIR", &target)
        .output()
        .expect("bash runs crates/lab/mutants/run.sh");
    let report = String::from_utf8_lossy(&output.stdout);
    let errors = String::from_utf8_lossy(&output.stderr);
    println!("{report}{errors}");
    assert!(
        output.status.success(),
        "some mutant survived or could not be applied:\n{report}{errors}"
    );
    assert!(report.contains(" killed: "), "{report}");
}
