//! Closed standard streams: `traxer … 2>&1 | true` or `traxer … | head` must not
//! turn a warning into a crash, an error into a panic, or end a run early; the
//! exit code stays what the run deserves.

use crate::common::{repo, traxer, write};
use std::process::{Command, Stdio};

/// Runs `cmd` with stdout and/or stderr connected to a pipe whose reading end is
/// already closed (every write fails with EPIPE); returns the exit code.
fn run_closed(cmd: &mut Command, close_stdout: bool, close_stderr: bool) -> Option<i32> {
    let closed = || {
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        Stdio::from(writer)
    };
    if close_stdout {
        cmd.stdout(closed());
    } else {
        cmd.stdout(Stdio::null());
    }
    if close_stderr {
        cmd.stderr(closed());
    } else {
        cmd.stderr(Stdio::null());
    }
    cmd.status().unwrap().code()
}

/// A scene that traces but warns (its sensor object has no sensor material).
const WARNS: &str = r#"
[[sources]]
type = "parallel"
aperture = { center = [0, 0, 10], radius = 1.0 }
energy = { line = 1.49 }

[[objects]]
material = "absorber"
shape = { type = "rectangle", size = [14.0, 14.0] }
"#;

#[test]
fn a_warning_with_stderr_closed_does_not_kill_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "s.toml", WARNS);
    let out = dir.path().join("out");
    let code = run_closed(
        traxer()
            .arg("trace")
            .arg(&scene)
            .args(["-n", "1000", "-o"])
            .arg(&out),
        true,
        true,
    );
    assert_eq!(code, Some(0));
    assert!(out.join("summary.json").is_file());
}

#[test]
fn an_error_with_stderr_closed_keeps_its_exit_code() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "s.toml", "[[objects]]\nmaterial = 3\n");
    let code = run_closed(traxer().arg("trace").arg(&scene), false, true);
    assert_eq!(code, Some(2), "bad input, not a panic (101)");
    let code = run_closed(
        traxer().args(["trace", "--photons", "lots", "x"]),
        false,
        true,
    );
    assert_eq!(code, Some(2));
}

#[test]
fn a_closed_stdout_does_not_end_a_focus_scan_early() {
    // The step lines go to stdout; with it closed the scan still runs to its end
    // and writes its files.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("focus");
    let code = run_closed(
        traxer()
            .arg("focus")
            .arg(repo().join("scenes/wolter1_parallel.toml"))
            .args(["--var", "focus_shift", "--from=-2", "--to=2", "--steps=5"])
            .args(["-n", "20000", "-o"])
            .arg(&out),
        true,
        true,
    );
    assert_eq!(code, Some(0));
    let csv = std::fs::read_to_string(out.join("focus.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 5, "{csv}");
}
