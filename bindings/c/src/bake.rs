//! Baking meshes into API buffers owned by a handle
//! (`bake::mesh::bake_meshes`): the options (levels by the library's
//! `bake_level`, the output limit `max_bytes`), the bake, and the result's
//! accessors.

use crate::constants::{
    MMI_ALL_GEOMETRIES, MMI_DEFAULT_MAX_BYTES, MMI_INTERPOLATION_F16, MMI_INTERPOLATION_F32,
    MMI_LEVEL_AUTO, MMI_LINEAR_FOOTPRINT, MMI_LINEAR_VALUE, MMI_MODEL_GPU_BINARY32,
};
use crate::ffi::{
    copy_out, guard, lend, mmi_result, null, reference, slice, try_vec, write, Error, Result,
    MMI_ERROR_INVALID_ARGUMENT, MMI_ERROR_INVALID_LEVEL, MMI_ERROR_LIMIT,
};
use crate::mesh::{enum_error, format, mesh_error, mmi_mesh, model, MeshInput};
use micromap_index::bake::mesh::{
    bake_meshes, output_bytes_bound, LevelRule, Mesh, MeshBake, MeshOptions,
};
use micromap_index::bake::{Interpolation, LinearRule, TextureUnit, DEFAULT_BLOCK_BUDGET};
use micromap_index::micromap::{usage_counts_to_le_bytes, IndexWidth, UnknownPolicy};
use micromap_index::Level;

/// How `mmi_bake` bakes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct mmi_bake_options {
    /// A fixed level 0..=12 (`MMI_MAX_BAKE_LEVEL`) for every triangle, or
    /// `MMI_LEVEL_AUTO`.
    pub level: u32,
    /// With `MMI_LEVEL_AUTO`: the highest level chosen, 0..=12.
    pub max_level: u32,
    /// `MMI_FORMAT_2_STATE` or `MMI_FORMAT_4_STATE`.
    pub format: u32,
    /// 2-state: what unknowns become (`MMI_UNKNOWN_*`).
    pub unknown: u32,
    /// Non-zero: at most `budget_bytes` of micromap data for all meshes
    /// together (the highest levels are lowered first).
    pub use_budget: u32,
    /// Block tests a micro-triangle may use (0 means the library's default).
    pub block_budget: u32,
    /// The byte budget, with `use_budget`.
    pub budget_bytes: u64,
    /// Which hits known states hold for: `MMI_MODEL_GPU_BINARY32` (the
    /// default, 0) or `MMI_MODEL_EXACT` (`docs/bake.md`).
    pub model: u32,
    /// Padding, 0.
    pub reserved: u32,
    /// Non-zero: no geometry mixes special indices with records (Vulkan
    /// KHR's "no mixed special indices", `micromap-index bake
    /// --no-mixed-special`): in a geometry that references any record,
    /// each special index becomes a shared level-0 record of its state. 0
    /// (the default): special indices wherever a triangle is uniform.
    pub no_mixed_special_indices: u32,
    /// Padding, 0.
    pub reserved2: u32,
    /// Refuse the bake (`MMI_ERROR_LIMIT`, before any micro-triangle is
    /// baked) when its output may exceed this many bytes
    /// (`bake::mesh::output_bytes_bound`: every triangle's micromap at its
    /// chosen level before deduplication, records, 32-bit indices, usage
    /// counts); 0 means `MMI_DEFAULT_MAX_BYTES` (1 GiB), as `micromap-index
    /// bake --max-bytes`.
    pub max_bytes: u64,
    /// The texture unit's sub-texel bits: texel coordinates snap to
    /// multiples of `2^-k` texels, 4..=16; 0 means 8 (the default;
    /// `docs/bake.md`, "The texture unit").
    pub subtexel_bits: u32,
    /// `MMI_INTERPOLATION_F32` (the default, 0) or `MMI_INTERPOLATION_F16`.
    pub interpolation: u32,
    /// `MMI_LINEAR_VALUE` (the default, 0) or `MMI_LINEAR_FOOTPRINT`.
    pub linear_rule: u32,
    /// The largest error of a linear filter's result, in alpha units,
    /// `(0, 1]`; 0 means `2^-7` (the default).
    pub filter_error: f32,
}

/// What `mmi_bake` found, over all meshes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct mmi_bake_stats {
    /// Triangles baked.
    pub triangles: u64,
    /// Entries of `levels` used (the highest level used plus one).
    pub level_count: u32,
    /// Padding, 0.
    pub reserved: u32,
    /// Triangles per chosen level.
    pub levels: [u64; 17],
    /// Micro-triangles per state (`MMI_STATE_*`), before a 2-state format
    /// resolves the unknowns.
    pub counts: [u64; 4],
    /// Triangles baked exactly.
    pub status_exact: u64,
    /// Triangles with a coordinate that is not finite.
    pub status_not_finite: u64,
    /// Triangles off the exact grid.
    pub status_out_of_exact_range: u64,
    /// Triangles where the block budget ran out.
    pub status_budget_exceeded: u64,
    /// Triangles where the work budget ran out (the rest unknown).
    pub status_work_budget_exceeded: u64,
    /// Known micro-triangles over all micro-triangles.
    pub known_fraction: f64,
    /// The known fraction weighted by texel area.
    pub known_area_fraction: f64,
    /// Distinct micromaps after deduplication.
    pub micromaps: u64,
    /// Triangles given a special index.
    pub special_index_triangles: u64,
    /// Bytes of packed micromap data.
    pub bytes_flat: u64,
    /// Bytes as the paper's succinct trees.
    pub bytes_paper_tree: u64,
    /// Bytes as level-order trees.
    pub bytes_level_order_tree: u64,
    /// Unknown micro-triangles that `MMI_MODEL_EXACT` would know: the GPU
    /// model's widening cost (0 under `MMI_MODEL_EXACT`).
    pub widened: u64,
}

/// A finished bake: the buffers, their serialised forms and the report.
/// Opaque to C; freed by `mmi_bake_result_free`.
pub struct mmi_bake_result {
    bake: MeshBake,
    records: Vec<u8>,
    usage: Vec<u8>,
}

// The header's `MMI_MAX_BAKE_LEVEL` is the library's range.
const _: () = assert!(crate::constants::MMI_MAX_BAKE_LEVEL == micromap_index::bake::MAX_BAKE_LEVEL);

/// `value` checked by the library's one bake-level rule
/// (`bake::bake_level`, 0..=`MAX_BAKE_LEVEL`), its words in the message.
fn bake_level(value: u32, what: &str, or: &str) -> Result<Level> {
    micromap_index::bake::bake_level(value)
        .map_err(|e| Error::new(MMI_ERROR_INVALID_LEVEL, format!("{what} {value}: {e}{or}")))
}

fn options(o: &mmi_bake_options) -> Result<MeshOptions> {
    Ok(MeshOptions {
        levels: if o.level == MMI_LEVEL_AUTO {
            LevelRule::Useful {
                max: bake_level(o.max_level, "max_level", "")?,
            }
        } else {
            LevelRule::Fixed(bake_level(o.level, "level", ", or MMI_LEVEL_AUTO")?)
        },
        format: format(o.format)?,
        unknown: match o.unknown {
            0 => UnknownPolicy::Fallback,
            1 => UnknownPolicy::Opaque,
            2 => UnknownPolicy::Transparent,
            other => {
                return Err(enum_error(
                    "unknown",
                    other,
                    "an MMI_UNKNOWN_* value (0..=2)",
                ))
            }
        },
        budget_bytes: (o.use_budget != 0).then_some(o.budget_bytes),
        block_budget: if o.block_budget == 0 {
            DEFAULT_BLOCK_BUDGET
        } else {
            o.block_budget
        },
        model: model(o.model)?,
        // Level 0, the library's default (the C options have no mip rule).
        mips: micromap_index::bake::mesh::Mips::Level0,
        // The library's defaults for the work budgets (docs/bake.md,
        // "Bounded work"); the C options do not offer them yet, and
        // mmi_bake_stats counts the triangles they cut.
        triangle_work_budget: micromap_index::bake::DEFAULT_TRIANGLE_WORK_BUDGET,
        bake_work_budget: micromap_index::bake::DEFAULT_BAKE_WORK_BUDGET,
        // On the caller's thread: the C API starts no threads (the library
        // is built without its `rayon` feature here, so this is also what
        // the default would do).
        threads: micromap_index::bake::Threads::Exactly(1),
        texture_unit: texture_unit(o)?,
        // Special indices as the library writes them by default, unless
        // the caller's pipeline disallows mixing them with records.
        buffers: micromap_index::micromap::BuildOptions {
            no_mixed_special_indices: o.no_mixed_special_indices != 0,
            ..micromap_index::micromap::BuildOptions::default()
        },
    })
}

/// The texture unit of `o` (0 fields mean the library's defaults), checked
/// by the library's ranges.
pub(crate) fn texture_unit(o: &mmi_bake_options) -> Result<TextureUnit> {
    let default = TextureUnit::default();
    let interpolation = match o.interpolation {
        MMI_INTERPOLATION_F32 => Interpolation::F32,
        MMI_INTERPOLATION_F16 => Interpolation::F16,
        other => {
            return Err(enum_error(
                "interpolation",
                other,
                "an MMI_INTERPOLATION_* value (0..=1)",
            ))
        }
    };
    let linear = match o.linear_rule {
        MMI_LINEAR_VALUE => LinearRule::Value,
        MMI_LINEAR_FOOTPRINT => LinearRule::Footprint,
        other => {
            return Err(enum_error(
                "linear_rule",
                other,
                "an MMI_LINEAR_* value (0..=1)",
            ))
        }
    };
    let unit = default
        .with_subtexel_bits(if o.subtexel_bits == 0 {
            default.subtexel_bits
        } else {
            o.subtexel_bits
        })
        .with_interpolation(interpolation)
        .with_linear_rule(linear)
        .with_filter_error(if o.filter_error == 0.0 {
            default.filter_error
        } else {
            o.filter_error
        });
    unit.check()
        .map_err(|e| Error::new(MMI_ERROR_INVALID_ARGUMENT, e.to_string()))
}

/// The limit on a bake's estimated output: `max_bytes`, or
/// `MMI_DEFAULT_MAX_BYTES` for 0.
fn max_bytes(o: &mmi_bake_options) -> u64 {
    match o.max_bytes {
        0 => MMI_DEFAULT_MAX_BYTES,
        n => n,
    }
}

/// The defaults: level `MMI_LEVEL_AUTO` up to 12, 4-state, fallback for
/// unknowns, no byte budget, the library's block budget, the GPU binary32
/// model, special indices mixed with records, an output of at most
/// `MMI_DEFAULT_MAX_BYTES` (the CLI's `micromap-index bake` defaults).
///
/// # Safety
/// `options` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_bake_options_default(options: *mut mmi_bake_options) -> mmi_result {
    guard(|| {
        let value = mmi_bake_options {
            level: MMI_LEVEL_AUTO,
            max_level: 12,
            format: 2,
            unknown: 0,
            use_budget: 0,
            block_budget: DEFAULT_BLOCK_BUDGET,
            budget_bytes: 0,
            model: MMI_MODEL_GPU_BINARY32,
            reserved: 0,
            no_mixed_special_indices: 0,
            reserved2: 0,
            max_bytes: MMI_DEFAULT_MAX_BYTES,
            subtexel_bits: 8,
            interpolation: MMI_INTERPOLATION_F32,
            linear_rule: MMI_LINEAR_VALUE,
            filter_error: TextureUnit::default().filter_error,
        };
        // SAFETY: the caller's promise about `options`.
        unsafe { write(options, value, "options") }
    })
}

/// Bakes `mesh_count` meshes exactly (`bake::mesh::bake_meshes`: one
/// geometry per mesh, micromaps deduplicated across all) into a new
/// handle written to `*result`; free it with `mmi_bake_result_free`. The
/// same inputs give the same bytes as `micromap-index bake`. On an error
/// `*result` is set to NULL. The order: options, then each mesh
/// (`MeshInput::read`), the output estimate against `max_bytes`
/// (`MMI_ERROR_LIMIT`), the bake; the codes are the header's.
///
/// # Safety
/// `meshes` must point to `mesh_count` meshes whose pointers satisfy
/// `mmi_mesh`'s description; `options` must be readable; `result`
/// writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_bake(
    meshes: *const mmi_mesh,
    mesh_count: usize,
    options: *const mmi_bake_options,
    result: *mut *mut mmi_bake_result,
) -> mmi_result {
    guard(|| {
        // SAFETY: the caller's promise about `result`.
        unsafe { write(result, core::ptr::null_mut(), "result") }?;
        // SAFETY: the caller's promises about `meshes` and `options`.
        let (meshes, options) = unsafe {
            (
                slice(meshes, mesh_count, "meshes")?,
                reference(options, "options")?,
            )
        };
        let limit = max_bytes(options);
        let options = self::options(options)?;
        let mut inputs = try_vec(meshes.len(), "the meshes")?;
        for m in meshes {
            // SAFETY: the caller's promise about each mesh's pointers.
            inputs.push(unsafe { MeshInput::read(m) }?);
        }
        let mut textures = try_vec(inputs.len(), "the textures")?;
        for input in &inputs {
            textures.push(input.texture()?);
        }
        let mut library_meshes: Vec<Mesh<'_>> = try_vec(inputs.len(), "the meshes")?;
        library_meshes.extend(inputs.iter().zip(&textures).map(|(i, t)| i.mesh(&**t)));
        // The output's size before deduplication (an upper bound), from the
        // levels bake_meshes chooses, checked before any micro-triangle is
        // baked, as `micromap-index bake --max-bytes` does.
        let estimate = output_bytes_bound(&library_meshes, &options, IndexWidth::U32)
            .map_err(|e| mesh_error(&e))?;
        if estimate > limit {
            return Err(Error::new(
                MMI_ERROR_LIMIT,
                format!(
                    "the output may take up to {estimate} bytes (before deduplication), over \
                     the limit of {limit} bytes; nothing baked (mmi_bake_options.max_bytes \
                     raises the limit, a byte budget or a lower level or max_level shrinks \
                     the output)"
                ),
            ));
        }
        let bake =
            bake_meshes(&library_meshes, &options, &mut |_, _| {}).map_err(|e| mesh_error(&e))?;
        let handle = Box::new(mmi_bake_result {
            records: bake.buffers.records_le_bytes(),
            usage: usage_counts_to_le_bytes(bake.buffers.usage_counts()),
            bake,
        });
        // SAFETY: checked writable above.
        unsafe { write(result, Box::into_raw(handle), "result") }
    })
}

/// # Safety
/// `result` must be NULL or a live handle from `mmi_bake`.
unsafe fn handle<'a>(result: *const mmi_bake_result) -> Result<&'a mmi_bake_result> {
    if result.is_null() {
        return Err(null("result"));
    }
    // SAFETY: a live handle from `mmi_bake` (the caller's promise).
    Ok(unsafe { &*result })
}

/// The packed micromap data (the Vulkan/DXR/glTF layout,
/// `micromap-data.bin`): `*data` and `*len` receive memory owned by the
/// handle, valid until `mmi_bake_result_free`.
///
/// # Safety
/// `result` must be NULL or a live handle; `data` and `len` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_bake_result_data(
    result: *const mmi_bake_result,
    data: *mut *const u8,
    len: *mut usize,
) -> mmi_result {
    guard(|| {
        // SAFETY: the caller's promises.
        unsafe { lend(handle(result)?.bake.buffers.data(), data, len) }
    })
}

/// The 8-byte triangle records `{u32 data offset, u16 level, u16 format}`,
/// little endian (`micromap-triangles.bin`), owned by the handle.
///
/// # Safety
/// As `mmi_bake_result_data`.
#[no_mangle]
pub unsafe extern "C" fn mmi_bake_result_triangle_records(
    result: *const mmi_bake_result,
    data: *mut *const u8,
    len: *mut usize,
) -> mmi_result {
    guard(|| {
        // SAFETY: the caller's promises.
        unsafe { lend(&handle(result)?.records, data, len) }
    })
}

/// The 12-byte usage counts `{u32 count, u32 level, u32 format}`, little
/// endian (`micromap-usage.bin`), owned by the handle.
///
/// # Safety
/// As `mmi_bake_result_data`.
#[no_mangle]
pub unsafe extern "C" fn mmi_bake_result_usage_counts(
    result: *const mmi_bake_result,
    data: *mut *const u8,
    len: *mut usize,
) -> mmi_result {
    guard(|| {
        // SAFETY: the caller's promises.
        unsafe { lend(&handle(result)?.usage, data, len) }
    })
}

/// The number of geometries (one per baked mesh).
///
/// # Safety
/// `result` must be NULL or a live handle; `count` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_bake_result_geometry_count(
    result: *const mmi_bake_result,
    count: *mut usize,
) -> mmi_result {
    guard(|| {
        // SAFETY: the caller's promises.
        unsafe {
            write(
                count,
                handle(result)?.bake.buffers.geometry_count(),
                "count",
            )
        }
    })
}

/// Whether `geometry`'s index buffer holds both special indices and
/// records (`micromap::MicromapBuffers::is_mixed`): `*mixed` receives 1 if
/// so, else 0. A Vulkan KHR pipeline created with
/// `VK_PIPELINE_CREATE_2_OPACITY_MICROMAP_DISALLOW_MIXED_SPECIAL_INDEX_BIT_KHR`
/// must not trace a mixed geometry; never 1 after a bake with
/// `no_mixed_special_indices`. A geometry past the last one is
/// `MMI_ERROR_INVALID_ARGUMENT`.
///
/// # Safety
/// `result` must be NULL or a live handle; `mixed` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_bake_result_is_mixed(
    result: *const mmi_bake_result,
    geometry: usize,
    mixed: *mut u32,
) -> mmi_result {
    guard(|| {
        // SAFETY: the caller's promise about `result`.
        let buffers = &unsafe { handle(result) }?.bake.buffers;
        let value = buffers
            .is_mixed(geometry)
            .map_err(|e| Error::new(MMI_ERROR_INVALID_ARGUMENT, e.to_string()))?;
        // SAFETY: the caller's promise about `mixed`.
        unsafe { write(mixed, u32::from(value), "mixed") }
    })
}

/// The per-triangle index buffer of `geometry` (or of every geometry,
/// concatenated, with `MMI_ALL_GEOMETRIES`, as `micromap-indices.bin`) at
/// `width_bits` 8, 16 or 32 (special indices -1..-4 as two's complement),
/// little endian, copied into the caller's buffer: `*len` receives the size
/// in bytes; with `out == NULL` that is all (a size query); a `capacity`
/// below it is `MMI_ERROR_BUFFER_TOO_SMALL`. An index too large for the
/// width is `MMI_ERROR_INVALID_ARGUMENT`; a geometry past the last one too.
///
/// # Safety
/// `result` must be NULL or a live handle; `out` NULL or `capacity`
/// writable bytes; `len` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_bake_result_indices(
    result: *const mmi_bake_result,
    geometry: usize,
    width_bits: u32,
    out: *mut u8,
    capacity: usize,
    len: *mut usize,
) -> mmi_result {
    guard(|| {
        // SAFETY: the caller's promise about `result`.
        let buffers = &unsafe { handle(result) }?.bake.buffers;
        let width = match width_bits {
            8 => IndexWidth::U8,
            16 => IndexWidth::U16,
            32 => IndexWidth::U32,
            other => return Err(enum_error("width_bits", other, "8, 16 or 32")),
        };
        let geometries = if geometry == MMI_ALL_GEOMETRIES {
            0..buffers.geometry_count()
        } else {
            geometry..geometry + 1
        };
        let mut bytes = Vec::new();
        for g in geometries {
            let geometry = buffers
                .index_bytes(g, width)
                .map_err(|e| Error::new(MMI_ERROR_INVALID_ARGUMENT, e.to_string()))?;
            if bytes.is_empty() {
                bytes = geometry;
                continue;
            }
            bytes.try_reserve_exact(geometry.len()).map_err(|_| {
                crate::ffi::out_of_memory(bytes.len() + geometry.len(), 1, "the index buffer")
            })?;
            bytes.extend(geometry);
        }
        // SAFETY: the caller's promises about `out` and `len`.
        unsafe { copy_out(&bytes, out, capacity, len, "the index buffer") }
    })
}

/// The bake's statistics (`bake::mesh::BakeReport`).
///
/// # Safety
/// `result` must be NULL or a live handle; `stats` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_bake_result_stats(
    result: *const mmi_bake_result,
    stats: *mut mmi_bake_stats,
) -> mmi_result {
    guard(|| {
        // SAFETY: the caller's promise about `result`.
        let r = &unsafe { handle(result) }?.bake.report;
        let mut levels = [0u64; 17];
        for (to, from) in levels.iter_mut().zip(&r.levels) {
            *to = *from;
        }
        let value = mmi_bake_stats {
            triangles: r.triangles as u64,
            level_count: r.levels.len().min(17) as u32,
            reserved: 0,
            levels,
            counts: r.counts,
            status_exact: r.status.exact as u64,
            status_not_finite: r.status.not_finite as u64,
            status_out_of_exact_range: r.status.out_of_exact_range as u64,
            status_budget_exceeded: r.status.block_budget_exceeded as u64,
            status_work_budget_exceeded: r.status.work_budget_exceeded as u64,
            known_fraction: r.known_fraction,
            known_area_fraction: r.known_area_fraction,
            micromaps: r.micromaps as u64,
            special_index_triangles: r.special_index_triangles as u64,
            bytes_flat: r.bytes_flat as u64,
            bytes_paper_tree: r.bytes_paper_tree,
            bytes_level_order_tree: r.bytes_level_order_tree,
            widened: r.widened,
        };
        // SAFETY: the caller's promise about `stats`.
        unsafe { write(stats, value, "stats") }
    })
}

/// Frees a handle from `mmi_bake` and everything its accessors lent; NULL
/// is ignored.
///
/// # Safety
/// `result` must be NULL or a live handle from `mmi_bake`, not used again.
#[no_mangle]
pub unsafe extern "C" fn mmi_bake_result_free(result: *mut mmi_bake_result) {
    if result.is_null() {
        return;
    }
    let _ = std::panic::catch_unwind(|| {
        // SAFETY: a live handle from `Box::into_raw` in `mmi_bake`,
        // freed once (the caller's promise).
        drop(unsafe { Box::from_raw(result) });
    });
}
