//! `micromap-index bake --gltf` reads materials as a renderer does: the
//! fern as published (its base-colour image has no alpha channel) bakes
//! opaque with a note in `summary.json`; a `--texture` mask keeps its grey
//! value; a texture transform that cannot be baked exactly is refused with
//! exit 2.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const FERN: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/polyhaven-fern02");

/// A 1 x 1 RGB PNG, black: alpha 1 in a glTF, luminance 0 as a mask.
const BLACK_RGB_PNG: &[u8] = b"\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x00\x01\x00\x00\x00\x01\x08\x02\x00\x00\x00\x90\x77\x53\xde\x00\x00\x00\x0c\x49\x44\x41\x54\x78\x9c\x63\x60\x60\x60\x00\x00\x00\x04\x00\x01\xf6\x17\x38\x55\x00\x00\x00\x00\x49\x45\x4e\x44\xae\x42\x60\x82";

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_micromap-index"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "micromap-bake-materials-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("textures")).unwrap();
    dir
}

/// The published fern glTF (edited by `edit`), its buffer, and the black
/// RGB PNG standing in for its base-colour JPEG, in `dir`.
fn fern_in(dir: &Path, edit: impl FnOnce(&mut serde_json::Value)) -> PathBuf {
    let text = std::fs::read(Path::new(FERN).join("fern_02_1k.original.gltf")).unwrap();
    let mut json: serde_json::Value = serde_json::from_slice(&text).unwrap();
    edit(&mut json);
    let gltf = dir.join("fern.gltf");
    std::fs::write(&gltf, serde_json::to_vec(&json).unwrap()).unwrap();
    std::fs::copy(Path::new(FERN).join("fern_02.bin"), dir.join("fern_02.bin")).unwrap();
    std::fs::write(dir.join("textures/fern_02_diff_1k.jpg"), BLACK_RGB_PNG).unwrap();
    gltf
}

fn micro(summary: &serde_json::Value, state: &str) -> u64 {
    summary["micro_triangles"][state].as_u64().unwrap()
}

#[test]
fn the_fern_as_published_bakes_opaque_with_a_note() {
    let dir = scratch("fern");
    let gltf = fern_in(&dir, |_| {});
    let out = dir.join("out");
    let output = run(&[
        "bake",
        "--gltf",
        gltf.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--level",
        "2",
        "--quiet",
    ]);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let summary: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(micro(&summary, "opaque"), 6232 * 16);
    assert_eq!(micro(&summary, "transparent"), 0);
    let warnings = summary["warnings"].to_string();
    assert!(
        warnings.contains("has no alpha channel: its alpha is 1 (glTF), so every texel is opaque"),
        "{warnings}"
    );

    // The same image as a standalone mask: its grey value (0) is the
    // alpha, so every micro-triangle is transparent.
    let mask = dir.join("black.png");
    std::fs::write(&mask, BLACK_RGB_PNG).unwrap();
    let tris = dir.join("tris.json");
    std::fs::write(&tris, r#"{"triangles": [[[0, 0], [1, 0], [0, 1]]]}"#).unwrap();
    let output = run(&[
        "bake",
        "--texture",
        mask.to_str().unwrap(),
        "--triangles",
        tris.to_str().unwrap(),
        "--out",
        dir.join("mask-out").to_str().unwrap(),
        "--level",
        "2",
        "--quiet",
    ]);
    assert_eq!(output.status.code(), Some(0));
    let summary: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(micro(&summary, "transparent"), 16);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A rotated texture transform with offsets and scales no binary32 sum
/// holds (Blender's mapping node writes such values) bakes (issue 34: it
/// was refused), differs from the untransformed bake, and the written
/// asset verifies sound.
#[test]
fn a_rotated_inexact_texture_transform_bakes_and_verifies() {
    let dir = scratch("transform");
    // The committed fern with its alpha texture, as is and transformed.
    std::fs::copy(Path::new(FERN).join("fern_02.bin"), dir.join("fern_02.bin")).unwrap();
    std::fs::copy(
        Path::new(FERN).join("textures/fern_02_diff_1k.png"),
        dir.join("textures/fern_02_diff_1k.png"),
    )
    .unwrap();
    let text = std::fs::read(Path::new(FERN).join("fern_02.gltf")).unwrap();
    let json: serde_json::Value = serde_json::from_slice(&text).unwrap();
    let plain = dir.join("plain.gltf");
    std::fs::write(&plain, serde_json::to_vec(&json).unwrap()).unwrap();
    let mut turned = json;
    for material in turned["materials"].as_array_mut().unwrap() {
        material["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = serde_json::json!(
            {"KHR_texture_transform": {"rotation": 0.3, "offset": [0.705, 0.285], "scale": [0.35, 0.35]}}
        );
    }
    turned["extensionsRequired"] = serde_json::json!(["KHR_texture_transform"]);
    turned["extensionsUsed"] = serde_json::json!(["KHR_texture_transform"]);
    let gltf = dir.join("turned.gltf");
    std::fs::write(&gltf, serde_json::to_vec(&turned).unwrap()).unwrap();
    let bake = |asset: &std::path::Path, name: &str| {
        let out = dir.join(name);
        let output = run(&[
            "bake",
            "--gltf",
            asset.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--level",
            "3",
            "--quiet",
            "--gltf-out",
            "out.glb",
        ]);
        assert_eq!(
            output.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        let summary: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
        (out, summary)
    };
    let (out, transformed) = bake(&gltf, "out");
    let (_, untransformed) = bake(&plain, "plain");
    assert!(transformed["refused_primitives"]
        .as_array()
        .is_none_or(Vec::is_empty));
    assert_ne!(
        micro(&transformed, "opaque"),
        micro(&untransformed, "opaque"),
        "the transform moves what the triangles read"
    );
    let verified = run(&[
        "verify-bake",
        "--gltf",
        out.join("out.glb").to_str().unwrap(),
    ]);
    assert_eq!(
        verified.status.code(),
        Some(0),
        "{}{}",
        String::from_utf8_lossy(&verified.stdout),
        String::from_utf8_lossy(&verified.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}
