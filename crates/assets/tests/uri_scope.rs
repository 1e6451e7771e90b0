//! `Limits::uri_scope` on real files: `UriScope::Anywhere` reads what a
//! relative URI names, `../` included; `UriScope::AssetFolder` refuses a URI
//! that climbs above the asset's folder (as written) or leaves it through a
//! symbolic link, and a file that is not a regular one; a FIFO is refused
//! under both, without blocking. The glTF readers (`read_gltf_file`,
//! `read_gltf_micromaps_file`) and the writer (`write_gltf_micromaps_file`)
//! resolve alike.

use micromap_index::micromap::State;
use micromap_index::micromap::{BuildOptions, MicromapBuffers, TriangleOpacity};
use micromap_index_assets::{
    read_gltf_file, read_gltf_micromaps_file, write_gltf_micromaps_file, AssetError, GltfContainer,
    Limits, UriScope,
};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A fresh, empty folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("micromap-uri-scope-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A 2 x 2 grey + alpha PNG.
fn png() -> Vec<u8> {
    let mut out = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut out, 2, 2);
        encoder.set_color(png::ColorType::GrayscaleAlpha);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().unwrap();
        writer
            .write_image_data(&[0, 0, 0, 255, 0, 255, 0, 0])
            .unwrap();
    }
    out
}

/// `bytes` as a percent-encoded `data:` URI.
fn data_uri(bytes: &[u8]) -> String {
    let mut uri = String::from("data:application/octet-stream,");
    for b in bytes {
        let _ = write!(uri, "%{b:02X}");
    }
    uri
}

/// The buffer: three UVs, then three positions (the same points at z 0).
fn bin() -> Vec<u8> {
    let mut bin = Vec::new();
    for x in [
        0f32, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0,
    ] {
        bin.extend_from_slice(&x.to_le_bytes());
    }
    bin
}

/// A glTF of one MASK triangle whose image is the file `image_uri` (its
/// UVs and positions in a `data:` buffer).
fn gltf(image_uri: &str) -> String {
    serde_json::json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": 60, "uri": data_uri(&bin())}],
        "bufferViews": [
            {"buffer": 0, "byteLength": 24},
            {"buffer": 0, "byteOffset": 24, "byteLength": 36},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC2"},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]},
        ],
        "images": [{"uri": image_uri}],
        "textures": [{"source": 0}],
        "materials": [{"alphaMode": "MASK", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "meshes": [{"primitives": [{"attributes": {"TEXCOORD_0": 0, "POSITION": 1}, "material": 0}]}],
    })
    .to_string()
}

fn limits(uri_scope: UriScope) -> Limits {
    Limits {
        uri_scope,
        ..Limits::default()
    }
}

/// The message of a URI refusal, or `None` when the read succeeded.
fn refusal(result: Result<impl Sized, AssetError>) -> Option<String> {
    match result {
        Ok(_) => None,
        Err(e) => Some(e.to_string()),
    }
}

/// `root/shared/leaf.png`, and `root/asset/` with `a.gltf` naming
/// `image_uri`.
fn layout(root: &Path, image_uri: &str) -> PathBuf {
    std::fs::create_dir_all(root.join("shared")).unwrap();
    std::fs::create_dir_all(root.join("asset/sub")).unwrap();
    std::fs::write(root.join("shared/leaf.png"), png()).unwrap();
    std::fs::write(root.join("asset/leaf.png"), png()).unwrap();
    let asset = root.join("asset/a.gltf");
    std::fs::write(&asset, gltf(image_uri)).unwrap();
    asset
}

#[test]
fn a_uri_inside_the_folder_reads_under_both_scopes() {
    let root = scratch("inside");
    // `..` that stays inside the folder is fine.
    let asset = layout(&root, "sub/../leaf.png");
    for scope in [UriScope::Anywhere, UriScope::AssetFolder] {
        let read = read_gltf_file(&asset, &limits(scope)).unwrap();
        assert_eq!(read.primitives.len(), 1, "{scope:?}");
    }
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn dot_dot_above_the_folder_is_refused_only_when_confined() {
    let root = scratch("dotdot");
    let asset = layout(&root, "../shared/leaf.png");
    assert!(read_gltf_file(&asset, &limits(UriScope::Anywhere)).is_ok());
    let message = refusal(read_gltf_file(&asset, &limits(UriScope::AssetFolder))).unwrap();
    assert!(
        message.contains("URI \"../shared/leaf.png\": names a file outside the asset's folder"),
        "{message}"
    );
    let _ = std::fs::remove_dir_all(&root);
}

#[cfg(unix)]
#[test]
fn a_symbolic_link_out_of_the_folder_is_refused_only_when_confined() {
    let root = scratch("symlink");
    let asset = layout(&root, "link.png");
    std::os::unix::fs::symlink(root.join("shared/leaf.png"), root.join("asset/link.png")).unwrap();
    assert!(read_gltf_file(&asset, &limits(UriScope::Anywhere)).is_ok());
    let message = refusal(read_gltf_file(&asset, &limits(UriScope::AssetFolder))).unwrap();
    assert!(
        message.contains("URI \"link.png\": names a file outside the asset's folder"),
        "{message}"
    );
    // A link that stays inside the folder is followed.
    std::fs::remove_file(root.join("asset/link.png")).unwrap();
    std::os::unix::fs::symlink("sub/../leaf.png", root.join("asset/link.png")).unwrap();
    assert!(read_gltf_file(&asset, &limits(UriScope::AssetFolder)).is_ok());
    let _ = std::fs::remove_dir_all(&root);
}

/// A FIFO among the URIs is refused before it is opened (opening it would
/// block forever, no writer ever comes), under both scopes; a device is
/// refused when confined.
#[cfg(unix)]
#[test]
fn a_fifo_is_refused_without_blocking() {
    let root = scratch("fifo");
    let asset = layout(&root, "pipe.png");
    let made = std::process::Command::new("mkfifo")
        .arg(root.join("asset/pipe.png"))
        .status()
        .unwrap();
    assert!(made.success());
    for scope in [UriScope::Anywhere, UriScope::AssetFolder] {
        let message = refusal(read_gltf_file(&asset, &limits(scope))).unwrap();
        assert!(message.contains("not a regular file"), "{message}");
    }
    std::fs::remove_file(root.join("asset/pipe.png")).unwrap();
    std::os::unix::fs::symlink("/dev/zero", root.join("asset/pipe.png")).unwrap();
    let message = refusal(read_gltf_file(&asset, &limits(UriScope::AssetFolder))).unwrap();
    assert!(message.contains("outside the asset's folder"), "{message}");
    let _ = std::fs::remove_dir_all(&root);
}

/// The micromaps reader and the writer resolve the same way: a buffer
/// above the folder is refused when confined.
#[test]
fn the_micromaps_reader_and_the_writer_are_confined_too() {
    let root = scratch("writer");
    let asset = layout(&root, "leaf.png");
    // The buffer moves to a file above the folder.
    let text = std::fs::read_to_string(&asset).unwrap();
    let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
    std::fs::write(root.join("shared/uv.bin"), bin()).unwrap();
    json["buffers"][0]["uri"] = "../shared/uv.bin".into();
    std::fs::write(&asset, json.to_string()).unwrap();
    let out = root.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let buffers = MicromapBuffers::build(
        [TriangleOpacity::Special(State::Opaque)],
        BuildOptions::default(),
    )
    .unwrap();
    let write = |scope| {
        write_gltf_micromaps_file(
            &asset,
            &buffers,
            &[(0, 0)],
            &GltfContainer::Glb,
            &limits(scope),
        )
    };
    write(UriScope::Anywhere).unwrap();
    let message = refusal(write(UriScope::AssetFolder)).unwrap();
    assert!(message.contains("outside the asset's folder"), "{message}");
    // The micromaps reader: a JSON output whose micromap buffer is moved
    // above its folder reads only anywhere.
    let written = write_gltf_micromaps_file(
        &asset,
        &buffers,
        &[(0, 0)],
        &GltfContainer::Json { stem: "b".into() },
        &limits(UriScope::Anywhere),
    )
    .unwrap();
    let (_, micromaps) = written
        .sidecars
        .iter()
        .find(|(name, _)| name == "b.micromap.bin")
        .unwrap();
    std::fs::write(root.join("shared/b.micromap.bin"), micromaps).unwrap();
    let main = String::from_utf8(written.main).unwrap();
    assert!(main.contains("\"b.micromap.bin\""));
    let moved = out.join("b.gltf");
    std::fs::write(
        &moved,
        main.replace("\"b.micromap.bin\"", "\"../shared/b.micromap.bin\""),
    )
    .unwrap();
    let read = read_gltf_micromaps_file(&moved, &limits(UriScope::Anywhere)).unwrap();
    assert_eq!(read.primitives.len(), 1);
    let message = refusal(read_gltf_micromaps_file(
        &moved,
        &limits(UriScope::AssetFolder),
    ))
    .unwrap();
    assert!(message.contains("outside the asset's folder"), "{message}");
    let _ = std::fs::remove_dir_all(&root);
}
