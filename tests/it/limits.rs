//! Names and sizes that would clobber or exhaust are refused when the scene is
//! loaded or the arguments are read, with exit code 2: sensors whose files would
//! collide, names no file system takes, more image memory than a stated limit,
//! sweeps too long to hold.

use crate::common::{run_fails, traxer, write};

/// A scene with one sensor object per (name, pixels) pair.
fn sensors_scene(sensors: &[(&str, u32)]) -> String {
    let mut s = String::from(
        "[[sources]]\ntype = \"parallel\"\naperture = { center = [0, 0, 10], radius = 1.0 }\nenergy = { line = 1.49 }\n",
    );
    for (i, (name, px)) in sensors.iter().enumerate() {
        s.push_str(&format!(
            "\n[materials.d{i}]\ntype = \"sensor\"\nsize = [1.0, 1.0]\npixels = [{px}, {px}]\n\n[[objects]]\nname = \"{name}\"\nmaterial = \"d{i}\"\nshape = {{ type = \"rectangle\", size = [1.0, 1.0] }}\ntransform = [ {{ translate = [0, 0, {z}] }} ]\n",
            z = -(i as f64)
        ));
    }
    s
}

fn trace_fails(scene: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "s.toml", scene);
    let out = dir.path().join("out");
    let err = run_fails(
        traxer()
            .arg("trace")
            .arg(&path)
            .args(["-n", "100", "-q", "-o"])
            .arg(&out),
        2,
    );
    assert!(!out.exists(), "nothing is written: {err}");
    err
}

#[test]
fn sensors_whose_files_would_collide_are_refused() {
    // The same file name after sanitising.
    let err = trace_fails(&sensors_scene(&[("a b", 4), ("a_b", 4)]));
    assert!(err.contains("a b") && err.contains("a_b.npy"), "{err}");
    // One sensor's derived file is another's main file.
    let err = trace_fails(&sensors_scene(&[("det", 4), ("det_counts", 4)]));
    assert!(
        err.contains("det_counts.npy") && err.contains("`det`"),
        "{err}"
    );
    // The run's own summary.
    let err = trace_fails(&sensors_scene(&[("summary", 4)]));
    assert!(err.contains("summary.json"), "{err}");
    // Distinct names pass.
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "s.toml", &sensors_scene(&[("a", 4), ("b", 4)]));
    crate::common::run_ok(
        traxer()
            .arg("trace")
            .arg(&path)
            .args(["-n", "100", "-q", "-o"])
            .arg(dir.path().join("out")),
    );
}

#[test]
fn sensor_names_no_file_system_takes_are_refused_at_load() {
    let long = "x".repeat(300);
    let err = trace_fails(&sensors_scene(&[(&long, 4)]));
    assert!(err.contains("255"), "{err}");
    let err = trace_fails(&sensors_scene(&[("..", 4)]));
    assert!(err.contains("letters or digits"), "{err}");
}

#[test]
fn image_memory_of_all_sensors_is_bounded_before_allocating() {
    // Three sensors at the per-sensor maximum (8192² = 2^26 each) exceed the
    // total of 2^27: refused at load, not an aborted allocation.
    let err = trace_fails(&sensors_scene(&[("s1", 8192), ("s2", 8192), ("s3", 8192)]));
    assert!(err.contains("134217728"), "{err}");
}

#[test]
fn sweeps_and_replays_too_large_to_hold_are_refused() {
    let scene = crate::common::repo().join("scenes/wolter1_parallel.toml");
    let err = run_fails(
        traxer().arg("focus").arg(&scene).args([
            "--var",
            "focus_shift",
            "--from=0",
            "--to=1",
            "--steps",
            "1000000000",
        ]),
        2,
    );
    assert!(err.contains("--steps"), "{err}");
    let err = run_fails(
        traxer().arg("bench").arg(&scene).args([
            "-n",
            "1000000000000",
            "--raw-photons",
            "1000000000000",
        ]),
        2,
    );
    assert!(err.contains("--raw-photons"), "{err}");
}
