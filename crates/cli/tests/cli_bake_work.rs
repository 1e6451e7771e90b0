//! `bake` under bounded work (issue 26): the issue's 47-byte triangle over
//! 10^6 texture periods bakes with little work at its auto level (level 0:
//! its micro-triangles would each hold whole periods) and stops at its work
//! budget at a fixed level 12 (reported); the per-bake budget is reported
//! the same way; the bundled assets never come near the default. No test
//! here bounds a time: work is counted in work units, and a generous hang
//! guard (`common::HANG`) fails only a bake that never ends.

mod common;

use common::{run, run_within_hang_guard, scratch};
use micromap_index::bake::{DEFAULT_BAKE_WORK_BUDGET, DEFAULT_TRIANGLE_WORK_BUDGET};
use serde_json::Value;
use std::path::Path;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

fn chain() -> String {
    format!("{ROOT}/assets/crytek-sponza/chain.png")
}

/// The issue's input: one triangle spanning 10^6 periods of the texture.
const HUGE: &str = r#"{"triangles":[[[0,0],[1000000,0],[0,1000000]]]}"#;

/// Bakes with `args` into `dir/out` (under the hang guard), expects exit
/// 0, returns summary.json.
fn bake(dir: &Path, args: &[&str]) -> Value {
    let out = dir.join("out");
    let mut all = vec![
        "bake",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
        "--no-preview",
    ];
    all.extend_from_slice(args);
    let output = run_within_hang_guard(&all);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{all:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    serde_json::from_str(&summary).unwrap()
}

/// verify-bake of `dir/out` against the triangles: sound (exit 0).
fn verifies_sound(dir: &Path, texture: &str, tris: &Path) {
    let out = dir.join("out");
    let output = run(&[
        "verify-bake",
        "--texture",
        texture,
        "--triangles",
        tris.to_str().unwrap(),
        "--micromaps",
        out.to_str().unwrap(),
    ]);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
}

fn count(summary: &Value, path: &[&str]) -> u64 {
    let mut v = summary;
    for key in path {
        v = &v[*key];
    }
    v.as_u64()
        .unwrap_or_else(|| panic!("{path:?} in {summary}"))
}

#[test]
fn the_many_periods_triangle_bakes_at_level_0_at_once() {
    let dir = scratch("work-auto");
    let tris = dir.join("huge.json");
    std::fs::write(&tris, HUGE).unwrap();
    let summary = bake(
        &dir,
        &["--texture", &chain(), "--triangles", tris.to_str().unwrap()],
    );
    assert_eq!(summary["levels"], serde_json::json!([1]));
    assert_eq!(count(&summary, &["period_level_zero_triangles"]), 1);
    assert_eq!(count(&summary, &["status", "exact"]), 1);
    assert!(count(&summary, &["work_units"]) < 10_000, "{summary}");
    verifies_sound(&dir, &chain(), &tris);
}

/// At level 12 the triangle stops at its work budget: on one thread the
/// work is the budget plus at most one step's lookups, as counted since
/// issue 26; on the default threads `work_units` is the same (the serial
/// walk's), and what a split walk threw away is counted apart in
/// `speculative_work_units`. The same output bytes either way, and sound.
#[test]
fn the_many_periods_triangle_at_level_12_stops_at_its_work_budget() {
    let dir = scratch("work-fixed");
    let tris = dir.join("huge.json");
    std::fs::write(&tris, HUGE).unwrap();
    let budget = 1u64 << 20;
    let budget_text = budget.to_string();
    let args = [
        "--texture",
        &chain(),
        "--triangles",
        tris.to_str().unwrap(),
        "--level",
        "12",
        "--work-budget",
        &budget_text,
    ];
    let mut serial_args = args.to_vec();
    serial_args.extend(["--threads", "1"]);
    let serial = bake(&dir, &serial_args);
    let work = count(&serial, &["work_units"]);
    assert!((budget..budget + 5000).contains(&work), "{work}");
    let serial_data = std::fs::read(dir.join("out/micromap-data.bin")).unwrap();
    let mut parallel_args = args.to_vec();
    parallel_args.push("--force");
    let summary = bake(&dir, &parallel_args);
    // `work_units` is the serial walk's whatever the threads; the work a
    // split triangle threw away is `speculative_work_units` (0 on one
    // thread).
    assert_eq!(count(&summary, &["work_units"]), work, "{summary}");
    assert_eq!(count(&serial, &["speculative_work_units"]), 0, "{serial}");
    let _ = count(&summary, &["speculative_work_units"]);
    assert_eq!(
        std::fs::read(dir.join("out/micromap-data.bin")).unwrap(),
        serial_data
    );
    for summary in [&serial, &summary] {
        assert_eq!(count(summary, &["status", "work_budget_exceeded"]), 1);
        assert_eq!(count(summary, &["status", "exact"]), 0);
        assert_eq!(count(summary, &["period_level_zero_triangles"]), 0);
        assert_eq!(count(summary, &["micro_triangles", "opaque"]), 0);
    }
    verifies_sound(&dir, &chain(), &tris);
}

#[test]
fn a_spent_bake_budget_leaves_the_rest_unknown_and_counted() {
    let dir = scratch("work-bake");
    let grid = format!("{ROOT}/assets/crytek-sponza/grid.tris.json");
    let common = ["--texture", &chain(), "--triangles", &grid, "--level", "6"];
    let full = bake(&dir, &common);
    let triangles = count(&full, &["triangles"]);
    assert_eq!(count(&full, &["status", "work_budget_exceeded"]), 0);
    let half = (count(&full, &["work_units"]) / 2).to_string();
    let mut args = common.to_vec();
    args.extend(["--bake-work-budget", &half, "--force"]);
    let cut = bake(&dir, &args);
    let exceeded = count(&cut, &["status", "work_budget_exceeded"]);
    assert!(
        exceeded > 0 && exceeded < triangles,
        "{exceeded} of {triangles}"
    );
    assert_eq!(exceeded + count(&cut, &["status", "exact"]), triangles);
    let known = |s: &Value| {
        count(s, &["micro_triangles", "opaque"]) + count(s, &["micro_triangles", "transparent"])
    };
    assert!(known(&cut) < known(&full));
    verifies_sound(&dir, &chain(), Path::new(&grid));
    // Nothing at all to spend: every triangle is unknown.
    let mut args = common.to_vec();
    args.extend(["--bake-work-budget", "0", "--force"]);
    let none = bake(&dir, &args);
    assert_eq!(count(&none, &["status", "work_budget_exceeded"]), triangles);
    assert_eq!((known(&none), count(&none, &["work_units"])), (0, 0));
}

/// The bundled assets at their auto levels stay under a sixteenth of the
/// default per-triangle budget: the default never cuts an ordinary bake.
#[test]
fn the_bundled_assets_stay_far_under_the_default_budget() {
    let sixteenth = (DEFAULT_TRIANGLE_WORK_BUDGET / 16).to_string();
    for (name, gltf) in [
        ("cards", "assets/crytek-sponza/cards.glb"),
        ("fern", "assets/polyhaven-fern02/fern_02.gltf"),
    ] {
        let dir = scratch(&format!("work-{name}"));
        let path = format!("{ROOT}/{gltf}");
        let summary = bake(&dir, &["--gltf", &path, "--work-budget", &sixteenth]);
        assert_eq!(
            count(&summary, &["status", "work_budget_exceeded"]),
            0,
            "{name}"
        );
        assert!(count(&summary, &["work_units"]) > 0, "{name}");
    }
}

#[test]
fn the_work_flags_show_their_defaults_and_refuse_non_numbers() {
    let help = run(&["help", "bake"]);
    // The help is wrapped into its column: the words, one space apart.
    let help = String::from_utf8_lossy(&help.stdout)
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    assert!(
        help.contains(&format!("(default {DEFAULT_TRIANGLE_WORK_BUDGET})")),
        "{help}"
    );
    assert!(
        help.contains(&format!("(default {DEFAULT_BAKE_WORK_BUDGET})")),
        "{help}"
    );
    let dir = scratch("work-flags");
    let tris = dir.join("huge.json");
    std::fs::write(&tris, HUGE).unwrap();
    for flag in ["--work-budget", "--bake-work-budget"] {
        let out = dir.join("out");
        let output = run(&[
            "bake",
            "--texture",
            &chain(),
            "--triangles",
            tris.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            flag,
            "lots",
        ]);
        assert_eq!(output.status.code(), Some(2), "{flag}");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            stderr.contains(&format!("{flag} \"lots\": expected a count")),
            "{stderr}"
        );
        assert!(!out.join("summary.json").exists());
    }
}
