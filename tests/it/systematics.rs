//! `traxer systematics`: the figure draws' spread of the HPD is the spread the
//! fit's error propagation predicts; the files agree with each other and with
//! the physics of a known variation; refusals name what is wrong.

use crate::common::{repo, run_fails, run_ok, traxer};
use traxer::studies::systematics::{self, Kind, Request, Settings};
use traxer::xray::figure_covariance::FigureCovariance;

fn request(sources: &[&str], draws: usize) -> Request {
    Request {
        sources: Some(sources.iter().map(|s| s.to_string()).collect()),
        figure_draws: draws,
        figure_preset: None,
        figure_hold: None,
        pointing_arcmin: 1.0,
        tilt_arcmin: 1.0,
        solar_model: "b16_gs98".into(),
        gas_pressure_mbar: None,
        gas_temperature_k: None,
        vary: Vec::new(),
        seed: 5,
    }
}

#[test]
fn the_figure_draws_spread_the_hpd_as_the_fits_error_propagation_predicts() {
    use traxer::studies::fit::{Bounds, FitSettings, LocalAlgorithm};
    use traxer::studies::fit_errors::sensitivity;
    // The PANTER Al Kα scene with the shipped preset, given a covariance of
    // the narrow width alone (σ = 10″). The fit's prediction of the HPD's
    // spread is linear propagation, σ_HPD = |∂HPD/∂narrow| · 10″, the
    // derivative by the fit's own central differences
    // (fit_errors::sensitivity, 1 M photons: ≈ 4 % error); the study's is the
    // sample standard deviation of 40 draws of 200 000 photons, whose relative
    // 1σ error is 1/√(2·39) = 11 % (the photons' own noise, ≈ 1.3″ about a
    // straight line through the draws, adds in quadrature to the ≈ 6″
    // spread: 2 %). Required: within 35 % (3σ of the two errors combined).
    let dev = crate::common::device();
    let path = repo().join("scenes/panter_al_ka.toml");
    let mut scene = traxer::scene::Scene::load(&dev, &path, &[]).unwrap();
    let sigma = 10.0;
    let entry = scene
        .figure_errors
        .figure_errors
        .get_mut("llnl_panter")
        .unwrap();
    entry.covariance = Some(FigureCovariance {
        parameters: vec!["in_plane_narrow".into()],
        matrix: vec![vec![sigma * sigma]],
        unconstrained: Vec::new(),
    });
    let nominal = entry.parameters();
    let plan = systematics::plan(&scene, &request(&["figure"], 40)).unwrap();
    assert_eq!(plan.variations.len(), 41);
    assert_eq!(plan.sources[0].kind, Kind::Draws);
    let settings = Settings {
        sampling: traxer::studies::Sampling {
            photons: 200_000,
            seed: 5,
            threads: 0,
            sensor: None,
        },
        central_mm: 5.0,
        central_circle: false,
    };
    let load = |_: &[String]| unreachable!("figure draws reuse the loaded scene");
    let s = systematics::run(&mut scene, &load, &plan, &settings, &[], &(), |_, _| {}).unwrap();
    let study = s.sources[0].effects[2].sigma;
    let fit = FitSettings {
        bounds: Bounds {
            lower: [0.0, nominal.in_plane_wide, nominal.wide_fraction, 0.0],
            upper: [120.0, nominal.in_plane_wide, nominal.wide_fraction, 0.0],
        },
        target: traxer::studies::Diameters {
            hpd: 206.0,
            d80: 397.0,
            d90: 549.0,
        },
        run: traxer::trace::RunConfig::new(1_000_000, 3),
        sensor: 0,
        global_evaluations: 0,
        local_evaluations: 0,
        local_algorithm: LocalAlgorithm::Sbplx,
    };
    let j = sensitivity(&mut scene, &fit, &nominal, &()).unwrap();
    let predicted = j.rows[0][0].abs() * sigma;
    eprintln!("HPD spread: study {study:.2}″, predicted {predicted:.2}″");
    assert!(
        predicted > 3.0,
        "the test needs a visible spread: {predicted}"
    );
    assert!(
        (study / predicted - 1.0).abs() < 0.35,
        "study {study} vs predicted {predicted}"
    );
    // The scene's mirrors are back at the preset after the draws.
    let again = systematics::run(
        &mut scene,
        &load,
        &plan,
        &settings,
        &s.outcomes[..1],
        &(),
        |_, _| {},
    )
    .unwrap();
    assert_eq!(
        again.outcomes, s.outcomes,
        "the same draws, the same photons"
    );
}

fn study(out: &std::path::Path, extra: &[&str]) -> std::process::Command {
    let mut c = traxer();
    c.arg("systematics")
        .arg(repo().join("scenes/panter_al_ka.toml"))
        .args(["-n", "30000", "--sources", "figure", "--figure-draws", "4"])
        .args(["--vary", "sensor_z=-1559:-1479", "-q", "-o"])
        .arg(out)
        .args(extra);
    c
}

#[test]
fn the_files_agree_and_a_defocus_range_gives_its_rms_difference() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s");
    run_ok(&mut study(&out, &[]));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("systematics.json")).unwrap())
            .unwrap();
    let csv = std::fs::read_to_string(out.join("systematics.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 1 + 4 + 2, "{csv}");
    assert_eq!(rows[0][0], "nominal");
    // The defocus range: σ is the RMS of the two HPD changes, the shift their
    // mean (recomputed here from the table's rows).
    let hpd = |r: &Vec<&str>| r[5].parse::<f64>().unwrap();
    let (d_lo, d_hi) = (hpd(&rows[5]) - hpd(&rows[0]), hpd(&rows[6]) - hpd(&rows[0]));
    let vary = &json["sources"][1];
    assert_eq!(vary["name"], "vary:sensor_z");
    let e = &vary["effects"]["hpd_arcsec"];
    let rms = (0.5 * (d_lo * d_lo + d_hi * d_hi)).sqrt();
    assert!(
        (e["sigma"].as_f64().unwrap() / rms - 1.0).abs() < 1e-6,
        "{e}"
    );
    // Defocus by ±40 mm, far beyond the depth of focus (the shells' rays
    // converge at 2·R/f ≈ 0.1 rad: 4 mm of blur, 550″), widens the image on
    // both sides of the focus: both changes are positive.
    assert!(d_lo > 0.0 && d_hi > 0.0, "{d_lo} {d_hi}");
    assert!((e["shift"].as_f64().unwrap() - 0.5 * (d_lo + d_hi)).abs() < 1e-6 * rms);
    // The maps: each variation's map holds its flux (a binned sensor image);
    // σ² is the sum of the sources' σ²; the nominal map is variation 0.
    let npy = |f: &str| traxer::output::read_npy(&out.join(f)).unwrap();
    let (shape, v) = npy("map_variations.npy");
    let n_pix = (shape[1] * shape[2]) as usize;
    for (k, r) in rows.iter().enumerate() {
        let sum: f64 = v[k * n_pix..(k + 1) * n_pix].iter().sum();
        let flux: f64 = r[3].parse().unwrap();
        assert!((sum / flux - 1.0).abs() < 1e-12, "row {k}: {sum} vs {flux}");
    }
    assert_eq!(npy("map_nominal.npy").1, v[..n_pix]);
    let total = npy("map_sigma.npy").1;
    let (by_shape, by) = npy("map_sigma_by_source.npy");
    assert_eq!(by_shape[0], 2);
    for p in 0..n_pix {
        let sq = by[p].powi(2) + by[n_pix + p].powi(2);
        assert!((total[p].powi(2) - sq).abs() <= 1e-12 * sq.max(1e-300));
    }
    for f in [
        "systematics.fits",
        "map_mean.png",
        "map_sigma.png",
        "map_mean.npy",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    // σ relative to the mean image, pixel by pixel.
    let mean = npy("map_mean.npy").1;
    let relative = npy("map_sigma_relative.npy").1;
    for p in 0..n_pix {
        match mean[p] > 0.0 {
            true => assert!(
                (relative[p] - total[p] / mean[p]).abs() <= 1e-12 * relative[p].abs().max(1e-300)
            ),
            false => assert!(relative[p].is_nan()),
        }
    }
    // The Monte Carlo noise of the σ map, from the two halves of the photons:
    // present, and far below the σ of a ±40 mm defocus (common random
    // numbers), but not zero (the halves are independent).
    let noise = npy("map_sigma_noise.npy").1;
    let ratio = json["maps"]["noise_to_sigma"].as_f64().unwrap();
    assert!(ratio > 0.0 && ratio < 0.5, "{ratio}");
    assert!(noise.iter().all(|v| v.is_finite() && *v >= 0.0));
    // Traced as two halves added exactly, the nominal image is a plain trace's
    // to the bit.
    let plain = out.parent().unwrap().join("plain");
    run_ok(
        traxer()
            .arg("trace")
            .arg(repo().join("scenes/panter_al_ka.toml"))
            .args(["-n", "30000", "-q", "-o"])
            .arg(&plain),
    );
    let sensor: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(plain.join("sensor.json")).unwrap()).unwrap();
    let traced = sensor["sensor"]["total_flux"].as_f64().unwrap();
    assert_eq!(
        traced.to_bits(),
        json["nominal"]["flux"].as_f64().unwrap().to_bits()
    );
}

#[test]
fn sources_the_scene_cannot_vary_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let base = |args: &[&str]| {
        let mut c = traxer();
        c.arg("systematics")
            .arg(repo().join("scenes/panter_al_ka.toml"))
            .args(["-n", "1000", "-q", "-o"])
            .arg(dir.path().join("x"))
            .args(args);
        c
    };
    let err = run_fails(&mut base(&["--sources", "pointing_x"]), 2);
    assert!(
        err.contains("cannot vary pointing_x") && err.contains("offset_x"),
        "{err}"
    );
    let err = run_fails(&mut base(&["--sources", "wobble"]), 2);
    assert!(
        err.contains("unknown source of uncertainty `wobble`"),
        "{err}"
    );
    let err = run_fails(&mut base(&["--vary", "no_such=1:2"]), 2);
    assert!(
        err.contains("no variable `no_such`") && err.contains("sensor_z"),
        "{err}"
    );
    let err = run_fails(&mut base(&["--vary", "sensor_z=3:1"]), 2);
    assert!(err.contains("LOW must be below HIGH"), "{err}");
    let err = run_fails(
        &mut base(&[
            "--sources",
            "figure",
            "--figure-preset",
            "llnl_panter_rough",
        ]),
        2,
    );
    assert!(err.contains("has no covariance"), "{err}");
    assert!(!dir.path().join("x").exists(), "nothing written");
}

/// A gas detector under a parallel beam (silently_wrong's scene) with the
/// pointing variable a built-in source varies: a scene that loads in
/// milliseconds, for refusals that must come before the first photon.
fn small_scene(dir: &std::path::Path) -> std::path::PathBuf {
    let text = crate::silently_wrong::GAS_SCENE.replace("[vars]\n", "[vars]\noffset_x = 0.0\n");
    crate::common::write(dir, "small.toml", &text)
}

#[test]
fn a_variable_varied_twice_a_misspelt_preset_and_impossible_draws_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = small_scene(dir.path());
    let out = dir.path().join("x");
    let base = |args: &[&str]| {
        let mut c = traxer();
        c.arg("systematics")
            .arg(&scene)
            .args(["-n", "100", "-q", "-o"])
            .arg(&out)
            .args(args);
        c
    };
    // Before: pointing_x and --vary offset_x both varied offset_x, and the
    // total counted it twice (σ √2 too big).
    let err = run_fails(&mut base(&["--vary", "offset_x=-1:1"]), 2);
    assert!(
        err.contains("pointing_x already varies `offset_x`") && err.contains("--pointing"),
        "{err}"
    );
    let err = run_fails(
        &mut base(&[
            "--sources",
            "pointing_x",
            "--vary",
            "energy=2:3",
            "--vary",
            "energy=1:4",
        ]),
        2,
    );
    assert!(err.contains("--vary energy is given twice"), "{err}");
    // Before: a misspelt preset made the figure "skipped" and the study ran
    // without it, exit 0.
    let err = run_fails(&mut base(&["--figure-preset", "llnl_pantr"]), 2);
    assert!(err.contains("cannot vary figure"), "{err}");
    let err = run_fails(
        &mut base(&["--sources", "pointing_x", "--figure-hold", "none"]),
        2,
    );
    assert!(
        err.contains("--figure-hold is given but figure is not among --sources"),
        "{err}"
    );
    let err = run_fails(&mut base(&["--figure-draws", "0"]), 2);
    assert!(
        err.contains("--figure-draws 0") && err.contains("at least 2"),
        "{err}"
    );
    assert!(!out.exists(), "nothing written");
}

#[test]
fn a_range_end_the_scene_refuses_is_found_before_the_first_photon() {
    // Before: the nominal scene and the low end were traced, the high end
    // refused, and the record left behind could never be resumed.
    let dir = tempfile::tempdir().unwrap();
    let scene = small_scene(dir.path());
    let out = dir.path().join("x");
    let err = run_fails(
        traxer()
            .arg("systematics")
            .arg(&scene)
            .args(["-n", "1000", "--sources", "pointing_x"])
            .args(["--vary", "energy=3:-1", "-q", "-o"])
            .arg(&out),
        2,
    );
    assert!(err.contains("LOW must be below HIGH"), "{err}");
    let err = run_fails(
        traxer()
            .arg("systematics")
            .arg(&scene)
            .args(["-n", "1000", "--sources", "pointing_x"])
            .args(["--vary", "energy=-1:3", "-q", "-o"])
            .arg(&out),
        2,
    );
    assert!(
        err.contains("vary:energy (energy=-1.0)") && err.contains("nothing was traced"),
        "{err}"
    );
    assert!(
        !out.join("systematics_checkpoint.jsonl").exists(),
        "no record to resume"
    );
}

#[test]
fn the_central_region_may_be_a_circle_a_signal_region() {
    // --central-radius: the table's central flux is the flux within that
    // circle about the sensor's centre; the nominal variation is a trace with
    // the same photons, so `traxer eef --radius --center 0,0` of that trace
    // gives the same number.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s");
    let scene = repo().join("scenes/panter_al_ka.toml");
    run_ok(
        traxer()
            .arg("systematics")
            .arg(&scene)
            .args(["-n", "30000", "--sources", "figure", "--figure-draws", "2"])
            .args(["--central-radius", "1", "-q", "-o"])
            .arg(&out),
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("systematics.json")).unwrap())
            .unwrap();
    assert!(
        json["central_region"]
            .as_str()
            .unwrap()
            .starts_with("circle"),
        "{json}"
    );
    let central = json["nominal"]["central_flux"].as_f64().unwrap();
    let plain = dir.path().join("t");
    run_ok(
        traxer()
            .arg("trace")
            .arg(&scene)
            .args(["-n", "30000", "-q", "-o"])
            .arg(&plain),
    );
    let r = run_ok(
        traxer()
            .current_dir(dir.path())
            .arg("eef")
            .arg(plain.join("sensor.npy"))
            .args(["--radius", "1", "--center", "0,0", "--json"]),
    );
    let q: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    let flux = q["signal_regions"]["regions"][0]["flux"].as_f64().unwrap();
    assert!((flux / central - 1.0).abs() < 1e-9, "{flux} vs {central}");
    let total = json["nominal"]["flux"].as_f64().unwrap();
    assert!(
        central > 0.3 * total && central < total,
        "{central} of {total}"
    );
}

#[test]
fn the_optical_constants_source_is_the_other_tables_difference() {
    // A flat gold mirror at 0.5° under an 8 keV beam: every photon's weight is
    // R, so the source's σ of the flux is |R_Chantler / R_Henke − 1| (that the
    // traced flux is R on each table: xray.rs). Here it is computed from two
    // plain traces of the scene on each table, not by the study (1e-9: the
    // same photons, weights only).
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "mirror_optical_constants = \"$mirror_optical_constants\"\n[vars]\nmirror_optical_constants = \"henke\"\n{}",
        crate::xray::coated_flat_mirror_scene("bare_gold", 0.5, "{ line = 8.0 }", "")
    );
    let scene = crate::common::write(dir.path(), "gold.toml", &text);
    let out = dir.path().join("s");
    run_ok(
        traxer()
            .arg("systematics")
            .arg(&scene)
            .args(["-n", "2000", "--sources", "optical_constants", "-q", "-o"])
            .arg(&out),
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("systematics.json")).unwrap())
            .unwrap();
    let r = |table: &str| {
        let defines = [format!("mirror_optical_constants={table}")];
        let s = traxer::scene::Scene::load(&crate::common::device(), &scene, &defines).unwrap();
        let r = traxer::trace::run(&s, &traxer::trace::RunConfig::new(2000, 1)).unwrap();
        r.images[0].total_flux()
    };
    let want = (r("chantler") / r("henke") - 1.0).abs();
    let text = json.to_string();
    let sigma = json["sources"]
        .as_array()
        .and_then(|s| s.iter().find(|s| s["name"] == "optical_constants"))
        .map(|s| s["effects"]["flux"]["sigma"].as_f64().unwrap())
        .unwrap_or_else(|| panic!("no optical_constants source: {text}"))
        / json["nominal"]["flux"].as_f64().unwrap();
    assert!(want > 1e-3, "the tables must differ here: {want}");
    assert!((sigma - want).abs() < 1e-9, "σ {sigma} vs |ΔR/R| {want}");
}
