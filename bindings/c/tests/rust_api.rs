//! The C entry points called from Rust: texel formats and row pitches give
//! the library's bytes, handles are shared across threads, the last error
//! is per thread, and the budget and 2-state options reach the library.

use micromap_index::bake::mesh::{
    bake_mesh, LevelRule, Material, Mesh, MeshOptions, MeshTriangles,
};
use micromap_index::bake::Unorm8Texture;
use micromap_index::micromap::{Format, UnknownPolicy};
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
    let expected = (
        library.buffers.data().to_vec(),
        library.buffers.records_le_bytes(),
        library
            .buffers
            .index_bytes(0, micromap_index::micromap::IndexWidth::U32)
            .unwrap(),
    );
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
    let view = mmi_texture {
        texels: t8.as_ptr().cast(),
        width: W,
        height: H,
        row_pitch: 0,
        format: MMI_TEXEL_U8,
    };
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
