//! `mmi_verify` is `bake::mesh::verify_mesh` (issue 32): for an alpha
//! factor, vertex alpha (strided, through indices) and both, its report
//! and witnesses equal the library's on the same mesh and buffers, the
//! C bake of the same material is sound, and buffers baked without the
//! material are contradicted where it lowers the alpha. Witnesses beyond
//! the caller's capacity are counted, not kept.

use micromap_index::bake::mesh::{verify_mesh, Material, Mesh, MeshOptions, MeshTriangles};
use micromap_index::bake::{Model, Unorm8Texture};
use micromap_index::micromap::{read_buffers, BufferBytes, IndexWidth, MicromapIndex, ReadOptions};
use micromap_index::micromap::{Overlap, TriangleOpacity};
use micromap_index_capi::constants::*;
use micromap_index_capi::*;
use std::ptr;

const W: u32 = 13;
const H: u32 = 9;

/// A disc of opaque texels with a soft edge.
fn texels() -> Vec<u8> {
    (0..W * H)
        .map(|i| {
            let (x, y) = ((i % W) as f32 - 6.0, (i / W) as f32 - 4.0);
            let d = (x * x + y * y).sqrt();
            (255.0 * (1.0 - d / 6.0).clamp(0.0, 1.0)) as u8
        })
        .collect()
}

/// Six vertices `(u, v, alpha)`, interleaved.
const VERTICES: [f32; 18] = [
    0.05, 0.1, 1.0, 0.9, 0.0, 0.25, 0.95, 0.85, 0.75, 0.1, 0.95, 0.5, 0.5, 0.5, 1.0, 0.2, 0.7, 0.0,
];
const INDICES: [u32; 9] = [2, 0, 1, 5, 3, 4, 1, 4, 2];

/// A contradiction's triangle, micro-triangle and texel (`u32::MAX` twice:
/// the border).
type Seen = (u64, u64, u32, u32);

struct Case {
    name: &'static str,
    alpha_factor: f32,
    vertex_alpha: bool,
}

const CASES: [Case; 4] = [
    Case {
        name: "plain",
        alpha_factor: 1.0,
        vertex_alpha: false,
    },
    Case {
        name: "factor",
        alpha_factor: 0.75,
        vertex_alpha: false,
    },
    Case {
        name: "vertex alpha",
        alpha_factor: 1.0,
        vertex_alpha: true,
    },
    Case {
        name: "both",
        alpha_factor: 0.75,
        vertex_alpha: true,
    },
];

fn c_mesh(t8: &[u8], case: &Case) -> mmi_mesh {
    let mut material = mmi_material::default();
    // SAFETY: a valid pointer.
    assert_eq!(unsafe { mmi_material_default(&mut material) }, MMI_OK);
    material.sampler.filter = MMI_FILTER_LINEAR;
    material.alpha_factor = case.alpha_factor;
    mmi_mesh {
        texture: mmi_texture {
            texels: t8.as_ptr().cast(),
            width: W,
            height: H,
            row_pitch: 0,
            format: MMI_TEXEL_U8,
        },
        material,
        uvs: VERTICES.as_ptr(),
        vertex_count: 6,
        uv_stride: 12,
        indices: INDICES.as_ptr(),
        index_count: INDICES.len(),
        vertex_alpha: if case.vertex_alpha {
            VERTICES[2..].as_ptr()
        } else {
            ptr::null()
        },
        vertex_alpha_stride: 12,
        uv_transform: std::ptr::null(),
    }
}

/// The C bake's (data, records, 32-bit indices) at level 5.
fn bake(mesh: &mmi_mesh) -> (Vec<u8>, Vec<u8>, Vec<u8>) {
    let mut options = mmi_bake_options::default();
    let mut result = ptr::null_mut();
    let (mut p, mut n) = (ptr::null(), 0);
    // SAFETY: valid pointers; the lent memory is copied before the free.
    unsafe {
        assert_eq!(mmi_bake_options_default(&mut options), MMI_OK);
        options.level = 5;
        assert_eq!(mmi_bake(mesh, 1, &options, &mut result), MMI_OK);
        assert_eq!(mmi_bake_result_data(result, &mut p, &mut n), MMI_OK);
        let data = std::slice::from_raw_parts(p, n).to_vec();
        assert_eq!(
            mmi_bake_result_triangle_records(result, &mut p, &mut n),
            MMI_OK
        );
        let records = std::slice::from_raw_parts(p, n).to_vec();
        let mut indices = vec![0u8; 64];
        assert_eq!(
            mmi_bake_result_indices(result, 0, 32, indices.as_mut_ptr(), 64, &mut n),
            MMI_OK
        );
        indices.truncate(n);
        mmi_bake_result_free(result);
        (data, records, indices)
    }
}

/// `mmi_verify` with room for `capacity` witnesses.
fn c_verify(
    mesh: &mmi_mesh,
    buffers: &(Vec<u8>, Vec<u8>, Vec<u8>),
    capacity: usize,
) -> (mmi_verify_report, Vec<mmi_contradiction>) {
    let view = mmi_buffers_view {
        data: buffers.0.as_ptr(),
        data_len: buffers.0.len(),
        records: buffers.1.as_ptr(),
        records_len: buffers.1.len(),
        usage_counts: ptr::null(),
        usage_counts_len: 0,
        indices: buffers.2.as_ptr(),
        indices_len: buffers.2.len(),
        index_width_bits: 32,
        record_stride: 0,
        index_stride: 0,
    };
    let mut report = mmi_verify_report::default();
    let mut witnesses = vec![mmi_contradiction::default(); capacity];
    // SAFETY: valid pointers; the arrays outlive the call.
    let code = unsafe {
        mmi_verify(
            mesh,
            &view,
            &mut report,
            witnesses.as_mut_ptr(),
            witnesses.len(),
        )
    };
    assert_eq!(code, MMI_OK);
    witnesses.truncate(report.witnesses_written as usize);
    (report, witnesses)
}

/// The library's verification of the same buffers: (triangles checked,
/// known, unknown, undecided, contradictions) and every contradiction's
/// (triangle, micro-triangle, texel).
fn library_verify(
    t8: &[u8],
    case: &Case,
    buffers: &(Vec<u8>, Vec<u8>, Vec<u8>),
) -> ([u64; 5], Vec<Seen>) {
    let texture = Unorm8Texture::new(W, H, t8).unwrap();
    let alphas: Vec<[f32; 3]> = INDICES
        .chunks_exact(3)
        .map(|c| [0, 1, 2].map(|k| VERTICES[3 * c[k] as usize + 2]))
        .collect();
    let mesh = Mesh {
        triangles: MeshTriangles::Indexed {
            indices: &INDICES,
            uvs: &VERTICES,
            stride: 3,
        },
        texture: &texture,
        material: Material {
            sampler: micromap_index::bake::Sampler {
                filter: micromap_index::bake::Filter::Linear,
                ..micromap_index::bake::Sampler::default()
            },
            alpha_factor: case.alpha_factor,
            uv_transform: micromap_index::bake::UvTransform::IDENTITY,
            ..Material::default()
        },
        vertex_alpha: case.vertex_alpha.then_some(&alphas[..]),
    };
    let read = read_buffers(
        &BufferBytes {
            records: &buffers.1,
            data: &buffers.0,
            usage_counts: None,
            indices: Some((&buffers.2, IndexWidth::U32)),
        },
        &ReadOptions {
            overlap: Overlap::Allow {
                max_decoded_bytes: 1 << 32,
            },
            ..ReadOptions::default()
        },
    )
    .unwrap();
    let opacities: Vec<TriangleOpacity<'_>> = read
        .indices
        .unwrap()
        .iter()
        .map(|i| match *i {
            MicromapIndex::Record(r) => TriangleOpacity::Micromap(&read.micromaps[r as usize]),
            MicromapIndex::Special(s) => TriangleOpacity::Special(s),
        })
        .collect();
    let mut found = Vec::new();
    let v = verify_mesh(
        &mesh,
        &opacities,
        &MeshOptions {
            model: Model::GpuBinary32,
            ..MeshOptions::default()
        },
        u64::MAX,
        &mut |t, c| {
            let texel = c.texel.unwrap_or((u32::MAX, u32::MAX));
            found.push((t as u64, c.micro_triangle, texel.0, texel.1));
        },
    )
    .unwrap();
    (
        [
            v.triangles_checked as u64,
            v.known,
            v.unknown,
            v.undecided,
            v.contradictions,
        ],
        found,
    )
}

fn numbers(r: &mmi_verify_report) -> [u64; 5] {
    [
        r.triangles_checked,
        r.known,
        r.unknown,
        r.undecided,
        r.contradictions,
    ]
}

fn seen(witnesses: &[mmi_contradiction]) -> Vec<Seen> {
    witnesses
        .iter()
        .map(|w| {
            let texel = if w.has_texel == 1 {
                (w.texel_x, w.texel_y)
            } else {
                (u32::MAX, u32::MAX)
            };
            (w.triangle, w.micro_triangle, texel.0, texel.1)
        })
        .collect()
}

#[test]
fn each_material_verifies_as_the_library_does() {
    let t8 = texels();
    let plain = bake(&c_mesh(&t8, &CASES[0]));
    for case in &CASES {
        let mesh = c_mesh(&t8, case);
        // Its own bake is sound, as the library says.
        let own = bake(&mesh);
        let (report, _) = c_verify(&mesh, &own, 8);
        let (library, _) = library_verify(&t8, case, &own);
        assert_eq!(numbers(&report), library, "{}", case.name);
        assert_eq!(report.contradictions, 0, "{}", case.name);
        assert!(report.known > 0, "{}", case.name);
        assert_eq!(report.triangles, 3);
        // The plain bake under this material: contradicted wherever the
        // material lowers the alpha below the cutoff, witness for witness
        // as the library finds them.
        let (report, witnesses) = c_verify(&mesh, &plain, 1000);
        let (library, found) = library_verify(&t8, case, &plain);
        assert_eq!(numbers(&report), library, "{}", case.name);
        assert_eq!(seen(&witnesses), found, "{}", case.name);
        if case.name == "plain" {
            assert_eq!(report.contradictions, 0);
        } else {
            assert!(report.contradictions > 3, "{}", case.name);
            // A capacity of 2 keeps the first two and counts them all.
            let (few, kept) = c_verify(&mesh, &plain, 2);
            assert_eq!(numbers(&few), library, "{}", case.name);
            assert_eq!(few.witnesses_written, 2);
            assert_eq!(seen(&kept), found[..2], "{}", case.name);
        }
    }
}
