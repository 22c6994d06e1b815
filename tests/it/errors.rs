//! Bad input gives a clear error naming file, line and key, exit code 2, and never
//! a panic; a failed run gives exit code 1.

use crate::common::{broken_mesh_files, write};
use std::path::Path;

const GOOD: &str = r#"
[vars]
energy = 1.49

[materials.detector]
type = "sensor"
size = [14.0, 14.0]
pixels = [10, 10]

[[sources]]
type = "parallel"
aperture = { center = [0, 0, 10], radius = 1.0 }
energy = { line = "$energy" }

[[objects]]
name = "sensor"
material = "detector"
shape = { type = "rectangle", size = [14.0, 14.0] }
"#;

/// Runs `traxer trace` on `scene_text` (+ files) and returns (exit code, stderr).
fn trace(dir: &Path, scene_text: &str, extra: &[&str]) -> (i32, String) {
    let scene = write(dir, "scene.toml", scene_text);
    let out = crate::common::traxer()
        .arg("trace")
        .arg(&scene)
        .args(["-n", "100", "-q", "--out"])
        .arg(dir.join("out"))
        .args(extra)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(!err.contains("panicked"), "panic: {err}");
    (out.status.code().unwrap_or(-1), err)
}

fn expect_input_error(scene_text: &str, extra: &[&str], needles: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let (code, err) = trace(dir.path(), scene_text, extra);
    assert_eq!(code, 2, "expected exit code 2, stderr: {err}");
    for n in needles {
        assert!(err.contains(n), "stderr lacks {n:?}:\n{err}");
    }
    // Nothing half-written.
    assert!(
        !dir.path().join("out").exists()
            || std::fs::read_dir(dir.path().join("out"))
                .unwrap()
                .next()
                .is_none()
    );
}

#[test]
fn the_good_scene_runs() {
    let dir = tempfile::tempdir().unwrap();
    let (code, err) = trace(dir.path(), GOOD, &[]);
    assert_eq!(code, 0, "{err}");
    for f in [
        "sensor.npy",
        "sensor_counts.npy",
        "sensor.png",
        "sensor_log.png",
        "sensor.json",
        "summary.json",
    ] {
        assert!(dir.path().join("out").join(f).is_file(), "{f} missing");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("out/sensor.json")).unwrap())
            .unwrap();
    assert_eq!(json["statistics"]["reached_sensor"], 100);
    assert_eq!(json["sensor"]["pixel_pitch_mm"][0], 1.4);
    assert_eq!(json["provenance"]["photons"], 100);
    assert_eq!(
        json["provenance"]["scene_sha256"].as_str().unwrap().len(),
        64
    );
    // The .npy loads as a (10, 10) float64 array whose sum is the photon count.
    let bytes = std::fs::read(dir.path().join("out/sensor.npy")).unwrap();
    let npy = npyz::NpyFile::new(&bytes[..]).unwrap();
    assert_eq!(npy.shape(), &[10, 10]);
    let data: Vec<f64> = npy.into_vec().unwrap();
    assert_eq!(data.iter().sum::<f64>(), 100.0);
}

#[test]
fn unknown_key_names_file_line_and_key() {
    let bad = GOOD.replace("name = \"sensor\"", "name = \"sensor\"\ncolour = \"red\"");
    expect_input_error(&bad, &[], &["scene.toml:17", "unknown field `colour`"]);
}

#[test]
fn unknown_shape_key_and_shape_type() {
    let bad = GOOD.replace("size = [14.0, 14.0] }", "size = [14.0, 14.0], radius = 3 }");
    expect_input_error(&bad, &[], &["scene.toml:18", "unknown field `radius`"]);
    let bad = GOOD.replace("type = \"rectangle\"", "type = \"triangle\"");
    expect_input_error(&bad, &[], &["scene.toml:18", "unknown variant `triangle`"]);
}

#[test]
fn wrong_type_names_the_line() {
    // Inside a `type = ...` table serde reports the whole table; the error names
    // the value's own line and key.
    let bad = GOOD.replace("pixels = [10, 10]", "pixels = \"many\"");
    expect_input_error(
        &bad,
        &[],
        &[
            "scene.toml:8: `materials.detector.pixels`: invalid type: string \"many\"",
            "| pixels = \"many\"",
        ],
    );
    let bad = GOOD.replace("pixels = [10, 10]", "pixels = [10, -10]");
    expect_input_error(
        &bad,
        &[],
        &["scene.toml:8: `materials.detector.pixels[1]`: invalid value: integer `-10`"],
    );
    let bad = GOOD.replace("radius = 1.0 }", "radius = \"wide\" }");
    expect_input_error(
        &bad,
        &[],
        &["scene.toml:12: `sources[0].aperture.radius`: invalid type: string \"wide\""],
    );
    let bad = GOOD.replace("pixels = [10, 10]", "pixels = [10, 10]\nside = \"front\"");
    expect_input_error(
        &bad,
        &[],
        &["scene.toml:9: `materials.detector.side`: unknown field `side`"],
    );
    // A bad value that came from a variable points at the line that uses it.
    expect_input_error(
        GOOD,
        &["-D", "energy=true"],
        &["scene.toml:13: `sources[0].energy.line`: invalid type: boolean `true`"],
    );
}

#[test]
fn positions_beyond_float32_geometry_are_refused() {
    // 1e300 is finite in f64 but infinite in f32: Embree would abort on such rays.
    expect_input_error(
        &GOOD.replace("center = [0, 0, 10]", "center = [0, 0, 1e300]"),
        &[],
        &["scene.toml:10", "within ±1e9 mm of the origin"],
    );
    expect_input_error(
        &GOOD.replace(
            "shape = { type = \"rectangle\", size = [14.0, 14.0] }",
            "shape = { type = \"rectangle\", size = [1e300, 14.0] }",
        ),
        &[],
        &["object `sensor` reaches", "within ±1e9 mm of the origin"],
    );
    expect_input_error(
        &format!(
            "{GOOD}\n[cameras.far]\nlook_from = [1e300, 0, 0]\nlook_at = [0, 0, 0]\nvfov = 30\n"
        ),
        &[],
        &["camera `far`", "within ±1e9 mm of the origin"],
    );
}

#[test]
fn missing_mesh_file_unknown_material_and_bad_values() {
    let bad = GOOD.replace(
        "{ type = \"rectangle\", size = [14.0, 14.0] }",
        "{ type = \"mesh\", file = \"nope.obj\" }",
    );
    expect_input_error(&bad, &[], &["scene.toml:18", "nope.obj does not exist"]);
    let bad = GOOD.replace("material = \"detector\"", "material = \"gold\"");
    expect_input_error(&bad, &[], &["scene.toml:17", "unknown material `gold`"]);
    let bad = GOOD.replace("size = [14.0, 14.0] }", "size = [-1.0, 14.0] }");
    expect_input_error(&bad, &[], &["scene.toml:18", "rectangle needs size"]);
    let bad = GOOD.replace("radius = 1.0 }", "radius = -1.0 }");
    expect_input_error(&bad, &[], &["scene.toml:1", "aperture"]);
    let bad = GOOD.replace(
        "[[objects]]",
        "[[objects]]\ntransform = [ { rotate = { axis = [0, 0, 0], angle = 3 } } ]",
    );
    expect_input_error(&bad, &[], &["scene.toml:16", "axis must not be zero"]);
}

#[test]
fn variables_and_overrides() {
    // A good override runs; unknown names and references are errors.
    let dir = tempfile::tempdir().unwrap();
    let (code, err) = trace(dir.path(), GOOD, &["-D", "energy=6.4"]);
    assert_eq!(code, 0, "{err}");
    let summary = std::fs::read_to_string(dir.path().join("out/summary.json")).unwrap();
    assert!(summary.contains("6.4"), "{summary}");
    expect_input_error(
        GOOD,
        &["-D", "energi=6.4"],
        &["no variable `energi`", "energy"],
    );
    let bad = GOOD.replace("\"$energy\"", "\"$enrgy\"");
    expect_input_error(&bad, &[], &["scene.toml:13", "unknown variable `$enrgy`"]);
    expect_input_error(
        GOOD,
        &["-D", "energy=hot"],
        &["invalid type: string \"hot\""],
    );
}

fn mesh_scene(file: &str) -> String {
    GOOD.replace("[[objects]]", &format!("[[objects]]\nname = \"part\"\nmaterial = \"absorber\"\nshape = {{ type = \"mesh\", file = \"{file}\" }}\n\n[[objects]]"))
}

fn expect_mesh_error(file: &str, content: &[u8], needles: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join(file), content).unwrap();
    let (code, err) = trace(dir.path(), &mesh_scene(file), &[]);
    assert_eq!(code, 2, "{file}: expected exit code 2, stderr: {err}");
    assert!(err.contains(file), "{err}");
    for n in needles {
        assert!(err.contains(n), "{file}: stderr lacks {n:?}:\n{err}");
    }
}

#[test]
fn broken_meshes_give_clear_errors() {
    for (file, content, needles) in broken_mesh_files() {
        expect_mesh_error(file, &content, &needles);
    }
}

#[test]
fn missing_scene_bad_arguments_and_run_failures() {
    let err = crate::common::run_fails(
        crate::common::traxer().args(["trace", "/nonexistent/scene.toml"]),
        2,
    );
    assert!(err.contains("/nonexistent/scene.toml"), "{err}");
    crate::common::run_fails(
        crate::common::traxer().args(["trace", "--photons", "lots", "x.toml"]),
        2,
    );
    // The output folder cannot be created (a file is in the way): refused before
    // tracing, as bad input (2).
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "out", "a file");
    let (code, err) = trace(dir.path(), GOOD, &[]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("is a file, not a folder"), "{err}");
    // Values that used to hang, wrap around or exhaust memory.
    expect_input_error(
        GOOD,
        &["-j", "100000"],
        &["0 (one per core) to 1024 worker threads"],
    );
    expect_input_error(GOOD, &["--shard", "2/0"], &["at least 1 shard"]);
    let err = crate::common::run_fails(
        crate::common::traxer()
            .args([
                "tessellate",
                "--shape",
                "type = \"sphere\", radius = 1",
                "--segments",
                "100000000",
                "--rings",
                "100000000",
                "--out",
            ])
            .arg(dir.path().join("huge.obj")),
        2,
    );
    assert!(err.contains("more than 50000000 quads"), "{err}");
}

/// A scene error located at a value also names that value's dotted key (the
/// Python module hands it on as `SceneError.key`): for TOML type errors, for the
/// scene's own checks and for the checks of sources and shapes.
#[test]
fn scene_errors_name_the_key_of_the_value() {
    let cases = [
        (
            GOOD.replace("pixels = [10, 10]", "pixels = [10, -1]"),
            "materials.detector.pixels[1]",
        ),
        (
            GOOD.replace("material = \"detector\"", "material = \"nothing\""),
            "objects[0].material",
        ),
        (
            GOOD.replace("radius = 1.0 }", "radius = -1.0 }"),
            "sources[0]",
        ),
        (
            GOOD.replace("size = [14.0, 14.0] }", "size = [14.0, -2.0] }"),
            "objects[0].shape",
        ),
    ];
    let device = crate::common::device();
    for (text, key) in cases {
        let dir = tempfile::tempdir().unwrap();
        let scene = write(dir.path(), "scene.toml", &text);
        let e = traxer::scene::Scene::load(&device, &scene, &[])
            .err()
            .expect("refused");
        assert_eq!(e.key.as_deref(), Some(key), "{e}");
        assert!(e.line.is_some(), "{e}");
    }
    // Errors of the whole file or of a -D override have no key.
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "scene.toml", GOOD);
    let e = traxer::scene::Scene::load(&device, &scene, &["nope=1".into()])
        .err()
        .expect("refused");
    assert_eq!(e.key, None, "{e}");
}
