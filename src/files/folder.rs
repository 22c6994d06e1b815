//! A results folder that holds exactly one run's results, complete, or is left
//! untouched.
//!
//! The design (issue 14): the files of a run are written into a fresh staging
//! folder beside the target (`.NAME.traxer-PID-XXXXXX`, same file system), and
//! only when every file is written is the staging folder swapped with the target
//! in one atomic step (Linux `renameat2(RENAME_EXCHANGE)`; a new or empty target
//! is simply replaced by a rename). Readers therefore see the previous run's
//! complete results or the new run's, never a mix; a run that fails or is stopped
//! leaves the target as it was and removes its staging folder (a signal handler
//! in the binary removes it too; one left by SIGKILL is removed by the next run
//! into the same place). A second run into a folder that a running traxer holds
//! (an exclusive `flock` on the target folder, taken before any work) is refused
//! at once. A target that holds files traxer did not write is refused before any
//! work, so a results folder swap never throws away someone's notes.
//!
//! Chosen over "a lock plus a manifest written last" because that leaves a mix
//! of old and new files on disk after a crash between two renames, which a
//! reader can only detect, not avoid.

use super::temporaries;
use super::OutputLocationError;
use std::ffi::OsString;
use std::fs::File;
use std::path::{Path, PathBuf};

/// The hidden list of a results folder's files, written by every run: how the
/// next run knows that replacing the folder throws away only traxer's files.
pub const MANIFEST: &str = ".traxer-files";

/// A results folder being written; see the module documentation.
pub struct OutputFolder {
    target: PathBuf,
    staging: Option<tempfile::TempDir>,
    /// The target did not exist: it is removed again if the run writes nothing.
    created: bool,
    /// Keeps the target locked against other traxer runs until the swap.
    _lock: File,
}

fn fail(path: &Path, message: impl Into<String>) -> OutputLocationError {
    OutputLocationError {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// Staging folders of processes that no longer run, beside `target`.
fn remove_stale_staging(parent: &Path, prefix: &str) {
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(rest) = name.strip_prefix(prefix) else {
            continue;
        };
        let pid = rest.split('-').next().and_then(|p| p.parse::<u32>().ok());
        if pid
            .is_some_and(|p| p != std::process::id() && !Path::new(&format!("/proc/{p}")).exists())
        {
            let _ = std::fs::remove_dir_all(e.path());
        }
    }
}

/// Entries of a results folder that belong to other traxer results and stay:
/// nested results folders (e.g. `out/focus` inside `out`) and
/// the staging folders of runs writing them.
fn kept_entries(dir: &Path) -> Vec<OsString> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    entries
        .flatten()
        .filter(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            let path = e.path();
            path.is_dir()
                && (path.join(MANIFEST).is_file()
                    || name.starts_with('.') && name.contains(".traxer-"))
        })
        .map(|e| e.file_name())
        .collect()
}

/// Whether `dir` is a folder that another running traxer holds (its exclusive
/// lock, taken by [`OutputFolder::prepare`]).
fn held_by_a_running_traxer(dir: &Path) -> bool {
    dir.is_dir()
        && File::open(dir).is_ok_and(|f| {
            matches!(
                rustix::fs::flock(&f, rustix::fs::FlockOperation::NonBlockingLockShared),
                Err(rustix::io::Errno::WOULDBLOCK)
            )
        })
}

/// Whether `file` is a temporary file [`super::atomic_write`] makes for one of
/// `names` (`.NAME.XXXXXX.tmp`): files written straight into a results folder
/// (a run's checkpoint) leave one behind when the process is killed mid-write.
fn is_temporary_of<S: AsRef<str>>(file: &str, names: &[S]) -> bool {
    names.iter().any(|n| {
        file.strip_prefix(&format!(".{}.", n.as_ref()))
            .is_some_and(|rest| rest.ends_with(".tmp"))
    })
}

/// Removes the temporary files of killed writers of `names` in `dir` (call with
/// the folder's lock held: no live traxer writes there then).
fn remove_stale_temporaries<S: AsRef<str>>(dir: &Path, names: &[S]) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        if is_temporary_of(&e.file_name().to_string_lossy(), names) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// The names in `dir` that no traxer run wrote: not in its manifest, nor among
/// `names` (what this command writes), nor other traxer results kept in it.
fn foreign_files<S: AsRef<str>>(dir: &Path, names: &[S]) -> std::io::Result<Vec<String>> {
    let kept: Vec<String> = kept_entries(dir)
        .iter()
        .map(|n| n.to_string_lossy().into_owned())
        .collect();
    let listed: Vec<String> = std::fs::read_to_string(dir.join(MANIFEST))
        .map(|t| t.lines().map(String::from).collect())
        .unwrap_or_default();
    let mut foreign = Vec::new();
    for e in std::fs::read_dir(dir)? {
        let name = e?.file_name().to_string_lossy().into_owned();
        if name != MANIFEST
            && !listed.contains(&name)
            && !names.iter().any(|n| n.as_ref() == name)
            && !kept.contains(&name)
            && !is_temporary_of(&name, names)
        {
            foreign.push(name);
        }
    }
    foreign.sort();
    Ok(foreign)
}

impl OutputFolder {
    /// Prepares to write the files `names` into the folder `target`: checks the
    /// location (see `check_output_dir`), refuses a target holding files traxer
    /// did not write or held by another running traxer, and makes the staging
    /// folder. Call before any work.
    pub fn prepare<S: AsRef<str>>(
        target: &Path,
        names: &[S],
    ) -> Result<OutputFolder, OutputLocationError> {
        super::check_output_dir(target, names)?;
        let created = !target.exists();
        super::create_dir_all(target).map_err(|e| fail(target, e.to_string()))?;
        if created {
            temporaries::register_new_folder(target);
        }
        let lock = File::open(target).map_err(|e| fail(target, e.to_string()))?;
        let locked = match rustix::fs::flock(
            &lock,
            rustix::fs::FlockOperation::NonBlockingLockExclusive,
        ) {
            Ok(()) => true,
            Err(rustix::io::Errno::WOULDBLOCK) => {
                return Err(fail(
                    target,
                    "another traxer run is writing its results here: wait for it, or choose another output folder",
                ))
            }
            // A file system without locks: the atomic swap still keeps the
            // folder whole, only concurrent runs are not refused.
            Err(_) => false,
        };
        let foreign = foreign_files(target, names).map_err(|e| fail(target, e.to_string()))?;
        // A folder inside that a running traxer holds (a study writing its first
        // results there) is not foreign: it is busy, and this run would swap the
        // folder that holds it.
        let busy: Vec<&String> = foreign
            .iter()
            .filter(|n| held_by_a_running_traxer(&target.join(n)))
            .collect();
        if let Some(first) = busy.first() {
            return Err(fail(
                &target.join(first),
                "a traxer run or study is writing its results here right now: wait for it to finish, then run again (this run would replace the folder that holds it)",
            ));
        }
        // Only if the lock was had: otherwise the file may be a live run's.
        if foreign.is_empty() && locked {
            remove_stale_temporaries(target, names);
        }
        if !foreign.is_empty() {
            let shown = foreign.len().min(5);
            return Err(fail(
                target,
                format!(
                    "holds files traxer did not write ({}{}): the results replace the folder's contents, so choose another output folder or move them",
                    foreign[..shown].join(", "),
                    if shown < foreign.len() { ", ..." } else { "" }
                ),
            ));
        }
        let parent = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let name = target
            .file_name()
            .ok_or_else(|| fail(target, "is not a folder name"))?
            .to_string_lossy()
            .into_owned();
        let prefix = format!(".{name}.traxer-");
        remove_stale_staging(&parent, &prefix);
        let staging = tempfile::Builder::new()
            .prefix(&format!("{prefix}{}-", std::process::id()))
            .tempdir_in(&parent)
            .map_err(|e| fail(&parent, format!("cannot write there: {e}")))?;
        temporaries::register(staging.path());
        Ok(OutputFolder {
            target: target.to_path_buf(),
            staging: Some(staging),
            created,
            _lock: lock,
        })
    }

    /// Where to write the files (the staging folder).
    pub fn path(&self) -> &Path {
        self.staging.as_ref().expect("not committed").path()
    }

    /// The folder the results will be in.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Puts the written files in place, all at once: writes the manifest, then
    /// swaps the staging folder with the target and removes the old contents.
    pub fn commit(mut self) -> std::io::Result<()> {
        let staging = self.staging.take().expect("committed once");
        let mut names: Vec<OsString> = std::fs::read_dir(staging.path())?
            .map(|e| e.map(|e| e.file_name()))
            .collect::<Result<_, _>>()?;
        names.sort();
        let list: String = names
            .iter()
            .map(|n| format!("{}\n", n.to_string_lossy()))
            .collect();
        super::atomic_write(&staging.path().join(MANIFEST), list.as_bytes())?;
        // Other results kept in the folder move along into the new one.
        let mut moved = Vec::new();
        for name in kept_entries(&self.target) {
            let (old, new) = (self.target.join(&name), staging.path().join(&name));
            if let Err(e) = std::fs::rename(&old, &new) {
                for (old, new) in moved {
                    let _ = std::fs::rename(new, old);
                }
                return Err(e);
            }
            moved.push((old, new));
        }
        let from = staging.keep();
        let swapped = rustix::fs::renameat_with(
            rustix::fs::CWD,
            &from,
            rustix::fs::CWD,
            &self.target,
            rustix::fs::RenameFlags::EXCHANGE,
        );
        let result = match swapped {
            // `from` now holds the previous contents.
            Ok(()) => std::fs::remove_dir_all(&from),
            // No atomic exchange here (another OS, some network file systems):
            // move the old folder aside, the new one in, and remove the old one.
            // Between the two renames the folder is briefly absent, never mixed.
            Err(_) => {
                let old = from.with_extension("old");
                std::fs::rename(&self.target, &old).and_then(|_| {
                    match std::fs::rename(&from, &self.target) {
                        Ok(()) => std::fs::remove_dir_all(&old),
                        Err(e) => {
                            let _ = std::fs::rename(&old, &self.target);
                            Err(e)
                        }
                    }
                })
            }
        };
        temporaries::forget(&from);
        temporaries::forget(&self.target);
        let _ = std::fs::remove_dir_all(&from);
        result.map_err(|e| {
            std::io::Error::new(
                e.kind(),
                format!(
                    "{}: cannot put the results in place: {e}",
                    self.target.display()
                ),
            )
        })
    }
}

impl Drop for OutputFolder {
    /// Not committed: the staging folder and everything in it go.
    fn drop(&mut self) {
        if let Some(s) = self.staging.take() {
            temporaries::forget(s.path());
            drop(s);
            if self.created {
                temporaries::forget(&self.target);
                let _ = std::fs::remove_dir(&self.target); // only if still empty
            }
        }
    }
}
