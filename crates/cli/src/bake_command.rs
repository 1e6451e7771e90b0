//! `micromap-index bake`: the exact baker (library: `micromap_index::bake`,
//! the whole-mesh pipeline in `bake::mesh`) on real assets read by
//! `micromap_index_assets`. This file parses bake's options (the bake's
//! own in `crate::bake_args`, shared with `render`), bakes and serialises
//! the results; `crate::inputs` reads what `bake`, `verify-bake` and
//! `render` share, `summary` is summary.json, and `crate::preview` draws
//! the picture.

mod summary;

use crate::bake_args::{self, BakeArgs};
use crate::inputs::sampler::sampler_options;
use crate::inputs::{flags, index_width, read_input, Job};
use crate::progress::{clear_on_interrupt, Progress};
use cli_support::args::{Command, Flag};
use cli_support::output::{print_then, Exit, Failure, Program};
use cli_support::write_all_or_nothing::{install_interrupt_handler, Destination, Refusal};
use micromap_index::bake::mesh::{bake_meshes, MeshBakeError};
use micromap_index::bake::UvTriangle;
use std::path::{Path, PathBuf};
use std::time::Instant;
use summary::{StateCounts, StatusCounts, Summary, Widening};

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
                            (.gltf: plus NAME.micromap.bin, and NAME.bin with
                            the asset's buffers and images, so DIR can be
                            moved; docs/gltf-out.md)
    preview.png             a tile per material (its texture, captioned with
                            material and cutoff), each pixel of a triangle coloured by
                            the state of the micro-triangle under it (green
                            opaque, blue transparent, yellow unknown-opaque,
                            red unknown-transparent), wrapped with the job's
                            address modes; each distinct triangle once, at
                            most 2^27 pixels of triangles (summary.json
                            counts the rest), with a legend of the colours
                            and the model
  DIR is locked (DIR/.micromap-index.lock, an OS lock that dies with the
  bake) from the check to the last rename: a second bake into the same DIR
  is refused (exit 3) and never mixes its files with the first one's; a
  lock left by a killed bake is taken over and its half-done renames
  undone. Ctrl-C before the last rename removes the temporaries, backups,
  lock and any directory the bake created and leaves DIR as it was; after
  it, DIR holds the new files; the message says which (exit 130).
  With --gltf, a MASK primitive the model does not cover (a
  KHR_texture_transform rotation beyond 65536 radians) is left out, named
  with its reason on stderr and in summary.json
  (refused_primitives), and the rest is baked and written: exit 5
  (--strict: exit 2, nothing written).
  Exit 0 baked; 2 bad options, malformed input, or existing outputs without
  --force (nothing written); 3 unreadable input, unwritable DIR or DIR in
  use by another bake (nothing written), or stdout unwritable after DIR was
  written (DIR complete); 130 interrupted (nothing written); 141 stdout
  closed (DIR complete). On a terminal, progress bars follow the bake and
  the preview on stderr (not with --quiet).",
    flags: &{
        const GROUPS: &[&[Flag]] = &[
            &[
                flags::GLTF,
                flags::CONFINE_URIS,
                Flag::value(
                    "--gltf-out",
                    "NAME",
                    "NAME.gltf or NAME.glb: also write the asset back into DIR with
                         the micromaps (its own samplers and cutoffs only)",
                ),
                Flag::switch(
                    "--strict",
                    "with --gltf: a primitive the model does not cover is an error
                         (exit 2, nothing written), not left out (exit 5)",
                ),
                flags::TEXTURE,
                flags::TRIANGLES,
                flags::OUT,
            ],
            &bake_args::LEVELS,
            &flags::SAMPLER,
            &flags::TEXTURE_UNIT,
            &bake_args::MIPS,
            &[flags::INDEX_WIDTH],
            &bake_args::LIMITS,
            &[
                flags::FORCE,
                Flag::switch("--no-preview", "skip preview.png"),
                Flag::switch("--quiet", "no progress on stderr"),
            ],
        ];
        cli_support::args::concat::<{ cli_support::args::total(GROUPS) }>(GROUPS)
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

pub(crate) fn run_bake(program: &Program, options: &[&str]) -> Exit {
    cli_support::output::finish(
        program,
        bake(program, options).map(|(text, exit)| print_then(program, &text, exit)),
    )
}

fn bake(program: &Program, options: &[&str]) -> Result<(String, Exit), Failure> {
    let p = BAKE
        .parse(options)
        .map_err(|error| Failure::Usage(BAKE.error_message(&error)))?;
    let out = PathBuf::from(
        p.get("--out")
            .ok_or_else(|| Failure::Usage("bake needs --out DIR".into()))?,
    );
    let args = BakeArgs::parse(&p)?;
    let width = index_width(&p)?;
    let s = sampler_options(&p)?;
    let preview = !p.flag("--no-preview");
    let gltf_out = crate::gltf_out::GltfOut::from_options(&p, &OUTPUTS)?;
    let gltf_names = gltf_out
        .as_ref()
        .map(crate::gltf_out::GltfOut::names)
        .unwrap_or_default();
    let mut outputs = OUTPUTS.to_vec();
    outputs.extend(gltf_names.iter().map(String::as_str));
    if let Err(message) = install_interrupt_handler(*program, clear_on_interrupt) {
        program.report(format_args!(
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
    if p.flag("--strict") {
        input.refuse_any()?;
    }
    // The preview's size is known from the textures: refused before the
    // bake, not after it.
    let (tiles, tile_of_job) =
        crate::preview::tiles_of(input.jobs.iter().map(|job| crate::preview::TileSpec {
            image: job.image,
            caption: job.tile_caption(),
        }));
    if preview {
        crate::preview::check_size(&input.images, &tiles, args.options.model)
            .map_err(Failure::Malformed)?;
    }

    // The textures as the baker reads them, and one mesh per job.
    let textures = input.textures()?;
    let meshes = input.meshes(&textures);
    args.check_output_size(&meshes, width)?;
    let options = &args.options;
    let (format, model, mips) = (options.format, options.model, options.mips);
    let threads_used = args.threads.unwrap_or_else(|| {
        std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
    });
    let total = input.jobs.iter().map(|job| job.triangles.len()).sum();
    let progress = Progress::on_stderr("baking", "triangles", total, p.flag("--quiet"));
    let started = Instant::now();
    let baked = bake_meshes(&meshes, options, &mut |done, total| {
        progress.update(done, total);
    })
    .map_err(|e| match e {
        MeshBakeError::Texture { mesh, error } => {
            Failure::Malformed(format!("{}: {error}", input.jobs[mesh].name))
        }
        other => Failure::Malformed(other.to_string()),
    })?;
    let bake_seconds = started.elapsed().as_secs_f64();
    progress.finish();
    let (buffers, report) = (&baked.buffers, &baked.report);
    let mut indices = Vec::new();
    for g in 0..buffers.geometry_count() {
        indices.extend(
            buffers
                .index_bytes(g, width)
                .map_err(|e| Failure::Malformed(e.to_string()))?,
        );
    }
    let jobs = summary::jobs(&input, buffers)?;
    // The preview before the summary, which times it.
    let preview_started = Instant::now();
    let drawn = if preview {
        let drawing = Progress::on_stderr(
            "drawing",
            "triangles of preview.png",
            total,
            p.flag("--quiet"),
        );
        // Drawn where the shader samples: the transformed triangles.
        let placed: Vec<Vec<UvTriangle>> = input.jobs.iter().map(Job::placed_triangles).collect();
        let drawn = crate::preview::render(
            &input.images,
            &tiles,
            model,
            input
                .jobs
                .iter()
                .zip(&placed)
                .zip(&tile_of_job)
                .map(|((job, placed), &tile)| (tile, job.sampler, placed.as_slice())),
            &baked,
            &mut |done| drawing.update(done, total),
        )
        .map_err(Failure::Io)?;
        drawing.finish();
        Some(drawn)
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
        format: format.to_string(),
        format_api_value: u32::from(format.raw()),
        threads: threads_used,
        model: model.name(),
        texture_unit: options.texture_unit.into(),
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
        speculative_work_units: report.speculative_work,
        bake_seconds,
        micro_triangles_per_second: micro as f64 / bake_seconds.max(1e-9),
        preview_seconds,
        preview_micro_triangles: preview_drawn,
        preview_micro_triangles_skipped: preview_skipped,
        jobs,
        warnings: input.warnings.clone(),
        refused_primitives: input
            .refused
            .iter()
            .map(|r| summary::Refused {
                mesh: r.mesh,
                primitive: r.primitive,
                reason: r.reason.to_string(),
            })
            .collect(),
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
            gltf_out.files(&p, asset, buffers, &primitives)?
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
    // Left out, not failed: the files are written; the exit says so.
    for r in &input.refused {
        eprintln!(
            "micromap-index: meshes[{}].primitives[{}] not baked: {}",
            r.mesh, r.primitive, r.reason
        );
    }
    let exit = if input.refused.is_empty() {
        Exit::Success
    } else {
        Exit::Partial
    };
    Ok((summary_json, exit))
}
