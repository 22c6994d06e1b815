//! `cargo bench`: photons per second through the shipped Wolter-I scenes (analytic
//! and meshed), Embree queries per photon, and the raw `rtcIntersect1` rate on the
//! same rays. The same numbers come from `traxer bench SCENE`.

use std::path::Path;
use traxer::embree::Device;
use traxer::scene::Scene;

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let device = Device::new().expect("Embree device");
    let photons = std::env::var("TRAXER_BENCH_PHOTONS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2_000_000);
    println!(
        "{:<22} {:>9} {:>13} {:>13} {:>9} {:>13} {:>7}",
        "scene", "triangles", "photons/s", "sensor ph/s", "queries", "raw rays/s", "ratio"
    );
    for name in ["wolter1_parallel.toml", "wolter1_meshed.toml"] {
        let scene =
            Scene::load(&device, &root.join("scenes").join(name), &[]).expect("shipped scene");
        let r = traxer::bench::run(&scene, photons, 0, 300_000).expect("thread pool");
        println!(
            "{:<22} {:>9} {:>13.0} {:>13.0} {:>9.3} {:>13.0} {:>7.2}",
            name,
            r.triangles,
            r.photons_per_second,
            r.sensor_photons_per_second,
            r.queries_per_photon,
            r.raw_rays_per_second,
            r.embree_fraction
        );
    }
}
