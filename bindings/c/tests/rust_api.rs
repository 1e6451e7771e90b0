//! The C entry points called from Rust: texel formats and row pitches give
//! the library's bytes, handles are shared across threads, the last error
//! is per thread, the budget, 2-state, model, texture-unit, vertex-alpha
//! and no-mixed options reach the library, and strided buffers read as tight ones.

use micromap_index::bake::mesh::{
    bake_mesh, LevelRule, Material, Mesh, MeshOptions, MeshTriangles,
};
use micromap_index::bake::{Model, Unorm8Texture};
use micromap_index::micromap::{
    BuildOptions, Format, IndexWidth, MicromapBuffers, ReadOptions, TriangleRecord, UnknownPolicy,
};
use micromap_index::Level;
use micromap_index_capi::constants::*;
use micromap_index_capi::*;
use std::ffi::CStr;
use std::ptr;

const W: u32 = 13;
const H: u32 = 9;

/// A texture with a disc of opaque texels and a soft edge.
fn texels() -> Vec<u8> {
    (0..W * H)
        .map(|i| {
            let (x, y) = ((i % W) as f32 - 6.0, (i / W) as f32 - 4.0);
            let d = (x * x + y * y).sqrt();
            (255.0 * (1.0 - d / 6.0).clamp(0.0, 1.0)) as u8
        })
        .collect()
}

const UVS: [f32; 12] = [
    0.05, 0.1, 0.9, 0.0, 0.95, 0.85, 0.1, 0.95, 0.5, 0.5, 0.2, 0.7,
];

fn mesh(texture: mmi_texture, material: mmi_material) -> mmi_mesh {
    mmi_mesh {
        texture,
        material,
        uvs: UVS.as_ptr(),
        vertex_count: 6,
        uv_stride: 0,
        indices: ptr::null(),
        index_count: 0,
        vertex_alpha: ptr::null(),
        vertex_alpha_stride: 0,
        uv_transform: std::ptr::null(),
    }
}

fn material() -> mmi_material {
    let mut m = mmi_material::default();
    // SAFETY: a valid pointer.
    assert_eq!(unsafe { mmi_material_default(&mut m) }, MMI_OK);
    m
}

fn options(level: u32, format: u32) -> mmi_bake_options {
    let mut o = mmi_bake_options::default();
    // SAFETY: a valid pointer.
    assert_eq!(unsafe { mmi_bake_options_default(&mut o) }, MMI_OK);
    o.level = level;
    o.format = format;
    o
}

/// Bakes and returns (data, records, 32-bit indices).
fn bake(mesh: &mmi_mesh, options: &mmi_bake_options) -> (Vec<u8>, Vec<u8>, Vec<u8>) {
    let mut result = ptr::null_mut();
    // SAFETY: valid pointers; the mesh's arrays outlive the call.
    let code = unsafe { mmi_bake(mesh, 1, options, &mut result) };
    assert_eq!(code, MMI_OK, "{}", last_error());
    let (mut p, mut n) = (ptr::null(), 0);
    // SAFETY: a live handle and valid out-pointers; the lent memory is read
    // before the handle is freed.
    unsafe {
        assert_eq!(mmi_bake_result_data(result, &mut p, &mut n), MMI_OK);
        let data = std::slice::from_raw_parts(p, n).to_vec();
        assert_eq!(
            mmi_bake_result_triangle_records(result, &mut p, &mut n),
            MMI_OK
        );
        let records = std::slice::from_raw_parts(p, n).to_vec();
        assert_eq!(
            mmi_bake_result_indices(result, 0, 32, ptr::null_mut(), 0, &mut n),
            MMI_OK
        );
        let mut indices = vec![0u8; n];
        assert_eq!(
            mmi_bake_result_indices(result, 0, 32, indices.as_mut_ptr(), n, &mut n),
            MMI_OK
        );
        mmi_bake_result_free(result);
        (data, records, indices)
    }
}

/// The `W` x `H` 8-bit texture `t8`, tightly packed, as the C API sees it.
fn u8_view(t8: &[u8]) -> mmi_texture {
    mmi_texture {
        texels: t8.as_ptr().cast(),
        width: W,
        height: H,
        row_pitch: 0,
        format: MMI_TEXEL_U8,
    }
}

/// The library's data, records and 32-bit indices of geometry 0, as
/// [`bake`] returns the C API's.
fn library_bytes(buffers: &MicromapBuffers) -> (Vec<u8>, Vec<u8>, Vec<u8>) {
    (
        buffers.data().to_vec(),
        buffers.records_le_bytes(),
        buffers.index_bytes(0, IndexWidth::U32).unwrap(),
    )
}

/// The tight buffers view of one bake's data, records and 32-bit indices
/// (the arrays must outlive its use).
fn buffers_view(data: &[u8], records: &[u8], indices: &[u8]) -> mmi_buffers_view {
    mmi_buffers_view {
        data: data.as_ptr(),
        data_len: data.len(),
        records: records.as_ptr(),
        records_len: records.len(),
        indices: indices.as_ptr(),
        indices_len: indices.len(),
        index_width_bits: 32,
        usage_counts: ptr::null(),
        usage_counts_len: 0,
        record_stride: 0,
        index_stride: 0,
    }
}

fn last_error() -> String {
    // SAFETY: never NULL, valid until the next call on this thread.
    unsafe { CStr::from_ptr(mmi_last_error_message()) }
        .to_string_lossy()
        .into_owned()
}

#[test]
fn texel_formats_and_pitches_give_the_librarys_bytes() {
    let t8 = texels();
    // The library directly.
    let texture = Unorm8Texture::new(W, H, &t8).unwrap();
    let triangles: Vec<[[f32; 2]; 3]> = UVS
        .chunks_exact(6)
        .map(|c| [[c[0], c[1]], [c[2], c[3]], [c[4], c[5]]])
        .collect();
    let library = bake_mesh(
        &Mesh {
            triangles: MeshTriangles::Uv(&triangles),
            texture: &texture,
            material: Material::default(),
            vertex_alpha: None,
        },
        &MeshOptions {
            levels: LevelRule::Fixed(Level::new(5).unwrap()),
            ..MeshOptions::default()
        },
    )
    .unwrap();
    let expected = library_bytes(&library.buffers);
    let options = options(5, MMI_FORMAT_4_STATE);
    let tight = mmi_texture {
        texels: t8.as_ptr().cast(),
        width: W,
        height: H,
        row_pitch: 0,
        format: MMI_TEXEL_U8,
    };
    assert_eq!(bake(&mesh(tight, material()), &options), expected);
    // A padded pitch: rows copied.
    let pitch = W as usize + 3;
    let mut padded = vec![0x5Au8; pitch * H as usize];
    for y in 0..H as usize {
        padded[y * pitch..y * pitch + W as usize]
            .copy_from_slice(&t8[y * W as usize..(y + 1) * W as usize]);
    }
    let pitched = mmi_texture {
        texels: padded.as_ptr().cast(),
        row_pitch: pitch,
        ..tight
    };
    assert_eq!(bake(&mesh(pitched, material()), &options), expected);
    // 16-bit unorm `c * 257` is the same alpha as 8-bit `c`, tight and
    // misaligned (copied), and f32 `c / 255` the same quotient.
    let t16: Vec<u16> = t8.iter().map(|&c| u16::from(c) * 257).collect();
    let wide = mmi_texture {
        texels: t16.as_ptr().cast(),
        format: MMI_TEXEL_U16,
        ..tight
    };
    assert_eq!(bake(&mesh(wide, material()), &options), expected);
    let mut shifted = vec![0u8; 1 + 2 * t16.len()];
    for (i, v) in t16.iter().enumerate() {
        shifted[1 + 2 * i..3 + 2 * i].copy_from_slice(&v.to_ne_bytes());
    }
    let misaligned = mmi_texture {
        // SAFETY: one byte into the buffer, which holds the texels after it.
        texels: unsafe { shifted.as_ptr().add(1) }.cast(),
        ..wide
    };
    assert_eq!(bake(&mesh(misaligned, material()), &options), expected);
    let tf: Vec<f32> = t8.iter().map(|&c| (f64::from(c) / 255.0) as f32).collect();
    let float = mmi_texture {
        texels: tf.as_ptr().cast(),
        format: MMI_TEXEL_F32,
        ..tight
    };
    // The f32 rounding of c / 255 may cross the cutoff for no code: the
    // cutoff 0.5 lies between 127/255 and 128/255 with room to spare.
    assert_eq!(bake(&mesh(float, material()), &options), expected);
}

#[test]
fn options_reach_the_library() {
    let t8 = texels();
    let texture = Unorm8Texture::new(W, H, &t8).unwrap();
    let view = u8_view(&t8);
    let triangles: Vec<[[f32; 2]; 3]> = UVS
        .chunks_exact(6)
        .map(|c| [[c[0], c[1]], [c[2], c[3]], [c[4], c[5]]])
        .collect();
    let mut c_options = options(MMI_LEVEL_AUTO, MMI_FORMAT_2_STATE);
    c_options.max_level = 9;
    c_options.unknown = MMI_UNKNOWN_OPAQUE;
    c_options.use_budget = 1;
    c_options.budget_bytes = 8;
    let mut c_material = material();
    c_material.sampler.filter = MMI_FILTER_LINEAR;
    c_material.sampler.address_u = MMI_ADDRESS_CLAMP_TO_BORDER;
    c_material.sampler.address_v = MMI_ADDRESS_MIRRORED_REPEAT;
    c_material.sampler.border_alpha = 1.0;
    c_material.cutoff = 0.25;
    c_material.comparison = MMI_OPAQUE_ABOVE;
    c_material.alpha_factor = 0.75;
    let library = bake_mesh(
        &Mesh {
            triangles: MeshTriangles::Uv(&triangles),
            texture: &texture,
            material: Material {
                sampler: micromap_index::bake::Sampler {
                    filter: micromap_index::bake::Filter::Linear,
                    address_u: micromap_index::bake::AddressMode::ClampToBorder,
                    address_v: micromap_index::bake::AddressMode::MirroredRepeat,
                    border_alpha: 1.0,
                },
                cutoff: micromap_index::bake::Cutoff::new(
                    0.25,
                    micromap_index::bake::Comparison::Above,
                )
                .unwrap(),
                alpha_factor: 0.75,
                uv_transform: micromap_index::bake::UvTransform::IDENTITY,
            },
            vertex_alpha: None,
        },
        &MeshOptions {
            levels: LevelRule::Useful {
                max: Level::new(9).unwrap(),
            },
            format: Format::TwoState,
            unknown: UnknownPolicy::Opaque,
            budget_bytes: Some(8),
            ..MeshOptions::default()
        },
    )
    .unwrap();
    let (data, records, _) = bake(&mesh(view, c_material), &c_options);
    assert_eq!(data, library.buffers.data());
    assert_eq!(records, library.buffers.records_le_bytes());
    assert!(data.len() <= 8, "{} bytes over the budget", data.len());
    // Without the budget the data is larger: the option mattered.
    c_options.use_budget = 0;
    let unbudgeted = bake(&mesh(view, c_material), &c_options).0.len();
    assert!(unbudgeted > 8, "{unbudgeted} bytes");
}

/// The bake's statistics (the code must be `MMI_OK`).
fn stats(mesh: &mmi_mesh, options: &mmi_bake_options) -> mmi_bake_stats {
    let mut result = ptr::null_mut();
    let mut stats = mmi_bake_stats::default();
    // SAFETY: valid pointers; the mesh's arrays outlive the call.
    unsafe {
        assert_eq!(
            mmi_bake(mesh, 1, options, &mut result),
            MMI_OK,
            "{}",
            last_error()
        );
        assert_eq!(mmi_bake_result_stats(result, &mut stats), MMI_OK);
        mmi_bake_result_free(result);
    }
    stats
}

/// The code `mmi_bake` returns (the handle, if any, freed).
fn bake_code(mesh: &mmi_mesh, options: &mmi_bake_options) -> mmi_result {
    let mut result = ptr::null_mut();
    // SAFETY: valid pointers; the mesh's arrays outlive the call.
    unsafe {
        let code = mmi_bake(mesh, 1, options, &mut result);
        mmi_bake_result_free(result);
        code
    }
}

/// `mmi_bake_options::model` selects the library's model (the same bytes
/// as `bake_mesh` with it), and the two differ where the doc-test of
/// `Baker` says: a triangle with an edge on a texel boundary is fully
/// known (16 of 16 opaque at level 2) only under the exact model. An
/// unknown model is refused, by `mmi_bake` and `mmi_verify_with_model`.
#[test]
fn the_model_reaches_the_library() {
    let t8 = texels();
    let texture = Unorm8Texture::new(W, H, &t8).unwrap();
    let view = u8_view(&t8);
    let triangles: Vec<[[f32; 2]; 3]> = UVS
        .chunks_exact(6)
        .map(|c| [[c[0], c[1]], [c[2], c[3]], [c[4], c[5]]])
        .collect();
    for (c_model, model) in [
        (MMI_MODEL_GPU_BINARY32, Model::GpuBinary32),
        (MMI_MODEL_EXACT, Model::Exact),
    ] {
        let library = bake_mesh(
            &Mesh {
                triangles: MeshTriangles::Uv(&triangles),
                texture: &texture,
                material: Material::default(),
                vertex_alpha: None,
            },
            &MeshOptions {
                levels: LevelRule::Fixed(Level::new(6).unwrap()),
                model,
                ..MeshOptions::default()
            },
        )
        .unwrap();
        let mut o = options(6, MMI_FORMAT_4_STATE);
        o.model = c_model;
        let (data, records, _) = bake(&mesh(view, material()), &o);
        assert_eq!(
            (data, records),
            (
                library.buffers.data().to_vec(),
                library.buffers.records_le_bytes()
            ),
            "{model:?}"
        );
    }
    // Left column opaque, right transparent; an edge on u = 0.
    let columns = [255u8, 0, 255, 0];
    let on_edge: [f32; 6] = [0.0, 0.0, 0.45, 0.0, 0.0, 1.0];
    let mut m = mesh(
        mmi_texture {
            texels: columns.as_ptr().cast(),
            width: 2,
            height: 2,
            row_pitch: 0,
            format: MMI_TEXEL_U8,
        },
        material(),
    );
    m.uvs = on_edge.as_ptr();
    m.vertex_count = 3;
    let mut o = options(2, MMI_FORMAT_4_STATE);
    assert_eq!(o.model, MMI_MODEL_GPU_BINARY32, "the default");
    let opaque = MMI_STATE_OPAQUE as usize;
    let gpu = stats(&m, &o);
    assert!(gpu.counts[opaque] < 16);
    // What the widening cost: the exact model's extra known ones.
    assert_eq!(gpu.counts[opaque] + gpu.widened, 16);
    o.model = MMI_MODEL_EXACT;
    let exact = stats(&m, &o);
    assert_eq!((exact.counts[opaque], exact.widened), (16, 0));
    o.model = 2;
    assert_eq!(bake_code(&m, &o), MMI_ERROR_INVALID_ENUM);
    assert!(last_error().contains("model 2"), "{}", last_error());
    // The verifier: the exact model's bake is sound under the exact model
    // and contradicted under the GPU model (its edge may read u = -1, the
    // transparent column under repeat).
    o.model = MMI_MODEL_EXACT;
    let (data, records, indices) = bake(&m, &o);
    let buffers = buffers_view(&data, &records, &indices);
    let verify = |model: u32| {
        let mut report = mmi_verify_report::default();
        // SAFETY: valid pointers; the arrays outlive the call.
        let code =
            unsafe { mmi_verify_with_model(&m, &buffers, model, &mut report, ptr::null_mut(), 0) };
        (code, report.contradictions)
    };
    assert_eq!(verify(MMI_MODEL_EXACT), (MMI_OK, 0));
    let (code, contradictions) = verify(MMI_MODEL_GPU_BINARY32);
    assert!(
        code == MMI_OK && contradictions > 0,
        "{code} {contradictions}"
    );
    assert_eq!(verify(7).0, MMI_ERROR_INVALID_ENUM);
}

/// The texture-unit fields of `mmi_bake_options` reach the library (0 the
/// defaults; each variant gives `bake_mesh`'s bytes with that
/// `TextureUnit`), out-of-range values are refused, and
/// `mmi_verify_with_options` judges by them: a bake by value is sound by
/// value and contradicted by footprint (it knows micro-triangles whose
/// footprint reads both classes).
#[test]
fn the_texture_unit_reaches_the_library() {
    use micromap_index::bake::{Filter, Interpolation, LinearRule, Sampler, TextureUnit};
    let t8 = texels();
    let texture = Unorm8Texture::new(W, H, &t8).unwrap();
    let view = u8_view(&t8);
    let mut linear = material();
    linear.sampler.filter = MMI_FILTER_LINEAR;
    let m = mesh(view, linear);
    let triangles: Vec<[[f32; 2]; 3]> = UVS
        .chunks_exact(6)
        .map(|c| [[c[0], c[1]], [c[2], c[3]], [c[4], c[5]]])
        .collect();
    let default = TextureUnit::default();
    let variants = [
        ((0, 0, 0, 0.0), default),
        ((4, 0, 0, 0.0), default.with_subtexel_bits(4)),
        (
            (0, MMI_INTERPOLATION_F16, 0, 0.0),
            default.with_interpolation(Interpolation::F16),
        ),
        (
            (0, 0, MMI_LINEAR_FOOTPRINT, 0.0),
            default.with_linear_rule(LinearRule::Footprint),
        ),
        (
            (16, 0, 0, 1.0 / 256.0),
            default
                .with_subtexel_bits(16)
                .with_filter_error(1.0 / 256.0),
        ),
    ];
    let mut all = Vec::new();
    for ((bits, interpolation, rule, error), unit) in variants {
        let library = bake_mesh(
            &Mesh {
                triangles: MeshTriangles::Uv(&triangles),
                texture: &texture,
                material: Material {
                    sampler: Sampler {
                        filter: Filter::Linear,
                        ..Sampler::default()
                    },
                    ..Material::default()
                },
                vertex_alpha: None,
            },
            &MeshOptions {
                levels: LevelRule::Fixed(Level::new(5).unwrap()),
                texture_unit: unit,
                ..MeshOptions::default()
            },
        )
        .unwrap();
        let mut o = options(5, MMI_FORMAT_4_STATE);
        (
            o.subtexel_bits,
            o.interpolation,
            o.linear_rule,
            o.filter_error,
        ) = (bits, interpolation, rule, error);
        let (data, records, _) = bake(&m, &o);
        assert_eq!(
            (&data, &records),
            (
                &library.buffers.data().to_vec(),
                &library.buffers.records_le_bytes()
            ),
            "{unit:?}"
        );
        all.push(library.report.counts);
    }
    // The variants differ where they should: by value knows more than by
    // footprint, 4 sub-texel bits less than 8.
    let known = |c: [u64; 4]| c[0] + c[1];
    assert!(known(all[0]) > known(all[3]), "{all:?}");
    assert!(known(all[0]) > known(all[1]), "{all:?}");
    // Out of range.
    for (field, value, code) in [
        ("sub-texel bits 3", 0, MMI_ERROR_INVALID_ARGUMENT),
        ("interpolation", 1, MMI_ERROR_INVALID_ENUM),
        ("linear_rule", 2, MMI_ERROR_INVALID_ENUM),
        ("filter error 2", 3, MMI_ERROR_INVALID_ARGUMENT),
        ("filter error NaN", 4, MMI_ERROR_INVALID_ARGUMENT),
    ] {
        let mut o = options(5, MMI_FORMAT_4_STATE);
        match value {
            0 => o.subtexel_bits = 3,
            1 => o.interpolation = 2,
            2 => o.linear_rule = 2,
            3 => o.filter_error = 2.0,
            _ => o.filter_error = f32::NAN,
        }
        assert_eq!(bake_code(&m, &o), code, "{field}");
        assert!(last_error().contains(field), "{field}: {}", last_error());
    }
    // The verifier by the same options.
    let o = options(5, MMI_FORMAT_4_STATE);
    let (data, records, indices) = bake(&m, &o);
    let buffers = buffers_view(&data, &records, &indices);
    let verify = |o: &mmi_bake_options| {
        let mut report = mmi_verify_report::default();
        // SAFETY: valid pointers; the arrays outlive the call.
        let code =
            unsafe { mmi_verify_with_options(&m, &buffers, o, &mut report, ptr::null_mut(), 0) };
        (code, report.contradictions, report.undecided)
    };
    assert_eq!(verify(&o), (MMI_OK, 0, 0));
    let mut footprint = o;
    footprint.linear_rule = MMI_LINEAR_FOOTPRINT;
    let (code, contradictions, _) = verify(&footprint);
    assert!(
        code == MMI_OK && contradictions > 0,
        "{code} {contradictions}"
    );
    let mut bad = o;
    bad.subtexel_bits = 17;
    assert_eq!(verify(&bad).0, MMI_ERROR_INVALID_ARGUMENT);
    let mut report = mmi_verify_report::default();
    // SAFETY: a NULL options pointer is refused before anything is read.
    let code = unsafe {
        mmi_verify_with_options(&m, &buffers, ptr::null(), &mut report, ptr::null_mut(), 0)
    };
    assert_eq!(code, MMI_ERROR_NULL_POINTER);
}

/// `mmi_mesh::vertex_alpha` reaches the library: strided (interleaved with
/// the UVs) and through indices it gives `bake_mesh`'s bytes with the
/// gathered per-triangle alphas; alpha 1 everywhere gives the bytes of no
/// vertex alpha; alpha 0 everywhere makes every micro-triangle transparent
/// (0 times any texel is below the cutoff 0.5). Bad strides, indices and
/// values are refused, and the verifier takes the vertex alpha as the bake
/// does.
#[test]
fn vertex_alpha_reaches_the_library() {
    let t8 = texels();
    let texture = Unorm8Texture::new(W, H, &t8).unwrap();
    let view = u8_view(&t8);
    let alphas = [1.0f32, 0.25, 0.75, 0.5, 1.0, 0.0];
    // (u, v, alpha) per vertex.
    let interleaved: Vec<f32> = (0..6)
        .flat_map(|i| [UVS[2 * i], UVS[2 * i + 1], alphas[i]])
        .collect();
    let indices = [2u32, 0, 1, 5, 3, 4, 1, 4, 2];
    let corner_uv = |i: u32| [UVS[2 * i as usize], UVS[2 * i as usize + 1]];
    let triangles: Vec<[[f32; 2]; 3]> = indices
        .chunks_exact(3)
        .map(|c| [corner_uv(c[0]), corner_uv(c[1]), corner_uv(c[2])])
        .collect();
    let gathered: Vec<[f32; 3]> = indices
        .chunks_exact(3)
        .map(|c| [0, 1, 2].map(|k| alphas[c[k] as usize]))
        .collect();
    let library = bake_mesh(
        &Mesh {
            triangles: MeshTriangles::Uv(&triangles),
            texture: &texture,
            material: Material::default(),
            vertex_alpha: Some(&gathered),
        },
        &MeshOptions {
            levels: LevelRule::Fixed(Level::new(5).unwrap()),
            ..MeshOptions::default()
        },
    )
    .unwrap();
    let mut m = mesh(view, material());
    m.uvs = interleaved.as_ptr();
    m.uv_stride = 12;
    m.indices = indices.as_ptr();
    m.index_count = indices.len();
    m.vertex_alpha = interleaved[2..].as_ptr();
    m.vertex_alpha_stride = 12;
    let o = options(5, MMI_FORMAT_4_STATE);
    let (data, records, c_indices) = bake(&m, &o);
    assert_eq!((data, records, c_indices), library_bytes(&library.buffers));
    // Alpha 1: as without; alpha 0: all transparent.
    let plain = mesh(view, material());
    let ones = [1.0f32; 6];
    let zeros = [0.0f32; 6];
    let mut with = plain;
    with.vertex_alpha = ones.as_ptr();
    assert_eq!(bake(&with, &o), bake(&plain, &o));
    assert!(stats(&plain, &o).counts[MMI_STATE_OPAQUE as usize] > 0);
    with.vertex_alpha = zeros.as_ptr();
    let s = stats(&with, &o);
    let total = 2 * 4u64.pow(5);
    assert_eq!(
        s.counts[MMI_STATE_TRANSPARENT as usize], total,
        "{:?}",
        s.counts
    );
    // Refusals.
    let mut bad = with;
    bad.vertex_alpha_stride = 6;
    assert_eq!(bake_code(&bad, &o), MMI_ERROR_INVALID_ARGUMENT);
    let over = [1.0f32, 1.0, 1.5, 1.0, 1.0, 1.0];
    bad = with;
    bad.vertex_alpha = over.as_ptr();
    assert_eq!(bake_code(&bad, &o), MMI_ERROR_BAKE);
    assert!(last_error().contains("1.5"), "{}", last_error());
    let far = [0u32, 1, 9];
    bad = with;
    bad.indices = far.as_ptr();
    bad.index_count = 3;
    assert_eq!(bake_code(&bad, &o), MMI_ERROR_INVALID_ARGUMENT);
    let (data, records, c_indices) = bake(&plain, &o);
    let buffers = buffers_view(&data, &records, &c_indices);
    // The verifier takes the vertex alpha as the bake does: alpha 0
    // makes every texel transparent, so each opaque micro-triangle of the
    // plain bake is contradicted, and only those.
    let mut report = mmi_verify_report::default();
    // SAFETY: valid pointers; the arrays outlive the call.
    let code = unsafe { mmi_verify(&with, &buffers, &mut report, ptr::null_mut(), 0) };
    assert_eq!(code, MMI_OK, "{}", last_error());
    let opaque = stats(&plain, &o).counts[MMI_STATE_OPAQUE as usize];
    assert!(opaque > 0);
    assert_eq!(report.contradictions, opaque);
}

#[test]
fn the_uv_transform_reaches_the_library() {
    use micromap_index::bake::UvTransform;
    let t8 = texels();
    let texture = Unorm8Texture::new(W, H, &t8).unwrap();
    let view = u8_view(&t8);
    let o = options(5, MMI_FORMAT_4_STATE);
    let triangles: Vec<[[f32; 2]; 3]> = UVS
        .chunks_exact(6)
        .map(|c| [[c[0], c[1]], [c[2], c[3]], [c[4], c[5]]])
        .collect();
    // A rotated, scaled and offset transform with inexact values, as
    // exporters write them.
    for (offset, rotation, scale) in [
        ([0.705f32, 0.285f32], 0.3f32, [0.35f32, 0.35f32]),
        ([0.0, 0.0], -1.2, [1.0, 0.8]),
        ([0.0, 0.0], 0.0, [1.0, 1.0]),
    ] {
        let transform = mmi_uv_transform {
            offset,
            rotation,
            scale,
        };
        let library = bake_mesh(
            &Mesh {
                triangles: MeshTriangles::Uv(&triangles),
                texture: &texture,
                material: Material {
                    uv_transform: UvTransform::new(offset, rotation, scale).unwrap(),
                    ..Material::default()
                },
                vertex_alpha: None,
            },
            &MeshOptions {
                levels: LevelRule::Fixed(Level::new(5).unwrap()),
                ..MeshOptions::default()
            },
        )
        .unwrap();
        let mut m = mesh(view, material());
        m.uv_transform = &transform;
        assert_eq!(
            bake(&m, &o),
            library_bytes(&library.buffers),
            "{transform:?}"
        );
        // The identity given or left NULL: the same bytes.
        if rotation == 0.0 && scale == [1.0, 1.0] {
            assert_eq!(bake(&m, &o), bake(&mesh(view, material()), &o));
        }
    }
    // The verifier reads it too: a bake under one transform judged under
    // none has contradictions, under its own none.
    let transform = mmi_uv_transform {
        offset: [0.5, 0.0],
        rotation: 0.0,
        scale: [1.0, 1.0],
    };
    let mut m = mesh(view, material());
    m.uv_transform = &transform;
    let (data, records, c_indices) = bake(&m, &o);
    let buffers = buffers_view(&data, &records, &c_indices);
    let verify = |mesh: &mmi_mesh| {
        let mut report = mmi_verify_report::default();
        // SAFETY: valid pointers; the arrays outlive the call.
        let code = unsafe { mmi_verify(mesh, &buffers, &mut report, ptr::null_mut(), 0) };
        assert_eq!(code, MMI_OK, "{}", last_error());
        report.contradictions
    };
    assert_eq!(verify(&m), 0);
    assert!(verify(&mesh(view, material())) > 0);
    // Refusals: not finite, a rotation beyond 65536 radians.
    for bad in [
        mmi_uv_transform {
            offset: [f32::NAN, 0.0],
            ..transform
        },
        mmi_uv_transform {
            rotation: 1e6,
            ..transform
        },
        mmi_uv_transform {
            scale: [1.0, f32::INFINITY],
            ..transform
        },
    ] {
        m.uv_transform = &bad;
        assert_eq!(bake_code(&m, &o), MMI_ERROR_INVALID_ARGUMENT, "{bad:?}");
        assert!(last_error().contains("uv_transform"), "{}", last_error());
    }
}

#[test]
fn handles_are_shared_across_threads_and_errors_are_per_thread() {
    fn send_sync<T: Send + Sync>() {}
    send_sync::<mmi_bake_result>();
    send_sync::<mmi_tree>();

    let states: Vec<u8> = (0..256u32).map(|i| (i * 7 % 5 % 4) as u8).collect();
    let mut tree = ptr::null_mut();
    // SAFETY: valid pointers.
    let code = unsafe {
        mmi_tree_encode(
            MMI_TREE_LEVEL_ORDER,
            4,
            MMI_FORMAT_4_STATE,
            states.as_ptr(),
            states.len(),
            &mut tree,
        )
    };
    assert_eq!(code, MMI_OK);
    let shared = tree as usize;
    std::thread::scope(|s| {
        for worker in 0..4u64 {
            let states = &states;
            s.spawn(move || {
                let tree = shared as *const mmi_tree;
                for i in 0..256u64 {
                    let mut state = 9;
                    // SAFETY: a live handle, read-only, freed after the scope.
                    assert_eq!(unsafe { mmi_tree_get(tree, i, &mut state) }, MMI_OK);
                    assert_eq!(state, states[i as usize]);
                }
                // An error on this thread leaves the others' messages alone.
                let mut out = 0;
                // SAFETY: a valid pointer.
                let code = unsafe { mmi_index_f32(0.0, 0.0, 20 + worker as u32, &mut out) };
                assert_eq!(code, MMI_ERROR_INVALID_LEVEL);
                let message = last_error();
                std::thread::yield_now();
                assert_eq!(last_error(), message);
                assert!(message.contains(&(20 + worker).to_string()), "{message}");
            });
        }
    });
    // SAFETY: the handle from mmi_tree_encode, freed once.
    unsafe { mmi_tree_free(tree) };
}

#[test]
fn empty_inputs_are_fine() {
    let mut result = ptr::null_mut();
    let options = options(3, MMI_FORMAT_4_STATE);
    // SAFETY: no meshes (NULL with count 0 is allowed), valid pointers.
    let code = unsafe { mmi_bake(ptr::null(), 0, &options, &mut result) };
    assert_eq!(code, MMI_OK, "{}", last_error());
    let mut count = 9;
    // SAFETY: a live handle, then freed once.
    unsafe {
        assert_eq!(mmi_bake_result_geometry_count(result, &mut count), MMI_OK);
        mmi_bake_result_free(result);
    }
    assert_eq!(count, 0);
}

/// The disc's two triangles and a third in its transparent corner
/// (texels (0, 7), (0, 8), (1, 8) and, across the repeat, (0, 0) are all
/// further than 6 texels from the disc's centre, so alpha 0): at a fixed
/// level the third is uniform, a special index.
const CORNER_UVS: [f32; 18] = [
    0.05, 0.1, 0.9, 0.0, 0.95, 0.85, 0.1, 0.95, 0.5, 0.5, 0.2, 0.7, 0.01, 0.9, 0.06, 0.9, 0.01,
    0.98,
];

/// What `mmi_bake_result_is_mixed` says of geometry 0.
fn mixed(mesh: &mmi_mesh, options: &mmi_bake_options) -> u32 {
    let mut result = ptr::null_mut();
    let mut mixed = 9;
    // SAFETY: valid pointers; the mesh's arrays outlive the call.
    unsafe {
        assert_eq!(mmi_bake(mesh, 1, options, &mut result), MMI_OK);
        assert_eq!(mmi_bake_result_is_mixed(result, 0, &mut mixed), MMI_OK);
        mmi_bake_result_free(result);
    }
    mixed
}

/// `mmi_bake_options::no_mixed_special_indices` reaches the library: the
/// same bytes as `bake_mesh` with `BuildOptions::no_mixed_special_indices`
/// off and on, the corner's special index becoming a record when on, and
/// `mmi_bake_result_is_mixed` answering `MicromapBuffers::is_mixed`.
#[test]
fn no_mixed_special_indices_reach_the_library() {
    let t8 = texels();
    let texture = Unorm8Texture::new(W, H, &t8).unwrap();
    let view = u8_view(&t8);
    let triangles: Vec<[[f32; 2]; 3]> = CORNER_UVS
        .chunks_exact(6)
        .map(|c| [[c[0], c[1]], [c[2], c[3]], [c[4], c[5]]])
        .collect();
    let mut m = mesh(view, material());
    m.uvs = CORNER_UVS.as_ptr();
    m.vertex_count = 9;
    let mut o = options(4, MMI_FORMAT_4_STATE);
    assert_eq!(o.no_mixed_special_indices, 0, "the default");
    let mut records_by_option = Vec::new();
    for no_mixed in [false, true] {
        let library = bake_mesh(
            &Mesh {
                triangles: MeshTriangles::Uv(&triangles),
                texture: &texture,
                material: Material::default(),
                vertex_alpha: None,
            },
            &MeshOptions {
                levels: LevelRule::Fixed(Level::new(4).unwrap()),
                buffers: BuildOptions {
                    no_mixed_special_indices: no_mixed,
                    ..BuildOptions::default()
                },
                ..MeshOptions::default()
            },
        )
        .unwrap();
        o.no_mixed_special_indices = u32::from(no_mixed);
        let (data, records, indices) = bake(&m, &o);
        assert_eq!(
            (&data[..], &records, &indices),
            (
                library.buffers.data(),
                &library.buffers.records_le_bytes(),
                &library.buffers.index_bytes(0, IndexWidth::U32).unwrap()
            ),
            "no_mixed {no_mixed}"
        );
        assert_eq!(library.buffers.is_mixed(0).unwrap(), !no_mixed);
        assert_eq!(mixed(&m, &o), u32::from(!no_mixed));
        // The corner: special index -1 (transparent), else a record.
        let corner = i32::from_le_bytes(indices[8..12].try_into().unwrap());
        assert_eq!(corner < 0, !no_mixed, "corner index {corner}");
        records_by_option.push(records.len() / 8);
    }
    // One shared level-0 record more: the transparent one.
    assert_eq!(records_by_option[1], records_by_option[0] + 1);
    // Any non-zero value is on.
    o.no_mixed_special_indices = 7;
    assert_eq!(mixed(&m, &o), 0);
    // Misuse of the query.
    let mut result = ptr::null_mut();
    let mut flag = 0;
    // SAFETY: valid pointers or NULL, as each case says.
    unsafe {
        assert_eq!(mmi_bake(&m, 1, &o, &mut result), MMI_OK);
        assert_eq!(
            mmi_bake_result_is_mixed(result, 1, &mut flag),
            MMI_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(
            mmi_bake_result_is_mixed(result, 0, ptr::null_mut()),
            MMI_ERROR_NULL_POINTER
        );
        assert_eq!(
            mmi_bake_result_is_mixed(ptr::null(), 0, &mut flag),
            MMI_ERROR_NULL_POINTER
        );
        mmi_bake_result_free(result);
    }
}

/// `element`-byte elements of `bytes` laid `stride` bytes apart, the gaps
/// filled with junk, ending with a whole stride or right after the last
/// element.
fn spread(bytes: &[u8], element: usize, stride: usize, whole: bool) -> Vec<u8> {
    let mut out = Vec::new();
    for chunk in bytes.chunks_exact(element) {
        out.extend_from_slice(chunk);
        out.extend((0..stride - element).map(|i| 0xa5 ^ i as u8));
    }
    if !whole && !out.is_empty() {
        out.truncate(out.len() - (stride - element));
    }
    out
}

/// `mmi_verify`'s report as comparable numbers.
fn report_numbers(r: &mmi_verify_report) -> [u64; 7] {
    [
        r.triangles,
        r.triangles_checked,
        r.known,
        r.unknown,
        r.undecided,
        r.contradictions,
        r.witnesses_written,
    ]
}

/// `mmi_buffers_view::record_stride` and `index_stride`: every record
/// stride 0..=40 and index stride 0..=20 (32-bit indices) is refused with
/// `MMI_ERROR_INVALID_ARGUMENT` exactly when `ReadOptions::check_strides`
/// refuses it (0 meaning tight), by `mmi_validate_buffers` and
/// `mmi_verify` alike; at every accepted pair the buffers re-laid with
/// junk in the gaps read as the tight ones (the same info and the same
/// verification report), whether they end with a whole stride or right
/// after the last element, and a byte short is `MMI_ERROR_MALFORMED`.
#[test]
fn strided_buffers_read_as_tight_ones() {
    let t8 = texels();
    let view = u8_view(&t8);
    let mut m = mesh(view, material());
    m.uvs = CORNER_UVS.as_ptr();
    m.vertex_count = 9;
    let (data, records, indices) = bake(&m, &options(4, MMI_FORMAT_4_STATE));
    let tight = mmi_buffers_view {
        data: data.as_ptr(),
        data_len: data.len(),
        records: records.as_ptr(),
        records_len: records.len(),
        usage_counts: ptr::null(),
        usage_counts_len: 0,
        indices: indices.as_ptr(),
        indices_len: indices.len(),
        index_width_bits: 32,
        record_stride: 0,
        index_stride: 0,
    };
    let validate = |v: &mmi_buffers_view| {
        let mut info = mmi_buffers_info::default();
        // SAFETY: the view's arrays outlive the call.
        let code = unsafe { mmi_validate_buffers(v, ptr::null(), &mut info) };
        (code, [info.records, info.indices, info.special_indices])
    };
    let verify = |v: &mmi_buffers_view| {
        let mut report = mmi_verify_report::default();
        // SAFETY: the mesh's and the view's arrays outlive the call.
        let code = unsafe { mmi_verify(&m, v, &mut report, ptr::null_mut(), 0) };
        (code, report_numbers(&report))
    };
    let expected_info = validate(&tight);
    let expected_report = verify(&tight);
    assert_eq!(expected_info.0, MMI_OK);
    assert_eq!(expected_info.1[2], 1, "the corner's special index");
    assert_eq!(expected_report.0, MMI_OK);
    assert_eq!(expected_report.1[5], 0, "the bake is sound");
    let mut accepted = 0;
    for record_stride in 0..=40 {
        for index_stride in 0..=20 {
            let library = ReadOptions {
                record_stride: if record_stride == 0 {
                    TriangleRecord::SIZE
                } else {
                    record_stride
                },
                index_stride: (index_stride != 0).then_some(index_stride),
                ..ReadOptions::default()
            }
            .check_strides(Some(IndexWidth::U32));
            let (rs, is) = (record_stride.max(8), index_stride.max(4));
            if library.is_err() {
                // The stride is refused before any byte is read.
                let v = mmi_buffers_view {
                    record_stride,
                    index_stride,
                    ..tight
                };
                assert_eq!(validate(&v).0, MMI_ERROR_INVALID_ARGUMENT);
                assert!(last_error().contains("stride"), "{}", last_error());
                assert_eq!(verify(&v).0, MMI_ERROR_INVALID_ARGUMENT);
                continue;
            }
            accepted += 1;
            for whole in [false, true] {
                let r = spread(&records, 8, rs, whole);
                let i = spread(&indices, 4, is, whole);
                let v = mmi_buffers_view {
                    records: r.as_ptr(),
                    records_len: r.len(),
                    indices: i.as_ptr(),
                    indices_len: i.len(),
                    record_stride,
                    index_stride,
                    ..tight
                };
                let case = format!("strides {record_stride} {index_stride} whole {whole}");
                assert_eq!(validate(&v), expected_info, "{case}");
                assert_eq!(verify(&v), expected_report, "{case}");
                if rs > 8 {
                    let short = mmi_buffers_view {
                        records_len: r.len() - 1,
                        ..v
                    };
                    assert_eq!(validate(&short).0, MMI_ERROR_MALFORMED, "{case}");
                    assert_eq!(verify(&short).0, MMI_ERROR_MALFORMED, "{case}");
                }
            }
        }
    }
    // 0 and 8..=40 by 4 for records, 0 and 4..=20 by 4 for indices.
    assert_eq!(accepted, 10 * 6);
}
