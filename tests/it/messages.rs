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
        err.contains("variable override figure_error=nosuch") && err.contains("nosuch"),
        "{err}"
    );
}

#[test]
fn bad_numbers_in_a_data_file_name_that_file() {
    let dir = tempfile::tempdir().unwrap();
    let data = std::fs::read_to_string(repo().join("data/telescopes/llnl.toml"))
        .unwrap()
        .replace("r1_mm = 63.2384", "r1_mm = 50.0");
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

/// A small scene with one sensor object whose lines after `[[objects]]` are
/// `object`.
fn sensor_scene_with(object: &str) -> String {
    format!(
        "[[sources]]\ntype = \"parallel\"\naperture = {{ center = [0, 0, 10], radius = 1.0 }}\nenergy = {{ line = 1.49 }}\n\n[materials.det]\ntype = \"sensor\"\nsize = [1.0, 1.0]\npixels = [4, 4]\n\n[[objects]]\n{object}\n"
    )
}

#[test]
fn scene_mistakes_name_line_and_key_and_say_what_is_allowed() {
    let rect = "material = \"det\"\nshape = { type = \"rectangle\", size = [1.0, 1.0] }";
    let cases = [
        (
            "unterminated multi-line string",
            "name = \"\"\"sensor\nmaterial = \"det\"".to_string(),
            vec!["s.toml:12:", "never closed", "name = \"\"\"sensor"],
        ),
        (
            "date where a number belongs",
            "name = \"s\"\nmaterial = \"det\"\nshape = { type = \"rectangle\", size = [1.0, 1979-05-27] }".into(),
            vec!["s.toml:14:", "objects[0].shape.size[1]", "`1979-05-27` is a date", "write a number"],
        ),
        (
            "a transform step with two keys",
            format!("name = \"s\"\n{rect}\ntransform = [ {{ translate = [0, 0, 1], scale = 2.0 }} ]"),
            vec!["s.toml:15:", "objects[0].transform[0]", "exactly one key (translate, rotate or scale)"],
        ),
        (
            "a huge translate",
            format!("name = \"s\"\n{rect}\ntransform = [ {{ translate = [0, 0, 1e300] }} ]"),
            vec!["s.toml:15:", "translate[2] = 1e300 mm", "±1e9 mm"],
        ),
    ];
    for (what, object, needles) in cases {
        let err = trace_error(&sensor_scene_with(&object));
        for n in &needles {
            assert!(err.contains(n), "{what}: lacks {n:?}:\n{err}");
        }
    }
    // A binary file given as OBJ.
    let dir = tempfile::tempdir().unwrap();
    let junk: Vec<u8> = (0..4000u32)
        .map(|i| (i.wrapping_mul(2654435761u32) >> 24) as u8)
        .collect();
    std::fs::write(dir.path().join("part.obj"), junk).unwrap();
    let err = trace_error_in(
        dir.path(),
        &sensor_scene_with(
            "name = \"s\"\nmaterial = \"det\"\nshape = { type = \"mesh\", file = \"part.obj\" }",
        ),
    );
    assert!(
        err.contains("s.toml:14:")
            && err.contains("part.obj: is not a text OBJ file")
            && err.contains(".glb"),
        "{err}"
    );
}

#[test]
fn a_pixel_grid_beside_its_sensor_warns() {
    let dir = tempfile::tempdir().unwrap();
    let text = sensor_scene_with(
        "name = \"s\"\nmaterial = \"det\"\nshape = { type = \"rectangle\", size = [1.0, 1.0] }",
    )
    .replace(
        "pixels = [4, 4]",
        "pixels = [4, 4]\npixel_grid = { pixels = [16, 16], pitch = 0.055, center = [5.0, 0.0] }",
    );
    let path = write(dir.path(), "s.toml", &text);
    let out = crate::common::run_ok(
        traxer()
            .arg("trace")
            .arg(&path)
            .args(["-n", "100", "-q", "-o"])
            .arg(dir.path().join("o")),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("pixel_grid") && err.contains("lies entirely outside"),
        "{err}"
    );
    // On the sensor: no warning.
    let on = write(
        dir.path(),
        "on.toml",
        &text.replace("center = [5.0, 0.0]", "center = [0.3, 0.0]"),
    );
    let out = crate::common::run_ok(
        traxer()
            .arg("trace")
            .arg(&on)
            .args(["-n", "100", "-q", "-o"])
            .arg(dir.path().join("o2")),
    );
    assert!(!String::from_utf8_lossy(&out.stderr).contains("pixel_grid"));
}

#[test]
fn a_define_given_twice_or_of_100_000_characters_is_said_short() {
    // Before: the second -D silently won, and a 100 000-character value was
    // echoed whole (100 kB on stderr).
    let dir = tempfile::tempdir().unwrap();
    let trace = |defines: &[String]| {
        let mut c = traxer();
        c.arg("trace").arg(repo().join("scenes/panter_al_ka.toml"));
        for d in defines {
            c.args(["-D", d]);
        }
        c.args(["-n", "10", "-q", "-o"]).arg(dir.path().join("o"));
        run_fails(&mut c, 2)
    };
    let err = trace(&["sensor_z=-1519".into(), "sensor_z=-1500".into()]);
    assert!(
        err.contains("`sensor_z` is overridden twice") && err.contains("-D sensor_z=-1500"),
        "{err}"
    );
    let err = trace(&[format!("sensor_z={}", "1".repeat(100_000))]);
    assert!(
        err.len() < 2000 && err.contains("characters)"),
        "{} bytes: {}",
        err.len(),
        &err[..err.len().min(3000)]
    );
}

#[test]
fn a_study_over_a_define_of_its_own_variable_takes_the_study_value() {
    // A focus scan sets sensor_z itself: the user's -D sensor_z is the
    // nominal value it replaces, not a second override to refuse.
    let dir = tempfile::tempdir().unwrap();
    crate::common::run_ok(
        traxer()
            .arg("focus")
            .arg(repo().join("scenes/panter_al_ka.toml"))
            .args([
                "-D",
                "sensor_z=-1519",
                "--from",
                "-1510",
                "--to",
                "-1530",
                "--steps",
                "4",
            ])
            .args(["-n", "2000", "-q", "-o"])
            .arg(dir.path().join("f")),
    );
}

#[test]
fn tables_of_huge_numbers_say_they_overflow_not_that_they_are_empty() {
    // Before: densities of 1e308 were "the spectrum holds no photons (all
    // densities zero)", and emission rates of 1e300 "emits nothing".
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "e.csv",
        "energy_keV,density\n1,1e308\n2,1e308\n3,1e308\n",
    );
    let err = trace_error_in(
        dir.path(),
        &scene("[70, 70]", "[0, 0, -1]", "{ table = \"e.csv\" }", "[]"),
    );
    assert!(
        err.contains("e.csv") && err.contains("largest number a double holds"),
        "{err}"
    );
    write(
        dir.path(),
        "em.csv",
        "Radius,Energy [keV],emRates\n0.1,1.0,1e300\n0.1,2.0,1e300\n0.2,1.0,1e300\n0.2,2.0,1e300\n",
    );
    let sun = "[materials.chip]\ntype = \"sensor\"\nsize = [14.0, 14.0]\npixels = [70, 70]\n\n[[sources]]\ntype = \"sun\"\nemission = \"em.csv\"\ncoupling = \"g_agamma = 1e-10\"\ntarget = { center = [0, 0, 0], radius = 1.0 }\n\n[[objects]]\nname = \"chip\"\nmaterial = \"chip\"\nshape = { type = \"rectangle\", size = [14.0, 14.0] }\ntransform = [ { translate = [0, 0, -100] } ]\n";
    let err = trace_error_in(dir.path(), sun);
    assert!(
        err.contains("largest number a double holds") && err.contains("emRates"),
        "{err}"
    );
}

#[test]
fn a_material_error_points_at_its_key_not_its_table() {
    // Issue 59 §4: a pixel grid of zero pixels was blamed on the material's
    // first line; the message is about `pixel_grid`, so its line is named.
    let text = scene("[20, 20]", "[0, 0, -1]", "{ line = 5.0 }", "[]").replace(
        "pixels = [20, 20]\n",
        "pixels = [20, 20]\n# a comment\npixel_grid = { pixels = [0, 256], pitch = 0.055 }\n",
    );
    let line = text
        .lines()
        .position(|l| l.starts_with("pixel_grid"))
        .unwrap()
        + 1;
    let err = trace_error(&text);
    assert!(
        err.contains(&format!(
            "s.toml:{line}: material `detector`: pixel_grid: pixels must be positive"
        )),
        "{err}"
    );
}

#[test]
fn a_foil_a_unit_slip_thick_is_refused_short() {
    // 1e300 nm is a unit slip, not a window, and is printed as 1e300, not in
    // 301 digits.
    let text = scene("[20, 20]", "[0, 0, -1]", "{ line = 5.0 }", "[]")
        + r#"
[materials.window]
type = "foil"
material = "Si3N4"
thickness_nm = 1e300

[[objects]]
name = "w"
material = "window"
shape = { type = "rectangle", size = [14.0, 14.0] }
transform = [ { translate = [0, 0, 5] } ]
"#;
    let err = trace_error(&text);
    assert!(
        err.contains("thickness_nm = 1e300: at most 1e7 nm (10 mm) for a foil"),
        "{err}"
    );
}

#[test]
fn an_emission_table_whose_rates_overflow_is_bad_input_naming_the_file() {
    // It said "the table emits nothing" with exit 1.
    let dir = tempfile::tempdir().unwrap();
    let rows = "Radius,Energy [keV],emRates\n0.1,1,1e300\n0.1,2,1e300\n0.2,1,1e300\n0.2,2,1e300\n";
    let path = write(dir.path(), "huge.csv", rows);
    let err = run_fails(
        traxer()
            .args(["solar-flux", "-q", "--table"])
            .arg(&path)
            .arg("-o")
            .arg(dir.path().join("out")),
        2,
    );
    assert!(
        err.contains("huge.csv: the rates, summed over the Sun's volume, exceed the largest number a double holds"),
        "{err}"
    );
    assert!(!dir.path().join("out").exists());
    let zero = write(dir.path(), "zero.csv", &rows.replace("1e300", "0"));
    let err = run_fails(
        traxer()
            .args(["solar-flux", "-q", "--table"])
            .arg(&zero)
            .arg("-o")
            .arg(dir.path().join("out")),
        2,
    );
    assert!(err.contains("zero.csv: every emission rate is 0"), "{err}");
}
