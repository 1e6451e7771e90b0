//! Writing a set of files into one directory all or nothing: after a
//! failure the directory holds what it held before (no new file, no
//! half-written file, no temporary left), and after success every file is
//! complete and synced.
//!
//! Each file is first written to a temporary file in the same directory and
//! synced; an existing file it will replace is kept under a backup name (a
//! hard link, or a copy where links are not supported); then the temporaries
//! are renamed over their targets one by one (a rename within a directory
//! replaces a file in one step, so a reader never sees a partial file). If a
//! rename fails, the files renamed so far are put back from their backups or
//! removed. Only a process killed in the middle (`kill -9`, power loss) can
//! leave temporaries (`.NAME.PID.tmp`) behind.

use std::fs::{self, File};
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// Why the destination was refused before anything was written.
pub(crate) fn check_destination(dir: &Path, names: &[&str], force: bool) -> Result<(), String> {
    if dir.as_os_str().is_empty() {
        return Err("--out needs a directory path, got an empty one".into());
    }
    if let Ok(metadata) = fs::metadata(dir) {
        if !metadata.is_dir() {
            return Err(format!(
                "--out {} exists and is not a directory",
                dir.display()
            ));
        }
    }
    for name in names {
        let path = dir.join(name);
        let Ok(metadata) = fs::symlink_metadata(&path) else {
            continue;
        };
        if !metadata.is_file() {
            return Err(format!(
                "{} exists and is not a file; nothing written",
                path.display()
            ));
        }
        if !force {
            return Err(format!(
                "{} exists; nothing written (--force replaces it)",
                path.display()
            ));
        }
    }
    Ok(())
}

/// Writes `files` (name, bytes) into `dir`, creating `dir` if needed: all
/// of them, or (after an error, which the message describes) none.
pub(crate) fn write_files(dir: &Path, files: &[(String, Vec<u8>)]) -> Result<(), String> {
    fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let mut staged = Staged::default();
    let result = staged.write(dir, files);
    staged.clean_up();
    if result.is_ok() {
        // Best effort: make the renames themselves durable.
        let _ = File::open(dir).and_then(|d| d.sync_all());
    }
    result
}

/// The paths created so far, for the clean-up.
#[derive(Default)]
struct Staged {
    /// Temporary files not yet renamed.
    temporaries: Vec<PathBuf>,
    /// (target, backup of its old content).
    backups: Vec<(PathBuf, PathBuf)>,
    /// Targets renamed into place, in order.
    renamed: Vec<PathBuf>,
    committed: bool,
}

impl Staged {
    fn write(&mut self, dir: &Path, files: &[(String, Vec<u8>)]) -> Result<(), String> {
        let pid = std::process::id();
        let mut pairs = Vec::new();
        for (name, bytes) in files {
            let temporary = dir.join(format!(".{name}.{pid}.tmp"));
            let mut file = File::options()
                .write(true)
                .create_new(true)
                .open(&temporary)
                .map_err(|e| format!("cannot create {}: {e}", temporary.display()))?;
            self.temporaries.push(temporary.clone());
            file.write_all(bytes)
                .and_then(|()| file.sync_all())
                .map_err(|e| format!("cannot write {}: {e}", temporary.display()))?;
            pairs.push((temporary, dir.join(name)));
        }
        for (_, target) in &pairs {
            if fs::symlink_metadata(target).is_ok_and(|m| m.is_file()) {
                let backup = PathBuf::from(format!("{}.{pid}.old", target.display()));
                keep_copy(target, &backup)
                    .map_err(|e| format!("cannot keep a backup of {}: {e}", target.display()))?;
                self.backups.push((target.clone(), backup));
            }
        }
        for (temporary, target) in pairs {
            fs::rename(&temporary, &target)
                .map_err(|e| format!("cannot rename into {}: {e}", target.display()))?;
            self.temporaries.retain(|t| *t != temporary);
            self.renamed.push(target);
        }
        self.committed = true;
        Ok(())
    }

    /// Removes temporaries and backups; after a failure, first restores or
    /// removes the targets renamed so far.
    fn clean_up(self) {
        if !self.committed {
            for target in self.renamed.iter().rev() {
                match self.backups.iter().find(|(t, _)| t == target) {
                    Some((_, backup)) => {
                        let _ = fs::rename(backup, target);
                    }
                    None => {
                        let _ = fs::remove_file(target);
                    }
                }
            }
        }
        for path in self.temporaries {
            let _ = fs::remove_file(path);
        }
        for (_, backup) in self.backups {
            let _ = fs::remove_file(backup);
        }
    }
}

/// `backup` as a hard link to `target`, or a copy where links fail.
fn keep_copy(target: &Path, backup: &Path) -> io::Result<()> {
    let _ = fs::remove_file(backup);
    fs::hard_link(target, backup).or_else(|_| fs::copy(target, backup).map(drop))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!(
            "micromap-index-write-all-{name}-{}",
            std::process::id()
        ));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn listing(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        names.sort();
        names
    }

    fn files(names: &[&str]) -> Vec<(String, Vec<u8>)> {
        names
            .iter()
            .map(|n| ((*n).to_owned(), format!("new {n}").into_bytes()))
            .collect()
    }

    #[test]
    fn writes_every_file() {
        let dir = scratch("ok");
        fs::write(dir.join("b"), "old b").unwrap();
        write_files(&dir, &files(&["a", "b", "c"])).unwrap();
        assert_eq!(listing(&dir), ["a", "b", "c"]);
        assert_eq!(fs::read_to_string(dir.join("b")).unwrap(), "new b");
        let _ = fs::remove_dir_all(&dir);
    }

    /// A rename that fails after another succeeded (the third target is a
    /// non-empty directory, which the up-front check would refuse): the
    /// first file gets its old content back, the second is removed, and no
    /// temporary or backup is left.
    #[test]
    fn a_failed_rename_restores_the_directory() {
        let dir = scratch("rollback");
        fs::write(dir.join("a"), "old a").unwrap();
        fs::create_dir_all(dir.join("c").join("inside")).unwrap();
        let error = write_files(&dir, &files(&["a", "b", "c"])).unwrap_err();
        assert!(error.contains("cannot rename into"), "{error}");
        assert_eq!(listing(&dir), ["a", "c"]);
        assert_eq!(fs::read_to_string(dir.join("a")).unwrap(), "old a");
        let _ = fs::remove_dir_all(&dir);
    }

    #[test]
    fn the_destination_is_checked_first() {
        let dir = scratch("check");
        fs::write(dir.join("a"), "old a").unwrap();
        fs::create_dir(dir.join("d")).unwrap();
        assert!(check_destination(&dir, &["x"], false).is_ok());
        let e = check_destination(&dir, &["x", "a"], false).unwrap_err();
        assert!(
            e.ends_with("a exists; nothing written (--force replaces it)"),
            "{e}"
        );
        assert!(check_destination(&dir, &["a"], true).is_ok());
        let e = check_destination(&dir, &["d"], true).unwrap_err();
        assert!(
            e.ends_with("d exists and is not a file; nothing written"),
            "{e}"
        );
        let e = check_destination(&dir.join("a"), &["x"], false).unwrap_err();
        assert!(e.ends_with("a exists and is not a directory"), "{e}");
        let e = check_destination(Path::new(""), &["x"], false).unwrap_err();
        assert_eq!(e, "--out needs a directory path, got an empty one");
        let _ = fs::remove_dir_all(&dir);
    }
}
