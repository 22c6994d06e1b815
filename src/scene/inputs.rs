//! The files a scene reads besides itself (mesh files and their glTF buffers, a
//! telescope's data file, a Sun's emission table), each with its SHA-256.
//!
//! Data flow: the builders note every file they read ([`InputFiles::note`]);
//! `build` hashes them once the scene stands ([`InputFiles::hashed`]) into
//! `Scene::inputs`, which a run's identity (`run::RunIdentity`) and the
//! studies' records carry: merging shards, resuming a run or a study whose
//! inputs changed in between is refused, naming the file. Shipped data (coatings,
//! telescope, built-in emissions) is compiled in and covered by the build's
//! version.

use crate::files::sha256_hex;
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Input file name (relative to the scene's folder where it lies inside it) →
/// SHA-256 of its bytes.
pub type InputHashes = BTreeMap<String, String>;

/// The files read while building one scene.
#[derive(Default)]
pub struct InputFiles {
    files: RefCell<Vec<PathBuf>>,
}

impl InputFiles {
    /// `path` was read.
    pub fn note(&self, path: &Path) {
        let mut files = self.files.borrow_mut();
        if !files.iter().any(|f| f == path) {
            files.push(path.to_path_buf());
        }
    }

    /// The files' names as seen from `dir` (the scene's folder) and their
    /// hashes; or the file that cannot be read again.
    pub fn hashed(self, dir: &Path) -> Result<InputHashes, String> {
        let mut hashes = InputHashes::new();
        for path in self.files.into_inner() {
            let bytes = std::fs::read(&path)
                .map_err(|e| format!("{}: cannot read it again to hash it: {e}", path.display()))?;
            hashes.insert(display_name(dir, &path), sha256_hex(&bytes));
        }
        Ok(hashes)
    }
}

/// `path` relative to `dir` if it lies inside it (as the scene names it), else
/// as it is.
fn display_name(dir: &Path, path: &Path) -> String {
    let relative = if dir.as_os_str().is_empty() {
        path
    } else {
        path.strip_prefix(dir).unwrap_or(path)
    };
    relative.display().to_string()
}

/// The first input that differs between two runs (`ours`, `theirs`), said for
/// a person in the style of `RunIdentity::difference`: "input file
/// meshes/a.glb with SHA-256 0a1b2c3d4e5f, not 9f8e7d6c5b4a".
pub fn input_difference(ours: &InputHashes, theirs: &InputHashes) -> Option<String> {
    let short = |h: &str| h.chars().take(12).collect::<String>();
    for (name, hash) in ours {
        match theirs.get(name) {
            None => return Some(format!("input file {name} read, not left unread")),
            Some(h) if h != hash => {
                return Some(format!(
                    "input file {name} with SHA-256 {}, not {}",
                    short(hash),
                    short(h)
                ))
            }
            Some(_) => {}
        }
    }
    theirs
        .keys()
        .find(|name| !ours.contains_key(*name))
        .map(|name| format!("input file {name} unread, not read"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hashes(pairs: &[(&str, &str)]) -> InputHashes {
        pairs
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect()
    }

    #[test]
    fn differences_name_the_file() {
        let then = hashes(&[("a.glb", "111"), ("b.csv", "222")]);
        assert_eq!(input_difference(&then, &then), None);
        let changed = hashes(&[("a.glb", "111"), ("b.csv", "333")]);
        assert!(input_difference(&then, &changed)
            .unwrap()
            .contains("input file b.csv with SHA-256 222, not 333"));
        let fewer = hashes(&[("a.glb", "111")]);
        assert!(input_difference(&then, &fewer).unwrap().contains("b.csv"));
        assert!(input_difference(&fewer, &then).unwrap().contains("b.csv"));
    }

    #[test]
    fn names_are_relative_to_the_scene_folder() {
        assert_eq!(
            display_name(Path::new("scenes"), Path::new("scenes/meshes/a.glb")),
            "meshes/a.glb"
        );
        assert_eq!(display_name(Path::new(""), Path::new("a.glb")), "a.glb");
        assert_eq!(
            display_name(Path::new("scenes"), Path::new("/data/a.glb")),
            "/data/a.glb"
        );
    }
}
