//! `micromap-index render`: the render check (library:
//! `micromap_index_render`). Reads the bake's input and its micromaps (or
//! bakes them), traces every method on a Vulkan device with ray queries,
//! writes the pictures, the difference pictures and `render.json`, and with
//! `--check` says whether every 4-state method renders the alpha test's
//! picture with no contradicted candidate.

use crate::bake_args::{self, BakeArgs};
use crate::inputs::files::read_buffer_files;
use crate::inputs::sampler::sampler_options;
use crate::inputs::{flags, index_width, read_input, Input};
use crate::preview::encode_rgb;
use cli_support::args::{Command, Flag, Parsed};
use cli_support::output::{print_then, Exit, Failure, Program};
use cli_support::write_all_or_nothing::{Destination, Refusal};
use micromap_index::bake::mesh::{bake_meshes, LevelRule};
use micromap_index::micromap::IndexWidth;
use micromap_index_render::{
    classify, Camera, Classified, ErrorClass, Faults, Frame, Method, Micromaps, RenderError,
    Renderer, Scene, SceneMesh, SceneTexture, Tracer,
};
use serde_json::{json, Value};
use std::fmt::Write as _;
use std::path::PathBuf;

/// The flag table of `render`.
pub(crate) static RENDER: Command = Command {
    name: "render",
    forms: &[
        "(--gltf ASSET.gltf|.glb | --texture T.png --triangles TRIS.json)
                           [--micromaps DIR] --out DIR [options]",
    ],
    about: "  The render check: traces one primary ray per pixel on a Vulkan device (Mesa's
  lavapipe on a CPU) against a BLAS of the asset's alpha-masked triangles (not
  opaque: every candidate reaches the shader) with each tracer: query
  (GL_EXT_ray_query, decisions in the rayQueryProceedEXT loop) and pipeline
  (VK_KHR_ray_tracing_pipeline, decisions in the any-hit shader; the same
  shader code decides), and decides each candidate by each method:
    alpha-test        the alpha test only (the reference picture)
    flat-4-state      the flat micromap: known states decide, unknown -> alpha test
    flat-2-state      the same micromap forced to 2 states (no texture fetch)
    level-order-tree  the level-order succinct tree, 4-state
    paper-tree        the paper's Algorithm 3, 4-state
  The micromaps are DIR's (bake's micromap-data.bin, micromap-triangles.bin,
  micromap-indices.bin; one index per triangle in the asset's order) or, without
  --micromaps, baked here with bake's options and --max-bytes guard. --texture
  and --triangles lay the UV triangles out flat at (u, -v, 0). glTF meshes are
  drawn in their own space (node transforms are not applied). Every known
  decision is checked against the alpha test; a contradicted candidate is
  explained exactly on the host from its binary32 barycentrics: micromap-wrong
  (the exact hit point's alpha test disagrees) or binary32-rounding (the
  shader's texture coordinate crossed a texel boundary). Writes into DIR, all
  or nothing: METHOD.png per method (pipeline-METHOD.png for the pipeline
  tracer), METHOD-diff.png (magenta: pixels that differ from the first
  tracer's alpha-test picture) and render.json (counters per tracer and
  method, CPU time per frame with the device's name, the contradictions).
  --check: exit 0 only if, under every tracer, the alpha test and every
  4-state method render the first tracer's alpha-test picture pixel for pixel
  (the same primitive and t bits) and no 4-state candidate is contradicted.
  Exit 0 rendered (and checked); 1 the check failed (the first contradictions
  on stdout); 2 bad options or input (nothing written); 3 unreadable input,
  unwritable DIR or a Vulkan call failing; 4 no Vulkan device with ray
  queries (nothing written).",
    flags: &{
        const GROUPS: &[&[Flag]] = &[
            &[
                flags::GLTF,
                flags::TEXTURE,
                flags::TRIANGLES,
                Flag::value(
                    "--micromaps",
                    "DIR",
                    "the micromaps, in bake's layout (default: bake them here)",
                ),
                flags::OUT,
            ],
            &bake_args::LEVELS,
            &flags::SAMPLER,
            &bake_args::MIPS,
            &bake_args::LIMITS,
            &[
                Flag::value(
                    "--index-width",
                    "16|32",
                    "micromap-indices.bin width (default 32)",
                ),
                Flag::value("--size", "WxH", "pixels (default 256x256; at most 2^22)"),
                Flag::value(
                    "--camera",
                    "EX,EY,EZ,TX,TY,TZ[,FOV]",
                    "eye, target and vertical field of view in degrees (default: one that
                         frames the asset from the front and above, 40 degrees)",
                ),
                Flag::value(
                    "--methods",
                    "LIST",
                    "comma-separated methods (default all; alpha-test always runs)",
                ),
                Flag::value(
                    "--tracer",
                    "T",
                    "query, pipeline or both (default both: the check needs both to agree)",
                ),
                Flag::value(
                    "--frames",
                    "N",
                    "frames per method; the CPU time is the least per frame (default 1)",
                ),
                Flag::value(
                    "--fault",
                    "F",
                    "a negative control: swap-barycentrics (look up at (b2, b1)) or
                         flip-known (flip every known state)",
                ),
                Flag::value(
                    "--max-report",
                    "N",
                    "contradictions kept per method (default 20)",
                ),
                Flag::switch("--check", "exit 1 unless the 4-state methods match"),
                flags::FORCE,
            ],
        ];
        cli_support::args::concat::<{ cli_support::args::total(GROUPS) }>(GROUPS)
    },
};

pub(crate) fn run(program: &Program, options: &[&str]) -> Exit {
    cli_support::output::finish(
        program,
        render(program, options).map(|(text, exit)| print_then(program, &text, exit)),
    )
}

fn count(p: &Parsed<'_>, name: &str, default: u32, max: u32) -> Result<u32, Failure> {
    match p.get(name) {
        None => Ok(default),
        Some(text) => match text.parse::<u32>() {
            Ok(n) if (1..=max).contains(&n) && text.bytes().all(|b| b.is_ascii_digit()) => Ok(n),
            _ => Err(Failure::Malformed(format!(
                "{name} {text:?}: expected a count 1..={max}"
            ))),
        },
    }
}

fn size(p: &Parsed<'_>) -> Result<(u32, u32), Failure> {
    let text = p.get("--size").unwrap_or("256x256");
    let parsed = text.split_once('x').and_then(|(w, h)| {
        let n = |t: &str| {
            t.bytes()
                .all(|b| b.is_ascii_digit())
                .then(|| t.parse::<u32>().ok())
                .flatten()
        };
        Some((n(w)?, n(h)?))
    });
    match parsed {
        Some((w, h))
            if w > 0
                && h > 0
                && u64::from(w) * u64::from(h) <= micromap_index_render::MAX_PIXELS =>
        {
            Ok((w, h))
        }
        _ => Err(Failure::Malformed(format!(
            "--size {text:?}: expected WxH with at least one pixel and at most {} pixels",
            micromap_index_render::MAX_PIXELS
        ))),
    }
}

/// `--camera`, checked before any setup; `None`: frame the scene
/// ([`framing`]).
fn camera(p: &Parsed<'_>) -> Result<Option<Camera>, Failure> {
    let Some(text) = p.get("--camera") else {
        return Ok(None);
    };
    let numbers: Option<Vec<f32>> = text
        .split(',')
        .map(|t| t.trim().parse::<f32>().ok().filter(|x| x.is_finite()))
        .collect();
    match numbers.as_deref() {
        Some(&[ex, ey, ez, tx, ty, tz]) => Ok(Some(Camera {
            eye: [ex, ey, ez],
            target: [tx, ty, tz],
            fov_y_degrees: 40.0,
        })),
        Some(&[ex, ey, ez, tx, ty, tz, fov]) => Ok(Some(Camera {
            eye: [ex, ey, ez],
            target: [tx, ty, tz],
            fov_y_degrees: fov,
        })),
        _ => Err(Failure::Malformed(format!(
            "--camera {text:?}: expected six or seven finite numbers EX,EY,EZ,TX,TY,TZ[,FOV]"
        ))),
    }
}

/// The camera that frames `scene` from the front and above.
fn framing(scene: &Scene, (w, h): (u32, u32)) -> Result<Camera, Failure> {
    scene
        .bounds()
        .map(|b| Camera::framing(b, w as f32 / h as f32))
        .ok_or_else(|| Failure::Malformed("the scene has no triangles".into()))
}

fn tracers(p: &Parsed<'_>) -> Result<Vec<Tracer>, Failure> {
    match p.get("--tracer") {
        None | Some("both") => Ok(Tracer::ALL.to_vec()),
        Some(name) => Tracer::from_name(name).map(|t| vec![t]).ok_or_else(|| {
            Failure::Malformed(format!(
                "--tracer {name:?}: expected query, pipeline or both"
            ))
        }),
    }
}

/// The name of `method`'s picture under `tracer` (`suffix` "" or "-diff").
fn picture_name(tracer: Tracer, method: Method, suffix: &str) -> String {
    match tracer {
        Tracer::Query => format!("{}{suffix}.png", method.name()),
        Tracer::Pipeline => format!("pipeline-{}{suffix}.png", method.name()),
    }
}

fn methods(p: &Parsed<'_>) -> Result<Vec<Method>, Failure> {
    let mut chosen = vec![Method::AlphaTest];
    match p.get("--methods") {
        None => chosen.extend(&Method::ALL[1..]),
        Some(text) => {
            for name in text.split(',') {
                let method = Method::from_name(name).ok_or_else(|| {
                    Failure::Malformed(format!(
                        "--methods: {name:?} is not one of {}",
                        Method::ALL.map(Method::name).join(", ")
                    ))
                })?;
                if !chosen.contains(&method) {
                    chosen.push(method);
                }
            }
        }
    }
    Ok(chosen)
}

/// The scene of the input: positions from glTF, or the UV layout for
/// `--texture`; refused: a glTF primitive without `POSITION`, `COLOR_0`
/// alpha (the tracer does not interpolate it).
fn scene_of(input: &Input, from_gltf: bool) -> Result<Scene, Failure> {
    let textures = input
        .images
        .iter()
        .map(|image| SceneTexture {
            width: image.width,
            height: image.height,
            alphas: (0..image.height)
                .flat_map(|y| (0..image.width).map(move |x| (x, y)))
                .map(|(x, y)| image.get(x, y).unwrap_or(0.0))
                .collect(),
        })
        .collect();
    let mut scene = Scene::new(textures);
    for job in &input.jobs {
        if job.vertex_alpha.is_some() {
            return Err(Failure::Malformed(format!(
                "{}: COLOR_0 alpha is not rendered (render interpolates no vertex colour); nothing rendered",
                job.name
            )));
        }
        let flat: Vec<[[f32; 3]; 3]>;
        let positions = match &job.positions {
            Some(positions) => positions,
            None if !from_gltf => {
                flat = job
                    .triangles
                    .iter()
                    .map(|t| t.map(|[u, v]| [u, -v, 0.0]))
                    .collect();
                &flat
            }
            None => {
                return Err(Failure::Malformed(format!(
                    "{}: no POSITION attribute to render",
                    job.name
                )))
            }
        };
        scene
            .add_mesh(
                SceneMesh {
                    texture: job.image,
                    material: micromap_index::bake::mesh::Material {
                        sampler: job.sampler,
                        cutoff: job.cutoff,
                        alpha_factor: job.factor,
                    },
                },
                positions,
                &job.triangles,
            )
            .map_err(|e| Failure::Malformed(format!("{}: {e}", job.name)))?;
    }
    Ok(scene)
}

/// Where the micromaps come from: DIR's files (`--micromaps`, read with
/// this index width), or a bake here with bake's options.
enum Source {
    Dir(PathBuf, IndexWidth),
    Bake(BakeArgs),
}

/// The micromap source, checked before any setup: with `--micromaps`, no
/// bake option may be given.
fn source(p: &Parsed<'_>) -> Result<Source, Failure> {
    if let Some(dir) = p.get("--micromaps") {
        for flag in bake_args::names().chain(["--model"]) {
            if p.get(flag).is_some() || p.flag(flag) {
                return Err(Failure::Usage(format!(
                    "{flag} is for baking here; it does not go with --micromaps"
                )));
            }
        }
        return Ok(Source::Dir(PathBuf::from(dir), index_width(p)?));
    }
    Ok(Source::Bake(BakeArgs::parse(p)?))
}

fn micromaps(source: &Source, input: &Input) -> Result<(Micromaps, String), Failure> {
    let args = match source {
        Source::Dir(dir, width) => {
            let files = read_buffer_files(dir)?;
            let maps = Micromaps::from_bytes(files.data, files.records, files.indices, *width)
                .map_err(|e| Failure::Malformed(format!("{}: {e}", dir.display())))?;
            return Ok((maps, dir.display().to_string()));
        }
        Source::Bake(args) => args,
    };
    let options = &args.options;
    let textures = input.textures()?;
    let meshes = input.meshes(&textures);
    args.check_output_size(&meshes, IndexWidth::U32)?;
    let baked = bake_meshes(&meshes, options, &mut |_, _| {})
        .map_err(|e| Failure::Malformed(e.to_string()))?;
    let maps =
        Micromaps::from_buffers(&baked.buffers).map_err(|e| Failure::Malformed(e.to_string()))?;
    let level = match options.levels {
        LevelRule::Fixed(l) => format!("level {}", l.get()),
        LevelRule::Useful { max } => format!("level auto (max {})", max.get()),
    };
    Ok((
        maps,
        format!(
            "baked here: {level}, {}-state, model {}",
            options.format.states(),
            options.model.name()
        ),
    ))
}

/// A colour per mesh, a little brighter or darker per triangle.
fn picture(frame: &Frame, scene: &Scene) -> Vec<u8> {
    const PALETTE: [[u8; 3]; 6] = [
        [96, 170, 72],
        [214, 160, 64],
        [80, 140, 210],
        [190, 96, 160],
        [220, 110, 80],
        [120, 190, 180],
    ];
    let mut mesh_index = std::collections::HashMap::new();
    frame
        .hits
        .iter()
        .flat_map(|&[hit, _]| {
            if hit == 0 {
                return [24, 24, 32];
            }
            let t = (hit - 1) as usize;
            let key = scene
                .mesh_of(t)
                .map(|m| (m.texture, m.material.cutoff.alpha().to_bits()));
            let next = mesh_index.len();
            let m = *mesh_index.entry(key).or_insert(next);
            let shade = 0.8 + 0.2 * ((t.wrapping_mul(2654435761) >> 8) % 256) as f32 / 255.0;
            PALETTE[m % PALETTE.len()].map(|c| (f32::from(c) * shade) as u8)
        })
        .collect()
}

fn difference(frame: &Frame, reference: &Frame, reference_rgb: &[u8]) -> (Vec<u8>, u64) {
    let mut differing = 0;
    let rgb = frame
        .hits
        .iter()
        .zip(&reference.hits)
        .enumerate()
        .flat_map(|(i, (a, b))| {
            if a == b {
                [0, 1, 2].map(|k| reference_rgb[3 * i + k] / 3)
            } else {
                differing += 1;
                [255, 0, 255]
            }
        })
        .collect();
    (rgb, differing)
}

fn hex(bits: u32) -> String {
    format!("0x{bits:08x}")
}

fn contradiction_json(c: &Classified) -> Value {
    let r = &c.contradiction;
    json!({
        "pixel": [r.x, r.y],
        "triangle": r.triangle,
        "micro_triangle": c.micro_triangle,
        "shader_micro_triangle": r.micro_triangle,
        "level": c.level,
        "b1": hex(r.b1_bits),
        "b2": hex(r.b2_bits),
        "state": if r.state == 1 { "opaque" } else { "transparent" },
        "class": c.class.name(),
        "exact_texel_point": c.exact_texel_point,
        "exact_alpha_test": if c.exact_opaque { "opaque" } else { "transparent" },
        "texels": c.texels.iter().map(|&(x, y, a)| json!({"x": x, "y": y, "alpha": a})).collect::<Vec<_>>(),
        "binary32_uv": c.binary32_uv,
    })
}

fn contradiction_line(label: &str, c: &Classified) -> String {
    let r = &c.contradiction;
    let texels: Vec<String> = c
        .texels
        .iter()
        .map(|(x, y, a)| format!("({x}, {y}) alpha {a}"))
        .collect();
    format!(
        "{}: pixel ({}, {}) triangle {} micro-triangle {} (level {}) known {} at b1 = {}, b2 = {}: {}; exact point ({}, {}) texels reads {} -> {}",
        label,
        r.x,
        r.y,
        r.triangle,
        c.micro_triangle,
        c.level.map_or("special".into(), |l| l.to_string()),
        if r.state == 1 { "opaque" } else { "transparent" },
        hex(r.b1_bits),
        hex(r.b2_bits),
        c.class.name(),
        c.exact_texel_point[0],
        c.exact_texel_point[1],
        if texels.is_empty() { "the border".into() } else { texels.join(", ") },
        if c.exact_opaque { "opaque" } else { "transparent" },
    )
}

/// Exit 4 after saying why there is no device.
fn no_device(program: &Program, message: &str) -> Failure {
    program.report(format_args!("render: {message}"));
    Failure::Exit(Exit::NoDevice)
}

fn render_failure(program: &Program, e: &RenderError) -> Failure {
    match e.class() {
        ErrorClass::NoDevice => no_device(program, &e.to_string()),
        ErrorClass::Input => Failure::Malformed(e.to_string()),
        ErrorClass::Device => Failure::Io(format!("render: {e}")),
    }
}

fn render(program: &Program, options: &[&str]) -> Result<(String, Exit), Failure> {
    let p = RENDER
        .parse(options)
        .map_err(|error| Failure::Usage(error.message("render")))?;
    let out = PathBuf::from(
        p.get("--out")
            .ok_or_else(|| Failure::Usage("render needs --out DIR".into()))?,
    );
    let size = size(&p)?;
    let methods = methods(&p)?;
    let tracers = tracers(&p)?;
    let frames = count(&p, "--frames", 1, 1000)?;
    let max_report = p
        .get("--max-report")
        .map_or(Ok(20), |t| {
            t.parse::<u32>()
                .map_err(|_| Failure::Malformed(format!("--max-report {t:?}: expected a count")))
        })?
        .min(1 << 16);
    let faults = match p.get("--fault") {
        None => Faults::default(),
        Some("swap-barycentrics") => Faults {
            swap_barycentrics: true,
            ..Faults::default()
        },
        Some("flip-known") => Faults {
            flip_known: true,
            ..Faults::default()
        },
        Some(other) => {
            return Err(Failure::Malformed(format!(
                "--fault {other:?}: expected swap-barycentrics or flip-known"
            )))
        }
    };
    let s = sampler_options(&p)?;
    let given_camera = camera(&p)?;
    let source = source(&p)?;
    let mut names: Vec<String> = vec!["render.json".into()];
    for (i, &t) in tracers.iter().enumerate() {
        for &m in &methods {
            names.push(picture_name(t, m, ""));
            if i > 0 || m != Method::AlphaTest {
                names.push(picture_name(t, m, "-diff"));
            }
        }
    }
    let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
    let input = read_input(&p, &s)?;
    let scene = scene_of(&input, p.get("--gltf").is_some())?;
    let camera = match given_camera {
        Some(camera) => camera,
        None => framing(&scene, size)?,
    };
    let (maps, source) = micromaps(&source, &input)?;
    let renderer = Renderer::new(&scene, Some(&maps)).map_err(|e| render_failure(program, &e))?;
    if let Some(missing) = tracers.iter().find(|t| !renderer.tracers().contains(t)) {
        return Err(no_device(
            program,
            &format!(
                "{}: no VK_KHR_ray_tracing_pipeline for the {} tracer (--tracer query traces without it)",
                renderer.device_name(),
                missing.name()
            ),
        ));
    }
    // Claimed once the device is there: exit 4 leaves DIR untouched.
    let destination = Destination::claim(&out, &name_refs, p.flag("--force")).map_err(
        |refusal| match refusal {
            Refusal::Refused(message) => Failure::Malformed(message),
            Refusal::Io(message) => Failure::Io(message),
        },
    )?;
    let mut traced: Vec<(Frame, Vec<Classified>, Option<f64>, f64)> = Vec::new();
    for &tracer in &tracers {
        for &method in &methods {
            let mut best: Option<Frame> = None;
            let (mut cpu, mut wall) = (None::<f64>, f64::INFINITY);
            for _ in 0..frames {
                let frame = renderer
                    .render(tracer, method, &camera, size, faults, max_report)
                    .map_err(|e| render_failure(program, &e))?;
                cpu = match (cpu, frame.cpu_seconds) {
                    (Some(a), Some(b)) => Some(a.min(b)),
                    (a, b) => a.or(b),
                };
                wall = wall.min(frame.wall_seconds);
                if let Some(previous) = &best {
                    if previous.hits != frame.hits || previous.counters != frame.counters {
                        return Err(Failure::Failed(format!(
                        "{} {}: two frames of the same method differ (the device is not deterministic)",
                        tracer.name(),
                        method.name()
                    )));
                    }
                }
                best = Some(frame);
            }
            let frame = best.expect("at least one frame");
            let classified = frame
                .contradictions
                .iter()
                .filter_map(|c| classify(&scene, &maps, c))
                .collect();
            traced.push((frame, classified, cpu, wall));
        }
    }
    let reference = traced[0].0.clone();
    let reference_rgb = picture(&reference, &scene);
    let mut files = Vec::new();
    let mut method_json = Vec::new();
    let mut text = format!(
        "device: {}\nmicromaps: {source}\nsize: {}x{}, {} triangles\n",
        renderer.device_name(),
        size.0,
        size.1,
        scene.triangle_count()
    );
    let _ = writeln!(
        text,
        "{:<8} {:<17} {:>10} {:>10} {:>9} {:>10} {:>8} {:>9} {:>10}",
        "tracer",
        "method",
        "candidates",
        "fetches",
        "known",
        "unknown",
        "contra",
        "differ",
        "cpu ms"
    );
    let mut failures = Vec::new();
    let encode = |rgb: &[u8]| {
        encode_rgb(size.0, size.1, rgb).map_err(|e| Failure::Io(format!("render: PNG: {e}")))
    };
    for (i, (frame, classified, cpu, wall)) in traced.iter().enumerate() {
        let (tracer, method) = (frame.tracer, frame.method);
        // The label in messages: the method, with the tracer when both run.
        let label = if tracers.len() > 1 {
            format!("{} {}", tracer.name(), method.name())
        } else {
            method.name().to_string()
        };
        let rgb = if i == 0 {
            reference_rgb.clone()
        } else {
            picture(frame, &scene)
        };
        files.push((picture_name(tracer, method, ""), encode(&rgb)?));
        let mut differing = 0;
        if i > 0 {
            let (diff, n) = difference(frame, &reference, &reference_rgb);
            differing = n;
            files.push((picture_name(tracer, method, "-diff"), encode(&diff)?));
        }
        let c = frame.counters;
        let ratio = |a: u64, b: u64| if b == 0 { 0.0 } else { a as f64 / b as f64 };
        // Against the same tracer's alpha test (the candidates it sees
        // depend on its traversal).
        let alpha_fetches = traced
            .iter()
            .find(|(f, ..)| f.tracer == tracer && f.method == Method::AlphaTest)
            .map_or(0, |(f, ..)| f.counters.texture_fetches);
        let fetches_saved = 1.0 - ratio(c.texture_fetches, alpha_fetches);
        let _ = writeln!(
            text,
            "{:<8} {:<17} {:>10} {:>10} {:>9} {:>10} {:>8} {:>9} {:>10}",
            tracer.name(),
            method.name(),
            c.candidates,
            c.texture_fetches,
            c.known,
            c.unknown,
            c.contradicted,
            differing,
            cpu.map_or("-".into(), |s| format!("{:.1}", 1e3 * s))
        );
        // The other tracer's alpha test must render the same picture too.
        if (method.is_four_state() || method == Method::AlphaTest) && differing > 0 {
            failures.push(format!(
                "{label}: {differing} pixels differ from {} (see {})",
                picture_name(reference.tracer, Method::AlphaTest, ""),
                picture_name(tracer, method, "-diff")
            ));
        }
        if method.is_four_state() {
            if c.contradicted > 0 {
                failures.push(format!(
                    "{label}: {} contradicted candidates",
                    c.contradicted
                ));
                failures.extend(
                    classified
                        .iter()
                        .take(5)
                        .map(|x| contradiction_line(&label, x)),
                );
            }
            if c.invalid > 0 {
                failures.push(format!(
                    "{label}: {} lookups returned the invalid state",
                    c.invalid
                ));
            }
        }
        let mut by_class = serde_json::Map::new();
        for x in classified {
            let e = by_class.entry(x.class.name()).or_insert(json!(0));
            *e = json!(e.as_u64().unwrap_or(0) + 1);
        }
        method_json.push(json!({
            "tracer": tracer.name(),
            "method": method.name(),
            "four_state": method.is_four_state(),
            "rays": c.rays,
            "candidates": c.candidates,
            "texture_fetches": c.texture_fetches,
            "known": c.known,
            "unknown": c.unknown,
            "invalid": c.invalid,
            "contradicted": c.contradicted,
            "pixels_differing_from_alpha_test": differing,
            "texture_fetches_saved_fraction": if method == Method::AlphaTest { 0.0 } else { fetches_saved },
            "decided_without_texture_fraction": ratio(c.known, c.candidates),
            "cpu_seconds_per_frame": cpu,
            "wall_seconds_per_frame": wall,
            "frames": frames,
            "contradictions_classified": by_class,
            "contradictions": classified.iter().map(contradiction_json).collect::<Vec<_>>(),
        }));
    }
    let passed = failures.is_empty();
    let report_json = json!({
        "device": renderer.device_name(),
        "time": "process CPU seconds per frame on this device (a CPU device's threads are the process's), least of the frames",
        "size": [size.0, size.1],
        "camera": {"eye": camera.eye, "target": camera.target, "fov_y_degrees": camera.fov_y_degrees},
        "triangles": scene.triangle_count(),
        "micromaps": source,
        "fault": p.get("--fault"),
        "tracers": tracers.iter().map(|t| t.name()).collect::<Vec<_>>(),
        "methods": method_json,
        "check": {"passed": passed, "failures": failures},
    });
    let json_text = serde_json::to_string_pretty(&report_json)
        .map_err(|e| Failure::Io(format!("render.json: {e}")))?;
    files.insert(
        0,
        ("render.json".into(), format!("{json_text}\n").into_bytes()),
    );
    destination.write(&files, &[]).map_err(Failure::Io)?;
    let exit = if p.flag("--check") && !passed {
        let _ = writeln!(text, "check: FAILED");
        for f in &failures {
            let _ = writeln!(text, "  {f}");
        }
        Exit::Failed
    } else {
        if p.flag("--check") {
            let _ = writeln!(
                text,
                "check: passed (under every tracer, every 4-state method renders the alpha test's picture; no contradicted candidate)"
            );
        }
        Exit::Success
    };
    let _ = write!(text, "wrote {}", out.display());
    text.push('\n');
    Ok((text, exit))
}
