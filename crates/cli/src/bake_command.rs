//! `micromap-index bake` and `micromap-index verify-bake`: the exact baker
//! (library: `micromap_index::bake`, the whole-mesh pipeline in
//! `bake::mesh`) on real assets read by `micromap_index_assets`, and its
//! verifier on any baker's buffers. This file parses the options, reads
//! the inputs and serialises the results; `preview.rs` draws the picture.

use crate::args::Parsed;
use crate::output::{print_then, report, Exit};
use crate::write_all_or_nothing::{check_destination, write_files};
use micromap_index::bake::mesh::{
    bake_meshes, LevelRule, Material, Mesh, MeshBakeError, MeshOptions, MeshTriangles,
};
use micromap_index::bake::{
    AddressMode, AlphaTexture, Baker, Comparison, Cutoff, Filter, Model, Sampler, UvTriangle,
};
use micromap_index::micromap::{
    read_buffers, BufferBytes, Format, IndexWidth, MicromapIndex, ReadOptions, TriangleOpacity,
    UnknownPolicy,
};
use micromap_index::Level;
use micromap_index_assets::{
    decode_alpha_image, read_gltf_file, read_triangles_json, AlphaImage, AssetError, Limits,
};
use serde::Serialize;
use std::fmt::Write as _;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

pub(crate) const BAKE_USAGE: &str = "\
usage: micromap-index bake (--gltf ASSET.gltf|.glb | --texture T.png --triangles TRIS.json)
                           --out DIR [options]
Bakes opacity micromaps exactly: a micro-triangle is opaque (transparent) only
if every point of it, closed, reads only opaque (transparent) texels under the
sampler; otherwise unknown (docs/bake.md). Writes into DIR, all or nothing:
  micromap-data.bin       the packed micromaps (Vulkan/DXR/glTF layout)
  micromap-triangles.bin  8-byte records {u32 offset, u16 level, u16 format}
  micromap-indices.bin    one index per input triangle (special indices
                          -1..-4 as negative values), little endian
  micromap-usage.bin      12-byte usage counts {u32 count, u32 level, u32 format}
  summary.json            states, known fraction, micromaps, sizes, time
  preview.png             the texture with every micro-triangle coloured by
                          state (green opaque, blue transparent, yellow
                          unknown-opaque, red unknown-transparent)
options:
  --level L|auto          fixed level 0..=12, or the paper's eq. 1 per
                          triangle (default auto)
  --max-level L           cap for auto (default 12)
  --budget BYTES          auto: lower the highest levels until the data fits
  --format 2|4            micromap format (default 4)
  --unknown-as fallback|opaque|transparent
                          2-state: what unknowns become (default fallback:
                          the texel under the micro-triangle's centroid)
  --filter nearest|linear (default nearest; glTF: the sampler's magFilter)
  --address MODE          both axes: repeat, mirrored-repeat, clamp-to-edge,
                          clamp-to-border, mirror-clamp-to-edge (default
                          repeat; glTF: the sampler's wrapS/wrapT)
  --address-u MODE, --address-v MODE   one axis
  --border ALPHA          clamp-to-border alpha (default 0)
  --cutoff C              alpha cutoff (default 0.5; glTF: alphaCutoff);
                          opaque when alpha >= C (glTF MASK)
  --opaque-above          opaque when alpha > C (the OMM SDK's rule)
  --model gpu-binary32|exact
                          the points known states hold for: every binary32
                          hit a GPU assigns to the micro-triangle and the
                          texel its binary32 arithmetic reads (default), or
                          the exact real points only (docs/bake.md)
  --index-width 16|32     micromap-indices.bin width (default 32)
  --force                 replace existing files in DIR
  --no-preview            skip preview.png
  --quiet                 no progress on stderr
Exit 0 baked; 2 bad options or malformed input (nothing written); 3 unreadable
input or unwritable DIR (nothing written).";

pub(crate) const VERIFY_USAGE: &str = "\
usage: micromap-index verify-bake --texture T.png --triangles TRIS.json --micromaps DIR
                                  [sampler and cutoff options as bake] [--index-width 16|32]
                                  [--model gpu-binary32|exact]
                                  [--json] [--max-report N]
Checks any baker's micromaps (DIR/micromap-data.bin, micromap-triangles.bin,
micromap-indices.bin in bake's layout) against the texture: every micro-triangle
with a known state whose closed area can read a texel of the other class under
the sampler model is reported with an exact witness point (texel coordinates as
n/2^k), the texel and its alpha. Unknown states are never wrong.
Exit 0 sound; 1 contradictions found; 2 bad options or malformed buffers;
3 unreadable input.";

/// Output file names, in the order written.
const OUTPUTS: [&str; 6] = [
    "micromap-data.bin",
    "micromap-triangles.bin",
    "micromap-indices.bin",
    "micromap-usage.bin",
    "summary.json",
    "preview.png",
];

/// A failure, by exit code.
enum Failure {
    /// Exit 2 with the usage text.
    Usage(String),
    /// Exit 2: malformed input or a value out of range.
    Malformed(String),
    /// Exit 3: unreadable input or unwritable output.
    Io(String),
}

fn finish(outcome: Result<(String, Exit), Failure>) -> ExitCode {
    match outcome {
        Ok((text, exit)) => print_then(&text, exit).into(),
        Err(Failure::Usage(message)) => crate::usage(&message).into(),
        Err(Failure::Malformed(message)) => {
            report(message);
            Exit::Usage.into()
        }
        Err(Failure::Io(message)) => {
            report(message);
            Exit::Io.into()
        }
    }
}

/// One texture with its sampler, cutoff and triangles (a mesh to bake).
struct Job {
    name: String,
    image: usize,
    /// glTF's `baseColorFactor[3]` (1 for `--texture`).
    factor: f32,
    sampler: Sampler,
    cutoff: Cutoff,
    triangles: Vec<UvTriangle>,
}

struct Input {
    images: Vec<AlphaImage>,
    jobs: Vec<Job>,
    warnings: Vec<String>,
}

fn parse_address(text: &str) -> Result<AddressMode, Failure> {
    Ok(match text {
        "repeat" => AddressMode::Repeat,
        "mirrored-repeat" => AddressMode::MirroredRepeat,
        "clamp-to-edge" => AddressMode::ClampToEdge,
        "clamp-to-border" => AddressMode::ClampToBorder,
        "mirror-clamp-to-edge" => AddressMode::MirrorClampToEdge,
        _ => {
            return Err(Failure::Malformed(format!(
                "address mode {text:?}: expected repeat, mirrored-repeat, clamp-to-edge, clamp-to-border or mirror-clamp-to-edge"
            )))
        }
    })
}

fn address_name(mode: AddressMode) -> &'static str {
    match mode {
        AddressMode::Repeat => "repeat",
        AddressMode::MirroredRepeat => "mirrored-repeat",
        AddressMode::ClampToEdge => "clamp-to-edge",
        AddressMode::ClampToBorder => "clamp-to-border",
        AddressMode::MirrorClampToEdge => "mirror-clamp-to-edge",
    }
}

fn parse_f32(name: &str, text: &str) -> Result<f32, Failure> {
    match text.parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(Failure::Malformed(format!(
            "{name} {text:?}: expected a finite number"
        ))),
    }
}

fn parse_level(name: &str, text: &str) -> Result<Level, Failure> {
    match text.parse::<u32>() {
        Ok(level) if level <= 12 && text.bytes().all(|b| b.is_ascii_digit()) => {
            Level::new(level).map_err(|e| Failure::Malformed(e.to_string()))
        }
        _ => Err(Failure::Malformed(format!(
            "{name} {text:?}: expected a level 0..=12 (the highest DXR allows and Vulkan devices report)"
        ))),
    }
}

/// The sampler and cutoff options shared by both commands; `None` fields
/// keep the asset's own (glTF) or the default.
struct SamplerOptions {
    filter: Option<Filter>,
    address_u: Option<AddressMode>,
    address_v: Option<AddressMode>,
    border: f32,
    cutoff: Option<f32>,
    comparison: Comparison,
}

const SAMPLER_VALUED: [&str; 6] = [
    "--filter",
    "--address",
    "--address-u",
    "--address-v",
    "--border",
    "--cutoff",
];

fn sampler_options(p: &Parsed<'_>) -> Result<SamplerOptions, Failure> {
    let filter = match p.get("--filter") {
        None => None,
        Some("nearest") => Some(Filter::Nearest),
        Some("linear") => Some(Filter::Linear),
        Some(other) => {
            return Err(Failure::Malformed(format!(
                "--filter {other:?}: expected nearest or linear"
            )))
        }
    };
    let both = p.get("--address").map(parse_address).transpose()?;
    let address_u = p
        .get("--address-u")
        .map(parse_address)
        .transpose()?
        .or(both);
    let address_v = p
        .get("--address-v")
        .map(parse_address)
        .transpose()?
        .or(both);
    let border = p
        .get("--border")
        .map(|t| parse_f32("--border", t))
        .transpose()?
        .unwrap_or(0.0);
    let cutoff = p
        .get("--cutoff")
        .map(|t| parse_f32("--cutoff", t))
        .transpose()?;
    if let Some(c) = cutoff {
        if !(0.0..=1.0).contains(&c) {
            return Err(Failure::Malformed(format!(
                "--cutoff {c}: expected an alpha in [0, 1]"
            )));
        }
    }
    Ok(SamplerOptions {
        filter,
        address_u,
        address_v,
        border,
        cutoff,
        comparison: if p.flag("--opaque-above") {
            Comparison::Above
        } else {
            Comparison::AtLeast
        },
    })
}

/// `--model` (default gpu-binary32).
fn model_option(p: &Parsed<'_>) -> Result<Model, Failure> {
    match p.get("--model") {
        None => Ok(Model::default()),
        Some(text) => Model::from_name(text).ok_or_else(|| {
            Failure::Malformed(format!("--model {text:?}: expected gpu-binary32 or exact"))
        }),
    }
}

fn read_file(path: &Path) -> Result<Vec<u8>, Failure> {
    std::fs::read(path).map_err(|e| Failure::Io(format!("cannot read {}: {e}", path.display())))
}

fn read_input(p: &Parsed<'_>, s: &SamplerOptions) -> Result<Input, Failure> {
    let limits = Limits::default();
    let cutoff_of = |value: f32| {
        Cutoff::new(value, s.comparison).map_err(|e| Failure::Malformed(e.to_string()))
    };
    match (p.get("--gltf"), p.get("--texture"), p.get("--triangles")) {
        (Some(asset), None, None) => {
            let path = PathBuf::from(asset);
            let gltf = read_gltf_file(&path, &limits).map_err(|e| {
                let message = format!("{asset}: {e}");
                if matches!(e.root(), AssetError::Io { .. }) {
                    Failure::Io(message)
                } else {
                    Failure::Malformed(message)
                }
            })?;
            let mut jobs = Vec::new();
            for prim in &gltf.primitives {
                jobs.push(Job {
                    name: format!("mesh {} primitive {}", prim.mesh, prim.primitive),
                    image: prim.image,
                    factor: prim.alpha_factor,
                    sampler: Sampler {
                        filter: s.filter.unwrap_or(prim.sampler.filter),
                        address_u: s.address_u.unwrap_or(prim.sampler.address_u),
                        address_v: s.address_v.unwrap_or(prim.sampler.address_v),
                        border_alpha: s.border,
                    },
                    cutoff: cutoff_of(s.cutoff.unwrap_or(prim.cutoff.alpha()))?,
                    triangles: prim.triangles.clone(),
                });
            }
            if jobs.is_empty() {
                return Err(Failure::Malformed(format!(
                    "{asset}: no primitive with an alphaMode MASK material and a base colour texture"
                )));
            }
            Ok(Input {
                images: gltf.images,
                jobs,
                warnings: gltf.warnings,
            })
        }
        (None, Some(texture), Some(triangles)) => {
            let image = decode_alpha_image(&read_file(Path::new(texture))?, &limits)
                .map_err(|e| Failure::Malformed(format!("{texture}: {e}")))?;
            let triangles = read_triangles_json(&read_file(Path::new(triangles))?)
                .map_err(|e| Failure::Malformed(format!("{triangles}: {e}")))?;
            Ok(Input {
                images: vec![image],
                jobs: vec![Job {
                    name: texture.to_string(),
                    image: 0,
                    factor: 1.0,
                    sampler: Sampler {
                        filter: s.filter.unwrap_or_default(),
                        address_u: s.address_u.unwrap_or_default(),
                        address_v: s.address_v.unwrap_or_default(),
                        border_alpha: s.border,
                    },
                    cutoff: cutoff_of(s.cutoff.unwrap_or(0.5))?,
                    triangles,
                }],
                warnings: Vec::new(),
            })
        }
        _ => Err(Failure::Usage(
            "give either --gltf ASSET or both --texture and --triangles".into(),
        )),
    }
}

fn index_width(p: &Parsed<'_>) -> Result<IndexWidth, Failure> {
    match p.get("--index-width").unwrap_or("32") {
        "32" => Ok(IndexWidth::U32),
        "16" => Ok(IndexWidth::U16),
        other => Err(Failure::Malformed(format!(
            "--index-width {other:?}: expected 16 or 32 (the widths Vulkan accepts)"
        ))),
    }
}

#[derive(Serialize)]
struct StateCounts {
    transparent: u64,
    opaque: u64,
    unknown_transparent: u64,
    unknown_opaque: u64,
}

impl From<[u64; 4]> for StateCounts {
    /// Counts by `State::bits`.
    fn from(counts: [u64; 4]) -> Self {
        StateCounts {
            transparent: counts[0],
            opaque: counts[1],
            unknown_transparent: counts[2],
            unknown_opaque: counts[3],
        }
    }
}

impl StateCounts {
    fn total(&self) -> u64 {
        self.transparent + self.opaque + self.unknown_transparent + self.unknown_opaque
    }
}

#[derive(Serialize)]
struct JobSummary {
    name: String,
    texture: [u32; 2],
    filter: &'static str,
    address: [&'static str; 2],
    cutoff: f32,
    opaque_when: &'static str,
    triangles: usize,
    /// Index of this job's first triangle in micromap-indices.bin.
    first_index: usize,
}

#[derive(Serialize)]
struct Summary {
    triangles: usize,
    format: u32,
    model: &'static str,
    levels: Vec<u64>,
    micro_triangles: StateCounts,
    known_fraction: f64,
    known_area_fraction: f64,
    status: StatusCounts,
    micromaps_after_dedup: usize,
    special_index_triangles: usize,
    bytes_flat: usize,
    bytes_paper_tree: u64,
    bytes_level_order_tree: u64,
    index_width_bits: usize,
    bake_seconds: f64,
    micro_triangles_per_second: f64,
    jobs: Vec<JobSummary>,
    warnings: Vec<String>,
}

#[derive(Serialize)]
struct StatusCounts {
    exact: usize,
    not_finite: usize,
    out_of_exact_range: usize,
    budget_exceeded: usize,
}

impl From<micromap_index::bake::mesh::StatusCounts> for StatusCounts {
    fn from(s: micromap_index::bake::mesh::StatusCounts) -> Self {
        StatusCounts {
            exact: s.exact,
            not_finite: s.not_finite,
            out_of_exact_range: s.out_of_exact_range,
            budget_exceeded: s.budget_exceeded,
        }
    }
}

pub(crate) fn run_bake(options: &[&str]) -> ExitCode {
    finish(bake(options))
}

fn bake(options: &[&str]) -> Result<(String, Exit), Failure> {
    let mut valued = vec![
        "--gltf",
        "--texture",
        "--triangles",
        "--out",
        "--level",
        "--max-level",
        "--budget",
        "--format",
        "--unknown-as",
        "--index-width",
        "--model",
    ];
    valued.extend(SAMPLER_VALUED);
    let p = Parsed::new(
        "bake",
        options,
        &valued,
        &["--opaque-above", "--force", "--no-preview", "--quiet"],
    )
    .map_err(Failure::Usage)?;
    let out = PathBuf::from(
        p.get("--out")
            .ok_or_else(|| Failure::Usage("bake needs --out DIR".into()))?,
    );
    let format = match p.get("--format").unwrap_or("4") {
        "4" => Format::FourState,
        "2" => Format::TwoState,
        other => {
            return Err(Failure::Malformed(format!(
                "--format {other:?}: expected 2 or 4"
            )))
        }
    };
    let two_state = match p.get("--unknown-as").unwrap_or("fallback") {
        "fallback" => UnknownPolicy::Fallback,
        "opaque" => UnknownPolicy::Opaque,
        "transparent" => UnknownPolicy::Transparent,
        other => {
            return Err(Failure::Malformed(format!(
                "--unknown-as {other:?}: expected fallback, opaque or transparent"
            )))
        }
    };
    let fixed_level = match p.get("--level").unwrap_or("auto") {
        "auto" => None,
        text => Some(parse_level("--level", text)?),
    };
    let max_level = parse_level("--max-level", p.get("--max-level").unwrap_or("12"))?;
    let budget = p
        .get("--budget")
        .map(|t| {
            t.parse::<u64>()
                .map_err(|_| Failure::Malformed(format!("--budget {t:?}: expected a byte count")))
        })
        .transpose()?;
    if budget.is_some() && fixed_level.is_some() {
        return Err(Failure::Usage(
            "--budget chooses levels: it goes with --level auto".into(),
        ));
    }
    let width = index_width(&p)?;
    let model = model_option(&p)?;
    let s = sampler_options(&p)?;
    let preview = !p.flag("--no-preview");
    check_destination(&out, &OUTPUTS, p.flag("--force")).map_err(Failure::Malformed)?;
    let input = read_input(&p, &s)?;

    // The textures as the baker reads them, and one mesh per job.
    let textures = input
        .images
        .iter()
        .map(|image| {
            image
                .texture()
                .map_err(|e| Failure::Malformed(e.to_string()))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let meshes: Vec<Mesh<'_>> = input
        .jobs
        .iter()
        .map(|job| Mesh {
            triangles: MeshTriangles::Uv(&job.triangles),
            texture: &textures[job.image],
            material: Material {
                sampler: job.sampler,
                cutoff: job.cutoff,
                alpha_factor: job.factor,
            },
        })
        .collect();
    let options = MeshOptions {
        levels: match fixed_level {
            Some(level) => LevelRule::Fixed(level),
            None => LevelRule::Useful { max: max_level },
        },
        format,
        unknown: two_state,
        budget_bytes: budget,
        model,
        ..MeshOptions::default()
    };
    let show_progress = !p.flag("--quiet") && std::io::stderr().is_terminal();
    let mut progress = |done: usize, total: usize| {
        if show_progress && (done % 64 == 0 || done == total) {
            crate::output::to_stderr(format_args!(
                "\rbaking: {done}/{total} triangles ({}%)",
                done * 100 / total.max(1)
            ));
        }
    };
    let started = Instant::now();
    let baked = bake_meshes(&meshes, &options, &mut progress).map_err(|e| match e {
        MeshBakeError::Texture { mesh, error } => {
            Failure::Malformed(format!("{}: {error}", input.jobs[mesh].name))
        }
        other => Failure::Malformed(other.to_string()),
    })?;
    let bake_seconds = started.elapsed().as_secs_f64();
    if show_progress {
        crate::output::to_stderr("\n");
    }
    let (buffers, report) = (&baked.buffers, &baked.report);
    let mut indices = Vec::new();
    for g in 0..buffers.geometry_count() {
        indices.extend(
            buffers
                .index_bytes(g, width)
                .map_err(|e| Failure::Malformed(e.to_string()))?,
        );
    }
    let mut first_index = 0;
    let jobs = input
        .jobs
        .iter()
        .map(|job| {
            let image = &input.images[job.image];
            let summary = JobSummary {
                name: job.name.clone(),
                texture: [image.width, image.height],
                filter: match job.sampler.filter {
                    Filter::Nearest => "nearest",
                    Filter::Linear => "linear",
                },
                address: [
                    address_name(job.sampler.address_u),
                    address_name(job.sampler.address_v),
                ],
                cutoff: job.cutoff.alpha(),
                opaque_when: match job.cutoff.comparison() {
                    Comparison::AtLeast => "alpha >= cutoff",
                    Comparison::Above => "alpha > cutoff",
                },
                triangles: job.triangles.len(),
                first_index,
            };
            first_index += job.triangles.len();
            summary
        })
        .collect();
    let counts = StateCounts::from(report.counts);
    let micro = counts.total();
    let summary = Summary {
        triangles: report.triangles,
        format: u32::from(format.raw()),
        model: model.name(),
        levels: report.levels.clone(),
        known_fraction: report.known_fraction,
        known_area_fraction: report.known_area_fraction,
        micro_triangles: counts,
        status: StatusCounts::from(report.status),
        micromaps_after_dedup: report.micromaps,
        special_index_triangles: report.special_index_triangles,
        bytes_flat: report.bytes_flat,
        bytes_paper_tree: report.bytes_paper_tree,
        bytes_level_order_tree: report.bytes_level_order_tree,
        index_width_bits: width.bytes() * 8,
        bake_seconds,
        micro_triangles_per_second: micro as f64 / bake_seconds.max(1e-9),
        jobs,
        warnings: input.warnings.clone(),
    };
    let summary_json = serde_json::to_string_pretty(&summary)
        .map_err(|e| Failure::Malformed(format!("summary: {e}")))?
        + "\n";
    let mut files = vec![
        ("micromap-data.bin".to_string(), buffers.data().to_vec()),
        (
            "micromap-triangles.bin".to_string(),
            buffers.records_le_bytes(),
        ),
        ("micromap-indices.bin".to_string(), indices),
        (
            "micromap-usage.bin".to_string(),
            micromap_index::micromap::usage_counts_to_le_bytes(buffers.usage_counts()),
        ),
        (
            "summary.json".to_string(),
            summary_json.clone().into_bytes(),
        ),
    ];
    if preview {
        let png = crate::preview::render(
            &input.images,
            input
                .jobs
                .iter()
                .zip(&baked.triangles)
                .map(|(job, baked)| (job.image, job.triangles.as_slice(), baked.as_slice())),
        )
        .map_err(Failure::Io)?;
        files.push(("preview.png".to_string(), png));
    }
    write_files(&out, &files).map_err(Failure::Io)?;
    Ok((summary_json, Exit::Success))
}

pub(crate) fn run_verify(options: &[&str]) -> ExitCode {
    finish(verify(options))
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

#[derive(Serialize)]
struct VerifyJson {
    model: &'static str,
    triangles: usize,
    triangles_checked: usize,
    known_micro_triangles: u64,
    unknown_micro_triangles: u64,
    unknown_fraction: f64,
    undecided: u64,
    contradictions: u64,
    first_contradictions: Vec<ContradictionJson>,
    sound: bool,
}

fn verify(options: &[&str]) -> Result<(String, Exit), Failure> {
    let mut valued = vec![
        "--texture",
        "--triangles",
        "--micromaps",
        "--index-width",
        "--max-report",
        "--model",
    ];
    valued.extend(SAMPLER_VALUED);
    let p = Parsed::new(
        "verify-bake",
        options,
        &valued,
        &["--opaque-above", "--json"],
    )
    .map_err(Failure::Usage)?;
    let dir = PathBuf::from(
        p.get("--micromaps")
            .ok_or_else(|| Failure::Usage("verify-bake needs --micromaps DIR".into()))?,
    );
    if p.get("--texture").is_none() || p.get("--triangles").is_none() {
        return Err(Failure::Usage(
            "verify-bake needs --texture and --triangles".into(),
        ));
    }
    let max_report: usize = p
        .get("--max-report")
        .unwrap_or("20")
        .parse()
        .map_err(|_| Failure::Malformed("--max-report: expected a count".into()))?;
    let width = index_width(&p)?;
    let model = model_option(&p)?;
    let s = sampler_options(&p)?;
    let input = read_input(&p, &s)?;
    let job = &input.jobs[0];
    let data = read_file(&dir.join("micromap-data.bin"))?;
    let records = read_file(&dir.join("micromap-triangles.bin"))?;
    let index_bytes = read_file(&dir.join("micromap-indices.bin"))?;
    let read = read_buffers(
        &BufferBytes {
            records: &records,
            data: &data,
            usage_counts: None,
            indices: Some((&index_bytes, width)),
        },
        &ReadOptions {
            overlap: micromap_index::micromap::Overlap::Allow {
                max_decoded_bytes: 1 << 32,
            },
            ..ReadOptions::default()
        },
    )
    .map_err(|e| Failure::Malformed(format!("{}: {e}", dir.display())))?;
    let indices = read.indices.unwrap_or_default();
    if indices.len() != job.triangles.len() {
        return Err(Failure::Malformed(format!(
            "{} has {} indices for {} triangles",
            dir.display(),
            indices.len(),
            job.triangles.len()
        )));
    }
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
        contradictions: 0,
        first_contradictions: Vec::new(),
        sound: true,
    };
    for (t, (uv, index)) in job.triangles.iter().zip(&indices).enumerate() {
        let opacity = match *index {
            MicromapIndex::Record(r) => TriangleOpacity::Micromap(&read.micromaps[r as usize]),
            MicromapIndex::Special(state) => TriangleOpacity::Special(state),
        };
        let v = baker.verify(uv, &opacity);
        out.triangles_checked += usize::from(v.checked);
        out.known_micro_triangles += v.known;
        out.unknown_micro_triangles += v.unknown;
        out.undecided += v.undecided;
        out.contradictions += v.contradictions.len() as u64;
        for c in v.contradictions {
            if out.first_contradictions.len() >= max_report {
                break;
            }
            out.first_contradictions.push(ContradictionJson {
                triangle: t,
                micro_triangle: c.micro_triangle,
                state: c.state.to_string(),
                witness_texel_space: c
                    .witness
                    .map(|w| [(w.x.to_string(), w.shift_x), (w.y.to_string(), w.shift_y)]),
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
        }
    }
    let micro = out.known_micro_triangles + out.unknown_micro_triangles;
    out.unknown_fraction = out.unknown_micro_triangles as f64 / micro.max(1) as f64;
    out.sound = out.contradictions == 0;
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
            if out.sound { "sound" } else { "NOT SOUND" },
            out.triangles,
            out.triangles_checked,
            out.known_micro_triangles,
            out.unknown_micro_triangles,
            out.unknown_fraction,
            out.undecided
        );
        let _ = writeln!(text, "contradictions: {}", out.contradictions);
        for c in &out.first_contradictions {
            let witness = match &c.witness_texel_space {
                Some([(x, sx), (y, sy)]) => format!(
                    "texel-space point ({x}/2^{sx}, {y}/2^{sy}) = uv ({:.9}, {:.9})",
                    c.witness_uv.unwrap_or_default()[0],
                    c.witness_uv.unwrap_or_default()[1]
                ),
                None => "no exact point (block search)".into(),
            };
            let texel = match c.texel {
                Some([x, y]) => format!("texel ({x}, {y})"),
                None => "the border".into(),
            };
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
