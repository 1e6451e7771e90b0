//! Writing a set of files into one directory all or nothing: after a
//! failure the directory holds what it held before (no new file, no
//! half-written file, no temporary left), and after success every file is
//! complete and synced.
//!
//! Each file is first written to a temporary file in the same directory and
//! synced; an existing file it will replace (or remove) is kept under a
//! backup name (a hard link, or a copy where links are not supported); then
//! the temporaries are renamed over their targets one by one (a rename
//! within a directory replaces a file in one step, so a reader never sees a
//! partial file). If a rename fails, the files renamed so far are put back
//! from their backups or removed.
//!
//! [`Destination`] (used by `bake` and `render`) adds what concurrent,
//! interrupted and killed use needs: a lock (`DIR/.micromap-index.lock`,
//! an OS file lock that dies with its process: `crate::dir_lock`), so a
//! second writer into the same directory is refused before it checks or
//! writes anything, and the existence check and the renames of one writer
//! cannot interleave with another's; the removal of the directories it
//! created when nothing was committed; and a Ctrl-C handler
//! ([`install_interrupt_handler`]) that, at any phase, leaves either the old
//! set (rolled back: temporaries, backups and lock removed) or the new set
//! (when every rename was done), says which, and exits 130. A process
//! killed in the middle (`kill -9`, a file-size limit) can leave
//! temporaries (`.NAME.PID.tmp`), backups (`NAME.PID.old`) and the lock
//! file behind; the next writer into the directory takes the dead lock
//! over and undoes them from the lock file's journal (`crate::dir_lock`).

pub use crate::dir_lock::LOCK_NAME;
use crate::dir_lock::{DirLock, LockError};
use crate::output::Program;
use std::fs::{self, File};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

/// Why the destination was refused before anything was written.
pub fn check_destination(dir: &Path, names: &[&str], force: bool) -> Result<(), String> {
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
pub fn write_files(dir: &Path, files: &[(String, impl AsRef<[u8]>)]) -> Result<(), String> {
    fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let staged = Mutex::new(Staged::default());
    let result = Staged::write(&staged, |s| s, |_, _| {}, dir, files, &[]);
    lock(&staged).clean_up();
    if result.is_ok() {
        sync_dir(dir);
    }
    result
}

/// Best effort: make the renames themselves durable.
fn sync_dir(dir: &Path) {
    let _ = File::open(dir).and_then(|d| d.sync_all());
}

/// The guard of `mutex`, also after a panic elsewhere (the state stays
/// meaningful: every step leaves it consistent).
fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(PoisonError::into_inner)
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
    /// Old files removed (their backups put them back).
    removed: Vec<PathBuf>,
    committed: bool,
}

impl Staged {
    /// Writes `files` and removes the existing files named in `remove`.
    /// Each step takes the lock on its own, so an interrupt handler can
    /// take it between two steps (and never gives it back: it exits).
    /// `note` appends a line to the writer's journal (`crate::dir_lock`).
    fn write<H>(
        state: &Mutex<H>,
        staged: fn(&mut H) -> &mut Staged,
        note: fn(&mut H, &str),
        dir: &Path,
        files: &[(String, impl AsRef<[u8]>)],
        remove: &[&str],
    ) -> Result<(), String> {
        let pid = std::process::id();
        let mut pairs = Vec::new();
        for (name, bytes) in files {
            let temporary = dir.join(format!(".{name}.{pid}.tmp"));
            let mut file = {
                let mut guard = lock(state);
                let file = File::options()
                    .write(true)
                    .create_new(true)
                    .open(&temporary)
                    .map_err(|e| format!("cannot create {}: {e}", temporary.display()))?;
                staged(&mut guard).temporaries.push(temporary.clone());
                file
            };
            file.write_all(bytes.as_ref())
                .and_then(|()| file.sync_all())
                .map_err(|e| format!("cannot write {}: {e}", temporary.display()))?;
            pairs.push((temporary, dir.join(name)));
        }
        let removals: Vec<PathBuf> = remove
            .iter()
            .map(|name| dir.join(name))
            .filter(|path| fs::symlink_metadata(path).is_ok_and(|m| m.is_file()))
            .collect();
        for target in pairs.iter().map(|(_, target)| target).chain(&removals) {
            if fs::symlink_metadata(target).is_ok_and(|m| m.is_file()) {
                let backup = PathBuf::from(format!("{}.{pid}.old", target.display()));
                let mut guard = lock(state);
                keep_copy(target, &backup)
                    .map_err(|e| format!("cannot keep a backup of {}: {e}", target.display()))?;
                staged(&mut guard).backups.push((target.clone(), backup));
            }
        }
        {
            let mut guard = lock(state);
            for (_, target) in &pairs {
                if !staged(&mut guard).backups.iter().any(|(t, _)| t == target) {
                    if let Some(name) = target.file_name() {
                        note(&mut guard, &format!("new {}", name.to_string_lossy()));
                    }
                }
            }
            note(&mut guard, "renaming");
        }
        stall_for_tests("staged");
        for (i, (temporary, target)) in pairs.into_iter().enumerate() {
            let mut guard = lock(state);
            fs::rename(&temporary, &target)
                .map_err(|e| format!("cannot rename into {}: {e}", target.display()))?;
            let staged = staged(&mut guard);
            staged.temporaries.retain(|t| *t != temporary);
            staged.renamed.push(target);
            drop(guard);
            if i == 0 {
                stall_for_tests("renaming");
            }
        }
        for target in removals {
            let mut guard = lock(state);
            fs::remove_file(&target)
                .map_err(|e| format!("cannot remove {}: {e}", target.display()))?;
            staged(&mut guard).removed.push(target);
        }
        let mut guard = lock(state);
        staged(&mut guard).committed = true;
        note(&mut guard, "committed");
        Ok(())
    }

    /// Removes temporaries and backups; after a failure, first restores or
    /// removes the targets renamed so far and puts removed files back.
    /// Leaves the state empty (a second call does nothing).
    fn clean_up(&mut self) {
        if !self.committed {
            for target in self.renamed.iter().rev().chain(&self.removed) {
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
        for path in self.temporaries.drain(..) {
            let _ = fs::remove_file(path);
        }
        for (_, backup) in self.backups.drain(..) {
            let _ = fs::remove_file(backup);
        }
        self.renamed.clear();
        self.removed.clear();
    }
}

/// For the interrupt and kill tests only: `MICROMAP_INDEX_TEST_STALL_MS=N`
/// waits N milliseconds at the phase `MICROMAP_INDEX_TEST_STALL_AT` names:
/// `staged` (the default: temporaries and backups written, before the first
/// rename, the moment with the most to clean up), `renaming` (after the
/// first rename) or `written` (every rename done and the lock released,
/// before the command prints).
fn stall_for_tests(phase: &str) {
    let at = std::env::var("MICROMAP_INDEX_TEST_STALL_AT");
    if at.as_deref().unwrap_or("staged") != phase {
        return;
    }
    if let Some(ms) = std::env::var("MICROMAP_INDEX_TEST_STALL_MS")
        .ok()
        .and_then(|v| v.parse::<u64>().ok())
    {
        std::thread::sleep(std::time::Duration::from_millis(ms));
    }
}

/// Why [`Destination::claim`] refused a directory.
pub enum Refusal {
    /// The destination itself is wrong (exit 2): an empty path, not a
    /// directory, an existing output without `--force`.
    Refused(String),
    /// Another writer holds the lock, or the directory or the lock cannot be
    /// created (exit 3).
    Io(String),
}

/// A destination directory held for one writer: created if needed, locked,
/// checked; released (lock removed, the directories it created removed
/// when still empty, anything staged rolled back) when dropped or
/// interrupted.
pub struct Destination {
    state: Arc<Mutex<Held>>,
}

/// What a [`Destination`] has to undo.
struct Held {
    dir: PathBuf,
    /// The lock, until released.
    lock: Option<DirLock>,
    /// Directories this writer created, outermost first.
    created: Vec<PathBuf>,
    staged: Staged,
}

impl Held {
    /// Rolls back what was not committed, removes the lock and (when nothing
    /// was committed) the directories it created if they are empty.
    fn release(&mut self) {
        let committed = self.staged.committed;
        self.staged.clean_up();
        if let Some(lock) = self.lock.take() {
            lock.release();
        }
        if !committed {
            for dir in self.created.drain(..).rev() {
                // Fails (and keeps it) when something else is inside.
                let _ = fs::remove_dir(dir);
            }
        }
        self.created.clear();
    }
}

/// The destinations held now, for the interrupt handler.
static HELD: Mutex<Vec<Arc<Mutex<Held>>>> = Mutex::new(Vec::new());

/// The directories this process has written completely (committed), for
/// the interrupt handler's message after the files are in place.
static WRITTEN: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

impl Destination {
    /// Creates `dir` (and missing parents) if needed, takes its lock and
    /// checks it as [`check_destination`] does, all before anything is read
    /// or written. A second writer into the same directory (another `bake`
    /// still running) gets [`Refusal::Io`] naming the lock and its holder.
    pub fn claim(dir: &Path, names: &[&str], force: bool) -> Result<Destination, Refusal> {
        if dir.as_os_str().is_empty() {
            return Err(Refusal::Refused(
                "--out needs a directory path, got an empty one".into(),
            ));
        }
        if fs::metadata(dir).is_ok_and(|m| !m.is_dir()) {
            return Err(Refusal::Refused(format!(
                "--out {} exists and is not a directory",
                dir.display()
            )));
        }
        let held = Arc::new(Mutex::new(Held {
            dir: dir.to_path_buf(),
            lock: None,
            created: Vec::new(),
            staged: Staged::default(),
        }));
        lock(&HELD).push(Arc::clone(&held));
        // From here on, dropping `destination` undoes what was done.
        let destination = Destination { state: held };
        destination.create_dirs(dir)?;
        let lock_path = dir.join(LOCK_NAME);
        match DirLock::acquire(dir) {
            Ok((held_lock, stale)) => {
                if let Some(stale) = stale {
                    stale.recover(dir, names);
                }
                lock(&destination.state).lock = Some(held_lock);
            }
            Err(LockError::Held(holder)) => {
                let holder = if holder.is_empty() {
                    String::new()
                } else {
                    format!(", held by process {holder}")
                };
                return Err(Refusal::Io(format!(
                    "{} is in use by another bake (lock {}{holder}); nothing written",
                    dir.display(),
                    lock_path.display()
                )));
            }
            Err(LockError::Io(e)) => {
                return Err(Refusal::Io(format!(
                    "cannot create the lock {}: {e}; nothing written",
                    lock_path.display()
                )))
            }
        }
        check_destination(dir, names, force).map_err(Refusal::Refused)?;
        Ok(destination)
    }

    /// Creates `dir` and its missing parents, recording each one created.
    fn create_dirs(&self, dir: &Path) -> Result<(), Refusal> {
        let mut missing = Vec::new();
        let mut at = Some(dir);
        while let Some(path) = at {
            if path.as_os_str().is_empty() || fs::symlink_metadata(path).is_ok() {
                break;
            }
            missing.push(path.to_path_buf());
            at = path.parent();
        }
        for path in missing.into_iter().rev() {
            match fs::create_dir(&path) {
                Ok(()) => lock(&self.state).created.push(path),
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists && path.is_dir() => {}
                Err(e) => {
                    return Err(Refusal::Io(format!(
                        "cannot create {}: {e}; nothing written",
                        path.display()
                    )))
                }
            }
        }
        Ok(())
    }

    /// Writes `files` into the directory and removes the existing files
    /// named in `remove` (outputs this run does not produce, so that no
    /// stale one is left beside the new ones): all of it, or (after an
    /// error, which the message describes) nothing.
    pub fn write(
        &self,
        files: &[(String, impl AsRef<[u8]>)],
        remove: &[&str],
    ) -> Result<(), String> {
        let dir = lock(&self.state).dir.clone();
        let result = Staged::write(
            &self.state,
            |h| &mut h.staged,
            |h, line| {
                if let Some(journal) = &mut h.lock {
                    journal.note(line);
                }
            },
            &dir,
            files,
            remove,
        );
        let mut held = lock(&self.state);
        if result.is_ok() {
            sync_dir(&dir);
            lock(&WRITTEN).push(dir);
        }
        held.release();
        drop(held);
        if result.is_ok() {
            stall_for_tests("written");
        }
        result
    }
}

impl Drop for Destination {
    fn drop(&mut self) {
        lock(&self.state).release();
        lock(&HELD).retain(|h| !Arc::ptr_eq(h, &self.state));
    }
}

/// Catches Ctrl-C (SIGINT) for a writer of [`Destination`]s, then exits
/// 130. A held destination whose renames are not all done is rolled back
/// and released (temporaries, backups, the lock, the directories created):
/// it holds its old set, and the message says "nothing written"; one whose
/// renames are all done keeps the new set, and the message says it was
/// written. The handler takes each destination's lock, so it runs between
/// two steps of a write, and never gives it back (it exits), so no step
/// follows it. `first` runs before anything else (`bake` clears its
/// progress bar, so that the message starts on a clean line); the message
/// is reported as `program`'s.
pub fn install_interrupt_handler(program: Program, first: fn()) -> Result<(), String> {
    ctrlc::set_handler(move || {
        first();
        let held = lock(&HELD);
        let mut guards: Vec<_> = held.iter().map(|h| lock(h)).collect();
        let mut written = lock(&WRITTEN).clone();
        let mut rolled_back = Vec::new();
        for guard in &mut guards {
            if guard.staged.committed {
                if !written.contains(&guard.dir) {
                    written.push(guard.dir.clone());
                }
            } else {
                rolled_back.push(guard.dir.clone());
            }
            guard.release();
        }
        if written.is_empty() {
            match rolled_back.as_slice() {
                [dir] => program.report(format_args!(
                    "interrupted; nothing written: {} holds what it held before",
                    dir.display()
                )),
                _ => program.report("interrupted; nothing written"),
            }
        } else {
            let dirs: Vec<String> = written.iter().map(|d| d.display().to_string()).collect();
            program.report(format_args!(
                "interrupted after the output was written: {} holds the new files",
                dirs.join(", ")
            ));
        }
        std::process::exit(130);
    })
    .map_err(|e| format!("cannot catch Ctrl-C ({e})"))
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

    /// One process, two claims on one directory: the second is refused
    /// while the first holds it, and succeeds once the first is dropped;
    /// the first's directory (created by it, still empty) is then removed.
    #[test]
    fn a_claimed_directory_is_refused_until_released() {
        let parent = scratch("claim");
        let dir = parent.join("made");
        let first = Destination::claim(&dir, &["a"], false).ok().unwrap();
        assert_eq!(listing(&dir), [LOCK_NAME]);
        match Destination::claim(&dir, &["a"], true) {
            Err(Refusal::Io(e)) => assert!(e.contains("is in use by another bake"), "{e}"),
            _ => panic!("a second claim was not refused"),
        }
        drop(first);
        assert!(!dir.exists(), "the created directory is left");
        let again = Destination::claim(&dir, &["a"], false).ok().unwrap();
        again.write(&files(&["a"]), &["gone"]).unwrap();
        assert_eq!(listing(&dir), ["a"]);
        drop(again);
        assert_eq!(listing(&dir), ["a"]);
        let _ = fs::remove_dir_all(&parent);
    }
}
