//! Every shipped scene is also a test: it loads, traces, and its sensor sees light.

use crate::common::{centroid_rms, device, repo};
use traxer::scene::Scene;
use traxer::trace::{self, RunConfig};

#[test]
fn every_shipped_scene_loads_and_traces() {
    let mut n = 0;
    for entry in std::fs::read_dir(repo().join("scenes")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let s = Scene::load(&device(), &path, &[]).unwrap_or_else(|e| panic!("{e}"));
        if s.sources.is_empty() {
            // A visible-light scene: it must have a camera and render light.
            let (name, cam) = s.cameras.iter().next().expect("a camera");
            let img = traxer::render::render(
                &s,
                cam,
                &s.sky,
                &[],
                &traxer::render::RenderSettings {
                    width: 16,
                    height: 12,
                    spp: 2,
                    max_depth: 8,
                    seed: 1,
                },
            );
            assert!(
                img.iter().any(|c| c.length() > 0.1),
                "{}: camera {name} sees nothing",
                path.display()
            );
            continue;
        }
        let r = trace::run(&s, &RunConfig::new(50_000, 1)).unwrap();
        assert_eq!(
            r.stats.fates(),
            50_000,
            "{}: every photon has one fate",
            path.display()
        );
        assert!(
            !s.sensors.is_empty() && r.stats.reached_sensor > 0,
            "{}: no photon reached a sensor",
            path.display()
        );
        n += 1;
    }
    assert!(n >= 2);
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
    let (_, _, ra) = centroid_rms(&a.images[0].flux, 512);
    let (_, _, rm) = centroid_rms(&m.images[0].flux, 512);
    assert!(
        (ra / rm - 1.0).abs() < 0.01,
        "RMS radius analytic {ra} px vs mesh {rm} px"
    );
}
