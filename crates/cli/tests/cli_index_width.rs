//! `--index-width 8` (Vulkan KHR, DXR and glTF take 8-bit micromap
//! indices): `bake` writes one byte per triangle and `verify-bake` reads it
//! back; a width that is not 8, 16 or 32 is refused (exit 2).

mod common;

use common::{run, scratch, text};

const SPONZA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/crytek-sponza");

#[test]
fn eight_bit_indices_bake_and_verify() {
    let dir = scratch("index-width-8");
    let out = dir.join("out");
    let (texture, triangles) = (
        format!("{SPONZA}/sponza_thorn.png"),
        format!("{SPONZA}/grid.tris.json"),
    );
    let o = out.to_str().unwrap();
    let common = ["--texture", &texture, "--triangles", &triangles];
    let mut args = vec!["bake"];
    args.extend(common);
    args.extend([
        "--out",
        o,
        "--level",
        "3",
        "--index-width",
        "8",
        "--quiet",
        "--no-preview",
    ]);
    let baked = run(&args);
    assert_eq!(baked.status.code(), Some(0), "{}", text(&baked.stderr));
    let summary: serde_json::Value = serde_json::from_slice(&baked.stdout).unwrap();
    assert_eq!(summary["index_width_bits"], 8);
    let indices = std::fs::read(out.join("micromap-indices.bin")).unwrap();
    assert_eq!(indices.len() as u64, summary["triangles"].as_u64().unwrap());
    let mut verify = vec!["verify-bake"];
    verify.extend(common);
    verify.extend(["--micromaps", o, "--index-width", "8"]);
    let verified = run(&verify);
    assert_eq!(
        verified.status.code(),
        Some(0),
        "{}",
        text(&verified.stdout)
    );
    // Read as 16-bit, the same bytes are half as many indices: refused.
    let wrong = run(&verify[..verify.len() - 1]
        .iter()
        .copied()
        .chain(["16"])
        .collect::<Vec<_>>());
    assert_eq!(wrong.status.code(), Some(2), "{}", text(&wrong.stdout));
    args.pop();
    let mut bad = args.clone();
    let w = bad.iter().position(|a| *a == "8").unwrap();
    bad[w] = "24";
    let refused = run(&bad);
    assert_eq!(refused.status.code(), Some(2));
    assert!(
        text(&refused.stderr).contains("expected 8, 16 or 32"),
        "{}",
        text(&refused.stderr)
    );
}
