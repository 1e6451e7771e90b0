//! `micromap-index render --check` on a real Vulkan device with ray queries
//! (Mesa's lavapipe in CI): our bakes of the committed assets (GPU model,
//! the default) pass at levels 2..=8; the negative controls fail: looking
//! the micromap up at swapped barycentrics, flipping the known states, a
//! nearest bake sampled linearly, the committed meshoptimizer bakes. The
//! driver's own micromaps (`--methods hardware,hardware-2-state`) pass where
//! the device has `VK_EXT_opacity_micromap` and exit 4 naming it where it
//! has not (lavapipe); the pipeline tracer runs without `VK_KHR_ray_query`;
//! `--device` picks a device; the default camera fits what is drawn; `--level
//! auto` lists the levels per primitive; both tracers list their first
//! contradictions in pixel order. The sampler lookup (`--lookup sampler`:
//! the alpha test through a combined image sampler, the device's texture
//! unit the judge) passes on our bakes of both assets and fails with
//! flipped states; lavapipe's 8-bit filtered alphas contradict only where
//! the exact point agrees (`texture-unit`), and a bake for a filter error of
//! 1/255 holds under them; a border alpha no Vulkan border colour has is
//! refused for it by name. `EXT_mesh_gpu_instancing` instances are each
//! drawn at their own place, as plain nodes would place them, and pass.
//! Exit codes for bad input and for a machine without a device.
//!
//! Without a device each test prints `SKIPPED: ...` and passes, unless
//! `MICROMAP_REQUIRE_VULKAN=1` (the CI tier), where it fails. The
//! assertions are invariants (exit codes, equal pictures, contradictions
//! present or absent, their classes), never candidate counts or times,
//! which depend on the driver's BVH.

mod common;

use common::{root, run, scratch, text};
use serde_json::Value;
use std::process::Output;
use std::sync::OnceLock;

const REQUIRE: &str = "MICROMAP_REQUIRE_VULKAN";

fn asset(path: &str) -> String {
    root().join(path).to_string_lossy().into_owned()
}

/// The probe's render.json: the device it found.
fn probe_json() -> Option<&'static Value> {
    PROBE.get().and_then(|p| p.as_ref().ok())
}

static PROBE: OnceLock<Result<Value, String>> = OnceLock::new();

/// Whether a device with ray queries is there (probed once with a 1x1
/// frame); without one, says SKIPPED (or fails under `REQUIRE=1`).
fn device(test: &str) -> bool {
    let probe = PROBE.get_or_init(|| {
        let out = scratch("render-probe");
        let o = run(&[
            "render",
            "--gltf",
            &asset("assets/crytek-sponza/cards.gltf"),
            "--level",
            "1",
            "--size",
            "1x1",
            "--methods",
            "flat-4-state",
            "--force",
            "--out",
            out.to_str().unwrap(),
        ]);
        match o.status.code() {
            Some(0) => Ok(
                serde_json::from_slice(&std::fs::read(out.join("render.json")).unwrap()).unwrap(),
            ),
            Some(4) => Err(text(&o.stderr).trim().to_string()),
            other => panic!("probe: exit {other:?}\n{}", text(&o.stderr)),
        }
    });
    match probe {
        Ok(_) => true,
        Err(why) => {
            assert!(
                std::env::var(REQUIRE).as_deref() != Ok("1"),
                "{REQUIRE}=1 but {why}"
            );
            println!("SKIPPED {test}: {why}");
            false
        }
    }
}

/// `render --check` with `args`, into a fresh directory; the output and
/// the parsed render.json (when written).
fn check(name: &str, args: &[&str]) -> (Output, Option<Value>) {
    let (o, json, _) = check_at(name, args);
    (o, json)
}

/// [`check`], and the directory it wrote into.
fn check_at(name: &str, args: &[&str]) -> (Output, Option<Value>, std::path::PathBuf) {
    let out = scratch(&format!("render-{name}"));
    let mut all = vec![
        "render",
        "--check",
        "--force",
        "--out",
        out.to_str().unwrap(),
    ];
    all.extend_from_slice(args);
    let o = run(&all);
    let json = std::fs::read(out.join("render.json"))
        .ok()
        .map(|b| serde_json::from_slice(&b).unwrap());
    (o, json, out)
}

/// Both tracers, as render.json names them (`render` traces both by
/// default).
const TRACERS: [&str; 2] = ["query", "pipeline"];

fn traced<'a>(json: &'a Value, tracer: &str, name: &str) -> &'a Value {
    json["methods"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["method"] == name && m["tracer"] == tracer)
        .unwrap_or_else(|| panic!("no {tracer} {name} in render.json"))
}

/// The entries of `name` under `tracer`, one per lookup traced (`render`
/// traces both lookups by default: the shader's first).
fn per_lookup<'a>(json: &'a Value, tracer: &str, name: &str) -> Vec<&'a Value> {
    let found: Vec<&Value> = json["methods"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["method"] == name && m["tracer"] == tracer)
        .collect();
    assert_eq!(
        found.len(),
        json["lookups"].as_array().unwrap().len(),
        "{tracer} {name}"
    );
    found
}

/// The query tracer's entry of `name`.
fn method<'a>(json: &'a Value, name: &str) -> &'a Value {
    traced(json, "query", name)
}

fn describe(o: &Output) -> String {
    format!(
        "exit {:?}\nstdout:\n{}\nstderr:\n{}",
        o.status.code(),
        text(&o.stdout),
        text(&o.stderr)
    )
}

/// Our bakes pass: every 4-state method equals the alpha test and no
/// candidate is contradicted; the methods agree on what they saw.
fn assert_passes(name: &str, args: &[&str]) {
    let (o, json) = check(name, args);
    assert_passed(name, &o, json);
}

/// [`assert_passes`] on a check's output and render.json, which it returns.
fn assert_passed(name: &str, o: &Output, json: Option<Value>) -> Value {
    assert_eq!(o.status.code(), Some(0), "{name}: {}", describe(o));
    let json = json.unwrap();
    assert_eq!(json["check"]["passed"], true, "{name}");
    assert_eq!(json["tracers"], serde_json::json!(TRACERS), "{name}");
    // Under each tracer and each lookup traced (both by default).
    for (tracer, l) in TRACERS.iter().flat_map(|&t| [(t, 0), (t, 1)]) {
        let Some(&alpha) = per_lookup(&json, tracer, "alpha-test").get(l) else {
            continue;
        };
        let lookup = alpha["lookup"].as_str().unwrap();
        // This lookup's entry of a method.
        let traced = |json: &Value, tracer: &str, m: &str| per_lookup(json, tracer, m)[l].clone();
        assert_eq!(alpha["known"], 0);
        assert_eq!(alpha["texture_fetches"], alpha["candidates"]);
        // The pipeline's alpha test renders the query's picture (under the
        // shader lookup; the sampler's first alpha test is compared with
        // the shader's, not checked against it).
        if alpha["must_equal"] == "alpha-test"
            && alpha["pixels_differing_from_must_equal"] != Value::Null
        {
            assert_eq!(
                alpha["pixels_differing_from_must_equal"], 0,
                "{name} {lookup} {tracer}"
            );
        }
        for m in ["flat-4-state", "level-order-tree", "paper-tree"] {
            let m = &traced(&json, tracer, m);
            assert_eq!(m["contradicted"], 0, "{name} {lookup} {tracer}");
            assert_eq!(
                m["pixels_differing_from_must_equal"], 0,
                "{name} {lookup} {tracer}"
            );
            // Every candidate is decided once: by a known state or a fetch.
            let (known, unknown) = (m["known"].as_u64().unwrap(), m["unknown"].as_u64().unwrap());
            assert_eq!(
                known + unknown,
                m["candidates"].as_u64().unwrap(),
                "{name} {tracer}"
            );
            assert_eq!(m["texture_fetches"], m["unknown"], "{name} {tracer}");
        }
        // The three 4-state lookups read the same states.
        let flat = traced(&json, tracer, "flat-4-state");
        for m in ["level-order-tree", "paper-tree"] {
            assert_eq!(
                traced(&json, tracer, m)["known"],
                flat["known"],
                "{name} {tracer} {m}"
            );
        }
    }
    assert!(json["device"].as_str().unwrap().len() > 3);
    json
}

/// A negative control fails the check (exit 1), naming contradictions.
fn assert_fails(name: &str, args: &[&str]) -> Value {
    let (o, json) = check(name, args);
    assert_eq!(o.status.code(), Some(1), "{name}: {}", describe(&o));
    let stdout = text(&o.stdout);
    assert!(stdout.contains("check: FAILED"), "{name}: {stdout}");
    let json = json.unwrap();
    assert_eq!(json["check"]["passed"], false);
    json
}

#[test]
fn our_bakes_of_cards_pass_at_levels_2_to_8() {
    if !device("cards") {
        return;
    }
    let cards = asset("assets/crytek-sponza/cards.gltf");
    for level in 2..=8 {
        let level = level.to_string();
        assert_passes(
            &format!("cards-{level}"),
            &["--gltf", &cards, "--level", &level, "--size", "192x64"],
        );
    }
}

#[test]
fn our_bakes_of_the_fern_pass_at_levels_2_to_8() {
    if !device("fern") {
        return;
    }
    let fern = asset("assets/polyhaven-fern02/fern_02.gltf");
    for level in 2..=8 {
        let level = level.to_string();
        assert_passes(
            &format!("fern-{level}"),
            &["--gltf", &fern, "--level", &level, "--size", "128x128"],
        );
    }
}

#[test]
fn a_bake_directory_renders_as_the_bake_on_the_fly() {
    if !device("bake-dir") {
        return;
    }
    let cards = asset("assets/crytek-sponza/cards.gltf");
    let baked = scratch("render-bake-dir-in");
    let o = run(&[
        "bake",
        "--gltf",
        &cards,
        "--level",
        "5",
        "--quiet",
        "--force",
        "--out",
        baked.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", describe(&o));
    let size = ["--size", "160x48"];
    let (a, from_dir) = check(
        "bake-dir",
        &[
            &["--gltf", &cards, "--micromaps", baked.to_str().unwrap()],
            &size[..],
        ]
        .concat(),
    );
    assert_eq!(a.status.code(), Some(0), "{}", describe(&a));
    let (b, on_the_fly) = check(
        "bake-here",
        &[&["--gltf", &cards, "--level", "5"], &size[..]].concat(),
    );
    assert_eq!(b.status.code(), Some(0), "{}", describe(&b));
    let (from_dir, on_the_fly) = (from_dir.unwrap(), on_the_fly.unwrap());
    for m in [
        "flat-4-state",
        "flat-2-state",
        "level-order-tree",
        "paper-tree",
    ] {
        for counter in ["candidates", "known", "unknown", "contradicted"] {
            assert_eq!(
                method(&from_dir, m)[counter],
                method(&on_the_fly, m)[counter],
                "{m} {counter}"
            );
        }
    }
}

#[test]
fn swapped_barycentrics_and_flipped_states_fail() {
    if !device("faults") {
        return;
    }
    let cards = asset("assets/crytek-sponza/cards.gltf");
    for fault in ["swap-barycentrics", "flip-known"] {
        let json = assert_fails(
            fault,
            &[
                "--gltf", &cards, "--level", "6", "--size", "192x64", "--fault", fault,
            ],
        );
        for (tracer, m) in TRACERS
            .iter()
            .flat_map(|t| ["flat-4-state", "level-order-tree", "paper-tree"].map(|m| (*t, m)))
        {
            // Under each lookup.
            for m in per_lookup(&json, tracer, m) {
                assert!(m["contradicted"].as_u64().unwrap() > 0, "{fault} {tracer}");
                // The exact hit point disagrees with what the shader decided.
                let first = &m["contradictions"][0];
                assert_eq!(first["class"], "micromap-wrong", "{fault}: {first}");
                assert!(first["b1"].as_str().unwrap().starts_with("0x"));
            }
        }
    }
}

#[test]
fn a_nearest_bake_sampled_linearly_fails() {
    if !device("nearest-as-linear") {
        return;
    }
    // The thorn grid: texel-aligned edges, micro-triangles of level 8 near
    // the texel size, where a bilinear footprint reaches past the texels a
    // nearest bake looked at.
    let texture = asset("assets/crytek-sponza/sponza_thorn.png");
    let triangles = asset("assets/crytek-sponza/grid.tris.json");
    let baked = scratch("render-nearest-in");
    let o = run(&[
        "bake",
        "--texture",
        &texture,
        "--triangles",
        &triangles,
        "--level",
        "8",
        "--filter",
        "nearest",
        "--quiet",
        "--force",
        "--out",
        baked.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", describe(&o));
    let micromaps = baked.to_str().unwrap();
    let input = [
        "--texture",
        &texture,
        "--triangles",
        &triangles,
        "--micromaps",
        micromaps,
    ];
    let rest = ["--size", "256x256", "--methods", "flat-4-state"];
    // Sampled as baked: passes.
    let (ok, _) = check(
        "nearest-as-nearest",
        &[&input[..], &["--filter", "nearest"], &rest[..]].concat(),
    );
    assert_eq!(ok.status.code(), Some(0), "{}", describe(&ok));
    let json = assert_fails(
        "nearest-as-linear",
        &[&input[..], &["--filter", "linear"], &rest[..]].concat(),
    );
    for tracer in TRACERS {
        // Under each lookup: the texture unit reads the texels the exact
        // point reads.
        for flat in per_lookup(&json, tracer, "flat-4-state") {
            assert!(flat["contradicted"].as_u64().unwrap() > 0, "{tracer}");
            assert_eq!(
                flat["contradictions"][0]["class"], "micromap-wrong",
                "{tracer} {}",
                flat["lookup"]
            );
        }
    }
}

#[test]
fn the_committed_meshoptimizer_bakes_fail() {
    if !device("meshoptimizer") {
        return;
    }
    let texture = asset("assets/crytek-sponza/sponza_thorn.png");
    let triangles = asset("assets/crytek-sponza/grid.tris.json");
    for baker in ["meshopt-cpp", "meshopt-rs"] {
        for level in ["L4", "L6"] {
            let dir = asset(&format!(
                "crates/other-bakers/out/{baker}/sponza_thorn-{level}-f4"
            ));
            // meshoptimizer samples bilinearly (its summary.json).
            let json = assert_fails(
                &format!("{baker}-{level}"),
                &[
                    "--texture",
                    &texture,
                    "--triangles",
                    &triangles,
                    "--micromaps",
                    &dir,
                    "--filter",
                    "linear",
                    "--size",
                    "128x128",
                ],
            );
            for tracer in TRACERS {
                for flat in per_lookup(&json, tracer, "flat-4-state") {
                    let lookup = &flat["lookup"];
                    assert!(
                        flat["contradicted"].as_u64().unwrap() > 0,
                        "{baker} {level} {tracer} {lookup}"
                    );
                    assert_eq!(
                        flat["contradictions"][0]["class"], "micromap-wrong",
                        "{baker} {level} {tracer} {lookup}"
                    );
                }
            }
        }
    }
}

#[test]
fn each_tracer_alone_renders_the_same_and_names_its_pictures() {
    if !device("one-tracer") {
        return;
    }
    let cards = asset("assets/crytek-sponza/cards.gltf");
    let args = ["--gltf", &cards, "--level", "4", "--size", "96x32"];
    let (both, both_json) = check("tracer-both", &args);
    assert_eq!(both.status.code(), Some(0), "{}", describe(&both));
    let both_json = both_json.unwrap();
    for (tracer, own, other) in [
        ("query", "alpha-test.png", "pipeline-alpha-test.png"),
        ("pipeline", "pipeline-alpha-test.png", "alpha-test.png"),
    ] {
        let name = format!("tracer-{tracer}");
        let (o, json) = check(&name, &[&args[..], &["--tracer", tracer]].concat());
        assert_eq!(o.status.code(), Some(0), "{tracer}: {}", describe(&o));
        let json = json.unwrap();
        assert_eq!(json["tracers"], serde_json::json!([tracer]));
        let tmp = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
        let dir = tmp.join(format!("render-{name}"));
        assert!(
            dir.join(own).exists() && !dir.join(other).exists(),
            "{tracer}"
        );
        // Alone, each tracer sees what it saw next to the other.
        for m in ["alpha-test", "flat-4-state", "flat-2-state", "paper-tree"] {
            for counter in ["candidates", "known", "unknown", "contradicted"] {
                assert_eq!(
                    traced(&json, tracer, m)[counter],
                    traced(&both_json, tracer, m)[counter],
                    "{tracer} {m} {counter}"
                );
            }
        }
        // The pictures are the same bytes.
        assert_eq!(
            std::fs::read(dir.join(own)).unwrap(),
            std::fs::read(tmp.join("render-tracer-both").join(own)).unwrap(),
            "{tracer}"
        );
    }
}

#[test]
fn bad_input_exits_2_and_writes_nothing() {
    let cards = asset("assets/crytek-sponza/cards.gltf");
    let parent = scratch("render-bad");
    let out = parent.join("out");
    let out = out.to_str().unwrap();
    let grid_bake = asset("crates/other-bakers/out/meshopt-rs/sponza_thorn-L4-f4");
    for (args, what) in [
        (vec!["--size", "0x10"], "--size"),
        (vec!["--size", "5000x5000"], "--size"),
        (vec!["--fault", "nonsense"], "--fault"),
        (vec!["--methods", "alpha-test,nope"], "--methods"),
        (vec!["--tracer", "query,pipeline"], "--tracer"),
        (vec!["--lookup", "texture"], "--lookup"),
        (vec!["--camera", "1,2,3"], "--camera"),
        (vec!["--level", "13"], "--level"),
        // 128 indices for the 144 triangles of cards.gltf.
        (vec!["--micromaps", &grid_bake], "indices"),
        (vec!["--micromaps", &grid_bake, "--level", "4"], "--level"),
    ] {
        let mut all = vec!["render", "--gltf", &cards, "--out", out];
        all.extend(args.iter().copied());
        let o = run(&all);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", describe(&o));
        assert!(text(&o.stderr).contains(what), "{args:?}: {}", describe(&o));
        assert!(!std::path::Path::new(out).exists(), "{args:?} wrote {out}");
    }
}

#[test]
fn no_device_exits_4_and_writes_nothing() {
    let cards = asset("assets/crytek-sponza/cards.gltf");
    let parent = scratch("render-no-device");
    let out = parent.join("out");
    // A loader that finds no driver.
    let o = common::binary()
        .args(["render", "--gltf", &cards, "--level", "2", "--out"])
        .arg(&out)
        .env("VK_ICD_FILENAMES", parent.join("none.json"))
        .env("VK_DRIVER_FILES", parent.join("none.json"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(4), "{}", describe(&o));
    assert!(text(&o.stderr).contains("Vulkan"), "{}", describe(&o));
    assert!(!out.exists());
}

/// Whether the probed device has `VK_EXT_opacity_micromap`.
fn has_opacity_micromap() -> bool {
    probe_json().is_some_and(|j| j["device_info"]["extensions"]["VK_EXT_opacity_micromap"] == true)
}

#[test]
fn the_drivers_micromaps_pass_or_exit_4_naming_the_extension() {
    if !device("hardware") {
        return;
    }
    let cards = asset("assets/crytek-sponza/cards.gltf");
    let args = [
        "--gltf",
        &cards,
        "--level",
        "5",
        "--size",
        "160x48",
        "--methods",
        "flat-4-state,hardware,hardware-2-state",
    ];
    if has_opacity_micromap() {
        // The driver's micromap renders the alpha test's picture, and forced
        // to 2 states the emulated flat-2-state picture: its index function
        // and state decoding are the shader library's.
        let (o, json) = check("hardware", &args);
        assert_eq!(o.status.code(), Some(0), "{}", describe(&o));
        let json = json.unwrap();
        for tracer in TRACERS {
            let hw = traced(&json, tracer, "hardware");
            assert_eq!(hw["pixels_differing_from_must_equal"], 0, "{tracer}");
            assert_eq!(hw["known"], 0, "{tracer}: the shader decides no state");
            let any_hit = hw["any_hit_invocations"].as_u64().unwrap();
            assert!(any_hit <= hw["alpha_test_candidates"].as_u64().unwrap());
            let two = traced(&json, tracer, "hardware-2-state");
            assert_eq!(two["must_equal"], "flat-2-state");
            assert_eq!(two["pixels_differing_from_must_equal"], 0, "{tracer}");
        }
        return;
    }
    // No driver here has the extension (lavapipe): exit 4, nothing written,
    // the extension named; the emulated methods still trace.
    let parent = scratch("render-no-omm");
    let out = parent.join("out");
    let mut all = vec!["render", "--out", out.to_str().unwrap()];
    all.extend_from_slice(&args);
    let o = run(&all);
    assert_eq!(o.status.code(), Some(4), "{}", describe(&o));
    let stderr = text(&o.stderr);
    assert!(stderr.contains("VK_EXT_opacity_micromap"), "{stderr}");
    assert!(stderr.contains("--methods without hardware"), "{stderr}");
    assert!(!out.exists());
    let (o, _) = check("no-omm-emulated", &args[..6]);
    assert_eq!(o.status.code(), Some(0), "{}", describe(&o));
}

#[test]
fn the_pipeline_tracer_runs_without_ray_queries() {
    if !device("pipeline-alone") {
        return;
    }
    let cards = asset("assets/crytek-sponza/cards.gltf");
    let (o, json) = check(
        "pipeline-alone",
        &[
            "--gltf", &cards, "--level", "4", "--size", "96x32", "--tracer", "pipeline",
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", describe(&o));
    let json = json.unwrap();
    let enabled = &json["device_info"]["enabled_extensions"];
    assert_eq!(
        enabled,
        &serde_json::json!([
            "VK_KHR_acceleration_structure",
            "VK_KHR_ray_tracing_pipeline"
        ]),
        "the device was opened without VK_KHR_ray_query"
    );
}

#[test]
fn device_picks_a_device_by_number_or_name() {
    if !device("device") {
        return;
    }
    let probe = probe_json().unwrap();
    let index = probe["device_info"]["index"].as_u64().unwrap().to_string();
    let name = probe["device_info"]["name"].as_str().unwrap().to_string();
    let part: String = name.chars().take(4).collect::<String>().to_uppercase();
    let cards = asset("assets/crytek-sponza/cards.gltf");
    for (label, selector) in [("number", index.as_str()), ("name", part.as_str())] {
        let (o, json) = check(
            &format!("device-{label}"),
            &[
                "--gltf", &cards, "--level", "2", "--size", "32x32", "--device", selector,
            ],
        );
        assert_eq!(o.status.code(), Some(0), "{selector}: {}", describe(&o));
        let info = &json.unwrap()["device_info"];
        assert_eq!(info["name"], name.as_str());
        for key in ["driver_name", "driver_version", "vulkan_api_version"] {
            assert!(!info[key].as_str().unwrap().is_empty(), "{key}");
        }
    }
    let parent = scratch("render-no-such-device");
    let out = parent.join("out");
    let o = run(&[
        "render",
        "--gltf",
        &cards,
        "--device",
        "no such device anywhere",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", describe(&o));
    assert!(
        text(&o.stderr).contains("named like \"no such device anywhere\""),
        "{}",
        describe(&o)
    );
    assert!(!out.exists());
}

#[test]
fn the_default_camera_fits_what_is_drawn_and_auto_lists_levels() {
    if !device("camera") {
        return;
    }
    let fern = asset("assets/polyhaven-fern02/fern_02.gltf");
    let (o, json) = check(
        "camera",
        &[
            "--gltf",
            &fern,
            "--max-level",
            "5",
            "--size",
            "96x96",
            "--methods",
            "flat-4-state",
            "--tracer",
            "query",
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", describe(&o));
    let json = json.unwrap();
    assert_eq!(json["camera"]["fitted"], true);
    // The four ferns, placed apart by their nodes, fill the frame: the old
    // camera, on unplaced meshes, hit 9% of the pixels.
    let hit = json["hit_fraction"].as_f64().unwrap();
    assert!(hit > 0.1, "hit fraction {hit}");
    // --level auto: the levels per primitive, on stdout and in render.json.
    let stdout = text(&o.stdout);
    assert!(stdout.contains("levels (--level auto):"), "{stdout}");
    let levels = json["levels"].as_array().unwrap();
    assert_eq!(levels.len(), 4);
    let mut total = 0;
    for mesh in levels {
        let line = format!("  {}: ", mesh["mesh"].as_str().unwrap());
        assert!(stdout.contains(&line), "{line} in {stdout}");
        let counted: u64 = mesh["levels"]
            .as_array()
            .unwrap()
            .iter()
            .map(|l| {
                assert!(l["level"].as_u64().unwrap() <= 5);
                l["triangles"].as_u64().unwrap()
            })
            .sum();
        assert_eq!(
            counted + mesh["special"].as_u64().unwrap(),
            mesh["triangles"]
        );
        total += mesh["triangles"].as_u64().unwrap();
    }
    assert_eq!(total, json["triangles"].as_u64().unwrap());
}

#[test]
fn both_tracers_list_their_first_contradictions_in_pixel_order() {
    if !device("order") {
        return;
    }
    let cards = asset("assets/crytek-sponza/cards.gltf");
    let (_, json) = check(
        "order",
        &[
            "--gltf",
            &cards,
            "--level",
            "5",
            "--size",
            "128x48",
            "--fault",
            "flip-known",
            "--methods",
            "flat-4-state",
            "--max-report",
            "7",
        ],
    );
    let json = json.unwrap();
    let pixels = |tracer: &str| -> Vec<(u64, u64)> {
        traced(&json, tracer, "flat-4-state")["contradictions"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| {
                (
                    c["pixel"][1].as_u64().unwrap(),
                    c["pixel"][0].as_u64().unwrap(),
                )
            })
            .collect()
    };
    for tracer in TRACERS {
        let listed = pixels(tracer);
        // More than 7 were contradicted: the 7 listed are the first pixels'.
        assert!(
            traced(&json, tracer, "flat-4-state")["contradicted"]
                .as_u64()
                .unwrap()
                > 7
        );
        assert_eq!(listed.len(), 7, "{tracer}");
        assert!(
            listed.windows(2).all(|w| w[0] <= w[1]),
            "{tracer}: {listed:?}"
        );
    }
    let (q, p) = (
        traced(&json, "query", "flat-4-state"),
        traced(&json, "pipeline", "flat-4-state"),
    );
    if q["contradicted"] == p["contradicted"] {
        // The same candidates, whatever order the device ran them in.
        assert_eq!(q["contradictions"], p["contradictions"]);
    }
}

/// Every entry of render.json was traced with `lookup`, and its pictures
/// carry the lookup's prefix.
fn assert_lookup(name: &str, json: &Value, lookup: &str) {
    assert_eq!(json["lookups"], serde_json::json!([lookup]), "{name}");
    for m in json["methods"].as_array().unwrap() {
        assert_eq!(m["lookup"], lookup, "{name}: {m}");
    }
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("render-{name}"));
    let (own, other) = match lookup {
        "sampler" => ("sampler-alpha-test.png", "alpha-test.png"),
        _ => ("alpha-test.png", "sampler-alpha-test.png"),
    };
    assert!(
        dir.join(own).exists() && !dir.join(other).exists(),
        "{name}: {own} without {other}"
    );
}

#[test]
fn the_sampler_lookup_passes_on_our_bakes() {
    if !device("sampler") {
        return;
    }
    let cards = asset("assets/crytek-sponza/cards.gltf");
    let fern = asset("assets/polyhaven-fern02/fern_02.gltf");
    // The default texture unit (filter error 2^-7), and one whose filter
    // error is lavapipe's (8-bit filtered alphas: 1/255, rounded up).
    for (name, input, level, size, filter_error) in [
        ("sampler-cards-3", &cards, "3", "96x32", "0.0078125"),
        ("sampler-cards-7", &cards, "7", "96x32", "0.004"),
        ("sampler-fern-2", &fern, "2", "64x64", "0.0078125"),
        ("sampler-fern-6", &fern, "6", "64x64", "0.004"),
    ] {
        let args = [
            "--gltf",
            input,
            "--level",
            level,
            "--size",
            size,
            "--lookup",
            "sampler",
            "--filter-error",
            filter_error,
        ];
        assert_passes(name, &args);
        let (_, json) = check(name, &args);
        assert_lookup(name, &json.unwrap(), "sampler");
    }
}

#[test]
fn both_lookups_trace_every_method_and_each_passes() {
    if !device("both-lookups") {
        return;
    }
    let cards = asset("assets/crytek-sponza/cards.gltf");
    let (o, json) = check(
        "lookup-both",
        &["--gltf", &cards, "--level", "5", "--size", "96x32"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", describe(&o));
    let json = json.unwrap();
    // Both, by default: every method under each lookup and tracer.
    assert_eq!(json["lookups"], serde_json::json!(["shader", "sampler"]));
    let entries = json["methods"].as_array().unwrap();
    for lookup in ["shader", "sampler"] {
        for tracer in TRACERS {
            for m in [
                "alpha-test",
                "flat-4-state",
                "level-order-tree",
                "paper-tree",
            ] {
                let e = entries
                    .iter()
                    .find(|e| e["lookup"] == lookup && e["tracer"] == tracer && e["method"] == m)
                    .unwrap_or_else(|| panic!("no {lookup} {tracer} {m}"));
                assert_eq!(e["contradicted"], 0, "{lookup} {tracer} {m}");
            }
        }
    }
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("render-lookup-both");
    for picture in [
        "alpha-test.png",
        "sampler-alpha-test.png",
        "sampler-alpha-test-diff.png",
        "sampler-pipeline-paper-tree-diff.png",
    ] {
        assert!(dir.join(picture).exists(), "{picture}");
    }
}

#[test]
fn flipped_states_fail_under_the_sampler_lookup() {
    if !device("sampler-flip") {
        return;
    }
    let cards = asset("assets/crytek-sponza/cards.gltf");
    let fern = asset("assets/polyhaven-fern02/fern_02.gltf");
    for (name, input, size) in [
        ("sampler-flip-cards", &cards, "96x32"),
        ("sampler-flip-fern", &fern, "64x64"),
    ] {
        let json = assert_fails(
            name,
            &[
                "--gltf",
                input,
                "--level",
                "5",
                "--size",
                size,
                "--lookup",
                "sampler",
                "--fault",
                "flip-known",
                "--methods",
                "flat-4-state",
            ],
        );
        for tracer in TRACERS {
            let m = traced(&json, tracer, "flat-4-state");
            assert_eq!(m["lookup"], "sampler");
            assert!(m["contradicted"].as_u64().unwrap() > 0, "{name} {tracer}");
            // The exact hit point disagrees with the flipped state, and the
            // texture unit read the alpha the exact point has.
            let first = &m["contradictions"][0];
            assert_eq!(first["class"], "micromap-wrong", "{name}: {first}");
            assert!(first["lookup_alpha"].as_f64().is_some(), "{first}");
        }
    }
}

#[test]
fn the_sampler_lookup_refuses_a_border_alpha_by_name() {
    if !device("sampler-border") {
        return;
    }
    let texture = asset("assets/crytek-sponza/sponza_thorn.png");
    let triangles = asset("assets/crytek-sponza/grid.tris.json");
    let out = scratch("render-sampler-border");
    let out = out.join("out");
    let args = |lookup: &'static str| {
        vec![
            "render".to_string(),
            "--texture".into(),
            texture.clone(),
            "--triangles".into(),
            triangles.clone(),
            "--address".into(),
            "clamp-to-border".into(),
            "--border".into(),
            "0.5".into(),
            "--level".into(),
            "2".into(),
            "--size".into(),
            "32x32".into(),
            "--methods".into(),
            "flat-4-state".into(),
            "--lookup".into(),
            lookup.into(),
            "--check".into(),
            "--force".into(),
            "--out".into(),
            out.to_string_lossy().into_owned(),
        ]
    };
    for lookup in ["sampler", "both"] {
        let a = args(lookup);
        let o = run(&a.iter().map(String::as_str).collect::<Vec<_>>());
        assert_eq!(o.status.code(), Some(2), "{lookup}: {}", describe(&o));
        let stderr = text(&o.stderr);
        assert!(
            stderr.contains("border alpha 0.5") && stderr.contains("--lookup shader"),
            "{stderr}"
        );
        assert!(!out.exists(), "{lookup} wrote {}", out.display());
    }
    // The shader's own lookup samples any border alpha.
    let a = args("shader");
    let o = run(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(o.status.code(), Some(0), "{}", describe(&o));
}

/// A 16x16 alpha texture of random alphas, half of them near the cutoff
/// (110..=145), as a PNG in `dir`; and a quad over it.
fn near_cutoff_texture(dir: &std::path::Path) -> (String, String) {
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = |n: u64| {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 33) % n
    };
    let mut pixels = Vec::new();
    for _ in 0..16 * 16 {
        let alpha = if next(2) == 0 {
            next(256)
        } else {
            110 + next(36)
        };
        pixels.extend([255, alpha as u8]);
    }
    let png = dir.join("near-cutoff.png");
    let file = std::io::BufWriter::new(std::fs::File::create(&png).unwrap());
    let mut encoder = png::Encoder::new(file, 16, 16);
    encoder.set_color(png::ColorType::GrayscaleAlpha);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().unwrap();
    writer.write_image_data(&pixels).unwrap();
    writer.finish().unwrap();
    let tris = dir.join("quad.tris.json");
    std::fs::write(
        &tris,
        r#"{"triangles": [[[0, 0], [1, 0], [1, 1]], [[0, 0], [1, 1], [0, 1]]]}"#,
    )
    .unwrap();
    (
        png.to_string_lossy().into_owned(),
        tris.to_string_lossy().into_owned(),
    )
}

#[test]
fn a_bake_for_the_texture_units_filter_error_holds_under_the_sampler() {
    if !device("filter-error") {
        return;
    }
    // Linear filtering near the cutoff: lavapipe's texture unit returns the
    // filtered alpha as an 8-bit value (127/255 or 128/255 around 0.5), up
    // to about 1/255 from the exact mix; a bake for a filter error of
    // 2^-16 (the default before this was seen) does not hold for it, the
    // default 2^-7 does.
    let dir = scratch("render-near-cutoff-in");
    std::fs::create_dir_all(&dir).unwrap();
    let (texture, triangles) = near_cutoff_texture(&dir);
    let args = |filter_error: Option<&'static str>| {
        let mut a = vec![
            "--texture".to_string(),
            texture.clone(),
            "--triangles".into(),
            triangles.clone(),
            "--filter".into(),
            "linear".into(),
            "--level".into(),
            "10".into(),
            "--size".into(),
            "256x256".into(),
            "--methods".into(),
            "flat-4-state".into(),
            "--tracer".into(),
            "query".into(),
            "--max-report".into(),
            "100".into(),
        ];
        if let Some(e) = filter_error {
            a.extend(["--filter-error".to_string(), e.to_string()]);
        }
        a
    };
    // A texture unit with a 2^-16 filter error: the shader's arithmetic
    // never contradicts a known state; the device's texture unit may, and
    // then only where the exact hit point agrees with the micromap
    // (outside that bake's model, not a wrong micromap).
    let tight = args(Some("0.0000152587890625"));
    let (_, json) = check(
        "near-cutoff-tight",
        &tight.iter().map(String::as_str).collect::<Vec<_>>(),
    );
    let json = json.unwrap();
    let [shader, sampler] = [0, 1].map(|l| per_lookup(&json, "query", "flat-4-state")[l].clone());
    assert_eq!(shader["contradicted"], 0, "{shader}");
    for c in sampler["contradictions"].as_array().unwrap() {
        assert_eq!(c["class"], "texture-unit", "{c}");
        let (lookup, exact) = (
            c["lookup_alpha"].as_f64().unwrap(),
            c["exact_alpha"].as_f64().unwrap(),
        );
        assert!((lookup - exact).abs() < 1.0 / 255.0 + 1e-6, "{c}");
    }
    println!(
        "{}: a bake for a 2^-16 filter error, {} known states contradicted by the texture unit",
        json["device"], sampler["contradicted"]
    );
    // The default bake (a filter error of 2^-7) and one for 1/255 (rounded
    // up) hold for it.
    for (name, a) in [
        ("near-cutoff-default", args(None)),
        ("near-cutoff-1-255", args(Some("0.004"))),
    ] {
        assert_passes_query(name, &a.iter().map(String::as_str).collect::<Vec<_>>());
    }
}

/// `--check` passes (exit 0) with the query tracer alone, under each lookup.
fn assert_passes_query(name: &str, args: &[&str]) {
    let (o, json) = check(name, args);
    assert_eq!(o.status.code(), Some(0), "{name}: {}", describe(&o));
    let json = json.unwrap();
    assert_eq!(json["lookups"], serde_json::json!(["shader", "sampler"]));
    for m in per_lookup(&json, "query", "flat-4-state") {
        assert_eq!(m["contradicted"], 0, "{name}: {m}");
        assert_eq!(m["pixels_differing_from_must_equal"], 0, "{name}: {m}");
    }
}

/// The committed fern with a `COLOR_0` alpha added, 0.3 at each mesh's
/// lowest vertex to 1.0 at its highest, linear in height (`FLOAT` `VEC4`,
/// a buffer of its own), written with copies of its buffer and texture
/// into `dir`; the path of its `.gltf`.
fn fern_with_vertex_alpha(dir: &std::path::Path) -> String {
    let fern = root().join("assets/polyhaven-fern02");
    let mut gltf: Value =
        serde_json::from_slice(&std::fs::read(fern.join("fern_02.gltf")).unwrap()).unwrap();
    let bin = std::fs::read(fern.join("fern_02.bin")).unwrap();
    let mut colors = Vec::new();
    let meshes = gltf["meshes"].as_array().unwrap().len();
    for m in 0..meshes {
        let primitives = gltf["meshes"][m]["primitives"].as_array().unwrap().len();
        for p in 0..primitives {
            let position = &gltf["accessors"][gltf["meshes"][m]["primitives"][p]["attributes"]
                ["POSITION"]
                .as_u64()
                .unwrap() as usize];
            let count = position["count"].as_u64().unwrap() as usize;
            let view = &gltf["bufferViews"][position["bufferView"].as_u64().unwrap() as usize];
            let at = view["byteOffset"].as_u64().unwrap_or(0) as usize
                + position["byteOffset"].as_u64().unwrap_or(0) as usize;
            let stride = view["byteStride"].as_u64().unwrap_or(12) as usize;
            let ys: Vec<f32> = (0..count)
                .map(|i| {
                    let o = at + stride * i + 4;
                    f32::from_le_bytes(bin[o..o + 4].try_into().unwrap())
                })
                .collect();
            let (lo, hi) = ys
                .iter()
                .fold((f32::INFINITY, f32::NEG_INFINITY), |(l, h), &y| {
                    (l.min(y), h.max(y))
                });
            let start = colors.len();
            for y in ys {
                let alpha = 0.3 + 0.7 * (y - lo) / (hi - lo).max(f32::MIN_POSITIVE);
                for c in [1.0f32, 1.0, 1.0, alpha.clamp(0.0, 1.0)] {
                    colors.extend_from_slice(&c.to_le_bytes());
                }
            }
            let views = gltf["bufferViews"].as_array_mut().unwrap();
            views.push(serde_json::json!({"buffer": 1, "byteOffset": start, "byteLength": colors.len() - start}));
            let view = views.len() - 1;
            let accessors = gltf["accessors"].as_array_mut().unwrap();
            accessors.push(serde_json::json!({"bufferView": view, "componentType": 5126, "count": count, "type": "VEC4"}));
            let accessor = accessors.len() - 1;
            gltf["meshes"][m]["primitives"][p]["attributes"]["COLOR_0"] = accessor.into();
        }
    }
    gltf["buffers"]
        .as_array_mut()
        .unwrap()
        .push(serde_json::json!({"byteLength": colors.len(), "uri": "colors.bin"}));
    std::fs::create_dir_all(dir.join("textures")).unwrap();
    std::fs::write(dir.join("colors.bin"), colors).unwrap();
    std::fs::write(dir.join("fern_02.bin"), bin).unwrap();
    for image in gltf["images"].as_array().unwrap() {
        let uri = image["uri"].as_str().unwrap();
        std::fs::copy(fern.join(uri), dir.join(uri)).unwrap();
    }
    let path = dir.join("fern_vertex_alpha.gltf");
    std::fs::write(&path, serde_json::to_vec(&gltf).unwrap()).unwrap();
    path.to_string_lossy().into_owned()
}

/// `render` draws vertex alpha (issue 34: it refused such assets): the
/// shader multiplies the binary32-interpolated `COLOR_0` alpha in after the
/// factor, and our bakes of the fern with a vertex alpha pass the check
/// under both lookups. The control: the micromaps of the fern without
/// vertex alpha, rendered with it, are contradicted (their opaque states
/// ignore the lower alpha), and the exact host classification calls the
/// contradictions the micromap's fault.
#[test]
fn vertex_alpha_is_rendered_and_checked() {
    if !device("vertex-alpha") {
        return;
    }
    let dir = scratch("render-vertex-alpha-asset");
    let fern = fern_with_vertex_alpha(&dir);
    for level in ["2", "5"] {
        assert_passes(
            &format!("vertex-alpha-{level}"),
            &["--gltf", &fern, "--level", level, "--size", "128x128"],
        );
    }
    let plain = scratch("render-vertex-alpha-plain");
    let o = run(&[
        "bake",
        "--gltf",
        &asset("assets/polyhaven-fern02/fern_02.gltf"),
        "--level",
        "5",
        "--quiet",
        "--force",
        "--no-preview",
        "--out",
        plain.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", describe(&o));
    let json = assert_fails(
        "vertex-alpha-ignored",
        &[
            "--gltf",
            &fern,
            "--micromaps",
            plain.to_str().unwrap(),
            "--size",
            "128x128",
            "--methods",
            "flat-4-state",
        ],
    );
    let contradicted = method(&json, "flat-4-state")["contradicted"]
        .as_u64()
        .unwrap();
    assert!(contradicted > 0, "{json}");
    let text = json.to_string();
    assert!(text.contains("micromap-wrong"), "{text}");
}

/// The committed cards with mesh 0 (the thorn cards, x 0..5.5, y 0..1,
/// z 0) placed three times, written with copies of its buffer and
/// textures into `dir`: with `instanced`, by one node with
/// `EXT_mesh_gpu_instancing` (required; `TRANSLATION` and `SCALE` in a
/// buffer of their own); without, by three plain nodes with the same
/// translations and scales. The other meshes keep their nodes. The path
/// of its `.gltf`.
fn cards_placed_thrice(dir: &std::path::Path, instanced: bool) -> String {
    let cards = root().join("assets/crytek-sponza");
    let mut gltf: Value =
        serde_json::from_slice(&std::fs::read(cards.join("cards.gltf")).unwrap()).unwrap();
    // Above the thorn grid (y 0..2), apart from each other; the middle one
    // squashed to half its height.
    let translations = [[0.0f32, 0.0, 0.0], [0.0, 3.0, 0.0], [0.0, 5.0, 0.0]];
    let scales = [[1.0f32, 1.0, 1.0], [1.0, 0.5, 1.0], [1.0, 1.0, 1.0]];
    assert_eq!(gltf["nodes"][0]["mesh"], 0);
    let mut nodes = gltf["nodes"].as_array().unwrap()[1..].to_vec();
    if instanced {
        let bytes: Vec<u8> = translations
            .iter()
            .chain(&scales)
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        std::fs::write(dir.join("instances.bin"), &bytes).unwrap();
        let buffers = gltf["buffers"].as_array_mut().unwrap();
        buffers.push(serde_json::json!({"byteLength": bytes.len(), "uri": "instances.bin"}));
        let buffer = buffers.len() - 1;
        let views = gltf["bufferViews"].as_array_mut().unwrap();
        views.push(serde_json::json!({"buffer": buffer, "byteOffset": 0, "byteLength": 36}));
        views.push(serde_json::json!({"buffer": buffer, "byteOffset": 36, "byteLength": 36}));
        let view = views.len() - 2;
        let accessors = gltf["accessors"].as_array_mut().unwrap();
        for k in 0..2 {
            accessors.push(serde_json::json!({"bufferView": view + k, "componentType": 5126, "count": 3, "type": "VEC3"}));
        }
        let accessor = accessors.len() - 2;
        nodes.insert(
            0,
            serde_json::json!({"mesh": 0, "extensions": {"EXT_mesh_gpu_instancing": {
                "attributes": {"TRANSLATION": accessor, "SCALE": accessor + 1}
            }}}),
        );
        gltf["extensionsUsed"] = serde_json::json!(["EXT_mesh_gpu_instancing"]);
        gltf["extensionsRequired"] = serde_json::json!(["EXT_mesh_gpu_instancing"]);
    } else {
        for (t, s) in translations.iter().zip(&scales).rev() {
            nodes.insert(
                0,
                serde_json::json!({"mesh": 0, "translation": t, "scale": s}),
            );
        }
    }
    gltf["nodes"] = Value::Array(nodes);
    // A scene of every root (each node is one).
    let roots: Vec<usize> = (0..gltf["nodes"].as_array().unwrap().len()).collect();
    gltf["scenes"] = serde_json::json!([{"nodes": roots}]);
    gltf["scene"] = serde_json::json!(0);
    std::fs::copy(cards.join("cards.bin"), dir.join("cards.bin")).unwrap();
    for image in gltf["images"].as_array().unwrap() {
        let uri = image["uri"].as_str().unwrap();
        std::fs::copy(cards.join(uri), dir.join(uri)).unwrap();
    }
    let path = dir.join(if instanced {
        "cards_instanced.gltf"
    } else {
        "cards_three_nodes.gltf"
    });
    std::fs::write(&path, serde_json::to_vec(&gltf).unwrap()).unwrap();
    path.to_string_lossy().into_owned()
}

/// `render` draws every `EXT_mesh_gpu_instancing` instance at its own
/// place (the reader once ignored the extension and drew an instanced
/// node's mesh once, at the node): our bake of the cards with the thorn
/// cards instanced three times passes the check under both tracers and
/// lookups; its pictures are those of the same placements by three plain
/// nodes, file for file (every picture of every tracer, lookup and
/// method); and under the same camera it hits more pixels than the
/// committed cards, placed once.
#[test]
fn gpu_instancing_draws_every_instance_and_passes() {
    if !device("instancing") {
        return;
    }
    let instanced = cards_placed_thrice(&scratch("render-instancing-asset"), true);
    let three_nodes = cards_placed_thrice(&scratch("render-instancing-nodes-asset"), false);
    // A fixed camera over everything (x 0..6.25, y 0..6), looking down -z.
    let options = [
        "--level",
        "4",
        "--size",
        "128x128",
        "--camera",
        "3.2,3.2,14,3.2,3.2,0,40",
    ];
    let with = |asset: &str, more: &[&'static str]| -> Vec<String> {
        ["--gltf", asset]
            .iter()
            .chain(&options)
            .chain(more)
            .map(|s| (*s).to_string())
            .collect()
    };
    let run_check = |name: &str, args: &[String]| {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        check_at(name, &args)
    };
    let (o, json, instanced_out) = run_check("instancing", &with(&instanced, &[]));
    assert!(!text(&o.stderr).contains("not applied"), "{}", describe(&o));
    let instanced_json = assert_passed("instancing", &o, json);
    let (o, json, nodes_out) = run_check("instancing-nodes", &with(&three_nodes, &[]));
    let nodes_json = assert_passed("instancing-nodes", &o, json);
    assert_eq!(instanced_json["hit_fraction"], nodes_json["hit_fraction"]);
    // Every file but render.json (which holds times) is a picture.
    let pictures = |dir: &std::path::Path| -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n != "render.json")
            .collect();
        names.sort();
        names
    };
    let names = pictures(&instanced_out);
    assert!(names.contains(&"alpha-test.png".to_string()), "{names:?}");
    assert_eq!(names, pictures(&nodes_out));
    for name in &names {
        assert!(
            std::fs::read(instanced_out.join(name)).unwrap()
                == std::fs::read(nodes_out.join(name)).unwrap(),
            "{name} differs between the instanced cards and three plain nodes"
        );
    }
    // The committed cards, under the same camera: the instances drawn
    // apart cover more of the picture.
    let cards = asset("assets/crytek-sponza/cards.gltf");
    let (o, json, _) = run_check(
        "instancing-once",
        &with(
            &cards,
            &[
                "--methods",
                "flat-4-state",
                "--tracer",
                "query",
                "--lookup",
                "shader",
            ],
        ),
    );
    assert_eq!(o.status.code(), Some(0), "{}", describe(&o));
    let once = json.unwrap()["hit_fraction"].as_f64().unwrap();
    let thrice = instanced_json["hit_fraction"].as_f64().unwrap();
    // The second and third instance (y 3..3.5 and 5..6) lie where the
    // committed cards have nothing.
    assert!(
        once > 0.0 && thrice > once,
        "hit fraction {thrice} instanced, {once} once"
    );
}
