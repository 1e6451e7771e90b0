//! `bake` writes Vulkan EXT's per-geometry usage counts
//! (micromap-geometry-usage.bin, and per job in summary.json) and, with
//! `--no-mixed-special`, indices that never mix special indices with
//! records; `verify-bake` checks the per-geometry counts when present.

mod common;

use common::{run, scratch, text};
use std::collections::BTreeMap;
use std::path::Path;

const SPONZA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/crytek-sponza");

fn common_args() -> [String; 4] {
    [
        "--texture".into(),
        format!("{SPONZA}/chain.png"),
        "--triangles".into(),
        format!("{SPONZA}/grid.tris.json"),
    ]
}

/// Bakes into `out` (with `extra` flags) and returns summary.json.
fn bake(out: &Path, extra: &[&str]) -> serde_json::Value {
    let c = common_args();
    let mut args = vec!["bake"];
    args.extend(c.iter().map(String::as_str));
    args.extend(["--out", out.to_str().unwrap(), "--level", "3", "--quiet"]);
    args.extend(["--no-preview"]);
    args.extend(extra);
    let baked = run(&args);
    assert_eq!(baked.status.code(), Some(0), "{}", text(&baked.stderr));
    serde_json::from_slice(&baked.stdout).unwrap()
}

fn verify(out: &Path) -> std::process::Output {
    let c = common_args();
    let mut args = vec!["verify-bake"];
    args.extend(c.iter().map(String::as_str));
    args.extend(["--micromaps", out.to_str().unwrap(), "--json"]);
    run(&args)
}

fn le32(bytes: &[u8]) -> Vec<u32> {
    bytes
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

/// The per-geometry counts recomputed from the written indices and
/// records: (level, format) -> triangles.
fn counts_from_indices(out: &Path) -> BTreeMap<(u32, u32), u32> {
    let indices = le32(&std::fs::read(out.join("micromap-indices.bin")).unwrap());
    let records = std::fs::read(out.join("micromap-triangles.bin")).unwrap();
    let mut counts = BTreeMap::new();
    for &index in &indices {
        if (index as i32) >= 0 {
            let r = &records[index as usize * 8..][..8];
            let level = u32::from(u16::from_le_bytes([r[4], r[5]]));
            let format = u32::from(u16::from_le_bytes([r[6], r[7]]));
            *counts.entry((level, format)).or_default() += 1;
        }
    }
    counts
}

/// The file's one geometry: (level, format) -> count.
fn counts_from_file(out: &Path) -> BTreeMap<(u32, u32), u32> {
    let words = le32(&std::fs::read(out.join("micromap-geometry-usage.bin")).unwrap());
    let n = words[0] as usize;
    assert_eq!(words.len(), 1 + 3 * n, "one geometry: {words:?}");
    words[1..]
        .chunks_exact(3)
        .map(|u| ((u[1], u[2]), u[0]))
        .collect()
}

#[test]
fn geometry_usage_counts_match_the_indices_and_verify_checks_them() {
    let out = scratch("geometry-usage").join("out");
    let summary = bake(&out, &[]);
    let from_indices = counts_from_indices(&out);
    assert!(!from_indices.is_empty());
    assert_eq!(counts_from_file(&out), from_indices);
    let job = &summary["jobs"][0];
    let json: BTreeMap<(u32, u32), u32> = job["geometry_usage_counts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|u| {
            let get = |k: &str| u[k].as_u64().unwrap() as u32;
            ((get("level"), get("format")), get("count"))
        })
        .collect();
    assert_eq!(json, from_indices);
    // The chain on the grid has cells of one state: the default mixes.
    assert_eq!(job["mixed_special_indices"], true);
    assert!(summary["special_index_triangles"].as_u64().unwrap() > 0);

    let verified = verify(&out);
    assert_eq!(
        verified.status.code(),
        Some(0),
        "{}",
        text(&verified.stdout)
    );
    let report: serde_json::Value = serde_json::from_slice(&verified.stdout).unwrap();
    assert_eq!(report["geometry_usage_counts_checked"], true);

    // One count off: refused with the numbers (exit 2).
    let path = out.join("micromap-geometry-usage.bin");
    let mut bytes = std::fs::read(&path).unwrap();
    bytes[4] = bytes[4].wrapping_add(1);
    std::fs::write(&path, &bytes).unwrap();
    let wrong = verify(&out);
    assert_eq!(wrong.status.code(), Some(2), "{}", text(&wrong.stdout));
    assert!(
        text(&wrong.stderr).contains("per-geometry usage counts say"),
        "{}",
        text(&wrong.stderr)
    );
    // Truncated: refused, naming the byte.
    std::fs::write(&path, &bytes[..bytes.len() - 1]).unwrap();
    let truncated = verify(&out);
    assert_eq!(truncated.status.code(), Some(2));
    assert!(
        text(&truncated.stderr).contains("at byte 0"),
        "{}",
        text(&truncated.stderr)
    );
    // Absent (another baker's output): not checked, still sound.
    std::fs::remove_file(&path).unwrap();
    let absent = verify(&out);
    assert_eq!(absent.status.code(), Some(0), "{}", text(&absent.stdout));
    let report: serde_json::Value = serde_json::from_slice(&absent.stdout).unwrap();
    assert_eq!(report["geometry_usage_counts_checked"], false);
}

#[test]
fn no_mixed_special_writes_shared_level_zero_records_and_verifies() {
    let dir = scratch("no-mixed-special");
    let (mixed, unmixed) = (dir.join("mixed"), dir.join("unmixed"));
    let before = bake(&mixed, &[]);
    let after = bake(&unmixed, &["--no-mixed-special"]);
    assert_eq!(after["jobs"][0]["mixed_special_indices"], false);
    assert_eq!(after["special_index_triangles"], 0);
    let indices = le32(&std::fs::read(unmixed.join("micromap-indices.bin")).unwrap());
    assert!(indices.iter().all(|&i| (i as i32) >= 0));
    // Each special index became a level-0 record of its state: as many
    // more records as states the specials used (4-state: one byte each).
    let old = le32(&std::fs::read(mixed.join("micromap-indices.bin")).unwrap());
    let states: std::collections::BTreeSet<u32> =
        old.iter().copied().filter(|&i| (i as i32) < 0).collect();
    assert!(!states.is_empty(), "the default bake has special indices");
    let micromaps = |s: &serde_json::Value| s["micromaps_after_dedup"].as_u64().unwrap();
    assert_eq!(micromaps(&after), micromaps(&before) + states.len() as u64);
    let records = std::fs::read(unmixed.join("micromap-triangles.bin")).unwrap();
    let data = std::fs::read(unmixed.join("micromap-data.bin")).unwrap();
    for (&was, &now) in old.iter().zip(&indices) {
        if (was as i32) < 0 {
            let r = &records[now as usize * 8..][..8];
            assert_eq!((r[4], r[5], r[6], r[7]), (0, 0, 2, 0), "level 0, 4-state");
            // Special index -1 - s holds state s: the record's one state.
            let offset = u32::from_le_bytes([r[0], r[1], r[2], r[3]]) as usize;
            assert_eq!(data[offset], !was as u8, "special index {}", was as i32);
        }
    }
    assert_eq!(counts_from_file(&unmixed), counts_from_indices(&unmixed));
    let verified = verify(&unmixed);
    assert_eq!(
        verified.status.code(),
        Some(0),
        "{}",
        text(&verified.stdout)
    );
}
