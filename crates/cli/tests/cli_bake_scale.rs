//! `bake` at scene scale: the committed Poly Haven fern (6,232 triangles,
//! copies of a few hundred) bakes, classifies each distinct triangle once
//! and verifies sound; `--threads` never changes a byte; `summary.json`
//! names the format.

mod common;

use common::{root, run, scratch};
use micromap_index_assets::{read_gltf_file, Limits};
use std::collections::BTreeSet;
use std::path::Path;

fn ok(args: &[&str]) -> String {
    let out = run(args);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

fn asset(path: &str) -> String {
    root()
        .join("assets")
        .join(path)
        .to_string_lossy()
        .into_owned()
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(dir.join("summary.json")).unwrap()).unwrap()
}

/// Every output of two bakes is the same bytes; `summary.json` apart from
/// its timings and thread count.
fn assert_same_outputs(a: &Path, b: &Path) {
    for name in [
        "micromap-data.bin",
        "micromap-triangles.bin",
        "micromap-indices.bin",
        "micromap-usage.bin",
        "preview.png",
    ] {
        let (x, y) = (std::fs::read(a.join(name)), std::fs::read(b.join(name)));
        match (x, y) {
            (Ok(x), Ok(y)) => assert!(
                x == y,
                "{name} differs between {} and {}",
                a.display(),
                b.display()
            ),
            (Err(_), Err(_)) => {}
            (x, y) => panic!("{name}: {:?} vs {:?}", x.is_ok(), y.is_ok()),
        }
    }
    let strip = |dir: &Path| {
        let mut s = summary(dir);
        let map = s.as_object_mut().unwrap();
        for key in [
            "bake_seconds",
            "micro_triangles_per_second",
            "preview_seconds",
            "threads",
        ] {
            map.remove(key);
        }
        s
    };
    assert_eq!(
        strip(a),
        strip(b),
        "summary.json of {} and {}",
        a.display(),
        b.display()
    );
}

/// The fern as committed (`fern_02.gltf`: the PNG with its alpha), level 4:
/// bakes, classifies each distinct UV triangle once (the count computed
/// here from the asset), gives the same bytes on 1 and 3 threads, and
/// `verify-bake` finds it sound against the same texture and triangles.
#[test]
fn the_fern_bakes_once_per_distinct_triangle_and_verifies_sound() {
    let gltf = asset("polyhaven-fern02/fern_02.gltf");
    let dir = scratch("scale-fern");
    let (one, three) = (dir.join("one"), dir.join("three"));
    for (out, threads) in [(&one, "1"), (&three, "3")] {
        ok(&[
            "bake",
            "--gltf",
            &gltf,
            "--out",
            out.to_str().unwrap(),
            "--level",
            "4",
            "--threads",
            threads,
            "--quiet",
        ]);
    }
    assert_same_outputs(&one, &three);

    // Every primitive reads the one image with one material, so the
    // distinct triangles are the distinct UV bit patterns.
    let read = read_gltf_file(Path::new(&gltf), &Limits::default()).unwrap();
    let first = &read.primitives[0];
    let mut distinct = BTreeSet::new();
    let mut all = Vec::new();
    for p in &read.primitives {
        assert_eq!(
            (p.image, p.sampler, p.cutoff, p.alpha_factor),
            (first.image, first.sampler, first.cutoff, first.alpha_factor)
        );
        assert!(p.vertex_alpha.is_none());
        for uv in &p.triangles {
            distinct.insert(uv.map(|c| c.map(f32::to_bits)));
            all.push(*uv);
        }
    }
    let s = summary(&one);
    assert_eq!(s["triangles"], all.len());
    assert_eq!(s["distinct_triangles"], distinct.len());
    assert!(
        distinct.len() * 5 < all.len(),
        "{} of {}",
        distinct.len(),
        all.len()
    );
    assert_eq!(
        (s["threads"].as_u64(), summary(&three)["threads"].as_u64()),
        (Some(1), Some(3))
    );

    // verify-bake reads TRIS.json: the same triangles, in index order.
    let tris = dir.join("fern.tris.json");
    let corner = |c: [f32; 2]| format!("[{},{}]", f64::from(c[0]), f64::from(c[1]));
    let body: Vec<String> = all
        .iter()
        .map(|uv| format!("[{},{},{}]", corner(uv[0]), corner(uv[1]), corner(uv[2])))
        .collect();
    std::fs::write(&tris, format!("{{\"triangles\":[{}]}}", body.join(","))).unwrap();
    let report = ok(&[
        "verify-bake",
        "--texture",
        &asset("polyhaven-fern02/textures/fern_02_diff_1k.png"),
        "--triangles",
        tris.to_str().unwrap(),
        "--micromaps",
        one.to_str().unwrap(),
        "--filter",
        "linear",
        "--address",
        "repeat",
    ]);
    assert!(report.contains("sound"), "{report}");
}

/// `--threads 1, 2, 5` give the same bytes on the committed Sponza assets
/// (auto levels with mixed sizes, both formats, several primitives).
#[test]
fn threads_never_change_the_bytes() {
    let cards = asset("crytek-sponza/cards.gltf");
    let thorn = asset("crytek-sponza/sponza_thorn.png");
    let grid = asset("crytek-sponza/grid.tris.json");
    let cases: [(&str, Vec<&str>); 3] = [
        ("cards-auto", vec!["--gltf", &cards, "--max-level", "7"]),
        (
            "cards-2",
            vec!["--gltf", &cards, "--level", "5", "--format", "2"],
        ),
        (
            "grid",
            vec![
                "--texture",
                &thorn,
                "--triangles",
                &grid,
                "--filter",
                "linear",
                "--max-level",
                "7",
            ],
        ),
    ];
    for (name, args) in cases {
        let dir = scratch(&format!("scale-threads-{name}"));
        let outs: Vec<_> = ["1", "2", "5"]
            .iter()
            .map(|threads| {
                let out = dir.join(threads);
                let mut full = vec!["bake", "--out", out.to_str().unwrap(), "--quiet"];
                full.extend(["--threads", threads]);
                full.extend(args.iter().copied());
                ok(&full);
                out
            })
            .collect();
        assert_same_outputs(&outs[0], &outs[1]);
        assert_same_outputs(&outs[0], &outs[2]);
    }
}

/// `summary.json` names the format and keeps the APIs' value beside it.
#[test]
fn the_summary_names_the_format() {
    let dir = scratch("scale-format");
    let chain = asset("crytek-sponza/chain.png");
    let grid = asset("crytek-sponza/grid.tris.json");
    for (format, name, value) in [("4", "4-state", 2), ("2", "2-state", 1)] {
        let out = dir.join(format);
        ok(&[
            "bake",
            "--texture",
            &chain,
            "--triangles",
            &grid,
            "--level",
            "2",
            "--format",
            format,
            "--out",
            out.to_str().unwrap(),
            "--no-preview",
            "--quiet",
        ]);
        let s = summary(&out);
        assert_eq!(
            (s["format"].as_str(), s["format_api_value"].as_u64()),
            (Some(name), Some(value))
        );
    }
    let out = run(&[
        "bake",
        "--threads",
        "0",
        "--texture",
        &chain,
        "--triangles",
        &grid,
        "--out",
        dir.join("zero").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--threads \"0\""));
    assert!(!dir.join("zero").exists());
}
