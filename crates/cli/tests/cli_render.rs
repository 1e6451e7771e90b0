//! `micromap-index render --check` on a real Vulkan device with ray queries
//! (Mesa's lavapipe in CI): our bakes of the committed assets (GPU model,
//! the default) pass at levels 2..=8; the negative controls fail: looking
//! the micromap up at swapped barycentrics, flipping the known states, a
//! nearest bake sampled linearly, the committed meshoptimizer bakes. Exit
//! codes for bad input and for a machine without a device.
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

/// Whether a device with ray queries is there (probed once with a 1x1
/// frame); without one, says SKIPPED (or fails under `REQUIRE=1`).
fn device(test: &str) -> bool {
    static PROBE: OnceLock<Result<(), String>> = OnceLock::new();
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
            Some(0) => Ok(()),
            Some(4) => Err(text(&o.stderr).trim().to_string()),
            other => panic!("probe: exit {other:?}\n{}", text(&o.stderr)),
        }
    });
    match probe {
        Ok(()) => true,
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
    (o, json)
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
    assert_eq!(o.status.code(), Some(0), "{name}: {}", describe(&o));
    let json = json.unwrap();
    assert_eq!(json["check"]["passed"], true, "{name}");
    assert_eq!(json["tracers"], serde_json::json!(TRACERS), "{name}");
    for tracer in TRACERS {
        let alpha = traced(&json, tracer, "alpha-test");
        assert_eq!(alpha["known"], 0);
        assert_eq!(alpha["texture_fetches"], alpha["candidates"]);
        // The pipeline's alpha test renders the query's picture.
        assert_eq!(
            alpha["pixels_differing_from_alpha_test"], 0,
            "{name} {tracer}"
        );
        for m in ["flat-4-state", "level-order-tree", "paper-tree"] {
            let m = traced(&json, tracer, m);
            assert_eq!(m["contradicted"], 0, "{name} {tracer}");
            assert_eq!(m["pixels_differing_from_alpha_test"], 0, "{name} {tracer}");
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
            let m = traced(&json, tracer, m);
            assert!(m["contradicted"].as_u64().unwrap() > 0, "{fault} {tracer}");
            // The exact hit point disagrees with what the shader decided.
            let first = &m["contradictions"][0];
            assert_eq!(first["class"], "micromap-wrong", "{fault}: {first}");
            assert!(first["b1"].as_str().unwrap().starts_with("0x"));
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
        let flat = traced(&json, tracer, "flat-4-state");
        assert!(flat["contradicted"].as_u64().unwrap() > 0, "{tracer}");
        assert_eq!(
            flat["contradictions"][0]["class"], "micromap-wrong",
            "{tracer}"
        );
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
                let flat = traced(&json, tracer, "flat-4-state");
                assert!(
                    flat["contradicted"].as_u64().unwrap() > 0,
                    "{baker} {level} {tracer}"
                );
                assert_eq!(
                    flat["contradictions"][0]["class"], "micromap-wrong",
                    "{baker} {level} {tracer}"
                );
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
