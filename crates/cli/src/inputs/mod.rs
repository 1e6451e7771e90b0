//! What `bake`, `verify-bake` and `render` read alike: the shared flags
//! ([`flags`]), the sampler and cutoff options ([`sampler`]), the files
//! under their size limits ([`files`]), and the input (a glTF asset, or a
//! texture and UV triangles) as jobs.

pub(crate) mod files;
pub(crate) mod flags;
pub(crate) mod sampler;

use cli_support::args::Parsed;
use cli_support::input::refuse_blocking;
use cli_support::output::Failure;
use files::{asset_failure, asset_limits, read_file, INPUT_FILE_LIMIT};
use micromap_index::bake::mesh::{Material, Mesh, MeshTriangles};
use micromap_index::bake::{Cutoff, Sampler, UvTransform, UvTriangle};
use micromap_index::micromap::IndexWidth;
use micromap_index_assets::{
    decode_alpha_image, read_gltf_file, read_triangles_json, AlphaImage, ImageTexture,
    RefusedPrimitive,
};
use sampler::SamplerOptions;
use std::path::{Path, PathBuf};

/// One texture with its sampler, cutoff and triangles (a mesh to bake).
pub(crate) struct Job {
    pub(crate) name: String,
    pub(crate) image: usize,
    /// glTF's `baseColorFactor[3]` (1 for `--texture`).
    pub(crate) factor: f32,
    pub(crate) sampler: Sampler,
    pub(crate) cutoff: Cutoff,
    /// The stored texture coordinates (before `uv_transform`).
    pub(crate) triangles: Vec<UvTriangle>,
    /// glTF's `KHR_texture_transform` (the identity for `--texture`).
    pub(crate) uv_transform: UvTransform,
    /// glTF's `COLOR_0` alpha per triangle (`None` for `--texture`).
    pub(crate) vertex_alpha: Option<Vec<[f32; 3]>>,
    /// glTF's `POSITION` per triangle (`None` for `--texture` or without
    /// `POSITION`), for `render`.
    pub(crate) positions: Option<Vec<[[f32; 3]; 3]>>,
    /// glTF's (mesh, primitive) (`None` for `--texture`).
    pub(crate) gltf: Option<(usize, usize)>,
    /// glTF's material index (`None` for `--texture`).
    pub(crate) material: Option<usize>,
    /// Where `render` draws the triangles: glTF's node transforms
    /// (`MaskPrimitive::instances`), the identity for `--texture`.
    pub(crate) instances: Vec<[f32; 12]>,
}

impl Job {
    /// The caption of the preview tile this job is drawn on (jobs with
    /// the same image and caption share a tile): its material and cutoff.
    pub(crate) fn tile_caption(&self) -> String {
        match self.material {
            Some(m) => format!("material {m}, cutoff {}", self.cutoff.alpha()),
            None => format!("cutoff {}", self.cutoff.alpha()),
        }
    }

    /// The triangles the shader samples: each vertex through
    /// `uv_transform`, rounded once to binary32 (for drawing; the bake
    /// models the shader's own transform).
    pub(crate) fn placed_triangles(&self) -> Vec<UvTriangle> {
        self.triangles
            .iter()
            .map(|t| self.uv_transform.place_triangle(t))
            .collect()
    }
}

pub(crate) struct Input {
    pub(crate) images: Vec<AlphaImage>,
    pub(crate) jobs: Vec<Job>,
    pub(crate) warnings: Vec<String>,
    /// `--gltf`'s `MASK` primitives the model does not cover
    /// (`GltfAsset::refused`): not among the jobs.
    pub(crate) refused: Vec<RefusedPrimitive>,
    /// The asset's path as given (`--gltf`), for messages.
    pub(crate) asset: Option<String>,
}

impl Input {
    /// Exit 2 naming the first refused primitive, if any: for commands that
    /// cannot leave a primitive out (`render`, `verify-bake`) and for
    /// `bake --strict`.
    pub(crate) fn refuse_any(&self) -> Result<(), Failure> {
        match RefusedPrimitive::refusal(&self.refused) {
            None => Ok(()),
            Some(refusal) => Err(Failure::Malformed(format!(
                "{}: {refusal}",
                self.asset.as_deref().unwrap_or("the asset")
            ))),
        }
    }

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
                    uv_transform: job.uv_transform,
                },
                vertex_alpha: job.vertex_alpha.as_deref(),
            })
            .collect()
    }
}

/// The input of `p`: `--gltf` (read under [`files::asset_limits`]: with
/// `--confine-uris` its URIs stay in its folder), or `--texture` and
/// `--triangles`.
pub(crate) fn read_input(p: &Parsed<'_>, s: &SamplerOptions) -> Result<Input, Failure> {
    let limits = asset_limits(p)?;
    let cutoff_of = |value: f32| {
        Cutoff::new(value, s.comparison).map_err(|e| Failure::Malformed(e.to_string()))
    };
    match (p.get("--gltf"), p.get("--texture"), p.get("--triangles")) {
        (Some(asset), None, None) => {
            let path = PathBuf::from(asset);
            refuse_blocking(&path).map_err(|e| Failure::Io(format!("cannot read {asset}: {e}")))?;
            // The error names the asset (`AssetError::In`).
            let gltf = read_gltf_file(&path, &limits).map_err(|e| asset_failure(&e, ""))?;
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
                    uv_transform: prim.uv_transform,
                    vertex_alpha: prim.vertex_alpha.clone(),
                    positions: prim.positions.clone(),
                    gltf: Some((prim.mesh, prim.primitive)),
                    material: Some(prim.material),
                    instances: prim.instances.clone(),
                });
            }
            let input = Input {
                images: gltf.images,
                jobs,
                warnings: gltf.warnings,
                refused: gltf.refused,
                asset: Some(asset.to_string()),
            };
            if input.jobs.is_empty() {
                // Nothing left to bake: the first refusal is the reason.
                input.refuse_any()?;
                return Err(Failure::Malformed(format!(
                    "{asset}: no primitive with an alphaMode MASK material and a base colour texture"
                )));
            }
            Ok(input)
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
                    uv_transform: UvTransform::IDENTITY,
                    vertex_alpha: None,
                    positions: None,
                    gltf: None,
                    material: None,
                    instances: vec![micromap_index_assets::IDENTITY_TRANSFORM],
                }],
                warnings: Vec::new(),
                refused: Vec::new(),
                asset: None,
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
