//! glTF materials as a renderer reads them: an image without alpha is
//! opaque, `baseColorFactor` multiplies in binary32, `texCoord` picks the
//! UV set, `COLOR_0` alpha multiplies in, `KHR_texture_transform` moves the
//! UVs (or is refused). Each on a small hand-made asset whose expected
//! states are computed here, independently of the baker.

use micromap_index::bake::mesh::{
    bake_mesh, LevelRule, Material, Mesh, MeshBakeError, MeshOptions, MeshTriangles,
};
use micromap_index::bake::{
    faithful_f32, AddressMode, Filter, Model, Sampler, Unorm8Texture, UvTransform,
};
use micromap_index::inverse::micro_triangle;
use micromap_index::micromap::State;
use micromap_index::Level;
use micromap_index_assets::{
    decode_alpha_image, decode_image_alpha, read_gltf_bytes, AlphaSource, AlphaTexels, AssetError,
    GltfAsset, Limits, MissingAlpha,
};
use serde_json::{json, Value};
use std::path::Path;

fn png(width: u32, height: u32, color: png::ColorType, data: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut out, width, height);
        encoder.set_color(color);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(data).unwrap();
    }
    out
}

/// A glTF of one MASK primitive (the quad (0,0)-(1,1) as two triangles,
/// `TEXCOORD_0` and a second set `TEXCOORD_1` = `TEXCOORD_0 / 2`), served
/// with `b.bin` and the image `a.png`; `edit` changes the JSON first.
fn asset(image: &[u8], edit: impl FnOnce(&mut Value)) -> Result<GltfAsset, AssetError> {
    let mut bin = Vec::new();
    for x in [0f32, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0] {
        bin.extend_from_slice(&x.to_le_bytes());
    }
    for x in [0f32, 0.0, 0.5, 0.0, 0.5, 0.5, 0.0, 0.5] {
        bin.extend_from_slice(&x.to_le_bytes());
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    bin.extend_from_slice(&[0; 4]);
    // COLOR_0 as normalized bytes (RGBA) at 80: alphas 51, 102, 204, 255.
    for a in [51u8, 102, 204, 255] {
        bin.extend_from_slice(&[255, 255, 255, a]);
    }
    let mut json = json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": bin.len(), "uri": "b.bin"}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 32},
            {"buffer": 0, "byteOffset": 32, "byteLength": 32},
            {"buffer": 0, "byteOffset": 64, "byteLength": 12},
            {"buffer": 0, "byteOffset": 80, "byteLength": 16},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"},
            {"bufferView": 3, "componentType": 5121, "normalized": true, "count": 4, "type": "VEC4"},
        ],
        "images": [{"uri": "a.png"}],
        "samplers": [{"magFilter": 9728, "wrapS": 33071, "wrapT": 33071}],
        "textures": [{"source": 0, "sampler": 0}],
        "materials": [{"alphaMode": "MASK", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "meshes": [{"primitives": [{"attributes": {"TEXCOORD_0": 0, "TEXCOORD_1": 1}, "indices": 2, "material": 0}]}],
    });
    edit(&mut json);
    let text = serde_json::to_vec(&json).unwrap();
    let image = image.to_vec();
    let mut resolve = |uri: &str| -> Result<Vec<u8>, AssetError> {
        match uri {
            "b.bin" => Ok(bin.clone()),
            "a.png" => Ok(image.clone()),
            _ => Err(AssetError::Io {
                path: uri.into(),
                message: "no such file".into(),
            }),
        }
    };
    read_gltf_bytes(&text, &mut resolve, &Limits::default())
}

/// A fixed level under the exact model: the expected states below are
/// computed for the exact real points (the GPU model, the default, widens
/// texel-aligned edges to unknown; `tests/bake_gpu_oracle.rs` in the lab
/// checks that model).
fn fixed(level: u32) -> MeshOptions {
    MeshOptions {
        levels: LevelRule::Fixed(Level::new(level).unwrap()),
        model: micromap_index::bake::Model::Exact,
        ..MeshOptions::default()
    }
}

// ------------------------------------------------ an image without alpha

#[test]
fn a_gltf_image_without_alpha_is_opaque_and_a_mask_keeps_its_grey() {
    // Black: as luminance every texel would be transparent.
    let grey = png(4, 4, png::ColorType::Grayscale, &[0; 16]);
    let rgb = png(2, 2, png::ColorType::Rgb, &[10; 12]);
    for (image, pixels) in [(&grey, 16), (&rgb, 4)] {
        let gltf = asset(image, |_| {}).unwrap();
        assert_eq!(
            gltf.images[0].texels,
            AlphaTexels::Unorm8(vec![255; pixels])
        );
        assert_eq!(gltf.image_info[0].alpha, AlphaSource::One);
        assert_eq!(
            gltf.warnings,
            ["images[0] (uri \"a.png\") has no alpha channel: its alpha is 1 (glTF), so every texel is opaque"]
        );
        // The bake: opaque everywhere, as glTF says.
        let texture = gltf.images[0].texture().unwrap();
        let p = &gltf.primitives[0];
        let mesh = Mesh {
            triangles: MeshTriangles::Uv(&p.triangles),
            texture: &texture,
            material: p.material(),
            vertex_alpha: None,
        };
        let report = bake_mesh(&mesh, &fixed(3)).unwrap().report;
        assert_eq!(report.counts, [0, 128, 0, 0]);
        // A standalone mask (`--texture`) still reads its grey value.
        let mask = decode_alpha_image(image, &Limits::default()).unwrap();
        assert_eq!(
            mask.texels,
            AlphaTexels::Unorm8(vec![if pixels == 16 { 0 } else { 10 }; pixels])
        );
        let (_, source) =
            decode_image_alpha(image, &Limits::default(), MissingAlpha::Luminance).unwrap();
        assert_eq!(source, AlphaSource::Luminance);
    }
    // An image with alpha keeps it, without a note.
    let rgba = png(1, 1, png::ColorType::Rgba, &[9, 9, 9, 7]);
    let gltf = asset(&rgba, |_| {}).unwrap();
    assert_eq!(gltf.images[0].texels, AlphaTexels::Unorm8(vec![7]));
    assert_eq!(gltf.image_info[0].alpha, AlphaSource::Channel);
    assert!(gltf.warnings.is_empty());
}

fn fern_dir() -> &'static Path {
    Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/polyhaven-fern02"
    ))
}

/// Bakes every primitive of a fern glTF at level 2 (the four meshes
/// together); the micro-triangle counts.
fn bake_fern(gltf_name: &str, diffuse: &[u8]) -> [u64; 4] {
    let dir = fern_dir();
    let text = std::fs::read(dir.join(gltf_name)).unwrap();
    let mut resolve = |uri: &str| -> Result<Vec<u8>, AssetError> {
        if uri.starts_with("textures/fern_02_diff_1k") {
            Ok(diffuse.to_vec())
        } else {
            std::fs::read(dir.join(uri)).map_err(|e| AssetError::Io {
                path: uri.into(),
                message: e.to_string(),
            })
        }
    };
    let gltf = read_gltf_bytes(&text, &mut resolve, &Limits::default()).unwrap();
    let textures: Vec<_> = gltf.images.iter().map(|i| i.texture().unwrap()).collect();
    let mut counts = [0; 4];
    for p in &gltf.primitives {
        let mesh = Mesh {
            triangles: MeshTriangles::Uv(&p.triangles),
            texture: &textures[p.image],
            material: p.material(),
            vertex_alpha: p.vertex_alpha.as_deref(),
        };
        let report = bake_mesh(&mesh, &fixed(2)).unwrap().report;
        for (sum, c) in counts.iter_mut().zip(report.counts) {
            *sum += c;
        }
    }
    counts
}

#[test]
fn the_fern_as_published_bakes_opaque() {
    let rgba = std::fs::read(fern_dir().join("textures/fern_02_diff_1k.png")).unwrap();
    // The published glTF names an RGB JPEG; an RGB copy of the PNG (its
    // alpha dropped) stands in for it.
    let decoder = png::Decoder::new(std::io::Cursor::new(&rgba));
    let mut reader = decoder.read_info().unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgba);
    let rgb: Vec<u8> = pixels
        .chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    let rgb = png(info.width, info.height, png::ColorType::Rgb, &rgb);
    let published = bake_fern("fern_02_1k.original.gltf", &rgb);
    // 6,232 triangles at level 2: 99,712 micro-triangles, all opaque.
    assert_eq!(published, [0, 6232 * 16, 0, 0]);
    // The edited glTF names the PNG with its cut-out alpha: the bake has
    // transparent micro-triangles (a control: the test can fail).
    let cut_out = bake_fern("fern_02.gltf", &rgba);
    assert!(cut_out[0] > 10_000, "{cut_out:?}");
    assert_eq!(cut_out.iter().sum::<u64>(), 6232 * 16);
}

// ------------------------------------------------ baseColorFactor in binary32

/// The factor multiplies the texel's binary32 value in binary32, and the
/// texel's value is either faithful conversion of `c / 255` (Vulkan does
/// not promise the nearest): where both products fall on one side of the
/// cutoff the bake knows that side; where they straddle it, the state is
/// unknown (every product near the cutoff that differs from the exact
/// one's side does).
#[test]
fn the_alpha_factor_multiplies_in_binary32() {
    let cutoff = 0.5f32;
    // Codes and factors around the cutoff: the products of both
    // conversions, and whether they fall on different sides.
    let mut cases = Vec::new();
    for c in 1..=255u8 {
        let (lo, hi) = faithful_f32(f64::from(c) / 255.0);
        let guess = cutoff / hi;
        let mut f = f32::from_bits(guess.to_bits() - 4);
        for _ in 0..8 {
            if f <= 1.0 {
                let gpu = [lo * f >= cutoff, hi * f >= cutoff];
                let exact = f64::from(c) / 255.0 * f64::from(f) >= f64::from(cutoff);
                if gpu.contains(&!exact) {
                    assert_ne!(gpu[0], gpu[1], "code {c}, factor {f:e}");
                }
                cases.push((c, f, gpu));
            }
            f = f32::from_bits(f.to_bits() + 1);
        }
    }
    // Every kind occurs; where they straddle, one conversion's product
    // lies on the other side from the exact product's (a state an exact
    // or a nearest-only model would call known is wrong on some GPU).
    for kind in [[true, true], [false, false], [false, true]] {
        assert!(cases.iter().any(|&(_, _, g)| g == kind), "no case {kind:?}");
    }
    for (c, factor, gpu) in cases {
        let texels = [c; 4];
        let texture = Unorm8Texture::new(2, 2, &texels).unwrap();
        let triangle = [[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]];
        let mesh = Mesh {
            triangles: MeshTriangles::Uv(&triangle),
            texture: &texture,
            material: Material {
                alpha_factor: factor,
                uv_transform: micromap_index::bake::UvTransform::IDENTITY,
                ..Material::default()
            },
            vertex_alpha: None,
        };
        let counts = bake_mesh(&mesh, &fixed(2)).unwrap().report.counts;
        match gpu {
            [true, true] => assert_eq!(counts, [0, 16, 0, 0], "code {c}, factor {factor:e}"),
            [false, false] => assert_eq!(counts, [16, 0, 0, 0], "code {c}, factor {factor:e}"),
            _ => assert_eq!(counts[0] + counts[1], 0, "code {c}, factor {factor:e}"),
        }
    }
}

// ------------------------------------------------ texCoord

#[test]
fn tex_coord_picks_the_uv_set() {
    let rgba = png(1, 1, png::ColorType::Rgba, &[0, 0, 0, 255]);
    let half = [
        [[0.0, 0.0], [0.5, 0.0], [0.5, 0.5]],
        [[0.0, 0.0], [0.5, 0.5], [0.0, 0.5]],
    ];
    let whole = [
        [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]],
        [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
    ];
    let set = |edit: fn(&mut Value)| {
        let gltf = asset(&rgba, edit).unwrap();
        (
            gltf.primitives[0].tex_coord,
            gltf.primitives[0].triangles.clone(),
        )
    };
    assert_eq!(set(|_| {}), (0, whole.to_vec()));
    assert_eq!(
        set(
            |j| j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] =
                json!(1)
        ),
        (1, half.to_vec())
    );
    // KHR_texture_transform's texCoord overrides the texture info's.
    assert_eq!(
        set(|j| {
            let info = &mut j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"];
            info["texCoord"] = json!(1);
            info["extensions"] = json!({"KHR_texture_transform": {"texCoord": 0}});
        }),
        (0, whole.to_vec())
    );
}

// ------------------------------------------------ COLOR_0

/// The alpha a GPU computes at barycentrics `(b1, b2)` of `uv` with vertex
/// alphas `va`: texel (nearest, clamp to edge) of an `n x 1` texture, times
/// the factor, times the interpolated vertex alpha, all in binary32.
fn gpu_alpha(texels: &[u8], uv: &[[f32; 2]; 3], va: [f32; 3], factor: f32, b: (f32, f32)) -> f32 {
    let (b1, b2) = b;
    let w = 1.0 - b1 - b2;
    let u = w * uv[0][0] + b1 * uv[1][0] + b2 * uv[2][0];
    let n = texels.len();
    let x = ((u * n as f32).floor().max(0.0) as usize).min(n - 1);
    let t = f32::from(texels[x]) / 255.0;
    let v = w * va[0] + b1 * va[1] + b2 * va[2];
    t * factor * v
}

#[test]
fn vertex_alpha_multiplies_in_soundly() {
    // Left texel alpha 1, right texel 0.6; cutoff 0.5.
    let texels = [255u8, 153];
    let texture = Unorm8Texture::new(2, 1, &texels).unwrap();
    let quad = [
        [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]],
        [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
    ];
    // Triangle 0: 0.54 on the right, opaque. Triangle 1: at most 0.48 on
    // the right, transparent; at least 0.7 on the left, opaque.
    let alphas = [[0.9f32, 0.9, 0.9], [0.7, 0.75, 0.8]];
    let material = Material {
        sampler: Sampler {
            filter: Filter::Nearest,
            address_u: AddressMode::ClampToEdge,
            address_v: AddressMode::ClampToEdge,
            border_alpha: 0.0,
        },
        ..Material::default()
    };
    let level = Level::new(3).unwrap();
    let bake = |vertex_alpha| {
        let mesh = Mesh {
            triangles: MeshTriangles::Uv(&quad),
            texture: &texture,
            material,
            vertex_alpha,
        };
        bake_mesh(&mesh, &fixed(3)).unwrap()
    };
    let baked = bake(Some(&alphas));
    let plain = bake(None);
    let mut known = 0;
    for t in 0..quad.len() {
        let opacity = baked.opacity(0, t).unwrap();
        for i in 0..64u64 {
            let state = opacity.state(i).unwrap();
            let micro = micro_triangle(level, i).unwrap();
            let corners = micro.vertices_f64();
            let us: Vec<f64> = corners
                .iter()
                .map(|&(b1, b2)| {
                    let uv = &quad[t];
                    (1.0 - b1 - b2) * f64::from(uv[0][0])
                        + b1 * f64::from(uv[1][0])
                        + b2 * f64::from(uv[2][0])
                })
                .collect();
            let (min_u, max_u) = us
                .iter()
                .fold((2.0f64, -1.0f64), |(a, b), &u| (a.min(u), b.max(u)));
            // The expected state where the micro-triangle reads one texel.
            let expected = if max_u < 0.5 {
                Some(State::Opaque)
            } else if min_u > 0.5 {
                Some(if t == 0 {
                    State::Opaque
                } else {
                    State::Transparent
                })
            } else {
                None
            };
            if let Some(expected) = expected {
                assert_eq!(state, expected, "triangle {t} micro {i}");
                known += 1;
            }
            // No point of a known micro-triangle contradicts it: a dense
            // sampling of its barycentrics, corners and edges included.
            if state.is_known() {
                for j in 0..=8 {
                    for k in 0..=(8 - j) {
                        let (s, r) = (f64::from(j) / 8.0, f64::from(k) / 8.0);
                        let b1 = corners[0].0
                            + s * (corners[1].0 - corners[0].0)
                            + r * (corners[2].0 - corners[0].0);
                        let b2 = corners[0].1
                            + s * (corners[1].1 - corners[0].1)
                            + r * (corners[2].1 - corners[0].1);
                        let a =
                            gpu_alpha(&texels, &quad[t], alphas[t], 1.0, (b1 as f32, b2 as f32));
                        assert_eq!(
                            a >= 0.5,
                            state == State::Opaque,
                            "triangle {t} micro {i} at ({b1}, {b2})"
                        );
                    }
                }
            }
        }
    }
    assert!(known > 64, "{known}");
    // Without the vertex alpha, triangle 1's right side is opaque: the
    // vertex alpha changed it.
    assert!(plain.report.counts[State::Transparent.bits() as usize] == 0);
    assert!(baked.report.counts[State::Transparent.bits() as usize] > 0);
    // A triangle whose vertex alpha crosses the cutoff over a texel is
    // unknown there, never known.
    let mixed = [[0.2f32, 0.9, 0.9], [0.2, 0.9, 0.9]];
    let report = bake(Some(&mixed)).report;
    let unknown = report.counts[State::UnknownOpaque.bits() as usize]
        + report.counts[State::UnknownTransparent.bits() as usize];
    assert_eq!(unknown, 128, "{:?}", report.counts);
}

#[test]
fn vertex_alpha_is_read_from_color_0_and_checked() {
    let rgba = png(1, 1, png::ColorType::Rgba, &[0, 0, 0, 255]);
    let gltf = asset(&rgba, |j| {
        j["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = json!(3);
    })
    .unwrap();
    let a = |c: u8| f32::from(c) / 255.0;
    assert_eq!(
        gltf.primitives[0].vertex_alpha,
        Some(vec![[a(51), a(102), a(204)], [a(51), a(204), a(255)]])
    );
    assert_eq!(
        gltf.warnings,
        ["1 primitive has COLOR_0 alpha, multiplied in with bounds per triangle (texels near the cutoff may bake unknown): meshes[0].primitives[0]"]
    );
    // VEC3: alpha 1, nothing to apply.
    let gltf = asset(&rgba, |j| {
        j["accessors"][3]["type"] = json!("VEC3");
        j["accessors"][3]["count"] = json!(4);
        j["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = json!(3);
    })
    .unwrap();
    assert_eq!(gltf.primitives[0].vertex_alpha, None);
    // Refused: a type that is not a colour, float values outside [0, 1].
    let error = asset(&rgba, |j| {
        j["accessors"][3]["normalized"] = json!(false);
        j["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = json!(3);
    })
    .unwrap_err()
    .to_string();
    assert!(
        error.contains("5121 (UNSIGNED_BYTE) is not a vertex colour type"),
        "{error}"
    );
    let error = asset(&rgba, |j| {
        j["accessors"][3] =
            json!({"bufferView": 0, "componentType": 5126, "count": 2, "type": "VEC4"});
        j["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = json!(3);
    })
    .unwrap_err()
    .to_string();
    // Vertices 0 and 1 as floats: (0, 0, 1, 0) and (1, 1, 0, 1): fine; the
    // indices then run past the 2 colours.
    assert!(error.contains("past the 2 colours"), "{error}");
    // The mesh bake checks its input too.
    let texels = [255u8];
    let texture = Unorm8Texture::new(1, 1, &texels).unwrap();
    let triangle = [[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]];
    let mesh = |vertex_alpha| Mesh {
        triangles: MeshTriangles::Uv(&triangle),
        texture: &texture,
        material: Material::default(),
        vertex_alpha,
    };
    for (alphas, message) in [
        (
            &[[0.5f32, 1.5, 0.5]][..],
            "mesh 0: vertex alpha: triangle 0 has vertex alpha 1.5, outside [0, 1]",
        ),
        (
            &[[0.5, f32::NAN, 0.5]][..],
            "mesh 0: vertex alpha: triangle 0 has vertex alpha NaN, outside [0, 1]",
        ),
        (&[][..], "mesh 0: vertex alpha: 0 entries for 1 triangles"),
    ] {
        let error = bake_mesh(&mesh(Some(alphas)), &fixed(1)).unwrap_err();
        assert!(matches!(error, MeshBakeError::VertexAlpha { .. }));
        assert_eq!(error.to_string(), message);
    }
}

// ------------------------------------------------ KHR_texture_transform

fn with_transform(transform: Value) -> impl FnOnce(&mut Value) {
    move |j: &mut Value| {
        j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] =
            json!({"KHR_texture_transform": transform});
    }
}

#[test]
fn texture_transform_is_read_and_modelled() {
    // 4 x 1: opaque in the left texel only.
    let rgba = png(
        4,
        1,
        png::ColorType::Rgba,
        &[0, 0, 0, 255, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
    );
    let gltf = asset(
        &rgba,
        with_transform(json!({"scale": [0.5, 0.5], "offset": [0.25, 0]})),
    )
    .unwrap();
    let stored: Vec<[[f32; 2]; 3]> = vec![
        [[0.0f32, 0.0], [1.0, 0.0], [1.0, 1.0]],
        [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
    ];
    // The triangles as stored; the transform beside them.
    let primitive = &gltf.primitives[0];
    assert_eq!(primitive.triangles, stored);
    assert_eq!(
        primitive.uv_transform,
        UvTransform::new([0.25, 0.0], 0.0, [0.5, 0.5]).unwrap()
    );
    // Scale first, then offset, computed here.
    let expected: Vec<[[f32; 2]; 3]> = stored
        .iter()
        .map(|t| t.map(|[u, v]| [u * 0.5 + 0.25, v * 0.5]))
        .collect();
    assert_eq!(primitive.placed_triangles(), expected);
    assert!(gltf
        .warnings
        .iter()
        .any(|w| w.contains("KHR_texture_transform: modelled as the shader applies it")));
    // The bake reads u in [0.25, 0.75]: texels 1 and 2, both transparent;
    // untransformed it would see the opaque texel 0.
    let texture = gltf.images[0].texture().unwrap();
    let bake_as = |primitive: &micromap_index_assets::MaskPrimitive, model| {
        let mesh = Mesh {
            triangles: MeshTriangles::Uv(&primitive.triangles),
            texture: &texture,
            material: primitive.material(),
            vertex_alpha: None,
        };
        let options = MeshOptions { model, ..fixed(2) };
        bake_mesh(&mesh, &options).unwrap().report.counts
    };
    let (exact, gpu) = (Model::Exact, Model::GpuBinary32);
    assert_eq!(bake_as(primitive, exact), [32, 0, 0, 0]);
    // The GPU model: the 8 micro-triangles on the texel boundary u' = 1/4
    // are unknown (a binary32 hit there may round into texel 0).
    assert_eq!(bake_as(primitive, gpu), [24, 0, 8, 0]);
    // A rotation, and values no binary32 sum holds exactly, are read and
    // modelled (issue 34): a quarter turn of the square scaled by 0.1 and
    // moved by the offset lands at u' in [0.605, 0.705], away from the
    // opaque texel.
    let turned = asset(
        &rgba,
        with_transform(
            json!({"rotation": std::f32::consts::FRAC_PI_2, "offset": [0.705, 0.285], "scale": [0.1, 0.1]}),
        ),
    )
    .unwrap();
    assert!(turned.refused.is_empty());
    let t = &turned.primitives[0];
    assert_eq!(t.uv_transform.rotation(), std::f32::consts::FRAC_PI_2);
    for (placed, source) in t.placed_triangles().iter().zip(&t.triangles) {
        for (p, [u, v]) in placed.iter().zip(source) {
            // offset + R (scale uv) with R a quarter turn: (-0.1 v, 0.1 u).
            assert!((p[0] - (0.705 - 0.1 * v)).abs() < 1e-6, "{p:?}");
            assert!((p[1] - (0.285 + 0.1 * u)).abs() < 1e-6, "{p:?}");
        }
    }
    // u' in [0.605, 0.705]: texels 1..=3 under linear filtering, all
    // transparent. The exact model cannot place vertices whose images are
    // not binary32: unknown-opaque (sound).
    assert_eq!(bake_as(t, gpu), [32, 0, 0, 0]);
    assert_eq!(bake_as(t, exact), [0, 0, 0, 32]);
    // Well-formed but not modelled: a rotation beyond 65536 radians. The
    // primitive is refused (listed with its reason, the field named), the
    // asset still reads.
    let read = asset(&rgba, with_transform(json!({"rotation": 1e6}))).unwrap();
    assert!(read.primitives.is_empty());
    assert_eq!(read.refused.len(), 1);
    let refused = &read.refused[0];
    assert_eq!((refused.mesh, refused.primitive), (0, 0));
    let reason = refused.reason.to_string();
    assert!(
        reason.starts_with("materials[0].pbrMetallicRoughness.baseColorTexture.extensions.KHR_texture_transform: texture transform rotation 1000000: expected at most 65536 radians in magnitude, refused"),
        "{reason}"
    );
    // Malformed: an error, with the field named.
    for (transform, message) in [
        (
            json!({"scale": [1]}),
            "materials[0].pbrMetallicRoughness.baseColorTexture.extensions.KHR_texture_transform.scale: an array [1], expected an array of 2 numbers",
        ),
        (
            json!({"offset": ["a", 0]}),
            "materials[0].pbrMetallicRoughness.baseColorTexture.extensions.KHR_texture_transform.offset: an array [\"a\",0], expected a finite number",
        ),
    ] {
        let error = asset(&rgba, with_transform(transform)).unwrap_err().to_string();
        assert!(error.starts_with(message), "{error}");
    }
    // Required, and modelled: read. Required and not modelled: refused.
    let gltf = asset(&rgba, |j| {
        with_transform(json!({"scale": [0.5, 0.5]}))(j);
        j["extensionsUsed"] = json!(["KHR_texture_transform"]);
        j["extensionsRequired"] = json!(["KHR_texture_transform"]);
    });
    assert!(gltf.is_ok());
    let error = asset(&rgba, |j| {
        j["extensionsRequired"] = json!(["KHR_texture_basisu"]);
    })
    .unwrap_err()
    .to_string();
    assert!(
        error.contains("requires extension KHR_texture_basisu, which is not supported"),
        "{error}"
    );
}
