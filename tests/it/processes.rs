//! Images per emission process: a Sun with Primakoff and ABC records each
//! process's image beside the total, from the same photons; the parts add up to
//! the total, each is the image a trace of that process alone gives, and the
//! image for other couplings built from them equals a trace with those
//! couplings.

use crate::common::{device, repo, scene_in};
use traxer::scene::Scene;
use traxer::source::Source;
use traxer::trace::{self, RunConfig};

/// (total image, process images, photons per process) in axions/s per pixel.
type Images = (Vec<f64>, Vec<Vec<f64>>, Vec<u64>);

fn trace_images(scene: &Scene, photons: u64, seed: u64) -> Images {
    let Source::Sun(sun) = &scene.sources[0] else {
        panic!("a Sun scene")
    };
    let scale = sun.rate_per_unit_weight(photons);
    let r = trace::run(scene, &RunConfig::new(photons, seed)).unwrap();
    let image = &r.images[0];
    let scaled = |v: Vec<f64>| v.into_iter().map(|x| x * scale).collect::<Vec<_>>();
    (
        scaled(image.flux()),
        image.processes.images().into_iter().map(scaled).collect(),
        image.processes.counts.clone(),
    )
}

fn cast_electron(vars: &[&str]) -> Scene {
    let vars: Vec<String> = vars.iter().map(|v| v.to_string()).collect();
    Scene::load(
        &device(),
        &repo().join("scenes/cast_axion_electron_image.toml"),
        &vars,
    )
    .unwrap()
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

#[test]
fn process_images_add_up_to_the_total_and_recombine_to_a_trace_with_other_couplings() {
    let n = 100_000;
    let run = cast_electron(&[]);
    assert_eq!(run.sensors[0].processes, ["primakoff", "abc"]);
    let (total, parts, counts) = trace_images(&run, n, 5);
    // Both processes were drawn for about half the photons each: binomial,
    // n/2 ± 5σ of the recorded ones (σ ≤ √n / 2).
    let recorded: u64 = counts.iter().sum();
    for c in &counts {
        let half = recorded as f64 / 2.0;
        assert!(
            (*c as f64 - half).abs() < 5.0 * (recorded as f64).sqrt() / 2.0,
            "{counts:?}"
        );
    }
    // The parts add up to the total pixel by pixel (exact sums, then one
    // rounding each: within a few ulps of the largest pixel).
    let sum: Vec<f64> = parts[0].iter().zip(&parts[1]).map(|(a, b)| a + b).collect();
    let diff: Vec<f64> = sum.iter().zip(&total).map(|(a, b)| a - b).collect();
    assert!(
        max_abs(&diff) <= 1e-14 * max_abs(&total),
        "{}",
        max_abs(&diff)
    );
    // Other couplings: 3× g_aγ and 2.5× g_ae. The recombined image equals the
    // direct trace pixel by pixel to 1e-12 of its largest pixel.
    let other = cast_electron(&["g_agamma=3e-12", "g_ae=2.5e-13"]);
    let (direct, direct_parts, direct_counts) = trace_images(&other, n, 5);
    assert_eq!(direct_counts, counts, "the same photons reach the chip");
    let recombined: Vec<f64> = parts[0]
        .iter()
        .zip(&parts[1])
        .map(|(p, a)| 9.0 * p + 6.25 * a)
        .collect();
    let diff: Vec<f64> = recombined.iter().zip(&direct).map(|(a, b)| a - b).collect();
    assert!(
        max_abs(&diff) <= 1e-12 * max_abs(&direct),
        "{} of {}",
        max_abs(&diff),
        max_abs(&direct)
    );
    let diff: Vec<f64> = direct_parts[1]
        .iter()
        .zip(&parts[1])
        .map(|(d, a)| d - 6.25 * a)
        .collect();
    assert!(max_abs(&diff) <= 1e-12 * max_abs(&direct_parts[1]));
    // And a different image: the test would see a wrong scaling.
    let unscaled: Vec<f64> = parts[0]
        .iter()
        .zip(&parts[1])
        .map(|(p, a)| 9.0 * p + 4.0 * a)
        .collect();
    let diff: Vec<f64> = unscaled.iter().zip(&direct).map(|(a, b)| a - b).collect();
    assert!(max_abs(&diff) > 1e-3 * max_abs(&direct));
}

#[test]
fn each_process_image_is_the_image_of_that_emission_alone() {
    // The Primakoff part of a Primakoff + ABC trace against a trace of the
    // Primakoff emission alone (another set of photons): equal flux on the chip
    // and the same centroid within Monte Carlo error. Photons carry nearly
    // equal weights, so the flux's relative 1σ is about 1/√(photons recorded);
    // the tolerance is 5σ of the two runs combined.
    let n = 200_000;
    let text =
        std::fs::read_to_string(repo().join("scenes/cast_axion_electron_image.toml")).unwrap();
    let alone = text
        .replace("emission = \"primakoff+abc\"", "emission = \"primakoff\"")
        .replace("g_ae = \"$g_ae\"\n", "");
    assert_ne!(alone, text);
    let dir = tempfile::tempdir().unwrap();
    let both = cast_electron(&[]);
    let primakoff = scene_in(dir.path(), &alone);
    assert!(primakoff.sensors[0].processes.is_empty());
    let (_, parts, counts) = trace_images(&both, n, 11);
    let (single, _, _) = trace_images(&primakoff, n, 12);
    let recorded_single = trace::run(&primakoff, &RunConfig::new(n, 12))
        .unwrap()
        .images[0]
        .total_counts();
    let (a, b): (f64, f64) = (parts[0].iter().sum(), single.iter().sum());
    let sigma = (1.0 / counts[0] as f64 + 1.0 / recorded_single as f64).sqrt();
    assert!((a / b - 1.0).abs() < 5.0 * sigma, "{a} vs {b} (σ {sigma})");
    // The ABC part is the larger: at g_aγ = 1e-12, g_ae = 1e-13 ABC makes 99 %
    // of the flux (2.57e9 against 3.6e7 cm⁻² s⁻¹ at 1 AU).
    let abc: f64 = parts[1].iter().sum();
    assert!(abc > 50.0 * a && abc < 200.0 * a, "{abc} vs {a}");
}
