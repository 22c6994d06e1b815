//! `traxer fit-figure-error` stopped (SIGKILL, SIGTERM) and resumed with
//! `--resume` ends exactly as an uninterrupted fit.

use crate::common::{repo, run_fails, run_ok, traxer};
use std::path::Path;
use std::time::{Duration, Instant};

fn fit(out: &Path, extra: &[&str]) -> std::process::Command {
    let mut c = traxer();
    c.arg("fit-figure-error")
        .arg(repo().join("scenes/panter_al_ka.toml"))
        .args([
            "--target-hpd",
            "206",
            "--target-c80",
            "397",
            "--target-c90",
            "549",
        ])
        .args([
            "-n",
            "100000",
            "--global-evals",
            "24",
            "--local-evals",
            "10",
        ])
        .args(["--check-seeds", "1", "-q", "-o"])
        .arg(out)
        .args(extra);
    c
}

/// Evaluations in the fit's record so far.
fn recorded(out: &Path) -> usize {
    std::fs::read_to_string(out.join("fit_checkpoint.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| v["evaluations"].as_array().map(Vec::len))
        .unwrap_or(0)
}

/// Starts `cmd`, waits until `out` records at least `n` evaluations, sends `sig`.
fn stop_after(
    mut cmd: std::process::Command,
    out: &Path,
    n: usize,
    sig: &str,
) -> std::process::Output {
    let child = cmd.stderr(std::process::Stdio::piped()).spawn().unwrap();
    let start = Instant::now();
    while recorded(out) < n && start.elapsed() < Duration::from_secs(120) {
        std::thread::sleep(Duration::from_millis(2));
    }
    run_ok(std::process::Command::new("kill").args([sig, &child.id().to_string()]));
    child.wait_with_output().unwrap()
}

fn json_without_run_details(path: &Path) -> serde_json::Value {
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let o = v.as_object_mut().unwrap();
    for k in [
        "provenance",
        "fit_seconds",
        "evaluations_resumed_from_record",
    ] {
        o.remove(k);
    }
    v
}

#[test]
fn a_fit_stopped_twice_and_resumed_ends_as_the_uninterrupted_fit() {
    let dir = tempfile::tempdir().unwrap();
    let reference = dir.path().join("reference");
    run_ok(&mut fit(&reference, &[]));
    let out = dir.path().join("fit");
    // Killed outright after 8 evaluations: the record has them.
    stop_after(fit(&out, &[]), &out, 8, "-KILL");
    let killed_at = recorded(&out);
    assert!((8..34).contains(&killed_at), "{killed_at}");
    // A new fit into the folder would lose them: refused.
    let err = run_fails(&mut fit(&out, &[]), 2);
    assert!(err.contains("--resume"), "{err}");
    // Resumed, then stopped by SIGTERM: exit 130 and how to continue.
    let stopped = stop_after(fit(&out, &["--resume"]), &out, killed_at + 6, "-TERM");
    let err = String::from_utf8_lossy(&stopped.stderr);
    assert_eq!(stopped.status.code(), Some(130), "{err}");
    assert!(err.contains("--resume"), "{err}");
    // Another fit's settings are refused.
    let err = run_fails(&mut fit(&out, &["--resume", "--seed", "2"]), 2);
    assert!(
        err.contains("records another fit") && err.contains("seed"),
        "{err}"
    );
    // Resumed to the end.
    run_ok(&mut fit(&out, &["--resume"]));
    assert!(!out.join("fit_checkpoint.json").exists());
    for f in ["history.csv", "figure_error.toml"] {
        assert!(
            std::fs::read(reference.join(f)).unwrap() == std::fs::read(out.join(f)).unwrap(),
            "{f} differs"
        );
    }
    assert_eq!(
        json_without_run_details(&reference.join("fit.json")),
        json_without_run_details(&out.join("fit.json"))
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("fit.json")).unwrap()).unwrap();
    assert!(v["evaluations_resumed_from_record"].as_u64().unwrap() >= killed_at as u64 + 6);
    // Nothing to resume in a finished folder.
    let err = run_fails(&mut fit(&out, &["--resume"]), 2);
    assert!(err.contains("no stopped fit"), "{err}");
}
