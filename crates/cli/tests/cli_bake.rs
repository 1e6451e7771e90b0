//! `micromap-index bake` and `verify-bake`: outputs, their consistency with
//! the library's reader, the verifier's verdicts, exit codes and the
//! all-or-nothing output, on the committed Crytek Sponza assets.

mod common;

use common::run;
use micromap_index::micromap::{read_buffers, BufferBytes, IndexWidth, MicromapIndex, State};
use std::path::{Path, PathBuf};

const ASSETS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/crytek-sponza");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("micromap-bake-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

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

fn write(path: &Path, text: &str) {
    std::fs::write(path, text).unwrap();
}

/// The chain texture on four triangles, at a fixed level: every output
/// file is consistent with the summary and with the library's reader, and
/// the verifier finds the bake sound; flipping one known state makes it
/// unsound with a witness.
#[test]
fn bake_writes_consistent_buffers_that_verify_sound_and_a_flip_is_caught() {
    let dir = scratch("chain");
    std::fs::create_dir_all(&dir).unwrap();
    let tris = dir.join("tris.json");
    write(
        &tris,
        r#"{"triangles": [[[0, 0], [1, 0], [0, 0.25]], [[1, 0], [1, 0.25], [0, 0.25]],
                          [[0.1, 0.3], [0.9, 0.35], [0.5, 0.9]], [[0, 0], [0, 0], [0, 0]]]}"#,
    );
    let out = dir.join("out");
    let texture = format!("{ASSETS}/chain.png");
    let summary = ok(&[
        "bake",
        "--texture",
        &texture,
        "--triangles",
        tris.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--level",
        "5",
        "--format",
        "4",
        "--quiet",
    ]);
    let summary: serde_json::Value = serde_json::from_str(&summary).unwrap();
    assert_eq!(summary["triangles"], 4);
    let micro = &summary["micro_triangles"];
    let total: u64 = [
        "transparent",
        "opaque",
        "unknown_transparent",
        "unknown_opaque",
    ]
    .iter()
    .map(|k| micro[k].as_u64().unwrap())
    .sum();
    assert_eq!(total, 4 * 1024);
    let read_file = |name: &str| std::fs::read(out.join(name)).unwrap();
    let (data, records, indices) = (
        read_file("micromap-data.bin"),
        read_file("micromap-triangles.bin"),
        read_file("micromap-indices.bin"),
    );
    assert_eq!(indices.len(), 16);
    let read = read_buffers(
        &BufferBytes {
            records: &records,
            data: &data,
            usage_counts: Some(&read_file("micromap-usage.bin")),
            indices: Some((&indices, IndexWidth::U32)),
        },
        &micromap_index::micromap::ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(
        read.micromaps.len() as u64,
        summary["micromaps_after_dedup"].as_u64().unwrap()
    );
    // The degenerate point triangle at (0, 0) reads one texel: a special
    // index.
    assert!(matches!(
        read.indices.as_ref().unwrap()[3],
        MicromapIndex::Special(_)
    ));
    assert_eq!(summary["bytes_flat"].as_u64().unwrap(), data.len() as u64);
    let preview = read_file("preview.png");
    assert_eq!(&preview[..8], b"\x89PNG\r\n\x1a\n");

    let verify = |micromaps: &Path| {
        run(&[
            "verify-bake",
            "--texture",
            &texture,
            "--triangles",
            tris.to_str().unwrap(),
            "--micromaps",
            micromaps.to_str().unwrap(),
            "--json",
        ])
    };
    let sound = verify(&out);
    assert_eq!(
        sound.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&sound.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&sound.stdout).unwrap();
    assert_eq!(report["contradictions"], 0);
    assert_eq!(report["sound"], true);

    // Flip the first known micro-triangle of the first micromap.
    let map = &read.micromaps[0];
    let (i, state) = (0..map.len())
        .map(|i| (i, map.get(i).unwrap()))
        .find(|(_, s)| s.is_known())
        .expect("a known micro-triangle");
    let flipped = if state == State::Opaque {
        State::Transparent
    } else {
        State::Opaque
    };
    let mut map = map.clone();
    map.set(i, flipped).unwrap();
    let offset = read.records[0].data_offset as usize;
    let mut bad = data.clone();
    bad[offset..offset + map.as_bytes().len()].copy_from_slice(map.as_bytes());
    let tampered = dir.join("tampered");
    std::fs::create_dir_all(&tampered).unwrap();
    for name in [
        "micromap-triangles.bin",
        "micromap-indices.bin",
        "micromap-usage.bin",
    ] {
        std::fs::copy(out.join(name), tampered.join(name)).unwrap();
    }
    std::fs::write(tampered.join("micromap-data.bin"), &bad).unwrap();
    let unsound = verify(&tampered);
    assert_eq!(unsound.status.code(), Some(1));
    let report: serde_json::Value = serde_json::from_slice(&unsound.stdout).unwrap();
    assert!(report["contradictions"].as_u64().unwrap() >= 1, "{report}");
    let first = &report["first_contradictions"][0];
    assert!(first["witness_texel_space"].is_array(), "{first}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The committed glTF asset (and its GLB twin) bakes with the material's
/// cutoffs and samplers; both give the same buffers.
#[test]
fn bake_reads_the_committed_gltf_and_glb_alike() {
    let dir = scratch("gltf");
    let (a, b) = (dir.join("gltf"), dir.join("glb"));
    let gltf = ok(&[
        "bake",
        "--gltf",
        &format!("{ASSETS}/cards.gltf"),
        "--out",
        a.to_str().unwrap(),
        "--level",
        "4",
        "--quiet",
        "--no-preview",
    ]);
    ok(&[
        "bake",
        "--gltf",
        &format!("{ASSETS}/cards.glb"),
        "--out",
        b.to_str().unwrap(),
        "--level",
        "4",
        "--quiet",
        "--no-preview",
    ]);
    let summary: serde_json::Value = serde_json::from_str(&gltf).unwrap();
    assert!(summary["jobs"].as_array().unwrap().len() >= 3, "{summary}");
    assert!(summary["triangles"].as_u64().unwrap() >= 128);
    for name in [
        "micromap-data.bin",
        "micromap-triangles.bin",
        "micromap-indices.bin",
    ] {
        assert_eq!(
            std::fs::read(a.join(name)).unwrap(),
            std::fs::read(b.join(name)).unwrap(),
            "{name}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Malformed input is exit 2 and unreadable input exit 3; nothing is
/// written either way.
#[test]
fn bad_input_is_refused_and_nothing_is_written() {
    let dir = scratch("bad");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("out");
    let texture = format!("{ASSETS}/chain.png");
    let tris = dir.join("bad.json");
    write(&tris, r#"{"triangles": [[[0, 0], [1, 0]]]}"#);
    let cases: [(&[&str], i32); 6] = [
        (
            &[
                "bake",
                "--texture",
                &texture,
                "--triangles",
                tris.to_str().unwrap(),
            ],
            2,
        ),
        (
            &[
                "bake",
                "--texture",
                &texture,
                "--triangles",
                "/nonexistent/t.json",
            ],
            3,
        ),
        (
            &[
                "bake",
                "--texture",
                "/nonexistent.png",
                "--triangles",
                tris.to_str().unwrap(),
            ],
            3,
        ),
        (
            &[
                "bake",
                "--texture",
                tris.to_str().unwrap(),
                "--triangles",
                tris.to_str().unwrap(),
            ],
            2,
        ),
        (&["bake", "--gltf", &texture], 2),
        (
            &[
                "bake",
                "--texture",
                &texture,
                "--triangles",
                tris.to_str().unwrap(),
                "--level",
                "13",
            ],
            2,
        ),
    ];
    for (args, code) in cases {
        let mut args = args.to_vec();
        args.extend(["--out", out.to_str().unwrap()]);
        let result = run(&args);
        assert_eq!(
            result.status.code(),
            Some(code),
            "{args:?}: {}",
            String::from_utf8_lossy(&result.stderr)
        );
        assert!(!result.stderr.is_empty());
        assert!(
            !out.exists() || std::fs::read_dir(&out).unwrap().next().is_none(),
            "{args:?} wrote"
        );
    }
    // A second bake into the same directory needs --force.
    write(&tris, r#"{"triangles": [[[0, 0], [1, 0], [0, 1]]]}"#);
    let args = [
        "bake",
        "--texture",
        &texture,
        "--triangles",
        tris.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--level",
        "2",
        "--quiet",
    ];
    ok(&args);
    assert_eq!(run(&args).status.code(), Some(2));
    let mut forced = args.to_vec();
    forced.push("--force");
    ok(&forced);
    let _ = std::fs::remove_dir_all(&dir);
}

/// FNV-1a, 64 bits: a digest of a file's bytes.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
    })
}

/// `--model`: the default is the GPU model; `--model exact` writes the
/// bytes earlier versions wrote (digests of a level-5 grid bake by the
/// baker before the GPU model, f81befe); the summary names the model; the
/// GPU model knows fewer micro-triangles on the texel-aligned grid; an
/// exact bake verifies sound for the exact model and not for the GPU model,
/// a GPU bake for both; an unknown model is refused.
#[test]
fn model_option_defaults_to_the_gpu_model_and_exact_keeps_the_old_bytes() {
    let dir = scratch("model");
    let texture = format!("{ASSETS}/sponza_thorn.png");
    let tris = format!("{ASSETS}/grid.tris.json");
    let input = ["--texture", &texture, "--triangles", &tris];
    let summary_of = |out: &Path, model: Option<&str>| -> serde_json::Value {
        let mut args = vec!["bake"];
        args.extend(input);
        args.extend([
            "--out",
            out.to_str().unwrap(),
            "--level",
            "5",
            "--no-preview",
            "--quiet",
        ]);
        if let Some(m) = model {
            args.extend(["--model", m]);
        }
        serde_json::from_str(&ok(&args)).unwrap()
    };
    let (exact, gpu, default) = (dir.join("exact"), dir.join("gpu"), dir.join("default"));
    let s_exact = summary_of(&exact, Some("exact"));
    let s_gpu = summary_of(&gpu, Some("gpu-binary32"));
    let s_default = summary_of(&default, None);
    assert_eq!(s_exact["model"], "exact");
    assert_eq!(s_gpu["model"], "gpu-binary32");
    assert_eq!(s_default["model"], "gpu-binary32");
    for (file, digest) in [
        ("micromap-data.bin", 0x8f98_e304_c9ec_83b3u64),
        ("micromap-triangles.bin", 0x93fd_08cf_6b1f_8925),
        ("micromap-indices.bin", 0x709f_2462_c272_f725),
        ("micromap-usage.bin", 0x9b38_f5ea_f9eb_c392),
    ] {
        assert_eq!(
            fnv1a(&std::fs::read(exact.join(file)).unwrap()),
            digest,
            "{file}"
        );
        assert_eq!(
            std::fs::read(gpu.join(file)).unwrap(),
            std::fs::read(default.join(file)).unwrap()
        );
    }
    let known = |s: &serde_json::Value| s["known_fraction"].as_f64().unwrap();
    assert!(known(&s_gpu) < known(&s_exact), "{s_gpu} {s_exact}");
    assert!(known(&s_gpu) > 0.5 * known(&s_exact));
    // The widening's cost, as the GPU bake reports it, is the exact bake's
    // extra known micro-triangles (same triangles, same levels).
    let widening = |s: &serde_json::Value, key: &str| s["widening"][key].clone();
    let count = |s: &serde_json::Value, state: &str| s["micro_triangles"][state].as_u64().unwrap();
    let known_count = |s: &serde_json::Value| count(s, "opaque") + count(s, "transparent");
    assert_eq!(
        widening(&s_gpu, "micro_triangles_made_unknown")
            .as_u64()
            .unwrap(),
        known_count(&s_exact) - known_count(&s_gpu)
    );
    assert_eq!(
        widening(&s_gpu, "known_fraction_exact_model"),
        s_exact["known_fraction"]
    );
    assert_eq!(widening(&s_exact, "micro_triangles_made_unknown"), 0);
    assert_eq!(
        widening(&s_exact, "known_fraction_exact_model"),
        s_exact["known_fraction"]
    );
    let verify = |dir: &Path, model: &str| {
        let mut args = vec!["verify-bake"];
        args.extend(input);
        args.extend([
            "--micromaps",
            dir.to_str().unwrap(),
            "--model",
            model,
            "--json",
        ]);
        let out = run(&args);
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(json["model"], model);
        (out.status.code(), json["contradictions"].as_u64().unwrap())
    };
    assert_eq!(verify(&exact, "exact"), (Some(0), 0));
    let (code, contradictions) = verify(&exact, "gpu-binary32");
    assert_eq!(code, Some(1));
    assert!(contradictions > 0);
    assert_eq!(verify(&gpu, "gpu-binary32"), (Some(0), 0));
    assert_eq!(verify(&gpu, "exact"), (Some(0), 0));
    let mut args = vec!["bake"];
    args.extend(input);
    let bad = dir.join("bad");
    args.extend(["--out", bad.to_str().unwrap(), "--model", "gpu"]);
    let out = run(&args);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--model"));
    assert!(!bad.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--mips`: the summary names the rule; each lower level a bake must also
/// hold for leaves fewer micro-triangles known (the grid at level 4:
/// levels 0, 0..=2, all); a rule that names no level is refused with exit
/// 2 and nothing written; vertex alpha is not needed for this.
#[test]
fn mips_option_names_its_rule_and_knows_less_per_level() {
    let dir = scratch("mips");
    let texture = format!("{ASSETS}/sponza_thorn.png");
    let tris = format!("{ASSETS}/grid.tris.json");
    let bake = |mips: &str| -> serde_json::Value {
        let out = dir.join(format!("m{mips}"));
        let args = [
            "bake",
            "--texture",
            &texture,
            "--triangles",
            &tris,
            "--out",
            out.to_str().unwrap(),
            "--level",
            "4",
            "--mips",
            mips,
            "--no-preview",
            "--quiet",
        ];
        serde_json::from_str(&ok(&args)).unwrap()
    };
    let known = |s: &serde_json::Value| s["known_fraction"].as_f64().unwrap();
    let (zero, two, all) = (bake("0"), bake("2"), bake("all"));
    assert_eq!(
        (
            zero["mips"].as_str(),
            two["mips"].as_str(),
            all["mips"].as_str()
        ),
        (Some("0"), Some("2"), Some("all"))
    );
    assert!(
        known(&zero) > known(&two) && known(&two) > known(&all),
        "{zero} {two} {all}"
    );
    for bad in ["-1", "x", "2.5", ""] {
        let out = dir.join("bad");
        let r = run(&[
            "bake",
            "--texture",
            &texture,
            "--triangles",
            &tris,
            "--out",
            out.to_str().unwrap(),
            "--mips",
            bad,
            "--quiet",
        ]);
        assert_eq!(r.status.code(), Some(2), "--mips {bad:?}");
        assert!(String::from_utf8_lossy(&r.stderr).contains("--mips"));
        assert!(!out.exists());
    }
}

/// Without `--quiet` but with stderr a pipe (not a terminal), a bake that
/// succeeds writes nothing at all to stderr: the progress bar and the
/// "drawing preview.png" line are for a terminal only, so a log gets no
/// escape codes and no partial lines.
#[test]
fn a_bake_through_a_pipe_writes_nothing_to_stderr() {
    let out = scratch("pipe");
    let asset = format!("{ASSETS}/cards.glb");
    let result = run(&[
        "bake",
        "--gltf",
        &asset,
        "--out",
        out.to_str().unwrap(),
        "--level",
        "3",
    ]);
    assert_eq!(
        result.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    assert_eq!(String::from_utf8_lossy(&result.stderr), "");
    // The whole bake ran, the preview step included.
    assert!(!result.stdout.is_empty());
    assert!(out.join("preview.png").is_file());
    let _ = std::fs::remove_dir_all(&out);
}
