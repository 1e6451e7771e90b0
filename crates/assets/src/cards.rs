//! The generator of `assets/crytek-sponza/cards.gltf`, `cards.bin`,
//! `cards.glb` and `grid.tris.json`, and the tests that read them.
//!
//! `committed_cards_are_reproducible` regenerates the files and compares
//! them with the committed ones byte for byte; with
//! `MICROMAP_INDEX_WRITE_ASSETS=1` it writes them instead:
//!
//! ```sh
//! MICROMAP_INDEX_WRITE_ASSETS=1 cargo test -p micromap-index-assets --lib cards
//! ```

use super::gltf::{GltfSampler, CLAMP_TO_EDGE, LINEAR, MIRRORED_REPEAT, NEAREST, REPEAT};
use super::{
    read_gltf_bytes, read_gltf_file, read_triangles_json, AlphaTexels, AssetError, Limits,
};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

type Triangle = [[f32; 2]; 3];

/// `assets/crytek-sponza/`.
fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/crytek-sponza")
}

/// One primitive of the generated asset.
struct Card {
    mesh: usize,
    name: &'static str,
    material: usize,
    /// Vertex positions and UVs.
    positions: Vec<[f32; 3]>,
    uvs: Vec<[f32; 2]>,
    /// Triangle corners; `None`: vertices in order (no `indices`).
    indices: Option<Vec<u32>>,
    /// Index component type (5121 or 5123).
    index_type: u64,
    /// Whether positions and UVs share one buffer view (stride 20).
    interleaved: bool,
}

impl Card {
    fn triangles(&self) -> Vec<Triangle> {
        let corners: Vec<usize> = match &self.indices {
            Some(indices) => indices.iter().map(|&i| i as usize).collect(),
            None => (0..self.uvs.len()).collect(),
        };
        corners
            .chunks_exact(3)
            .map(|c| [self.uvs[c[0]], self.uvs[c[1]], self.uvs[c[2]]])
            .collect()
    }
}

/// A quad card: corners top-left, top-right, bottom-right, bottom-left (in
/// UV space: `v` grows downwards), two triangles `0 1 2`, `0 2 3`, placed at
/// `x` in the `z = 0` plane.
fn quad(uv_corners: [[f64; 2]; 4], x: f32) -> (Vec<[f32; 3]>, Vec<[f32; 2]>, Vec<u32>) {
    let positions = vec![
        [x, 1.0, 0.0],
        [x + 1.0, 1.0, 0.0],
        [x + 1.0, 0.0, 0.0],
        [x, 0.0, 0.0],
    ];
    let uvs = uv_corners
        .iter()
        .map(|&[u, v]| [u as f32, v as f32])
        .collect();
    (positions, uvs, vec![0, 1, 2, 0, 2, 3])
}

fn rect(u0: f64, v0: f64, u1: f64, v1: f64) -> [[f64; 2]; 4] {
    [[u0, v0], [u1, v0], [u1, v1], [u0, v1]]
}

/// An indexed card (16-bit indices, separate buffers) from a [`quad`].
fn indexed_card(
    mesh: usize,
    name: &'static str,
    material: usize,
    (positions, uvs, indices): (Vec<[f32; 3]>, Vec<[f32; 2]>, Vec<u32>),
) -> Card {
    Card {
        mesh,
        name,
        material,
        positions,
        uvs,
        indices: Some(indices),
        index_type: 5123,
        interleaved: false,
    }
}

/// The primitives, in mesh and primitive order.
fn cards() -> Vec<Card> {
    let mut cards = Vec::new();
    // Mesh 0: four leaf cards on sponza_thorn.png.
    // The leaf cluster at the top left, axis-aligned.
    cards.push(indexed_card(
        0,
        "leaves_top_left",
        0,
        quad(rect(0.0, 0.0, 0.34, 0.34), 0.0),
    ));
    // The cluster in the middle, the card turned by 30 degrees about
    // (0.47, 0.36), half a side 0.15.
    let (sin, cos) = 30f64.to_radians().sin_cos();
    let turned = rect(-0.15, -0.15, 0.15, 0.15)
        .map(|[du, dv]| [0.47 + cos * du - sin * dv, 0.36 + sin * du + cos * dv]);
    let (positions, uvs, indices) = quad(turned, 1.5);
    // Not indexed: the six corners in order.
    cards.push(Card {
        mesh: 0,
        name: "leaves_rotated",
        material: 1,
        positions: indices.iter().map(|&i| positions[i as usize]).collect(),
        uvs: indices.iter().map(|&i| uvs[i as usize]).collect(),
        indices: None,
        index_type: 0,
        interleaved: false,
    });
    // Across the right edge (u in [0.75, 1.25]) and the bottom edge: REPEAT
    // brings in the left and top of the texture.
    cards.push(indexed_card(
        0,
        "leaves_repeat",
        0,
        quad(rect(0.75, 0.6, 1.25, 1.1), 3.0),
    ));
    // Across u = 0 and v = 1 with MIRRORED_REPEAT.
    cards.push(indexed_card(
        0,
        "leaves_mirrored",
        2,
        quad(rect(-0.2, 0.75, 0.2, 1.25), 4.5),
    ));
    // Mesh 1: the whole texture as an 8 x 8 grid of quads, 128 triangles,
    // positions and UVs interleaved.
    let mut grid = Card {
        mesh: 1,
        name: "grid_8x8",
        material: 0,
        positions: Vec::new(),
        uvs: Vec::new(),
        indices: Some(Vec::new()),
        index_type: 5123,
        interleaved: true,
    };
    for j in 0..=8u8 {
        for i in 0..=8u8 {
            let (u, v) = (f32::from(i) / 8.0, f32::from(j) / 8.0);
            grid.positions.push([2.0 * u, 2.0 - 2.0 * v, -1.0]);
            grid.uvs.push([u, v]);
        }
    }
    let at = |i: u32, j: u32| j * 9 + i;
    for j in 0..8 {
        for i in 0..8 {
            let quad = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
            grid.indices
                .as_mut()
                .unwrap()
                .extend([quad[0], quad[1], quad[2], quad[0], quad[2], quad[3]]);
        }
    }
    cards.push(grid);
    // Mesh 2: a strip of four chain cards down chain.png, sharing edges,
    // 8-bit indices.
    let mut chain = Card {
        mesh: 2,
        name: "chain_strip",
        material: 3,
        positions: Vec::new(),
        uvs: Vec::new(),
        indices: Some(Vec::new()),
        index_type: 5121,
        interleaved: false,
    };
    for k in 0..=4u8 {
        let v = f32::from(k) / 4.0;
        for u in [0.0, 1.0] {
            chain.positions.push([6.0 + 0.25 * u, 1.0 - v, 0.0]);
            chain.uvs.push([u, v]);
        }
    }
    for k in 0..4 {
        let (tl, tr, bl, br) = (2 * k, 2 * k + 1, 2 * k + 2, 2 * k + 3);
        chain
            .indices
            .as_mut()
            .unwrap()
            .extend([tl, tr, br, tl, br, bl]);
    }
    cards.push(chain);
    cards
}

/// The samplers, as read back.
fn samplers() -> [GltfSampler; 4] {
    let sampler = |wrap_s, wrap_t, filter| GltfSampler {
        wrap_s,
        wrap_t,
        mag_filter: Some(filter),
        min_filter: Some(filter),
    };
    [
        sampler(REPEAT, REPEAT, LINEAR),
        sampler(REPEAT, REPEAT, NEAREST),
        sampler(MIRRORED_REPEAT, MIRRORED_REPEAT, LINEAR),
        sampler(CLAMP_TO_EDGE, REPEAT, NEAREST),
    ]
}

/// Texture `t` uses image `TEXTURES[t].0` and sampler `TEXTURES[t].1`;
/// material `m` uses texture `m`, with cutoff `CUTOFFS[m]` (`None`: the
/// default 0.5, not written).
const TEXTURES: [(usize, usize); 4] = [(0, 0), (0, 1), (0, 2), (1, 3)];
const CUTOFFS: [Option<f64>; 4] = [Some(0.5), Some(0.3), None, Some(0.5)];
const MATERIALS: [&str; 4] = [
    "thorn_linear",
    "thorn_nearest_cutoff_0.3",
    "thorn_mirrored",
    "chain",
];
const MESHES: [&str; 3] = ["thorn_cards", "thorn_grid", "chain_strip"];
const IMAGES: [&str; 2] = ["sponza_thorn.png", "chain.png"];

/// Appends `bytes`, then zeros to a multiple of 4; returns the offset.
fn append(bin: &mut Vec<u8>, bytes: &[u8]) -> usize {
    let offset = bin.len();
    bin.extend_from_slice(bytes);
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    offset
}

/// The glTF JSON (without buffers and images) and the binary buffer.
fn build() -> (Value, Vec<u8>) {
    let cards = cards();
    let mut bin = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut view = |bin: &mut Vec<u8>, bytes: &[u8], stride: Option<usize>, target: u64| {
        let offset = append(bin, bytes);
        let mut v =
            json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len(), "target": target});
        if let Some(stride) = stride {
            v["byteStride"] = json!(stride);
        }
        views.push(v);
        views.len() - 1
    };
    let mut meshes: Vec<Vec<Value>> = vec![Vec::new(); MESHES.len()];
    for card in &cards {
        let (mut min, mut max) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for p in &card.positions {
            for k in 0..3 {
                min[k] = min[k].min(p[k]);
                max[k] = max[k].max(p[k]);
            }
        }
        let count = card.positions.len();
        let (position_view, uv_view, uv_offset) = if card.interleaved {
            let mut bytes = Vec::new();
            for (p, uv) in card.positions.iter().zip(&card.uvs) {
                for x in p.iter().chain(uv) {
                    bytes.extend_from_slice(&x.to_le_bytes());
                }
            }
            let v = view(&mut bin, &bytes, Some(20), 34962);
            (v, v, 12)
        } else {
            let positions: Vec<u8> = card
                .positions
                .iter()
                .flatten()
                .flat_map(|x| x.to_le_bytes())
                .collect();
            let uvs: Vec<u8> = card
                .uvs
                .iter()
                .flatten()
                .flat_map(|x| x.to_le_bytes())
                .collect();
            (
                view(&mut bin, &positions, None, 34962),
                view(&mut bin, &uvs, None, 34962),
                0,
            )
        };
        let f64s = |v: [f32; 3]| v.map(f64::from).to_vec();
        accessors.push(json!({
            "bufferView": position_view, "componentType": 5126, "count": count,
            "type": "VEC3", "min": f64s(min), "max": f64s(max),
        }));
        let mut uv =
            json!({"bufferView": uv_view, "componentType": 5126, "count": count, "type": "VEC2"});
        if uv_offset != 0 {
            uv["byteOffset"] = json!(uv_offset);
        }
        accessors.push(uv);
        let mut primitive = json!({
            "attributes": {"POSITION": accessors.len() - 2, "TEXCOORD_0": accessors.len() - 1},
            "material": card.material,
            "mode": 4,
        });
        if let Some(indices) = &card.indices {
            let bytes: Vec<u8> = match card.index_type {
                5121 => indices.iter().map(|&i| i as u8).collect(),
                _ => indices
                    .iter()
                    .flat_map(|&i| (i as u16).to_le_bytes())
                    .collect(),
            };
            let v = view(&mut bin, &bytes, None, 34963);
            accessors.push(json!({
                "bufferView": v, "componentType": card.index_type, "count": indices.len(), "type": "SCALAR",
            }));
            primitive["indices"] = json!(accessors.len() - 1);
        }
        primitive["extras"] = json!({"name": card.name});
        meshes[card.mesh].push(primitive);
    }
    let samplers: Vec<Value> = samplers()
        .iter()
        .map(|s| json!({"magFilter": s.mag_filter, "minFilter": s.min_filter, "wrapS": s.wrap_s, "wrapT": s.wrap_t}))
        .collect();
    let materials: Vec<Value> = (0..MATERIALS.len())
        .map(|m| {
            let mut material = json!({
                "name": MATERIALS[m],
                "alphaMode": "MASK",
                "doubleSided": true,
                "pbrMetallicRoughness": {"baseColorTexture": {"index": m}, "metallicFactor": 0.0, "roughnessFactor": 1.0},
            });
            if let Some(cutoff) = CUTOFFS[m] {
                material["alphaCutoff"] = json!(cutoff);
            }
            material
        })
        .collect();
    let gltf = json!({
        "asset": {
            "version": "2.0",
            // The committed asset names its generator by the crate's old name: kept, so the bytes stay identical.
            "generator": "micromap-index-verify src/assets/cards.rs",
            "copyright": "Textures: Crytek Sponza by Frank Meinl (Crytek), with modifications by Morgan McGuire, CC BY 3.0 (see README.md)",
        },
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": MESHES.iter().enumerate().map(|(m, name)| json!({"name": name, "mesh": m})).collect::<Vec<_>>(),
        "meshes": meshes.into_iter().zip(MESHES).map(|(primitives, name)| json!({"name": name, "primitives": primitives})).collect::<Vec<_>>(),
        "materials": materials,
        "textures": TEXTURES.iter().map(|&(source, sampler)| json!({"source": source, "sampler": sampler})).collect::<Vec<_>>(),
        "samplers": samplers,
        "accessors": accessors,
        "bufferViews": views,
    });
    (gltf, bin)
}

/// The four files: `cards.gltf`, `cards.bin`, `cards.glb`, `grid.tris.json`.
fn generate() -> Vec<(&'static str, Vec<u8>)> {
    let (mut gltf, bin) = build();
    let mut text_gltf = gltf.clone();
    text_gltf["buffers"] = json!([{"uri": "cards.bin", "byteLength": bin.len()}]);
    text_gltf["images"] = json!(IMAGES
        .iter()
        .map(|uri| json!({"uri": uri}))
        .collect::<Vec<_>>());
    let mut gltf_text = serde_json::to_string_pretty(&text_gltf).unwrap();
    gltf_text.push('\n');

    // The GLB: the same, with the images after the geometry in one buffer.
    let mut glb_bin = bin.clone();
    let mut images = Vec::new();
    for uri in IMAGES {
        let png = std::fs::read(dir().join(uri)).unwrap();
        let offset = append(&mut glb_bin, &png);
        gltf["bufferViews"]
            .as_array_mut()
            .unwrap()
            .push(json!({"buffer": 0, "byteOffset": offset, "byteLength": png.len()}));
        let view = gltf["bufferViews"].as_array().unwrap().len() - 1;
        images.push(json!({"bufferView": view, "mimeType": "image/png"}));
    }
    gltf["buffers"] = json!([{"byteLength": glb_bin.len()}]);
    gltf["images"] = json!(images);
    let mut json = serde_json::to_string(&gltf).unwrap().into_bytes();
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() + 8 + glb_bin.len();
    let mut glb = Vec::with_capacity(total);
    glb.extend_from_slice(b"glTF");
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&(total as u32).to_le_bytes());
    glb.extend_from_slice(&(json.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"JSON");
    glb.extend_from_slice(&json);
    glb.extend_from_slice(&(glb_bin.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"BIN\0");
    glb.extend_from_slice(&glb_bin);

    let grid = cards().into_iter().find(|c| c.name == "grid_8x8").unwrap();
    let mut tris = String::from(
        "{\n  \"source\": \"cards.gltf meshes[1].primitives[0] (thorn_grid, 8 x 8 quads)\",\n  \"triangles\": [\n",
    );
    let triangles = grid.triangles();
    for (t, triangle) in triangles.iter().enumerate() {
        let corners: Vec<String> = triangle
            .iter()
            .map(|[u, v]| format!("[{u}, {v}]"))
            .collect();
        let comma = if t + 1 < triangles.len() { "," } else { "" };
        tris.push_str(&["    [", &corners.join(", "), "]", comma, "\n"].concat());
    }
    tris.push_str("  ]\n}\n");
    vec![
        ("cards.gltf", gltf_text.into_bytes()),
        ("cards.bin", bin),
        ("cards.glb", glb),
        ("grid.tris.json", tris.into_bytes()),
    ]
}

#[test]
fn committed_cards_are_reproducible() {
    let write = std::env::var_os("MICROMAP_INDEX_WRITE_ASSETS").is_some_and(|v| v == "1");
    for (name, bytes) in generate() {
        let path = dir().join(name);
        if write {
            std::fs::write(&path, &bytes).unwrap();
        }
        let committed = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(
            committed == bytes,
            "{} differs from what crates/assets/src/cards.rs generates; rerun with MICROMAP_INDEX_WRITE_ASSETS=1",
            path.display()
        );
    }
}

/// The expected content of both `cards.gltf` and `cards.glb`.
fn check_cards(asset: &super::GltfAsset) {
    let cards = cards();
    assert_eq!(asset.primitives.len(), 6);
    assert_eq!(asset.warnings, Vec::<String>::new());
    let per_primitive: Vec<usize> = asset.primitives.iter().map(|p| p.triangles.len()).collect();
    assert_eq!(per_primitive, [2, 2, 2, 2, 128, 8]);
    let mut next_in_mesh = [0usize; 3];
    for (primitive, card) in asset.primitives.iter().zip(&cards) {
        assert_eq!(primitive.mesh, card.mesh);
        assert_eq!(primitive.primitive, next_in_mesh[card.mesh]);
        next_in_mesh[card.mesh] += 1;
        assert_eq!(primitive.material, card.material);
        assert_eq!(primitive.texture, card.material);
        let (image, sampler) = TEXTURES[card.material];
        assert_eq!(asset.image_info[primitive.image].index, image);
        assert_eq!(primitive.sampler, samplers()[sampler].to_sampler());
        let cutoff = CUTOFFS[card.material].unwrap_or(0.5) as f32;
        assert_eq!(primitive.cutoff.alpha(), cutoff, "{}", card.name);
        assert_eq!(primitive.alpha_factor, 1.0);
        assert_eq!(primitive.tex_coord, 0);
        assert_eq!(primitive.triangles, card.triangles(), "{}", card.name);
    }
    assert_eq!(asset.primitives[1].cutoff.alpha(), 0.3f32);
    assert_eq!(asset.images.len(), 2);
    let sizes: Vec<(u32, u32)> = asset.images.iter().map(|i| (i.width, i.height)).collect();
    assert_eq!(sizes, [(512, 512), (256, 1024)]);
    for image in &asset.images {
        let AlphaTexels::Unorm8(texels) = &image.texels else {
            panic!("8-bit RGBA textures");
        };
        assert!(texels.contains(&0) && texels.contains(&255));
    }
    // The repeat card reaches past u = 1 and v = 1, the mirrored past u = 0.
    let uvs = |p: usize| {
        asset.primitives[p]
            .triangles
            .iter()
            .flatten()
            .copied()
            .collect::<Vec<_>>()
    };
    assert!(uvs(2).iter().any(|&[u, v]| u > 1.0 && v > 1.0));
    assert!(uvs(3).iter().any(|&[u, _]| u < 0.0));
}

#[test]
fn cards_gltf_reads_as_generated() {
    let asset = read_gltf_file(&dir().join("cards.gltf"), &Limits::default()).unwrap();
    check_cards(&asset);
    assert_eq!(
        asset
            .image_info
            .iter()
            .map(|i| i.uri.clone())
            .collect::<Vec<_>>(),
        [
            Some("sponza_thorn.png".to_string()),
            Some("chain.png".to_string())
        ]
    );
}

#[test]
fn cards_glb_reads_like_cards_gltf() {
    let gltf = read_gltf_file(&dir().join("cards.gltf"), &Limits::default()).unwrap();
    let glb = read_gltf_file(&dir().join("cards.glb"), &Limits::default()).unwrap();
    check_cards(&glb);
    assert_eq!(glb.primitives, gltf.primitives);
    assert_eq!(glb.images, gltf.images);
    assert!(glb
        .image_info
        .iter()
        .all(|i| i.uri.is_none() && i.buffer_view.is_some()));
    // The GLB needs no files.
    let bytes = std::fs::read(dir().join("cards.glb")).unwrap();
    let mut no_files = |uri: &str| -> Result<Vec<u8>, AssetError> { panic!("asked for {uri}") };
    let again = read_gltf_bytes(&bytes, &mut no_files, &Limits::default()).unwrap();
    assert_eq!(again, glb);
}

#[test]
fn grid_tris_json_is_the_grid() {
    let triangles =
        read_triangles_json(&std::fs::read(dir().join("grid.tris.json")).unwrap()).unwrap();
    assert_eq!(triangles.len(), 128);
    let gltf = read_gltf_file(&dir().join("cards.gltf"), &Limits::default()).unwrap();
    assert_eq!(gltf.primitives[4].triangles, triangles);
    // The grid covers the texture: every triangle has area 1/128 of it.
    let area: f64 = triangles
        .iter()
        .map(|[a, b, c]| {
            let (ab, ac) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
            f64::from(ab[0] * ac[1] - ab[1] * ac[0]).abs() / 2.0
        })
        .sum();
    assert_eq!(area, 1.0);
}

#[test]
fn limits_apply_to_the_cards() {
    let path = dir().join("cards.gltf");
    let small = Limits {
        max_pixels: 512 * 512 - 1,
        ..Limits::default()
    };
    let error = read_gltf_file(&path, &small).unwrap_err();
    assert!(
        matches!(error.root(), AssetError::LimitExceeded { .. }),
        "{error}"
    );
    assert!(error.to_string().contains("images[0]"), "{error}");
    let tiny = Limits {
        max_bytes: 4096,
        ..Limits::default()
    };
    let error = read_gltf_file(&path, &tiny).unwrap_err();
    assert!(
        matches!(error.root(), AssetError::LimitExceeded { .. }),
        "{error}"
    );
}
