//! Reproducibility: the same seed gives bit-identical images for any thread count,
//! and shards of a run add up to the whole run.

use crate::common::{device, repo};
use traxer::scene::Scene;
use traxer::trace::{self, Flow, RunConfig, Tally};

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
    assert_eq!(bits(&a.images[0].flux()), bits(&b.images[0].flux()));
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
fn parts_of_a_run_add_up_to_the_whole_run_bit_for_bit() {
    // Gold mirrors: weights below 1, which floating-point sums would round
    // differently in another grouping.
    let s = Scene::load(
        &device(),
        &repo().join("scenes/wolter1_parallel.toml"),
        &["off_axis=0.02".into(), "coating=gold".into()],
    )
    .unwrap();
    let tally = |c: &RunConfig| {
        trace::run_part(&s, c, Tally::new(&s), &(), &mut |_| Flow::Continue)
            .unwrap()
            .0
    };
    let whole = tally(&cfg(100_000, 2, 0));
    let a = tally(&cfg(37_000, 2, 0));
    let b = tally(&cfg(63_000, 1, 37_000));
    let mut sum = b.clone();
    sum.add(&a, 0);
    assert_eq!(sum, whole);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&sum.images[0].flux()), bits(&whole.images[0].flux()));
    // Plain floating-point sums of the parts' images would not be the whole's
    // (why the sums are exact): some pixel differs in its last bits.
    let naive: Vec<f64> = a.images[0]
        .flux()
        .iter()
        .zip(b.images[0].flux())
        .map(|(x, y)| x + y)
        .collect();
    let sequential = sequential_flux(&s, 100_000);
    assert_ne!(bits(&naive), bits(&sequential));
    assert!(naive
        .iter()
        .zip(&sequential)
        .all(|(x, y)| (x - y).abs() <= 1e-12 * y.abs()));
}

/// Each pixel's weights added in photon order as plain f64.
fn sequential_flux(s: &Scene, photons: u64) -> Vec<f64> {
    let (records, _) = trace::trace_range(s, 42, 0, photons);
    let mut img = vec![0.0; s.sensors[0].pixel_count() * s.sensors[0].bands()];
    for r in records {
        img[r.pixel as usize] += r.weight;
    }
    img
}
