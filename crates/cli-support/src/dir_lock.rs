//! The lock of an output directory (`DIR/.micromap-index.lock`), held by an
//! OS file lock (`flock`) that dies with its process: a second writer is
//! refused while the first runs, and a lock left by a process that was
//! killed (`kill -9`, a file-size limit) is taken over by the next writer,
//! which then undoes what the dead one left half done.
//!
//! The lock file is also the writer's journal: its first line is the
//! holder's process id, then `renaming` once its temporaries and backups
//! are complete and it starts renaming them over the targets, `new NAME`
//! for each target that had no old file, and `committed` once every rename
//! is done. A writer that takes over a dead holder's lock reads it: killed
//! while renaming, the dead one's backups (`NAME.PID.old`) are put back and
//! its new files removed (the directory holds the old set again);
//! committed or not yet renaming, its backups are removed (the directory
//! holds the new set, or the old set untouched). Its temporaries
//! (`.NAME.PID.tmp`) are removed either way.

use std::fs::{self, File};
use std::io::{self, Read as _, Seek as _, Write as _};
use std::path::{Path, PathBuf};

/// The lock file's name inside the destination directory.
pub const LOCK_NAME: &str = ".micromap-index.lock";

/// The held lock of one directory (released by [`DirLock::release`] or by
/// the process's end).
pub(crate) struct DirLock {
    path: PathBuf,
    file: File,
}

/// Why the lock could not be taken.
pub(crate) enum LockError {
    /// A live process holds it (its journal's first line, if readable).
    Held(String),
    /// The lock file cannot be created or locked.
    Io(io::Error),
}

/// What a dead holder left: its journal.
pub(crate) struct Stale {
    journal: String,
}

impl DirLock {
    /// Takes `dir`'s lock, or says who holds it. A lock file left by a dead
    /// process is taken over, and returned as [`Stale`] for
    /// [`Stale::recover`].
    pub(crate) fn acquire(dir: &Path) -> Result<(DirLock, Option<Stale>), LockError> {
        let path = dir.join(LOCK_NAME);
        // A holder that releases unlinks the file after we opened it: then
        // our lock is on a file no one else will see, so open again.
        for _ in 0..64 {
            let mut file = File::options()
                .read(true)
                .write(true)
                .create(true)
                .truncate(false)
                .open(&path)
                .map_err(LockError::Io)?;
            if !try_lock(&file).map_err(LockError::Io)? {
                let mut holder = String::new();
                let _ = file.read_to_string(&mut holder);
                return Err(LockError::Held(
                    holder.lines().next().unwrap_or("").trim().to_owned(),
                ));
            }
            if !same_file(&file, &path) {
                continue;
            }
            let mut journal = String::new();
            file.read_to_string(&mut journal).map_err(LockError::Io)?;
            file.set_len(0).map_err(LockError::Io)?;
            file.rewind().map_err(LockError::Io)?;
            writeln!(file, "{}", std::process::id()).map_err(LockError::Io)?;
            let stale = (!journal.is_empty()).then_some(Stale { journal });
            return Ok((DirLock { path, file }, stale));
        }
        Err(LockError::Io(io::Error::other(
            "the lock file keeps being replaced",
        )))
    }

    /// Appends `line` to the journal (best effort: a lost line costs only
    /// the recovery of a killed writer).
    pub(crate) fn note(&mut self, line: &str) {
        let _ = writeln!(self.file, "{line}");
    }

    /// Removes the lock file, then unlocks it (closing it).
    pub(crate) fn release(self) {
        let _ = fs::remove_file(&self.path);
        drop(self.file);
    }
}

impl Stale {
    /// Undoes what the dead holder left in `dir` (module docs); `names` are
    /// the outputs whose temporaries of any process are removed (none can
    /// be live: the lock is held).
    pub(crate) fn recover(&self, dir: &Path, names: &[&str]) {
        let mut lines = self.journal.lines();
        let pid = lines.next().unwrap_or("").trim().to_owned();
        let rest: Vec<&str> = lines.collect();
        let renaming = rest.contains(&"renaming") && !rest.contains(&"committed");
        let Ok(entries) = fs::read_dir(dir) else {
            return;
        };
        let mut backups = Vec::new();
        for entry in entries.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            if let Some(target) = temporary_of(&name) {
                if names.contains(&target) {
                    let _ = fs::remove_file(entry.path());
                }
            } else if let Some(target) = name
                .strip_suffix(".old")
                .and_then(|n| n.strip_suffix(&pid))
                .and_then(|n| n.strip_suffix('.'))
            {
                if !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()) {
                    backups.push((entry.path(), dir.join(target)));
                }
            }
        }
        for (backup, target) in backups {
            if renaming {
                // A target not renamed yet is a hard link to its backup:
                // then the rename does nothing, and the backup goes below.
                let _ = fs::rename(&backup, target);
            }
            let _ = fs::remove_file(backup);
        }
        if renaming {
            for new in rest.iter().filter_map(|l| l.strip_prefix("new ")) {
                // Only a bare name of this directory.
                if !new.contains(['/', '\\']) && new != ".." && new != "." {
                    let _ = fs::remove_file(dir.join(new));
                }
            }
        }
    }
}

/// `NAME` of a temporary `.NAME.PID.tmp`.
fn temporary_of(name: &str) -> Option<&str> {
    let inner = name.strip_prefix('.')?.strip_suffix(".tmp")?;
    let (target, pid) = inner.rsplit_once('.')?;
    (!pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit())).then_some(target)
}

/// Whether `file` is still the file at `path` (not unlinked or replaced).
#[cfg(unix)]
fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt as _;
    match (file.metadata(), fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_file(_: &File, path: &Path) -> bool {
    path.exists()
}

/// An exclusive `flock` without waiting: `false` when another holds it.
#[cfg(unix)]
fn try_lock(file: &File) -> io::Result<bool> {
    use rustix::fs::{flock, FlockOperation};
    match flock(file, FlockOperation::NonBlockingLockExclusive) {
        Ok(()) => Ok(true),
        Err(e) if e == rustix::io::Errno::WOULDBLOCK => Ok(false),
        Err(e) => Err(e.into()),
    }
}

/// Elsewhere no OS lock: the first writer wins only while it holds the file
/// open (a best effort; the tools are built and tested on Linux).
#[cfg(not(unix))]
fn try_lock(_: &File) -> io::Result<bool> {
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::temporary_of;

    #[test]
    fn temporaries_are_told_by_their_pattern() {
        assert_eq!(temporary_of(".summary.json.123.tmp"), Some("summary.json"));
        assert_eq!(temporary_of(".summary.json.x.tmp"), None);
        assert_eq!(temporary_of("summary.json.123.tmp"), None);
    }
}
