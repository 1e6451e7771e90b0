//! `verify-bake --texture T --triangles TRIS --micromaps DIR`: bake's
//! buffer layout (any baker's) read and checked as `micromap::read_buffers`
//! does, then every triangle's map against the texture by `verify_mesh`.

use super::chunked::verify_with_progress;
use super::verdict::{verdict, witness_and_texel, witness_texel_space};
use crate::inputs::files::{read_buffer_files, read_file, BufferFiles, DATA_FILE_LIMIT};
use crate::inputs::sampler::sampler_options;
use crate::inputs::sampler::TextureUnitJson;
use crate::inputs::{index_width, read_input};
use crate::progress::Progress;
use cli_support::args::Parsed;
use cli_support::output::{Exit, Failure};
use micromap_index::bake::mesh::{
    Material, Mesh, MeshBakeError, MeshOptions, MeshTriangles, MeshVerifyError,
};
use micromap_index::bake::AlphaTexture;
use micromap_index::micromap::{
    read_buffers, BufferBytes, MicromapIndex, ReadOptions, TriangleOpacity,
};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::PathBuf;

/// The most bytes `micromap-usage.bin` may hold (87,381 entries; 34 are
/// enough for every level and format).
const USAGE_FILE_LIMIT: u64 = 1 << 20;

#[derive(Serialize)]
struct ContradictionJson {
    triangle: usize,
    micro_triangle: u64,
    state: String,
    /// Exact witness in texel space: [numerator, log2 denominator] per axis.
    witness_texel_space: Option<[(String, u32); 2]>,
    witness_uv: Option<[f64; 2]>,
    texel: Option<[u32; 2]>,
    texel_alpha: f64,
}

// A JSON report: its flags are separate answers, not a state machine.
#[allow(clippy::struct_excessive_bools)]
#[derive(Serialize)]
struct VerifyJson {
    model: &'static str,
    texture_unit: TextureUnitJson,
    triangles: usize,
    triangles_checked: usize,
    known_micro_triangles: u64,
    unknown_micro_triangles: u64,
    unknown_fraction: f64,
    undecided: u64,
    /// Known micro-triangles past `--max-checks`: not checked.
    unchecked_micro_triangles: u64,
    /// Every known micro-triangle was checked (no `--max-checks` cut).
    complete: bool,
    contradictions: u64,
    first_contradictions: Vec<ContradictionJson>,
    /// Whether `micromap-usage.bin` was checked (not with `--no-usage`).
    usage_counts_checked: bool,
    /// Whether `micromap-geometry-usage.bin` was there and checked.
    geometry_usage_counts_checked: bool,
    /// Data after the last block (only accepted with `--lenient-layout`).
    trailing_data_bytes: u64,
    sound: bool,
}

/// The texture path of `verify-bake`; the flags other than the
/// micromaps' are parsed by the caller.
pub(super) fn verify_texture(
    p: &Parsed<'_>,
    judge: &MeshOptions,
    max_report: usize,
    max_checks: u64,
) -> Result<(String, Exit), Failure> {
    let dir = PathBuf::from(
        p.get("--micromaps")
            .ok_or_else(|| Failure::Usage("verify-bake needs --micromaps DIR".into()))?,
    );
    if p.get("--texture").is_none() || p.get("--triangles").is_none() {
        return Err(Failure::Usage(
            "verify-bake needs --texture and --triangles".into(),
        ));
    }
    let width = index_width(p)?;
    let s = sampler_options(p)?;
    let input = read_input(p, &s)?;
    input.refuse_any()?;
    let job = &input.jobs[0];
    let BufferFiles {
        data,
        records,
        indices: index_bytes,
    } = read_buffer_files(&dir)?;
    let lenient = p.flag("--lenient-layout");
    let usage_path = dir.join("micromap-usage.bin");
    let usage = if p.flag("--no-usage") {
        None
    } else if usage_path.exists() {
        Some(read_file(&usage_path, USAGE_FILE_LIMIT, "usage counts")?)
    } else {
        return Err(Failure::Malformed(format!(
            "{} is missing: the usage counts are checked against the records \
             (--no-usage skips the check, for bakers that write none)",
            usage_path.display()
        )));
    };
    let read = read_buffers(
        &BufferBytes {
            records: &records,
            data: &data,
            usage_counts: usage.as_deref(),
            indices: Some((&index_bytes, width)),
        },
        &ReadOptions {
            overlap: if lenient {
                micromap_index::micromap::Overlap::Allow {
                    max_decoded_bytes: DATA_FILE_LIMIT,
                }
            } else {
                micromap_index::micromap::Overlap::Forbid
            },
            ..ReadOptions::default()
        },
    )
    .map_err(|e| Failure::Malformed(format!("{}: {e}", dir.display())))?;
    // Data past the last block: no record reaches it (read_buffers checks
    // that every block lies inside the data, not that the data ends there).
    let used_end = read
        .records
        .iter()
        .zip(&read.micromaps)
        .map(|(r, m)| u64::from(r.data_offset) + m.as_bytes().len() as u64)
        .max()
        .unwrap_or(0);
    let trailing_data_bytes = data.len() as u64 - used_end.min(data.len() as u64);
    if trailing_data_bytes > 0 && !lenient {
        return Err(Failure::Malformed(format!(
            "{}: {trailing_data_bytes} bytes of micromap-data.bin after the last block \
             (byte {used_end}) belong to no record (--lenient-layout accepts them)",
            dir.display()
        )));
    }
    let indices = read.indices.unwrap_or_default();
    if indices.len() != job.triangles.len() {
        return Err(Failure::Malformed(format!(
            "{} has {} indices for {} triangles",
            dir.display(),
            indices.len(),
            job.triangles.len()
        )));
    }
    let geometry_usage_checked = crate::geometry_usage::verify_in(&dir, &indices, &read.records)?;
    let image = &input.images[job.image];
    let textures = input.textures()?;
    let texture = &textures[job.image];
    // The texture path's material: its sampler and cutoff, alpha factor 1.
    let mesh = Mesh {
        triangles: MeshTriangles::Uv(&job.triangles),
        texture,
        material: Material {
            sampler: job.sampler,
            cutoff: job.cutoff,
            alpha_factor: job.factor,
            uv_transform: job.uv_transform,
        },
        vertex_alpha: None,
    };
    let opacities: Vec<TriangleOpacity<'_>> = indices
        .iter()
        .map(|index| match *index {
            MicromapIndex::Record(r) => TriangleOpacity::Micromap(&read.micromaps[r as usize]),
            MicromapIndex::Special(state) => TriangleOpacity::Special(state),
        })
        .collect();
    let mut first = Vec::new();
    // Only the first --max-report contradictions are kept (the rest are
    // counted), so memory stays bounded however wrong the maps are.
    let total = opacities.len();
    let progress = Progress::on_stderr("verifying", "triangles", total, p.flag("--quiet"));
    let v = verify_with_progress(
        &mesh,
        &opacities,
        judge,
        max_checks,
        &mut |t, c| {
            if first.len() >= max_report {
                return;
            }
            first.push(ContradictionJson {
                triangle: t,
                micro_triangle: c.micro_triangle,
                state: c.state.to_string(),
                witness_texel_space: witness_texel_space(c.witness),
                witness_uv: c.witness.map(|w| {
                    let (u, v) = w.uv_f64(image.width, image.height);
                    [u, v]
                }),
                texel: c.texel.map(|(x, y)| [x, y]),
                texel_alpha: match c.texel {
                    Some((x, y)) => texture.alpha(x, y),
                    None => f64::from(job.sampler.border_alpha),
                },
            });
        },
        &mut |done| progress.update(done, total),
    )
    .map_err(|e| match e {
        MeshVerifyError::Mesh(MeshBakeError::Texture { error, .. }) => {
            Failure::Malformed(error.to_string())
        }
        other => Failure::Malformed(other.to_string()),
    })?;
    progress.finish();
    let mut out = VerifyJson {
        model: judge.model.name(),
        texture_unit: judge.texture_unit.into(),
        triangles: job.triangles.len(),
        triangles_checked: v.triangles_checked,
        known_micro_triangles: v.known,
        unknown_micro_triangles: v.unknown,
        unknown_fraction: 0.0,
        undecided: v.undecided,
        unchecked_micro_triangles: v.unchecked,
        complete: true,
        contradictions: v.contradictions,
        first_contradictions: first,
        usage_counts_checked: usage.is_some(),
        geometry_usage_counts_checked: geometry_usage_checked,
        trailing_data_bytes,
        sound: true,
    };
    let micro = out.known_micro_triangles + out.unknown_micro_triangles;
    out.unknown_fraction = out.unknown_micro_triangles as f64 / micro.max(1) as f64;
    out.complete = out.unchecked_micro_triangles == 0;
    out.sound = out.contradictions == 0 && out.complete;
    let exit = if out.sound {
        Exit::Success
    } else {
        Exit::Failed
    };
    let text = if p.flag("--json") {
        serde_json::to_string_pretty(&out).unwrap_or_default() + "\n"
    } else {
        let mut text = format!(
            "{}: {} triangles ({} checked), {} known and {} unknown micro-triangles (unknown fraction {:.4}), {} undecided\n",
            verdict(out.sound, out.contradictions),
            out.triangles,
            out.triangles_checked,
            out.known_micro_triangles,
            out.unknown_micro_triangles,
            out.unknown_fraction,
            out.undecided
        );
        if !out.complete {
            let _ = writeln!(
                text,
                "not checked: {} known micro-triangles past --max-checks",
                out.unchecked_micro_triangles
            );
        }
        let _ = writeln!(text, "contradictions: {}", out.contradictions);
        for c in &out.first_contradictions {
            let (mut witness, texel) = witness_and_texel(c.witness_texel_space.as_ref(), c.texel);
            if let Some([u, v]) = c.witness_uv {
                let _ = write!(witness, " = uv ({u:.9}, {v:.9})");
            }
            let _ = writeln!(
                text,
                "  triangle {} micro-triangle {} is {} but {witness} reads {texel} with alpha {}",
                c.triangle, c.micro_triangle, c.state, c.texel_alpha
            );
        }
        text
    };
    Ok((text, exit))
}
