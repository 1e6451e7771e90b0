//! What `bake`, `verify-bake` and `render` read alike: the sampler and
//! cutoff options, the input (a glTF asset, or a texture and UV triangles)
//! as jobs, and the buffer files under their size limits.

use crate::args::Parsed;
use crate::output::Failure;
use micromap_index::bake::mesh::{Material, Mesh, MeshTriangles};
use micromap_index::bake::{AddressMode, Comparison, Cutoff, Filter, Model, Sampler, UvTriangle};
use micromap_index::micromap::{Format, IndexWidth};
use micromap_index::Level;
use micromap_index_assets::{
    decode_alpha_image, read_gltf_file, read_triangles_json, AlphaImage, AssetError, ImageTexture,
    Limits,
};
use std::path::{Path, PathBuf};

/// The flags more than one command has, each defined once: a command's
/// table lists them by name (`args::concat` joins the groups).
pub(crate) mod flags {
    use crate::args::Flag;

    /// `bake`'s and `render`'s glTF input.
    pub(crate) const GLTF: Flag = Flag::value(
        "--gltf",
        "ASSET",
        "a glTF 2.0 asset (.gltf or .glb): its MASK primitives",
    );
    /// `bake`'s and `render`'s texture input.
    pub(crate) const TEXTURE: Flag =
        Flag::value("--texture", "T.png", "an alpha texture (PNG or JPEG)");
    /// `bake`'s and `render`'s UV triangles over [`TEXTURE`].
    pub(crate) const TRIANGLES: Flag =
        Flag::value("--triangles", "TRIS.json", "UV triangles over --texture");
    /// `bake`'s and `render`'s output directory.
    pub(crate) const OUT: Flag = Flag::value("--out", "DIR", "the output directory");
    /// `bake`'s and `render`'s cap for `--level auto`.
    pub(crate) const MAX_LEVEL: Flag = Flag::value("--max-level", "L", "cap for auto (default 12)");
    /// `bake`'s and `render`'s replacing of existing outputs.
    pub(crate) const FORCE: Flag = Flag::switch("--force", "replace existing files in DIR");
    /// `bake`'s and `verify-bake`'s width of micromap-indices.bin.
    pub(crate) const INDEX_WIDTH: Flag = Flag::value(
        "--index-width",
        "8|16|32",
        "micromap-indices.bin width (default 32; 8: Vulkan KHR, DXR, glTF only)",
    );

    /// The sampler, cutoff and model flags `bake`, `verify-bake` and
    /// `render` share; all but `--model` are the asset's own with
    /// `--gltf-out` and `verify-bake --gltf`.
    pub(crate) const SAMPLER: [Flag; 8] = [
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
    ];
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

pub(crate) fn address_name(mode: AddressMode) -> &'static str {
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
const RECORD_FILE_LIMIT: u64 = 1 << 30;

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

/// The buffer files in bake's layout, each read under its limit.
pub(crate) struct BufferFiles {
    /// `micromap-data.bin`.
    pub(crate) data: Vec<u8>,
    /// `micromap-triangles.bin`.
    pub(crate) records: Vec<u8>,
    /// `micromap-indices.bin`.
    pub(crate) indices: Vec<u8>,
}

/// `dir`'s data, records and indices (in that order: the first that
/// fails is reported), as [`read_file`] reads each.
pub(crate) fn read_buffer_files(dir: &Path) -> Result<BufferFiles, Failure> {
    Ok(BufferFiles {
        data: read_file(
            &dir.join("micromap-data.bin"),
            DATA_FILE_LIMIT,
            "micromap data",
        )?,
        records: read_file(
            &dir.join("micromap-triangles.bin"),
            RECORD_FILE_LIMIT,
            "triangle records",
        )?,
        indices: read_file(
            &dir.join("micromap-indices.bin"),
            RECORD_FILE_LIMIT,
            "indices",
        )?,
    })
}

/// `--format` (default 4).
pub(crate) fn format_option(p: &Parsed<'_>) -> Result<Format, Failure> {
    match p.get("--format").unwrap_or("4") {
        "4" => Ok(Format::FourState),
        "2" => Ok(Format::TwoState),
        other => Err(Failure::Malformed(format!(
            "--format {other:?}: expected 2 or 4"
        ))),
    }
}

/// `--model` (default gpu-binary32).
pub(crate) fn model_option(p: &Parsed<'_>) -> Result<Model, Failure> {
    match p.get("--model") {
        None => Ok(Model::default()),
        Some(text) => text
            .parse()
            .map_err(|e| Failure::Malformed(format!("--model {text:?}: {e}"))),
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
