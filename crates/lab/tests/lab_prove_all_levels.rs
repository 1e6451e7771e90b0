//! `micromap-lab prove --all-levels`: exit 0 when the product search
//! proves the walk for every level, 1 with a confirmed face for version 1,
//! 2 on a usage error.

mod common;

use common::cli;

fn command(args: &[&str]) -> std::process::Output {
    cli::run(args)
}

#[test]
fn command_exits_0_when_proved_and_1_for_version1() {
    let proved = command(&["prove", "--all-levels"]);
    let text = String::from_utf8_lossy(&proved.stdout);
    assert_eq!(proved.status.code(), Some(0), "{text}");
    assert!(text.contains("proved in"), "{text}");
    for entry_point in [
        "the kernel's integer halves equal the reference's",
        "spec::cell_dyadic is the definition's cell",
        "exact_index_f64's first half (levels 0..=32) is the definition's",
        "the kernel's binary32 first half on the bits (wide, levels 0..=32;",
        "the kernel's float first half (clamp_flushed, truncate_float) holds its claims",
        "uv2index::index_unchecked and index are, token for token, the fold",
        "the x86-64 SIMD lanes are, token for token, the modelled intrinsics",
    ] {
        assert!(text.contains(entry_point), "{entry_point}: {text}");
    }
    assert!(!text.contains("NOT proved"), "{text}");

    let refuted = command(&["prove", "--all-levels", "--version1"]);
    let text = String::from_utf8_lossy(&refuted.stdout);
    assert_eq!(refuted.status.code(), Some(1), "{text}");
    assert!(text.contains("confirmed by the real functions"), "{text}");

    let json = command(&["prove", "--all-levels", "--version1", "--json"]);
    let text = String::from_utf8_lossy(&json.stdout);
    assert_eq!(json.status.code(), Some(1), "{text}");
    assert!(text.contains("\"verdict\":\"counterexample\""), "{text}");
    assert!(text.contains("\"confirmed\":true"), "{text}");
    for field in [
        "kernel_integer_halves",
        "cell_dyadic",
        "binary32_first_half",
        "binary64_first_half",
        "float_first_half",
        "float_clamp",
        "literal_first_half",
        "walk_fold",
        "rationals_source",
        "fixed_arithmetic",
        "simd_lanes",
    ] {
        let proved = format!("\"{field}\":{{\"verdict\":\"proved\"");
        assert!(text.contains(&proved), "{field}: {text}");
    }

    let bad = command(&["prove", "--all-levels", "--levels", "3"]);
    assert_eq!(bad.status.code(), Some(2));
}

/// `--certificate FILE` writes the proved product, byte for byte the
/// committed `docs/results/all_levels_certificate.json` (the file
/// `crates/lab/certificates/product.py` checks); nothing when not proved.
#[test]
fn certificate_is_the_committed_one_byte_for_byte() {
    let dir = cli::scratch("all_levels_certificate");
    let file = dir.join("product.json");
    let proved = command(&[
        "prove",
        "--all-levels",
        "--certificate",
        file.to_str().unwrap(),
    ]);
    assert_eq!(
        proved.status.code(),
        Some(0),
        "{}",
        cli::text(&proved.stderr)
    );
    let written = std::fs::read(&file).unwrap();
    let committed =
        std::fs::read(cli::root().join("docs/results/all_levels_certificate.json")).unwrap();
    assert!(
        written == committed,
        "prove --all-levels --certificate differs from docs/results/all_levels_certificate.json \
         (regenerate it and rerun crates/lab/certificates/product.py):\n{}",
        cli::text(&written)
    );

    let refuted_file = dir.join("version1.json");
    let refuted = command(&[
        "prove",
        "--all-levels",
        "--version1",
        "--certificate",
        refuted_file.to_str().unwrap(),
    ]);
    assert_eq!(refuted.status.code(), Some(1));
    assert!(cli::text(&refuted.stdout).contains("no certificate written"));
    assert!(!refuted_file.exists());
    let entries: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert_eq!(
        entries.len(),
        1,
        "only the proved certificate, no temporaries"
    );

    let missing = command(&["prove", "--all-levels", "--certificate"]);
    assert_eq!(missing.status.code(), Some(2));

    // A file below a file: cannot be written, exit 3, nothing left.
    let blocked = file.join("below-a-file.json");
    let unwritable = command(&[
        "prove",
        "--all-levels",
        "--certificate",
        blocked.to_str().unwrap(),
    ]);
    assert_eq!(
        unwritable.status.code(),
        Some(3),
        "{}",
        cli::text(&unwritable.stderr)
    );
    assert!(cli::text(&unwritable.stderr).contains("cannot create"));
    assert_eq!(std::fs::read(&file).unwrap(), committed);
}
