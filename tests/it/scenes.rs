//! Every shipped scene is also a regression test: it loads, traces (or renders),
//! and gives the numbers recorded in tests/data/scene_expectations.toml — the
//! fraction of photons reaching the sensor, the flux per photon, and the HPD, 80 %
//! and 90 % diameters — within 5 standard deviations of one run (the recorded
//! spread over 8 seeds), so Monte Carlo noise at any seed cannot fail it but a
//! change of the physics, the geometry or the analysis that moves a result does.
//! scripts/scene_expectations.py re-measures them when a change is meant to.

use crate::common::{centroid_rms, device, repo};
use traxer::analysis::{analyse, ImageGeometry};
use traxer::scene::Scene;
use traxer::trace::{self, RunConfig};

/// Allowed distance from the recorded mean, in recorded standard deviations.
const SIGMAS: f64 = 5.0;

fn expectations() -> toml::Table {
    let text = std::fs::read_to_string(repo().join("tests/data/scene_expectations.toml")).unwrap();
    toml::from_str(&text).unwrap()
}

/// (mean, standard deviation) of `key` in a scene's table.
fn expected(table: &toml::Table, key: &str) -> (f64, f64) {
    let v = table[key].as_array().unwrap_or_else(|| panic!("{key}"));
    let f = |x: &toml::Value| x.as_float().or(x.as_integer().map(|i| i as f64)).unwrap();
    (f(&v[0]), f(&v[1]))
}

fn check(scene: &str, key: &str, got: f64, table: &toml::Table) {
    let (mean, sd) = expected(table, key);
    // The means are recorded to 6 significant digits: a spread smaller than that
    // (a spot within a few pixels) must not make the rounding fail the check.
    let rounding = 5e-6 * mean.abs();
    assert!(
        (got - mean).abs() <= SIGMAS * sd + rounding,
        "{scene}: {key} = {got}, expected {mean} ± {SIGMAS} × {sd}"
    );
}

/// The recorded results of scene `name`, or a message naming the scene that
/// has none and what to do (a user's own scene in scenes/ used to panic with
/// "no entry found for key").
fn recorded<'a>(scenes: &'a toml::Table, name: &str) -> Result<&'a toml::Table, String> {
    scenes.get(name).and_then(|t| t.as_table()).ok_or_else(|| {
        format!(
            "scenes/{name}.toml has no recorded results in tests/data/scene_expectations.toml: every scene in scenes/ is a test; record its numbers with scripts/scene_expectations.py, or keep your own scenes outside scenes/"
        )
    })
}

#[test]
fn a_scene_without_recorded_results_is_named() {
    let all = expectations();
    let scenes = all["scenes"].as_table().unwrap();
    assert!(recorded(scenes, "panter_al_ka").is_ok());
    let e = recorded(scenes, "my_own_scene").unwrap_err();
    assert!(
        e.contains("scenes/my_own_scene.toml") && e.contains("scene_expectations.py"),
        "{e}"
    );
}

#[test]
fn every_shipped_scene_gives_its_recorded_results() {
    let all = expectations();
    let photons = all["photons"].as_integer().unwrap() as u64;
    let scenes = all["scenes"].as_table().unwrap();
    let mut n = 0;
    for entry in std::fs::read_dir(repo().join("scenes")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let table = recorded(scenes, &name).unwrap_or_else(|e| panic!("{e}"));
        let s = Scene::load(&device(), &path, &[]).unwrap_or_else(|e| panic!("{e}"));
        if s.sources.is_empty() {
            check_render(&name, &s, table);
            n += 1;
            continue;
        }
        // A seed the expectations were not measured with.
        let r = trace::run(&s, &RunConfig::new(photons, 7)).unwrap();
        assert_eq!(
            r.stats.fates(),
            photons,
            "{name}: every photon has one fate"
        );
        let emitted = r.stats.photons_emitted as f64;
        check(
            &name,
            "reached_fraction",
            r.stats.reached_sensor as f64 / emitted,
            table,
        );
        // A Sun's images are in axions per second (as summary.json gives them).
        let scale = s.rate_per_unit_weight(photons).unwrap_or(1.0);
        check(
            &name,
            "flux_per_photon",
            r.images[0].total_flux() * scale / emitted,
            table,
        );
        let spec = &s.sensors[0];
        let (q, _) = analyse(
            &r.images[0].flux_summed(spec),
            &ImageGeometry::of_sensor(spec),
            spec.focal_length,
        )
        .expect("an image");
        let arcsec = table["diameter_unit"].as_str() == Some("arcsec");
        for (key, mm, angle) in [
            ("hpd", q.hpd_mm, q.hpd_arcsec),
            ("d80", q.d80_mm, q.d80_arcsec),
            ("d90", q.d90_mm, q.d90_arcsec),
        ] {
            let got = if arcsec {
                angle.expect("a focal length")
            } else {
                mm
            };
            check(&name, key, got, table);
        }
        n += 1;
    }
    assert_eq!(n, scenes.len(), "a recorded scene is no longer shipped");
}

/// Mean radiance (linear RGB, averaged over channels and pixels) of a 48 × 32,
/// 8-spp picture from the scene's first camera.
fn mean_radiance(s: &Scene, seed: u64) -> f64 {
    let (_, cam) = s.cameras.iter().next().expect("a camera");
    let img = traxer::render::render(
        s,
        cam,
        &s.sky,
        &[],
        &traxer::render::RenderSettings {
            width: 48,
            height: 32,
            spp: 8,
            max_depth: 8,
            seed,
        },
    );
    img.iter().map(|c| c.element_sum() / 3.0).sum::<f64>() / img.len() as f64
}

/// A render-only scene: its picture's mean radiance is recorded.
fn check_render(name: &str, s: &Scene, table: &toml::Table) {
    let mean = mean_radiance(s, 7);
    assert!(mean > 0.05, "{name}: the camera sees nothing");
    check(name, "mean_radiance", mean, table);
}

/// Prints the mean and spread of the render-only scenes' mean radiance over seeds
/// 101..108, for tests/data/scene_expectations.toml:
/// `cargo test --release -- --ignored --nocapture render_expectations`.
#[test]
#[ignore]
fn render_expectations() {
    for entry in std::fs::read_dir(repo().join("scenes")).unwrap() {
        let path = entry.unwrap().path();
        let s = Scene::load(&device(), &path, &[]).unwrap();
        if !s.sources.is_empty() {
            continue;
        }
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let v: Vec<f64> = (101..109).map(|seed| mean_radiance(&s, seed)).collect();
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        let sd = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (v.len() - 1) as f64).sqrt();
        println!("[scenes.{name}]\nmean_radiance = [{mean:.6}, {sd:.3e}]");
    }
}

#[test]
fn meshed_wolter_telescope_matches_the_analytic_one() {
    // Same photons through exact surfaces and through 720 × 8 smooth-normal meshes.
    let run = |name: &str| {
        let s = Scene::load(
            &device(),
            &repo().join("scenes").join(name),
            &["focus_shift=3".into()],
        )
        .unwrap();
        trace::run(&s, &RunConfig::new(300_000, 3)).unwrap()
    };
    let a = run("wolter1_parallel.toml");
    let m = run("wolter1_meshed.toml");
    // Same photons reach the sensor except the few that hit within the chord sag
    // of a shell edge (< 0.1 %).
    let (na, nm) = (a.stats.reached_sensor as f64, m.stats.reached_sensor as f64);
    assert!((na - nm).abs() / na < 1e-3, "analytic {na} vs mesh {nm}");
    // 3 mm out of focus the image is a set of rings; their RMS radius agrees to 1 %.
    let (_, _, ra) = centroid_rms(&a.images[0].flux(), 512);
    let (_, _, rm) = centroid_rms(&m.images[0].flux(), 512);
    assert!(
        (ra / rm - 1.0).abs() < 0.01,
        "RMS radius analytic {ra} px vs mesh {rm} px"
    );
}
