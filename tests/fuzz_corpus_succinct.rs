//! Replays the `succinct_tree` fuzz target's committed inputs on stable
//! (feature `fuzzing`): every file of `fuzz/corpus/succinct_tree/` and
//! `fuzz/regressions/succinct_tree/` goes through
//! `micromap_index::succinct::fuzzing::succinct_tree`, and every seed that
//! is a tree's bytes is accepted by the reader of its layout (the seeds are
//! written by an independent encoder, `fuzz/seeds/make_succinct_seeds.py`).
#![cfg(feature = "fuzzing")]

use micromap_index::succinct::fuzzing::succinct_tree;
use micromap_index::succinct::{LevelOrderTree, PaperTree};
use std::fs;
use std::path::{Path, PathBuf};

fn inputs(kind: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fuzz")
        .join(kind)
        .join("succinct_tree");
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

#[test]
fn succinct_tree_corpus() {
    let corpus = inputs("corpus");
    assert!(
        !corpus.is_empty(),
        "fuzz/corpus/succinct_tree/ is missing or empty"
    );
    let regressions = inputs("regressions");
    for path in corpus.iter().chain(&regressions) {
        let data = fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let outcome = std::panic::catch_unwind(|| succinct_tree(&data));
        if let Err(panic) = outcome {
            eprintln!("failing input: {}", path.display());
            std::panic::resume_unwind(panic);
        }
    }
    eprintln!(
        "succinct_tree: replayed {} corpus and {} regression inputs",
        corpus.len(),
        regressions.len()
    );
}

/// The independent encoder's bytes are what this crate writes.
#[test]
fn seeds_from_the_python_encoder_are_accepted() {
    let mut trees = 0;
    for path in inputs("corpus") {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let data = fs::read(&path).unwrap();
        if name.starts_with("seed-paper-") {
            let tree = PaperTree::from_bytes(&data).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(tree.to_bytes(), data, "{name}");
            trees += 1;
        } else if name.starts_with("seed-level-order-") {
            let tree = LevelOrderTree::from_bytes(&data).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(tree.to_bytes(), data, "{name}");
            trees += 1;
        }
    }
    assert_eq!(trees, 12, "the six maps in both layouts");
}
