//! Atomic writes: whole files or nothing, unique temporary names.

use traxer::files::atomic_write;

/// Names in `dir` other than `keep`.
fn others(dir: &std::path::Path, keep: &str) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != keep)
        .collect()
}

#[test]
fn concurrent_writers_of_one_path_leave_one_whole_file_and_no_temporaries() {
    // Eight threads of one process write the same path at once, each a file of
    // its own byte repeated: with a temporary name shared by the process (the old
    // `.NAME.tmp-PID`) they wrote into one file and renamed it under each other.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("image.npy");
    let size = 1 << 20;
    std::thread::scope(|s| {
        for k in 0..8u8 {
            let path = &path;
            s.spawn(move || {
                for _ in 0..5 {
                    atomic_write(path, &vec![b'a' + k; size]).unwrap();
                }
            });
        }
    });
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(bytes.len(), size);
    assert!(
        bytes.iter().all(|&b| b == bytes[0]),
        "the file mixes two writers"
    );
    assert!(others(dir.path(), "image.npy").is_empty());
}

#[test]
fn a_failed_write_leaves_the_old_file_and_no_temporary() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("summary.json");
    atomic_write(&path, b"old").unwrap();
    // A folder cannot be renamed over: the write fails after the data is written.
    let blocked = dir.path().join("sub");
    std::fs::create_dir(&blocked).unwrap();
    std::fs::write(blocked.join("x"), b"x").unwrap();
    let e = atomic_write(&blocked, b"new").unwrap_err();
    assert!(e.to_string().contains("sub"), "{e}");
    assert_eq!(std::fs::read(&path).unwrap(), b"old");
    let mut left = others(dir.path(), "summary.json");
    left.sort();
    assert_eq!(left, ["sub"]);
}

#[cfg(unix)]
#[test]
fn written_files_are_readable_by_others_as_with_a_plain_create() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let plain = dir.path().join("plain");
    std::fs::write(&plain, b"x").unwrap();
    let atomic = dir.path().join("atomic");
    atomic_write(&atomic, b"x").unwrap();
    let mode = |p: &std::path::Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode(&atomic), mode(&plain));
}
