//! `bake --gltf-out` round-trips through glTF with `EXT_mesh_opacity_micromap`
//! and `verify-bake --gltf` passes on it, from another directory than the
//! asset's (a `.glb` holds its images and buffers, a `.gltf` holds them in
//! its `NAME.bin`; both verify moved away), as `.gltf` and `.glb`; micromaps made
//! wrong are caught (exit 1); what cannot be written is refused (exit 2)
//! with nothing written.

mod common;

use common::{run, scratch, text};
use std::path::Path;

const SPONZA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/crytek-sponza");

fn bake(input: &str, out: &Path, name: &str, extra: &[&str]) -> std::process::Output {
    let asset = format!("{SPONZA}/{input}");
    let out = out.to_str().unwrap();
    let mut args = vec![
        "bake",
        "--gltf",
        &asset,
        "--out",
        out,
        "--gltf-out",
        name,
        "--level",
        "4",
        "--quiet",
    ];
    args.extend_from_slice(extra);
    run(&args)
}

#[test]
fn baked_gltf_verifies_in_every_container() {
    for (input, name) in [
        ("cards.gltf", "with omm.gltf"),
        ("cards.gltf", "c.glb"),
        ("cards.glb", "c.glb"),
        ("cards.glb", "c.gltf"),
    ] {
        let dir = scratch(&format!("gltf-out-{input}-{name}"));
        let out = dir.join("deeper");
        let baked = bake(input, &out, name, &[]);
        assert_eq!(baked.status.code(), Some(0), "{}", text(&baked.stderr));
        // The raw buffers are still written.
        for raw in [
            "micromap-data.bin",
            "micromap-triangles.bin",
            "summary.json",
        ] {
            assert!(out.join(raw).is_file(), "{input} -> {name}: {raw}");
        }
        let written = out.join(name);
        let verified = run(&["verify-bake", "--gltf", written.to_str().unwrap(), "--json"]);
        let report = text(&verified.stdout);
        assert_eq!(
            verified.status.code(),
            Some(0),
            "{input} -> {name}: {report}{}",
            text(&verified.stderr)
        );
        let json: serde_json::Value = serde_json::from_str(&report).unwrap();
        assert_eq!(json["sound"], true);
        let primitives = json["primitives"].as_array().unwrap();
        assert_eq!(primitives.len(), 6, "{report}");
        assert!(primitives.iter().all(|p| p["has_micromaps"] == true));
        let known: u64 = primitives
            .iter()
            .map(|p| p["known_micro_triangles"].as_u64().unwrap())
            .sum();
        assert!(known > 0, "{report}");
        // The output stands alone: a .glb moved into a folder of its own,
        // a .gltf's folder moved (its images and buffers are in its BIN
        // chunk or its NAME.bin), it still verifies.
        let moved = if Path::new(name).extension().is_some_and(|e| e == "glb") {
            let alone = dir.join("alone");
            std::fs::create_dir_all(&alone).unwrap();
            let moved = alone.join(name);
            std::fs::rename(&written, &moved).unwrap();
            moved
        } else {
            let elsewhere = dir.join("elsewhere/deeper still");
            std::fs::create_dir_all(elsewhere.parent().unwrap()).unwrap();
            std::fs::rename(&out, &elsewhere).unwrap();
            let gltf: serde_json::Value =
                serde_json::from_slice(&std::fs::read(elsewhere.join(name)).unwrap()).unwrap();
            let stem = name.trim_end_matches(".gltf").replace(' ', "%20");
            let uris: Vec<&str> = ["buffers", "images"]
                .iter()
                .flat_map(|k| gltf[*k].as_array().unwrap())
                .filter_map(|o| o["uri"].as_str())
                .collect();
            assert_eq!(
                uris,
                [format!("{stem}.bin"), format!("{stem}.micromap.bin")],
                "{input} -> {name}: only its own files"
            );
            elsewhere.join(name)
        };
        let again = run(&["verify-bake", "--gltf", moved.to_str().unwrap(), "--json"]);
        assert_eq!(
            again.status.code(),
            Some(0),
            "{input} -> {name}, moved: {}",
            text(&again.stderr)
        );
        assert_eq!(text(&again.stdout), report, "{input} -> {name}, moved");
    }
}

/// XOR 0b01 on every 2-bit state swaps transparent and opaque (and the two
/// unknowns): every known state becomes wrong.
#[test]
fn micromaps_made_wrong_are_caught() {
    let dir = scratch("gltf-out-wrong");
    let baked = bake("cards.gltf", &dir, "w.gltf", &[]);
    assert_eq!(baked.status.code(), Some(0), "{}", text(&baked.stderr));
    let gltf: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("w.gltf")).unwrap()).unwrap();
    let ext = &gltf["extensions"]["EXT_mesh_opacity_micromap"]["micromaps"][0];
    let view = &gltf["bufferViews"][ext["data"].as_u64().unwrap() as usize];
    let (offset, length) = (
        view["byteOffset"].as_u64().unwrap() as usize,
        view["byteLength"].as_u64().unwrap() as usize,
    );
    let sidecar = dir.join("w.micromap.bin");
    let mut bytes = std::fs::read(&sidecar).unwrap();
    for b in &mut bytes[offset..offset + length] {
        *b ^= 0x55;
    }
    std::fs::write(&sidecar, bytes).unwrap();
    let verified = run(&[
        "verify-bake",
        "--gltf",
        dir.join("w.gltf").to_str().unwrap(),
    ]);
    let report = text(&verified.stdout);
    assert_eq!(verified.status.code(), Some(1), "{report}");
    assert!(report.starts_with("NOT SOUND"), "{report}");
    assert!(report.contains("mesh 0 primitive 0 triangle"), "{report}");
}

#[test]
fn what_cannot_be_written_or_checked_is_refused() {
    let dir = scratch("gltf-out-refused");
    let asset = format!("{SPONZA}/cards.gltf");
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    for (args, message) in [
        (
            vec![
                "bake",
                "--gltf",
                &asset,
                "--out",
                o,
                "--gltf-out",
                "x.gltf",
                "--cutoff",
                "0.4",
            ],
            "--cutoff with --gltf-out",
        ),
        (
            vec![
                "bake",
                "--gltf",
                &asset,
                "--out",
                o,
                "--gltf-out",
                "sub/x.glb",
            ],
            "expected a file name NAME.gltf or NAME.glb",
        ),
        (
            vec!["bake", "--gltf", &asset, "--out", o, "--gltf-out", "x.obj"],
            "expected a file name NAME.gltf or NAME.glb",
        ),
        (
            vec![
                "bake",
                "--texture",
                "t.png",
                "--triangles",
                "t.json",
                "--out",
                o,
                "--gltf-out",
                "x.glb",
            ],
            "give --gltf ASSET",
        ),
        (
            vec![
                "bake",
                "--gltf",
                &asset,
                "--out",
                o,
                "--gltf-out",
                "micromap-data.gltf",
            ],
            "would write micromap-data.bin, which bake writes too",
        ),
        (
            vec!["verify-bake", "--gltf", &asset],
            "no primitive has EXT_mesh_opacity_micromap",
        ),
        (
            vec!["verify-bake", "--gltf", &asset, "--micromaps", o],
            "--micromaps with --gltf",
        ),
        (
            vec!["verify-bake", "--gltf", &asset, "--filter", "linear"],
            "--filter with verify-bake --gltf",
        ),
    ] {
        let output = run(&args);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        assert!(
            text(&output.stderr).contains(message),
            "{args:?}: {}",
            text(&output.stderr)
        );
        assert!(
            !out.join("x.gltf").exists() && !out.join("x.glb").exists(),
            "{args:?}"
        );
    }
    // An existing output is kept without --force, and replaced with it.
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("x.micromap.bin"), b"mine").unwrap();
    let refused = bake("cards.gltf", &out, "x.gltf", &[]);
    assert_eq!(refused.status.code(), Some(2), "{}", text(&refused.stderr));
    assert_eq!(std::fs::read(out.join("x.micromap.bin")).unwrap(), b"mine");
    assert!(!out.join("x.gltf").exists());
    let forced = bake("cards.gltf", &out, "x.gltf", &["--force"]);
    assert_eq!(forced.status.code(), Some(0), "{}", text(&forced.stderr));
    assert_ne!(std::fs::read(out.join("x.micromap.bin")).unwrap(), b"mine");
}

/// A primitive the model does not cover (here `KHR_texture_transform`
/// with a rotation beyond 65536 radians on the one material of
/// meshes[2].primitives[0]) is left
/// out: exit 5, named on stderr and in summary.json, the other five baked,
/// written back without the extension on it, and the output verifies
/// sound. `--strict` makes it exit 2 with nothing written.
#[test]
fn a_primitive_that_cannot_be_baked_is_left_out_or_refused() {
    let dir = scratch("gltf-out-partial");
    for file in ["cards.bin", "sponza_thorn.png", "chain.png"] {
        std::fs::copy(format!("{SPONZA}/{file}"), dir.join(file)).unwrap();
    }
    let mut gltf: serde_json::Value =
        serde_json::from_slice(&std::fs::read(format!("{SPONZA}/cards.gltf")).unwrap()).unwrap();
    gltf["materials"][3]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] =
        serde_json::json!({"KHR_texture_transform": {"rotation": 1e6}});
    gltf["extensionsUsed"] = serde_json::json!(["KHR_texture_transform"]);
    let asset = dir.join("rotated.gltf");
    std::fs::write(&asset, serde_json::to_vec(&gltf).unwrap()).unwrap();
    let asset = asset.to_str().unwrap();
    let reason = "materials[3].pbrMetallicRoughness.baseColorTexture.extensions.\
                  KHR_texture_transform: texture transform rotation 1000000: expected at most 65536 radians";

    let strict = dir.join("strict");
    let refused = run(&[
        "bake",
        "--gltf",
        asset,
        "--out",
        strict.to_str().unwrap(),
        "--level",
        "3",
        "--quiet",
        "--strict",
    ]);
    assert_eq!(refused.status.code(), Some(2), "{}", text(&refused.stderr));
    let message = text(&refused.stderr);
    assert!(
        message.contains("meshes[2].primitives[0] cannot be baked soundly"),
        "{message}"
    );
    assert!(message.contains(reason), "{message}");
    assert!(!strict.exists(), "nothing written");

    let out = dir.join("partial");
    let baked = run(&[
        "bake",
        "--gltf",
        asset,
        "--out",
        out.to_str().unwrap(),
        "--level",
        "3",
        "--quiet",
        "--gltf-out",
        "p.glb",
    ]);
    assert_eq!(baked.status.code(), Some(5), "{}", text(&baked.stderr));
    let message = text(&baked.stderr);
    assert!(
        message.contains("meshes[2].primitives[0] not baked: "),
        "{message}"
    );
    assert!(message.contains(reason), "{message}");
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    let listed = summary["refused_primitives"].as_array().unwrap();
    assert_eq!(listed.len(), 1, "{summary}");
    assert_eq!(
        (listed[0]["mesh"].as_u64(), listed[0]["primitive"].as_u64()),
        (Some(2), Some(0))
    );
    assert!(listed[0]["reason"].as_str().unwrap().starts_with(reason));
    assert_eq!(summary["jobs"].as_array().unwrap().len(), 5);
    let verified = run(&[
        "verify-bake",
        "--gltf",
        out.join("p.glb").to_str().unwrap(),
        "--json",
    ]);
    let report = text(&verified.stdout);
    assert_eq!(
        verified.status.code(),
        Some(0),
        "{report}{}",
        text(&verified.stderr)
    );
    let report: serde_json::Value = serde_json::from_str(&report).unwrap();
    let with: Vec<_> = report["primitives"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            (
                p["mesh"].as_u64().unwrap(),
                p["primitive"].as_u64().unwrap(),
            )
        })
        .collect();
    assert_eq!(with.len(), 5);
    assert!(!with.contains(&(2, 0)));
}
