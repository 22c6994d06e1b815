//! Names and sizes that would clobber or exhaust are refused when the scene is
//! loaded or the arguments are read, with exit code 2: sensors whose files would
//! collide, names no file system takes, more image memory than a stated limit,
//! sweeps too long to hold.

use crate::common::{run_fails, run_ok, traxer, write};

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

#[test]
fn bench_reports_the_peak_memory_of_its_scene() {
    let scene = crate::common::repo().join("scenes/panter_al_ka.toml");
    let out = run_ok(
        traxer()
            .arg("bench")
            .arg(&scene)
            .args(["-n", "20000", "--json", "-q"]),
    );
    let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // At least the images and tables the trace holds, at most what the
    // machine has: a number, not a placeholder.
    let mb = r["peak_rss_mb"].as_f64().unwrap();
    assert!(mb > 5.0 && mb < 24_000.0, "{mb}");
}

#[test]
fn sensor_names_whose_temporary_or_class_file_names_are_too_long_are_refused() {
    // 236 characters: `NAME_conversion_spectrum.csv` would be 264 bytes, but
    // even the shortest file plus the temporary name's 12 bytes is too long
    // once the longest (`NAME_front_rear.npy`, `NAME_conversion_…`) counts.
    let name = "x".repeat(230);
    let err = trace_fails(&sensors_scene(&[(&name, 4)]));
    assert!(
        err.contains("temporary names") && err.contains("255"),
        "{err}"
    );
}

#[test]
fn class_images_are_named_like_the_sensors_other_files() {
    let dir = tempfile::tempdir().unwrap();
    let text = sensors_scene(&[("det 1", 4)])
        .replace("pixels = [4, 4]", "pixels = [4, 4]\nhistory_images = true");
    let path = write(dir.path(), "s.toml", &text);
    let out = dir.path().join("out");
    crate::common::run_ok(
        traxer()
            .arg("trace")
            .arg(&path)
            .args(["-n", "100", "-q", "-o"])
            .arg(&out),
    );
    assert!(out.join("det_1.npy").is_file());
    assert!(out.join("det_1_direct.npy").is_file());
    assert!(!out.join("det 1_direct.npy").exists());
}

#[test]
fn class_images_and_pixel_grids_count_toward_the_image_cap() {
    // Two sensors of 2^26 values fill the cap; with history_images the class
    // images (5 × 2^26 more) do not fit.
    let two = sensors_scene(&[("s1", 8192), ("s2", 8192)]);
    let err = trace_fails(&two.replacen(
        "pixels = [8192, 8192]",
        "pixels = [8192, 8192]\nhistory_images = true",
        1,
    ));
    assert!(
        err.contains("history_images") && err.contains("134217728"),
        "{err}"
    );
    let err = trace_fails(&two.replacen(
        "pixels = [8192, 8192]",
        "pixels = [8192, 8192]\npixel_grid = { pixels = [4096, 4096], pitch = 0.001 }",
        1,
    ));
    assert!(
        err.contains("pixel grids") && err.contains("134217728"),
        "{err}"
    );
}

#[test]
fn emission_grids_and_area_sweeps_too_large_are_refused_before_work() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    // A two-shell model in the B16 format (mass, radius, T, ρ, P, L, then 29
    // mass fractions adding up to 1): the grid is refused before any work.
    let row = |r: f64| {
        let fractions = std::iter::once("0.72".to_string())
            .chain(std::iter::repeat_n("0.01".to_string(), 28))
            .collect::<Vec<_>>()
            .join(" ");
        format!("0.1 {r} 1.5e7 150 1e17 0.1 {fractions}\n")
    };
    let model = write(dir.path(), "model.dat", &(row(0.1) + &row(0.2)));
    let err = run_fails(
        traxer()
            .args(["solar-flux", "-q", "--model"])
            .arg(&model)
            .args([
                "--radii",
                "0.0001:1:0.0001",
                "--energies",
                "0.1:15:0.0001",
                "-o",
            ])
            .arg(&out),
        2,
    );
    assert!(err.contains("10000 radii × 149001 energies"), "{err}");
    assert!(!out.exists());
    let scene = crate::common::repo().join("scenes/llnl_effective_area.toml");
    let err = run_fails(
        traxer()
            .arg("effective-area")
            .arg(&scene)
            .args(["--energies", "1:10:0.0001", "--angles", "0:100:0.01", "-o"])
            .arg(&out),
        2,
    );
    assert!(err.contains("90001 energies × 10001 angles"), "{err}");
    assert!(!out.exists());
    for au in ["0", "1e300", "0.01", "nan"] {
        let err = run_fails(
            traxer()
                .args(["solar-flux", "-q", "--distance-au", au, "-o"])
                .arg(&out),
            2,
        );
        assert!(
            err.contains("--distance-au") && err.contains("0.983"),
            "{au}: {err}"
        );
    }
}
