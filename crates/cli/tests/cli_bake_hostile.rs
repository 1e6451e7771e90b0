//! `bake` and `verify-bake` under hostile use (issue 26): concurrent bakes
//! into one directory, Ctrl-C, stale outputs, failed bakes, closed or full
//! stdout, oversized inputs, incomplete or garbage layouts, bounded reports.

mod common;

use common::HANG;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Duration;

const ASSETS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/crytek-sponza");
const BIN: &str = env!("CARGO_BIN_EXE_micromap-index");

fn run(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .output()
        .expect("the binary runs")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "micromap-bake-hostile-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn texture() -> String {
    format!("{ASSETS}/chain.png")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    names
}

/// Two triangle files whose bakes differ in every output.
fn two_inputs(dir: &Path) -> [PathBuf; 2] {
    let a = dir.join("a.json");
    let b = dir.join("b.json");
    std::fs::write(
        &a,
        r#"{"triangles": [[[0, 0], [1, 0], [0, 0.25]], [[0.1, 0.3], [0.9, 0.35], [0.5, 0.9]]]}"#,
    )
    .unwrap();
    std::fs::write(
        &b,
        r#"{"triangles": [[[0, 0], [0.5, 0], [0, 0.5]], [[0.2, 0.2], [0.7, 0.3], [0.4, 0.8]], [[0, 0], [1, 1], [0, 1]]]}"#,
    )
    .unwrap();
    [a, b]
}

fn bake_args<'a>(tris: &'a Path, out: &'a Path, extra: &[&'a str]) -> Vec<String> {
    let mut args: Vec<String> = [
        "bake",
        "--texture",
        &texture(),
        "--triangles",
        tris.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--level",
        "4",
        "--quiet",
    ]
    .iter()
    .map(|s| (*s).to_owned())
    .collect();
    args.extend(extra.iter().map(|s| (*s).to_owned()));
    args
}

/// The outputs of a bake with the timings taken out of the summary.
fn outputs(dir: &Path) -> Vec<(String, Vec<u8>)> {
    listing(dir)
        .into_iter()
        .map(|name| {
            let bytes = std::fs::read(dir.join(&name)).unwrap();
            if name == "summary.json" {
                let mut summary: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
                let map = summary.as_object_mut().unwrap();
                for key in [
                    "bake_seconds",
                    "micro_triangles_per_second",
                    "preview_seconds",
                ] {
                    map.remove(key);
                }
                (name, summary.to_string().into_bytes())
            } else {
                (name, bytes)
            }
        })
        .collect()
}

/// Two bakes of different inputs started together into one `--out`, many
/// times: exactly one succeeds, the other is refused (exit 3 while the
/// first holds the directory, exit 2 once it has finished), and the
/// directory always holds one bake's complete output, never a mix. Before
/// the lock, both often exited 0 and the directory could mix the two.
#[test]
fn concurrent_bakes_into_one_directory_never_mix() {
    let dir = scratch("concurrent");
    let inputs = two_inputs(&dir);
    let references: Vec<_> = inputs
        .iter()
        .enumerate()
        .map(|(i, tris)| {
            let out = dir.join(format!("reference-{i}"));
            let done = Command::new(BIN)
                .args(bake_args(tris, &out, &[]))
                .output()
                .unwrap();
            assert_eq!(done.status.code(), Some(0), "{}", stderr(&done));
            outputs(&out)
        })
        .collect();
    assert_ne!(references[0], references[1]);
    let mut locked = 0;
    for round in 0..40 {
        let out = dir.join(format!("race-{round}"));
        let children: Vec<_> = inputs
            .iter()
            .map(|tris| {
                Command::new(BIN)
                    .args(bake_args(tris, &out, &[]))
                    .stdout(Stdio::null())
                    .stderr(Stdio::piped())
                    .spawn()
                    .unwrap()
            })
            .collect();
        let results: Vec<Output> = children
            .into_iter()
            .map(|c| c.wait_with_output().unwrap())
            .collect();
        let codes: Vec<Option<i32>> = results.iter().map(|r| r.status.code()).collect();
        let winners: Vec<usize> = (0..2).filter(|&i| codes[i] == Some(0)).collect();
        assert_eq!(
            winners.len(),
            1,
            "round {round}: exit codes {codes:?}: {} / {}",
            stderr(&results[0]),
            stderr(&results[1])
        );
        let loser = &results[1 - winners[0]];
        match loser.status.code() {
            Some(3) => {
                locked += 1;
                assert!(
                    stderr(loser).contains("is in use by another bake"),
                    "{}",
                    stderr(loser)
                );
            }
            Some(2) => assert!(
                stderr(loser).contains("exists; nothing written"),
                "{}",
                stderr(loser)
            ),
            other => panic!(
                "round {round}: the second bake exited {other:?}: {}",
                stderr(loser)
            ),
        }
        assert_eq!(
            outputs(&out),
            references[winners[0]],
            "round {round}: a mix"
        );
    }
    eprintln!("{locked} of 40 rounds refused by the lock");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The directory's files and their bytes.
fn contents(dir: &Path) -> Vec<(String, Vec<u8>)> {
    listing(dir)
        .into_iter()
        .map(|n| {
            let bytes = std::fs::read(dir.join(&n)).unwrap();
            (n, bytes)
        })
        .collect()
}

/// A bake of `args` held (by the test hook) `at` a phase for 20 s.
fn stalled(args: &[String], at: &str) -> std::process::Child {
    Command::new(BIN)
        .args(args)
        .env("MICROMAP_INDEX_TEST_STALL_MS", "20000")
        .env("MICROMAP_INDEX_TEST_STALL_AT", at)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// The pause between two looks at a directory in [`wait_for`].
const POLL: Duration = Duration::from_millis(10);

/// Waits until `ready` holds for `dir`'s listing (none while `dir` does
/// not exist) and returns that listing. The hang guard counts looks, not
/// time: `HANG / POLL` of them take at least `HANG` however busy the
/// machine, so only a bake that never gets there fails it.
fn wait_for(dir: &Path, ready: impl Fn(&[String]) -> bool) -> Vec<String> {
    let looks = HANG.as_millis() / POLL.as_millis();
    let mut names = Vec::new();
    for _ in 0..looks {
        names = if dir.exists() {
            listing(dir)
        } else {
            Vec::new()
        };
        if ready(&names) {
            return names;
        }
        std::thread::sleep(POLL);
    }
    panic!("{} never got ready: {names:?}", dir.display());
}

fn signal(child: &std::process::Child, signal: &str) {
    let sent = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
}

/// A lock held by a running bake refuses a second bake (exit 3, naming the
/// holder); once the holder is killed (`kill -9`, 8 of 8 runs locked the
/// directory for good before), the next bake takes the dead lock over and
/// undoes the half-done renames from the lock file's journal: the
/// directory holds the old set again, no temporary, backup or lock left;
/// and a later `--force` bake succeeds.
#[test]
fn a_killed_bake_locks_nothing_and_is_undone_by_the_next() {
    let dir = scratch("killed");
    let [a, b] = two_inputs(&dir);
    let out = dir.join("out");
    let first = run_strings(&bake_args(&a, &out, &[]));
    assert_eq!(first.status.code(), Some(0), "{}", stderr(&first));
    let before = contents(&out);
    let mut child = stalled(&bake_args(&b, &out, &["--force"]), "renaming");
    // Stalled after its first rename: one temporary renamed, 7 backups.
    wait_for(&out, |names| {
        names.iter().filter(|n| is_temporary(n)).count() == 6
            && names.iter().filter(|n| is_backup(n)).count() == 7
    });
    let refused = run_strings(&bake_args(&b, &out, &["--force"]));
    assert_eq!(refused.status.code(), Some(3), "{}", stderr(&refused));
    assert!(
        stderr(&refused).contains(&format!(
            ".micromap-index.lock, held by process {}); nothing written",
            child.id()
        )),
        "{}",
        stderr(&refused)
    );
    signal(&child, "-KILL");
    let _ = child.wait();
    // A bake that claims the directory, then fails on its input: the dead
    // bake's renames are undone, and nothing of its own is written.
    let bad = dir.join("bad.json");
    std::fs::write(&bad, r#"{"triangles": [[[0, 0], [1, 0]]]}"#).unwrap();
    let failed = run_strings(&bake_args(&bad, &out, &["--force"]));
    assert_eq!(failed.status.code(), Some(2), "{}", stderr(&failed));
    assert_eq!(contents(&out), before);
    let again = run_strings(&bake_args(&b, &out, &["--force"]));
    assert_eq!(again.status.code(), Some(0), "{}", stderr(&again));
    assert!(
        listing(&out)
            .iter()
            .all(|n| !is_temporary(n) && !is_backup(n) && *n != ".micromap-index.lock"),
        "{:?}",
        listing(&out)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A lock file no live process holds (left by a killed bake of an earlier
/// version, or written by hand), with orphan temporaries: the bake goes
/// ahead and removes them.
#[test]
fn a_dead_lock_and_orphan_temporaries_are_cleaned() {
    let dir = scratch("dead-lock");
    let [tris, _] = two_inputs(&dir);
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join(".micromap-index.lock"), "12345\n").unwrap();
    std::fs::write(out.join(".micromap-data.bin.12345.tmp"), vec![0; 1 << 16]).unwrap();
    let result = run_strings(&bake_args(&tris, &out, &[]));
    assert_eq!(result.status.code(), Some(0), "{}", stderr(&result));
    assert_eq!(
        listing(&out),
        [
            "micromap-data.bin",
            "micromap-geometry-usage.bin",
            "micromap-indices.bin",
            "micromap-triangles.bin",
            "micromap-usage.bin",
            "preview.png",
            "summary.json"
        ]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Ctrl-C in `--force`'s rename phase (after the first rename; in 3 of 3
/// trials this left the new set under the message "nothing written"): the
/// renames are undone, the directory holds exactly the old set, and the
/// message says so.
#[test]
fn ctrl_c_while_renaming_leaves_the_old_set_and_says_so() {
    let dir = scratch("sigint-renaming");
    let [a, b] = two_inputs(&dir);
    let out = dir.join("out");
    let first = run_strings(&bake_args(&a, &out, &[]));
    assert_eq!(first.status.code(), Some(0), "{}", stderr(&first));
    let before = contents(&out);
    let child = stalled(&bake_args(&b, &out, &["--force"]), "renaming");
    wait_for(&out, |names| {
        names.iter().filter(|n| is_temporary(n)).count() == 6
            && names.iter().filter(|n| is_backup(n)).count() == 7
    });
    signal(&child, "-INT");
    let result = child.wait_with_output().unwrap();
    assert_eq!(result.status.code(), Some(130), "{}", stderr(&result));
    assert!(
        stderr(&result).contains(&format!(
            "interrupted; nothing written: {} holds what it held before",
            out.display()
        )),
        "{}",
        stderr(&result)
    );
    assert_eq!(contents(&out), before);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Ctrl-C after every rename (before the summary is printed): the
/// directory holds the complete new set, and the message says so.
#[test]
fn ctrl_c_after_the_renames_keeps_the_new_set_and_says_so() {
    let dir = scratch("sigint-written");
    let [a, b] = two_inputs(&dir);
    let out = dir.join("out");
    let reference = dir.join("reference");
    let made = run_strings(&bake_args(&b, &reference, &[]));
    assert_eq!(made.status.code(), Some(0), "{}", stderr(&made));
    let first = run_strings(&bake_args(&a, &out, &[]));
    assert_eq!(first.status.code(), Some(0), "{}", stderr(&first));
    let before = contents(&out);
    let child = stalled(&bake_args(&b, &out, &["--force"]), "written");
    // Written: the lock released, no temporary or backup, new contents.
    wait_for(&out, |names| {
        !names
            .iter()
            .any(|n| *n == ".micromap-index.lock" || is_temporary(n) || is_backup(n))
            && contents(&out) != before
    });
    signal(&child, "-INT");
    let result = child.wait_with_output().unwrap();
    assert_eq!(result.status.code(), Some(130), "{}", stderr(&result));
    assert!(
        stderr(&result).contains(&format!(
            "interrupted after the output was written: {} holds the new files",
            out.display()
        )),
        "{}",
        stderr(&result)
    );
    assert_eq!(outputs(&out), outputs(&reference));
    let _ = std::fs::remove_dir_all(&dir);
}

fn run_strings(args: &[String]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

/// `--force --no-preview` over an earlier bake with a preview removes the
/// stale `preview.png`, so every file in the directory is from one bake.
#[test]
fn force_without_preview_removes_a_stale_preview() {
    let dir = scratch("stale-preview");
    let [a, b] = two_inputs(&dir);
    let out = dir.join("out");
    let first = run_strings(&bake_args(&a, &out, &[]));
    assert_eq!(first.status.code(), Some(0), "{}", stderr(&first));
    assert!(out.join("preview.png").exists());
    let second = run_strings(&bake_args(&b, &out, &["--force", "--no-preview"]));
    assert_eq!(second.status.code(), Some(0), "{}", stderr(&second));
    assert_eq!(
        listing(&out),
        [
            "micromap-data.bin",
            "micromap-geometry-usage.bin",
            "micromap-indices.bin",
            "micromap-triangles.bin",
            "micromap-usage.bin",
            "summary.json"
        ]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A bake that fails after its directory was created removes the
/// directories it created (and only those).
#[test]
fn a_failed_bake_removes_the_directories_it_created() {
    let dir = scratch("failed");
    let bad = dir.join("bad.json");
    std::fs::write(&bad, r#"{"triangles": [[[0, 0], [1, 0]]]}"#).unwrap();
    let out = dir.join("new").join("deeper");
    let result = run_strings(&bake_args(&bad, &out, &[]));
    assert_eq!(result.status.code(), Some(2), "{}", stderr(&result));
    assert!(
        !dir.join("new").exists(),
        "the created directories are left"
    );
    // An existing (empty) directory stays.
    let existing = dir.join("existing");
    std::fs::create_dir(&existing).unwrap();
    let result = run_strings(&bake_args(&bad, &existing, &[]));
    assert_eq!(result.status.code(), Some(2));
    assert!(existing.is_dir());
    assert!(listing(&existing).is_empty());
    let _ = std::fs::remove_dir_all(&dir);
}

fn is_backup(name: &str) -> bool {
    Path::new(name).extension().is_some_and(|e| e == "old")
}

fn is_temporary(name: &str) -> bool {
    Path::new(name).extension().is_some_and(|e| e == "tmp")
}

/// Ctrl-C at the worst moment (temporaries written, backups of the old
/// files made, nothing renamed yet; the test hook holds the bake there):
/// exit 130, and the directory holds exactly the old files with their old
/// contents: no temporary, no backup, no lock.
#[test]
fn ctrl_c_removes_temporaries_backups_and_the_lock() {
    let dir = scratch("sigint");
    let [a, b] = two_inputs(&dir);
    let out = dir.join("out");
    let first = run_strings(&bake_args(&a, &out, &[]));
    assert_eq!(first.status.code(), Some(0), "{}", stderr(&first));
    let before: Vec<(String, Vec<u8>)> = listing(&out)
        .into_iter()
        .map(|n| {
            let bytes = std::fs::read(out.join(&n)).unwrap();
            (n, bytes)
        })
        .collect();
    let child = Command::new(BIN)
        .args(bake_args(&b, &out, &["--force"]))
        .env("MICROMAP_INDEX_TEST_STALL_MS", "20000")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // (The bake stalls 20 s for the test once its backups are made.)
    let names = wait_for(&out, |names| {
        names.iter().filter(|n| is_backup(n)).count() == 7
    });
    assert!(names.iter().any(|n| is_temporary(n)), "{names:?}");
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let result = child.wait_with_output().unwrap();
    assert_eq!(result.status.code(), Some(130), "{}", stderr(&result));
    assert!(stderr(&result).contains("interrupted; nothing written"));
    let after: Vec<(String, Vec<u8>)> = listing(&out)
        .into_iter()
        .map(|n| {
            let bytes = std::fs::read(out.join(&n)).unwrap();
            (n, bytes)
        })
        .collect();
    assert_eq!(after, before);
    // Interrupted into a new directory: the directory goes too.
    let fresh = dir.join("fresh");
    let child = Command::new(BIN)
        .args(bake_args(&b, &fresh, &[]))
        .env("MICROMAP_INDEX_TEST_STALL_MS", "20000")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_for(&fresh, |names| names.iter().any(|n| is_temporary(n)));
    std::thread::sleep(Duration::from_millis(100));
    Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    let result = child.wait_with_output().unwrap();
    assert_eq!(result.status.code(), Some(130));
    assert!(!fresh.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Stdout that cannot be written after the files were (`>/dev/full`):
/// exit 3 as the help says ("stdout unwritable after DIR was written"), and
/// the directory is complete.
#[test]
fn a_full_stdout_after_the_files_exits_3_with_the_files_complete() {
    let dir = scratch("full");
    let [a, _] = two_inputs(&dir);
    let out = dir.join("out");
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let result = Command::new(BIN)
        .args(bake_args(&a, &out, &[]))
        .stdout(full)
        .output()
        .unwrap();
    assert_eq!(result.status.code(), Some(3), "{}", stderr(&result));
    assert!(stderr(&result).contains("writing stdout"));
    assert_eq!(listing(&out).len(), 7);
    let help = run(&["bake", "--help"]);
    let help = String::from_utf8_lossy(&help.stdout)
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    assert!(help.contains("stdout unwritable after DIR was written (DIR complete)"));
    let _ = std::fs::remove_dir_all(&dir);
}

fn verify_args(tris: &Path, micromaps: &Path, extra: &[&str]) -> Vec<String> {
    let mut args: Vec<String> = [
        "verify-bake",
        "--texture",
        &texture(),
        "--triangles",
        tris.to_str().unwrap(),
        "--micromaps",
        micromaps.to_str().unwrap(),
        "--json",
    ]
    .iter()
    .map(|s| (*s).to_owned())
    .collect();
    args.extend(extra.iter().map(|s| (*s).to_owned()));
    args
}

/// A copy of `from`'s three buffers and usage counts in `to`, with `edit`
/// applied to (data, records, usage).
fn tampered(
    from: &Path,
    to: &Path,
    edit: impl FnOnce(&mut Vec<u8>, &mut Vec<u8>, &mut Option<Vec<u8>>),
) {
    let _ = std::fs::remove_dir_all(to);
    std::fs::create_dir_all(to).unwrap();
    let mut data = std::fs::read(from.join("micromap-data.bin")).unwrap();
    let mut records = std::fs::read(from.join("micromap-triangles.bin")).unwrap();
    let mut usage = Some(std::fs::read(from.join("micromap-usage.bin")).unwrap());
    edit(&mut data, &mut records, &mut usage);
    std::fs::write(to.join("micromap-data.bin"), data).unwrap();
    std::fs::write(to.join("micromap-triangles.bin"), records).unwrap();
    std::fs::copy(
        from.join("micromap-indices.bin"),
        to.join("micromap-indices.bin"),
    )
    .unwrap();
    if let Some(usage) = usage {
        std::fs::write(to.join("micromap-usage.bin"), usage).unwrap();
    }
}

/// `verify-bake` checks the whole layout: a missing, garbage or lying
/// `micromap-usage.bin`, overlapping blocks and data after the last block
/// are exit 2 naming the fault (they were all "sound" before); the two
/// escape hatches (`--no-usage`, `--lenient-layout`) say what they skipped.
#[test]
fn verify_bake_checks_the_whole_layout() {
    let dir = scratch("layout");
    let [_, tris] = two_inputs(&dir);
    let good = dir.join("good");
    let baked = run_strings(&bake_args(&tris, &good, &["--no-preview"]));
    assert_eq!(baked.status.code(), Some(0), "{}", stderr(&baked));
    let sound = run_strings(&verify_args(&tris, &good, &[]));
    assert_eq!(sound.status.code(), Some(0), "{}", stderr(&sound));
    let report: serde_json::Value = serde_json::from_slice(&sound.stdout).unwrap();
    assert_eq!(report["usage_counts_checked"], true);
    assert_eq!(report["trailing_data_bytes"], 0);
    let records = std::fs::read(good.join("micromap-triangles.bin")).unwrap();
    assert!(records.len() >= 16, "the test needs two records");
    let bad = dir.join("bad");
    let refused = |extra: &[&str], needle: &str| {
        let out = run_strings(&verify_args(&tris, &bad, extra));
        assert_eq!(out.status.code(), Some(2), "{needle}: {}", stderr(&out));
        assert!(stderr(&out).contains(needle), "{needle}: {}", stderr(&out));
    };
    let accepted = |extra: &[&str]| -> serde_json::Value {
        let out = run_strings(&verify_args(&tris, &bad, extra));
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        serde_json::from_slice(&out.stdout).unwrap()
    };
    // Missing usage counts.
    tampered(&good, &bad, |_, _, usage| *usage = None);
    refused(&[], "micromap-usage.bin is missing");
    assert_eq!(accepted(&["--no-usage"])["usage_counts_checked"], false);
    // Garbage usage counts: not a whole entry, and a count that lies.
    tampered(&good, &bad, |_, _, usage| {
        *usage = Some(b"garbage".to_vec());
    });
    refused(&[], "usage");
    tampered(&good, &bad, |_, _, usage| {
        let usage = usage.as_mut().unwrap();
        usage[0] = usage[0].wrapping_add(1);
    });
    refused(&[], "usage counts declare");
    // Trailing data.
    tampered(&good, &bad, |data, _, _| data.extend_from_slice(&[0; 5]));
    refused(&[], "5 bytes of micromap-data.bin after the last block");
    assert_eq!(accepted(&["--lenient-layout"])["trailing_data_bytes"], 5);
    // Record 1's block moved onto record 0's (same level and format: the
    // bake used one level).
    tampered(&good, &bad, |_, records, _| {
        let first: [u8; 4] = records[0..4].try_into().unwrap();
        records[8..12].copy_from_slice(&first);
    });
    refused(&[], "overlapping data");
    // An endless usage file (a device) stops at its limit.
    tampered(&good, &bad, |_, _, usage| *usage = None);
    std::os::unix::fs::symlink("/dev/zero", bad.join("micromap-usage.bin")).unwrap();
    refused(&[], "over the limit of 1048576 bytes for usage counts");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--texture` and `--triangles` files past 1 GiB are refused from their
/// size (a sparse file: nothing is read), and an endless stream stops at
/// the limit; the message names the limit.
#[test]
fn oversized_texture_and_triangles_are_refused_by_a_named_limit() {
    let dir = scratch("oversized");
    let [tris, _] = two_inputs(&dir);
    let huge = dir.join("huge");
    std::fs::File::create(&huge)
        .unwrap()
        .set_len((1 << 30) + 1)
        .unwrap();
    let out = dir.join("out");
    let mut args = bake_args(&tris, &out, &[]);
    args[2] = huge.to_str().unwrap().to_owned();
    let result = run_strings(&args);
    assert_eq!(result.status.code(), Some(2), "{}", stderr(&result));
    assert!(stderr(&result).contains("over the limit of 1073741824 bytes for a --texture file"));
    let mut args = bake_args(&huge, &out, &[]);
    args[2] = texture();
    let result = run_strings(&args);
    assert_eq!(result.status.code(), Some(2), "{}", stderr(&result));
    assert!(stderr(&result).contains("over the limit of 1073741824 bytes for a --triangles file"));
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// On meshoptimizer's committed thorn level-4 output (1,329 contradictions
/// under nearest filtering and the exact model): `--max-report 3` keeps 3 and still counts all;
/// `--max-checks 100` checks 100 known micro-triangles, reports the rest as
/// not checked, and the verdict is INCOMPLETE with exit 1, never sound.
#[test]
fn verify_bake_keeps_the_first_n_counts_all_and_reports_its_work_cap() {
    let micromaps = format!(
        "{}/../other-bakers/out/meshopt-cpp/sponza_thorn-L4-f4",
        env!("CARGO_MANIFEST_DIR")
    );
    let args = |extra: &[&str]| {
        let mut args = vec![
            "verify-bake".to_owned(),
            "--texture".to_owned(),
            format!("{ASSETS}/sponza_thorn.png"),
            "--triangles".to_owned(),
            format!("{ASSETS}/grid.tris.json"),
            "--micromaps".to_owned(),
            micromaps.clone(),
            "--filter".to_owned(),
            "nearest".to_owned(),
            "--address".to_owned(),
            "clamp-to-edge".to_owned(),
            "--no-usage".to_owned(),
            // The 1,329 are the exact model's count (the GPU model finds more).
            "--model".to_owned(),
            "exact".to_owned(),
        ];
        args.extend(extra.iter().map(|s| (*s).to_owned()));
        run_strings(&args)
    };
    let out = args(&["--json", "--max-report", "3"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["contradictions"], 1329);
    assert_eq!(report["first_contradictions"].as_array().unwrap().len(), 3);
    assert_eq!(report["complete"], true);
    let out = args(&["--json", "--max-checks", "100"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["known_micro_triangles"], 100);
    assert_eq!(report["unchecked_micro_triangles"], 21326 - 100);
    assert_eq!(report["complete"], false);
    assert_eq!(report["sound"], false);
    // A cap on a sound bake: INCOMPLETE, not sound.
    let dir = scratch("max-checks");
    let [a, _] = two_inputs(&dir);
    let good = dir.join("good");
    let baked = run_strings(&bake_args(&a, &good, &["--no-preview"]));
    assert_eq!(baked.status.code(), Some(0), "{}", stderr(&baked));
    // The text report (without --json).
    let mut text_args = verify_args(&a, &good, &["--max-checks", "10"]);
    text_args.retain(|arg| arg != "--json");
    let out = run_strings(&text_args);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.starts_with("INCOMPLETE: "), "{text}");
    assert!(
        text.contains("known micro-triangles past --max-checks"),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `tree encode` on an endless stdin stops at its limit (4^L characters and
/// 4096 bytes of whitespace) with exit 2 naming it.
#[test]
fn tree_encode_reads_stdin_up_to_a_named_limit() {
    use std::io::Write as _;
    let mut child = Command::new(BIN)
        .args(["tree", "encode", "--format", "4", "--level", "2"])
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let feeder = std::thread::spawn(move || {
        let chunk = [b'0'; 4096];
        // Endless until the command stops reading (then the write fails).
        for _ in 0..100_000 {
            if stdin.write_all(&chunk).is_err() {
                return true;
            }
        }
        false
    });
    let result = child.wait_with_output().unwrap();
    assert_eq!(result.status.code(), Some(2), "{}", stderr(&result));
    assert!(
        stderr(&result).contains("over the limit of 4112 bytes for a level-2 state string"),
        "{}",
        stderr(&result)
    );
    assert!(feeder.join().unwrap(), "the whole stream was read");
}

/// `check --answers /dev/zero` stops at the 1 GiB limit with exit 2 naming
/// it (it read until memory ran out before).
#[test]
fn check_answers_are_read_up_to_a_named_limit() {
    let vectors = format!("{}/../../vectors", env!("CARGO_MANIFEST_DIR"));
    let vectors = std::fs::read_dir(&vectors)
        .ok()
        .and_then(|mut d| d.next())
        .map_or_else(
            || "/dev/null".to_owned(),
            |e| e.unwrap().path().to_str().unwrap().to_owned(),
        );
    let result = run(&["check", "--vectors", &vectors, "--answers", "/dev/zero"]);
    assert_eq!(result.status.code(), Some(2), "{}", stderr(&result));
    assert!(
        stderr(&result).contains("/dev/zero: over the limit of 1073741824 bytes for --answers"),
        "{}",
        stderr(&result)
    );
}

/// The output-size estimate is checked before baking: 300 triangles at
/// level 12 (4 MiB each, 1.2 GiB) are refused by the default 1 GiB limit at
/// once; `--max-bytes` sets the limit, exactly at the estimate (data before
/// deduplication, 8-byte records, indices and 34 usage entries).
#[test]
fn an_output_over_the_size_limit_is_refused_before_baking() {
    let dir = scratch("max-bytes");
    let many = dir.join("many.json");
    let triangle = "[[0, 0], [1, 0], [0, 1]]";
    std::fs::write(
        &many,
        format!("{{\"triangles\": [{}]}}", vec![triangle; 300].join(", ")),
    )
    .unwrap();
    let out = dir.join("out");
    let mut args = bake_args(&many, &out, &[]);
    let at = args.iter().position(|a| a == "--level").unwrap();
    args[at + 1] = "12".to_owned();
    // The refusal names the estimate, which is checked before any
    // micro-triangle is baked (baking these would take hours); the hang
    // guard fails only if the bake ran anyway and never ended.
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    let result = common::run_within_hang_guard(&refs);
    assert_eq!(result.status.code(), Some(2), "{}", stderr(&result));
    let estimate = 34 * 12 + 300 * ((1u64 << 22) + 12);
    assert!(
        stderr(&result).contains(&format!(
            "the output may take up to {estimate} bytes (before deduplication), over the limit of 1073741824 bytes"
        )),
        "{}",
        stderr(&result)
    );
    assert!(!out.exists());
    // Two level-4 triangles: 2 x (64 + 12) + 408 = 560 bytes.
    let [a, _] = two_inputs(&dir);
    let refused = run_strings(&bake_args(&a, &out, &["--max-bytes", "559"]));
    assert_eq!(refused.status.code(), Some(2), "{}", stderr(&refused));
    assert!(stderr(&refused).contains("up to 560 bytes"));
    let baked = run_strings(&bake_args(&a, &out, &["--max-bytes", "560"]));
    assert_eq!(baked.status.code(), Some(0), "{}", stderr(&baked));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The preview draws each distinct triangle once and at most its pixel
/// budget of micro-triangles; the rest are counted in `summary.json`, with
/// the time it took (`preview_seconds`).
#[test]
fn the_preview_is_bounded_counted_and_timed() {
    let dir = scratch("preview");
    let same = dir.join("same.json");
    let triangle = "[[0, 0], [1, 0], [0, 1]]";
    std::fs::write(
        &same,
        format!("{{\"triangles\": [{}]}}", vec![triangle; 2000].join(", ")),
    )
    .unwrap();
    let out = dir.join("same");
    let mut args = bake_args(&same, &out, &[]);
    let at = args.iter().position(|a| a == "--level").unwrap();
    args[at + 1] = "3".to_owned();
    let result = run_strings(&args);
    assert_eq!(result.status.code(), Some(0), "{}", stderr(&result));
    let summary: serde_json::Value = serde_json::from_slice(&result.stdout).unwrap();
    assert_eq!(summary["preview_micro_triangles"], 64);
    assert_eq!(summary["preview_micro_triangles_skipped"], 1999 * 64);
    assert!(summary["preview_seconds"].as_f64().unwrap() >= 0.0);
    // 1000 distinct whole-texture triangles at level 0: more pixels than the
    // budget (2^27), so some are not drawn, and counted.
    let many = dir.join("many.json");
    let triangles: Vec<String> = (0..1000)
        .map(|i| format!("[[0, 0], [1, {}], [0, 1]]", f64::from(i) / 1000.0))
        .collect();
    std::fs::write(
        &many,
        format!("{{\"triangles\": [{}]}}", triangles.join(", ")),
    )
    .unwrap();
    let out = dir.join("many");
    let mut args = bake_args(&many, &out, &[]);
    args[at + 1] = "0".to_owned();
    let result = run_strings(&args);
    assert_eq!(result.status.code(), Some(0), "{}", stderr(&result));
    let summary: serde_json::Value = serde_json::from_slice(&result.stdout).unwrap();
    let drawn = summary["preview_micro_triangles"].as_u64().unwrap();
    let skipped = summary["preview_micro_triangles_skipped"].as_u64().unwrap();
    assert_eq!(drawn + skipped, 1000);
    assert!(skipped > 0 && drawn > 0, "{drawn} drawn, {skipped} skipped");
    let _ = std::fs::remove_dir_all(&dir);
}
