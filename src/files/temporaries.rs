//! Temporary files and folders that exist only while traxer writes: registered
//! here so that a signal handler (in the binary) can remove them before the
//! process exits, leaving neither partial nor temporary files behind.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
/// Folders made for results that are still empty: removed only if still empty.
static EMPTY_FOLDERS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Records `path` as temporary until [`forget`] is called for it.
pub fn register(path: &Path) {
    if let Ok(mut t) = TEMPORARIES.lock() {
        t.push(path.to_path_buf());
    }
}

/// Records a folder traxer created for results, to be removed if it is still
/// empty when the process stops on a signal.
pub fn register_new_folder(path: &Path) {
    if let Ok(mut t) = EMPTY_FOLDERS.lock() {
        t.push(path.to_path_buf());
    }
}

/// `path` is no longer temporary (it was renamed into place or removed).
pub fn forget(path: &Path) {
    if let Ok(mut t) = TEMPORARIES.lock() {
        t.retain(|p| p != path);
    }
    if let Ok(mut t) = EMPTY_FOLDERS.lock() {
        t.retain(|p| p != path);
    }
}

/// Removes every registered temporary file and folder (for a process about to
/// exit on a signal). Never blocks on a writer that holds the list: a lock that
/// cannot be had at once is skipped.
pub fn remove_all() {
    let paths = match TEMPORARIES.try_lock() {
        Ok(mut t) => std::mem::take(&mut *t),
        Err(_) => return,
    };
    for p in paths {
        let _ = if p.is_dir() {
            std::fs::remove_dir_all(&p)
        } else {
            std::fs::remove_file(&p)
        };
    }
    if let Ok(mut t) = EMPTY_FOLDERS.try_lock() {
        for p in std::mem::take(&mut *t) {
            let _ = std::fs::remove_dir(&p); // fails, as it should, if not empty
        }
    }
}
