//! `cargo bench`: photons per second through the shipped Wolter-I and PANTER Al Kα
//! scenes (analytic and meshed, perfect and Pt/C-coated mirrors; the meshed PANTER
//! telescope is the shipped meshes/llnl_telescope.glb), the CAST axion image and the
//! parallel beam of the effective-area scene, Embree queries per photon, the raw
//! `rtcIntersect1` rate on the same rays and the best one on them sorted (the same
//! numbers come from `traxer bench SCENE`); the effective-area sweep of the README;
//! the BVH build of a 1 M-triangle mesh; reflectivity evaluations per second,
//! direct and through the photon loop's tables; camera rays per second of the
//! visible-light renders of scenes/spheres.toml and the PANTER telescope view.

use std::path::Path;
use traxer::embree::Device;
use traxer::scene::Scene;
use traxer::trace::RunConfig;

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let device = Device::new().expect("Embree device");
    let photons = std::env::var("TRAXER_BENCH_PHOTONS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2_000_000);
    println!(
        "{:<66} {:>9} {:>13} {:>13} {:>9} {:>13} {:>7} {:>13} {:>7}",
        "scene, variables",
        "triangles",
        "photons/s",
        "sensor ph/s",
        "queries",
        "raw rays/s",
        "ratio",
        "sorted rays/s",
        "ratio"
    );
    for (name, defines) in [
        ("wolter1_parallel.toml", "coating=perfect"),
        ("wolter1_parallel.toml", "coating=llnl_recipe_3"),
        ("wolter1_meshed.toml", "coating=perfect"),
        ("wolter1_meshed.toml", "coating=llnl_recipe_3"),
        ("panter_al_ka.toml", "coating=perfect figure_error=none"),
        (
            "panter_al_ka.toml",
            "coating=as_built figure_error=llnl_panter",
        ),
        (
            "panter_al_ka_meshed.toml",
            "coating=perfect figure_error=none",
        ),
        (
            "panter_al_ka_meshed.toml",
            "coating=as_built figure_error=llnl_panter",
        ),
        ("cast_axion_image.toml", ""),
        ("llnl_effective_area.toml", ""),
    ] {
        let defines: Vec<String> = defines.split_whitespace().map(String::from).collect();
        let scene =
            Scene::load(&device, &root.join("scenes").join(name), &defines).expect("shipped scene");
        let r = traxer::bench::run(&scene, &RunConfig::new(photons, 1), 300_000, &())
            .expect("thread pool");
        println!(
            "{:<66} {:>9} {:>13.0} {:>13.0} {:>9.3} {:>13.0} {:>7.2} {:>13.0} {:>7.2}",
            format!("{name}, {}", defines.join(" ")),
            r.triangles,
            r.photons_per_second,
            r.sensor_photons_per_second,
            r.queries_per_photon,
            r.raw_rays_per_second,
            r.embree_fraction,
            r.best_raw_rays_per_second,
            r.photons_per_second * r.queries_per_photon / r.best_raw_rays_per_second
        );
    }
    println!();
    magnet_cost(&device, root, photons);
    println!();
    // The effective-area sweep of the README: 91 energies × 5 angles.
    let scene = Scene::load(&device, &root.join("scenes/llnl_effective_area.toml"), &[])
        .expect("shipped scene");
    let sweep = traxer::studies::effective_area::AreaSweep {
        energies: (0..91).map(|i| 1.0 + 0.1 * i as f64).collect(),
        angles_arcmin: vec![0.0, 2.5, 5.0, 7.5, 10.0],
        sampling: traxer::studies::Sampling {
            photons: 200_000,
            seed: 1,
            threads: 0,
            sensor: None,
        },
        radius_mm: None,
    };
    let r = traxer::studies::effective_area::sweep(&scene, &sweep, &[], &(), |_, _| {})
        .expect("shipped scene sweeps");
    println!(
        "effective-area sweep, 91 energies × 5 angles × 200 000 photons: {:.2} s ({:.0} photons/s, {} threads)",
        r.seconds,
        5.0 * 200_000.0 / r.seconds,
        r.threads
    );
    let (triangles, seconds) = traxer::bench::bvh_build_seconds(&device, 1_000_000).expect("BVH");
    println!("BVH build (rtcCommitScene) of a {triangles}-triangle mesh: {seconds:.3} s");
    println!();
    println!(
        "{:<16} {:>10} {:>16} {:>16} {:>12}",
        "coating", "band keV", "direct R/s", "table R/s", "table build"
    );
    let lib = traxer::xray::CoatingLibrary::shipped();
    for (name, lo, hi) in [
        ("llnl_recipe_3", 1.48, 1.50),
        ("llnl_recipe_3", 0.5, 10.0),
        ("gold", 0.5, 10.0),
    ] {
        let r = traxer::bench::reflectivity_rates(&lib.coating(name).expect("shipped"), lo, hi);
        println!(
            "{:<16} {:>10} {:>16.0} {:>16.0} {:>10.2} s",
            name,
            format!("{lo}–{hi}"),
            r.direct_per_second,
            r.table_per_second,
            r.table_build_seconds
        );
    }
    println!();
    println!(
        "{:<36} {:>10} {:>5} {:>16}",
        "visible-light render", "pixels", "spp", "camera rays/s"
    );
    for (name, camera, (w, h), spp) in [
        ("spheres.toml", "classic", (600, 400), 16),
        ("panter_al_ka.toml", "telescope", (480, 300), 16),
    ] {
        let scene =
            Scene::load(&device, &root.join("scenes").join(name), &[]).expect("shipped scene");
        let settings = traxer::render::RenderSettings {
            width: w,
            height: h,
            spp,
            max_depth: 12,
            seed: 1,
        };
        let start = std::time::Instant::now();
        let img =
            traxer::render::render(&scene, &scene.cameras[camera], &scene.sky, &[], &settings);
        let seconds = start.elapsed().as_secs_f64();
        assert_eq!(img.len(), w * h);
        println!(
            "{:<36} {:>10} {:>5} {:>16.0}",
            format!("{name}, camera {camera}"),
            format!("{w}×{h}"),
            spp,
            (w * h) as f64 * spp as f64 / seconds
        );
    }
}

/// The magnet's cost (issue 60): BabyIAXO's Primakoff image through its field
/// map against the same trace without the magnet, and the whole campaign
/// (vacuum + the planned helium settings × their masses) against the same
/// photons without it; the runs alternate, best of three each, in one process.
fn magnet_cost(device: &Device, root: &Path, photons: u64) {
    let scene = |defines: &[&str]| {
        let mut d = vec!["emission=primakoff".to_string(), "pixels=200".to_string()];
        d.extend(defines.iter().map(|s| s.to_string()));
        Scene::load(device, &root.join("scenes/babyiaxo_axion_image.toml"), &d)
            .expect("shipped scene")
    };
    let seconds = |scene: &Scene, n: u64| {
        let r = traxer::trace::run_with_progress(scene, &RunConfig::new(n, 1), &())
            .expect("thread pool");
        r.seconds
    };
    let best = |scene: &Scene, n: u64| (0..3).map(|_| seconds(scene, n)).fold(f64::MAX, f64::min);
    let (off, on) = (scene(&["magnet=false"]), scene(&["magnet=true"]));
    let campaign = scene(&["magnet=true", "campaign=true"]);
    let (t_off, t_on) = (best(&off, photons), best(&on, photons));
    println!(
        "BabyIAXO, field map, one mass, {photons} photons: {t_off:.2} s without the magnet, {t_on:.2} s with it: ratio {:.2} (goal 1.25)",
        t_on / t_off
    );
    // The campaign costs minutes at 1e6 photons: an eighth of the photons.
    let n = (photons / 8).max(1);
    let (t_off, t_camp) = (best(&off, n), seconds(&campaign, n));
    println!(
        "BabyIAXO campaign, {n} photons: {t_camp:.1} s ({t_off:.2} s without the magnet); × {:.0} for 1e6 photons: {:.0} s (goal 300 s)",
        1e6 / n as f64,
        t_camp * 1e6 / n as f64
    );
}
