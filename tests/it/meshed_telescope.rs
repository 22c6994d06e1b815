//! The meshed LLNL telescope against the analytic one: the shipped mesh files are
//! what `traxer tessellate` makes from the data, they load as the telescope, and
//! `traxer compare` shows the meshes converging to the analytic image.

use crate::common::{repo, run_ok, traxer};

#[test]
fn shipped_telescope_meshes_are_regenerated_exactly_by_tessellate() {
    let dir = tempfile::tempdir().unwrap();
    for ext in ["glb", "obj"] {
        let out = dir.path().join(format!("t.{ext}"));
        run_ok(
            traxer()
                .arg("tessellate")
                .arg(repo().join("meshes/llnl_telescope.toml"))
                .args(["--segments", "60", "--rings", "2", "--out"])
                .arg(&out),
        );
        let shipped = std::fs::read(repo().join(format!("meshes/llnl_telescope.{ext}"))).unwrap();
        assert!(
            std::fs::read(&out).unwrap() == shipped,
            "meshes/llnl_telescope.{ext} is stale: run scripts/make_meshes.sh"
        );
    }
}

#[test]
fn shipped_mesh_file_builds_the_whole_telescope() {
    let dev = crate::common::device();
    let analytic =
        traxer::scene::Scene::load(&dev, &repo().join("scenes/panter_al_ka.toml"), &[]).unwrap();
    for ext in ["glb", "obj"] {
        let define = format!("telescope=../meshes/llnl_telescope.{ext}");
        let meshed = traxer::scene::Scene::load(
            &dev,
            &repo().join("scenes/panter_al_ka_meshed.toml"),
            &[define],
        )
        .unwrap();
        // Same objects, same names, same materials (coatings per shell).
        let names = |s: &traxer::scene::Scene| -> Vec<(String, String)> {
            s.objects
                .iter()
                .map(|o| (o.name.clone(), format!("{:?}", o.material)))
                .collect()
        };
        assert_eq!(names(&meshed), names(&analytic), "{ext}");
        // 13 shells × (2 mirrors + 2 backs + 4 edges) × 60 × 2 × 2 triangles.
        assert_eq!(meshed.triangle_count, 13 * 8 * 240, "{ext}");
    }
}

#[test]
fn meshes_converge_to_the_analytic_telescope() {
    let dir = tempfile::tempdir().unwrap();
    run_ok(
        traxer()
            .arg("compare")
            .arg(repo().join("scenes/panter_al_ka.toml"))
            .args(["--resolutions", "4x1,15x1,60x2", "-n", "300000", "-q"])
            .arg("--also")
            .arg(repo().join("scenes/panter_al_ka_meshed.toml"))
            .args(["-D", "coating=perfect", "-D", "figure_error=none", "-o"])
            .arg(dir.path()),
    );
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("compare.json")).unwrap()).unwrap();
    let rows = v["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 5);
    let get = |i: usize, k: &str| rows[i]["diameter_diff_pct"][k].as_f64().unwrap().abs();
    let on = |i: usize| {
        rows[i]["photons_on_sensor_diff_pct"]
            .as_f64()
            .unwrap()
            .abs()
    };
    // The chords of a coarse mesh lie inside the cones (sagitta r·Δφ²/8: 0.17 mm
    // at 4 segments per 30°) and lose photons at the edges; the loss shrinks as
    // 1/N² with the segments N, and with it the change of the image.
    assert!(on(1) > on(2) && on(2) > on(3), "{rows:?}");
    assert!(on(1) > 1.0 && on(3) < 0.2, "{rows:?}");
    assert!(get(1, "hpd") > get(3, "hpd"), "{rows:?}");
    // At the shipped resolution (60 × 2, row 3 in memory, row 4 from the file)
    // HPD, 80 % and 90 % agree with the analytic telescope to better than 1 %
    // (the issue's bound; about 0.05 % is reached).
    for row in [3, 4] {
        for k in ["hpd", "d80", "d90"] {
            assert!(get(row, k) < 1.0, "row {row} {k}: {rows:?}");
        }
    }
    assert!(dir.path().join("compare.csv").is_file());
}

#[test]
fn telescope_mesh_option_errors_name_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let scene = |extra: &str| {
        format!(
            r#"
[[sources]]
type = "parallel"
aperture = {{ center = [0, 0, 300], radius = 110.0 }}
energy = {{ line = 1.49 }}

[[assemblies]]
type = "llnl_telescope"
mesh = "{}"
{extra}
"#,
            repo().join("meshes/llnl_telescope.glb").display()
        )
    };
    let e = crate::common::load_error(
        dir.path(),
        &scene("tessellate = { segments = 10, rings = 1 }"),
    );
    assert!(e.contains("not both"), "{e}");
    // The parts are looked up as <assembly name>_<part>.
    let e = crate::common::load_error(dir.path(), &scene(r#"name = "tel""#));
    assert!(
        e.contains("no part named `tel_front_1`") && e.contains("llnl_front_1"),
        "{e}"
    );
}
