//! Figure errors (SPEC §5): the perturbation's statistics drawn directly and
//! measured on a flat mirror, absorption below the surface, and that a zero figure
//! error is exactly the perfect mirror.

use glam::DVec3;
use traxer::random::PhotonRng;
use traxer::trace::{self, RunConfig};
use traxer::xray::figure_error::{FigureError, Perturbed};

/// PANTER's Al Kα diameters (SPEC §3) as `fit-figure-error` arguments.
const PANTER_AL_TARGETS: [&str; 6] = [
    "--target-hpd",
    "206",
    "--target-c80",
    "397",
    "--target-c90",
    "549",
];

const ARCSEC: f64 = std::f64::consts::PI / (180.0 * 3600.0);

#[test]
fn perturbation_has_zero_mean_and_the_requested_widths() {
    let fe = FigureError {
        in_plane_narrow: 30.0,
        in_plane_wide: 200.0,
        wide_fraction: 0.25,
        out_of_plane: 12.0,
    };
    // A ray reflected at 0.8° off a surface with normal +z, travelling along +x.
    let g = 0.8f64.to_radians();
    let n = DVec3::Z;
    let r = DVec3::new(g.cos(), 0.0, g.sin());
    let n_perp = n.cross(r).normalize();
    let s = n_perp.cross(r);
    let count = 400_000;
    let (mut m_in, mut m_out, mut in2, mut in4, mut out2, mut cross) =
        (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for i in 0..count {
        let mut rng = PhotonRng::new(7, i);
        let Perturbed::Direction(d) = fe.perturb(r, n, &mut rng) else {
            panic!("200″ tilts cannot reach 0.8° below the surface at this count");
        };
        assert!((d.length() - 1.0).abs() < 1e-12);
        // The in-plane and out-of-plane tilt angles, exactly.
        let a = d.dot(s).atan2(d.dot(r)) / ARCSEC;
        let b = d.dot(n_perp).atan2(d.dot(r)) / ARCSEC;
        m_in += a;
        m_out += b;
        in2 += a * a;
        in4 += a.powi(4);
        out2 += b * b;
        cross += a * b;
    }
    let c = count as f64;
    let (w, sn, sw, so) = (
        fe.wide_fraction,
        fe.in_plane_narrow,
        fe.in_plane_wide,
        fe.out_of_plane,
    );
    let var_in = (1.0 - w) * sn * sn + w * sw * sw;
    // Means: zero within 4 standard errors.
    assert!(
        (m_in / c).abs() < 4.0 * (var_in / c).sqrt(),
        "in-plane mean {}",
        m_in / c
    );
    assert!(
        (m_out / c).abs() < 4.0 * so / c.sqrt(),
        "out-of-plane mean {}",
        m_out / c
    );
    // Widths: the mixture's variance and fourth moment (3 Σ wᵢσᵢ⁴), and σ⊥.
    assert!(
        (in2 / c / var_in - 1.0).abs() < 0.02,
        "{} vs {var_in}",
        in2 / c
    );
    let m4 = 3.0 * ((1.0 - w) * sn.powi(4) + w * sw.powi(4));
    assert!((in4 / c / m4 - 1.0).abs() < 0.05, "{} vs {m4}", in4 / c);
    assert!(
        (out2 / c / (so * so) - 1.0).abs() < 0.01,
        "{} vs {}",
        out2 / c,
        so * so
    );
    // Independent directions: correlation ≈ 0.
    let corr = cross / c / (in2 / c * out2 / c).sqrt();
    assert!(corr.abs() < 0.01, "correlation {corr}");
}

#[test]
fn zero_widths_leave_the_reflection_bit_for_bit_specular() {
    let fe = FigureError {
        in_plane_narrow: 0.0,
        in_plane_wide: 0.0,
        wide_fraction: 0.4,
        out_of_plane: 0.0,
    };
    assert!(fe.is_perfect());
    let r = DVec3::new(0.3, 0.1, 0.2).normalize();
    for i in 0..100 {
        assert_eq!(
            fe.perturb(r, DVec3::Z, &mut PhotonRng::new(1, i)),
            Perturbed::Direction(r)
        );
    }
}

/// The spot on the flat-mirror bench's screen: (mean, variance) along x and y in
/// mm, and the photons recorded, for a mirror material line `figure`.
fn flat_mirror_spot(graze_deg: f64, figure: &str) -> ([f64; 4], u64, u64) {
    let mirror = format!("type = \"mirror\"\n{figure}");
    let s = crate::common::scene(&crate::common::flat_mirror_bench(
        graze_deg,
        &mirror,
        "{ line = 1.49 }",
        600,
        "",
        "",
    ));
    let r = trace::run(&s, &RunConfig::new(200_000, 3)).unwrap();
    let img = &r.images[0].flux();
    let (n, pitch) = (600usize, 0.1);
    let (mut w, mut sx, mut sy, mut sxx, mut syy) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (k, &v) in img.iter().enumerate() {
        let (x, y) = (
            ((k % n) as f64 + 0.5) * pitch,
            ((k / n) as f64 + 0.5) * pitch,
        );
        w += v;
        sx += v * x;
        sy += v * y;
        sxx += v * x * x;
        syy += v * y * y;
    }
    let (mx, my) = (sx / w, sy / w);
    (
        [mx, sxx / w - mx * mx, my, syy / w - my * my],
        r.stats.reached_sensor,
        r.stats.scattered_below_surface,
    )
}

#[test]
fn flat_mirror_spreads_the_spot_in_and_out_of_the_plane_of_incidence() {
    // θ = 3°: the reflected beam leaves at 2θ = 6° from −z in the y–z plane (the
    // plane of incidence) and meets the screen 200 mm below, so an in-plane tilt δ
    // moves the spot along y by 200·δ/cos²(2θ) and an out-of-plane tilt ε along x
    // by (200/cos 2θ)·ε. Widths far below θ: nothing is tilted below the surface.
    let (graze, s_in, s_out) = (3.0f64, 1000.0, 400.0);
    let (perfect, n0, _) = flat_mirror_spot(graze, "");
    let (fuzzy, n1, below) = flat_mirror_spot(
        graze,
        &format!(
            "figure_error = {{ in_plane_narrow = {s_in}, in_plane_wide = 0.0, wide_fraction = 0.0, out_of_plane = {s_out} }}"
        ),
    );
    assert_eq!((n0, n1, below), (200_000, 200_000, 0));
    let c2 = (2.0 * graze).to_radians().cos();
    let want_y = 200.0 * s_in * ARCSEC / (c2 * c2);
    let want_x = 200.0 / c2 * s_out * ARCSEC;
    // The pencil beam's own size (and the pixels) add in quadrature: subtract the
    // perfect mirror's variance.
    let got_x = (fuzzy[1] - perfect[1]).sqrt();
    let got_y = (fuzzy[3] - perfect[3]).sqrt();
    assert!(
        (got_y / want_y - 1.0).abs() < 0.02,
        "in-plane: {got_y} mm vs {want_y}"
    );
    assert!(
        (got_x / want_x - 1.0).abs() < 0.03,
        "out-of-plane: {got_x} mm vs {want_x}"
    );
    // The spot stays centred where the specular beam lands.
    assert!((fuzzy[0] - perfect[0]).abs() < 0.01 && (fuzzy[2] - perfect[2]).abs() < 0.02);
}

#[test]
fn photons_tilted_below_the_surface_are_absorbed() {
    // In-plane σ equal to the grazing angle (0.3° = 1080″): a tilt below −θ, i.e.
    // a standard normal deviate below −1, goes into the mirror: Φ(−1) = 0.158655.
    let (_, reached, below) = flat_mirror_spot(
        0.3,
        "figure_error = { in_plane_narrow = 1080.0, in_plane_wide = 0.0, wide_fraction = 0.0, out_of_plane = 0.0 }",
    );
    let p = below as f64 / 200_000.0;
    let sigma = (0.158655f64 * (1.0 - 0.158655) / 200_000.0).sqrt();
    assert!((p - 0.158655).abs() < 4.0 * sigma, "absorbed fraction {p}");
    assert_eq!(reached + below, 200_000);
}

#[test]
fn zero_figure_error_reproduces_the_perfect_mirror_exactly() {
    let scene = crate::common::repo().join("scenes/panter_al_ka.toml");
    let dev = crate::common::device();
    let run = |fe: &str| {
        let s = traxer::scene::Scene::load(&dev, &scene, &[format!("figure_error={fe}")]).unwrap();
        let cfg = RunConfig::new(30_000, 5);
        trace::run(&s, &cfg).unwrap()
    };
    let perfect = run("\"none\"");
    let zero = run(
        "{ in_plane_narrow = 0.0, in_plane_wide = 0.0, wide_fraction = 0.3, out_of_plane = 0.0 }",
    );
    assert_eq!(perfect.images[0].flux(), zero.images[0].flux());
    assert_eq!(perfect.stats, zero.stats);
    // ... while a small one changes the image.
    let small = run(
        "{ in_plane_narrow = 5.0, in_plane_wide = 0.0, wide_fraction = 0.0, out_of_plane = 0.0 }",
    );
    assert_ne!(perfect.images[0].flux(), small.images[0].flux());
}

#[test]
fn bad_figure_errors_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let scene = |fe: &str| {
        format!(
            r#"
[[sources]]
type = "parallel"
aperture = {{ center = [0, 0, 10], radius = 1.0 }}
energy = {{ line = 1.49 }}

[materials.m]
type = "mirror"
figure_error = {fe}

[[objects]]
material = "m"
shape = {{ type = "disk", radius = 5.0 }}
"#
        )
    };
    let e = crate::common::load_error(dir.path(), &scene("\"nosuch\""));
    assert!(
        e.contains("unknown figure error `nosuch`") && e.contains("none"),
        "{e}"
    );
    let e = crate::common::load_error(
        dir.path(),
        &scene("{ in_plane_narrow = 1.0, in_plane_wide = 2.0, wide_fraction = 1.5, out_of_plane = 0.0 }"),
    );
    assert!(e.contains("wide_fraction = 1.5"), "{e}");
    let e = crate::common::load_error(
        dir.path(),
        &scene("{ in_plane_narrow = -1.0, in_plane_wide = 2.0, wide_fraction = 0.5, out_of_plane = 0.0 }"),
    );
    assert!(e.contains("in_plane_narrow = -1"), "{e}");
}

#[test]
fn fit_recovers_the_parameters_it_was_simulated_with() {
    use traxer::studies::fit::{fit, set_figure_error, Bounds, FitSettings};
    use traxer::studies::measure_arcsec;
    // Synthetic problem: the PANTER Al Kα scene (perfect reflectivity) traced with
    // known figure errors gives the "measured" diameters; the fit, within bounds
    // that do not centre on the truth, must find the parameters again. The wide
    // width is held at its true value: with all three free, (wide width, weight)
    // pairs along a valley give nearly the same three diameters, so only the
    // diameters, not the parameters, are determined (see the README).
    let dev = crate::common::device();
    let mut scene = traxer::scene::Scene::load(
        &dev,
        &crate::common::repo().join("scenes/panter_al_ka.toml"),
        &["coating=perfect".into(), "figure_error=none".into()],
    )
    .unwrap();
    let truth = FigureError {
        in_plane_narrow: 40.0,
        in_plane_wide: 300.0,
        wide_fraction: 0.15,
        out_of_plane: 0.0,
    };
    let run = RunConfig::new(60_000, 11);
    set_figure_error(&mut scene, Some(truth));
    let target = measure_arcsec(&scene, 0, &run, &()).unwrap().unwrap();
    let settings = FitSettings {
        bounds: Bounds {
            lower: [10.0, 300.0, 0.02, 0.0],
            upper: [90.0, 300.0, 0.4, 0.0],
        },
        target,
        run,
        sensor: 0,
        global_evaluations: 40,
        local_evaluations: 40,
        local_algorithm: traxer::studies::fit::LocalAlgorithm::Sbplx,
    };
    let result = fit(&mut scene, &settings, &[], &(), |_, _, _| {}).unwrap();
    let p = result.best.parameters;
    let d = result.best.diameters.unwrap();
    // The same photons as the truth: the diameters are reproduced to 0.5 %...
    for (got, want) in [
        (d.hpd, target.hpd),
        (d.d80, target.d80),
        (d.d90, target.d90),
    ] {
        assert!((got / want - 1.0).abs() < 0.005, "{d:?} vs {target:?}");
    }
    eprintln!("recovered {p:?} with {d:?}, truth {target:?}");
    // ... and the parameters to 5 %.
    assert!((p.in_plane_narrow / 40.0 - 1.0).abs() < 0.05, "{p:?}");
    assert!((p.wide_fraction / 0.15 - 1.0).abs() < 0.05, "{p:?}");
    assert_eq!((p.in_plane_wide, p.out_of_plane), (300.0, 0.0));
    assert!(result.history.len() <= 80);
}

#[test]
fn fit_command_writes_history_and_a_loadable_preset() {
    let dir = tempfile::tempdir().unwrap();
    let scene = crate::common::repo().join("scenes/panter_al_ka.toml");
    crate::common::run_ok(
        crate::common::traxer()
            .arg("fit-figure-error")
            .arg(&scene)
            .args(PANTER_AL_TARGETS)
            .args(["-n", "20000", "--global-evals", "8", "--local-evals", "4"])
            .args([
                "--check-seeds",
                "1",
                "--name",
                "mine",
                "-q",
                "-D",
                "coating=perfect",
            ])
            .args(["--bound", "in_plane_wide=400"])
            .arg("-o")
            .arg(dir.path()),
    );
    let history = std::fs::read_to_string(dir.path().join("history.csv")).unwrap();
    assert_eq!(history.lines().count(), 1 + 12, "{history}");
    // The preset file is a valid [figure_errors] table: a scene can use it.
    let preset = std::fs::read_to_string(dir.path().join("figure_error.toml")).unwrap();
    let text = format!(
        "{preset}\n[[sources]]\ntype = \"parallel\"\naperture = {{ center = [0, 0, 10], radius = 1.0 }}\nenergy = {{ line = 1.49 }}\n\n[materials.m]\ntype = \"mirror\"\nfigure_error = \"mine\"\n\n[[objects]]\nmaterial = \"m\"\nshape = {{ type = \"disk\", radius = 5.0 }}\n"
    );
    let s = crate::common::scene(&text);
    let fit: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("fit.json")).unwrap()).unwrap();
    let best = &fit["best"]["parameters"];
    match s.objects[0].material {
        traxer::material::Material::Mirror {
            figure_error: Some(fe),
            ..
        } => {
            assert_eq!(fe.in_plane_wide, 400.0);
            assert!((fe.in_plane_narrow - best["in_plane_narrow"].as_f64().unwrap()).abs() < 1e-3);
            assert!((fe.wide_fraction - best["wide_fraction"].as_f64().unwrap()).abs() < 1e-4);
        }
        ref m => panic!("{m:?}"),
    }
    // The preset carries the fit's covariance, read back as written in fit.json.
    let lib: traxer::xray::FigureErrorLibrary = toml::from_str(&preset).unwrap();
    let (_, cov) = lib.with_covariance("mine").unwrap();
    let errors = &fit["parameter_errors"];
    let names: Vec<&str> = errors["names"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap())
        .collect();
    assert_eq!(cov.parameters, names);
    for (a, row) in cov.matrix.iter().enumerate() {
        for (b, x) in row.iter().enumerate() {
            let y = errors["covariance"][a][b].as_f64().unwrap();
            assert!((x - y).abs() <= 1e-12 * y.abs(), "[{a}][{b}] {x} vs {y}");
        }
    }
    assert!(cov.matrix[0][0] > 0.0, "a fitted width has an error");
    // A misspelt bound is a usage error.
    let err = crate::common::run_fails(
        crate::common::traxer()
            .arg("fit-figure-error")
            .arg(&scene)
            .args(PANTER_AL_TARGETS)
            .args(["--bound", "narrow=0:50"]),
        2,
    );
    assert!(err.contains("unknown parameter"), "{err}");
}

/// The "over N seeds m ± s″, ..." means and standard deviations (HPD, 80 %,
/// 90 %) that `fit-figure-error` recorded in a preset's `source`.
fn recorded_seed_check(source: &str) -> [(f64, f64); 3] {
    let tail = source.rsplit_once(" seeds ").expect("a seed check").1;
    let numbers: Vec<(f64, f64)> = tail
        .split(',')
        .map(|part| {
            let (m, s) = part.split_once('±').expect("mean ± sd");
            let num = |t: &str| t.trim().trim_end_matches('″').parse::<f64>().unwrap();
            (num(m), num(s))
        })
        .collect();
    [numbers[0], numbers[1], numbers[2]]
}

#[test]
fn fitted_preset_reproduces_the_panter_al_ka_measurement() {
    // Two halves, so that Monte Carlo noise cannot decide the outcome:
    //
    // 1. The shipped preset (data/figure_errors.toml) records what its fit
    //    reached, as the mean ± sd over 4 seeds of 1 M photons: those means must
    //    lie within 2 % of PANTER's 206″, 397″, 549″ (SPEC §3). This is the
    //    physics claim; it is a fixed record, so it cannot flicker.
    // 2. The code must still produce that record: the mean over 4 other seeds of
    //    400 000 photons each must agree with it within 1 %. The recorded spread
    //    (0.4″, 0.2″, 0.6″ at 1 M photons) scales to ≤ 1″ per seed at 400 000, so
    //    the standard error of the difference of the two means is ≤ 0.6″; 1 % (2–5″)
    //    is ≥ 3.5σ for every diameter. A change of the tracer, the coatings or the
    //    analysis that moves the image by more fails here.
    //
    // (Before, one 400 000-photon run was compared with 206″ within 2 %: its HPD
    // is +1.6 to +2.3 % off depending on the seed, so the test passed by its seed.)
    let lib = traxer::xray::FigureErrorLibrary::shipped();
    let entry = &lib.figure_errors["llnl_panter"];
    let recorded = recorded_seed_check(entry.source.as_deref().expect("a source"));
    for ((mean, _), panter) in recorded.iter().zip([206.0, 397.0, 549.0]) {
        assert!(
            (mean / panter - 1.0).abs() < 0.02,
            "recorded {recorded:?} vs PANTER"
        );
    }
    let dev = crate::common::device();
    let scene = traxer::scene::Scene::load(
        &dev,
        &crate::common::repo().join("scenes/panter_al_ka.toml"),
        &[],
    )
    .unwrap();
    let seeds = [91, 92, 93, 94];
    let runs: Vec<_> = seeds
        .iter()
        .map(|&seed| {
            traxer::studies::measure_arcsec(&scene, 0, &RunConfig::new(400_000, seed), &())
                .unwrap()
                .unwrap()
        })
        .collect();
    let mean = |f: fn(&traxer::studies::Diameters) -> f64| {
        runs.iter().map(f).sum::<f64>() / runs.len() as f64
    };
    let now = [mean(|d| d.hpd), mean(|d| d.d80), mean(|d| d.d90)];
    for (got, (want, _)) in now.iter().zip(recorded) {
        assert!(
            (got / want - 1.0).abs() < 0.01,
            "now {now:?} vs recorded {recorded:?}"
        );
    }
}

/// The fit's errors and predictions: predicting the fitted scene itself with
/// the seeds of the seed check gives the seed check's mean, and its fit error
/// is the assumed target error and the Monte Carlo spread carried through the
/// parameters and back (J C Jᵀ = S for as many diameters as free parameters),
/// √((0.03 t)² + sd²), to rounding; a second scene is predicted on its own
/// sensor; a target error outside 0–100 % is refused before any tracing.
#[test]
fn fit_errors_carry_back_to_the_targets_and_predictions_are_written() {
    let dir = tempfile::tempdir().unwrap();
    let scene = crate::common::repo().join("scenes/panter_al_ka.toml");
    let ti = crate::common::repo().join("scenes/panter_ti_ka.toml");
    crate::common::run_ok(
        crate::common::traxer()
            .arg("fit-figure-error")
            .arg(&scene)
            .args(PANTER_AL_TARGETS)
            .args(["-n", "40000", "--global-evals", "8", "--local-evals", "4"])
            .args([
                "--check-seeds",
                "2",
                "--predict-seeds",
                "3",
                "--target-error",
                "3",
            ])
            .args(["-q", "-D", "coating=perfect", "--bound", "out_of_plane=0"])
            .arg("--predict")
            .arg(&scene)
            .arg("--predict")
            .arg(&ti)
            .arg("-o")
            .arg(dir.path()),
    );
    let fit: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("fit.json")).unwrap()).unwrap();
    let e = &fit["parameter_errors"];
    assert_eq!(e["names"].as_array().unwrap().len(), 3, "{e}");
    let own = &fit["predictions"][0];
    let check = &fit["seed_check"];
    let targets: [f64; 3] = [206.0, 397.0, 549.0];
    for (k, key) in ["hpd", "d80", "d90"].iter().enumerate() {
        let (mean, sd) = (
            check[format!("{key}_mean_sd")][0].as_f64().unwrap(),
            check[format!("{key}_mean_sd")][1].as_f64().unwrap(),
        );
        let predicted = own["diameters"][*key].as_f64().unwrap();
        assert!(
            (predicted - mean).abs() < 1e-9 * mean,
            "{key}: {predicted} vs {mean}"
        );
        let fit_error = own["fit"][k].as_f64().unwrap();
        let expect = ((0.03 * targets[k]).powi(2) + sd * sd).sqrt();
        assert!(
            (fit_error / expect - 1.0).abs() < 1e-6,
            "{key}: fit error {fit_error} vs {expect}"
        );
    }
    let other = &fit["predictions"][1];
    assert!(other["scene"]
        .as_str()
        .unwrap()
        .ends_with("panter_ti_ka.toml"));
    assert!(other["diameters"]["hpd"].as_f64().unwrap() > 50.0);
    assert!(other["fit"][0].as_f64().unwrap() > 0.0);
    let err = crate::common::run_fails(
        crate::common::traxer()
            .arg("fit-figure-error")
            .arg(&scene)
            .args(PANTER_AL_TARGETS)
            .args(["--target-error", "0", "-o"])
            .arg(dir.path().join("x")),
        2,
    );
    assert!(err.contains("--target-error"), "{err}");
    // A dotted preset name would become nested TOML tables: refused up front.
    let err = crate::common::run_fails(
        crate::common::traxer()
            .arg("fit-figure-error")
            .arg(&scene)
            .args(PANTER_AL_TARGETS)
            .args(["--name", "sigma_0.5", "-o"])
            .arg(dir.path().join("y")),
        2,
    );
    assert!(err.contains("bare TOML key"), "{err}");
}

#[test]
fn a_preset_whose_covariance_is_no_covariance_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let scene = |matrix: &str| {
        format!(
            "[figure_errors.mine]\nin_plane_narrow = 50.0\nin_plane_wide = 0.0\nwide_fraction = 0.0\nout_of_plane = 0.0\n\n[figure_errors.mine.covariance]\nparameters = [\"in_plane_narrow\", \"wide_fraction\"]\nmatrix = {matrix}\n\n[[sources]]\ntype = \"parallel\"\naperture = {{ center = [0, 0, 10], radius = 1.0 }}\nenergy = {{ line = 1.49 }}\n\n[materials.m]\ntype = \"mirror\"\nfigure_error = \"mine\"\n\n[[objects]]\nmaterial = \"m\"\nshape = {{ type = \"disk\", radius = 5.0 }}\n"
        )
    };
    let err = crate::common::load_error(dir.path(), &scene("[[4.0, 3.0], [3.0, 1.0]]"));
    assert!(
        err.contains("mine") && err.contains("positive semi-definite"),
        "{err}"
    );
    // A covariance loads.
    crate::common::scene_in(dir.path(), &scene("[[4.0, 0.1], [0.1, 0.01]]"));
}
