//! `bake --gltf-out NAME` (the asset written back into DIR with
//! `EXT_mesh_opacity_micromap`, by `micromap_index_assets`'s writer) and
//! `verify-bake --gltf ASSET` (a glTF's own micromaps checked against its
//! own textures and materials, by `bake::mesh::verify_mesh`).

use crate::args::Parsed;
use crate::bake_command::inputs::flags;
use crate::bake_command::verify::{verdict, witness_and_texel, witness_texel_space};
use crate::output::{Exit, Failure};
use micromap_index::bake::mesh::{verify_mesh, Mesh, MeshTriangles};
use micromap_index::bake::Model;
use micromap_index::micromap::{MicromapBuffers, TriangleOpacity};
use micromap_index_assets::{
    read_gltf_file, read_gltf_micromaps, relative_uri_prefix, write_gltf_micromaps, AssetError,
    GltfContainer, GltfMicromapWrite, Limits,
};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Component, Path, PathBuf};

/// `--gltf-out NAME`: the file name and its container, checked.
pub(crate) struct GltfOut {
    name: String,
    container: GltfContainer,
}

impl GltfOut {
    /// `--gltf-out`, if given: a bare file name ending in `.gltf` or
    /// `.glb`, with `--gltf` and without sampler overrides, none of whose
    /// files is one of `reserved` (bake's other outputs).
    pub(crate) fn from_options(
        p: &Parsed<'_>,
        reserved: &[&str],
    ) -> Result<Option<GltfOut>, Failure> {
        let Some(name) = p.get("--gltf-out") else {
            return Ok(None);
        };
        if p.get("--gltf").is_none() {
            return Err(Failure::Usage(
                "--gltf-out writes the --gltf asset back: give --gltf ASSET".into(),
            ));
        }
        refuse_overrides(p, "--gltf-out")?;
        let bare = !name.contains(['/', '\\'])
            && !matches!(
                Path::new(name).components().next(),
                Some(Component::ParentDir)
            );
        let container = match (bare, name.rsplit_once('.')) {
            (true, Some((stem, "gltf"))) if !stem.is_empty() => GltfContainer::Json {
                stem: stem.to_string(),
            },
            (true, Some((stem, "glb"))) if !stem.is_empty() => GltfContainer::Glb,
            _ => {
                return Err(Failure::Usage(format!(
                    "--gltf-out {name:?}: expected a file name NAME.gltf or NAME.glb (written into --out DIR)"
                )))
            }
        };
        let out = GltfOut {
            name: name.to_string(),
            container,
        };
        if let Some(clash) = out.names().iter().find(|n| reserved.contains(&n.as_str())) {
            return Err(Failure::Usage(format!(
                "--gltf-out {name:?} would write {clash}, which bake writes too: choose another name"
            )));
        }
        Ok(Some(out))
    }

    /// Every file this may write into DIR (for the existence check).
    pub(crate) fn names(&self) -> Vec<String> {
        let mut names = vec![self.name.clone()];
        if let GltfContainer::Json { stem } = &self.container {
            names.push(format!("{stem}.micromap.bin"));
            names.push(format!("{stem}.bin"));
        }
        names
    }

    /// The files of the asset at `asset` written back with `buffers` (one
    /// geometry per `(mesh, primitive)` of `primitives`), for DIR `out`.
    pub(crate) fn files(
        &self,
        asset: &Path,
        out: &Path,
        buffers: &MicromapBuffers,
        primitives: &[(usize, usize)],
    ) -> Result<Vec<(String, Vec<u8>)>, Failure> {
        let malformed =
            |e: AssetError| Failure::Malformed(format!("--gltf-out {}: {e}", self.name));
        let limits = Limits::default();
        let input = read_limited(asset, &limits)?;
        let from = asset.parent().unwrap_or(Path::new(""));
        let prefix = relative_uri_prefix(out, from).map_err(|e| match e {
            AssetError::Io { .. } => Failure::Io(format!("cannot resolve {e}")),
            other => Failure::Malformed(other.to_string()),
        })?;
        let mut resolve = |uri: &str| read_asset_file(&from.join(uri), &limits);
        let written = write_gltf_micromaps(
            &input,
            &mut resolve,
            &GltfMicromapWrite {
                buffers,
                primitives,
                uri_prefix: &prefix,
            },
            &self.container,
        )
        .map_err(malformed)?;
        let mut files = vec![(self.name.clone(), written.main)];
        files.extend(written.sidecars);
        Ok(files)
    }
}

/// The sampler and cutoff flags (every sampler flag but `--model`) are
/// refused with `what`: they would bake (or check) micromaps for another
/// sampling than the one the asset's renderer does.
fn refuse_overrides(p: &Parsed<'_>, what: &str) -> Result<(), Failure> {
    let mut overrides = flags::SAMPLER
        .iter()
        .map(|flag| flag.name)
        .filter(|&name| name != "--model");
    if let Some(flag) = overrides.find(|f| p.get(f).is_some() || p.flag(f)) {
        return Err(Failure::Usage(format!(
            "{flag} with {what}: the micromaps must match the asset's own samplers and \
             alphaCutoff, which the renderer uses"
        )));
    }
    Ok(())
}

/// A file of at most `limits.max_bytes` (the glTF reader's limit).
fn read_asset_file(path: &Path, limits: &Limits) -> Result<Vec<u8>, AssetError> {
    use std::io::Read as _;
    let io = |e: std::io::Error| AssetError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::new();
    file.take(limits.max_bytes + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > limits.max_bytes {
        return Err(AssetError::LimitExceeded {
            what: format!("file {}", path.display()),
            size: bytes.len() as u64,
            limit: limits.max_bytes,
        });
    }
    Ok(bytes)
}

/// [`read_asset_file`] for the CLI: unreadable exit 3, too large exit 2.
fn read_limited(path: &Path, limits: &Limits) -> Result<Vec<u8>, Failure> {
    read_asset_file(path, limits).map_err(|e| match e {
        AssetError::Io { .. } => Failure::Io(e.to_string()),
        other => Failure::Malformed(other.to_string()),
    })
}

#[derive(Serialize)]
struct PrimitiveReport {
    mesh: usize,
    primitive: usize,
    triangles: usize,
    /// No `EXT_mesh_opacity_micromap` on it (nothing claimed).
    has_micromaps: bool,
    known_micro_triangles: u64,
    unknown_micro_triangles: u64,
    undecided: u64,
    unchecked_micro_triangles: u64,
    contradictions: u64,
    sound: bool,
}

#[derive(Serialize)]
struct ContradictionReport {
    mesh: usize,
    primitive: usize,
    triangle: usize,
    micro_triangle: u64,
    state: String,
    /// Exact witness in texel space: [numerator, log2 denominator] per axis.
    witness_texel_space: Option<[(String, u32); 2]>,
    texel: Option<[u32; 2]>,
}

#[derive(Serialize)]
struct GltfVerifyReport {
    model: &'static str,
    micromaps: usize,
    primitives: Vec<PrimitiveReport>,
    /// Primitives with the extension whose material is not alpha-tested
    /// with a base colour texture: their claims cannot be checked.
    primitives_not_checked: Vec<[usize; 2]>,
    contradictions: u64,
    first_contradictions: Vec<ContradictionReport>,
    complete: bool,
    sound: bool,
}

/// `verify-bake --gltf ASSET`: the asset's `EXT_mesh_opacity_micromap`
/// micromaps against its MASK primitives' textures and materials. Exit 0
/// sound, 1 contradictions or incomplete, 2 malformed, 3 unreadable.
pub(crate) fn verify_gltf(
    p: &Parsed<'_>,
    asset: &str,
    model: Model,
    max_report: usize,
    max_checks: u64,
) -> Result<(String, Exit), Failure> {
    refuse_overrides(p, "verify-bake --gltf")?;
    for flag in ["--texture", "--triangles", "--micromaps", "--index-width"] {
        if p.get(flag).is_some() {
            return Err(Failure::Usage(format!(
                "{flag} with --gltf: the micromaps and triangles are the asset's own"
            )));
        }
    }
    for flag in ["--no-usage", "--lenient-layout"] {
        if p.flag(flag) {
            return Err(Failure::Usage(format!(
                "{flag} with --gltf: the extension's layout rules are always checked"
            )));
        }
    }
    let limits = Limits::default();
    let path = PathBuf::from(asset);
    let classify = |e: AssetError| {
        let message = format!("{asset}: {e}");
        if matches!(e.root(), AssetError::Io { .. }) {
            Failure::Io(message)
        } else {
            Failure::Malformed(message)
        }
    };
    let gltf = read_gltf_file(&path, &limits).map_err(classify)?;
    let bytes = read_limited(&path, &limits)?;
    let base = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let mut resolve = |uri: &str| read_asset_file(&base.join(uri), &limits);
    let micromaps = read_gltf_micromaps(&bytes, &mut resolve, &limits).map_err(classify)?;
    if micromaps.primitives.is_empty() {
        return Err(Failure::Malformed(format!(
            "{asset}: no primitive has EXT_mesh_opacity_micromap: nothing to verify"
        )));
    }
    let textures = gltf
        .images
        .iter()
        .map(|image| {
            image
                .texture()
                .map_err(|e| Failure::Malformed(e.to_string()))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut report = GltfVerifyReport {
        model: model.name(),
        micromaps: micromaps.micromaps.len(),
        primitives: Vec::new(),
        primitives_not_checked: Vec::new(),
        contradictions: 0,
        first_contradictions: Vec::new(),
        complete: true,
        sound: true,
    };
    let mut known_so_far = 0u64;
    for prim in &gltf.primitives {
        let Some(found) = micromaps.primitive(prim.mesh, prim.primitive) else {
            report.primitives.push(PrimitiveReport {
                mesh: prim.mesh,
                primitive: prim.primitive,
                triangles: prim.triangles.len(),
                has_micromaps: false,
                known_micro_triangles: 0,
                unknown_micro_triangles: 0,
                undecided: 0,
                unchecked_micro_triangles: 0,
                contradictions: 0,
                sound: true,
            });
            continue;
        };
        let opacities = (0..found.indices.len())
            .map(|t| micromaps.opacity(found, t))
            .collect::<Option<Vec<TriangleOpacity<'_>>>>()
            .ok_or_else(|| {
                Failure::Malformed(format!(
                    "{asset}: mesh {} primitive {}: an index names no record",
                    prim.mesh, prim.primitive
                ))
            })?;
        let mesh = Mesh {
            triangles: MeshTriangles::Uv(&prim.triangles),
            texture: &textures[prim.image],
            material: prim.material(),
            vertex_alpha: prim.vertex_alpha.as_deref(),
        };
        let first = &mut report.first_contradictions;
        let v = verify_mesh(
            &mesh,
            &opacities,
            model,
            max_checks.saturating_sub(known_so_far),
            &mut |t, c| {
                if first.len() < max_report {
                    first.push(ContradictionReport {
                        mesh: prim.mesh,
                        primitive: prim.primitive,
                        triangle: t,
                        micro_triangle: c.micro_triangle,
                        state: c.state.to_string(),
                        witness_texel_space: witness_texel_space(c.witness),
                        texel: c.texel.map(|(x, y)| [x, y]),
                    });
                }
            },
        )
        .map_err(|e| {
            Failure::Malformed(format!(
                "{asset}: mesh {} primitive {}: {e}",
                prim.mesh, prim.primitive
            ))
        })?;
        known_so_far += v.known;
        let sound = v.is_sound(prim.triangles.len());
        report.contradictions += v.contradictions;
        report.complete &= v.unchecked == 0 && v.triangles_checked == prim.triangles.len();
        report.primitives.push(PrimitiveReport {
            mesh: prim.mesh,
            primitive: prim.primitive,
            triangles: prim.triangles.len(),
            has_micromaps: true,
            known_micro_triangles: v.known,
            unknown_micro_triangles: v.unknown,
            undecided: v.undecided,
            unchecked_micro_triangles: v.unchecked,
            contradictions: v.contradictions,
            sound,
        });
    }
    for found in &micromaps.primitives {
        if !gltf
            .primitives
            .iter()
            .any(|p| p.mesh == found.mesh && p.primitive == found.primitive)
        {
            report
                .primitives_not_checked
                .push([found.mesh, found.primitive]);
        }
    }
    report.complete &= report.primitives_not_checked.is_empty();
    report.sound = report.contradictions == 0 && report.complete;
    let exit = if report.sound {
        Exit::Success
    } else {
        Exit::Failed
    };
    let text = if p.flag("--json") {
        serde_json::to_string_pretty(&report).unwrap_or_default() + "\n"
    } else {
        render_text(&report)
    };
    Ok((text, exit))
}

fn render_text(report: &GltfVerifyReport) -> String {
    let verdict = verdict(report.sound, report.contradictions);
    let with = report.primitives.iter().filter(|p| p.has_micromaps).count();
    let known: u64 = report
        .primitives
        .iter()
        .map(|p| p.known_micro_triangles)
        .sum();
    let unknown: u64 = report
        .primitives
        .iter()
        .map(|p| p.unknown_micro_triangles)
        .sum();
    let mut text = format!(
        "{verdict}: {with} of {} MASK primitives have EXT_mesh_opacity_micromap ({} micromaps), \
         {known} known and {unknown} unknown micro-triangles\n",
        report.primitives.len(),
        report.micromaps
    );
    for p in report.primitives.iter().filter(|p| !p.sound) {
        let _ = writeln!(
            text,
            "  mesh {} primitive {}: {} contradictions, {} known micro-triangles not checked",
            p.mesh, p.primitive, p.contradictions, p.unchecked_micro_triangles
        );
    }
    for [m, p] in &report.primitives_not_checked {
        let _ = writeln!(
            text,
            "  mesh {m} primitive {p}: has micromaps but no alpha-tested base colour texture to check them against"
        );
    }
    let _ = writeln!(text, "contradictions: {}", report.contradictions);
    for c in &report.first_contradictions {
        let (witness, texel) = witness_and_texel(c.witness_texel_space.as_ref(), c.texel);
        let _ = writeln!(
            text,
            "  mesh {} primitive {} triangle {} micro-triangle {} is {} but {witness} reads {texel}",
            c.mesh, c.primitive, c.triangle, c.micro_triangle, c.state
        );
    }
    text
}
