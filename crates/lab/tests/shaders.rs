//! The shader library (`shaders/glsl/`) run for real and compared with the
//! Rust library bit for bit: every shader is compiled with `glslangValidator`
//! and validated with `spirv-val`, then compute kernels run on the first
//! Vulkan device (Mesa's lavapipe in CI) and evaluate
//!
//! - the index function, through the conformance driver
//!   `reference/drivers/glsl/spec_f32.comp`, on the committed `spec-f32`
//!   vectors;
//! - the flat lookup (`micromap_state.glsl`) on every micro-triangle of
//!   random and structured maps of levels 0..=12, both formats, through the
//!   buffers `MicromapBuffers` writes (special indices, 8-, 16- and 32-bit
//!   index buffers), and on malformed buffers;
//! - the level-order tree (`level_order_tree.glsl`) on every index of the
//!   same maps, with and without top tables, against `LevelOrderTree::get`;
//! - the paper's Algorithm 3 (`paper_tree.glsl`) against `PaperTree::get`:
//!   every index up to level 6, sampled indices of the maps whose trees stay
//!   small above (its scan costs about 4x per level; a bit-serial scan of a
//!   large level-12 tree for every index would take hours on a CPU device);
//! - both tree lookups on malformed and changed bytes: answers stay in
//!   `0..=4`, and equal the library's wherever it accepts the bytes;
//! - the HLSL twins (`shaders/hlsl/`, glslang's HLSL front end) on the same
//!   vectors and maps of levels 0..=9.
//!
//! Without `glslangValidator`/`spirv-val` on `PATH` or without a Vulkan
//! device each test prints `skipped: ...` and passes, unless
//! `MICROMAP_REQUIRE_VULKAN=1` (the CI tier), where it fails.
//!
//! The random maps come from the workspace's one PRNG
//! (`micromap_index_test_support::SplitMix64`).

use micromap_index_test_support::SplitMix64;

use micromap_index::inverse::micro_triangle;
use micromap_index::micromap::BakedOpacity;
use micromap_index::micromap::{
    Api, BuildOptions, Format, IndexWidth, Micromap, MicromapBuffers, State, TriangleOpacity,
};
use micromap_index::succinct::{LevelOrderTree, PaperTree};
use micromap_index::{spec, Level, SpecLevel};
use micromap_index_lab::vectors::{check, parse_vector_file, Answer, Answers};
use micromap_index_render::vulkan::{ComputeKernel, Device, DeviceRequest};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Set to `1` to make a missing tool or device a failure.
const REQUIRE: &str = "MICROMAP_REQUIRE_VULKAN";
/// What the shaders return for malformed input (`MMI_STATE_INVALID`).
const INVALID: u32 = 4;
/// The lookups' level range (`MMI_MAX_LEVEL`).
const MAX_LEVEL: u32 = 12;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `None` after printing why, or a panic when the environment requires the
/// device.
fn skip<T>(why: &str) -> Option<T> {
    assert!(
        std::env::var(REQUIRE).as_deref() != Ok("1"),
        "{REQUIRE}=1 but {why}"
    );
    println!("skipped: {why}");
    None
}

fn tool_runs(name: &str) -> bool {
    Command::new(name)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// The device, or `None` (said) when the tools or a device are missing.
fn setup() -> Option<Device> {
    for tool in ["glslangValidator", "spirv-val"] {
        if !tool_runs(tool) {
            return skip(&format!(
                "no `{tool}` on PATH (Debian: apt-get install glslang-tools spirv-tools)"
            ));
        }
    }
    // Any device with a compute queue: the kernels need no extension.
    match Device::open(&DeviceRequest::default()) {
        Ok(gpu) => {
            println!("device: {}", gpu.info().label());
            Some(gpu)
        }
        Err(why) => skip(&why.to_string()),
    }
}

/// SPIR-V of a compute shader: `glslangValidator -V` with `shaders/glsl` on
/// the include path, then `spirv-val`; both must accept it.
fn compile(source: &Path) -> Vec<u32> {
    // One file per compilation: tests compile the same source in parallel.
    static COMPILED: AtomicUsize = AtomicUsize::new(0);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("shaders");
    std::fs::create_dir_all(&dir).unwrap();
    let name = source.file_name().unwrap().to_str().unwrap();
    let n = COMPILED.fetch_add(1, Ordering::Relaxed);
    let out = dir.join(format!("{name}.{}.{n}.spv", std::process::id()));
    let hlsl = source.extension().is_some_and(|e| e == "hlsl");
    let folder = if hlsl { "shaders/hlsl" } else { "shaders/glsl" };
    let include = format!("-I{}", root().join(folder).display());
    let front_end: &[&str] = if hlsl {
        &["-D", "-S", "comp", "-e", "main"]
    } else {
        &[]
    };
    let compiled = Command::new("glslangValidator")
        .args(["-V", "--target-env", "vulkan1.1", &include])
        .args(front_end)
        .arg(source)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        compiled.status.success(),
        "glslangValidator {}:\n{}{}",
        source.display(),
        String::from_utf8_lossy(&compiled.stdout),
        String::from_utf8_lossy(&compiled.stderr)
    );
    let valid = Command::new("spirv-val")
        .args(["--target-env", "vulkan1.1"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        valid.status.success(),
        "spirv-val {}:\n{}{}",
        out.display(),
        String::from_utf8_lossy(&valid.stdout),
        String::from_utf8_lossy(&valid.stderr)
    );
    let spirv = words(&std::fs::read(&out).unwrap());
    let _ = std::fs::remove_file(&out);
    spirv
}

fn kernel(gpu: &Device, source: &str, bindings: usize) -> ComputeKernel {
    let spirv = compile(&root().join(source));
    gpu.compute_kernel(&spirv, bindings as u32, 16)
        .unwrap_or_else(|e| panic!("{source}: {e}"))
}

/// Little-endian words of `bytes`, zero-padded to a whole word.
fn words(bytes: &[u8]) -> Vec<u32> {
    bytes
        .chunks(4)
        .map(|c| {
            let mut w = [0u8; 4];
            w[..c.len()].copy_from_slice(c);
            u32::from_le_bytes(w)
        })
        .collect()
}

/// The 4-bit answers of a check kernel, `count` of them.
fn nibbles(packed: &[u32], count: usize) -> Vec<u32> {
    (0..count)
        .map(|i| (packed[i / 8] >> (4 * (i % 8))) & 15)
        .collect()
}

/// Runs `kernel` once: `inputs` at bindings `0..n-1`, an output of
/// `out_words` words at the last binding (zeroed first), `push` as the push
/// constants, and at least `invocations` invocations of 64-wide workgroups
/// (in two dimensions past 4,096 groups: `x + y * width`).
fn run(
    gpu: &Device,
    kernel: &ComputeKernel,
    inputs: &[&[u32]],
    out_words: usize,
    push: [u32; 4],
    invocations: u32,
) -> Result<Vec<u32>, micromap_index_render::RenderError> {
    let groups = invocations.div_ceil(64).max(1);
    let width = groups.min(4096);
    let height = groups.div_ceil(width);
    let push: Vec<u8> = push.iter().flat_map(|w| w.to_le_bytes()).collect();
    gpu.run_kernel(kernel, inputs, out_words, &push, [width, height, 1])
}

/// Runs a check kernel (push constants `start, count, a, b`) over `count`
/// answers.
fn answers(gpu: &Device, k: &ComputeKernel, inputs: &[&[u32]], push: [u32; 4]) -> Vec<u32> {
    let count = push[1] as usize;
    let invocations = count.div_ceil(8) as u32;
    let packed = run(gpu, k, inputs, count.div_ceil(8), push, invocations)
        .unwrap_or_else(|e| panic!("dispatch: {e}"));
    nibbles(&packed, count)
}

/// The first difference between two answer lists, for messages.
fn first_difference(got: &[u32], expected: &[u32]) -> Option<(usize, u32, u32)> {
    got.iter()
        .zip(expected)
        .enumerate()
        .find(|(_, (g, e))| g != e)
        .map(|(i, (&g, &e))| (i, g, e))
}

// ---------------------------------------------------------------- maps

fn state_of(format: Format, bits: u64) -> State {
    let bits = match format {
        Format::TwoState => bits & 1,
        Format::FourState => bits & 3,
    };
    State::from_bits(bits as u8).unwrap()
}

/// Random states in aligned runs of `4^k` micro-triangles (`k` 0..=3 or up
/// to the level): subtrees of every size merge.
fn runs(level: u32, format: Format, seed: u64) -> Vec<State> {
    let count = 1usize << (2 * level);
    let mut rng = SplitMix64::new(seed);
    let mut states = Vec::with_capacity(count);
    while states.len() < count {
        let k = (rng.next_u64() % 4) as u32;
        let state = state_of(format, rng.next_u64());
        // Aligned: a run of 4^k starts at a multiple of 4^k.
        let mut run = 1usize << (2 * k.min(level));
        while states.len() % run != 0 {
            run /= 4;
        }
        states.extend(std::iter::repeat(state).take(run.min(count - states.len())));
    }
    states
}

/// Independent random states (no merging to speak of).
fn noise(level: u32, format: Format, seed: u64) -> Vec<State> {
    let mut rng = SplitMix64::new(seed);
    (0..1usize << (2 * level))
        .map(|_| state_of(format, rng.next_u64()))
        .collect()
}

/// Opaque inside a disc of radius 0.3 around `(1/3, 1/3)`; in 4-state maps
/// micro-triangles with vertices on both sides are unknown-opaque.
fn disc(level: u32, format: Format) -> Vec<State> {
    let inside = |(u, v): (f64, f64)| {
        let (du, dv) = (u - 1.0 / 3.0, v - 1.0 / 3.0);
        du * du + dv * dv <= 0.09
    };
    let level_n = Level::new(level).unwrap();
    (0..1u64 << (2 * level))
        .map(|i| {
            let t = micro_triangle(level_n, i).unwrap();
            match format {
                Format::TwoState => state_of(format, u64::from(inside(t.centroid_f64()))),
                Format::FourState => {
                    match t.vertices_f64().into_iter().filter(|&p| inside(p)).count() {
                        0 => State::Transparent,
                        3 => State::Opaque,
                        _ => State::UnknownOpaque,
                    }
                }
            }
        })
        .collect()
}

/// The paper's worst case: the states in turn along the curve.
fn alternating(level: u32, format: Format) -> Vec<State> {
    let period = 2 * format.bits_per_state() as usize;
    (0..1usize << (2 * level))
        .map(|i| State::ALL[i % period])
        .collect()
}

/// The maps of one level and format: named, random and structured. Levels
/// above 8 leave out pure noise (its trees are as large as the map and it
/// adds nothing the run-length maps do not), levels above 10 keep two maps.
fn maps(level: u32, format: Format) -> Vec<(&'static str, Vec<State>)> {
    let seed = 0x5eed_0000 + u64::from(level) * 8 + u64::from(format.raw());
    let mut maps = vec![
        ("runs", runs(level, format, seed)),
        ("disc", disc(level, format)),
        ("alternating", alternating(level, format)),
        (
            "uniform",
            vec![state_of(format, u64::from(level) + 1); 1 << (2 * level)],
        ),
    ];
    if level <= 8 {
        maps.push(("noise", noise(level, format, seed ^ 0xff)));
    }
    if level > 10 {
        // Levels 11 and 12 (16.7 million micro-triangles): the random and
        // the disc map, which keep every tree depth busy; the uniform and
        // alternating shapes are the same at every level.
        maps.truncate(2);
    }
    maps
}

fn bits(state: Option<State>) -> u32 {
    state.map_or(INVALID, |s| u32::from(s.bits()))
}

// ------------------------------------------------- level-order host data

// The rank directory and top table `level_order_tree.glsl` reads, built as
// the renderer builds them (one implementation).
use micromap_index_render::tables::{rank_directory, top_table};

// ---------------------------------------------------------------- tests

/// The two languages of the shader library: each has its check kernels in
/// `crates/lab/tests/shaders/`. The HLSL twins include the same sources, so
/// they are checked on fewer levels (0..=9) to keep the test short.
#[derive(Clone, Copy, Debug)]
enum Lang {
    Glsl,
    Hlsl,
}

impl Lang {
    const ALL: [Lang; 2] = [Lang::Glsl, Lang::Hlsl];

    fn kernel(self, name: &str) -> String {
        match self {
            Lang::Glsl => format!("crates/lab/tests/shaders/{name}.comp"),
            Lang::Hlsl => format!("crates/lab/tests/shaders/{name}.hlsl"),
        }
    }

    fn index_driver(self) -> &'static str {
        match self {
            Lang::Glsl => "reference/drivers/glsl/spec_f32.comp",
            Lang::Hlsl => "crates/lab/tests/shaders/spec_f32.hlsl",
        }
    }

    fn max_level(self) -> u32 {
        match self {
            Lang::Glsl => MAX_LEVEL,
            Lang::Hlsl => 9,
        }
    }
}

#[test]
fn index_function_passes_the_spec_f32_vectors() {
    let Some(gpu) = setup() else { return };
    for lang in Lang::ALL {
        index_function_on_vectors(&gpu, lang);
    }
}

fn index_function_on_vectors(gpu: &Device, lang: Lang) {
    let path = root().join("reference/vectors/spec-f32.json");
    let vectors = parse_vector_file(&std::fs::read(&path).unwrap()).unwrap();
    assert_eq!(vectors.function, "spec-f32");
    let hex = |s: &str| u32::from_str_radix(s.strip_prefix("0x").unwrap(), 16).unwrap();
    let mut cases = Vec::new();
    for c in &vectors.cases {
        cases.extend([hex(&c.u), hex(&c.v), c.level, 0]);
    }
    let count = vectors.cases.len() as u32;
    // The conformance driver itself (it includes
    // shaders/glsl/micromap_index.glsl), or its HLSL twin.
    let k = kernel(gpu, lang.index_driver(), 2);
    // One dimension: the driver indexes by gl_GlobalInvocationID.x only.
    assert!(count.div_ceil(64) <= 4096);
    let indices = run(gpu, &k, &[&cases], count as usize, [count, 0, 0, 0], count).unwrap();
    drop(k);
    let mut by_id = BTreeMap::new();
    for (c, &index) in vectors.cases.iter().zip(&indices) {
        let (u, v) = (f32::from_bits(hex(&c.u)), f32::from_bits(hex(&c.v)));
        let library = spec::index_f32(u, v, SpecLevel::new(c.level).unwrap());
        assert_eq!(
            (index, u64::from(index)),
            (library, c.index),
            "case {} level {}: u {} v {}",
            c.id,
            c.level,
            c.u,
            c.v
        );
        by_id.insert(c.id, Answer::Index(u64::from(index)));
    }
    let report = check(&vectors, &Answers { by_id });
    assert!(report.passed(), "{report:?}");
    println!(
        "{}: {} of {} spec-f32 cases match on {}",
        lang.index_driver(),
        report.matched,
        report.cases,
        gpu.info().label()
    );
}

#[test]
fn flat_lookup_agrees_with_the_micromap_buffers() {
    let Some(gpu) = setup() else { return };
    for lang in Lang::ALL {
        flat_lookup_on_maps(&gpu, lang);
    }
}

fn flat_lookup_on_maps(gpu: &Device, lang: Lang) {
    let k = kernel(gpu, &lang.kernel("flat_lookup"), 4);
    let mut lookups = 0usize;
    for level in 0..=lang.max_level() {
        let level_n = Level::new(level).unwrap();
        let mut all = Vec::new();
        for format in [Format::TwoState, Format::FourState] {
            for (name, states) in maps(level, format) {
                all.push((
                    name,
                    Micromap::from_states(level_n, format, states.iter().copied()).unwrap(),
                ));
            }
        }
        let mut triangles: Vec<TriangleOpacity<'_>> = all
            .iter()
            .map(|(_, m)| TriangleOpacity::Micromap(m))
            .collect();
        // A repeated map (deduplicated to one record) and the four specials.
        triangles.push(TriangleOpacity::Micromap(&all[0].1));
        triangles.extend(State::ALL.map(TriangleOpacity::Special));
        let buffers = MicromapBuffers::build(
            triangles.iter().copied(),
            BuildOptions {
                uniform_to_special: false,
                ..BuildOptions::default()
            },
        )
        .unwrap();
        let data = words(buffers.data());
        let records = words(&buffers.records_le_bytes());
        // Wider indices at every level, 8-bit ones where the records fit.
        let widths: &[IndexWidth] = if level % 3 == 0 && level < 12 {
            &[IndexWidth::U8, IndexWidth::U16, IndexWidth::U32]
        } else {
            &[IndexWidth::U32]
        };
        for &width in widths {
            let indices = words(&buffers.index_bytes(0, width).unwrap());
            for t in 0..triangles.len() {
                let resolved = buffers.resolve(0, t).unwrap();
                let expected_of = |i: u64| match &resolved {
                    BakedOpacity::Map(m) => bits(m.get(i)),
                    BakedOpacity::Special(s) => u32::from(s.bits()),
                };
                // Every micro-triangle and eight past the end.
                let count = (1usize << (2 * level)) + 8;
                let push = [0, count as u32, t as u32, width.bytes() as u32];
                let got = answers(gpu, &k, &[&data, &records, &indices], push);
                let expected: Vec<u32> = (0..count as u64).map(expected_of).collect();
                if let Some((i, g, e)) = first_difference(&got, &expected) {
                    let name = all.get(t).map_or("special or repeat", |m| m.0);
                    panic!("level {level} triangle {t} ({name}) {width}: micro-triangle {i}: shader {g}, library {e}");
                }
                lookups += count;
            }
            // Past the last triangle: invalid, never a read out of bounds.
            let past = (indices.len() * 4 / width.bytes()) as u32;
            let push = [0, 8, past, width.bytes() as u32];
            let got = answers(gpu, &k, &[&data, &records, &indices], push);
            assert_eq!(got, [INVALID; 8], "level {level} {width}: triangle {past}");
        }
    }
    drop(k);
    println!(
        "{lang:?} flat lookup: {lookups} lookups match, levels 0..={}, both formats",
        lang.max_level()
    );
}

#[test]
fn flat_lookup_of_malformed_buffers_is_invalid() {
    let Some(gpu) = setup() else { return };
    for lang in Lang::ALL {
        flat_lookup_of_malformed(&gpu, lang);
    }
}

fn flat_lookup_of_malformed(gpu: &Device, lang: Lang) {
    let k = kernel(gpu, &lang.kernel("flat_lookup"), 4);
    let record = |offset: u32, level: u32, format: u32| [offset, level | format << 16];
    // Records: 0 fine (level 1, 4-state, 1 byte at 0), 1 level 13, 2 format
    // 3, 3 format 0, 4 data past the buffer's end, 5 level 2 2-state at 3
    // (2 bytes, one past the 4-byte buffer).
    let records: Vec<u32> = [
        record(0, 1, 2),
        record(0, 13, 1),
        record(0, 1, 3),
        record(0, 1, 0),
        record(4, 1, 2),
        record(3, 2, 1),
    ]
    .concat();
    let data = [0b1110_0100u32];
    let expect = |indices: &[u32], width: u32, triangle: u32, expected: &[u32]| {
        let push = [0, expected.len() as u32, triangle, width];
        let got = answers(gpu, &k, &[&data, &records, indices], push);
        assert_eq!(got, expected, "{lang:?}: triangle {triangle} width {width}");
    };
    let u32s: Vec<u32> = (0..6).chain([0xffff_fffb, 6, 0xffff_fffc]).collect();
    // The good record: states 0, 1, 2, 3, then invalid past 4^1.
    expect(&u32s, 4, 0, &[0, 1, 2, 3, INVALID]);
    for bad in 1..=5 {
        expect(&u32s, 4, bad, &[INVALID; 4]);
    }
    // -5 (reserved), a record past the end, -4 (a special index).
    expect(&u32s, 4, 6, &[INVALID; 2]);
    expect(&u32s, 4, 7, &[INVALID; 2]);
    expect(&u32s, 4, 8, &[3; 2]);
    // Past the index buffer; index widths other than 1, 2, 4.
    expect(&u32s, 4, 9, &[INVALID; 2]);
    for width in [0, 3, 5, 8] {
        expect(&u32s, width, 0, &[INVALID; 2]);
    }
    // 16-bit: 0xfffb is -5, 0xfffe is -2; 8-bit: 0xfb, 0xfd.
    expect(&[0xfffe_fffb], 2, 0, &[INVALID; 2]);
    expect(&[0xfffe_fffb], 2, 1, &[1; 2]);
    expect(&[0x00fd_00fb], 1, 0, &[INVALID; 2]);
    expect(&[0x00fd_00fb], 1, 2, &[2; 2]);
    expect(&[0x00fd_00fb], 1, 1, &[0, 1, 2, 3, INVALID]);
    drop(k);
}

#[test]
fn tree_lookups_agree_with_the_library() {
    let Some(gpu) = setup() else { return };
    for lang in Lang::ALL {
        tree_lookups_on_maps(&gpu, lang);
    }
}

fn tree_lookups_on_maps(gpu: &Device, lang: Lang) {
    let lot = kernel(gpu, &lang.kernel("level_order_lookup"), 4);
    let paper_k = kernel(gpu, &lang.kernel("paper_lookup"), 3);
    let (mut lot_lookups, mut paper_lookups) = (0usize, 0usize);
    let mut paper_skipped = Vec::new();
    for level in 0..=lang.max_level() {
        let level_n = Level::new(level).unwrap();
        for format in [Format::TwoState, Format::FourState] {
            for (name, states) in maps(level, format) {
                let what = format!("{lang:?} level {level} {format:?} {name}");
                let count = (1usize << (2 * level)) + 8;
                let tree = LevelOrderTree::encode(level_n, format, &states).unwrap();
                let expected: Vec<u32> = (0..count as u64).map(|i| bits(tree.get(i))).collect();
                for (i, &s) in states.iter().enumerate() {
                    assert_eq!(expected[i], u32::from(s.bits()), "{what}: library at {i}");
                }
                let bytes = words(&tree.to_bytes());
                let directory = rank_directory(&tree.to_bytes());
                let mut depths = vec![0, tree.top_depth(), 7.min(level.saturating_sub(1))];
                depths.dedup();
                if level > 10 {
                    // The largest maps: the library's table only (the
                    // others are covered below).
                    depths = vec![tree.top_depth()];
                }
                for depth in depths {
                    let (top, top_start) = top_table(&tree.to_bytes(), depth);
                    let push = [0, count as u32, depth, top_start];
                    let got = answers(gpu, &lot, &[&bytes, &directory, &top], push);
                    if let Some((i, g, e)) = first_difference(&got, &expected) {
                        panic!("{what}, top depth {depth}: index {i}: shader {g}, library {e}");
                    }
                    lot_lookups += count;
                }

                let paper = PaperTree::encode(level_n, format, &states).unwrap();
                let paper_bytes = words(&paper.to_bytes());
                let list: Vec<u32> = if level <= 6 {
                    (0..count as u32).collect()
                } else if paper.tree_bits() <= 1 << 17 {
                    let mut rng = SplitMix64::new(u64::from(level) << 8 | u64::from(format.raw()));
                    let n = 1u64 << (2 * level);
                    (0..512)
                        .map(|_| (rng.next_u64() % n) as u32)
                        .chain([0, n as u32 - 1, n as u32])
                        .collect()
                } else {
                    paper_skipped.push(what);
                    continue;
                };
                let push = [0, list.len() as u32, 1, 0];
                let got = answers(gpu, &paper_k, &[&paper_bytes, &list], push);
                for (&i, &g) in list.iter().zip(&got) {
                    let library = bits(paper.get(u64::from(i)));
                    assert_eq!(g, library, "{what}: paper tree, index {i}");
                    if let Some(&e) = expected.get(i as usize) {
                        assert_eq!(library, e, "{what}: paper tree and level order at {i}");
                    }
                }
                paper_lookups += list.len();
            }
        }
    }
    // Malformed bytes: every lookup invalid, none out of bounds.
    let states = runs(4, Format::FourState, 7);
    let tree = LevelOrderTree::encode(Level::new(4).unwrap(), Format::FourState, &states).unwrap();
    let good = tree.to_bytes();
    let directory = rank_directory(&good);
    let paper = PaperTree::encode(Level::new(4).unwrap(), Format::FourState, &states)
        .unwrap()
        .to_bytes();
    let broken = |bytes: &[u8], at: usize, value: u8| {
        let mut b = bytes.to_vec();
        b[at] = value;
        words(&b)
    };
    for (why, lot_bytes, paper_bytes) in [
        ("magic", broken(&good, 0, b'X'), broken(&paper, 0, b'X')),
        ("version", broken(&good, 4, 2), broken(&paper, 4, 2)),
        ("layout", broken(&good, 5, 0), broken(&paper, 5, 1)),
        ("level 13", broken(&good, 6, 13), broken(&paper, 6, 13)),
        ("format 3", broken(&good, 7, 3), broken(&paper, 7, 3)),
        (
            "tree_bits high",
            broken(&good, 12, 1),
            broken(&paper, 12, 1),
        ),
        (
            "truncated",
            words(&good[..good.len() - 8]),
            words(&paper[..paper.len() - 8]),
        ),
        ("header only", words(&good[..20]), words(&paper[..20])),
    ] {
        let push = [0, 256, 0, 0];
        let got = answers(gpu, &lot, &[&lot_bytes, &directory, &[]], push);
        assert!(
            got.iter().all(|&s| s == INVALID),
            "{lang:?} level order, {why}: {got:?}"
        );
        let got = answers(gpu, &paper_k, &[&paper_bytes, &[]], [0, 256, 0, 0]);
        assert!(
            got.iter().all(|&s| s == INVALID),
            "{lang:?} paper tree, {why}: {got:?}"
        );
    }
    // A top depth the level does not allow, and a missing table.
    let got = answers(gpu, &lot, &[&words(&good), &directory, &[]], [0, 256, 4, 0]);
    assert!(got.iter().all(|&s| s == INVALID), "top depth 4 at level 4");
    // (A one-word table of zeros: prefixes 0 and 1 read it, the others
    // are missing.)
    let got = answers(gpu, &lot, &[&words(&good), &directory, &[]], [0, 256, 2, 5]);
    assert!(got[32..].iter().all(|&s| s == INVALID), "top table missing");
    drop(lot);
    drop(paper_k);
    println!(
        "{lang:?} level-order tree: {lot_lookups} lookups match; paper tree: {paper_lookups} match \
         (every index up to level 6, 515 sampled above where the tree has at most 2^17 bits; \
         not run on {} larger trees)",
        paper_skipped.len()
    );
}

/// Every byte of small trees' bytes replaced by a few values: the shaders
/// answer in `0..=4` for every index, and exactly as the library wherever
/// the library accepts the changed bytes.
#[test]
fn tree_lookups_of_changed_bytes() {
    let Some(gpu) = setup() else { return };
    let lot = kernel(&gpu, &Lang::Glsl.kernel("level_order_lookup"), 4);
    let paper_k = kernel(&gpu, &Lang::Glsl.kernel("paper_lookup"), 3);
    let (mut accepted, mut rejected) = (0, 0);
    for (level, format, seed) in [(3, Format::FourState, 11), (5, Format::TwoState, 12)] {
        let level_n = Level::new(level).unwrap();
        let states = runs(level, format, seed);
        let count = (1u32 << (2 * level)) + 8;
        let trees = [
            LevelOrderTree::encode(level_n, format, &states)
                .unwrap()
                .to_bytes(),
            PaperTree::encode(level_n, format, &states)
                .unwrap()
                .to_bytes(),
        ];
        for (layout, good) in trees.iter().enumerate() {
            for at in 0..good.len() {
                for value in [good[at] ^ 1, good[at] ^ 0x80, 0xff, 0] {
                    if value == good[at] {
                        continue;
                    }
                    let mut bytes = good.clone();
                    bytes[at] = value;
                    let library: Option<Vec<u32>> = if layout == 0 {
                        LevelOrderTree::from_bytes(&bytes)
                            .ok()
                            .map(|t| (0..u64::from(count)).map(|i| bits(t.get(i))).collect())
                    } else {
                        PaperTree::from_bytes(&bytes)
                            .ok()
                            .map(|t| (0..u64::from(count)).map(|i| bits(t.get(i))).collect())
                    };
                    let got = if layout == 0 {
                        // The directory of the changed bits where the header
                        // still describes them, else the original one.
                        let tree_bits = u64::from_le_bytes(bytes[8..16].try_into().unwrap());
                        let fits = 24 + tree_bits.div_ceil(8) <= bytes.len() as u64;
                        let directory = rank_directory(if fits { &bytes } else { good });
                        answers(
                            &gpu,
                            &lot,
                            &[&words(&bytes), &directory, &[]],
                            [0, count, 0, 0],
                        )
                    } else {
                        answers(&gpu, &paper_k, &[&words(&bytes), &[]], [0, count, 0, 0])
                    };
                    assert!(
                        got.iter().all(|&s| s <= INVALID),
                        "layout {layout} byte {at} = {value:#x}"
                    );
                    if let Some(library) = library {
                        assert_eq!(got, library, "layout {layout} byte {at} = {value:#x}");
                        accepted += 1;
                    } else {
                        rejected += 1;
                    }
                }
            }
        }
    }
    drop(lot);
    drop(paper_k);
    println!(
        "changed tree bytes: {accepted} accepted by the library and answered alike, \
         {rejected} rejected (shader answers in 0..=4)"
    );
}

/// The numbers in `micromap_constants.glsl` (its `#define` lines) equal the
/// library's.
#[test]
fn shader_constants_equal_the_rust_constants() {
    let path = root().join("shaders/glsl/micromap_constants.glsl");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut defined = BTreeMap::new();
    for line in text.lines() {
        let Some(rest) = line.strip_prefix("#define ") else {
            continue;
        };
        let mut parts = rest.split_whitespace();
        let (Some(name), Some(value)) = (parts.next(), parts.next()) else {
            continue;
        };
        let value = value.trim_start_matches('(').trim_end_matches(')');
        let value = value.strip_suffix('u').unwrap_or(value);
        let parsed = if let Some(hex) = value.strip_prefix("0x") {
            i64::from_str_radix(hex, 16).unwrap()
        } else {
            value.parse::<i64>().unwrap()
        };
        defined.insert(name.to_owned(), parsed);
    }
    let get = |name: &str| {
        *defined
            .get(name)
            .unwrap_or_else(|| panic!("{name} not defined in {}", path.display()))
    };
    for (name, state) in [
        ("TRANSPARENT", State::Transparent),
        ("OPAQUE", State::Opaque),
        ("UNKNOWN_TRANSPARENT", State::UnknownTransparent),
        ("UNKNOWN_OPAQUE", State::UnknownOpaque),
    ] {
        assert_eq!(get(&format!("MMI_STATE_{name}")), i64::from(state.bits()));
        assert_eq!(
            get(&format!("MMI_SPECIAL_INDEX_{name}")),
            i64::from(state.special_index())
        );
    }
    assert!(State::from_bits(get("MMI_STATE_INVALID") as u8).is_none());
    assert_eq!(get("MMI_STATE_INVALID"), i64::from(INVALID));
    assert_eq!(get("MMI_FORMAT_2_STATE"), i64::from(Format::TwoState.raw()));
    assert_eq!(
        get("MMI_FORMAT_4_STATE"),
        i64::from(Format::FourState.raw())
    );
    // Format numbers are the bits per state (the shaders rely on it).
    for format in [Format::TwoState, Format::FourState] {
        assert_eq!(u32::from(format.raw()), format.bits_per_state());
    }
    // -5 is the reserved pattern: not a special index, not a record.
    assert!(State::from_special_index(get("MMI_SPECIAL_INDEX_RESERVED") as i32).is_none());
    assert_eq!(
        micromap_index::micromap::MicromapIndex::decode(0xffff_fffb, IndexWidth::U32),
        None
    );
    assert_eq!(get("MMI_MAX_LEVEL"), i64::from(MAX_LEVEL));
    assert_eq!(Api::Dxr.max_level(), Some(MAX_LEVEL));

    // The byte format, read off the trees' own bytes.
    let level = Level::new(6).unwrap();
    let states = runs(6, Format::FourState, 3);
    let lot = LevelOrderTree::encode(level, Format::FourState, &states).unwrap();
    let paper = PaperTree::encode(level, Format::FourState, &states).unwrap();
    for (bytes, layout) in [
        (lot.to_bytes(), get("MMI_TREE_LAYOUT_LEVEL_ORDER")),
        (paper.to_bytes(), get("MMI_TREE_LAYOUT_PAPER")),
    ] {
        assert_eq!(
            i64::from(u32::from_le_bytes(bytes[..4].try_into().unwrap())),
            get("MMI_TREE_MAGIC")
        );
        assert_eq!(i64::from(bytes[4]), get("MMI_TREE_VERSION"));
        assert_eq!(i64::from(bytes[5]), layout);
        assert_eq!(4 * get("MMI_TREE_HEADER_WORDS"), 24);
    }
    // The rank directory: one u64 per block of MMI_RANK_BLOCK_BITS bits
    // (past 128 bits), as the library counts it.
    let bare = lot.clone().with_top_depth(0);
    let block = get("MMI_RANK_BLOCK_BITS") as u64;
    assert!(bare.internal_bits() > 128);
    assert_eq!(
        bare.directory_bits(),
        64 * bare.internal_bits().div_ceil(block)
    );
    assert_eq!(
        rank_directory(&lot.to_bytes()).len() as u64,
        2 * bare.internal_bits().div_ceil(block)
    );
    // The top table's deepest depth, and its leaf mark (bit 15 of an entry
    // that can never be an offset below 4^7).
    let deep = Level::new(12).unwrap();
    let big =
        LevelOrderTree::encode(deep, Format::TwoState, &runs(12, Format::TwoState, 5)).unwrap();
    assert_eq!(
        i64::from(big.with_top_depth(99).top_depth()),
        get("MMI_TOP_MAX_DEPTH")
    );
    assert_eq!(get("MMI_TOP_LEAF"), 1 << 15);
    assert!(4i64.pow(get("MMI_TOP_MAX_DEPTH") as u32) <= get("MMI_TOP_LEAF"));
}
