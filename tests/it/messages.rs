//! Messages that point at the cause: the key of a badly typed value, the `-D`
//! that set a bad value, the data file that holds bad numbers, what a mesh path
//! really is, the OBJ line, a truncated GLB — and never megabytes of a line.

use crate::common::{repo, run_fails, traxer, write};

const SCENE: &str = r#"
[materials.detector]
type = "sensor"
size = [14.0, 14.0]
pixels = PIXELS

[[sources]]
type = "parallel"
direction = DIRECTION
aperture = { center = [0, 0, 10], radius = 1.0 }
energy = ENERGY

[[objects]]
name = "s"
material = "detector"
shape = { type = "rectangle", size = [14.0, 14.0] }
transform = TRANSFORM
"#;

fn trace_error(text: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "s.toml", text);
    run_fails(
        traxer()
            .arg("trace")
            .arg(&path)
            .args(["-n", "10", "-q", "-o"])
            .arg(dir.path().join("o")),
        2,
    )
}

fn scene(pixels: &str, direction: &str, energy: &str, transform: &str) -> String {
    SCENE
        .replace("PIXELS", pixels)
        .replace("DIRECTION", direction)
        .replace("ENERGY", energy)
        .replace("TRANSFORM", transform)
}

#[test]
fn type_errors_name_their_key_and_line() {
    let ok = ("[10, 10]", "[0, 0, -1]", "{ line = 1.49 }", "[]");
    for ((p, d, e, t), key, line) in [
        (
            ("[10.0, 10.0]", ok.1, ok.2, ok.3),
            "`materials.detector.pixels`",
            ":5:",
        ),
        (
            (ok.0, "[0, -1]", ok.2, ok.3),
            "`sources[0].direction`",
            ":9:",
        ),
        (
            (ok.0, ok.1, "{ line = 1.49, band = [1.0, 2.0] }", ok.3),
            "`sources[0].energy`",
            ":11:",
        ),
        (
            (
                ok.0,
                ok.1,
                ok.2,
                "[ { translate = [0, 0, 1], scale = 2.0 } ]",
            ),
            "`objects[0].transform[0]`",
            ":17:",
        ),
    ] {
        let err = trace_error(&scene(p, d, e, t));
        assert!(err.contains(key) && err.contains(line), "{key}: {err}");
    }
}

#[test]
fn a_syntax_error_on_a_huge_line_is_quoted_short() {
    let long = format!("comment = \"{}\" oops\n", "x".repeat(1_000_000));
    let err = trace_error(&format!(
        "{long}{}",
        scene("[10, 10]", "[0, 0, -1]", "{ line = 1.49 }", "[]")
    ));
    assert!(err.len() < 2_000, "{} bytes of message", err.len());
    assert!(err.contains(":1:"), "{err}");
}

#[test]
fn a_bad_value_from_a_define_names_the_define() {
    let dir = tempfile::tempdir().unwrap();
    let err = run_fails(
        traxer()
            .arg("trace")
            .arg(repo().join("scenes/panter_al_ka.toml"))
            .args(["-D", "figure_error=nosuch", "-n", "10", "-q", "-o"])
            .arg(dir.path().join("o")),
        2,
    );
    assert!(
        err.contains("-D figure_error=nosuch") && err.contains("nosuch"),
        "{err}"
    );
}

#[test]
fn bad_numbers_in_a_data_file_name_that_file() {
    let dir = tempfile::tempdir().unwrap();
    let data = std::fs::read_to_string(repo().join("data/llnl_telescope.toml"))
        .unwrap()
        .replace("r1 = 63.2384", "r1 = 50.0");
    write(dir.path(), "my_telescope.toml", &data);
    let err = trace_error_in(
        dir.path(),
        &format!(
            "{}\n[[assemblies]]\ntype = \"llnl_telescope\"\ndata = \"my_telescope.toml\"\n",
            scene("[10, 10]", "[0, 0, -1]", "{ line = 1.49 }", "[]")
        ),
    );
    assert!(
        err.contains("my_telescope.toml") && err.contains("shell 1"),
        "{err}"
    );
}

fn trace_error_in(dir: &std::path::Path, text: &str) -> String {
    let path = write(dir, "s.toml", text);
    run_fails(
        traxer()
            .arg("trace")
            .arg(&path)
            .args(["-n", "10", "-q", "-o"])
            .arg(dir.join("o")),
        2,
    )
}

#[test]
fn mesh_files_say_what_is_wrong_and_where() {
    let dir = tempfile::tempdir().unwrap();
    // A folder given as a mesh file.
    std::fs::create_dir(dir.path().join("parts.glb")).unwrap();
    let err = trace_error_in(
        dir.path(),
        &scene("[10, 10]", "[0, 0, -1]", "{ line = 1.49 }", "[]").replace(
            "shape = { type = \"rectangle\", size = [14.0, 14.0] }",
            "shape = { type = \"mesh\", file = \"parts.glb\" }",
        ),
    );
    assert!(err.contains("is a folder"), "{err}");
    let err = run_fails(traxer().arg("inspect").arg(dir.path().join("parts.glb")), 2);
    assert!(err.contains("is a folder"), "{err}");
    // OBJ errors name the line.
    let obj = write(
        dir.path(),
        "bad.obj",
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\nf 1 2 9\n",
    );
    let err = run_fails(traxer().arg("inspect").arg(&obj), 2);
    assert!(err.contains("line 5") && err.contains("f 1 2 9"), "{err}");
    let obj = write(
        dir.path(),
        "bad2.obj",
        "v 0 0 0\nv 1 zero 0\nv 1 1 0\nf 1 2 3\n",
    );
    let err = run_fails(traxer().arg("inspect").arg(&obj), 2);
    assert!(err.contains("line 2"), "{err}");
    // A GLB cut off in the middle says so.
    let glb = std::fs::read(repo().join("meshes/llnl_telescope.glb")).unwrap();
    let cut = dir.path().join("cut.glb");
    std::fs::write(&cut, &glb[..glb.len() / 3]).unwrap();
    let err = run_fails(traxer().arg("inspect").arg(&cut), 2);
    assert!(err.contains("truncated"), "{err}");
}
