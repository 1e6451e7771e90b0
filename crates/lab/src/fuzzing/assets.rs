//! The bodies of the fuzz targets `alpha_image`, `triangles_json` and
//! `gltf_asset` (the readers of [`micromap_index_assets`]), replayed on stable by
//! `crates/lab/tests/fuzz_corpus.rs`.

use micromap_index::bake::mesh::{
    bake_mesh, BakeReport, LevelRule, Mesh, MeshBakeError, MeshOptions, MeshTriangles, Mips,
};
use micromap_index::bake::Model;
use micromap_index::micromap::{BuildOptions, MicromapBuffersBuilder, State, TriangleOpacity};
use micromap_index::Level;
use micromap_index_assets::{
    decode_alpha_image, read_gltf_bytes, read_gltf_micromaps, read_triangles_json,
    write_gltf_micromaps, AlphaSource, AlphaTexels, AssetError, GltfAsset, GltfContainer,
    GltfMicromapWrite, GltfMicromaps, Limits, MaskPrimitive, UriScope, MAX_GLTF_LEVEL,
};

/// The limits of the asset targets: 2^16 pixels and 16 MiB, so that no
/// input can make a run slow or large.
pub const FUZZ_LIMITS: Limits = Limits {
    max_pixels: 1 << 16,
    max_bytes: 1 << 24,
    uri_scope: UriScope::Anywhere,
};

/// A 2 x 2 grey + alpha PNG (alpha 0, 85, 170, 255), which the
/// `gltf_asset` body serves for every external URI, buffers included
/// (written by `fuzz/seeds/make_asset_seeds.py`).
pub const FUZZ_PNG: [u8; 75] = [
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52,
    0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x04, 0x00, 0x00, 0x00, 0xd8, 0xbf, 0xc5,
    0xaf, 0x00, 0x00, 0x00, 0x12, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0x60, 0x60, 0x60, 0x08,
    0x65, 0x60, 0x58, 0xc5, 0xf0, 0x1f, 0x00, 0x05, 0x05, 0x01, 0xff, 0x9f, 0xe8, 0xa7, 0xeb, 0x00,
    0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82,
];

/// [`decode_alpha_image`] on any bytes (the whole input is the image file)
/// under [`FUZZ_LIMITS`]: never panics, and an accepted image has
/// `width * height` texels, within the pixel limit, and `Float` texels (no
/// decoder makes them) in `[0, 1]`; the error of a rejected one displays on
/// one line.
///
/// ```
/// use micromap_index_lab::fuzzing::{alpha_image, FUZZ_PNG};
/// alpha_image(&FUZZ_PNG);
/// alpha_image(b"\x89PNG\r\n\x1a\n");
/// alpha_image(b"\xff\xd8\xff");
/// ```
///
/// # Panics
///
/// When a property fails.
pub fn alpha_image(data: &[u8]) {
    match decode_alpha_image(data, &FUZZ_LIMITS) {
        Ok(image) => {
            let pixels = u64::from(image.width) * u64::from(image.height);
            assert!(
                (1..=FUZZ_LIMITS.max_pixels).contains(&pixels),
                "accepted a {} x {} image",
                image.width,
                image.height
            );
            assert_eq!(
                image.texels.len() as u64,
                pixels,
                "{} x {} image with {} texels",
                image.width,
                image.height,
                image.texels.len()
            );
            if let AlphaTexels::Float(texels) = &image.texels {
                assert!(
                    texels.iter().all(|t| (0.0..=1.0).contains(t)),
                    "float texels outside [0, 1]"
                );
            }
        }
        Err(error) => check_error(&error),
    }
}

/// [`read_triangles_json`] on any bytes: never panics; what it accepts
/// writes back (each number as Rust's shortest round-trip decimal, `±inf`
/// as `±1e39`) to text that reads back bit for bit; the error of a rejected
/// input displays on one line.
///
/// ```
/// use micromap_index_lab::fuzzing::triangles_json;
/// triangles_json(br#"{"triangles": [[[0.1, 0], [1e39, 0], [0, 1]]]}"#);
/// triangles_json(b"{");
/// ```
///
/// # Panics
///
/// When a property fails.
pub fn triangles_json(data: &[u8]) {
    match read_triangles_json(data) {
        Ok(triangles) => {
            let number = |x: f32| {
                if x.is_infinite() {
                    if x > 0.0 { "1e39" } else { "-1e39" }.to_string()
                } else {
                    format!("{x:?}")
                }
            };
            let items: Vec<String> = triangles
                .iter()
                .map(|t| {
                    let corners: Vec<String> = t
                        .iter()
                        .map(|[u, v]| format!("[{}, {}]", number(*u), number(*v)))
                        .collect();
                    format!("[{}]", corners.join(", "))
                })
                .collect();
            let text = format!("{{\"triangles\": [{}]}}", items.join(", "));
            let again = match read_triangles_json(text.as_bytes()) {
                Ok(again) => again,
                Err(e) => panic!("{triangles:?} writes as {text:?}, which fails: {e}"),
            };
            let bits = |t: &[[[f32; 2]; 3]]| -> Vec<u32> {
                t.iter().flatten().flatten().map(|x| x.to_bits()).collect()
            };
            assert_eq!(
                bits(&again),
                bits(&triangles),
                "{text:?} reads back differently"
            );
        }
        Err(error) => check_error(&error),
    }
}

/// [`read_gltf_bytes`] on any bytes (the whole input is the `.gltf` or
/// `.glb`) under [`FUZZ_LIMITS`], every external URI resolving to
/// [`FUZZ_PNG`] (except URIs ending in `.missing`, which fail): never
/// panics; an accepted asset is consistent (each primitive's image exists,
/// images within the pixel limit with `width * height` texels, the cutoff
/// not negative, everything held within the byte limit); the error of a
/// rejected input displays on one line.
///
/// ```
/// use micromap_index_lab::fuzzing::gltf_asset;
/// gltf_asset(br#"{"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": {}}]}]}"#);
/// gltf_asset(b"glTF\x02\0\0\0");
/// ```
///
/// # Panics
///
/// When a property fails.
pub fn gltf_asset(data: &[u8]) {
    let mut resolve = |uri: &str| {
        if uri.ends_with(".missing") {
            Err(AssetError::Io {
                path: uri.to_string(),
                message: "not found".to_string(),
            })
        } else {
            Ok(FUZZ_PNG.to_vec())
        }
    };
    match read_gltf_bytes(data, &mut resolve, &FUZZ_LIMITS) {
        Ok(asset) => {
            check_asset(&asset);
            check_written(data, &asset, &mut resolve);
        }
        Err(error) => check_error(&error),
    }
    match read_gltf_micromaps(data, &mut resolve, &FUZZ_LIMITS) {
        Ok(found) => check_micromaps(&found),
        Err(error) => check_error(&error),
    }
}

/// What [`read_gltf_micromaps`] accepts is consistent: every level within
/// the draft's 0..=12, usage counts summing to the records, every
/// primitive's index naming a record of its micromap.
fn check_micromaps(found: &GltfMicromaps) {
    for m in &found.micromaps {
        assert_eq!(m.records.len(), m.micromaps.len());
        assert!(m
            .records
            .iter()
            .all(|r| u32::from(r.subdivision_level) <= MAX_GLTF_LEVEL));
        let total: u64 = m.usage.iter().map(|u| u64::from(u.count)).sum();
        assert_eq!(total, m.records.len() as u64, "usage total");
    }
    for p in &found.primitives {
        for t in 0..p.indices.len() {
            assert!(
                found.opacity(p, t).is_some(),
                "primitive {}/{} triangle {t}",
                p.mesh,
                p.primitive
            );
        }
    }
}

/// An accepted asset written back with one unknown-opaque special index
/// per triangle (as a GLB) either reads back with exactly those indices on
/// every primitive, or is refused with a one-line error.
fn check_written(
    data: &[u8],
    asset: &GltfAsset,
    resolve: &mut dyn FnMut(&str) -> Result<Vec<u8>, AssetError>,
) {
    if asset.primitives.is_empty() {
        return;
    }
    let mut builder = MicromapBuffersBuilder::new(BuildOptions::default());
    for p in &asset.primitives {
        let specials = p
            .triangles
            .iter()
            .map(|_| TriangleOpacity::Special(State::UnknownOpaque));
        builder
            .add_geometry(specials)
            .expect("special indices always build");
    }
    let buffers = builder.finish().expect("special indices always build");
    let primitives: Vec<(usize, usize)> = asset
        .primitives
        .iter()
        .map(|p| (p.mesh, p.primitive))
        .collect();
    let write = GltfMicromapWrite {
        buffers: &buffers,
        primitives: &primitives,
    };
    let written = match write_gltf_micromaps(data, resolve, &write, &GltfContainer::Glb) {
        Ok(files) => files,
        Err(error) => return check_error(&error),
    };
    let back = read_gltf_micromaps(&written.main, resolve, &FUZZ_LIMITS)
        .unwrap_or_else(|e| panic!("the written GLB does not read back: {e}"));
    for (g, &(m, p)) in primitives.iter().enumerate() {
        let found = back
            .primitive(m, p)
            .unwrap_or_else(|| panic!("primitive {m}/{p} lost its extension"));
        assert_eq!(
            found.indices,
            buffers.geometry_indices(g).expect("geometry"),
            "primitive {m}/{p}"
        );
    }
}

fn check_asset(asset: &GltfAsset) {
    assert_eq!(asset.images.len(), asset.image_info.len());
    let mut held = 0u64;
    for image in &asset.images {
        let pixels = u64::from(image.width) * u64::from(image.height);
        assert!((1..=FUZZ_LIMITS.max_pixels).contains(&pixels));
        assert_eq!(image.texels.len() as u64, pixels);
        held += match image.texels {
            AlphaTexels::Unorm8(_) => pixels,
            AlphaTexels::Unorm16(_) => 2 * pixels,
            AlphaTexels::Float(_) => 4 * pixels,
        };
    }
    for primitive in &asset.primitives {
        assert!(
            primitive.image < asset.images.len(),
            "primitive {}/{} uses image {} of {}",
            primitive.mesh,
            primitive.primitive,
            primitive.image,
            asset.images.len()
        );
        assert!(primitive.cutoff.alpha() >= 0.0);
        held += 24 * primitive.triangles.len() as u64;
        if let Some(alphas) = &primitive.vertex_alpha {
            assert_eq!(alphas.len(), primitive.triangles.len());
            assert!(alphas.iter().flatten().all(|a| (0.0..=1.0).contains(a)));
            held += 12 * alphas.len() as u64;
        }
        bake_primitive(asset, primitive);
    }
    for (image, info) in asset.images.iter().zip(&asset.image_info) {
        // glTF: an image without alpha is opaque.
        if info.alpha == AlphaSource::One {
            assert!((0..image.texels.len()).all(|i| image.texels.get(i) == Some(1.0)));
        }
    }
    assert!(
        held <= FUZZ_LIMITS.max_bytes,
        "{held} bytes of images and triangles"
    );
    for warning in &asset.warnings {
        assert!(!warning.contains('\n'), "warning {warning:?}");
    }
}

/// Bakes the first few triangles of `primitive` at level 1 with its
/// material and vertex alpha: what the reader accepts, the bake takes.
fn bake_primitive(asset: &GltfAsset, primitive: &MaskPrimitive) {
    let texture = asset.images[primitive.image]
        .texture()
        .expect("the reader's images are views");
    let n = primitive.triangles.len().min(8);
    let mesh = Mesh {
        triangles: MeshTriangles::Uv(&primitive.triangles[..n]),
        texture: &texture,
        material: primitive.material(),
        vertex_alpha: primitive.vertex_alpha.as_ref().map(|a| &a[..n]),
    };
    let options = MeshOptions {
        levels: LevelRule::Fixed(Level::new(1).expect("level 1")),
        ..MeshOptions::default()
    };
    match bake_mesh(&mesh, &options) {
        Ok(baked) => {
            assert_eq!(baked.report.triangles, n);
            widening_and_mips_hold(&mesh, &options, &baked.report);
        }
        // A factor the vertex-alpha bake does not take (negative, say).
        Err(MeshBakeError::VertexAlpha { .. }) => {
            assert!(!(primitive.alpha_factor >= 0.0 && primitive.alpha_factor.is_finite()));
        }
        Err(error) => panic!("bake of an accepted primitive failed: {error}"),
    }
}

/// The GPU-model bake's widening count is the exact model's extra known
/// micro-triangles (where both place the triangles alike), and a bake for mip levels 0..=2 (without vertex alpha,
/// which it refuses) knows no more than the level-0 bake, all of the
/// same state.
fn widening_and_mips_hold(mesh: &Mesh<'_>, options: &MeshOptions, gpu: &BakeReport) {
    let known = |r: &BakeReport| r.counts[0] + r.counts[1];
    let exact = bake_mesh(
        mesh,
        &MeshOptions {
            model: Model::Exact,
            ..*options
        },
    )
    .expect("the GPU model's bake succeeded");
    // (A transformed vertex the exact model cannot place exactly leaves its
    // triangle unknown there, while the GPU model's widening is counted on
    // its own placement: the count holds where the exact model places every
    // triangle, as the GPU model does, or without a transform.)
    let placed_alike =
        mesh.material.uv_transform.is_identity() || exact.report.status.out_of_exact_range == 0;
    if gpu.status.block_budget_exceeded + exact.report.status.block_budget_exceeded == 0
        && placed_alike
    {
        assert_eq!(known(gpu) + gpu.widened, known(&exact.report));
    }
    let mips = MeshOptions {
        mips: Mips::UpTo(2),
        ..*options
    };
    match (bake_mesh(mesh, &mips), mesh.vertex_alpha) {
        (Err(MeshBakeError::VertexAlpha { .. }), Some(_)) => {}
        (Ok(lower), None) => {
            let (low, zero) = (&lower.report, gpu);
            assert!(low.counts[0] <= zero.counts[0] && low.counts[1] <= zero.counts[1]);
            let zero_bake = bake_mesh(mesh, options).expect("baked before");
            let triangles = lower.report.triangles;
            for t in 0..triangles {
                let (Some(a), Some(b)) = (lower.opacity(0, t), zero_bake.opacity(0, t)) else {
                    panic!("triangle {t} of {triangles} missing");
                };
                let micro = lower
                    .triangle(0, t)
                    .map_or(0, |t| t.counts.iter().sum::<u64>());
                for i in 0..micro {
                    let state = a.state(i);
                    if state.is_some_and(State::is_known) {
                        assert_eq!(state, b.state(i));
                    }
                }
            }
        }
        (other, _) => panic!("mips bake: {:?}", other.map(|b| b.report)),
    }
}

fn check_error(error: &AssetError) {
    let text = error.to_string();
    assert!(
        !text.is_empty() && !text.contains('\n'),
        "error message {text:?}"
    );
}
