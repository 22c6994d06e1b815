//! A new user's toolchain: the declared minimum Rust is the true one, and the
//! setup script refuses an older rustc with a way out, before any build.

use crate::common::repo;

/// "1.88.0" → (1, 88, 0).
fn version(s: &str) -> (u32, u32, u32) {
    let mut it = s.trim().split('.').map(|x| x.parse::<u32>().unwrap_or(0));
    (
        it.next().unwrap_or(0),
        it.next().unwrap_or(0),
        it.next().unwrap_or(0),
    )
}

#[test]
fn declared_rust_version_covers_every_locked_dependency() {
    let manifest: toml::Table =
        toml::from_str(&std::fs::read_to_string(repo().join("Cargo.toml")).unwrap()).unwrap();
    let declared = version(manifest["package"]["rust-version"].as_str().unwrap());
    let lock: toml::Table =
        toml::from_str(&std::fs::read_to_string(repo().join("Cargo.lock")).unwrap()).unwrap();
    // The sources cargo unpacked for this build.
    let home = std::env::var_os("CARGO_HOME")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| std::path::PathBuf::from(std::env::var("HOME").unwrap()).join(".cargo"));
    let registries: Vec<_> = std::fs::read_dir(home.join("registry/src"))
        .map(|d| d.map(|e| e.unwrap().path()).collect())
        .unwrap_or_default();
    let mut checked = 0;
    let mut highest = ((0, 0, 0), String::new());
    for p in lock["package"].as_array().unwrap() {
        if p.get("source").is_none() {
            continue; // traxer itself
        }
        let (name, v) = (p["name"].as_str().unwrap(), p["version"].as_str().unwrap());
        let Some(text) = registries
            .iter()
            .find_map(|r| std::fs::read_to_string(r.join(format!("{name}-{v}/Cargo.toml"))).ok())
        else {
            continue; // not built on this platform
        };
        checked += 1;
        let m: toml::Table = toml::from_str(&text).unwrap();
        if let Some(rv) = m
            .get("package")
            .and_then(|p| p.get("rust-version"))
            .and_then(|v| v.as_str())
        {
            if version(rv) > highest.0 {
                highest = (version(rv), format!("{name} {v}"));
            }
        }
    }
    assert!(checked > 50, "only {checked} dependency sources found");
    assert!(
        declared >= highest.0,
        "Cargo.toml declares rust-version {declared:?}, but {} needs {:?}",
        highest.1,
        highest.0
    );
}

#[test]
fn setup_refuses_a_rustc_older_than_declared() {
    let dir = tempfile::tempdir().unwrap();
    for (tool, out) in [
        ("rustc", "rustc 1.75.0 (82e1608df 2023-12-21)"),
        ("cargo", "cargo 1.75.0"),
    ] {
        let p = dir.path().join(tool);
        std::fs::write(&p, format!("#!/bin/sh\necho '{out}'\n")).unwrap();
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    let path = format!(
        "{}:{}",
        dir.path().display(),
        std::env::var("PATH").unwrap()
    );
    let out = std::process::Command::new("bash")
        .arg(repo().join("scripts/setup.sh"))
        .env("PATH", path)
        // Embree and libclang are not the question here.
        .env("EMBREE_DIR", "/nonexistent")
        .env("LIBCLANG_PATH", "/nonexistent")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("1.75.0") && err.contains("rustup"), "{err}");
    // The real toolchain passes.
    let out = std::process::Command::new("bash")
        .arg(repo().join("scripts/setup.sh"))
        .env("EMBREE_DIR", "/nonexistent")
        .env("LIBCLANG_PATH", "/nonexistent")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
