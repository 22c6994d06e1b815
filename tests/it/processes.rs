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
        (0..image.processes.len())
            .map(|k| scaled(image.processes.image(k)))
            .collect(),
        image.processes.counts.clone(),
    )
}

/// The CAST ABC + Primakoff scene, its axions before the conversion (the
/// magnet off: these tests are of the emission's images).
fn cast_electron(vars: &[&str]) -> Scene {
    let vars: Vec<String> = std::iter::once("magnet=false")
        .chain(vars.iter().copied())
        .map(str::to_string)
        .collect();
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
    assert_eq!(
        run.sensors[0].processes,
        [
            "primakoff",
            "abc",
            "atomic",
            "electron_ion",
            "electron_electron",
            "compton"
        ]
    );
    let (total, parts, counts) = trace_images(&run, n, 5);
    // Both couplings were drawn for about half the photons each: binomial,
    // n/2 ± 5σ of the recorded ones (σ ≤ √n / 2).
    let recorded: u64 = counts[..2].iter().sum();
    for c in &counts[..2] {
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

/// A 0.1 mm pinhole 10 m in front of a film, every photon on the film: the
/// camera obscura of the Sun, with `emission`.
fn pinhole(dir: &std::path::Path, emission: &str) -> Scene {
    scene_in(
        dir,
        &format!(
            r#"
[materials.film]
type = "sensor"
size = [80.0, 80.0]
pixels = [400, 400]

[[sources]]
type = "sun"
emission = "{emission}"
target = {{ center = [0, 0, 0], radius = 0.05 }}

[[objects]]
name = "film"
material = "film"
shape = {{ type = "rectangle", size = [80.0, 80.0] }}
transform = [ {{ translate = [0, 0, -10000] }} ]
"#
        ),
    )
}

#[test]
fn abc_process_images_split_the_sun_as_its_processes_emit() {
    // The Sun through a pinhole with ABC alone: four images, atomic,
    // electron–ion, electron–electron and Compton, adding up to the total.
    let dir = tempfile::tempdir().unwrap();
    let scene = pinhole(dir.path(), "abc");
    assert_eq!(
        scene.sensors[0].processes,
        ["atomic", "electron_ion", "electron_electron", "compton"]
    );
    let n = 200_000;
    let (total, parts, _) = trace_images(&scene, n, 8);
    let sum: Vec<f64> = (0..total.len())
        .map(|k| parts.iter().map(|p| p[k]).sum())
        .collect();
    let diff: Vec<f64> = sum.iter().zip(&total).map(|(a, b)| a - b).collect();
    assert!(max_abs(&diff) <= 1e-13 * max_abs(&total));
    // Each process's share of the flux through the pinhole is its share of the
    // flux at Earth, from the per-process spectra (computed with the process
    // tables, not with the shares the trace splits by). Every photon reaches
    // the film, so only the spread of the shares over the cells drawn is
    // noise: the shares lie in [0, 1], σ ≤ 0.5/√n = 0.11 % of the total;
    // tolerance 5σ plus the shares' four decimals.
    let spectra = traxer::source::sun::builtin::abc_process_spectra();
    let edges = traxer::source::sun::builtin::abc_table().energy_edges();
    let at_earth: Vec<f64> = spectra
        .iter()
        .map(|s| {
            s.iter()
                .zip(edges.windows(2))
                .map(|(f, w)| f * (w[1] - w[0]))
                .sum()
        })
        .collect();
    let all: f64 = at_earth.iter().sum();
    let flux: f64 = total.iter().sum();
    for (p, part) in parts.iter().enumerate() {
        let got = part.iter().sum::<f64>() / flux;
        let want = at_earth[p] / all;
        assert!(
            (got - want).abs() < 5.0 * 0.5 / (n as f64).sqrt() + 1e-4,
            "process {p}: {got} of the flux, {want} at Earth"
        );
    }
    // Where they come from: the processes follow density and temperature
    // differently (within 0.1 R_sun, projected, lies 49 % of the atomic
    // emission, 53 % of electron–ion, 51 % of electron–electron, 58 % of
    // Compton), so their images differ in size: the images' RMS radii must
    // order as the processes' radial tables (the ABC table times the shares)
    // say, for every pair whose enclosed fractions differ by more than 0.01.
    let table = traxer::source::sun::builtin::abc_table();
    let shares = traxer::source::sun::shares::builtin_shares();
    let rms = |img: &[f64]| {
        let (mut s, mut w) = (0.0, 0.0);
        for (k, v) in img.iter().enumerate() {
            let (x, y) = ((k % 400) as f64 * 0.2 - 39.9, (k / 400) as f64 * 0.2 - 39.9);
            s += v * (x * x + y * y);
            w += v;
        }
        (s / w).sqrt()
    };
    let mut by_table = Vec::new();
    for p in 0..4 {
        let rates: Vec<f64> = table
            .rates
            .iter()
            .zip(shares.iter())
            .map(|(r, s)| r * s[p])
            .collect();
        let t = traxer::source::sun::EmissionTable::new(
            table.radii.clone(),
            table.energies.clone(),
            rates,
        )
        .unwrap();
        let sampler = traxer::source::sun::EmissionSampler::new(&t, 0.0, 30.0).unwrap();
        by_table.push(sampler.enclosed_projected(0.1));
    }
    let radii: Vec<f64> = parts.iter().map(|p| rms(p)).collect();
    eprintln!("enclosed within 0.1 R_sun {by_table:?}, RMS radii {radii:?} mm");
    let spread = by_table.iter().cloned().fold(f64::MIN, f64::max)
        - by_table.iter().cloned().fold(f64::MAX, f64::min);
    assert!(
        spread > 0.05,
        "the processes come from different radii: {by_table:?}"
    );
    for a in 0..4 {
        for b in 0..4 {
            if by_table[a] > by_table[b] + 0.01 {
                assert!(
                    radii[a] < radii[b],
                    "{a} more compact than {b}: {radii:?}, {by_table:?}"
                );
            }
        }
    }
}

#[test]
fn eef_finds_the_pitch_of_a_process_image_as_of_the_total() {
    // Before: `traxer eef NAME_primakoff.npy` asked for --pixel-pitch, while
    // NAME.npy beside it took the pitch from the sensor's JSON.
    let dir = tempfile::tempdir().unwrap();
    pinhole(dir.path(), "primakoff+abc");
    let out = dir.path().join("o");
    crate::common::run_ok(
        crate::common::traxer()
            .args(["trace", "-n", "20000", "-q", "-o"])
            .arg(&out)
            .arg(dir.path().join("scene.toml")),
    );
    let diameters = |file: &str| {
        let r = crate::common::run_ok(
            crate::common::traxer()
                .current_dir(dir.path())
                .args(["eef", "--json"])
                .arg(out.join(file)),
        );
        let q: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
        q["hpd_mm"].as_f64().unwrap()
    };
    let (total, primakoff) = (diameters("film.npy"), diameters("film_primakoff.npy"));
    // The same Sun through the same pinhole: HPDs of tens of mm, alike.
    assert!(
        total > 1.0 && (primakoff / total - 1.0).abs() < 0.3,
        "{total} {primakoff}"
    );
}
