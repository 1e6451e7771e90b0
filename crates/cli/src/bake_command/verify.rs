//! `micromap-index verify-bake`: any baker's micromaps (bake's buffer
//! layout, or a glTF's own `EXT_mesh_opacity_micromap`, in `gltf_out`)
//! checked against the texture under the sampler model.

use super::inputs::{
    flags, index_width, model_option, read_buffer_files, read_file, read_input, sampler_options,
    BufferFiles, DATA_FILE_LIMIT,
};
use crate::args::{Command, Flag};
use crate::output::{print_then, Exit, Failure};
use micromap_index::bake::{AlphaTexture, Baker, TexelPoint};
use micromap_index::micromap::{
    read_buffers, BufferBytes, MicromapIndex, ReadOptions, TriangleOpacity,
};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::PathBuf;

/// The flag table of `verify-bake`.
pub(crate) static VERIFY_BAKE: Command = Command {
    name: "verify-bake",
    forms: &[
        "--texture T.png --triangles TRIS.json --micromaps DIR [options]",
        "--gltf ASSET.gltf|.glb [options]",
    ],
    about: "  Checks any baker's micromaps (DIR/micromap-data.bin, micromap-triangles.bin,
  micromap-indices.bin in bake's layout) against the texture: every
  micro-triangle with a known state whose closed area can read a texel of
  the other class under the sampler model is reported with an exact witness
  point (texel coordinates as n/2^k), the texel and its alpha. Unknown
  states are never wrong.
  Every contradiction is counted; only the first --max-report N (default
  20) are kept and printed, so memory stays bounded. --max-checks N stops
  checking after N known micro-triangles (default: no cap); the rest are
  reported as not checked and the verdict is INCOMPLETE (exit 1), never
  sound.
  The layout is checked first, as micromap::read_buffers does: the usage
  counts (DIR/micromap-usage.bin, required unless --no-usage) against the
  records, no two blocks overlapping and no data after the last block
  (--lenient-layout accepts both). Each buffer file is read up to a limit
  named in its error (data 5 GiB, records and indices 1 GiB, usage counts
  1 MiB; --texture and --triangles 1 GiB). DIR/micromap-geometry-usage.bin,
  when present, its geometries' counts, summed, must match the indices.
  With --gltf, the asset's own EXT_mesh_opacity_micromap micromaps (as bake
  --gltf-out writes them; the extension's rules checked first) against its
  MASK primitives' textures, samplers, cutoffs, alpha factors and vertex
  alpha; a primitive with micromaps but no such material makes the verdict
  INCOMPLETE.
  Exit 0 sound; 1 contradictions found or INCOMPLETE; 2 bad options or
  malformed buffers (a layout error, a file over its limit); 3 unreadable
  input.",
    flags: &{
        const GROUPS: &[&[Flag]] = &[
            &[
                Flag::value("--texture", "T.png", "the alpha texture (PNG or JPEG)"),
                Flag::value(
                    "--triangles",
                    "TRIS.json",
                    "the UV triangles the micromaps are for",
                ),
                Flag::value("--micromaps", "DIR", "the buffers, in bake's layout"),
                Flag::value(
                    "--gltf",
                    "ASSET",
                    "a glTF with EXT_mesh_opacity_micromap, checked against itself",
                ),
            ],
            &flags::SAMPLER,
            &[
                flags::INDEX_WIDTH,
                Flag::switch("--json", "the report as JSON"),
                Flag::value(
                    "--max-report",
                    "N",
                    "contradictions kept and listed (default 20)",
                ),
                Flag::value(
                    "--max-checks",
                    "N",
                    "known micro-triangles checked at most (default: all)",
                ),
                Flag::switch(
                    "--no-usage",
                    "no micromap-usage.bin to check (other bakers' outputs)",
                ),
                Flag::switch(
                    "--lenient-layout",
                    "accept overlapping blocks and trailing data",
                ),
            ],
        ];
        crate::args::concat::<{ crate::args::total(GROUPS) }>(GROUPS)
    },
};

/// The most bytes `micromap-usage.bin` may hold (87,381 entries; 34 are
/// enough for every level and format).
const USAGE_FILE_LIMIT: u64 = 1 << 20;

pub(crate) fn run(options: &[&str]) -> Exit {
    crate::output::finish(verify(options).map(|(text, exit)| print_then(&text, exit)))
}

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

fn verify(options: &[&str]) -> Result<(String, Exit), Failure> {
    let p = VERIFY_BAKE
        .parse(options)
        .map_err(|error| Failure::Usage(error.message("verify-bake")))?;
    let max_report: usize = p
        .get("--max-report")
        .unwrap_or("20")
        .parse()
        .map_err(|_| Failure::Malformed("--max-report: expected a count".into()))?;
    let max_checks = match p.get("--max-checks") {
        None => u64::MAX,
        Some(text) => text
            .parse()
            .map_err(|_| Failure::Malformed(format!("--max-checks {text:?}: expected a count")))?,
    };
    let model = model_option(&p)?;
    if let Some(asset) = p.get("--gltf") {
        return crate::gltf_out::verify_gltf(&p, asset, model, max_report, max_checks);
    }
    let dir = PathBuf::from(
        p.get("--micromaps")
            .ok_or_else(|| Failure::Usage("verify-bake needs --micromaps DIR".into()))?,
    );
    if p.get("--texture").is_none() || p.get("--triangles").is_none() {
        return Err(Failure::Usage(
            "verify-bake needs --texture and --triangles".into(),
        ));
    }
    let width = index_width(&p)?;
    let s = sampler_options(&p)?;
    let input = read_input(&p, &s)?;
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
    // The texture path has no alpha factor.
    let texture = image
        .texture()
        .map_err(|e| Failure::Malformed(e.to_string()))?;
    let baker = Baker::new(&texture, job.sampler, job.cutoff)
        .map_err(|e| Failure::Malformed(e.to_string()))?
        .with_model(model);
    let mut out = VerifyJson {
        model: model.name(),
        triangles: job.triangles.len(),
        triangles_checked: 0,
        known_micro_triangles: 0,
        unknown_micro_triangles: 0,
        unknown_fraction: 0.0,
        undecided: 0,
        unchecked_micro_triangles: 0,
        complete: true,
        contradictions: 0,
        first_contradictions: Vec::new(),
        usage_counts_checked: usage.is_some(),
        geometry_usage_counts_checked: geometry_usage_checked,
        trailing_data_bytes,
        sound: true,
    };
    for (t, (uv, index)) in job.triangles.iter().zip(&indices).enumerate() {
        let opacity = match *index {
            MicromapIndex::Record(r) => TriangleOpacity::Micromap(&read.micromaps[r as usize]),
            MicromapIndex::Special(state) => TriangleOpacity::Special(state),
        };
        // Only the first --max-report contradictions are kept (the rest are
        // counted), so memory stays bounded however wrong the maps are.
        let first = &mut out.first_contradictions;
        let remaining = max_checks.saturating_sub(out.known_micro_triangles);
        let v = baker.verify_each(uv, &opacity, remaining, |c| {
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
        });
        out.triangles_checked += usize::from(v.checked);
        out.known_micro_triangles += v.known;
        out.unchecked_micro_triangles += v.unchecked;
        out.unknown_micro_triangles += v.unknown;
        out.undecided += v.undecided;
        out.contradictions += v.contradictions;
    }
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

/// The verdict's word: `sound`, `INCOMPLETE` (nothing contradicted, but not
/// everything checked) or `NOT SOUND`.
pub(crate) fn verdict(sound: bool, contradictions: u64) -> &'static str {
    if sound {
        "sound"
    } else if contradictions == 0 {
        "INCOMPLETE"
    } else {
        "NOT SOUND"
    }
}

/// A contradiction's exact witness in texel space, as the JSON reports give
/// it: (numerator, log2 denominator) per axis.
pub(crate) fn witness_texel_space(witness: Option<TexelPoint>) -> Option<[(String, u32); 2]> {
    witness.map(|w| [(w.x.to_string(), w.shift_x), (w.y.to_string(), w.shift_y)])
}

/// A contradiction's witness (as [`witness_texel_space`] gives it) and
/// texel, as the text reports name them.
pub(crate) fn witness_and_texel(
    witness: Option<&[(String, u32); 2]>,
    texel: Option<[u32; 2]>,
) -> (String, String) {
    let witness = match witness {
        Some([(x, sx), (y, sy)]) => format!("texel-space point ({x}/2^{sx}, {y}/2^{sy})"),
        None => "no exact point (block search)".into(),
    };
    let texel = match texel {
        Some([x, y]) => format!("texel ({x}, {y})"),
        None => "the border".into(),
    };
    (witness, texel)
}
