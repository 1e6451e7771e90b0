//! `--confine-uris` (issue 37): every command that reads a `--gltf` asset
//! (`bake`, `--gltf-out`, `verify-bake --gltf`, `render`) reads only
//! regular files inside the asset's folder when it is given; without it
//! `../` URIs read as before. A FIFO among the URIs is refused either way
//! (it would block the read forever).

mod common;

use common::{root, run, scratch, text};
use std::path::{Path, PathBuf};

/// `dir/asset/cards.gltf`, the committed Sponza cards whose two textures
/// are named as `../shared/NAME` (in `dir/shared/`), or as `NAME` beside
/// the asset when `beside`.
fn cards(dir: &Path, beside: bool) -> PathBuf {
    let source = root().join("assets/crytek-sponza");
    let asset_dir = dir.join("asset");
    std::fs::create_dir_all(&asset_dir).unwrap();
    std::fs::create_dir_all(dir.join("shared")).unwrap();
    std::fs::copy(source.join("cards.bin"), asset_dir.join("cards.bin")).unwrap();
    let mut gltf = std::fs::read_to_string(source.join("cards.gltf")).unwrap();
    for png in ["sponza_thorn.png", "chain.png"] {
        if beside {
            std::fs::copy(source.join(png), asset_dir.join(png)).unwrap();
        } else {
            std::fs::copy(source.join(png), dir.join("shared").join(png)).unwrap();
            gltf = gltf.replace(&format!("\"{png}\""), &format!("\"../shared/{png}\""));
        }
    }
    let asset = asset_dir.join("cards.gltf");
    std::fs::write(&asset, gltf).unwrap();
    asset
}

fn bake(asset: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "bake",
        "--gltf",
        asset.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--level",
        "2",
        "--no-preview",
        "--quiet",
    ];
    args.extend_from_slice(extra);
    run(&args)
}

#[test]
fn bake_reads_dot_dot_uris_unless_confined() {
    let dir = scratch("confine-dotdot");
    let asset = cards(&dir, false);
    let free = bake(&asset, &dir.join("free"), &[]);
    assert_eq!(free.status.code(), Some(0), "{}", text(&free.stderr));
    let out = dir.join("confined");
    let confined = bake(&asset, &out, &["--confine-uris"]);
    let message = text(&confined.stderr);
    assert_eq!(confined.status.code(), Some(2), "{message}");
    assert!(
        message.contains(
            "URI \"../shared/sponza_thorn.png\": names a file outside the asset's folder"
        ),
        "{message}"
    );
    assert!(!out.join("summary.json").exists());
}

#[cfg(unix)]
#[test]
fn a_symbolic_link_out_of_the_folder_is_refused_when_confined() {
    let dir = scratch("confine-symlink");
    let asset = cards(&dir, true);
    let thorn = asset.with_file_name("sponza_thorn.png");
    std::fs::remove_file(&thorn).unwrap();
    std::os::unix::fs::symlink(root().join("assets/crytek-sponza/sponza_thorn.png"), &thorn)
        .unwrap();
    let free = bake(&asset, &dir.join("free"), &[]);
    assert_eq!(free.status.code(), Some(0), "{}", text(&free.stderr));
    let confined = bake(&asset, &dir.join("confined"), &["--confine-uris"]);
    let message = text(&confined.stderr);
    assert_eq!(confined.status.code(), Some(2), "{message}");
    assert!(
        message.contains("URI \"sponza_thorn.png\": names a file outside the asset's folder"),
        "{message}"
    );
}

/// Inside the folder, a confined bake writes the same bytes as a free one,
/// `--gltf-out` included.
#[test]
fn inside_the_folder_confined_is_the_same_bake() {
    let dir = scratch("confine-same");
    let asset = cards(&dir, true);
    let (free, confined) = (dir.join("free"), dir.join("confined"));
    for (out, extra) in [
        (&free, &["--gltf-out", "x.glb"][..]),
        (&confined, &["--gltf-out", "x.glb", "--confine-uris"][..]),
    ] {
        let result = bake(&asset, out, extra);
        assert_eq!(result.status.code(), Some(0), "{}", text(&result.stderr));
    }
    for file in ["micromap-data.bin", "micromap-indices.bin", "x.glb"] {
        assert_eq!(
            std::fs::read(free.join(file)).unwrap(),
            std::fs::read(confined.join(file)).unwrap(),
            "{file}"
        );
    }
}

/// `verify-bake --gltf` reads the asset's micromaps under the same scope.
/// A `--gltf-out` output stands alone, so it verifies with the flag; with
/// its micromap buffer moved out of its folder (its URI `../`), it is
/// verified without the flag and refused with it.
#[test]
fn verify_bake_is_confined_too() {
    let dir = scratch("confine-verify");
    let asset = cards(&dir, false);
    let out = dir.join("asset/baked");
    let baked = bake(&asset, &out, &["--gltf-out", "x.gltf"]);
    assert_eq!(baked.status.code(), Some(0), "{}", text(&baked.stderr));
    let written = out.join("x.gltf");
    let verify = |confined: bool| {
        let mut args = vec!["verify-bake", "--gltf", written.to_str().unwrap()];
        if confined {
            args.push("--confine-uris");
        }
        run(&args)
    };
    for confined in [false, true] {
        let o = verify(confined);
        assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    }
    std::fs::rename(out.join("x.micromap.bin"), dir.join("asset/x.micromap.bin")).unwrap();
    let json = std::fs::read_to_string(&written).unwrap();
    assert!(json.contains("\"x.micromap.bin\""));
    std::fs::write(
        &written,
        json.replace("\"x.micromap.bin\"", "\"../x.micromap.bin\""),
    )
    .unwrap();
    let free = verify(false);
    assert_eq!(free.status.code(), Some(0), "{}", text(&free.stderr));
    let confined = verify(true);
    let message = text(&confined.stderr);
    assert_eq!(confined.status.code(), Some(2), "{message}");
    assert!(
        message.contains("names a file outside the asset's folder"),
        "{message}"
    );
}

/// `render` reads its input through the same shared flags: the refusal
/// comes before any Vulkan device is looked for (exit 2, not 4).
#[test]
fn render_is_confined_before_it_looks_for_a_device() {
    let dir = scratch("confine-render");
    let asset = cards(&dir, false);
    let result = run(&[
        "render",
        "--gltf",
        asset.to_str().unwrap(),
        "--out",
        dir.join("out").to_str().unwrap(),
        "--level",
        "1",
        "--confine-uris",
    ]);
    let message = text(&result.stderr);
    assert_eq!(result.status.code(), Some(2), "{message}");
    assert!(
        message.contains("names a file outside the asset's folder"),
        "{message}"
    );
}

/// The flag confines a glTF's URIs: without `--gltf` it is a usage error.
#[test]
fn without_gltf_the_flag_is_a_usage_error() {
    let dir = scratch("confine-texture");
    let assets = root().join("assets/crytek-sponza");
    let result = run(&[
        "bake",
        "--texture",
        assets.join("chain.png").to_str().unwrap(),
        "--triangles",
        assets.join("grid.tris.json").to_str().unwrap(),
        "--out",
        dir.join("out").to_str().unwrap(),
        "--confine-uris",
    ]);
    let message = text(&result.stderr);
    assert_eq!(result.status.code(), Some(2), "{message}");
    assert!(
        message.contains("--confine-uris confines a glTF asset's URIs: it goes with --gltf"),
        "{message}"
    );
}

/// A FIFO among the URIs is refused at once (exit 3, unreadable), with or
/// without the flag; before, the read blocked forever.
#[cfg(unix)]
#[test]
fn a_fifo_among_the_uris_is_refused() {
    let dir = scratch("confine-fifo");
    let asset = cards(&dir, true);
    let thorn = asset.with_file_name("sponza_thorn.png");
    std::fs::remove_file(&thorn).unwrap();
    let made = std::process::Command::new("mkfifo")
        .arg(&thorn)
        .status()
        .unwrap();
    assert!(made.success());
    for extra in [&[][..], &["--confine-uris"][..]] {
        let result = common::run_within_hang_guard(
            &[
                &[
                    "bake",
                    "--gltf",
                    asset.to_str().unwrap(),
                    "--out",
                    dir.join("out").to_str().unwrap(),
                    "--quiet",
                ][..],
                extra,
            ]
            .concat(),
        );
        let message = text(&result.stderr);
        assert!(message.contains("not a regular file"), "{message}");
        assert_eq!(result.status.code(), Some(3), "{message}");
    }
}
