//! Files on disk, at the bottom of every data flow: atomic writes, checks of
//! output locations before any work, and content hashes. Everything traxer writes
//! (images, tables, plots, meshes, sidecars) goes through [`atomic_write`], which
//! only ever replaces regular files; commands call [`check_output_dir`] or
//! [`check_output_file`] before tracing, so that a location that cannot take the
//! results is refused at once; scenes and provenance hash with [`sha256_hex`].
//! This module uses no other part of traxer.

mod folder;
pub mod temporaries;

pub use folder::{OutputFolder, MANIFEST};

use sha2::{Digest, Sha256};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The temporary name of `NAME` is `.NAME.XXXXXX.tmp`.
const TEMPORARY_SUFFIX: &str = ".tmp";
const TEMPORARY_RANDOM_CHARS: usize = 6;
/// How many bytes the temporary name adds to a file's name: file names must
/// stay this far below the file systems' limit.
pub const TEMPORARY_NAME_EXTRA_BYTES: usize = 2 + TEMPORARY_RANDOM_CHARS + TEMPORARY_SUFFIX.len();

/// Writes `bytes` to `path` so that readers see either the old file or the whole
/// new one, never a part: the bytes go to a temporary file with a unique name in
/// the same folder (two writers of one path, even in one process, never share
/// it), are flushed to disk, and the file is renamed over `path`. On failure the
/// temporary file is removed and `path` is untouched.
pub fn atomic_write(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    // A rename would replace a device node, a FIFO or a socket with a regular file.
    if let Ok(m) = std::fs::metadata(path) {
        if !m.is_file() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!(
                    "{}: is {}, not a regular file; traxer only replaces regular files",
                    path.display(),
                    kind(&m)
                ),
            ));
        }
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::InvalidInput, "no file name"))?;
    let with_path =
        |e: std::io::Error| std::io::Error::new(e.kind(), format!("{}: {e}", path.display()));
    // A hidden name that says whose it is, so a file left by a killed process
    // can be recognised.
    let prefix = format!(".{}.", name.to_string_lossy());
    let mut builder = tempfile::Builder::new();
    builder
        .prefix(&prefix)
        .suffix(TEMPORARY_SUFFIX)
        .rand_bytes(TEMPORARY_RANDOM_CHARS);
    // tempfile creates private (0600) files; results are read by others on a
    // cluster, so ask for what `File::create` gives: 0666 less the umask.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut tmp = builder.tempfile_in(dir).map_err(with_path)?;
    // Registered, so that a signal arriving meanwhile removes it too.
    let tmp_path = tmp.path().to_path_buf();
    temporaries::register(&tmp_path);
    let written = tmp.write_all(bytes).and_then(|_| tmp.as_file().sync_all());
    let result = match written {
        Ok(()) => tmp.persist(path).map(drop).map_err(|e| e.error),
        Err(e) => Err(e),
    };
    temporaries::forget(&tmp_path);
    result.map_err(with_path)
}

/// Refuses an output folder `out` that is one of the folders a command reads
/// (`inputs`) or holds one of them: the results replace the output folder's
/// contents, so the command would delete what it read. A folder inside an
/// input (`RUN/signal`, the default) is fine.
pub fn refuse_replacing_inputs(out: &Path, inputs: &[&Path]) -> Result<(), OutputLocationError> {
    let Ok(target) = std::fs::canonicalize(out) else {
        return Ok(()); // does not exist yet: it holds nothing
    };
    for input in inputs {
        let Ok(read) = std::fs::canonicalize(input) else {
            continue;
        };
        if read.starts_with(&target) {
            let what = if read == target {
                "is".to_string()
            } else {
                format!("holds {}, which", input.display())
            };
            return Err(OutputLocationError {
                path: out.to_path_buf(),
                message: format!(
                    "the output folder {what} is a folder this command reads ({}): the results replace the output folder's contents and would delete it; give another --out (the default is a folder inside the run)",
                    input.display()
                ),
            });
        }
    }
    Ok(())
}

/// Why an output location cannot take a command's results (exit code 2).
#[derive(Debug, thiserror::Error)]
#[error("{}: {message}", path.display())]
pub struct OutputLocationError {
    pub path: PathBuf,
    pub message: String,
}

/// What a non-regular file is, for messages.
fn kind(m: &std::fs::Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    let t = m.file_type();
    if t.is_dir() {
        "a folder"
    } else if t.is_char_device() || t.is_block_device() {
        "a device"
    } else if t.is_fifo() {
        "a named pipe"
    } else if t.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

/// Checks that `dir` is, or can be created as, a folder this process can write
/// files into: the nearest existing ancestor must be a folder (not a file in the
/// way) and writable (a temporary file is made in it and removed).
fn check_writable_folder(dir: &Path) -> Result<(), OutputLocationError> {
    let fail = |path: &Path, message: String| OutputLocationError {
        path: path.to_path_buf(),
        message,
    };
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    let mut existing = dir;
    while std::fs::metadata(existing).is_err() {
        match existing.parent() {
            Some(p) if !p.as_os_str().is_empty() => existing = p,
            _ => {
                existing = Path::new(".");
                break;
            }
        }
    }
    let m = std::fs::metadata(existing).map_err(|e| fail(existing, e.to_string()))?;
    if !m.is_dir() {
        let what = if m.is_file() { "a file" } else { kind(&m) };
        return Err(if existing == dir {
            fail(dir, format!("is {what}, not a folder"))
        } else {
            fail(
                dir,
                format!("cannot be created: {} is {what}", existing.display()),
            )
        });
    }
    tempfile::Builder::new()
        .prefix(".traxer-write-check")
        .tempfile_in(existing)
        .map(drop)
        .map_err(|e| fail(existing, format!("cannot write there: {e}")))
}

/// Checks, before any work, that `path` can receive an output file: its folder
/// exists or can be created and is writable, and `path` is a new name or a
/// regular file (never a folder, device, pipe or socket).
pub fn check_output_file(path: &Path) -> Result<(), OutputLocationError> {
    if let Ok(m) = std::fs::metadata(path) {
        if !m.is_file() {
            return Err(OutputLocationError {
                path: path.to_path_buf(),
                message: format!(
                    "is {}; give a file name (traxer only replaces regular files)",
                    kind(&m)
                ),
            });
        }
    }
    if path.file_name().is_none() {
        return Err(OutputLocationError {
            path: path.to_path_buf(),
            message: "is not a file name".into(),
        });
    }
    check_writable_folder(path.parent().unwrap_or(Path::new(".")))
}

/// Checks, before any work, that `dir` can receive the files `names`: it is (or
/// can be created as) a writable folder, and none of the names is there as
/// anything but a regular file.
pub fn check_output_dir<S: AsRef<str>>(dir: &Path, names: &[S]) -> Result<(), OutputLocationError> {
    check_writable_folder(dir)?;
    for n in names {
        let p = dir.join(n.as_ref());
        if let Ok(m) = std::fs::metadata(&p) {
            if !m.is_file() {
                return Err(OutputLocationError {
                    path: p,
                    message: format!("is {}, in the way of an output file of that name", kind(&m)),
                });
            }
        }
    }
    Ok(())
}

/// Creates `dir` and its parents if missing; the error names the folder.
pub fn create_dir_all(dir: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)
        .map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", dir.display())))
}

/// SHA-256 of `bytes`, as 64 lowercase hex digits.
pub fn sha256_hex(bytes: &[u8]) -> String {
    let digest = Sha256::digest(bytes);
    digest.iter().map(|b| format!("{b:02x}")).collect()
}
