//! What every output carries: CSV that survives awkward names, the provenance
//! record, and progress reports that add up.

use crate::common::{device, repo, run_ok, traxer};
use traxer::analysis::ImageQuality;
use traxer::studies::compare::Row;
use traxer::studies::Measured;

fn row(label: &str, hpd: f64, seconds: f64) -> Row {
    let q = ImageQuality {
        centroid_mm: [0.0, 0.0],
        total_flux: 1.0,
        hpd_mm: hpd,
        d80_mm: 2.0 * hpd,
        d90_mm: 3.0 * hpd,
        focal_length_mm: None,
        hpd_arcsec: None,
        d80_arcsec: None,
        d90_arcsec: None,
    };
    Row {
        label: label.into(),
        path: label.into(),
        triangles: 10,
        measured: Measured {
            quality: Some(q),
            emitted: 1000,
            on_sensor: 500,
            seconds,
            threads: 2,
        },
    }
}

#[test]
fn a_file_path_with_a_comma_stays_one_csv_field() {
    // compare.csv's first column is the scene file of `--also` rows: a comma in
    // it used to split the row.
    let dir = tempfile::tempdir().unwrap();
    let rows = [
        row("analytic", 1.0, 1.0),
        row("scenes/run 3, \"meshed\".toml", 1.1, 2.0),
    ];
    let provenance = traxer::output::Provenance::of_table(&traxer::run::Invocation::new(["test"]));
    traxer::output::write_compare(dir.path(), &rows, &provenance).unwrap();
    let text = std::fs::read_to_string(dir.path().join("compare.csv")).unwrap();
    let mut r = csv::Reader::from_reader(text.as_bytes());
    let header = r.headers().unwrap().clone();
    let records: Vec<csv::StringRecord> = r.records().map(|x| x.unwrap()).collect();
    assert_eq!(records.len(), 2);
    for rec in &records {
        assert_eq!(rec.len(), header.len(), "{text}");
    }
    assert_eq!(&records[1][0], "scenes/run 3, \"meshed\".toml");
    // The difference is computed against the first row: +10 %.
    let hpd_diff: f64 = records[1][6].parse().unwrap();
    assert!((hpd_diff - 10.0).abs() < 1e-9, "{text}");
}

fn sha256_of(path: &std::path::Path) -> String {
    traxer::files::sha256_hex(&std::fs::read(path).unwrap())
}

#[test]
fn renders_plots_and_studies_carry_the_same_provenance() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/spheres.toml");
    let png = dir.path().join("look.png");
    run_ok(
        traxer()
            .arg("render")
            .arg(&scene)
            .args([
                "--width", "24", "--height", "16", "--spp", "1", "-q", "-s", "5",
            ])
            .arg("--out")
            .arg(&png),
    );
    let side: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("look.json")).unwrap()).unwrap();
    let p = &side["provenance"];
    assert_eq!(p["scene_sha256"], sha256_of(&scene));
    assert_eq!(p["seed"], 5);
    assert_eq!(p["git_hash"], traxer::run::git_hash());
    assert!(p["embree_version"]
        .as_str()
        .unwrap()
        .starts_with(['3', '4']));
    assert!(p["command_line"].as_array().unwrap().len() > 3);
    assert_eq!(side["file"], "look.png");
    assert_eq!(side["details"]["width"], 24);

    let plot = dir.path().join("r.png");
    run_ok(
        traxer()
            .args(["reflectivity", "--coating", "gold", "--energy", "1.49"])
            .args(["--angle", "0:1:0.5", "--plot"])
            .arg(&plot),
    );
    let side: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("r.json")).unwrap()).unwrap();
    assert_eq!(side["provenance"]["scene_path"], serde_json::Value::Null);
    assert_eq!(side["details"]["coating"], "gold");

    // A focus scan records the scene, its variables and the run.
    let focus = dir.path().join("focus");
    let scene = repo().join("scenes/wolter1_parallel.toml");
    run_ok(
        traxer()
            .arg("focus")
            .arg(&scene)
            .args(["--var", "focus_shift", "--from=-2", "--to=2", "--steps=5"])
            .args(["-n", "20000", "-s", "3", "-q", "-D", "off_axis=0.01", "-o"])
            .arg(&focus),
    );
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(focus.join("focus.json")).unwrap()).unwrap();
    let p = &json["provenance"];
    assert_eq!(p["scene_sha256"], sha256_of(&scene));
    assert_eq!(p["overrides"], serde_json::json!(["off_axis=0.01"]));
    assert_eq!(p["variables"]["off_axis"], 0.01);
    assert_eq!(
        p["variables"].get("focus_shift"),
        None,
        "the swept variable"
    );
    assert_eq!(
        (p["seed"].as_u64(), p["photons"].as_u64()),
        (Some(3), Some(20000))
    );
}

#[test]
fn progress_reports_add_up_to_the_work_done() {
    use std::sync::atomic::{AtomicU64, Ordering};
    let scene =
        traxer::scene::Scene::load(&device(), &repo().join("scenes/wolter1_parallel.toml"), &[])
            .unwrap();
    // Not a multiple of the chunk size: the last chunk reports its own size.
    let photons = 3 * traxer::trace::CHUNK + 123;
    let done = AtomicU64::new(0);
    let cfg = traxer::trace::RunConfig::new(photons, 1);
    let with = traxer::trace::run_with_progress(&scene, &cfg, &|n| {
        done.fetch_add(n, Ordering::Relaxed);
    })
    .unwrap();
    assert_eq!(done.load(Ordering::Relaxed), photons);
    // Reporting changes nothing.
    let without = traxer::trace::run(&scene, &cfg).unwrap();
    assert_eq!(with.images[0].counts, without.images[0].counts);
    // A render reports its rows.
    let rows = AtomicU64::new(0);
    let s =
        traxer::scene::Scene::load(&device(), &repo().join("scenes/spheres.toml"), &[]).unwrap();
    let settings = traxer::render::RenderSettings {
        width: 8,
        height: 5,
        spp: 1,
        max_depth: 2,
        seed: 1,
    };
    let (_, cam) = s.cameras.iter().next().unwrap();
    traxer::render::render_with_progress(&s, cam, &s.sky, &[], &settings, &|n| {
        rows.fetch_add(n, Ordering::Relaxed);
    });
    assert_eq!(rows.load(Ordering::Relaxed), 5);
}
