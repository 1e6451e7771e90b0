//! `micromap-index verify-bake`: any baker's micromaps checked against
//! the texture under the sampler model, every path through the library's
//! one verifier, `micromap_index::bake::mesh::verify_mesh`: bake's buffer
//! layout against `--texture` and `--triangles` ([`texture`]), or a glTF's
//! own `EXT_mesh_opacity_micromap` against its own textures and materials
//! ([`gltf`]); [`verdict`] is the verdict and witness text both print;
//! [`chunked`] runs the verifier in chunks of triangles for the progress bar
//! (on a terminal only, not with `--quiet`).

mod chunked;
mod gltf;
mod texture;
mod verdict;

use crate::inputs::flags;
use crate::inputs::sampler::judge_option;
use cli_support::args::{Command, Flag};
use cli_support::output::{print_then, Exit, Failure, Program};

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
                flags::CONFINE_URIS,
            ],
            &flags::SAMPLER,
            &flags::TEXTURE_UNIT,
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
                Flag::switch("--quiet", "no progress on stderr"),
            ],
        ];
        cli_support::args::concat::<{ cli_support::args::total(GROUPS) }>(GROUPS)
    },
};

pub(crate) fn run(program: &Program, options: &[&str]) -> Exit {
    cli_support::output::finish(
        program,
        verify(options).map(|(text, exit)| print_then(program, &text, exit)),
    )
}

fn verify(options: &[&str]) -> Result<(String, Exit), Failure> {
    let p = VERIFY_BAKE
        .parse(options)
        .map_err(|error| Failure::Usage(VERIFY_BAKE.error_message(&error)))?;
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
    let judge = judge_option(&p)?;
    if let Some(asset) = p.get("--gltf") {
        return gltf::verify_gltf(&p, asset, &judge, max_report, max_checks);
    }
    texture::verify_texture(&p, &judge, max_report, max_checks)
}
