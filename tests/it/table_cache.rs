//! The reflectivity tables' disk cache (src/xray/table_cache.rs): a second build
//! reads what the first wrote and gives the same images bit for bit; a damaged
//! file is rebuilt; two runs filling an empty cache at once both succeed and
//! leave whole files; `TRAXER_CACHE=off` writes nothing; the note about building
//! appears when a table is built, and never with `-q`.

use crate::common::{repo, run_ok, traxer};
use std::path::Path;

/// `traxer trace` of the Wolter-I scene (two coatings' tables) with the cache in
/// `cache`; returns (stderr, the image's bytes).
fn trace(cache: &str, out: &Path, quiet: bool) -> (String, Vec<u8>) {
    let mut cmd = traxer();
    cmd.env("TRAXER_CACHE", cache)
        .arg("trace")
        .arg(repo().join("scenes/wolter1_parallel.toml"))
        .args(["-n", "20000", "-D", "coating=gold", "--out"])
        .arg(out);
    if quiet {
        cmd.arg("-q");
    }
    let o = run_ok(&mut cmd);
    let image = std::fs::read(out.join("sensor.npy")).unwrap();
    (String::from_utf8_lossy(&o.stderr).into_owned(), image)
}

fn tables(cache: &Path) -> Vec<std::path::PathBuf> {
    match std::fs::read_dir(cache.join("reflectivity")) {
        Ok(d) => d.map(|e| e.unwrap().path()).collect(),
        Err(_) => Vec::new(),
    }
}

#[test]
fn a_second_build_reads_the_tables_and_traces_the_same_photons() {
    let tmp = tempfile::tempdir().unwrap();
    let cache = tmp.path().join("cache");
    let c = cache.to_str().unwrap();
    let (note, first) = trace(c, &tmp.path().join("a"), false);
    assert!(
        note.contains("building the reflectivity table of coating `gold`"),
        "{note}"
    );
    assert!(note.contains("kept in"), "{note}");
    let files = tables(&cache);
    assert!(!files.is_empty());
    let (note, second) = trace(c, &tmp.path().join("b"), false);
    assert!(
        !note.contains("building"),
        "the second build rebuilt: {note}"
    );
    assert_eq!(first, second, "the cached table changed the image");
    // A damaged file (one flipped byte) is noticed by its checksum and rebuilt.
    let mut bytes = std::fs::read(&files[0]).unwrap();
    let mid = bytes.len() / 2;
    bytes[mid] ^= 0x40;
    std::fs::write(&files[0], &bytes).unwrap();
    let (note, third) = trace(c, &tmp.path().join("c"), false);
    assert!(
        note.contains("building"),
        "a damaged table was used: {note}"
    );
    assert_eq!(first, third);
    // A truncated file too.
    let bytes = std::fs::read(&files[0]).unwrap();
    std::fs::write(&files[0], &bytes[..bytes.len() / 3]).unwrap();
    let (note, fourth) = trace(c, &tmp.path().join("d"), true);
    assert_eq!(note, "", "-q must keep the note to itself");
    assert_eq!(first, fourth);
    // Off: no cache written, the note says nothing about keeping it.
    let off = tmp.path().join("off");
    let (note, fifth) = trace("off", &off, false);
    assert!(
        note.contains("building") && !note.contains("kept in"),
        "{note}"
    );
    assert_eq!(first, fifth);
}

#[test]
fn runs_filling_an_empty_cache_at_once_both_succeed_and_leave_whole_tables() {
    let tmp = tempfile::tempdir().unwrap();
    let cache = tmp.path().join("cache");
    let spawn = |out: &str| {
        traxer()
            .env("TRAXER_CACHE", &cache)
            .arg("trace")
            .arg(repo().join("scenes/wolter1_parallel.toml"))
            .args(["-n", "20000", "-D", "coating=gold", "-q", "--out"])
            .arg(tmp.path().join(out))
            .spawn()
            .unwrap()
    };
    let (mut a, mut b) = (spawn("a"), spawn("b"));
    assert!(a.wait().unwrap().success() && b.wait().unwrap().success());
    let read = |d: &str| std::fs::read(tmp.path().join(d).join("sensor.npy")).unwrap();
    assert_eq!(read("a"), read("b"));
    // No temporary files left, and the tables read back without a rebuild.
    for f in tables(&cache) {
        assert_eq!(f.extension().and_then(|e| e.to_str()), Some("bin"), "{f:?}");
    }
    let (note, again) = trace(cache.to_str().unwrap(), &tmp.path().join("c"), false);
    assert!(!note.contains("building"), "{note}");
    assert_eq!(again.len(), read("a").len());
}

#[test]
fn traxer_cache_lists_marks_use_and_clears_only_its_tables() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let c = cache.to_str().unwrap();
    trace(c, &dir.path().join("a"), true);
    let files = tables(&cache);
    assert!(!files.is_empty());
    // A file that is not a table stays whatever the command does.
    std::fs::write(cache.join("reflectivity/notes.txt"), "mine").unwrap();
    // Reading a table marks it used: an old time becomes now.
    let old = std::time::SystemTime::UNIX_EPOCH + std::time::Duration::from_secs(1_000_000_000);
    for f in &files {
        let file = std::fs::File::options().append(true).open(f).unwrap();
        file.set_modified(old).unwrap();
    }
    trace(c, &dir.path().join("b"), true);
    let list = |args: &[&str]| {
        let o = run_ok(traxer().env("TRAXER_CACHE", c).arg("cache").args(args));
        String::from_utf8(o.stdout).unwrap()
    };
    let v: serde_json::Value = serde_json::from_str(&list(&["--json"])).unwrap();
    let listed = v["tables"].as_array().unwrap();
    assert_eq!(listed.len(), files.len(), "{v}");
    let bytes: u64 = files
        .iter()
        .map(|f| std::fs::metadata(f).unwrap().len())
        .sum();
    assert!((v["total_mb"].as_f64().unwrap() - bytes as f64 / 1e6).abs() < 1e-9);
    for t in listed {
        assert!(t["hours_since_used"].as_f64().unwrap() < 1.0, "{t}");
    }
    let cleared = list(&["--clear"]);
    assert!(
        cleared.contains(&format!("removed {} table", files.len())),
        "{cleared}"
    );
    let left: Vec<_> = tables(&cache);
    assert_eq!(left, vec![cache.join("reflectivity/notes.txt")]);
}

#[test]
fn the_cache_keeps_within_its_bound_by_dropping_the_least_recently_used() {
    // Each coating is one table. With a bound of 1 byte a second coating's
    // table replaces the first (the one just written stays even above the
    // bound); with the default bound the next one is added.
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let build = |coating: &str, bound: Option<&str>| {
        let mut c = traxer();
        c.env("TRAXER_CACHE", &cache)
            .env_remove("TRAXER_CACHE_MAX_MB");
        if let Some(b) = bound {
            c.env("TRAXER_CACHE_MAX_MB", b);
        }
        c.arg("trace")
            .arg(repo().join("scenes/wolter1_parallel.toml"))
            .args(["-n", "2000", "-q", "--replace", "-D"])
            .arg(format!("coating={coating}"))
            .arg("-o")
            .arg(dir.path().join("o"));
        run_ok(&mut c);
        tables(&cache)
    };
    let gold = build("gold", Some("0.000001"));
    assert_eq!(gold.len(), 1);
    let recipe = build("llnl_recipe_1", Some("0.000001"));
    assert_eq!(recipe.len(), 1);
    assert_ne!(gold, recipe, "the older table went, the new one stayed");
    assert_eq!(build("gold", None).len(), 2);
}
