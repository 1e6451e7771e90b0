//! The glTF that `write_gltf_micromaps` writes, checked against the
//! `EXT_mesh_opacity_micromap` draft (KhronosGroup/glTF pull request 2623,
//! newest text 4b95e4d3, summarised in `../shared/gltf-micromap-extension.md`)
//! by a checker written here from the draft's text, on `serde_json::Value`
//! and raw bytes: it shares no code with the writer or with the crate's
//! reader. Then: the rest of the asset is kept, the micromaps decode to
//! what was baked, the reader reads it back, and what the draft forbids is
//! refused by the writer and the reader with typed errors.

use micromap_index::bake::mesh::{bake_meshes, LevelRule, Mesh, MeshOptions, MeshTriangles};
use micromap_index::micromap::BakedOpacity;
use micromap_index::micromap::{
    BuildOptions, Format, Micromap, MicromapBuffers, MicromapIndex, State, TriangleOpacity,
};
use micromap_index::Level;
use micromap_index_assets::{
    read_gltf_bytes, read_gltf_micromaps, write_gltf_micromaps, AssetError, GltfContainer,
    GltfFiles, GltfMicromapWrite, Limits,
};
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::path::Path;

const EXT: &str = "EXT_mesh_opacity_micromap";

fn sponza(name: &str) -> Vec<u8> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/crytek-sponza");
    std::fs::read(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[allow(clippy::unnecessary_wraps)] // a resolver's signature
fn resolve_sponza(uri: &str) -> Result<Vec<u8>, AssetError> {
    Ok(sponza(uri))
}

/// The parts of a GLB, checked against the core rules: header length,
/// JSON chunk first, chunk lengths multiples of 4.
fn split_glb(bytes: &[u8]) -> (Value, Option<Vec<u8>>) {
    let u32_at = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    assert_eq!(&bytes[0..4], b"glTF");
    assert_eq!(u32_at(4), 2, "GLB version");
    assert_eq!(u32_at(8), bytes.len(), "GLB header length");
    let mut at = 12;
    let mut chunks = Vec::new();
    while at < bytes.len() {
        let (length, kind) = (u32_at(at), u32_at(at + 4));
        assert_eq!(length % 4, 0, "GLB chunk {} length {length}", chunks.len());
        chunks.push((kind, bytes[at + 8..at + 8 + length].to_vec()));
        at += 8 + length;
    }
    assert_eq!(chunks[0].0, 0x4E4F_534A, "the first chunk is JSON");
    let json = serde_json::from_slice(&chunks[0].1).expect("the JSON chunk parses");
    let bin = chunks
        .iter()
        .find(|(kind, _)| *kind == 0x004E_4942)
        .map(|(_, b)| b.clone());
    (json, bin)
}

/// A written glTF as the checker sees it: its JSON and every buffer's bytes.
struct Written {
    json: Value,
    buffers: Vec<Vec<u8>>,
}

fn open(files: &GltfFiles, container: &GltfContainer) -> Written {
    let (json, bin) = match container {
        GltfContainer::Glb => split_glb(&files.main),
        GltfContainer::Json { .. } => (serde_json::from_slice(&files.main).unwrap(), None),
    };
    let buffers = json["buffers"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
        .map(|(b, buffer)| {
            let length = buffer["byteLength"].as_u64().unwrap() as usize;
            let mut bytes = match buffer["uri"].as_str() {
                None => {
                    assert_eq!(b, 0, "only buffer 0 may lack a uri (the BIN chunk)");
                    bin.clone().expect("a BIN chunk for buffer 0")
                }
                // Every output stands alone: a URI names one of its files.
                Some(uri) => match files.sidecars.iter().find(|(name, _)| percent(name) == uri) {
                    Some((_, bytes)) => bytes.clone(),
                    None => panic!("buffers[{b}].uri {uri:?} leads out of the output's files"),
                },
            };
            assert!(
                bytes.len() >= length,
                "buffers[{b}] shorter than byteLength"
            );
            bytes.truncate(length);
            bytes
        })
        .collect();
    Written { json, buffers }
}

impl Written {
    /// The bytes of buffer view `v`, checked inside its buffer; `tight`:
    /// the draft forbids `byteStride` on it.
    fn view(&self, v: &Value, tight: bool) -> Vec<u8> {
        let view = &self.json["bufferViews"][v.as_u64().expect("a bufferView index") as usize];
        assert!(view.is_object(), "bufferView {v} exists");
        if tight {
            assert!(
                view.get("byteStride").is_none(),
                "bufferView {v}: byteStride"
            );
        }
        let buffer = &self.buffers[view["buffer"].as_u64().unwrap() as usize];
        let offset = view.get("byteOffset").and_then(Value::as_u64).unwrap_or(0) as usize;
        let length = view["byteLength"].as_u64().unwrap() as usize;
        assert!(length >= 1, "bufferView {v}: byteLength minimum 1");
        assert!(
            offset + length <= buffer.len(),
            "bufferView {v} past its buffer"
        );
        buffer[offset..offset + length].to_vec()
    }
}

/// A record: `{u32 dataOffset, u16 subdivisionLevel, u16 format}`.
struct Record {
    offset: usize,
    level: u32,
    format: u32,
}

/// Every rule of the draft an exporter must meet; returns, per primitive
/// with the extension, `(mesh, primitive)` and each triangle's record
/// (`Err(state bits)` for a special index).
#[allow(clippy::type_complexity)]
fn check_draft(
    w: &Written,
) -> (
    Vec<Vec<Record>>,
    Vec<((usize, usize), Vec<Result<usize, u8>>)>,
) {
    let j = &w.json;
    let used: Vec<&str> = j["extensionsUsed"]
        .as_array()
        .expect("extensionsUsed")
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert!(used.contains(&EXT), "extensionsUsed lists {EXT}");
    if let Some(required) = j.get("extensionsRequired") {
        assert!(
            !required.as_array().unwrap().iter().any(|v| v == EXT),
            "{EXT} SHOULD NOT be required"
        );
        assert!(!required.as_array().unwrap().is_empty(), "minItems 1");
    }
    let micromaps = j["extensions"][EXT]["micromaps"]
        .as_array()
        .expect("root micromaps");
    assert!(!micromaps.is_empty(), "micromaps minItems 1");
    let mut all_records = Vec::new();
    for (i, m) in micromaps.iter().enumerate() {
        let counts = m["usageCounts"].as_array().expect("usageCounts");
        let levels = m["usageLevels"].as_array().expect("usageLevels");
        let formats = m["usageFormats"].as_array().expect("usageFormats");
        assert!(!counts.is_empty(), "micromap {i}: usage minItems 1");
        assert_eq!(counts.len(), levels.len(), "micromap {i}: usage lengths");
        assert_eq!(counts.len(), formats.len(), "micromap {i}: usage lengths");
        let mut declared: BTreeMap<(u64, u64), u64> = BTreeMap::new();
        for k in 0..counts.len() {
            let (c, l, f) = (
                counts[k].as_u64().unwrap(),
                levels[k].as_u64().unwrap(),
                formats[k].as_u64().unwrap(),
            );
            assert!(c >= 1, "usageCounts[{k}] minimum 1");
            assert!(l <= 12, "usageLevels[{k}] = {l}, maximum 12");
            assert!(f == 1 || f == 2, "usageFormats[{k}] = {f}");
            *declared.entry((l, f)).or_default() += c;
        }
        let data = w.view(&m["data"], true);
        let triangles = w.view(&m["triangles"], true);
        assert_eq!(triangles.len() % 8, 0, "triangles byteLength multiple of 8");
        let records: Vec<Record> = triangles
            .chunks_exact(8)
            .map(|r| Record {
                offset: u32::from_le_bytes(r[0..4].try_into().unwrap()) as usize,
                level: u32::from(u16::from_le_bytes([r[4], r[5]])),
                format: u32::from(u16::from_le_bytes([r[6], r[7]])),
            })
            .collect();
        let mut actual: BTreeMap<(u64, u64), u64> = BTreeMap::new();
        let mut regions = Vec::new();
        for (r, rec) in records.iter().enumerate() {
            assert!(rec.level <= 12, "record {r}: level {}", rec.level);
            assert!(rec.format == 1 || rec.format == 2, "record {r}: format");
            *actual
                .entry((u64::from(rec.level), u64::from(rec.format)))
                .or_default() += 1;
            let bits = (1u64 << (2 * rec.level)) * u64::from(rec.format);
            let len = bits.div_ceil(8) as usize;
            assert!(
                rec.offset + len <= data.len(),
                "record {r}: region past data"
            );
            regions.push((rec.offset, rec.offset + len));
        }
        assert_eq!(declared, actual, "micromap {i}: usage per (level, format)");
        regions.sort_unstable();
        for pair in regions.windows(2) {
            assert!(pair[0].1 <= pair[1].0, "regions {pair:?} overlap");
        }
        all_records.push(records);
    }

    let mut primitives = Vec::new();
    for (mi, mesh) in j["meshes"].as_array().unwrap().iter().enumerate() {
        for (pi, p) in mesh["primitives"].as_array().unwrap().iter().enumerate() {
            let Some(e) = p.get("extensions").and_then(|e| e.get(EXT)) else {
                continue;
            };
            assert_eq!(
                p.get("mode").and_then(Value::as_u64).unwrap_or(4),
                4,
                "mode"
            );
            let m = e["micromap"].as_u64().expect("micromap is required") as usize;
            let records = &all_records[m];
            let base = e
                .get("micromapBaseTriangle")
                .map_or(0, |b| b.as_u64().expect("micromapBaseTriangle >= 0"))
                as usize;
            let count_accessor = p
                .get("indices")
                .unwrap_or(&p["attributes"]["POSITION"])
                .as_u64()
                .unwrap() as usize;
            let triangles = j["accessors"][count_accessor]["count"].as_u64().unwrap() as usize / 3;
            let uses: Vec<Result<usize, u8>> = match e.get("micromapIndices") {
                None => {
                    assert!(
                        triangles + base <= records.len(),
                        "records >= triangles + base"
                    );
                    (0..triangles).map(|t| Ok(t + base)).collect()
                }
                Some(a) => {
                    let acc = &j["accessors"][a.as_u64().unwrap() as usize];
                    assert_eq!(acc["type"], "SCALAR");
                    assert_ne!(acc.get("normalized"), Some(&Value::Bool(true)));
                    assert_eq!(acc["count"].as_u64().unwrap() as usize, triangles, "count");
                    let ct = acc["componentType"].as_u64().unwrap();
                    let (size, signed) = match ct {
                        5121 => (1, false),
                        5123 => (2, false),
                        5125 => (4, false),
                        5122 => (2, true),
                        5124 => (4, true),
                        other => panic!("componentType {other}"),
                    };
                    let view = &j["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
                    let view_offset = view.get("byteOffset").and_then(Value::as_u64).unwrap_or(0);
                    let offset = acc.get("byteOffset").and_then(Value::as_u64).unwrap_or(0);
                    assert_eq!(view_offset % size as u64, 0, "view offset alignment");
                    assert_eq!(offset % size as u64, 0, "accessor offset alignment");
                    let bytes = w.view(&acc["bufferView"], true);
                    let bits = 8 * size as u32;
                    (0..triangles)
                        .map(|t| {
                            let at = offset as usize + t * size;
                            let mut raw = [0u8; 8];
                            raw[..size].copy_from_slice(&bytes[at..at + size]);
                            let raw = u64::from_le_bytes(raw);
                            let value: i64 = if signed {
                                let shift = 64 - bits;
                                ((raw << shift) as i64) >> shift
                            } else if raw >= (1u64 << bits) - 4 {
                                raw as i64 - (1i64 << bits)
                            } else {
                                raw as i64
                            };
                            assert!(value >= -4, "triangle {t}: value {value}");
                            if value < 0 {
                                Err((-value - 1) as u8)
                            } else {
                                let r = value as usize + base;
                                assert!(r < records.len(), "triangle {t}: record {r}");
                                Ok(r)
                            }
                        })
                        .collect()
                }
            };
            primitives.push(((mi, pi), uses));
        }
    }
    (all_records, primitives)
}

/// The micro-triangle states of record `r` (`format` bits each, LSB first).
fn states(w: &Written, micromap: usize, rec: &Record) -> Vec<u8> {
    let m = &w.json["extensions"][EXT]["micromaps"][micromap];
    let data = w.view(&m["data"], true);
    let b = rec.format as usize;
    (0..1usize << (2 * rec.level))
        .map(|i| {
            let bit = i * b;
            (data[rec.offset + bit / 8] >> (bit % 8)) & ((1u8 << b) - 1)
        })
        .collect()
}

fn bake(
    input: &[u8],
    level: Option<u32>,
    format: Format,
) -> (MicromapBuffers, Vec<(usize, usize)>) {
    let asset = read_gltf_bytes(input, &mut resolve_sponza, &Limits::default()).unwrap();
    let textures: Vec<_> = asset.images.iter().map(|i| i.texture().unwrap()).collect();
    let meshes: Vec<Mesh<'_>> = asset
        .primitives
        .iter()
        .map(|p| Mesh {
            triangles: MeshTriangles::Uv(&p.triangles),
            texture: &textures[p.image],
            material: p.material(),
            vertex_alpha: p.vertex_alpha.as_deref(),
        })
        .collect();
    let options = MeshOptions {
        levels: match level {
            Some(l) => LevelRule::Fixed(Level::new(l).unwrap()),
            None => LevelRule::Useful {
                max: Level::new(7).unwrap(),
            },
        },
        format,
        ..MeshOptions::default()
    };
    let baked = bake_meshes(&meshes, &options, &mut |_, _| {}).unwrap();
    let prims = asset
        .primitives
        .iter()
        .map(|p| (p.mesh, p.primitive))
        .collect();
    (baked.buffers, prims)
}

fn input_json(input: &[u8]) -> Value {
    if input.starts_with(b"glTF") {
        split_glb(input).0
    } else {
        serde_json::from_slice(input).unwrap()
    }
}

/// Everything the writer does not own is unchanged; the output (`.glb`
/// or `.gltf`) holds the input's images as views of their very bytes.
fn check_kept(input: &Value, written: &Written) {
    let output = &written.json;
    for (key, value) in input.as_object().unwrap() {
        match key.as_str() {
            "images" => {
                for (i, image) in value.as_array().unwrap().iter().enumerate() {
                    let out = &output["images"][i];
                    let Some(uri) = image.get("uri").and_then(Value::as_str) else {
                        assert_eq!(out, image, "images[{i}] kept");
                        continue;
                    };
                    assert_eq!(
                        written.view(&out["bufferView"], false),
                        sponza(uri),
                        "images[{i}]"
                    );
                    assert_eq!(out["mimeType"], "image/png", "images[{i}]");
                    let mut rest = out.clone();
                    let rest = rest.as_object_mut().unwrap();
                    rest.remove("bufferView");
                    rest.remove("mimeType");
                    let mut kept = image.clone();
                    kept.as_object_mut().unwrap().remove("uri");
                    assert_eq!(&Value::Object(rest.clone()), &kept, "images[{i}] kept");
                }
            }
            "meshes" => {
                for (m, mesh) in value.as_array().unwrap().iter().enumerate() {
                    for (p, prim) in mesh["primitives"].as_array().unwrap().iter().enumerate() {
                        let mut out = output["meshes"][m]["primitives"][p].clone();
                        if let Some(ext) = out.get_mut("extensions").and_then(Value::as_object_mut)
                        {
                            ext.remove(EXT);
                            if ext.is_empty() {
                                out.as_object_mut().unwrap().remove("extensions");
                            }
                        }
                        assert_eq!(&out, prim, "meshes[{m}].primitives[{p}]");
                    }
                }
            }
            "accessors" | "bufferViews" => {
                let out = output[key].as_array().unwrap();
                for (i, item) in value.as_array().unwrap().iter().enumerate() {
                    assert_eq!(&out[i], item, "{key}[{i}] kept");
                }
            }
            "buffers" | "extensionsUsed" | "extensions" => {}
            _ => assert_eq!(&output[key], value, "{key} kept"),
        }
    }
}

fn write(
    input: &[u8],
    buffers: &MicromapBuffers,
    prims: &[(usize, usize)],
    c: &GltfContainer,
) -> GltfFiles {
    let w = GltfMicromapWrite {
        buffers,
        primitives: prims,
    };
    write_gltf_micromaps(input, &mut resolve_sponza, &w, c).unwrap()
}

#[test]
fn written_gltf_meets_the_draft_and_keeps_the_asset() {
    let containers = [
        GltfContainer::Glb,
        GltfContainer::Json {
            stem: "out put".into(),
        },
    ];
    for input_name in ["cards.gltf", "cards.glb"] {
        let input = sponza(input_name);
        for (level, format) in [
            (Some(3), Format::FourState),
            (None, Format::TwoState),
            (Some(0), Format::FourState),
        ] {
            let (buffers, prims) = bake(&input, level, format);
            for c in &containers {
                let what = format!("{input_name} level {level:?} {format:?} as {c:?}");
                let files = write(&input, &buffers, &prims, c);
                let w = open(&files, c);
                let (records, primitives) = check_draft(&w);
                check_kept(&input_json(&input), &w);
                assert_eq!(records.len(), 1, "{what}");
                assert_eq!(
                    primitives.len(),
                    prims.len(),
                    "{what}: every baked primitive"
                );
                // What the file says is what was baked.
                for (g, ((m, p), uses)) in primitives.iter().enumerate() {
                    assert_eq!((*m, *p), prims[g], "{what}");
                    let baked = buffers.geometry_indices(g).unwrap();
                    for (t, (u, b)) in uses.iter().zip(baked).enumerate() {
                        match (u, b) {
                            (Err(bits), MicromapIndex::Special(s)) => assert_eq!(*bits, s.bits()),
                            (Ok(r), MicromapIndex::Record(_)) => {
                                let Some(BakedOpacity::Map(map)) = buffers.resolve(g, t) else {
                                    panic!("{what}: triangle {t}")
                                };
                                let expected: Vec<u8> = map.states().map(State::bits).collect();
                                let stored = states(&w, 0, &records[0][*r]);
                                let expected: Vec<u8> = match format {
                                    Format::FourState => expected,
                                    Format::TwoState => expected.iter().map(|s| s & 1).collect(),
                                };
                                assert_eq!(stored, expected, "{what}: triangle {t}");
                            }
                            other => panic!("{what}: triangle {t}: {other:?}"),
                        }
                    }
                }
                // The crate's reader agrees, and the asset still reads.
                let mut resolve = |uri: &str| {
                    Ok(
                        match files
                            .sidecars
                            .iter()
                            .find(|(n, _)| percent(n) == uri || n == uri)
                        {
                            Some((_, b)) => b.clone(),
                            None => sponza(uri),
                        },
                    )
                };
                let read = read_gltf_micromaps(&files.main, &mut resolve, &Limits::default())
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                assert_eq!(read.primitives.len(), prims.len());
                for (g, found) in read.primitives.iter().enumerate() {
                    for t in 0..found.indices.len() {
                        let ours = buffers.resolve(g, t);
                        assert_eq!(
                            read.opacity(found, t),
                            ours.as_ref().map(BakedOpacity::as_opacity),
                            "{what}"
                        );
                    }
                }
                let again = read_gltf_bytes(&files.main, &mut resolve, &Limits::default()).unwrap();
                assert_eq!(again.primitives.len(), prims.len(), "{what}");
                // A .glb stands alone: it reads with no file beside it.
                if *c == GltfContainer::Glb {
                    let mut nothing = |uri: &str| -> Result<Vec<u8>, AssetError> {
                        panic!("{what}: the .glb names {uri:?}")
                    };
                    let alone = read_gltf_bytes(&files.main, &mut nothing, &Limits::default())
                        .unwrap_or_else(|e| panic!("{what}: {e}"));
                    assert_eq!(alone.primitives.len(), prims.len(), "{what}");
                    assert_eq!(alone.images, again.images, "{what}: the same texels");
                }
            }
        }
    }
}

fn percent(name: &str) -> String {
    name.replace(' ', "%20")
}

/// One triangle, `POSITION` only: the smallest asset a primitive can be.
fn one_triangle(extra: &Value) -> Vec<u8> {
    let mut j = json!({
        "asset": {"version": "2.0"},
        "accessors": [{"count": 3, "componentType": 5126, "type": "VEC3"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    });
    for (k, v) in extra.as_object().unwrap() {
        j[k] = v.clone();
    }
    serde_json::to_vec(&j).unwrap()
}

#[test]
fn all_special_bake_gets_one_record_and_the_rest_is_kept() {
    let input = one_triangle(&json!({
        "extensionsRequired": [EXT],
        "extensionsUsed": [EXT, "KHR_other"],
        "materials": [{"alphaCutoff": 0.3}],
    }));
    let buffers = MicromapBuffers::build(
        [TriangleOpacity::Special(State::Opaque)],
        BuildOptions::default(),
    )
    .unwrap();
    // serde_json would round the text; the input keeps it.
    let input = String::from_utf8(input)
        .unwrap()
        .replace("\"alphaCutoff\":0.3", "\"alphaCutoff\":0.30000000000000001")
        .into_bytes();
    for c in [GltfContainer::Glb, GltfContainer::Json { stem: "a".into() }] {
        let files = write(&input, &buffers, &[(0, 0)], &c);
        let w = open(&files, &c);
        let (records, primitives) = check_draft(&w);
        assert_eq!(records[0].len(), 1, "one level-0 record for the minItems");
        assert_eq!(primitives[0].1, [Err(State::Opaque.bits())]);
        assert!(
            w.json.get("extensionsRequired").is_none(),
            "{EXT} no longer required"
        );
        assert_eq!(w.json["extensionsUsed"], json!([EXT, "KHR_other"]));
        // The decimal text of alphaCutoff is copied, never re-rounded.
        let text = match c {
            GltfContainer::Glb => String::from_utf8_lossy(&files.main).into_owned(),
            GltfContainer::Json { .. } => String::from_utf8(files.main.clone()).unwrap(),
        };
        assert!(text.contains("0.30000000000000001"), "{text}");
    }
}

#[test]
fn consecutive_records_need_no_index_accessor() {
    let input = sponza("cards.gltf");
    let (buffers, prims) = bake(&input, Some(3), Format::FourState);
    let c = GltfContainer::Glb;
    let w = open(&write(&input, &buffers, &prims, &c), &c);
    let (_, primitives) = check_draft(&w);
    let mut without = 0;
    for (m, mesh) in w.json["meshes"].as_array().unwrap().iter().enumerate() {
        for (p, prim) in mesh["primitives"].as_array().unwrap().iter().enumerate() {
            let e = &prim["extensions"][EXT];
            if e.get("micromapIndices").is_none() {
                without += 1;
                let uses = &primitives.iter().find(|(k, _)| *k == (m, p)).unwrap().1;
                let base = e
                    .get("micromapBaseTriangle")
                    .and_then(Value::as_u64)
                    .unwrap_or(0) as usize;
                assert!(uses.iter().enumerate().all(|(t, u)| *u == Ok(t + base)));
            } else {
                // The narrowest width: u8 while every record fits.
                let a = e["micromapIndices"].as_u64().unwrap() as usize;
                assert_eq!(w.json["accessors"][a]["componentType"], 5121);
            }
        }
    }
    assert!(
        without > 0,
        "cards has primitives whose records are consecutive"
    );
}

#[test]
fn writer_refuses_what_the_draft_forbids() {
    let input = one_triangle(&json!({}));
    let map13 = Micromap::new(Level::new(13).unwrap(), Format::TwoState).unwrap();
    let mut map13 = map13;
    map13.set(0, State::Opaque).unwrap();
    let high = MicromapBuffers::build([TriangleOpacity::Micromap(&map13)], BuildOptions::default())
        .unwrap();
    let special = MicromapBuffers::build(
        [TriangleOpacity::Special(State::Opaque)],
        BuildOptions::default(),
    )
    .unwrap();
    let two = MicromapBuffers::build(
        [
            TriangleOpacity::Special(State::Opaque),
            TriangleOpacity::Special(State::Opaque),
        ],
        BuildOptions::default(),
    )
    .unwrap();
    let attempt = |input: &[u8], buffers: &MicromapBuffers, prims: &[(usize, usize)]| {
        let w = GltfMicromapWrite {
            buffers,
            primitives: prims,
        };
        write_gltf_micromaps(input, &mut resolve_sponza, &w, &GltfContainer::Glb)
            .unwrap_err()
            .to_string()
    };
    assert!(attempt(&input, &high, &[(0, 0)]).contains("level 13"));
    assert!(attempt(&input, &special, &[(1, 0)]).contains("meshes[1]: does not exist"));
    assert!(attempt(&input, &special, &[]).contains("1 geometries for 0 primitives"));
    assert!(attempt(&input, &two, &[(0, 0)]).contains("1 triangles, but its geometry has 2"));
    let lines = one_triangle(
        &json!({"meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "mode": 1}]}]}),
    );
    assert!(attempt(&lines, &special, &[(0, 0)]).contains("TRIANGLES (4) only"));
    assert!(attempt(b"{\"a\": 1, \"a\": 2}", &special, &[(0, 0)]).contains("duplicate member"));
}

/// A level-2 map (4 bytes of data).
fn level2() -> Micromap {
    Micromap::from_states(
        Level::new(2).unwrap(),
        Format::FourState,
        State::ALL.into_iter().cycle().take(16),
    )
    .unwrap()
}

/// A `.gltf` of one triangle with a level-2 micromap, for the reader's cases.
fn written_glb() -> Value {
    let input = one_triangle(&json!({}));
    let map = level2();
    let buffers =
        MicromapBuffers::build([TriangleOpacity::Micromap(&map)], BuildOptions::default()).unwrap();
    let files = write(
        &input,
        &buffers,
        &[(0, 0)],
        &GltfContainer::Json { stem: "m".into() },
    );
    assert_eq!(files.sidecars.len(), 1);
    serde_json::from_slice(&files.main).unwrap()
}

/// An edit of the JSON.
type Edit = Box<dyn Fn(&mut Value)>;

#[test]
fn reader_refuses_each_malformed_case_with_a_typed_error() {
    let base = written_glb();
    let input = one_triangle(&json!({}));
    let map = level2();
    let buffers =
        MicromapBuffers::build([TriangleOpacity::Micromap(&map)], BuildOptions::default()).unwrap();
    let sidecar = write(
        &input,
        &buffers,
        &[(0, 0)],
        &GltfContainer::Json { stem: "m".into() },
    )
    .sidecars
    .remove(0)
    .1;
    let read = |j: &Value| {
        let mut resolve = |_: &str| Ok(sidecar.clone());
        read_gltf_micromaps(
            &serde_json::to_vec(j).unwrap(),
            &mut resolve,
            &Limits::default(),
        )
    };
    read(&base).expect("the unedited file reads");
    let ext = format!("/extensions/{EXT}/micromaps/0");
    let prim = format!("/meshes/0/primitives/0/extensions/{EXT}");
    let cases: Vec<(&str, Edit, &str)> = vec![
        (
            "not in extensionsUsed",
            Box::new(|j| j["extensionsUsed"] = json!([])),
            "extensionsUsed does not list",
        ),
        (
            "no micromaps",
            Box::new(|j| j["extensions"][EXT]["micromaps"] = json!([])),
            "at least one micromap",
        ),
        (
            "usage level 13",
            Box::new({
                let e = ext.clone();
                move |j| *j.pointer_mut(&format!("{e}/usageLevels/0")).unwrap() = json!(13)
            }),
            "0..=12",
        ),
        (
            "usage format 3",
            Box::new({
                let e = ext.clone();
                move |j| *j.pointer_mut(&format!("{e}/usageFormats/0")).unwrap() = json!(3)
            }),
            "expected 1 or 2",
        ),
        (
            "usage count 0",
            Box::new({
                let e = ext.clone();
                move |j| *j.pointer_mut(&format!("{e}/usageCounts/0")).unwrap() = json!(0)
            }),
            "at least 1",
        ),
        (
            "usage count 2",
            Box::new({
                let e = ext.clone();
                move |j| *j.pointer_mut(&format!("{e}/usageCounts/0")).unwrap() = json!(2)
            }),
            "declare 2 micromaps of level 2 format 2, the records have 1",
        ),
        (
            "usage lengths",
            Box::new({
                let e = ext.clone();
                move |j| *j.pointer_mut(&format!("{e}/usageLevels")).unwrap() = json!([1, 1])
            }),
            "equal lengths",
        ),
        (
            "usage empty",
            Box::new({
                let e = ext.clone();
                move |j| *j.pointer_mut(&format!("{e}/usageCounts")).unwrap() = json!([])
            }),
            "at least one entry",
        ),
        (
            "no data",
            Box::new({
                let e = ext.clone();
                move |j| {
                    j.pointer_mut(&e)
                        .unwrap()
                        .as_object_mut()
                        .unwrap()
                        .remove("data");
                }
            }),
            "data: missing",
        ),
        (
            "stride on triangles",
            Box::new(|j| j["bufferViews"][1]["byteStride"] = json!(8)),
            "must not have a byteStride",
        ),
        (
            "records not a multiple of 8",
            Box::new(|j| j["bufferViews"][1]["byteLength"] = json!(7)),
            "not a multiple of 8",
        ),
        (
            "data view too short",
            Box::new(|j| j["bufferViews"][0]["byteLength"] = json!(1)),
            "record 0: 4 bytes at offset 0 pass the end",
        ),
        (
            "no micromap",
            Box::new({
                let p = prim.clone();
                move |j| {
                    j.pointer_mut(&p)
                        .unwrap()
                        .as_object_mut()
                        .unwrap()
                        .remove("micromap");
                }
            }),
            "micromap: missing",
        ),
        (
            "micromap 1",
            Box::new({
                let p = prim.clone();
                move |j| j.pointer_mut(&p).unwrap()["micromap"] = json!(1)
            }),
            "root has 1 micromaps",
        ),
        (
            "base past the records",
            Box::new({
                let p = prim.clone();
                move |j| j.pointer_mut(&p).unwrap()["micromapBaseTriangle"] = json!(1)
            }),
            "has 1 records",
        ),
        (
            "negative base",
            Box::new({
                let p = prim.clone();
                move |j| j.pointer_mut(&p).unwrap()["micromapBaseTriangle"] = json!(-1)
            }),
            "non-negative integer",
        ),
        (
            "mode 1",
            Box::new(|j| j["meshes"][0]["primitives"][0]["mode"] = json!(1)),
            "TRIANGLES (4) only",
        ),
    ];
    for (name, edit, expected) in &cases {
        let mut j = base.clone();
        edit(&mut j);
        let error = read(&j).expect_err(name);
        let text = error.to_string();
        assert!(text.contains(expected), "{name}: {text}");
        assert!(!text.contains('\n'), "{name}: one line");
    }
}

#[test]
fn reader_checks_index_accessors_and_reads_2_pow_n_minus_5() {
    // Two triangles, 252 records: the u8 index 251 (2^8 - 5) is a regular
    // index under the draft ("less than 2^n - 4").
    let maps: Vec<Micromap> = (0..252u32)
        .map(|i| {
            let mut m = Micromap::new(Level::new(4).unwrap(), Format::FourState).unwrap();
            for k in 0..8 {
                m.set(
                    k,
                    if i >> k & 1 == 1 {
                        State::Opaque
                    } else {
                        State::Transparent
                    },
                )
                .unwrap();
            }
            m.set(200, State::UnknownOpaque).unwrap();
            m
        })
        .collect();
    let mut opacities: Vec<TriangleOpacity<'_>> =
        maps.iter().map(TriangleOpacity::Micromap).collect();
    opacities.push(TriangleOpacity::Special(State::Opaque));
    let buffers = MicromapBuffers::build(opacities, BuildOptions::default()).unwrap();
    let input = serde_json::to_vec(&json!({
        "asset": {"version": "2.0"},
        "accessors": [{"count": 253 * 3, "componentType": 5126, "type": "VEC3"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    }))
    .unwrap();
    let files = write(
        &input,
        &buffers,
        &[(0, 0)],
        &GltfContainer::Json { stem: "m".into() },
    );
    let mut j: Value = serde_json::from_slice(&files.main).unwrap();
    let sidecar = files.sidecars[0].1.clone();
    let a = j["meshes"][0]["primitives"][0]["extensions"][EXT]["micromapIndices"]
        .as_u64()
        .unwrap() as usize;
    assert_eq!(
        j["accessors"][a]["componentType"], 5123,
        "251 records need u16 under 2^n - 6"
    );
    // Rewrite the index buffer as u8, record 251 as the byte 251.
    let view = j["accessors"][a]["bufferView"].as_u64().unwrap() as usize;
    let offset = j["bufferViews"][view]["byteOffset"].as_u64().unwrap() as usize;
    let mut bytes = sidecar.clone();
    let u16s: Vec<u16> = bytes[offset..offset + 2 * 253]
        .chunks(2)
        .map(|c| u16::from_le_bytes([c[0], c[1]]))
        .collect();
    for (t, v) in u16s.iter().enumerate() {
        bytes[offset + t] = if *v == 0xfffe { 0xfe } else { *v as u8 };
    }
    j["accessors"][a]["componentType"] = json!(5121);
    j["bufferViews"][view]["byteLength"] = json!(253);
    let read = |j: &Value, bytes: &[u8]| {
        let mut resolve = |_: &str| Ok(bytes.to_vec());
        read_gltf_micromaps(
            &serde_json::to_vec(j).unwrap(),
            &mut resolve,
            &Limits::default(),
        )
    };
    let got = read(&j, &bytes).unwrap();
    assert_eq!(got.primitives[0].indices[251], MicromapIndex::Record(251));
    assert_eq!(
        got.primitives[0].indices[252],
        MicromapIndex::Special(State::Opaque)
    );
    let cases: Vec<(&str, Value, &str)> = vec![
        ("type", json!({"type": "VEC2"}), "expected \"SCALAR\""),
        ("float", json!({"componentType": 5126}), "expected 5121"),
        ("normalized", json!({"normalized": true}), "normalized"),
        ("count", json!({"count": 2}), "253 triangles"),
        (
            "offset",
            json!({"componentType": 5123, "byteOffset": 1}),
            "not a multiple",
        ),
    ];
    for (name, patch, expected) in cases {
        let mut k = j.clone();
        for (key, value) in patch.as_object().unwrap() {
            k["accessors"][a][key] = value.clone();
        }
        let text = read(&k, &bytes).expect_err(name).to_string();
        assert!(text.contains(expected), "{name}: {text}");
    }
    // Signed indices: -2 is the special opaque index, -5 is refused.
    let mut k = j.clone();
    k["accessors"][a]["componentType"] = json!(5122);
    k["bufferViews"][view]["byteLength"] = json!(2 * 253);
    let mut signed = sidecar.clone();
    for t in 0..253 {
        let v: i16 = if t == 252 { -2 } else { t as i16 };
        signed[offset + 2 * t..offset + 2 * t + 2].copy_from_slice(&v.to_le_bytes());
    }
    let got = read(&k, &signed).unwrap();
    assert_eq!(
        got.primitives[0].indices[252],
        MicromapIndex::Special(State::Opaque)
    );
    signed[offset..offset + 2].copy_from_slice(&(-5i16).to_le_bytes());
    let text = read(&k, &signed).unwrap_err().to_string();
    assert!(text.contains("value -5"), "{text}");
    // An index naming no record: 251 + micromapBaseTriangle 1.
    let mut shifted = j.clone();
    shifted["meshes"][0]["primitives"][0]["extensions"][EXT]["micromapBaseTriangle"] = json!(1);
    let text = read(&shifted, &bytes).unwrap_err().to_string();
    assert!(text.contains("has 252 records"), "{text}");
}

/// A `.gltf` whose views all name a second buffer (buffer 0 unused), and
/// whose second image is a `data:` URI: the `.glb` written from it holds
/// every byte in its `BIN` chunk (one buffer, the views rebased), reads
/// with no file beside it, and reads as the input does.
#[test]
fn a_glb_output_embeds_every_buffer_and_image() {
    let mut doc = input_json(&sponza("cards.gltf"));
    let length = doc["buffers"][0]["byteLength"].clone();
    // Buffer 0: 5 bytes of padding, unused; buffer 1: cards.bin.
    doc["buffers"] = json!([
        {"byteLength": 5, "uri": "data:application/octet-stream;base64,AAAAAAA="},
        {"byteLength": length, "uri": "cards.bin"},
    ]);
    for view in doc["bufferViews"].as_array_mut().unwrap() {
        view["buffer"] = json!(1);
    }
    let chain = sponza("chain.png");
    doc["images"][1] = json!({"uri": format!("data:image/png;base64,{}", base64(&chain))});
    let input = serde_json::to_vec(&doc).unwrap();
    let original = read_gltf_bytes(&input, &mut resolve_sponza, &Limits::default()).unwrap();
    let (buffers, prims) = bake(&input, Some(2), Format::FourState);
    let files = write(&input, &buffers, &prims, &GltfContainer::Glb);
    let (json, bin) = split_glb(&files.main);
    assert_eq!(json["buffers"].as_array().unwrap().len(), 1);
    assert!(json["buffers"][0].get("uri").is_none());
    let bin = bin.unwrap();
    for (v, view) in json["bufferViews"].as_array().unwrap().iter().enumerate() {
        assert_eq!(view["buffer"], 0, "bufferViews[{v}]");
    }
    // The file's image and the data: URI's (decoded: a third smaller).
    for (i, file) in [(0, "sponza_thorn.png"), (1, "chain.png")] {
        let image = &json["images"][i];
        assert!(image.get("uri").is_none(), "images[{i}]");
        assert_eq!(image["mimeType"], "image/png");
        let view = &json["bufferViews"][image["bufferView"].as_u64().unwrap() as usize];
        let at = view["byteOffset"].as_u64().unwrap() as usize;
        let len = view["byteLength"].as_u64().unwrap() as usize;
        assert!(
            bin[at..at + len] == sponza(file)[..],
            "images[{i}]: the bytes of {file}"
        );
    }
    let mut nothing = |uri: &str| -> Result<Vec<u8>, AssetError> { panic!("names {uri:?}") };
    let alone = read_gltf_bytes(&files.main, &mut nothing, &Limits::default()).unwrap();
    assert_eq!(alone.primitives, original.primitives);
    assert_eq!(alone.images, original.images);
}

/// Standard base64 with padding (the test's own, for a `data:` URI).
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * i)) as usize & 63] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}
