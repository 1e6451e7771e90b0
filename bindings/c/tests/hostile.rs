//! The hostile inputs of issue 37, each in a child process under an
//! address-space cap (`ulimit -v`, Linux only): every call returns its
//! documented code and the process goes on, where the C API used to abort
//! its host (SIGABRT from an infallible allocation) or grow without bound.
//!
//! Each test runs itself again as the child (this binary, `--exact` its
//! own name, with `MMI_HOSTILE_CASE` set), so the cap holds for that case
//! alone; the parent asserts that the child exited normally. The caps are
//! chosen so that the old code's extra copy (or kept contradictions) does
//! not fit: each test says what it was.
//!
//! Large inputs are zero-filled `Vec`s: `calloc` maps them without
//! touching a page, so they cost address space, not memory, until read.

use micromap_index_capi::constants::*;
use micromap_index_capi::*;
use std::ffi::CStr;
use std::process::Command;
use std::ptr;

const CHILD: &str = "MMI_HOSTILE_CASE";
const GIB: u64 = 1 << 20; // in KiB, as `ulimit -v` counts

/// In the child: `true` (run the case). In the parent: runs this test
/// again as a child under `ulimit -v cap_kib`, asserts that it passed
/// (exited 0: no abort, no failed assertion), and returns `false`.
fn in_capped_child(name: &str, cap_kib: u64) -> bool {
    if std::env::var(CHILD).as_deref() == Ok(name) {
        return true;
    }
    if !cfg!(target_os = "linux") {
        println!("skipped: the cap needs Linux's ulimit -v");
        return false;
    }
    let exe = std::env::current_exe().unwrap();
    let output = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v {cap_kib} && exec \"$0\" --exact {name} --test-threads=1 --nocapture"
        ))
        .arg(&exe)
        .env(CHILD, name)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success() && stdout.contains("1 passed"),
        "{name} under ulimit -v {cap_kib}: {}\n{stdout}\n{}",
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
    false
}

fn last_error() -> String {
    // SAFETY: never NULL, valid until the next call on this thread.
    unsafe { CStr::from_ptr(mmi_last_error_message()) }
        .to_string_lossy()
        .into_owned()
}

fn options() -> mmi_bake_options {
    let mut o = mmi_bake_options::default();
    // SAFETY: a valid pointer.
    assert_eq!(unsafe { mmi_bake_options_default(&mut o) }, MMI_OK);
    o
}

fn material() -> mmi_material {
    let mut m = mmi_material::default();
    // SAFETY: a valid pointer.
    assert_eq!(unsafe { mmi_material_default(&mut m) }, MMI_OK);
    m
}

const TRIANGLE: [f32; 6] = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0];

fn mesh(texture: mmi_texture, uvs: &[f32]) -> mmi_mesh {
    mmi_mesh {
        texture,
        material: material(),
        uvs: uvs.as_ptr(),
        vertex_count: uvs.len() / 2,
        uv_stride: 0,
        indices: ptr::null(),
        index_count: 0,
        vertex_alpha: ptr::null(),
        vertex_alpha_stride: 0,
        uv_transform: std::ptr::null(),
    }
}

/// The code of `mmi_bake` on one mesh (a handle, if any, freed).
fn bake_code(mesh: &mmi_mesh, options: &mmi_bake_options) -> mmi_result {
    let mut result = ptr::null_mut();
    // SAFETY: valid pointers; the mesh's arrays outlive the call.
    unsafe {
        let code = mmi_bake(mesh, 1, options, &mut result);
        mmi_bake_result_free(result);
        code
    }
}

/// A 65535 x 65535 8-bit texture with a row pitch of 65536 bytes: its
/// rows are copied (4 GiB) next to the caller's 4 GiB. Under a 6 GiB cap
/// the copy cannot be had: `MMI_ERROR_OUT_OF_MEMORY`, where the
/// infallible copy aborted the process.
#[test]
fn a_pitched_u8_texture_too_large_to_copy_is_out_of_memory() {
    if !in_capped_child(
        "a_pitched_u8_texture_too_large_to_copy_is_out_of_memory",
        6 * GIB,
    ) {
        return;
    }
    let (side, pitch) = (65535usize, 65536usize);
    let texels = vec![0u8; pitch * (side - 1) + side];
    let texture = mmi_texture {
        texels: texels.as_ptr().cast(),
        width: side as u32,
        height: side as u32,
        row_pitch: pitch,
        format: MMI_TEXEL_U8,
    };
    let code = bake_code(&mesh(texture, &TRIANGLE), &options());
    assert_eq!(code, MMI_ERROR_OUT_OF_MEMORY, "{}", last_error());
    assert_eq!(
        last_error(),
        "cannot allocate 4294836225 bytes for a copy of the texture's rows"
    );
}

/// The same for `float` texels with a pitch 4 bytes wider than the row
/// (32768 x 32768: 4 GiB given, 4 GiB to copy, a 6 GiB cap).
#[test]
fn a_pitched_f32_texture_too_large_to_copy_is_out_of_memory() {
    if !in_capped_child(
        "a_pitched_f32_texture_too_large_to_copy_is_out_of_memory",
        6 * GIB,
    ) {
        return;
    }
    let side = 32768usize;
    let pitch = 4 * side + 4;
    let texels = vec![0u32; (pitch * (side - 1) + 4 * side) / 4];
    let texture = mmi_texture {
        texels: texels.as_ptr().cast(),
        width: side as u32,
        height: side as u32,
        row_pitch: pitch,
        format: MMI_TEXEL_F32,
    };
    let code = bake_code(&mesh(texture, &TRIANGLE), &options());
    assert_eq!(code, MMI_ERROR_OUT_OF_MEMORY, "{}", last_error());
}

/// 2048 triangles at level 12 would be 8 GiB of 4-state micromaps: refused
/// by the default `max_bytes` (1 GiB) before anything is baked, under a
/// 1 GiB cap (where the C API used to bake on up to 5.2 GB). A raised
/// limit is named in the message; 0 is the default.
#[test]
fn an_output_over_max_bytes_is_refused_before_the_bake() {
    if !in_capped_child("an_output_over_max_bytes_is_refused_before_the_bake", GIB) {
        return;
    }
    let texels = [0u8, 255, 255, 0];
    let texture = mmi_texture {
        texels: texels.as_ptr().cast(),
        width: 2,
        height: 2,
        row_pitch: 0,
        format: MMI_TEXEL_U8,
    };
    let uvs: Vec<f32> = TRIANGLE.repeat(2048);
    let m = mesh(texture, &uvs);
    let mut o = options();
    o.level = 12;
    assert_eq!(bake_code(&m, &o), MMI_ERROR_LIMIT, "{}", last_error());
    let estimate = 2048 * (4u64.pow(12) / 4 + 8 + 4) + 34 * 12;
    assert_eq!(
        last_error(),
        format!(
            "the output may take up to {estimate} bytes (before deduplication), over the \
             limit of 1073741824 bytes; nothing baked (mmi_bake_options.max_bytes raises the \
             limit, a byte budget or a lower level or max_level shrinks the output)"
        )
    );
    o.max_bytes = 1 << 20;
    assert_eq!(bake_code(&m, &o), MMI_ERROR_LIMIT);
    assert!(last_error().contains("limit of 1048576 bytes"));
    // Level 16 is refused by the level range first, in the library's words.
    o.level = 16;
    assert_eq!(bake_code(&m, &o), MMI_ERROR_INVALID_LEVEL);
    assert_eq!(
        last_error(),
        "level 16: expected a level 0..=12 (the highest DXR allows and Vulkan devices \
         report), or MMI_LEVEL_AUTO"
    );
}

/// A level-12 micromap whose every micro-triangle is opaque over a
/// transparent texture: 16.7 million contradictions. `mmi_verify` keeps
/// the caller's 3 and counts the rest, in well under the 1 GiB cap (the
/// old path kept them all: 1.58 GB).
#[test]
fn verify_keeps_the_callers_witnesses_and_counts_the_rest() {
    if !in_capped_child(
        "verify_keeps_the_callers_witnesses_and_counts_the_rest",
        GIB,
    ) {
        return;
    }
    let texels = [0u8];
    let texture = mmi_texture {
        texels: texels.as_ptr().cast(),
        width: 1,
        height: 1,
        row_pitch: 0,
        format: MMI_TEXEL_U8,
    };
    let m = mesh(texture, &TRIANGLE);
    // One 4-state level-12 record, every state 1 (opaque): bytes 0x55.
    let data = vec![0x55u8; 1 << 22];
    let mut records = Vec::new();
    records.extend(0u32.to_le_bytes());
    records.extend(12u16.to_le_bytes());
    records.extend(2u16.to_le_bytes());
    let indices = 0u32.to_le_bytes();
    let view = mmi_buffers_view {
        data: data.as_ptr(),
        data_len: data.len(),
        records: records.as_ptr(),
        records_len: records.len(),
        usage_counts: ptr::null(),
        usage_counts_len: 0,
        indices: indices.as_ptr(),
        indices_len: 4,
        index_width_bits: 32,
        record_stride: 0,
        index_stride: 0,
    };
    let mut report = mmi_verify_report::default();
    let mut witnesses = [mmi_contradiction::default(); 3];
    // SAFETY: valid pointers; the arrays outlive the call.
    let code = unsafe { mmi_verify(&m, &view, &mut report, witnesses.as_mut_ptr(), 3) };
    assert_eq!(code, MMI_OK, "{}", last_error());
    let all = 1u64 << 24;
    assert_eq!(
        (
            report.known,
            report.contradictions,
            report.witnesses_written
        ),
        (all, all, 3)
    );
    for w in &witnesses {
        assert_eq!(w.state, MMI_STATE_OPAQUE);
        assert_eq!((w.has_texel, w.texel_alpha), (1, 0.0));
    }
}

/// `4^16` state bytes (4 GiB) given to `mmi_tree_encode`: read in place,
/// not copied (the copy aborted at 4 GiB). Under a 6 GiB cap a state the
/// format refuses at the very end is found with its code: a byte above 3
/// by the C side, an unknown state in a 2-state map by the library.
#[test]
fn tree_encode_reads_level_16_states_in_place() {
    if !in_capped_child("tree_encode_reads_level_16_states_in_place", 6 * GIB) {
        return;
    }
    let mut states = vec![0u8; 1 << 32];
    let last = states.len() - 1;
    let mut tree = ptr::null_mut();
    let mut encode = |states: &[u8]| {
        // SAFETY: valid pointers; the states outlive the call.
        unsafe {
            mmi_tree_encode(
                MMI_TREE_PAPER,
                16,
                MMI_FORMAT_2_STATE,
                states.as_ptr(),
                states.len(),
                &mut tree,
            )
        }
    };
    states[last] = 4;
    assert_eq!(encode(&states), MMI_ERROR_INVALID_ENUM);
    assert_eq!(
        last_error(),
        format!("states[{last}] = 4: expected a state 0..=3")
    );
    states[last] = MMI_STATE_UNKNOWN_TRANSPARENT as u8;
    assert_eq!(
        encode(&states),
        MMI_ERROR_INVALID_ARGUMENT,
        "{}",
        last_error()
    );
    assert!(tree.is_null());
}
