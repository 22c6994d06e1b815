//! Studies that trace point after point — `fit-figure-error`, `focus`,
//! `effective-area` — stopped (SIGKILL, SIGTERM) and resumed with `--resume`
//! end exactly as uninterrupted ones.

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

/// Points in a study's record so far.
fn recorded(out: &Path) -> usize {
    let Ok(entries) = std::fs::read_dir(out) else {
        return 0;
    };
    entries
        .flatten()
        .filter(|e| {
            e.file_name()
                .to_string_lossy()
                .ends_with("_checkpoint.jsonl")
        })
        .filter_map(|e| std::fs::read_to_string(e.path()).ok())
        // A header line, then one whole line per point.
        .map(|t| t.matches('\n').count().saturating_sub(1))
        .max()
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
    o.retain(|k, _| {
        !(k == "provenance"
            || k.contains("seconds")
            || k == "threads"
            || k == "evaluations_resumed_from_record")
    });
    v
}

/// The files of two results folders agree: JSON apart from provenance and
/// timing, everything else byte for byte.
fn assert_same_files(a: &Path, b: &Path, names: &[&str]) {
    for f in names {
        if f.ends_with(".json") {
            assert_eq!(
                json_without_run_details(&a.join(f)),
                json_without_run_details(&b.join(f)),
                "{f}"
            );
        } else {
            assert!(
                std::fs::read(a.join(f)).unwrap() == std::fs::read(b.join(f)).unwrap(),
                "{f} differs"
            );
        }
    }
}

/// A study killed after `n` points, then resumed to the end: the same files as
/// uninterrupted; a new run into the stopped folder is refused.
fn check_kill_and_resume(
    command: impl Fn(&Path, &[&str]) -> std::process::Command,
    n: usize,
    files: &[&str],
) {
    let dir = tempfile::tempdir().unwrap();
    let reference = dir.path().join("reference");
    run_ok(&mut command(&reference, &[]));
    let out = dir.path().join("stopped");
    stop_after(command(&out, &[]), &out, n, "-KILL");
    let killed_at = recorded(&out);
    assert!(killed_at >= n);
    let err = run_fails(&mut command(&out, &[]), 2);
    assert!(err.contains("--resume"), "{err}");
    let resumed = run_ok(&mut command(&out, &["--resume"]));
    assert_eq!(recorded(&out), 0, "the record stayed");
    assert_same_files(&reference, &out, files);
    // Deterministic points re-traced would give the same files: the study
    // says how many it took from the record, and they are all that it held.
    let json = files.iter().find(|f| f.ends_with(".json")).unwrap();
    assert_eq!(points_from_record(&reference.join(json)), 0);
    assert_eq!(points_from_record(&out.join(json)), killed_at);
    // -q keeps the CLI's line about it (tested in the comparison's test) quiet.
    assert!(!String::from_utf8_lossy(&resumed.stdout).contains("resumed:"));
}

/// The provenance's count of points a study took from its record.
fn points_from_record(json: &Path) -> usize {
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap();
    v["provenance"]["points_from_record"]
        .as_u64()
        .unwrap_or_else(|| panic!("{}: no provenance.points_from_record", json.display()))
        as usize
}

#[test]
fn a_focus_scan_killed_and_resumed_is_the_uninterrupted_scan() {
    let command = |out: &Path, extra: &[&str]| {
        let mut c = traxer();
        c.arg("focus")
            .arg(repo().join("scenes/panter_al_ka.toml"))
            .args(["--from", "-1460", "--to", "-1580", "--steps", "9"])
            .args(["-n", "300000", "-q", "-o"])
            .arg(out)
            .args(extra);
        c
    };
    check_kill_and_resume(command, 3, &["focus.csv", "focus.png", "focus.json"]);
}

#[test]
fn an_effective_area_sweep_killed_and_resumed_is_the_uninterrupted_sweep() {
    let command = |out: &Path, extra: &[&str]| {
        let mut c = traxer();
        c.arg("effective-area")
            .arg(repo().join("scenes/llnl_effective_area.toml"))
            .args(["--energies", "1:8:0.5", "--angles", "0:10:2"])
            .args(["-n", "150000", "-q", "-o"])
            .arg(out)
            .args(extra);
        c
    };
    let files = [
        "effective_area.csv",
        "off_axis.csv",
        "effective_area.json",
        "effective_area.png",
        "off_axis.png",
        "vignetting.png",
    ];
    check_kill_and_resume(command, 2, &files);
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
        err.contains("records another run") && err.contains("seed"),
        "{err}"
    );
    // Resumed to the end.
    run_ok(&mut fit(&out, &["--resume"]));
    assert!(!out.join("fit_checkpoint.jsonl").exists());
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

#[test]
fn a_study_record_edited_or_of_changed_inputs_is_not_resumed() {
    let dir = tempfile::tempdir().unwrap();
    // The PANTER scene reading the telescope's data from a file beside it.
    let data = std::fs::read_to_string(repo().join("data/telescopes/llnl.toml")).unwrap();
    std::fs::write(dir.path().join("llnl.toml"), &data).unwrap();
    let text = std::fs::read_to_string(repo().join("scenes/panter_al_ka.toml"))
        .unwrap()
        .replacen(
            "name = \"llnl\"\n",
            "name = \"llnl\"\ndata = \"llnl.toml\"\n",
            1,
        );
    let scene = dir.path().join("panter.toml");
    std::fs::write(&scene, text).unwrap();
    let out = dir.path().join("stopped");
    let command = |extra: &[&str]| {
        let mut c = traxer();
        c.arg("focus")
            .arg(&scene)
            .args(["--from", "-1460", "--to", "-1580", "--steps", "9"])
            .args(["-n", "300000", "-q", "-o"])
            .arg(&out)
            .args(extra);
        c
    };
    stop_after(command(&[]), &out, 2, "-KILL");
    let record = out.join("focus_checkpoint.jsonl");
    let good = std::fs::read_to_string(&record).unwrap();
    // One digit of a recorded point changed.
    let at = good.find("\"value\":").expect("points have values") + "\"value\":".len();
    let digit = good[at..].find(|c: char| c.is_ascii_digit()).unwrap() + at;
    let mut edited = good.clone().into_bytes();
    edited[digit] = if edited[digit] == b'7' { b'8' } else { b'7' };
    std::fs::write(&record, edited).unwrap();
    let err = run_fails(&mut command(&["--resume"]), 2);
    assert!(err.contains("damaged or was edited"), "{err}");
    // The telescope's data file changed.
    std::fs::write(&record, &good).unwrap();
    std::fs::write(dir.path().join("llnl.toml"), format!("{data}\n# edited\n")).unwrap();
    let err = run_fails(&mut command(&["--resume"]), 2);
    // Refused naming the file (a study whose identity holds its scene's input
    // files says so when it opens; one that loads later, when it loads).
    assert!(
        err.contains("input file llnl.toml with SHA-256")
            || (err.contains("records another run") && err.contains("llnl.toml")),
        "{err}"
    );
    // As it was, the study resumes and ends.
    std::fs::write(dir.path().join("llnl.toml"), &data).unwrap();
    run_ok(&mut command(&["--resume"]));
    assert!(out.join("focus.csv").is_file());
}

#[test]
fn a_psf_library_killed_and_resumed_is_the_uninterrupted_library() {
    let command = |out: &Path, extra: &[&str]| {
        let mut c = traxer();
        c.arg("psf")
            .arg(repo().join("scenes/xmm_effective_area.toml"))
            .args([
                "--energies",
                "1.5,4,8",
                "--angles",
                "0:15:5",
                "--window",
                "41",
            ])
            .args(["-n", "100000", "-q", "-o"])
            .arg(out)
            .args(extra);
        c
    };
    check_kill_and_resume(command, 3, &["psf.npy", "psf.json"]);
}

#[test]
fn a_systematics_study_killed_and_resumed_is_the_uninterrupted_study() {
    let command = |out: &Path, extra: &[&str]| {
        let mut c = traxer();
        c.arg("systematics")
            .arg(repo().join("scenes/panter_al_ka.toml"))
            .args(["-n", "200000", "--sources", "figure", "--figure-draws", "5"])
            .args(["--vary", "sensor_z=-1529:-1509", "-q", "-o"])
            .arg(out)
            .args(extra);
        c
    };
    check_kill_and_resume(
        command,
        3,
        &[
            "systematics.csv",
            "systematics.json",
            "map_variations.npy",
            "map_sigma.npy",
            "map_mean.npy",
            "map_sigma_noise.npy",
        ],
    );
}

#[test]
fn a_mesh_comparison_killed_and_resumed_measures_what_the_uninterrupted_one_does() {
    let command = |out: &Path, extra: &[&str]| {
        let mut c = traxer();
        c.arg("compare")
            .arg(repo().join("scenes/panter_al_ka.toml"))
            .args(["--resolutions", "4x1,8x1,15x1,30x1"])
            .args(["-n", "200000", "-q", "-o"])
            .arg(out)
            .args(extra);
        c
    };
    let dir = tempfile::tempdir().unwrap();
    let reference = dir.path().join("reference");
    run_ok(&mut command(&reference, &[]));
    let out = dir.path().join("stopped");
    stop_after(command(&out, &[]), &out, 2, "-KILL");
    let killed_at = recorded(&out);
    assert!(killed_at >= 2);
    let err = run_fails(&mut command(&out, &[]), 2);
    assert!(err.contains("--resume"), "{err}");
    // Without -q the CLI says what it took from the record.
    let resume = command(&out, &["--resume"]);
    let loud: Vec<_> = resume.get_args().filter(|a| *a != "-q").collect();
    let said = run_ok(traxer().args(loud));
    let said = String::from_utf8_lossy(&said.stdout);
    assert!(
        said.contains(&format!(
            "resumed: {killed_at} variants taken from the record"
        )),
        "{said}"
    );
    assert_eq!(recorded(&out), 0, "the record stayed");
    assert_eq!(points_from_record(&out.join("compare.json")), killed_at);
    // Every column but the last two (photons per second and seconds: the
    // machine's speed, not the measurement) is the uninterrupted run's.
    let measured = |folder: &Path| -> Vec<String> {
        let text = std::fs::read_to_string(folder.join("compare.csv")).unwrap();
        text.lines()
            .map(|l| l.rsplitn(3, ',').nth(2).unwrap().to_string())
            .collect()
    };
    let (a, b) = (measured(&reference), measured(&out));
    assert_eq!(a.len(), 6, "header, analytic and four meshes: {a:?}");
    assert_eq!(a, b);
}
