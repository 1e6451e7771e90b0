//! `verify-bake --gltf ASSET`: a glTF's own `EXT_mesh_opacity_micromap`
//! micromaps (as `bake --gltf-out` writes them; the extension's rules
//! checked first by `micromap_index_assets`) against its own MASK
//! primitives' textures and materials, by `bake::mesh::verify_mesh`.

use super::chunked::verify_with_progress;
use super::verdict::{verdict, witness_and_texel, witness_texel_space};
use crate::inputs::files::{asset_failure, asset_limits};
use crate::inputs::sampler::refuse_overrides;
use crate::inputs::sampler::TextureUnitJson;
use crate::progress::Progress;
use cli_support::args::Parsed;
use cli_support::input::refuse_blocking;
use cli_support::output::{Exit, Failure};
use micromap_index::bake::mesh::{Mesh, MeshOptions, MeshTriangles};
use micromap_index::micromap::TriangleOpacity;
use micromap_index_assets::{read_gltf_file, read_gltf_micromaps_file};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::PathBuf;

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
    texture_unit: TextureUnitJson,
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
pub(super) fn verify_gltf(
    p: &Parsed<'_>,
    asset: &str,
    judge: &MeshOptions,
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
    let limits = asset_limits(p)?;
    let path = PathBuf::from(asset);
    refuse_blocking(&path).map_err(|e| Failure::Io(format!("cannot read {asset}: {e}")))?;
    // The errors name the asset (`AssetError::In`).
    let gltf = read_gltf_file(&path, &limits).map_err(|e| asset_failure(&e, ""))?;
    let micromaps = read_gltf_micromaps_file(&path, &limits).map_err(|e| asset_failure(&e, ""))?;
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
        model: judge.model.name(),
        texture_unit: judge.texture_unit.into(),
        micromaps: micromaps.micromaps.len(),
        primitives: Vec::new(),
        primitives_not_checked: Vec::new(),
        contradictions: 0,
        first_contradictions: Vec::new(),
        complete: true,
        sound: true,
    };
    let mut known_so_far = 0u64;
    let total = gltf
        .primitives
        .iter()
        .map(|prim| prim.triangles.len())
        .sum();
    let progress = Progress::on_stderr("verifying", "triangles", total, p.flag("--quiet"));
    let mut done_before = 0;
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
            done_before += prim.triangles.len();
            progress.update(done_before, total);
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
        let before = done_before;
        let v = verify_with_progress(
            &mesh,
            &opacities,
            judge,
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
            &mut |done| progress.update(before + done, total),
        )
        .map_err(|e| {
            Failure::Malformed(format!(
                "{asset}: mesh {} primitive {}: {e}",
                prim.mesh, prim.primitive
            ))
        })?;
        known_so_far += v.known;
        done_before += prim.triangles.len();
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
    progress.finish();
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
