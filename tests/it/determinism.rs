//! Reproducibility: the same seed gives bit-identical images for any thread count,
//! and shards of a run add up to the whole run.

use crate::common::{device, repo};
use traxer::scene::Scene;
use traxer::trace::{self, RunConfig};

fn cfg(photons: u64, threads: usize, first: u64) -> RunConfig {
    RunConfig {
        threads,
        first_photon: first,
        ..RunConfig::new(photons, 42)
    }
}

#[test]
fn same_seed_gives_bit_identical_images_for_1_and_2_threads() {
    let s = Scene::load(&device(), &repo().join("scenes/wolter1_meshed.toml"), &[]).unwrap();
    let a = trace::run(&s, &cfg(150_000, 1, 0)).unwrap();
    let b = trace::run(&s, &cfg(150_000, 2, 0)).unwrap();
    assert_eq!(a.threads, 1);
    assert_eq!(b.threads, 2);
    assert!(a.stats.reached_sensor > 1000);
    assert_eq!(a.stats, b.stats);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.images[0].flux), bits(&b.images[0].flux));
    assert_eq!(a.images[0].counts, b.images[0].counts);
    // A different seed gives a different image (the test can fail).
    let c = trace::run(
        &s,
        &RunConfig {
            seed: 43,
            ..cfg(150_000, 2, 0)
        },
    )
    .unwrap();
    assert_ne!(a.images[0].counts, c.images[0].counts);
}

#[test]
fn shards_add_up_to_the_whole_run() {
    let s = Scene::load(
        &device(),
        &repo().join("scenes/wolter1_parallel.toml"),
        &["off_axis=0.02".into()],
    )
    .unwrap();
    let whole = trace::run(&s, &cfg(100_000, 2, 0)).unwrap();
    let a = trace::run(&s, &cfg(37_000, 2, 0)).unwrap();
    let b = trace::run(&s, &cfg(63_000, 1, 37_000)).unwrap();
    let mut stats = a.stats.clone();
    stats.add(&b.stats);
    assert_eq!(stats, whole.stats);
    let counts: Vec<u64> = a.images[0]
        .counts
        .iter()
        .zip(&b.images[0].counts)
        .map(|(x, y)| x + y)
        .collect();
    assert_eq!(counts, whole.images[0].counts);
}
