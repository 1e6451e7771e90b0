//! `other-bake`: run another opacity-micromap baker, write Vulkan-layout buffers.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use micromap_index::bake::{AddressMode, Filter};
use other_bakers::bakers::{self, Request, SamplerRequest};
use other_bakers::input::{grid_triangles, parse_triangles, read_png_alpha, triangles_json};
use other_bakers::output::Format;

const USAGE: &str = "\
usage:
  other-bake --baker NAME --texture T.png --triangles TRIS.json --level L --format 2|4 --out DIR
             [--repeat N] [--filter nearest|linear] [--address MODE]
                                       MODE: clamp-to-edge (default), repeat, mirrored-repeat,
                                       clamp-to-border, mirror-clamp-to-edge; filter default linear
  other-bake --grid N                  print an N x N quad grid (2 N^2 triangles) as TRIS.json
  other-bake --list                    list the bakers in this build
environment:
  OMM_SDK_LIB=PATH     your own build of NVIDIA's OMM SDK library (libomm-lib.so), for --baker omm-sdk
  OTHER_BAKE_THREADS=N micromap-index: N threads (default 1); omm-sdk: N > 1 turns on its internal
                       (OpenMP) threads";

struct Args {
    baker: String,
    texture: PathBuf,
    triangles: PathBuf,
    level: u8,
    format: Format,
    out: PathBuf,
    repeat: u32,
    sampler: SamplerRequest,
}

fn parse_args(mut it: impl Iterator<Item = String>) -> Result<Args, String> {
    let (mut baker, mut texture, mut triangles, mut level, mut format, mut out) =
        (None, None, None, None, None, None);
    let mut repeat = 1u32;
    let mut sampler = SamplerRequest::default();
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or_else(|| format!("{flag} needs a value"));
        match flag.as_str() {
            "--baker" => baker = Some(value()?),
            "--texture" => texture = Some(PathBuf::from(value()?)),
            "--triangles" => triangles = Some(PathBuf::from(value()?)),
            "--level" => {
                let v = value()?;
                level = Some(
                    v.parse::<u8>()
                        .ok()
                        .filter(|l| *l <= 12)
                        .ok_or(format!("--level {v}: want 0..=12"))?,
                );
            }
            "--format" => {
                let v = value()?;
                format = Some(
                    v.parse::<u8>()
                        .ok()
                        .and_then(Format::from_states)
                        .ok_or(format!("--format {v}: want 2 or 4"))?,
                );
            }
            "--out" => out = Some(PathBuf::from(value()?)),
            "--filter" => {
                let v = value()?;
                sampler.filter = v
                    .parse::<Filter>()
                    .map_err(|e| format!("--filter {v:?}: {e}"))?;
            }
            "--address" => {
                let v = value()?;
                sampler.address = v
                    .parse::<AddressMode>()
                    .map_err(|e| format!("--address {v:?}: {e}"))?;
            }
            "--repeat" => {
                let v = value()?;
                repeat = v
                    .parse::<u32>()
                    .ok()
                    .filter(|n| *n >= 1)
                    .ok_or(format!("--repeat {v}: want >= 1"))?;
            }
            _ => return Err(format!("unknown argument {flag}")),
        }
    }
    let need = |name: &str| format!("missing {name}");
    Ok(Args {
        baker: baker.ok_or_else(|| need("--baker"))?,
        texture: texture.ok_or_else(|| need("--texture"))?,
        triangles: triangles.ok_or_else(|| need("--triangles"))?,
        level: level.ok_or_else(|| need("--level"))?,
        format: format.ok_or_else(|| need("--format"))?,
        out: out.ok_or_else(|| need("--out"))?,
        repeat,
        sampler,
    })
}

fn run(args: Args) -> Result<(), String> {
    let baker = bakers::by_name(&args.baker).ok_or_else(|| {
        let names: Vec<_> = bakers::all().iter().map(|b| b.name()).collect();
        format!(
            "unknown baker {:?}; this build has {}",
            args.baker,
            names.join(", ")
        )
    })?;
    let texture = read_png_alpha(&args.texture)?;
    let text = std::fs::read_to_string(&args.triangles)
        .map_err(|e| format!("{}: {e}", args.triangles.display()))?;
    let triangles = parse_triangles(&text)?;
    if triangles.is_empty() {
        return Err("no triangles".into());
    }
    let request = Request {
        texture: &texture,
        triangles: &triangles,
        level: args.level,
        format: args.format,
        sampler: args.sampler,
    };
    let mut best = Duration::MAX;
    let mut times = Vec::new();
    let mut result = None;
    for _ in 0..args.repeat {
        let start = Instant::now();
        let baked = baker.bake(&request)?;
        let elapsed = start.elapsed();
        times.push(elapsed.as_secs_f64());
        best = best.min(elapsed);
        match &result {
            None => result = Some(baked),
            Some(first) => {
                let first: &bakers::Baked = first;
                if first.maps != baked.maps {
                    return Err("the baker gave different output on a repeated run".into());
                }
            }
        }
    }
    let baked = result.expect("repeat >= 1");
    baked.maps.validate(triangles.len())?;
    baked
        .maps
        .write(&args.out)
        .map_err(|e| format!("{}: {e}", args.out.display()))?;
    let counts = baked.maps.state_counts(args.level);
    let mut levels: Vec<u16> = baked.maps.records.iter().map(|r| r.level).collect();
    levels.sort_unstable();
    levels.dedup();
    let specials = |i: i32| baked.maps.indices.iter().filter(|&&x| x == i).count();
    let seconds = best.as_secs_f64();
    let mut sorted = times.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    let summary = serde_json::json!({
        "baker": baker.name(),
        "version": baker.version(),
        "texture": {
            "path": args.texture.display().to_string(),
            "width": texture.width,
            "height": texture.height,
        },
        "triangles_file": args.triangles.display().to_string(),
        "level": args.level,
        "record_levels": levels,
        "format": args.format.states(),
        "format_vk": args.format.vk(),
        "sampler": {
            "filter": args.sampler.filter.to_string(),
            "address": args.sampler.address.to_string(),
        },
        "triangles": triangles.len(),
        "micromaps": baked.maps.records.len(),
        "data_bytes": baked.maps.data.len(),
        "special_indices": {
            "fully_transparent": specials(-1),
            "fully_opaque": specials(-2),
            "fully_unknown_transparent": specials(-3),
            "fully_unknown_opaque": specials(-4),
        },
        "micro_triangles_baked": baked.micro_triangles_baked,
        "micro_triangle_states": {
            "transparent": counts[0],
            "opaque": counts[1],
            "unknown_transparent": counts[2],
            "unknown_opaque": counts[3],
        },
        "conventions": baker.conventions(),
        "timing": {
            "what": "wall time of the baker's whole bake call (all of its pipeline steps, \
                     one thread), input already in memory, output not yet converted to files",
            "repeat": args.repeat,
            "best_seconds": seconds,
            "median_seconds": median,
            "all_seconds": times,
            "micro_triangles_per_second": baked.micro_triangles_baked as f64 / seconds,
        },
    });
    let text = serde_json::to_string_pretty(&summary).expect("json") + "\n";
    std::fs::write(args.out.join("summary.json"), &text)
        .map_err(|e| format!("{}: {e}", args.out.display()))?;
    eprintln!(
        "{} L{} f{}: {} micromaps, {} bytes, best {:.6} s (median {:.6} s), {:.3e} micro-triangles/s -> {}",
        baker.name(),
        args.level,
        args.format.states(),
        baked.maps.records.len(),
        baked.maps.data.len(),
        seconds,
        median,
        baked.micro_triangles_baked as f64 / seconds,
        args.out.display()
    );
    Ok(())
}

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1).peekable();
    let result = match args.peek().map(String::as_str) {
        None | Some("-h" | "--help") => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        Some("--list") => {
            for b in bakers::all() {
                println!("{}\t{}", b.name(), b.version());
            }
            println!("omm-sdk loads: {}", bakers::omm_sdk::library::describe());
            return ExitCode::SUCCESS;
        }
        Some("--grid") => {
            let n = args.nth(1).and_then(|n| n.parse::<u32>().ok());
            match n {
                Some(n) if n >= 1 => {
                    print!("{}", triangles_json(&grid_triangles(n)));
                    return ExitCode::SUCCESS;
                }
                _ => Err("--grid N: want N >= 1".to_string()),
            }
        }
        Some(_) => parse_args(args).and_then(run),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("other-bake: {e}\n{USAGE}");
            ExitCode::FAILURE
        }
    }
}
