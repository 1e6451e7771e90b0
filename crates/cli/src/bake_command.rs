//! `micromap-index bake` and `micromap-index verify-bake`: the exact baker
//! (library: `micromap_index::bake`, the whole-mesh pipeline in
//! `bake::mesh`) on real assets read by `micromap_index_assets`, and its
//! verifier on any baker's buffers. This file parses the options, reads
//! the inputs and serialises the results; `preview.rs` draws the picture.

use crate::args::{Command, Flag, Parsed};
use crate::output::{print_then, report, Exit, Failure};
use crate::write_all_or_nothing::{install_interrupt_handler, Destination, Refusal};
use micromap_index::bake::mesh::{
    bake_meshes, output_bytes_bound, LevelRule, Material, Mesh, MeshBakeError, MeshOptions,
    MeshTriangles, Mips,
};
use micromap_index::bake::{
    AddressMode, AlphaTexture, Baker, Comparison, Cutoff, Filter, Model, Sampler, Threads,
    UvTriangle, DEFAULT_BAKE_WORK_BUDGET, DEFAULT_TRIANGLE_WORK_BUDGET,
};
use micromap_index::micromap::{
    read_buffers, BufferBytes, BuildOptions, Format, IndexWidth, MicromapIndex, ReadOptions,
    TriangleOpacity, UnknownPolicy,
};
use micromap_index::Level;
use micromap_index_assets::{
    decode_alpha_image, read_gltf_file, read_triangles_json, AlphaImage, AssetError, ImageTexture,
    Limits,
};
use serde::Serialize;
use std::fmt::Write as _;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The sampler, cutoff and model flags `bake` and `verify-bake` share.
macro_rules! sampler_flags {
    () => {
        [
            Flag::value(
                "--filter",
                "F",
                "nearest or linear (default nearest; glTF: the sampler's magFilter)",
            ),
            Flag::value(
                "--address",
                "MODE",
                "both axes: repeat (default; glTF: wrapS/wrapT), mirrored-repeat,
                         clamp-to-edge, clamp-to-border or mirror-clamp-to-edge",
            ),
            Flag::value("--address-u", "MODE", "the u axis only"),
            Flag::value("--address-v", "MODE", "the v axis only"),
            Flag::value("--border", "ALPHA", "clamp-to-border alpha (default 0)"),
            Flag::value(
                "--cutoff",
                "C",
                "alpha cutoff (default 0.5; glTF: alphaCutoff); opaque when alpha >= C",
            ),
            Flag::switch(
                "--opaque-above",
                "opaque when alpha > C (the OMM SDK's rule)",
            ),
            Flag::value(
                "--model",
                "M",
                "the points known states hold for: gpu-binary32 (default: every binary32
                         hit a GPU assigns to the micro-triangle and the texel its binary32
                         arithmetic reads) or exact (the exact real points only; docs/bake.md)",
            ),
        ]
    };
}
pub(crate) use sampler_flags;

/// The flag table of `bake`.
pub(crate) static BAKE: Command = Command {
    name: "bake",
    forms: &[
        "(--gltf ASSET.gltf|.glb | --texture T.png --triangles TRIS.json)
                           --out DIR [options]",
    ],
    about: "  Bakes opacity micromaps exactly: a micro-triangle is opaque (transparent)
  only if every point of it, closed, reads only opaque (transparent) texels
  under the sampler, and by default every binary32 hit a GPU assigns to it
  too (--model); otherwise unknown (docs/bake.md). Writes into DIR, all
  or nothing:
    micromap-data.bin       the packed micromaps (Vulkan/DXR/glTF layout)
    micromap-triangles.bin  8-byte records {u32 offset, u16 level, u16 format}
    micromap-indices.bin    one index per input triangle (special indices
                            -1..-4 as negative values), little endian
    micromap-usage.bin      12-byte usage counts {u32 count, u32 level, u32 format}
    micromap-geometry-usage.bin
                            Vulkan EXT's per-geometry usage counts: per job,
                            u32 n then n usage counts (docs/cli.md)
    summary.json            states, known fraction, micromaps, sizes, time
    NAME.gltf or NAME.glb   with --gltf-out: the asset written back with
                            EXT_mesh_opacity_micromap on every baked primitive
                            (.gltf: plus NAME.micromap.bin, and NAME.bin for a
                            .glb input's BIN chunk; docs/gltf-out.md)
    preview.png             the texture with every micro-triangle coloured by
                            state (green opaque, blue transparent, yellow
                            unknown-opaque, red unknown-transparent), wrapped
                            with the job's address modes; each distinct
                            triangle once, at most 2^27 pixels of
                            micro-triangles (summary.json counts the rest),
                            with a legend of the colours and the model
  DIR is locked (DIR/.micromap-index.lock) from the check to the last
  rename: a second bake into the same DIR is refused (exit 3) and never
  mixes its files with the first one's. Ctrl-C removes the temporaries,
  backups, lock and any directory the bake created, and leaves DIR as it
  was (exit 130).
  Exit 0 baked; 2 bad options, malformed input, or existing outputs without
  --force (nothing written); 3 unreadable input, unwritable DIR or DIR in
  use by another bake (nothing written), or stdout unwritable after DIR was
  written (DIR complete); 130 interrupted (nothing written); 141 stdout
  closed (DIR complete).",
    flags: &{
        const SAMPLER: [Flag; 8] = sampler_flags!();
        [
            Flag::value(
                "--gltf",
                "ASSET",
                "a glTF 2.0 asset (.gltf or .glb): its MASK primitives",
            ),
            Flag::value(
                "--gltf-out",
                "NAME",
                "NAME.gltf or NAME.glb: also write the asset back into DIR with
                         the micromaps (its own samplers and cutoffs only)",
            ),
            Flag::value("--texture", "T.png", "an alpha texture (PNG or JPEG)"),
            Flag::value("--triangles", "TRIS.json", "UV triangles over --texture"),
            Flag::value("--out", "DIR", "the output directory"),
            Flag::value(
                "--level",
                "L|auto",
                "fixed level 0..=12, or the paper's eq. 1 per triangle (default auto)",
            ),
            Flag::value("--max-level", "L", "cap for auto (default 12)"),
            Flag::value(
                "--budget",
                "BYTES",
                "auto: lower the highest levels until the data fits",
            ),
            Flag::value("--format", "2|4", "micromap format (default 4)"),
            Flag::value(
                "--unknown-as",
                "U",
                "2-state: what unknowns become: fallback (default: the texel under
                         the micro-triangle's centroid), opaque or transparent",
            ),
            SAMPLER[0],
            SAMPLER[1],
            SAMPLER[2],
            SAMPLER[3],
            SAMPLER[4],
            SAMPLER[5],
            SAMPLER[6],
            SAMPLER[7],
            Flag::value(
                "--mips",
                "0|N|all",
                "the mip levels known states hold for: 0 (default: level 0, which ray
                         tracing shaders sample), 0..=N or all, each level the box filter of
                         the one above, under either filter (docs/bake.md)",
            ),
            Flag::value(
                "--index-width",
                "8|16|32",
                "micromap-indices.bin width (default 32; 8: Vulkan KHR, DXR, glTF only)",
            ),
            Flag::value(
                "--max-bytes",
                "N",
                "refuse (exit 2) before baking when the output may exceed N bytes
                         (default 1073741824; the estimate counts every map before dedup)",
            ),
            Flag::value(
                "--work-budget",
                "N",
                "work units (texel-table lookups) one triangle may spend; the rest
                         is unknown (default 67108864)",
            ),
            Flag::value(
                "--bake-work-budget",
                "N",
                "work units all triangles may spend together (default 17179869184)",
            ),
            Flag::value(
                "--threads",
                "N",
                "threads to bake on (default: every core; 1: serial); the bytes are
                         the same for every N",
            ),
            Flag::switch(
                "--no-mixed-special",
                "no job mixes special indices with records: shared level-0 records
                         instead (Vulkan KHR no-mixed pipelines)",
            ),
            Flag::switch("--force", "replace existing files in DIR"),
            Flag::switch("--no-preview", "skip preview.png"),
            Flag::switch("--quiet", "no progress on stderr"),
        ]
    },
};

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
        const SAMPLER: [Flag; 8] = sampler_flags!();
        [
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
            SAMPLER[0],
            SAMPLER[1],
            SAMPLER[2],
            SAMPLER[3],
            SAMPLER[4],
            SAMPLER[5],
            SAMPLER[6],
            SAMPLER[7],
            Flag::value(
                "--index-width",
                "8|16|32",
                "micromap-indices.bin width (default 32; 8: Vulkan KHR, DXR, glTF only)",
            ),
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
        ]
    },
};

/// Output file names, in the order written.
const OUTPUTS: [&str; 7] = [
    "micromap-data.bin",
    "micromap-triangles.bin",
    "micromap-indices.bin",
    "micromap-usage.bin",
    crate::geometry_usage::FILE,
    "summary.json",
    "preview.png",
];

fn finish(outcome: Result<(String, Exit), Failure>) -> Exit {
    match outcome {
        Ok((text, exit)) => print_then(&text, exit),
        Err(failure) => failure.exit(),
    }
}

/// One texture with its sampler, cutoff and triangles (a mesh to bake).
pub(crate) struct Job {
    pub(crate) name: String,
    pub(crate) image: usize,
    /// glTF's `baseColorFactor[3]` (1 for `--texture`).
    pub(crate) factor: f32,
    pub(crate) sampler: Sampler,
    pub(crate) cutoff: Cutoff,
    pub(crate) triangles: Vec<UvTriangle>,
    /// glTF's `COLOR_0` alpha per triangle (`None` for `--texture`).
    pub(crate) vertex_alpha: Option<Vec<[f32; 3]>>,
    /// glTF's `POSITION` per triangle (`None` for `--texture` or without
    /// `POSITION`), for `render`.
    pub(crate) positions: Option<Vec<[[f32; 3]; 3]>>,
    /// glTF's (mesh, primitive) (`None` for `--texture`).
    pub(crate) gltf: Option<(usize, usize)>,
}

pub(crate) struct Input {
    pub(crate) images: Vec<AlphaImage>,
    pub(crate) jobs: Vec<Job>,
    pub(crate) warnings: Vec<String>,
}

impl Input {
    /// The textures as the baker reads them.
    pub(crate) fn textures(&self) -> Result<Vec<ImageTexture<'_>>, Failure> {
        self.images
            .iter()
            .map(|image| {
                image
                    .texture()
                    .map_err(|e| Failure::Malformed(e.to_string()))
            })
            .collect()
    }

    /// One mesh per job, over `textures` (from [`Input::textures`]).
    pub(crate) fn meshes<'a>(&'a self, textures: &'a [ImageTexture<'a>]) -> Vec<Mesh<'a>> {
        self.jobs
            .iter()
            .map(|job| Mesh {
                triangles: MeshTriangles::Uv(&job.triangles),
                texture: &textures[job.image],
                material: Material {
                    sampler: job.sampler,
                    cutoff: job.cutoff,
                    alpha_factor: job.factor,
                },
                vertex_alpha: job.vertex_alpha.as_deref(),
            })
            .collect()
    }
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

pub(crate) fn parse_level(name: &str, text: &str) -> Result<Level, Failure> {
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
pub(crate) struct SamplerOptions {
    filter: Option<Filter>,
    address_u: Option<AddressMode>,
    address_v: Option<AddressMode>,
    border: f32,
    cutoff: Option<f32>,
    comparison: Comparison,
}

pub(crate) fn sampler_options(p: &Parsed<'_>) -> Result<SamplerOptions, Failure> {
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

/// The most bytes `--texture` and `--triangles` may hold (the 1 GiB the glTF
/// reader allows a whole asset).
const INPUT_FILE_LIMIT: u64 = 1 << 30;
/// The most bytes `micromap-data.bin` may hold: every block lies below a
/// 32-bit offset plus one level-16 4-state block (1 GiB).
pub(crate) const DATA_FILE_LIMIT: u64 = (1 << 32) + (1 << 30);
/// The most bytes `micromap-triangles.bin` and `micromap-indices.bin` may
/// hold (2^27 records or 2^28 32-bit indices).
pub(crate) const RECORD_FILE_LIMIT: u64 = 1 << 30;
/// The most bytes `micromap-usage.bin` may hold (87,381 entries; 34 are
/// enough for every level and format).
const USAGE_FILE_LIMIT: u64 = 1 << 20;

/// `path`'s bytes, refused past `limit` bytes (read at most `limit + 1`, so
/// `/dev/zero` or an endless pipe cannot exhaust memory): exit 2 with a
/// message naming the limit; unreadable: exit 3.
pub(crate) fn read_file(path: &Path, limit: u64, what: &str) -> Result<Vec<u8>, Failure> {
    use std::io::Read as _;
    let io = |e: std::io::Error| Failure::Io(format!("cannot read {}: {e}", path.display()));
    let file = std::fs::File::open(path).map_err(io)?;
    let too_large = || {
        Failure::Malformed(format!(
            "{}: over the limit of {limit} bytes for {what}",
            path.display()
        ))
    };
    // A regular file's size is known at once; a pipe or a device is read
    // up to the limit.
    if file
        .metadata()
        .is_ok_and(|m| m.is_file() && m.len() > limit)
    {
        return Err(too_large());
    }
    let mut bytes = Vec::new();
    file.take(limit + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(too_large());
    }
    Ok(bytes)
}

/// `--threads N` (N >= 1); `None`: every core.
fn threads_option(p: &Parsed<'_>) -> Result<Option<usize>, Failure> {
    match p.get("--threads") {
        None => Ok(None),
        Some(text) => match text.parse::<usize>() {
            Ok(n) if n >= 1 && text.bytes().all(|b| b.is_ascii_digit()) => Ok(Some(n)),
            _ => Err(Failure::Malformed(format!(
                "--threads {text:?}: expected a number of threads, at least 1"
            ))),
        },
    }
}

/// `--model` (default gpu-binary32).
pub(crate) fn model_option(p: &Parsed<'_>) -> Result<Model, Failure> {
    match p.get("--model") {
        None => Ok(Model::default()),
        Some(text) => Model::from_name(text).ok_or_else(|| {
            Failure::Malformed(format!("--model {text:?}: expected gpu-binary32 or exact"))
        }),
    }
}

pub(crate) fn read_input(p: &Parsed<'_>, s: &SamplerOptions) -> Result<Input, Failure> {
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
                    vertex_alpha: prim.vertex_alpha.clone(),
                    positions: prim.positions.clone(),
                    gltf: Some((prim.mesh, prim.primitive)),
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
            let image = decode_alpha_image(
                &read_file(Path::new(texture), INPUT_FILE_LIMIT, "a --texture file")?,
                &limits,
            )
            .map_err(|e| Failure::Malformed(format!("{texture}: {e}")))?;
            let triangles = read_triangles_json(&read_file(
                Path::new(triangles),
                INPUT_FILE_LIMIT,
                "a --triangles file",
            )?)
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
                    vertex_alpha: None,
                    positions: None,
                    gltf: None,
                }],
                warnings: Vec::new(),
            })
        }
        _ => Err(Failure::Usage(
            "give either --gltf ASSET or both --texture and --triangles".into(),
        )),
    }
}

pub(crate) fn index_width(p: &Parsed<'_>) -> Result<IndexWidth, Failure> {
    match p.get("--index-width").unwrap_or("32") {
        "32" => Ok(IndexWidth::U32),
        "16" => Ok(IndexWidth::U16),
        "8" => Ok(IndexWidth::U8),
        other => Err(Failure::Malformed(format!(
            "--index-width {other:?}: expected 8, 16 or 32 (Vulkan EXT takes 16 and 32; \
             Vulkan KHR, DXR and glTF also 8)"
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
    /// Vulkan EXT's usage counts of this job's geometry (as in
    /// micromap-geometry-usage.bin).
    geometry_usage_counts: Vec<crate::geometry_usage::UsageJson>,
    /// Whether the job's indices hold both special indices and records.
    mixed_special_indices: bool,
}

#[derive(Serialize)]
struct Summary {
    triangles: usize,
    /// Triangles classified: equal UVs, level and material bake once.
    distinct_triangles: usize,
    /// "4-state" or "2-state".
    format: &'static str,
    /// The APIs' value of the format (`VkOpacityMicromapFormatEXT`: 1
    /// 2-state, 2 4-state).
    format_api_value: u32,
    /// The threads the bake ran on.
    threads: usize,
    model: &'static str,
    /// `--mips`: `0`, `N` or `all`.
    mips: String,
    /// What the GPU model's widening cost this bake (zero under `exact`).
    widening: Widening,
    levels: Vec<u64>,
    /// Auto levels lowered to 0: micro-triangles would each hold a whole
    /// texture period.
    period_level_zero_triangles: usize,
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
    /// Work units spent (texel-table lookups, `micromap_index::bake::work`).
    work_units: u64,
    bake_seconds: f64,
    micro_triangles_per_second: f64,
    /// Drawing preview.png (0 with --no-preview).
    preview_seconds: f64,
    /// Micro-triangles drawn in preview.png.
    preview_micro_triangles: u64,
    /// Not drawn: repeated triangles, or past the preview's pixel budget.
    preview_micro_triangles_skipped: u64,
    jobs: Vec<JobSummary>,
    warnings: Vec<String>,
}

#[derive(Serialize)]
struct Widening {
    /// Unknown micro-triangles the exact model knows (`BakeReport::widened`).
    micro_triangles_made_unknown: u64,
    /// The known fraction the same bake has under `--model exact`.
    known_fraction_exact_model: f64,
}

#[derive(Serialize)]
struct StatusCounts {
    exact: usize,
    not_finite: usize,
    out_of_exact_range: usize,
    budget_exceeded: usize,
    work_budget_exceeded: usize,
}

impl From<micromap_index::bake::mesh::StatusCounts> for StatusCounts {
    fn from(s: micromap_index::bake::mesh::StatusCounts) -> Self {
        StatusCounts {
            exact: s.exact,
            not_finite: s.not_finite,
            out_of_exact_range: s.out_of_exact_range,
            budget_exceeded: s.budget_exceeded,
            work_budget_exceeded: s.work_budget_exceeded,
        }
    }
}

/// The default limit on bake's estimated output (`--max-bytes`): 1 GiB, 256
/// level-12 4-state maps.
const DEFAULT_MAX_OUTPUT_BYTES: u64 = 1 << 30;

pub(crate) fn run_bake(options: &[&str]) -> Exit {
    finish(bake(options))
}

fn bake(options: &[&str]) -> Result<(String, Exit), Failure> {
    let p = BAKE
        .parse(options)
        .map_err(|error| Failure::Usage(error.message("bake")))?;
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
    let max_bytes = p
        .get("--max-bytes")
        .map(|t| {
            t.parse::<u64>().map_err(|_| {
                Failure::Malformed(format!("--max-bytes {t:?}: expected a byte count"))
            })
        })
        .transpose()?
        .unwrap_or(DEFAULT_MAX_OUTPUT_BYTES);
    let work_budget = |flag: &str, default: u64| {
        p.get(flag).map_or(Ok(default), |t| {
            t.parse::<u64>()
                .map_err(|_| Failure::Malformed(format!("{flag} {t:?}: expected a count")))
        })
    };
    let triangle_work_budget = work_budget("--work-budget", DEFAULT_TRIANGLE_WORK_BUDGET)?;
    let bake_work_budget = work_budget("--bake-work-budget", DEFAULT_BAKE_WORK_BUDGET)?;
    let width = index_width(&p)?;
    let model = model_option(&p)?;
    let mips = match p.get("--mips") {
        None => Mips::default(),
        Some(text) => Mips::from_name(text).ok_or_else(|| {
            Failure::Malformed(format!("--mips {text:?}: expected 0, a level N or all"))
        })?,
    };
    let threads = threads_option(&p)?;
    let s = sampler_options(&p)?;
    let preview = !p.flag("--no-preview");
    let gltf_out = crate::gltf_out::GltfOut::from_options(&p, &OUTPUTS)?;
    let gltf_names = gltf_out
        .as_ref()
        .map(crate::gltf_out::GltfOut::names)
        .unwrap_or_default();
    let mut outputs = OUTPUTS.to_vec();
    outputs.extend(gltf_names.iter().map(String::as_str));
    if let Err(message) = install_interrupt_handler() {
        report(format_args!(
            "bake: {message}; Ctrl-C may leave temporaries"
        ));
    }
    // Held (locked) until the files are written or the bake fails; dropping
    // it removes the lock and the directories it created.
    let destination =
        Destination::claim(&out, &outputs, p.flag("--force")).map_err(|refusal| match refusal {
            Refusal::Refused(message) => Failure::Malformed(message),
            Refusal::Io(message) => Failure::Io(message),
        })?;
    let input = read_input(&p, &s)?;

    // The textures as the baker reads them, and one mesh per job.
    let textures = input.textures()?;
    let meshes = input.meshes(&textures);
    let rule = match fixed_level {
        Some(level) => LevelRule::Fixed(level),
        None => LevelRule::Useful { max: max_level },
    };
    let options = MeshOptions {
        levels: rule,
        format,
        unknown: two_state,
        budget_bytes: budget,
        triangle_work_budget,
        bake_work_budget,
        model,
        mips,
        threads: match threads {
            Some(n) => Threads::Exactly(n),
            None => Threads::All,
        },
        buffers: BuildOptions {
            no_mixed_special_indices: p.flag("--no-mixed-special"),
            ..BuildOptions::default()
        },
        ..MeshOptions::default()
    };
    // The output's size before deduplication (an upper bound: maps that
    // dedup or become special indices only shrink it), from the levels
    // bake_meshes chooses, checked before any micro-triangle is baked.
    let estimate = output_bytes_bound(&meshes, &options, width)
        .map_err(|e| Failure::Malformed(e.to_string()))?;
    if estimate > max_bytes {
        return Err(Failure::Malformed(format!(
            "the output may take up to {estimate} bytes (before deduplication), over the \
             limit of {max_bytes} bytes; nothing written (--max-bytes raises the limit, \
             --budget or a lower --level/--max-level shrinks the output)"
        )));
    }
    let threads_used = threads.unwrap_or_else(|| {
        std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
    });
    let show_progress = !p.flag("--quiet") && std::io::stderr().is_terminal();
    let mut progress = |done: usize, total: usize| {
        // Called once per chunk of the bake (about 2^22 micro-triangles
        // per thread), so every call is printed.
        if show_progress {
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
        .enumerate()
        .map(|(g, job)| {
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
                geometry_usage_counts: crate::geometry_usage::to_json(buffers, g)?,
                mixed_special_indices: buffers
                    .is_mixed(g)
                    .map_err(|e| Failure::Malformed(e.to_string()))?,
            };
            first_index += job.triangles.len();
            Ok(summary)
        })
        .collect::<Result<_, Failure>>()?;
    // The preview before the summary, which times it.
    let preview_started = Instant::now();
    let drawn = if preview {
        if show_progress {
            crate::output::to_stderr("drawing preview.png\n");
        }
        Some(
            crate::preview::render(
                &input.images,
                model,
                input
                    .jobs
                    .iter()
                    .map(|job| (job.image, job.sampler, job.triangles.as_slice())),
                &baked,
            )
            .map_err(Failure::Io)?,
        )
    } else {
        None
    };
    let preview_seconds = preview_started.elapsed().as_secs_f64();
    let preview_skipped = drawn.as_ref().map_or(0, |d| d.skipped);
    let preview_drawn = drawn.as_ref().map_or(0, |d| d.micro_triangles);
    let preview_png = drawn.map(|d| d.png);
    let counts = StateCounts::from(report.counts);
    let micro = counts.total();
    let summary = Summary {
        triangles: report.triangles,
        distinct_triangles: report.distinct_triangles,
        format: match format {
            Format::FourState => "4-state",
            Format::TwoState => "2-state",
        },
        format_api_value: u32::from(format.raw()),
        threads: threads_used,
        model: model.name(),
        mips: mips.to_string(),
        widening: Widening {
            micro_triangles_made_unknown: report.widened,
            known_fraction_exact_model: (report.counts[0] + report.counts[1] + report.widened)
                as f64
                / micro.max(1) as f64,
        },
        levels: report.levels.clone(),
        period_level_zero_triangles: report.period_level_zero,
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
        work_units: report.work,
        bake_seconds,
        micro_triangles_per_second: micro as f64 / bake_seconds.max(1e-9),
        preview_seconds,
        preview_micro_triangles: preview_drawn,
        preview_micro_triangles_skipped: preview_skipped,
        jobs,
        warnings: input.warnings.clone(),
    };
    let summary_json = serde_json::to_string_pretty(&summary)
        .map_err(|e| Failure::Malformed(format!("summary: {e}")))?
        + "\n";
    // Borrowed where the bytes already exist: the data, the largest
    // output, is written from the buffers without a copy.
    let gltf_files = match &gltf_out {
        Some(gltf_out) => {
            let asset = Path::new(p.get("--gltf").unwrap_or_default());
            let primitives: Vec<(usize, usize)> =
                input.jobs.iter().filter_map(|j| j.gltf).collect();
            gltf_out.files(asset, &out, buffers, &primitives)?
        }
        None => Vec::new(),
    };
    let records = buffers.records_le_bytes();
    let usage = micromap_index::micromap::usage_counts_to_le_bytes(buffers.usage_counts());
    let geometry_usage = crate::geometry_usage::to_le_bytes(buffers)?;
    let mut files: Vec<(String, &[u8])> = vec![
        ("micromap-data.bin".to_string(), buffers.data()),
        ("micromap-triangles.bin".to_string(), &records),
        ("micromap-indices.bin".to_string(), &indices),
        ("micromap-usage.bin".to_string(), &usage),
        (crate::geometry_usage::FILE.to_string(), &geometry_usage),
        ("summary.json".to_string(), summary_json.as_bytes()),
    ];
    if let Some(png) = &preview_png {
        files.push(("preview.png".to_string(), png));
    }
    // Without a preview, a stale preview.png (--force) is removed with the
    // same all-or-nothing commit.
    let mut stale: Vec<&str> = if preview { vec![] } else { vec!["preview.png"] };
    if gltf_out.is_some() {
        files.extend(gltf_files.iter().map(|(n, b)| (n.clone(), b.as_slice())));
        // A sidecar this run does not write (NAME.bin) is not left stale.
        stale.extend(
            gltf_names
                .iter()
                .filter(|n| !files.iter().any(|(f, _)| f == *n))
                .map(String::as_str),
        );
    }
    destination.write(&files, &stale).map_err(Failure::Io)?;
    Ok((summary_json, Exit::Success))
}

pub(crate) fn run_verify(options: &[&str]) -> Exit {
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
    let data = read_file(
        &dir.join("micromap-data.bin"),
        DATA_FILE_LIMIT,
        "micromap data",
    )?;
    let records = read_file(
        &dir.join("micromap-triangles.bin"),
        RECORD_FILE_LIMIT,
        "triangle records",
    )?;
    let index_bytes = read_file(
        &dir.join("micromap-indices.bin"),
        RECORD_FILE_LIMIT,
        "indices",
    )?;
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
            if out.sound {
                "sound"
            } else if out.contradictions == 0 {
                "INCOMPLETE"
            } else {
                "NOT SOUND"
            },
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
