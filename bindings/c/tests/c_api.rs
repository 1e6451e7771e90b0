//! The C API from C, compiled here with the system's C compiler against the
//! static library cargo built for this test (`libmicromap_index_capi.a`
//! next to the test executable):
//!
//! - the header alone compiles as C99 and as C++17 with warnings as errors;
//! - `tests/api_test.c` (answers, misuse codes, handles) runs plain and
//!   under the address and undefined-behaviour sanitizers, and the struct
//!   sizes it prints equal Rust's;
//! - `examples/bake_grid.c` bakes the committed thorn texture and
//!   `grid.tris.json` (handed over as raw files: C has no PNG decoder),
//!   prepared here with a wide row pitch and a 3-float stride, and as the
//!   example's own converter `examples/make_inputs.py` writes them, and
//!   writes the same bytes as `micromap-index bake` (the CLI binary, built
//!   by cargo with the test profile in a target directory of its own).

use micromap_index_assets::{decode_alpha_image, read_triangles_json, AlphaTexels, Limits};
use micromap_index_capi::*;
use std::path::{Path, PathBuf};
use std::process::Command;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
const HERE: &str = env!("CARGO_MANIFEST_DIR");
const C_FLAGS: [&str; 5] = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"];
const SANITIZE: [&str; 3] = [
    "-fsanitize=address,undefined",
    "-fno-sanitize-recover=undefined",
    "-fno-omit-frame-pointer",
];

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("capi")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The static library cargo built for this test run.
fn static_lib() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let lib = exe.parent().unwrap().join("libmicromap_index_capi.a");
    assert!(lib.is_file(), "{} is missing", lib.display());
    lib
}

fn cc() -> String {
    std::env::var("CC").unwrap_or_else(|_| "cc".into())
}

/// Compiles `sources` into `out` with the C flags (and `extra`), linked
/// with the static library; the compiler's output on failure.
fn build(sources: &[PathBuf], out: &Path, extra: &[&str]) -> Result<(), String> {
    let mut command = Command::new(cc());
    command
        .args(C_FLAGS)
        .args(extra)
        .arg(format!("-I{HERE}/include"))
        .args(sources)
        .arg(static_lib())
        // `rustc --print native-static-libs` on Linux (docs/c.md).
        .args([
            "-lgcc_s",
            "-lutil",
            "-lrt",
            "-lpthread",
            "-lm",
            "-ldl",
            "-lc",
        ])
        .arg("-o")
        .arg(out);
    compile(command)
}

fn compile(mut command: Command) -> Result<(), String> {
    let output = command
        .output()
        .map_err(|e| format!("cannot run {}: {e}", cc()))?;
    if output.status.success() {
        Ok(())
    } else {
        Err(format!(
            "{command:?} failed:\n{}",
            String::from_utf8_lossy(&output.stderr)
        ))
    }
}

/// Whether the sanitizer runtimes link and run here.
fn sanitizers_available(dir: &Path) -> bool {
    let probe = dir.join("probe.c");
    std::fs::write(&probe, "int main(void) { return 0; }\n").unwrap();
    let exe = dir.join("probe");
    let built = Command::new(cc())
        .args(SANITIZE)
        .arg(&probe)
        .arg("-o")
        .arg(&exe)
        .output()
        .is_ok_and(|o| o.status.success());
    built && Command::new(&exe).status().is_ok_and(|s| s.success())
}

fn run(exe: &Path, args: &[&Path]) -> String {
    let output = Command::new(exe)
        .args(args)
        .env("ASAN_OPTIONS", "abort_on_error=0:detect_leaks=1")
        .env("UBSAN_OPTIONS", "print_stacktrace=1:halt_on_error=1")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "{} failed ({}):\n{stdout}\n{}",
        exe.display(),
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
}

#[test]
fn the_c_api_test_passes_linked_with_the_shared_library() {
    let dir = tmp("shared");
    let lib_dir = static_lib().parent().unwrap().to_path_buf();
    assert!(lib_dir.join("libmicromap_index_capi.so").is_file());
    let exe = dir.join("api_test_shared");
    let mut command = Command::new(cc());
    command
        .args(C_FLAGS)
        .arg(format!("-I{HERE}/include"))
        .arg(format!("{HERE}/tests/api_test.c"))
        .arg(format!("-L{}", lib_dir.display()))
        .arg(format!("-Wl,-rpath,{}", lib_dir.display()))
        .args(["-lmicromap_index_capi", "-lm", "-o"])
        .arg(&exe);
    compile(command).unwrap();
    let stdout = run(&exe, &[]);
    assert!(stdout.contains("\nok "), "{stdout}");
}

#[test]
fn the_pkg_config_file_links_the_static_library() {
    if Command::new("pkg-config")
        .arg("--version")
        .output()
        .is_err()
    {
        println!("skipped: pkg-config is not installed");
        return;
    }
    // An installed prefix: the archive alone (so -l finds it), the header
    // and the .pc file from its template.
    let prefix = tmp("pkg-config");
    for sub in ["lib/pkgconfig", "include"] {
        std::fs::create_dir_all(prefix.join(sub)).unwrap();
    }
    std::fs::copy(static_lib(), prefix.join("lib/libmicromap_index_capi.a")).unwrap();
    std::fs::copy(
        format!("{HERE}/include/micromap_index.h"),
        prefix.join("include/micromap_index.h"),
    )
    .unwrap();
    let pc = std::fs::read_to_string(format!("{HERE}/micromap_index.pc.in"))
        .unwrap()
        .replace("@PREFIX@", prefix.to_str().unwrap())
        .replace("@VERSION@", env!("CARGO_PKG_VERSION"));
    std::fs::write(prefix.join("lib/pkgconfig/micromap_index.pc"), pc).unwrap();
    let flags = Command::new("pkg-config")
        .env("PKG_CONFIG_PATH", prefix.join("lib/pkgconfig"))
        .args(["--static", "--cflags", "--libs", "micromap_index"])
        .output()
        .unwrap();
    assert!(
        flags.status.success(),
        "{}",
        String::from_utf8_lossy(&flags.stderr)
    );
    let flags = String::from_utf8(flags.stdout).unwrap();
    let exe = prefix.join("api_test_pkg_config");
    let mut command = Command::new(cc());
    command
        .args(C_FLAGS)
        .arg(format!("{HERE}/tests/api_test.c"))
        .args(flags.split_whitespace())
        .arg("-o")
        .arg(&exe);
    compile(command).unwrap();
    let stdout = run(&exe, &[]);
    assert!(stdout.contains("\nok "), "{stdout}");
}

#[test]
fn the_header_compiles_as_c99_and_as_cpp17() {
    let header = format!("{HERE}/include/micromap_index.h");
    let c = Command::new(cc())
        .args(C_FLAGS)
        .args(["-fsyntax-only", "-x", "c", &header])
        .output()
        .unwrap();
    assert!(c.status.success(), "{}", String::from_utf8_lossy(&c.stderr));
    let cxx = std::env::var("CXX").unwrap_or_else(|_| "c++".into());
    let cpp = Command::new(&cxx)
        .args(["-std=c++17", "-Wall", "-Wextra", "-Werror", "-pedantic"])
        .args(["-fsyntax-only", "-x", "c++", &header])
        .output()
        .unwrap_or_else(|e| panic!("cannot run {cxx}: {e}"));
    assert!(
        cpp.status.success(),
        "{}",
        String::from_utf8_lossy(&cpp.stderr)
    );
}

/// `sizeof NAME N` lines against Rust's sizes.
fn check_sizes(stdout: &str) {
    let rust = [
        ("mmi_micro_triangle", size_of::<mmi_micro_triangle>()),
        ("mmi_texture", size_of::<mmi_texture>()),
        ("mmi_sampler", size_of::<mmi_sampler>()),
        ("mmi_material", size_of::<mmi_material>()),
        ("mmi_uv_transform", size_of::<mmi_uv_transform>()),
        ("mmi_mesh", size_of::<mmi_mesh>()),
        ("mmi_bake_options", size_of::<mmi_bake_options>()),
        ("mmi_bake_stats", size_of::<mmi_bake_stats>()),
        ("mmi_buffers_view", size_of::<mmi_buffers_view>()),
        ("mmi_read_options", size_of::<mmi_read_options>()),
        ("mmi_buffers_info", size_of::<mmi_buffers_info>()),
        ("mmi_verify_report", size_of::<mmi_verify_report>()),
        ("mmi_contradiction", size_of::<mmi_contradiction>()),
        ("mmi_tree_info", size_of::<mmi_tree_info>()),
    ];
    let c: Vec<(&str, usize)> = stdout
        .lines()
        .filter_map(|l| l.strip_prefix("sizeof "))
        .map(|l| {
            let (name, size) = l.split_once(' ').unwrap();
            (name, size.parse().unwrap())
        })
        .collect();
    assert_eq!(c, rust, "C and Rust struct sizes differ");
}

#[test]
fn the_c_api_test_passes_plain_and_under_sanitizers() {
    let dir = tmp("api_test");
    let source = PathBuf::from(format!("{HERE}/tests/api_test.c"));
    let exe = dir.join("api_test");
    build(std::slice::from_ref(&source), &exe, &[]).unwrap();
    let stdout = run(&exe, &[]);
    assert!(stdout.contains("\nok "), "{stdout}");
    check_sizes(&stdout);

    if !sanitizers_available(&dir) {
        println!("skipped: the AddressSanitizer/UndefinedBehaviorSanitizer runtime is missing");
        return;
    }
    let exe = dir.join("api_test_sanitized");
    build(&[source], &exe, &SANITIZE).unwrap();
    let stdout = run(&exe, &[]);
    assert!(stdout.contains("\nok "), "{stdout}");
}

/// The committed texture as a raw file with a row pitch wider than the
/// row (so the C side exercises the pitch), and the triangles as
/// 3-float vertices (so it exercises the stride).
fn prepare_inputs(dir: &Path) -> (PathBuf, PathBuf, PathBuf, PathBuf) {
    let texture_path = PathBuf::from(format!("{ROOT}/assets/crytek-sponza/sponza_thorn.png"));
    let triangles_path = PathBuf::from(format!("{ROOT}/assets/crytek-sponza/grid.tris.json"));
    let image =
        decode_alpha_image(&std::fs::read(&texture_path).unwrap(), &Limits::default()).unwrap();
    let (format, size, texels): (u32, usize, Vec<u8>) = match &image.texels {
        AlphaTexels::Unorm8(t) => (0, 1, t.clone()),
        AlphaTexels::Unorm16(t) => (1, 2, t.iter().flat_map(|x| x.to_ne_bytes()).collect()),
        AlphaTexels::Float(t) => (2, 4, t.iter().flat_map(|x| x.to_ne_bytes()).collect()),
    };
    let row = image.width as usize * size;
    let pitch = row + 4 * size + 4;
    let mut raw = Vec::new();
    for word in [image.width, image.height, format, pitch as u32] {
        raw.extend(word.to_ne_bytes());
    }
    for y in 0..image.height as usize {
        raw.extend(&texels[y * row..(y + 1) * row]);
        raw.extend(std::iter::repeat(0xA5).take(pitch - row));
    }
    let raw_path = dir.join("texture.raw");
    std::fs::write(&raw_path, raw).unwrap();

    let triangles = read_triangles_json(&std::fs::read(&triangles_path).unwrap()).unwrap();
    let mut uvs = Vec::new();
    uvs.extend(((triangles.len() * 3) as u32).to_ne_bytes());
    uvs.extend(3u32.to_ne_bytes());
    for corner in triangles.iter().flatten() {
        for x in [corner[0], corner[1], 7.0] {
            uvs.extend(x.to_ne_bytes());
        }
    }
    let uvs_path = dir.join("uvs.bin");
    std::fs::write(&uvs_path, uvs).unwrap();
    (texture_path, triangles_path, raw_path, uvs_path)
}

/// `micromap-index bake` from the CLI crate, built (or found up to date)
/// by cargo with the test profile in a target directory of its own: the
/// workspace's `target/debug/micromap-index` is the binary the CLI's own
/// tests run, and a build here with other features must not replace it.
fn cli_bake(texture: &Path, triangles: &Path, level: &str, out: &Path) {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let target = Path::new(env!("CARGO_TARGET_TMPDIR")).join("capi-cli-target");
    let status = Command::new(&cargo)
        .current_dir(ROOT)
        .args(["run", "-q", "--profile", "test", "-p", "micromap-index-cli"])
        .args(["--bin", "micromap-index", "--target-dir"])
        .arg(&target)
        .args(["--", "bake", "--texture"])
        .arg(texture)
        .arg("--triangles")
        .arg(triangles)
        .args([
            "--level",
            level,
            "--no-preview",
            "--quiet",
            "--force",
            "--out",
        ])
        .arg(out)
        .stdout(std::process::Stdio::null())
        .status()
        .unwrap_or_else(|e| panic!("cannot run {cargo}: {e}"));
    assert!(status.success(), "micromap-index bake failed");
}

#[test]
fn bake_grid_c_writes_the_clis_bytes() {
    let dir = tmp("bake_grid");
    let (texture, triangles, raw, uvs) = prepare_inputs(&dir);
    let exe = dir.join("bake_grid");
    let extra: &[&str] = if sanitizers_available(&dir) {
        &SANITIZE
    } else {
        println!("skipped: sanitizers for bake_grid (runtime missing); built plain");
        &[]
    };
    build(
        &[PathBuf::from(format!("{HERE}/examples/bake_grid.c"))],
        &exe,
        extra,
    )
    .unwrap();
    // The converter that ships with the example (the documented way to
    // its inputs), when Python is here: its files bake to the same bytes.
    let script = dir.join("script");
    let converted = Command::new("python3")
        .arg(format!("{HERE}/examples/make_inputs.py"))
        .args([&texture, &triangles, &script])
        .status()
        .is_ok_and(|status| status.success());
    if !converted {
        println!("skipped: make_inputs.py (no python3 here)");
    }
    for level in ["4", "auto"] {
        let c_out = dir.join(format!("c-{level}"));
        let cli_out = dir.join(format!("cli-{level}"));
        std::fs::create_dir_all(&c_out).unwrap();
        let stdout = run(&exe, &[&raw, &uvs, Path::new(level), &c_out]);
        assert!(stdout.starts_with("triangles 128 "), "{stdout}");
        cli_bake(&texture, &triangles, level, &cli_out);
        let mut outputs = vec![c_out];
        if converted {
            let script_out = dir.join(format!("script-{level}"));
            std::fs::create_dir_all(&script_out).unwrap();
            let (raw, uvs) = (script.join("texture.raw"), script.join("uvs.bin"));
            let stdout = run(&exe, &[&raw, &uvs, Path::new(level), &script_out]);
            assert!(stdout.starts_with("triangles 128 "), "{stdout}");
            outputs.push(script_out);
        }
        for name in [
            "micromap-data.bin",
            "micromap-triangles.bin",
            "micromap-indices.bin",
            "micromap-usage.bin",
        ] {
            let cli = std::fs::read(cli_out.join(name)).unwrap();
            assert!(
                !cli.is_empty() || name == "micromap-data.bin",
                "{name} is empty"
            );
            for c_out in &outputs {
                let c = std::fs::read(c_out.join(name)).unwrap();
                assert!(
                    c == cli,
                    "level {level}: {} differs ({} vs {} bytes)",
                    c_out.join(name).display(),
                    c.len(),
                    cli.len()
                );
            }
        }
    }
}
