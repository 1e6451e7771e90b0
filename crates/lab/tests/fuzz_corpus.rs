//! Replays the fuzz targets' committed inputs on stable (feature `fuzzing`):
//! every file of `fuzz/corpus/<target>/` (the seed corpus, minimized after
//! each campaign), of `fuzz/seeds/<target>/` (hand-made seeds of the asset
//! targets, written by `fuzz/seeds/make_asset_seeds.py`) and of
//! `fuzz/regressions/<target>/` (inputs that once failed) goes through the
//! target's body in `micromap_index_lab::fuzzing`.
//! `docs/fuzzing.md` describes the targets and the campaigns.
//!
//! The `spec_vs_mirror` replay also compares the C reference, as the fuzz
//! target does (the oracle is a dev-dependency here).

use micromap_index_c_reference::spec_index;
use micromap_index_lab::fuzzing;
use std::fs;
use std::path::{Path, PathBuf};

/// The files of `fuzz/<kind>/<target>/`, sorted; none if the directory does
/// not exist.
fn inputs(kind: &str, target: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join("fuzz")
        .join(kind)
        .join(target);
    let Ok(entries) = fs::read_dir(&dir) else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = entries
        .map(|entry| entry.expect("readable directory entry").path())
        .filter(|path| path.is_file())
        .collect();
    files.sort();
    files
}

/// Runs `body` on every corpus and regression input of `target`; the corpus
/// must not be empty.
fn replay(target: &str, body: impl Fn(&[u8])) {
    let corpus = inputs("corpus", target);
    assert!(
        !corpus.is_empty(),
        "fuzz/corpus/{target}/ is missing or empty"
    );
    run_all(target, &corpus, body);
}

/// Runs `body` on every seed (`fuzz/seeds/<target>/`, which must not be
/// empty), corpus and regression input of `target`.
fn replay_seeds(target: &str, body: impl Fn(&[u8])) {
    let seeds = inputs("seeds", target);
    assert!(
        !seeds.is_empty(),
        "fuzz/seeds/{target}/ is missing or empty"
    );
    let mut files = seeds;
    files.extend(inputs("corpus", target));
    run_all(target, &files, body);
}

/// Runs `body` on `files` and on the regression inputs of `target`.
fn run_all(target: &str, files: &[PathBuf], body: impl Fn(&[u8])) {
    let regressions = inputs("regressions", target);
    for path in files.iter().chain(&regressions) {
        let data = fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| body(&data)));
        if let Err(panic) = outcome {
            eprintln!("failing input: {}", path.display());
            std::panic::resume_unwind(panic);
        }
    }
    eprintln!(
        "{target}: replayed {} corpus (and seed) and {} regression inputs",
        files.len(),
        regressions.len()
    );
}

#[test]
fn spec_vs_mirror() {
    replay("spec_vs_mirror", |data| {
        fuzzing::spec_vs_mirror(data).assert_agrees("the C reference", spec_index);
    });
}

#[test]
fn exact_walk_vs_fixed() {
    replay("exact_walk_vs_fixed", fuzzing::exact_walk_vs_fixed);
}

#[test]
fn inverse_round_trip() {
    replay("inverse_round_trip", fuzzing::inverse_round_trip);
}

#[test]
fn eval_input() {
    replay("eval_input", fuzzing::eval_input);
}

#[test]
fn vector_reader() {
    replay("vector_reader", fuzzing::vector_reader);
}

#[test]
fn micromap_buffers() {
    replay(
        "micromap_buffers",
        micromap_index_lab::fuzzing::micromap_buffers,
    );
}

#[test]
fn strided_buffers() {
    replay("strided_buffers", fuzzing::strided_buffers);
}

#[test]
fn succinct_tree() {
    replay("succinct_tree", fuzzing::succinct_tree);
}

#[test]
fn alpha_image() {
    replay_seeds("alpha_image", fuzzing::alpha_image);
}

#[test]
fn triangles_json() {
    replay_seeds("triangles_json", fuzzing::triangles_json);
}

#[test]
fn gltf_asset() {
    replay_seeds("gltf_asset", fuzzing::gltf_asset);
}

#[test]
fn bake_budgets() {
    replay("bake_budgets", fuzzing::bake_budgets);
}

#[test]
fn bake_transformed() {
    replay("bake_transformed", fuzzing::bake_transformed);
}

#[test]
fn bake_vertex_alpha() {
    replay("bake_vertex_alpha", fuzzing::bake_vertex_alpha);
}

#[test]
fn texel_tables_within() {
    replay("texel_tables_within", fuzzing::texel_tables_within);
}
