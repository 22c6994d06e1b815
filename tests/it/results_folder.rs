//! A results folder holds exactly one run's results, complete, or is untouched:
//! concurrent runs into one folder, runs that fail or are stopped while writing,
//! and stale files of an earlier run.

use crate::common::{repo, run_fails, run_ok, traxer, write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The seed recorded in a results folder's summary.
fn seed_of(out: &Path) -> u64 {
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    v["provenance"]["seed"].as_u64().unwrap()
}

/// Hidden staging folders and temporary files left in `dir` (and in `dir/out`).
fn leftovers(dir: &Path) -> Vec<PathBuf> {
    let mut v = Vec::new();
    for d in [dir.to_path_buf(), dir.join("out")] {
        if let Ok(entries) = std::fs::read_dir(&d) {
            for e in entries.flatten() {
                let n = e.file_name().to_string_lossy().into_owned();
                if n.contains(".traxer-") && n != ".traxer-files" || n.ends_with(".tmp") {
                    v.push(e.path());
                }
            }
        }
    }
    v
}

/// A trace into `out`, replacing what another run left there (these tests are
/// about how a folder is replaced, not whether).
fn trace(out: &Path, photons: &str, seed: &str) -> Command {
    let mut c = traxer();
    c.arg("trace")
        .arg(repo().join("scenes/panter_al_ka.toml"))
        .args(["-n", photons, "-s", seed, "-q", "--replace", "-o"])
        .arg(out);
    c
}

/// Waits until a staging folder for `out` exists (the run holds the folder).
fn wait_for_staging(dir: &Path) {
    let start = Instant::now();
    while leftovers(dir).is_empty() {
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "no staging folder"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn a_second_run_into_a_folder_being_written_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let mut first = trace(&out, "4000000", "11")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_for_staging(dir.path());
    let err = run_fails(&mut trace(&out, "1000", "12"), 2);
    assert!(err.contains("another traxer run"), "{err}");
    assert!(first.wait().unwrap().success());
    // The folder holds the first run, whole.
    assert_eq!(seed_of(&out), 11);
    assert!(
        leftovers(dir.path()).is_empty(),
        "{:?}",
        leftovers(dir.path())
    );
}

#[test]
fn a_run_that_fails_while_writing_leaves_the_previous_results() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    run_ok(&mut trace(&out, "20000", "1"));
    let before = std::fs::read(out.join("sensor.npy")).unwrap();
    // A file-size limit of 64 KiB: the 8 MB image cannot be written. With
    // SIGXFSZ ignored the write fails (exit 1); without, the kernel kills the
    // process mid-write, as a power cut or SIGKILL would.
    for ignore_signal in [true, false] {
        let script = format!(
            "ulimit -f 64; {} exec \"$0\" \"$@\"",
            if ignore_signal { "trap '' XFSZ;" } else { "" }
        );
        let status = Command::new("bash")
            .args(["-c", &script])
            .arg(env!("CARGO_BIN_EXE_traxer"))
            .args(["trace"])
            .arg(repo().join("scenes/panter_al_ka.toml"))
            .args(["-n", "20000", "-s", "2", "-q", "--replace", "-o"])
            .arg(&out)
            .stderr(Stdio::null())
            .status()
            .unwrap();
        assert!(!status.success());
        assert_eq!(seed_of(&out), 1, "the previous results are intact");
        assert_eq!(std::fs::read(out.join("sensor.npy")).unwrap(), before);
        if ignore_signal {
            assert_eq!(status.code(), Some(1));
            assert!(
                leftovers(dir.path()).is_empty(),
                "{:?}",
                leftovers(dir.path())
            );
        }
    }
    // What the killed run left is removed by the next run into the same place.
    run_ok(&mut trace(&out, "20000", "3"));
    assert_eq!(seed_of(&out), 3);
    assert!(
        leftovers(dir.path()).is_empty(),
        "{:?}",
        leftovers(dir.path())
    );
}

#[test]
fn a_stopped_run_leaves_nothing_behind() {
    for signal in ["INT", "TERM"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let mut run = trace(&out, "1000000000", "1")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        wait_for_staging(dir.path());
        let sent = Instant::now();
        Command::new("kill")
            .args([&format!("-{signal}"), &run.id().to_string()])
            .status()
            .unwrap();
        let status = run.wait().unwrap();
        assert!(
            sent.elapsed() < Duration::from_secs(5),
            "{signal}: {:?}",
            sent.elapsed()
        );
        assert_eq!(status.code(), Some(130), "{signal}");
        assert!(
            leftovers(dir.path()).is_empty(),
            "{signal}: {:?}",
            leftovers(dir.path())
        );
        assert!(
            !out.exists(),
            "{signal}: the folder it made for the results is gone"
        );
    }
}

#[test]
fn a_new_run_replaces_the_whole_folder_and_no_foreign_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let scene = |sensor: &str| {
        format!(
            "[materials.d]\ntype = \"sensor\"\nsize = [2.0, 2.0]\npixels = [8, 8]\n\n[[sources]]\ntype = \"parallel\"\naperture = {{ center = [0, 0, 10], radius = 1.0 }}\nenergy = {{ line = 1.49 }}\n\n[[objects]]\nname = \"{sensor}\"\nmaterial = \"d\"\nshape = {{ type = \"rectangle\", size = [2.0, 2.0] }}\n"
        )
    };
    for sensor in ["first", "second"] {
        let path = write(dir.path(), &format!("{sensor}.toml"), &scene(sensor));
        run_ok(
            traxer()
                .arg("trace")
                .arg(&path)
                .args(["-n", "100", "-q", "--replace", "-o"])
                .arg(&out),
        );
    }
    // Only the second run's files: the first run's sensor files are gone.
    let mut names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert!(names.iter().all(|n| !n.starts_with("first")), "{names:?}");
    assert!(names.contains(&"second.npy".to_string()), "{names:?}");
    // A file traxer did not write is never thrown away: refused before tracing.
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let path = dir.path().join("first.toml");
    let err = run_fails(
        traxer()
            .arg("trace")
            .arg(&path)
            .args(["-n", "100", "-q", "-o"])
            .arg(&out),
        2,
    );
    assert!(err.contains("notes.txt"), "{err}");
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "mine"
    );
    assert!(out.join("second.npy").is_file());
}

#[test]
fn results_nested_in_a_results_folder_are_kept() {
    // Results nest: a trace in `out`, a focus scan in `out/focus`. A new trace
    // replaces its own files and keeps the focus scan.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let scene = repo().join("scenes/wolter1_parallel.toml");
    let trace = |seed: &str| {
        run_ok(
            traxer()
                .arg("trace")
                .arg(&scene)
                .args(["-n", "2000", "-s", seed, "-q", "--replace", "-o"])
                .arg(&out),
        );
    };
    trace("1");
    run_ok(
        traxer()
            .arg("focus")
            .arg(&scene)
            .args(["--var", "focus_shift", "--from=-2", "--to=2", "--steps=4"])
            .args(["-n", "5000", "-q", "-o"])
            .arg(out.join("focus")),
    );
    let scan = std::fs::read(out.join("focus/focus.csv")).unwrap();
    trace("2");
    assert_eq!(seed_of(&out), 2);
    assert_eq!(std::fs::read(out.join("focus/focus.csv")).unwrap(), scan);
    assert!(
        leftovers(dir.path()).is_empty(),
        "{:?}",
        leftovers(dir.path())
    );
}

#[test]
fn without_out_results_go_to_out_scene_with_studies_nested_and_kept() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/wolter1_parallel.toml");
    let run = |args: &[&str]| {
        run_ok(
            traxer()
                .current_dir(dir.path())
                .args(args)
                .arg(&scene)
                .arg("-q"),
        );
    };
    run(&["trace", "-n", "2000"]);
    run(&[
        "focus",
        "--var",
        "focus_shift",
        "--from=-2",
        "--to=2",
        "--steps=4",
        "-n",
        "3000",
    ]);
    let out = dir.path().join("out/wolter1_parallel");
    assert!(out.join("sensor.npy").is_file());
    let scan = std::fs::read(out.join("focus/focus.csv")).unwrap();
    run(&["trace", "-n", "3000", "--replace"]);
    assert_eq!(std::fs::read(out.join("focus/focus.csv")).unwrap(), scan);
    run(&["effective-area", "--energies", "1,2", "-n", "2000"]);
    assert!(out.join("effective_area/effective_area.csv").is_file());
}
