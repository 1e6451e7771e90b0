//! `micromap-index render`: the render check (library:
//! `micromap_index_render`). Reads the bake's input and its micromaps (or
//! bakes them), traces every method on a Vulkan device with each tracer,
//! writes the pictures, the difference pictures and `render.json`, and with
//! `--check` says whether every 4-state method (the driver's micromap
//! included) renders the alpha test's picture with no contradicted
//! candidate, and the driver's forced 2-state micromap the emulated one's.
//! What it writes about the frames is in `report`.

mod options;
mod report;

use crate::bake_args::{self, BakeArgs};
use crate::inputs::files::read_buffer_files;
use crate::inputs::sampler::sampler_options;
use crate::inputs::{flags, index_width, read_input, Input};
use crate::preview::encode_rgb;
use cli_support::args::{Command, Flag, Parsed};
use cli_support::output::{print_then, Exit, Failure, Program};
use cli_support::write_all_or_nothing::{Destination, Refusal};
use micromap_index::bake::mesh::{bake_meshes, LevelRule};
use micromap_index::bake::UvTransform;
use micromap_index::micromap::IndexWidth;
use micromap_index_render::{
    classify_lookup, Camera, Classified, ErrorClass, Faults, Frame, Lookup, Method, Micromaps,
    RenderError, Renderer, RendererOptions, Scene, SceneMesh, SceneTexture, Tracer,
};
use options::{camera, count, device, faults, lookups, max_report, methods, size, tracers};
use report::{contradiction_json, contradiction_line, difference, picture, picture_name};
use serde_json::json;
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
  lavapipe on a CPU) against the asset's alpha-masked meshes (one BLAS each,
  placed by glTF's node transforms; not opaque: every candidate the traversal
  does not decide reaches the shader) with each tracer: query (GL_EXT_ray_query,
  decisions in the rayQueryProceedEXT loop) and pipeline
  (VK_KHR_ray_tracing_pipeline, decisions in the any-hit shader; the same
  shader code decides), with each lookup (what reads the texture for the alpha
  test): shader (binary32 code filters texels from a buffer, so the host can
  recompute every fetch) and sampler (textureLod through a combined image
  sampler per mesh: an R8_UNORM image of the alpha, the mesh's filter, address
  modes and border, level 0; the device's texture unit judges; border alphas
  other than 0 and 1 are refused, mirror clamp to edge needs
  samplerMirrorClampToEdge), and decides each candidate by each method:
    alpha-test        the alpha test only (the reference picture)
    flat-4-state      the flat micromap: known states decide, unknown -> alpha test
    flat-2-state      the same micromap forced to 2 states (no texture fetch)
    level-order-tree  the level-order succinct tree, 4-state
    paper-tree        the paper's Algorithm 3, 4-state
    hardware          the driver's micromap (VK_EXT_opacity_micromap) built from
                      the same buffers; any-hit runs the alpha test on what the
                      traversal hands it (only with --methods)
    hardware-2-state  the same, every instance forced to 2 states (with it,
                      flat-2-state runs too)
  The micromaps are DIR's (bake's micromap-data.bin, micromap-triangles.bin,
  micromap-indices.bin; one index per triangle in the asset's order) or, without
  --micromaps, baked here with bake's options and --max-bytes guard. --texture
  and --triangles lay the UV triangles out flat at (u, -v, 0). Every known
  decision is checked against the alpha test; a contradicted candidate is
  explained exactly on the host from its binary32 barycentrics: micromap-wrong
  (the exact hit point's alpha test disagrees) or binary32-rounding (the
  shader's texture coordinate crossed a texel boundary; texture-unit under the
  sampler lookup); the first ones are listed in pixel order. Writes into DIR,
  all or nothing: METHOD.png per method (pipeline-METHOD.png for the pipeline
  tracer; sampler-... for the sampler lookup), METHOD-diff.png (magenta:
  pixels that differ from the picture the method must equal: the first
  tracer's alpha test under the same lookup, or flat-2-state for
  hardware-2-state; for the sampler lookup's own, the shader's) and render.json
  (the device, driver and Vulkan version; counters, the hit fraction and times
  per tracer and method; the micromaps' levels per primitive; the
  contradictions). --check: exit 0 only if, under every tracer and lookup, the
  alpha test, every 4-state method and hardware render the first tracer's
  alpha-test picture of that lookup pixel for pixel (the same primitive and t
  bits), hardware-2-state renders the same tracer's flat-2-state picture, and no
  4-state candidate is contradicted. Exit 0 rendered (and checked); 1 the check
  failed (the first contradictions on stdout); 2 bad options or input (nothing
  written); 3 unreadable input, unwritable DIR or a Vulkan call failing; 4 no
  Vulkan device with what the tracers, lookups and methods need:
  VK_KHR_ray_query (query), VK_KHR_ray_tracing_pipeline (pipeline),
  runtimeDescriptorArray and shaderSampledImageArrayNonUniformIndexing
  (sampler), VK_EXT_opacity_micromap (hardware) (nothing written).",
    flags: &{
        const GROUPS: &[&[Flag]] = &[
            &[
                flags::GLTF,
                flags::CONFINE_URIS,
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
            &flags::TEXTURE_UNIT,
            &bake_args::MIPS,
            &bake_args::LIMITS,
            &[
                flags::INDEX_WIDTH,
                Flag::value("--size", "WxH", "pixels (default 256x256; at most 2^22)"),
                Flag::value(
                    "--camera",
                    "EX,EY,EZ,TX,TY,TZ[,FOV]",
                    "eye, target and vertical field of view in degrees (default: one that
                         fits the drawn triangles from the front and above, 40 degrees)",
                ),
                Flag::value(
                    "--methods",
                    "LIST",
                    "comma-separated methods (default: the five emulated ones; alpha-test
                         always runs)",
                ),
                Flag::value(
                    "--tracer",
                    "T",
                    "query, pipeline or both (default both: the check needs both to agree)",
                ),
                Flag::value(
                    "--lookup",
                    "L",
                    "shader, sampler or both (default both: the check holds under the
                         shader's arithmetic and the device's texture unit alike)",
                ),
                Flag::value(
                    "--device",
                    "N|NAME",
                    "the Vulkan device: its number in the loader's order or a part of its
                         name (default: the first with what the tracers and methods need)",
                ),
                Flag::value(
                    "--frames",
                    "N",
                    "frames per method; each time is the least per frame (default 1)",
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

/// The camera that fits `scene`'s drawn triangles from the front and above.
fn framing(scene: &Scene, (w, h): (u32, u32)) -> Result<Camera, Failure> {
    Camera::fitting(&scene.world_triangles(), w as f32 / h as f32)
        .ok_or_else(|| Failure::Malformed("the scene draws no triangle".into()))
}

/// The scene of the input: positions from glTF (with `COLOR_0` alpha and
/// the transformed texture coordinates), or the UV layout for
/// `--texture`; refused: a glTF primitive without `POSITION`.
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
        let placed = job.placed_triangles();
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
            .add_placed_mesh_with_vertex_alpha(
                SceneMesh {
                    texture: job.image,
                    // The shader samples the transformed coordinates:
                    // the scene interpolates them per vertex (placed),
                    // which the bake's margin covers too (`docs/bake.md`,
                    // "Texture transforms").
                    material: micromap_index::bake::mesh::Material {
                        sampler: job.sampler,
                        cutoff: job.cutoff,
                        alpha_factor: job.factor,
                        uv_transform: UvTransform::IDENTITY,
                    },
                },
                positions,
                &placed,
                job.vertex_alpha.as_deref(),
                &job.instances,
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

/// Exit 4 after saying why there is no device.
fn no_device(program: &Program, message: &str) -> Failure {
    program.report(format_args!("render: {message}"));
    Failure::Exit(Exit::NoDevice)
}

fn render_failure(program: &Program, e: &RenderError) -> Failure {
    match e.class() {
        ErrorClass::NoDevice => {
            let mut message = e.to_string();
            if let RenderError::NoSuitableDevice { found, .. } = e {
                let lacks = |name| found.iter().any(|(_, l)| l.contains(&name));
                if lacks("VK_KHR_ray_query") {
                    message.push_str(" (--tracer pipeline traces without VK_KHR_ray_query)");
                }
                if lacks("VK_KHR_ray_tracing_pipeline") {
                    message
                        .push_str(" (--tracer query traces without VK_KHR_ray_tracing_pipeline)");
                }
                if lacks("VK_EXT_opacity_micromap") {
                    message.push_str(" (--methods without hardware traces without it)");
                }
            }
            no_device(program, &message)
        }
        ErrorClass::Input => Failure::Malformed(e.to_string()),
        ErrorClass::Device => Failure::Io(format!("render: {e}")),
    }
}

/// One traced method: its (first) frame, the classified contradictions
/// and the least times of its frames.
struct Traced {
    frame: Frame,
    classified: Vec<Classified>,
    cpu: Option<f64>,
    wall: f64,
    device: Option<f64>,
}

/// The least of two optional times.
fn least(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// What `render` traces, and how.
struct Plan<'a> {
    lookups: &'a [Lookup],
    tracers: &'a [Tracer],
    methods: &'a [Method],
    camera: Camera,
    size: (u32, u32),
    faults: Faults,
    max_report: u32,
    frames: u32,
}

/// Every method under every tracer, `frames` times each (the frames must
/// agree), with its contradictions classified.
fn trace_all(
    program: &Program,
    renderer: &Renderer,
    plan: &Plan<'_>,
    (scene, maps): (&Scene, &Micromaps),
) -> Result<Vec<Traced>, Failure> {
    let mut traced = Vec::new();
    let passes = plan
        .lookups
        .iter()
        .flat_map(|&l| plan.tracers.iter().map(move |&t| (l, t)));
    for (lookup, tracer) in passes {
        for &method in plan.methods {
            let mut best: Option<Frame> = None;
            let (mut cpu, mut wall, mut device) = (None, f64::INFINITY, None);
            for _ in 0..plan.frames {
                let frame = renderer
                    .render(
                        (tracer, lookup),
                        method,
                        &plan.camera,
                        plan.size,
                        plan.faults,
                        plan.max_report,
                    )
                    .map_err(|e| render_failure(program, &e))?;
                cpu = least(cpu, frame.cpu_seconds);
                device = least(device, frame.device_seconds);
                wall = wall.min(frame.wall_seconds);
                if let Some(previous) = &best {
                    if previous.hits != frame.hits || previous.counters != frame.counters {
                        return Err(Failure::Failed(format!(
                            "{} {} {}: two frames of the same method differ (the device is not deterministic)",
                            lookup.name(),
                            tracer.name(),
                            method.name()
                        )));
                    }
                }
                best.get_or_insert(frame);
            }
            let frame = best.expect("at least one frame");
            let classified = frame
                .contradictions
                .iter()
                .filter_map(|c| classify_lookup(scene, maps, c, lookup))
                .collect();
            traced.push(Traced {
                frame,
                classified,
                cpu,
                wall,
                device,
            });
        }
    }
    Ok(traced)
}

fn ms(seconds: Option<f64>) -> String {
    seconds.map_or("-".into(), |s| format!("{:.2}", 1e3 * s))
}

fn render(program: &Program, options: &[&str]) -> Result<(String, Exit), Failure> {
    let p = RENDER
        .parse(options)
        .map_err(|error| Failure::Usage(RENDER.error_message(&error)))?;
    let out = PathBuf::from(
        p.get("--out")
            .ok_or_else(|| Failure::Usage("render needs --out DIR".into()))?,
    );
    let size = size(&p)?;
    let methods = methods(&p)?;
    let tracers = tracers(&p)?;
    let lookups = lookups(&p)?;
    let device = device(&p)?;
    let frames = count(&p, "--frames", 1, 1000)?;
    let max_report = max_report(&p)?;
    let faults = faults(&p)?;
    let s = sampler_options(&p)?;
    let given_camera = camera(&p)?;
    let source = source(&p)?;
    let auto_levels = matches!(&source, Source::Bake(args) if matches!(args.options.levels, LevelRule::Useful { .. }));
    let mut names: Vec<String> = vec!["render.json".into()];
    for (j, &l) in lookups.iter().enumerate() {
        for (i, &t) in tracers.iter().enumerate() {
            for &m in &methods {
                names.push(picture_name((l, t), m, ""));
                if j > 0 || i > 0 || m != Method::AlphaTest {
                    names.push(picture_name((l, t), m, "-diff"));
                }
            }
        }
    }
    let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
    let input = read_input(&p, &s)?;
    // render draws and checks every primitive it reads: none may be left out.
    input.refuse_any()?;
    let scene = scene_of(&input, p.get("--gltf").is_some())?;
    let camera = match given_camera {
        Some(camera) => camera,
        None => framing(&scene, size)?,
    };
    let (maps, source) = micromaps(&source, &input)?;
    let options = RendererOptions {
        device,
        tracers: tracers.clone(),
        hardware: methods.iter().any(|m| m.is_hardware()),
        lookups: lookups.clone(),
    };
    let renderer =
        Renderer::new(&scene, Some(&maps), &options).map_err(|e| render_failure(program, &e))?;
    // Claimed once the device is there: exit 4 leaves DIR untouched.
    let destination = Destination::claim(&out, &name_refs, p.flag("--force")).map_err(
        |refusal| match refusal {
            Refusal::Refused(message) => Failure::Malformed(message),
            Refusal::Io(message) => Failure::Io(message),
        },
    )?;
    let plan = Plan {
        lookups: &lookups,
        tracers: &tracers,
        methods: &methods,
        camera,
        size,
        faults,
        max_report,
        frames,
    };
    let traced = trace_all(program, &renderer, &plan, (&scene, &maps))?;
    let reference = traced[0].frame.clone();
    let reference_rgb = picture(&reference, &scene);
    let mut level_json = Vec::new();
    let mut level_lines = Vec::new();
    for (m, job) in input.jobs.iter().enumerate() {
        let range = scene.mesh_triangles(m);
        let (value, line) = report::levels(&job.name, range.len(), &maps.level_counts(range));
        level_json.push(value);
        level_lines.push(line);
    }
    let mut files = Vec::new();
    let mut method_json = Vec::new();
    let mut text = format!(
        "device: {}\nmicromaps: {source}\nsize: {}x{}, {} triangles, {:.1}% of the pixels hit (the first tracer's alpha test)\n",
        renderer.device_name(),
        size.0,
        size.1,
        scene.triangle_count(),
        100.0 * reference.hit_fraction()
    );
    if auto_levels {
        let _ = writeln!(text, "levels (--level auto):");
        for line in &level_lines {
            let _ = writeln!(text, "  {line}");
        }
    }
    let _ = writeln!(
        text,
        "{:<10} {:<17} {:>10} {:>10} {:>9} {:>10} {:>8} {:>9} {:>9} {:>9}",
        "tracer",
        "method",
        "candidates",
        "fetches",
        "known",
        "unknown",
        "contra",
        "differ",
        "cpu ms",
        "device ms"
    );
    let mut failures = Vec::new();
    let encode = |rgb: &[u8]| {
        encode_rgb(size.0, size.1, rgb).map_err(|e| Failure::Io(format!("render: PNG: {e}")))
    };
    let find = |lookup: Lookup, tracer: Tracer, method: Method| {
        traced.iter().find(|t| {
            t.frame.lookup == lookup && t.frame.tracer == tracer && t.frame.method == method
        })
    };
    for (i, t) in traced.iter().enumerate() {
        let frame = &t.frame;
        let (lookup, tracer, method) = (frame.lookup, frame.tracer, frame.method);
        let pass = (lookup, tracer);
        // The label in messages: the method, with the tracer when both run
        // and the lookup when both run.
        let mut label = method.name().to_string();
        if tracers.len() > 1 {
            label = format!("{} {label}", tracer.name());
        }
        if lookups.len() > 1 {
            label = format!("{} {label}", lookup.name());
        }
        // This lookup's reference: its first tracer's alpha test.
        let lookup_reference = traced
            .iter()
            .find(|r| r.frame.lookup == lookup && r.frame.method == Method::AlphaTest)
            .map_or(&reference, |r| &r.frame);
        // The reference of another lookup is compared with the first
        // lookup's (the "differ" column and its difference picture), not
        // checked against it.
        let own_reference = i > 0 && std::ptr::eq(frame, lookup_reference);
        let rgb = if i == 0 {
            reference_rgb.clone()
        } else {
            picture(frame, &scene)
        };
        files.push((picture_name(pass, method, ""), encode(&rgb)?));
        // Against the first tracer's alpha test: the "differ" column.
        let differing = if i > 0 {
            difference(frame, &reference, &reference_rgb).1
        } else {
            0
        };
        // Against the picture it must equal (and its difference picture).
        let must_equal = match method.reference() {
            _ if own_reference => Some(&reference),
            Some(Method::AlphaTest) | None => Some(lookup_reference),
            Some(other) => find(lookup, tracer, other).map(|r| &r.frame),
        };
        let mut differing_from_reference = None;
        if let (true, Some(r)) = (i > 0, must_equal) {
            let r_rgb = if std::ptr::eq(r, &reference) {
                reference_rgb.clone()
            } else {
                picture(r, &scene)
            };
            let (diff, n) = difference(frame, r, &r_rgb);
            files.push((picture_name(pass, method, "-diff"), encode(&diff)?));
            if !own_reference {
                differing_from_reference = method.reference().map(|_| n);
            }
        }
        let c = frame.counters;
        let ratio = |a: u64, b: u64| if b == 0 { 0.0 } else { a as f64 / b as f64 };
        // Against the same tracer's alpha test (the candidates it sees
        // depend on its traversal).
        let alpha = find(lookup, tracer, Method::AlphaTest).map_or(c, |a| a.frame.counters);
        let fetches_saved = 1.0 - ratio(c.texture_fetches, alpha.texture_fetches);
        let _ = writeln!(
            text,
            "{:<10} {:<17} {:>10} {:>10} {:>9} {:>10} {:>8} {:>9} {:>9} {:>9}",
            match lookup {
                Lookup::Shader => tracer.name().to_string(),
                Lookup::Sampler => format!("{}+s", tracer.name()),
            },
            method.name(),
            c.candidates,
            c.texture_fetches,
            c.known,
            c.unknown,
            c.contradicted,
            differing,
            ms(t.cpu),
            ms(t.device)
        );
        if let (Some(n), Some(r)) = (differing_from_reference, method.reference()) {
            if n > 0 {
                let r_name = if r == Method::AlphaTest {
                    picture_name((lookup, lookup_reference.tracer), Method::AlphaTest, "")
                } else {
                    picture_name(pass, r, "")
                };
                failures.push(format!(
                    "{label}: {n} pixels differ from {r_name} (see {})",
                    picture_name(pass, method, "-diff")
                ));
            }
        }
        if method.is_four_state() {
            if c.contradicted > 0 {
                failures.push(format!(
                    "{label}: {} contradicted candidates",
                    c.contradicted
                ));
                failures.extend(
                    t.classified
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
        for x in &t.classified {
            let e = by_class.entry(x.class.name()).or_insert(json!(0));
            *e = json!(e.as_u64().unwrap_or(0) + 1);
        }
        let mut entry = json!({
            "tracer": tracer.name(),
            "lookup": lookup.name(),
            "method": method.name(),
            "four_state": method.is_four_state(),
            "hardware": method.is_hardware(),
            "rays": c.rays,
            "candidates": c.candidates,
            "texture_fetches": c.texture_fetches,
            "known": c.known,
            "unknown": c.unknown,
            "invalid": c.invalid,
            "contradicted": c.contradicted,
            "hit_fraction": frame.hit_fraction(),
            "pixels_differing_from_alpha_test": differing,
            "must_equal": method.reference().map(Method::name),
            "pixels_differing_from_must_equal": differing_from_reference,
            "texture_fetches_saved_fraction": if method == Method::AlphaTest { 0.0 } else { fetches_saved },
            "decided_without_texture_fraction": ratio(c.known, c.candidates),
            "cpu_seconds_per_frame": t.cpu,
            "wall_seconds_per_frame": t.wall,
            "device_seconds_per_frame": t.device,
            "frames": frames,
            "contradictions_classified": by_class,
            "contradictions": t.classified.iter().map(contradiction_json).collect::<Vec<_>>(),
        });
        if method.is_hardware() {
            // The shader sees only what the traversal hands it.
            entry["any_hit_invocations"] = json!(c.candidates);
            entry["alpha_test_candidates"] = json!(alpha.candidates);
            entry["any_hit_saved_fraction"] = json!(1.0 - ratio(c.candidates, alpha.candidates));
        }
        method_json.push(entry);
    }
    let passed = failures.is_empty();
    let report_json = json!({
        "device": renderer.device_name(),
        "device_info": report::device_json(renderer.device_info(), renderer.enabled()),
        "sampling": {
            "shader": "shader code (render_common.glsl): binary32 nearest or bilinear, Vulkan's address modes, no hardware sampler",
            "sampler": "the device's texture unit: textureLod(sampler2D, uv, 0.0).r of the same binary32 uv through a combined image sampler per mesh (R8_UNORM image of the alpha, one level; the mesh's filter as mag and min filter, its address modes, border colour FLOAT_TRANSPARENT_BLACK or FLOAT_OPAQUE_WHITE, mipmap mode nearest, maxLod 0, normalized coordinates, no anisotropy), then the same binary32 alpha test",
        },
        "lookups": lookups.iter().map(|l| l.name()).collect::<Vec<_>>(),
        "time": "cpu: process CPU seconds per frame (a CPU device's threads are the process's); wall: the submission, waited for; device: between the device's timestamps around the dispatch (a GPU's frame time); each the least of the frames",
        "size": [size.0, size.1],
        "camera": {"eye": camera.eye, "target": camera.target, "fov_y_degrees": camera.fov_y_degrees, "fitted": given_camera.is_none()},
        "hit_fraction": reference.hit_fraction(),
        "triangles": scene.triangle_count(),
        "micromaps": source,
        "levels": level_json,
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
                "check: passed (under every tracer and lookup, every 4-state method renders the alpha test's picture and the forced 2-state hardware micromap flat-2-state's; no contradicted candidate)"
            );
        }
        Exit::Success
    };
    let _ = write!(text, "wrote {}", out.display());
    text.push('\n');
    Ok((text, exit))
}
