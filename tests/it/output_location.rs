//! Output locations are checked before any work, and only regular files are ever
//! replaced: a `--out` under a regular file, in a place nobody can write, or an
//! output name taken by a folder or a device is refused at once with exit code 2.

use crate::common::{repo, run_fails, traxer, write};
use std::path::Path;
use std::time::{Duration, Instant};

/// Commands with their output argument, given the location to try. The photon
/// counts are large enough that tracing first would take a while.
fn commands(out: &Path) -> Vec<(&'static str, std::process::Command)> {
    let panter = repo().join("scenes/panter_al_ka.toml");
    let wolter = repo().join("scenes/wolter1_parallel.toml");
    let mut v = Vec::new();
    let mut c = traxer();
    c.arg("trace")
        .arg(&panter)
        .args(["-n", "3000000", "-q", "-o"])
        .arg(out);
    v.push(("trace", c));
    let mut c = traxer();
    c.arg("focus")
        .arg(&wolter)
        .args(["--var", "focus_shift", "--from=-1", "--to=1"]);
    c.args(["-n", "3000000", "-q", "-o"]).arg(out);
    v.push(("focus", c));
    let mut c = traxer();
    c.arg("compare")
        .arg(&wolter)
        .args(["-n", "3000000", "-q", "-o"])
        .arg(out);
    v.push(("compare", c));
    let mut c = traxer();
    c.arg("fit-figure-error").arg(&panter);
    c.args([
        "--target-hpd",
        "206",
        "--target-c80",
        "397",
        "--target-c90",
        "549",
    ]);
    c.args(["-n", "1000000", "-q", "-o"]).arg(out);
    v.push(("fit-figure-error", c));
    let mut c = traxer();
    c.arg("render").arg(repo().join("scenes/spheres.toml"));
    c.args([
        "--width", "800", "--height", "600", "--spp", "64", "-q", "--out",
    ])
    .arg(out.join("r.png"));
    v.push(("render", c));
    let mut c = traxer();
    c.args([
        "reflectivity",
        "--coating",
        "gold",
        "--energy",
        "1.49",
        "--angle",
        "0:3:0.01",
    ]);
    c.arg("--plot").arg(out.join("r.png"));
    v.push(("reflectivity", c));
    let mut c = traxer();
    c.args([
        "tessellate",
        "--shape",
        "type = \"sphere\", radius = 1",
        "--out",
    ])
    .arg(out.join("s.obj"));
    v.push(("tessellate (file)", c));
    let mut c = traxer();
    c.args([
        "tessellate",
        "--shape",
        "type = \"sphere\", radius = 1",
        "--out",
    ])
    .arg(out);
    v.push(("tessellate (folder)", c));
    v
}

#[test]
fn an_output_under_a_regular_file_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), "results", "a file, not a folder");
    for (name, mut cmd) in commands(&file.join("sub")) {
        let start = Instant::now();
        let err = run_fails(&mut cmd, 2);
        assert!(err.contains("results"), "{name}: {err}");
        assert!(
            start.elapsed() < Duration::from_secs(20),
            "{name}: took {:?}, so it worked first",
            start.elapsed()
        );
    }
}

#[test]
fn an_output_where_nothing_can_be_written_is_refused() {
    // /proc takes no new files, not even from root (tests may run as root, for
    // whom permission bits do not count).
    for (name, mut cmd) in commands(Path::new("/proc/traxer-test-out")) {
        let err = run_fails(&mut cmd, 2);
        assert!(err.contains("/proc"), "{name}: {err}");
    }
}

/// `traxer reflectivity` plotting to `plot`.
fn reflectivity_to(plot: &Path) -> std::process::Command {
    let mut c = traxer();
    c.args([
        "reflectivity",
        "--coating",
        "gold",
        "--energy",
        "1.49",
        "--angle",
        "1",
    ])
    .arg("--plot")
    .arg(plot);
    c
}

#[test]
fn an_output_name_taken_by_a_folder_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir_all(out.join("summary.json")).unwrap();
    let err = run_fails(
        traxer()
            .arg("trace")
            .arg(repo().join("scenes/wolter1_parallel.toml"))
            .args(["-n", "1000", "-q", "-o"])
            .arg(&out),
        2,
    );
    assert!(
        err.contains("summary.json") && err.contains("folder"),
        "{err}"
    );
    // Nothing was written next to it.
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 1);
    std::fs::create_dir_all(out.join("r.png")).unwrap();
    let err = run_fails(&mut reflectivity_to(&out.join("r.png")), 2);
    assert!(err.contains("folder"), "{err}");
}

#[test]
fn a_device_is_never_replaced_by_an_output_file() {
    // A named pipe stands for any special file (device nodes need root to make).
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("plot.png");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    let err = run_fails(&mut reflectivity_to(&fifo), 2);
    assert!(err.contains("named pipe"), "{err}");
    let err = run_fails(
        traxer()
            .arg("render")
            .arg(repo().join("scenes/spheres.toml"))
            .args(["--width", "8", "--height", "6", "--spp", "1", "--out"])
            .arg(&fifo),
        2,
    );
    assert!(err.contains("named pipe"), "{err}");
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    // And the library refuses too, whatever calls it.
    let e = traxer::files::atomic_write(&fifo, b"x").unwrap_err();
    assert!(e.to_string().contains("not a regular file"), "{e}");
    // /dev/null is a device: refused as an output, untouched.
    let err = run_fails(&mut reflectivity_to(Path::new("/dev/null")), 2);
    assert!(err.contains("device"), "{err}");
}
