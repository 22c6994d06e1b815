//! The solar axion emission and the `sun` source: the built-in table against the
//! full computation from the solar model, the spectrum against the CAST 2007
//! parameterisation, the sampler against the table, the image through a pinhole
//! against the table's projected profile, and malformed tables.

use crate::common::{repo, run_fails, run_ok, scene_in, traxer, write};
use std::path::{Path, PathBuf};
use traxer::constants::{AU_CM, R_SUN_CM};
use traxer::output::cast2007_flux;
use traxer::random::PhotonRng;
use traxer::source::sun::builtin::{
    abc_process_spectra, abc_table, builtin_emission, model_emission,
    primakoff_table as builtin_table,
};
use traxer::source::sun::opacity_project::OpacityTables;
use traxer::source::sun::primakoff::emission_table;
use traxer::source::sun::{EmissionSampler, EmissionTable, SolarModel};
use traxer::source::Source;
use traxer::trace::{self, RunConfig};

/// The standard solar model, where CI and the development machine keep it.
fn model_path() -> Option<PathBuf> {
    let p = repo().join("../shared/solar/SolarModel_B16-AGSS09met.dat");
    p.exists().then_some(p)
}

/// The Opacity Project tables and Redondo's benchmarks, beside the model.
fn op_dir() -> Option<PathBuf> {
    let p = repo().join("../shared/solar/op");
    p.exists().then_some(p)
}

/// Flux at 1 AU between `lo` and `hi` keV, cm⁻² s⁻¹.
fn band_flux(t: &EmissionTable, lo: f64, hi: f64) -> f64 {
    t.luminosity(lo, hi) / (4.0 * std::f64::consts::PI * AU_CM * AU_CM)
}

#[test]
#[ignore = "needs ../shared/solar/: scripts/test.sh runs it (`-- --ignored shared_solar_`) where it is, and CI fails without it"]
fn shared_solar_the_builtin_table_reproduces_the_full_computation() {
    let path = model_path().expect("../shared/solar/ is not here");
    let model = SolarModel::read(&path).unwrap();
    // Every row of the model (0.0005 R_sun steps) and 0.01 keV steps to 20 keV.
    let radii: Vec<f64> = model.shells.iter().map(|s| s.radius).collect();
    let energies: Vec<f64> = (0..2000).map(|k| 0.035 + 0.01 * k as f64).collect();
    let full = emission_table(&model, &radii, &energies).unwrap();
    let shipped = builtin_table();
    let (f, s) = (band_flux(&full, 0.0, 30.0), band_flux(shipped, 0.0, 30.0));
    assert!(
        (s / f - 1.0).abs() < 0.01,
        "total: built-in {s:.4e}, full {f:.4e}"
    );
    for k in 0..18 {
        let lo = 1.0 + 0.5 * k as f64;
        let (f, s) = (
            band_flux(&full, lo, lo + 0.5),
            band_flux(shipped, lo, lo + 0.5),
        );
        assert!(
            (s / f - 1.0).abs() < 0.02,
            "{lo}–{} keV: built-in {s:.4e}, full {f:.4e}",
            lo + 0.5
        );
    }
}

#[test]
#[ignore = "needs ../shared/solar/: scripts/test.sh runs it (`-- --ignored shared_solar_`) where it is, and CI fails without it"]
fn shared_solar_the_builtin_abc_table_reproduces_the_full_computation() {
    let (path, op) = (
        model_path().expect("../shared/solar/ is not here"),
        op_dir().expect("../shared/solar/op is not here"),
    );
    let model = SolarModel::read(&path).unwrap();
    let op = OpacityTables::read(&op).unwrap();
    let shipped = abc_table();
    // The same grid: the shipped file is today's computation (CSV: 7 digits).
    let again = model_emission(
        &model,
        "m",
        Some(&op),
        &shipped.radii,
        &shipped.energies,
        None,
        Some(1e-13),
    )
    .unwrap();
    for (k, (a, b)) in shipped.rates.iter().zip(&again.table.rates).enumerate() {
        assert!(
            (a - b).abs() <= 6e-7 * b.abs(),
            "rate {k}: shipped {a:e}, computed {b:e}"
        );
    }
    // The shipped shares of the four processes in every cell: the computation's
    // own to their four decimals (±5e-5 each, and reading rescales them to add
    // up to 1, which moves each by at most the four roundings: ±2.5e-4).
    let shipped_shares = traxer::source::sun::shares::builtin_shares();
    let computed = again.couplings[0]
        .shares
        .as_ref()
        .expect("ABC from a model has shares");
    assert_eq!(shipped_shares.len(), computed.len());
    for (k, (a, b)) in shipped_shares.iter().zip(computed.iter()).enumerate() {
        for p in 0..4 {
            assert!(
                (a[p] - b[p]).abs() <= 2.5e-4,
                "cell {k}, process {p}: shipped {}, computed {}",
                a[p],
                b[p]
            );
        }
    }
    let spectra = abc_process_spectra();
    for (p, s) in spectra.iter().enumerate() {
        for (j, (x, y)) in s.iter().zip(&again.parts[p].spectrum_1au).enumerate() {
            assert!(
                (x - y).abs() <= 6e-7 * y.abs(),
                "process {p}, energy {j}: {x:e} vs {y:e}"
            );
        }
    }
    // The full computation in 0.1 keV cells against the table's 0.025 keV cells
    // summed: the lines are averaged, not sampled, so every 0.1 keV bin agrees
    // (required: 1 %).
    let coarse: Vec<f64> = (0..149).map(|k| 0.15 + 0.1 * k as f64).collect();
    let full = model_emission(
        &model,
        "m",
        Some(&op),
        &shipped.radii,
        &coarse,
        None,
        Some(1e-13),
    )
    .unwrap();
    let mut worst: f64 = 0.0;
    for &e in &coarse {
        let (lo, hi) = (e - 0.05, e + 0.05);
        let (f, s) = (band_flux(&full.table, lo, hi), band_flux(shipped, lo, hi));
        worst = worst.max((s / f - 1.0).abs());
    }
    assert!(worst < 0.01, "worst 0.1 keV bin differs by {worst}");
}

/// Redondo's ABC spectrum (JCAP 12 (2013) 008; ../shared/solar/op/benchmarks):
/// (energy keV, dΦ/dE at 1 AU in cm⁻² s⁻¹ keV⁻¹ for g_ae = 1e-13).
fn redondo(file: &str) -> Vec<(f64, f64)> {
    let text = std::fs::read_to_string(op_dir().unwrap().join("benchmarks").join(file)).unwrap();
    // all: 1e19 / (keV cm² day) at g_ae = 0.511e-10; the digitised ff and Compton
    // curves: 1 / (keV m² year) at g_ae = 1e-13 (Hoof et al.'s reading of them).
    let scale = if file.ends_with("all.dat") {
        1e19 / 86400.0 * (1e-13f64 / 0.511e-10).powi(2)
    } else {
        1e-4 / (365.25 * 86400.0)
    };
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            (v[0], v[1] * scale)
        })
        .collect()
}

/// ∫ of a tabulated curve between lo and hi (trapezoids on its points).
fn integral(curve: &[(f64, f64)], lo: f64, hi: f64) -> f64 {
    curve
        .windows(2)
        .filter(|w| w[0].0 >= lo && w[1].0 <= hi)
        .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0))
        .sum()
}

/// Linear interpolation in a tabulated curve.
fn at(curve: &[(f64, f64)], e: f64) -> f64 {
    let k = curve.partition_point(|p| p.0 < e).clamp(1, curve.len() - 1);
    let ((x0, y0), (x1, y1)) = (curve[k - 1], curve[k]);
    y0 + (e - x0) / (x1 - x0) * (y1 - y0)
}

#[test]
#[ignore = "needs ../shared/solar/: scripts/test.sh runs it (`-- --ignored shared_solar_`) where it is, and CI fails without it"]
fn shared_solar_the_abc_spectrum_agrees_with_redondo_2013() {
    op_dir().expect("../shared/solar/op is not here");
    let abc = builtin_emission(None, Some(1e-13)).unwrap();
    let all = redondo("2013_redondo_all.dat");
    // Total 0.1–12 keV: Redondo 2.645e9 cm⁻² s⁻¹; traxer 2.569e9 (−2.9 %: another
    // solar model — Redondo used AGSS09 — and OP release). Tolerance 5 %.
    let (ours, his) = (band_flux(&abc.table, 0.1, 12.0), integral(&all, 0.1, 12.0));
    assert!(
        (ours / his - 1.0).abs() < 0.05,
        "total {ours:.4e} vs {his:.4e}"
    );
    // Shape per 0.5 keV bin: within 5 % to 3 keV (measured ≤ 3.5 %); above, the
    // atomic part falls below his (8–13 % at 6–10 keV, measured), so 15 %.
    for k in 1..20 {
        let lo = 0.5 * k as f64;
        let (o, h) = (
            band_flux(&abc.table, lo, lo + 0.5),
            integral(&all, lo, lo + 0.5),
        );
        let tolerance = if lo < 3.0 { 0.05 } else { 0.15 };
        assert!(
            (o / h - 1.0).abs() < tolerance,
            "{lo}–{} keV: {o:.4e} vs {h:.4e}",
            lo + 0.5
        );
    }
    // Free–free (electron–ion + electron–electron) and Compton against his
    // digitised curves, 1–6 keV: within 5 % (measured ≤ 3 %). Compton with both
    // photon polarisations: half of it would miss by 50 %.
    let energies = &abc.table.energies;
    let part = |name: &str| {
        &abc.parts
            .iter()
            .find(|p| p.name == name)
            .unwrap()
            .spectrum_1au
    };
    let (ei, ee, c) = (
        part("electron_ion"),
        part("electron_electron"),
        part("compton"),
    );
    let (ff_his, c_his) = (
        redondo("2013_redondo_ff.dat"),
        redondo("2013_redondo_compton.dat"),
    );
    for e in [1.0, 2.0, 3.0, 4.0, 5.0, 6.0] {
        let j = energies.partition_point(|&x| x < e);
        let ff: f64 = ei[j] + ee[j];
        let e_j = energies[j];
        assert!(
            (ff / at(&ff_his, e_j) - 1.0).abs() < 0.05,
            "ff at {e_j}: {ff:.4e} vs {:.4e}",
            at(&ff_his, e_j)
        );
        assert!(
            (c[j] / at(&c_his, e_j) - 1.0).abs() < 0.05,
            "Compton at {e_j}: {:.4e} vs {:.4e}",
            c[j],
            at(&c_his, e_j)
        );
    }
}

#[test]
fn couplings_scale_the_flux_as_their_squares_and_add() {
    let p = builtin_emission(Some(1e-10), None).unwrap();
    let a = builtin_emission(None, Some(1e-13)).unwrap();
    let both = builtin_emission(Some(3e-11), Some(2e-13)).unwrap();
    let f = |t: &EmissionTable| band_flux(t, 0.0, 30.0);
    // The Primakoff part loses only what lies outside the ABC grid, 0.1–15 keV.
    let expected = 0.09 * band_flux(&p.table, 0.1, 15.0) + 4.0 * f(&a.table);
    assert!(
        (f(&both.table) / expected - 1.0).abs() < 1e-9,
        "{} vs {expected}",
        f(&both.table)
    );
    // Every 0.5 keV band of the resampled Primakoff part keeps its rate.
    let prim = both.parts[0].table.as_ref().unwrap();
    for k in 1..20 {
        let lo = 0.5 * k as f64;
        let (x, y) = (
            band_flux(prim, lo, lo + 0.5),
            0.09 * band_flux(&p.table, lo, lo + 0.5),
        );
        assert!((x / y - 1.0).abs() < 1e-9, "{lo} keV: {x} vs {y}");
    }
    // ABC is more compact than Primakoff (SPEC §3): half its emission lies within a
    // smaller radius.
    let r50 = |t: &EmissionTable| {
        let s = EmissionSampler::new(t, 0.1, 15.0).unwrap();
        (1..1000)
            .map(|k| k as f64 / 1000.0)
            .find(|&r| s.enclosed_3d(r) >= 0.5)
            .unwrap()
    };
    assert!(
        r50(&a.table) < r50(&p.table) - 0.01,
        "{} vs {}",
        r50(&a.table),
        r50(&p.table)
    );
}

#[test]
fn the_spectrum_at_earth_is_close_to_the_cast_2007_parameterisation() {
    // CAST 2007 fitted the Primakoff flux of the BP04 solar model; B16-AGSS09met's
    // core is 1.7 % cooler (1.544e7 vs 1.57e7 K), which lowers the flux and softens
    // the spectrum: we measure −5.3 % in total and −4 % (1–2 keV) to −10 % (9–10
    // keV) per bin. Accepted: total within −10 … +3 %, each 1 keV bin from 1 to 10
    // keV within −15 … +5 %; a wrong unit, coupling or phase-space factor is off by
    // far more (a factor 2 for a missed polarisation).
    let t = builtin_table();
    let cast = |lo: f64, hi: f64| {
        let n = 10_000;
        (0..n)
            .map(|k| cast2007_flux(lo + (hi - lo) * (k as f64 + 0.5) / n as f64))
            .sum::<f64>()
            * (hi - lo)
            / n as f64
    };
    let total = band_flux(t, 0.0, 30.0) / cast(0.0, 20.0);
    assert!((0.90..1.03).contains(&total), "total ratio {total}");
    for k in 1..10 {
        let lo = k as f64;
        let r = band_flux(t, lo, lo + 1.0) / cast(lo, lo + 1.0);
        assert!(
            (0.85..1.05).contains(&r),
            "{lo}–{} keV: ratio {r}",
            lo + 1.0
        );
    }
}

#[test]
fn the_sampler_draws_energies_and_radii_as_the_table_says() {
    let t = builtin_table();
    let s = EmissionSampler::new(t, 0.0, 30.0).unwrap();
    let n = 400_000;
    let mut e_hist = [0u64; 12];
    let mut r_hist = [0u64; 10];
    for i in 0..n {
        let (r, e) = s.sample(&mut PhotonRng::new(11, i));
        e_hist[(e as usize).min(11)] += 1;
        r_hist[((r / 0.05) as usize).min(9)] += 1;
    }
    // Each bin within 5 standard deviations of its expected count (binomial):
    // a false alarm at any seed has probability ~1e-6 per bin.
    let check = |what: &str, got: u64, p: f64| {
        let expected = p * n as f64;
        let sigma = (n as f64 * p * (1.0 - p)).sqrt().max(1.0);
        assert!(
            (got as f64 - expected).abs() < 5.0 * sigma,
            "{what}: {got} drawn, {expected:.0} expected"
        );
    };
    let total = t.luminosity(0.0, 30.0);
    for (k, &got) in e_hist.iter().enumerate() {
        let hi = if k == 11 { 30.0 } else { k as f64 + 1.0 };
        check(
            &format!("energy bin {k}"),
            got,
            t.luminosity(k as f64, hi) / total,
        );
    }
    for (k, &got) in r_hist.iter().enumerate() {
        let (lo, hi) = (
            0.05 * k as f64,
            if k == 9 { 1.0 } else { 0.05 * (k + 1) as f64 },
        );
        check(
            &format!("radius bin {k}"),
            got,
            s.enclosed_3d(hi) - s.enclosed_3d(lo),
        );
    }
}

#[test]
fn a_non_uniform_radial_grid_is_integrated_over_its_own_cells() {
    // Emissivity uniform in volume up to 0.5 R_sun (w·E² constant), on a grid
    // that is fine inside and coarse outside: the emission within r must be
    // (r/0.5)³ whatever the steps. The r_i²Δr_i quadrature is exact to O(Δr²).
    let mut radii: Vec<f64> = (0..100).map(|k| 0.001 + 0.002 * k as f64).collect();
    radii.extend((0..30).map(|k| 0.2025 + 0.01 * k as f64));
    let energies = vec![2.0, 3.0];
    let rates = radii
        .iter()
        .flat_map(|_| energies.iter().map(|e| 1e-30 / (e * e)))
        .collect();
    let t = EmissionTable::new(radii, energies, rates).unwrap();
    let s = EmissionSampler::new(&t, 0.0, 30.0).unwrap();
    for r in [0.1, 0.2, 0.3, 0.4] {
        let want = (r / 0.4975f64).powi(3);
        assert!(
            (s.enclosed_3d(r) - want).abs() < 0.01,
            "r {r}: {} vs {want}",
            s.enclosed_3d(r)
        );
    }
}

/// A Sun 0.989 AU away seen through a pinhole of radius 0.05 mm, with a 80 × 80 mm
/// sensor `distance` mm behind it.
fn pinhole_scene(dir: &Path, distance: f64) -> String {
    let text = format!(
        r#"
[materials.film]
type = "sensor"
size = [80.0, 80.0]
pixels = [800, 800]

[[sources]]
type = "sun"
target = {{ center = [0, 0, 0], radius = 0.05 }}

[[objects]]
name = "film"
material = "film"
shape = {{ type = "rectangle", size = [80.0, 80.0] }}
transform = [ {{ translate = [0, 0, -{distance}] }} ]
"#
    );
    write(dir, "pinhole.toml", &text).display().to_string()
}

#[test]
fn a_pinhole_image_of_the_sun_has_the_projected_profile_and_the_absolute_rate() {
    let dir = tempfile::tempdir().unwrap();
    let distance = 10_000.0;
    let text = std::fs::read_to_string(pinhole_scene(dir.path(), distance)).unwrap();
    let scene = scene_in(dir.path(), &text);
    let Source::Sun(sun) = &scene.sources[0] else {
        panic!("a sun")
    };
    let n = 200_000;
    let r = trace::run(&scene, &RunConfig::new(n, 5)).unwrap();
    assert_eq!(r.stats.reached_sensor, n);
    // Absolute rate: every photon reaches the film, so the image's sum is the
    // rate through the pinhole (weights differ from 1 by < 1e-3).
    let rate = r.images[0].total_flux() * sun.rate_per_unit_weight(n);
    let expected = sun.rate_through_target();
    assert!(
        (rate / expected - 1.0).abs() < 2e-3,
        "{rate} vs {expected} axions/s"
    );
    let flux_per_cm2 = expected / (std::f64::consts::PI * 0.05f64.powi(2)) * 100.0;
    let at_0989 = 3.551e11 / (0.989f64 * 0.989);
    assert!(
        (flux_per_cm2 / at_0989 - 1.0).abs() < 0.01,
        "{flux_per_cm2:.4e} cm⁻² s⁻¹"
    );
    // Enclosed fraction within radius R on the film = the table's projection
    // within ρ = atan(R/L)·D/R_sun. Tolerance: binomial noise (σ ≤ 0.0011) plus
    // the pixel edges (0.1 mm pixels) — 0.01.
    let img = &r.images[0].flux();
    let total: f64 = img.iter().sum();
    let d_mm = 0.989 * AU_CM * 10.0;
    for radius in [3.0, 6.0, 10.0, 15.0, 25.0] {
        let inside: f64 = img
            .iter()
            .enumerate()
            .filter(|(k, _)| {
                let (x, y) = (
                    (k % 800) as f64 * 0.1 - 39.95,
                    (k / 800) as f64 * 0.1 - 39.95,
                );
                x * x + y * y < radius * radius
            })
            .map(|(_, v)| v)
            .sum();
        let rho = (radius / distance).atan() * d_mm / (R_SUN_CM * 10.0);
        let want = sun.emission_draw.enclosed_projected(rho);
        assert!(
            (inside / total - want).abs() < 0.01,
            "R = {radius} mm (ρ = {rho:.3}): {} vs {want}",
            inside / total
        );
    }
}

#[test]
fn trace_writes_the_sun_image_in_axions_per_second() {
    let dir = tempfile::tempdir().unwrap();
    let scene = pinhole_scene(dir.path(), 10_000.0);
    let out = dir.path().join("out");
    run_ok(
        traxer()
            .args(["trace", &scene, "--photons", "20000", "--quiet", "--out"])
            .arg(&out),
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let through = summary["sources"][0]["rate_through_target_per_s"]
        .as_f64()
        .unwrap();
    let on_sensor = summary["sensors"][0]["total_flux"].as_f64().unwrap();
    assert!(
        (on_sensor / through - 1.0).abs() < 2e-3,
        "{on_sensor} vs {through}"
    );
    let image = traxer::output::read_image(&out.join("film.npy")).unwrap();
    let sum: f64 = image.summed.iter().sum();
    assert!((sum / on_sensor - 1.0).abs() < 1e-9);
    assert!(summary["sensors"][0]["units"]["flux"]
        .as_str()
        .unwrap()
        .contains("axions per second"));
}

#[test]
fn malformed_emission_tables_are_refused_with_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let header = "Radius,Energy [keV],emRates\n";
    let good_rows = "0.1,1.0,1e-30\n0.1,2.0,1e-30\n0.2,1.0,1e-30\n0.2,2.0,1e-30\n";
    let cases: [(&str, String, &str); 10] = [
        (
            "missing column",
            "Radius,Energy [keV]\n0.1,1.0\n".into(),
            ":1: no column `emRates`",
        ),
        (
            "not a number",
            format!("{header}0.1,1.0,abc\n"),
            ":2: emRates `abc` is not a number",
        ),
        (
            "negative",
            format!("{header}0.1,1.0,-1e-30\n"),
            ":2: emission rate -0.00",
        ),
        (
            "radius zero",
            format!("{header}0.0,1.0,1e-30\n"),
            ":2: radius 0: expected a fraction",
        ),
        (
            "radius above one",
            format!("{header}1.5,1.0,1e-30\n"),
            ":2: radius 1.5",
        ),
        (
            "unsorted radii",
            format!("{header}0.2,1.0,1e-30\n0.1,1.0,1e-30\n"),
            ":3: radius 0.1 after 0.2",
        ),
        (
            "duplicate point",
            format!("{header}0.1,1.0,1e-30\n0.1,1.0,1e-30\n"),
            ":3: energy 1 keV at radius 0.1 repeats",
        ),
        (
            "energy below Henke",
            format!("{header}0.1,0.001,1e-30\n"),
            ":2: energy 0.001 keV: outside the Henke range",
        ),
        (
            "ragged grid",
            format!("{header}{good_rows}0.3,1.0,1e-30\n"),
            "radius 0.3",
        ),
        (
            // One radius at 1 was a ring at the limb with 3× the Sun's volume.
            "one radius",
            format!("{header}1.0,1.0,1e-30\n1.0,2.0,1e-30\n"),
            "one radius (1): a radial profile needs at least 2 radii",
        ),
    ];
    for (what, text, expected) in cases {
        let csv = write(dir.path(), "bad.csv", &text);
        let e = EmissionTable::read_csv(&csv).unwrap_err().to_string();
        assert!(e.contains("bad.csv") && e.contains(expected), "{what}: {e}");
        // From the command line: exit code 2, nothing written.
        let out = dir.path().join("out");
        let msg = run_fails(
            traxer()
                .args(["solar-flux", "--quiet", "--table"])
                .arg(&csv)
                .arg("--out")
                .arg(&out),
            2,
        );
        assert!(msg.contains(expected), "{what}: {msg}");
        assert!(!out.exists(), "{what}: an output folder was written");
    }
    let csv = write(
        dir.path(),
        "good.csv",
        &format!("# a comment\n{header}{good_rows}"),
    );
    let t = EmissionTable::read_csv(&csv).unwrap();
    assert_eq!((t.radii.len(), t.energies.len()), (2, 2));
    // In a scene: the scene's line and the table's.
    write(dir.path(), "bad.csv", &format!("{header}0.1,1.0,x\n"));
    let scene = write(
        dir.path(),
        "s.toml",
        "[[sources]]\ntype = \"sun\"\nemission = \"bad.csv\"\ntarget = { center = [0, 0, 0], radius = 1.0 }\n",
    );
    let out = dir.path().join("out2");
    let msg = run_fails(traxer().arg("trace").arg(&scene).arg("--out").arg(&out), 2);
    assert!(msg.contains("s.toml") && msg.contains("bad.csv:2"), "{msg}");
    assert!(!out.exists());
}

#[test]
fn an_abc_sun_traces_in_axions_per_second_that_scale_as_g_ae_squared() {
    let dir = tempfile::tempdir().unwrap();
    let base = std::fs::read_to_string(pinhole_scene(dir.path(), 10_000.0)).unwrap();
    let with = |extra: &str| base.replace("type = \"sun\"", &format!("type = \"sun\"\n{extra}"));
    let n = 50_000;
    let rate = |text: &str| {
        let scene = scene_in(dir.path(), text);
        let Source::Sun(sun) = &scene.sources[0] else {
            panic!("a sun")
        };
        let r = trace::run(&scene, &RunConfig::new(n, 3)).unwrap();
        let on_film = r.images[0].total_flux() * sun.rate_per_unit_weight(n);
        (
            on_film,
            sun.rate_through_target(),
            r.images[0].flux().to_vec(),
        )
    };
    let (one, through, img1) = rate(&with("emission = \"abc\""));
    let (two, _, img2) = rate(&with("emission = \"abc\"\ng_ae = 2e-13"));
    // Every photon reaches the film: the rate is the flux through the pinhole.
    assert!((one / through - 1.0).abs() < 2e-3, "{one} vs {through}");
    // The ABC flux at 0.989 AU through the 0.05 mm pinhole, from the table.
    let abc = builtin_emission(None, Some(1e-13)).unwrap();
    let flux = band_flux(&abc.table, 0.0, 30.0) / (0.989f64 * 0.989);
    let expected = flux * std::f64::consts::PI * 0.005f64.powi(2);
    assert!(
        (through / expected - 1.0).abs() < 1e-3,
        "{through} vs {expected}"
    );
    // g_ae² scaling: the same photons, four times the axions per second.
    assert_eq!(img1, img2);
    assert!((two / one - 4.0).abs() < 1e-12, "{}", two / one);
    // Primakoff + ABC: the sum of both rates.
    let (_, both, _) = rate(&with("emission = \"primakoff+abc\"\ng_agamma = 1e-12"));
    let (_, prim, _) = rate(&with("g_agamma = 1e-12"));
    assert!(
        ((prim + through) / both - 1.0).abs() < 1e-3,
        "{prim} + {through} vs {both}"
    );
    // A coupling for a process the emission does not have is refused.
    let bad = write(dir.path(), "bad.toml", &with("g_ae = 1e-13"));
    let err = run_fails(
        traxer().args(["trace", bad.to_str().unwrap(), "--photons", "10"]),
        2,
    );
    assert!(
        err.contains("g_ae") && err.contains("primakoff+abc"),
        "{err}"
    );
}

#[test]
fn degenerate_solar_models_and_overflowing_couplings_are_refused_not_panicked() {
    let Some(model) = model_path() else {
        return;
    };
    let text = std::fs::read_to_string(&model).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    // Replace column `col` (0-based) of every data row by `value`, or every
    // mass fraction (columns 6 onward) when `col` is None.
    let edited = |col: Option<usize>, value: &str| -> String {
        text.lines()
            .map(|l| {
                if l.trim_start().starts_with('#') || l.trim().is_empty() {
                    return l.to_string();
                }
                let f: Vec<&str> = l.split_whitespace().collect();
                f.iter()
                    .enumerate()
                    .map(|(k, x)| match col {
                        Some(c) if c == k => value,
                        None if k >= 6 => value,
                        _ => x,
                    })
                    .collect::<Vec<_>>()
                    .join(" ")
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    for (what, body, needle) in [
        (
            "no matter",
            edited(None, "0.0"),
            "the mass fractions add up to 0",
        ),
        ("hot", edited(Some(2), "1e30"), "temperature 1e30 K"),
        ("no density", edited(Some(3), "nan"), "density NaN"),
    ] {
        let file = write(dir.path(), "model.dat", &body);
        let err = run_fails(
            traxer()
                .args(["solar-flux", "-q", "--model"])
                .arg(&file)
                .arg("-o")
                .arg(&out),
            2,
        );
        assert!(
            err.contains("model.dat:") && err.contains(needle) && !err.contains("panicked"),
            "{what}: {err}"
        );
        assert!(!out.exists());
    }
    let err = run_fails(
        traxer()
            .args(["solar-flux", "-q", "--g-agamma", "1e200", "-o"])
            .arg(&out),
        2,
    );
    assert!(
        err.contains("overflows") && !err.contains("panicked"),
        "{err}"
    );
    let scene = write(
        dir.path(),
        "s.toml",
        "[[sources]]\ntype = \"sun\"\ng_agamma = 1e200\ntarget = { center = [0, 0, 0], radius = 1.0 }\n",
    );
    let err = run_fails(traxer().arg("trace").arg(&scene).arg("-o").arg(&out), 2);
    assert!(err.contains("overflows") && err.contains("s.toml"), "{err}");
}

#[test]
#[ignore = "needs ../shared/solar/: scripts/test.sh runs it (`-- --ignored shared_solar_`) where it is, and CI fails without it"]
fn shared_solar_a_radius_outside_the_opacity_project_grid_is_named() {
    // Before: the OP grid point was named, not the radius of the model that
    // needed it.
    let (model, op) = (
        model_path().expect("../shared/solar/ is not here"),
        op_dir().expect("../shared/solar/op is not here"),
    );
    let dir = tempfile::tempdir().unwrap();
    let err = crate::common::run_fails(
        crate::common::traxer()
            .args(["solar-flux", "--emission", "abc", "--model"])
            .arg(&model)
            .arg("--opacities")
            .arg(&op)
            .args(["--radii", "0.1,0.5,0.95", "--energies", "1,2,3", "-q", "-o"])
            .arg(dir.path().join("o")),
        2,
    );
    assert!(err.contains("r = 0.95"), "{err}");
    // Issue 59 §4: and the option, and the radii the tables cover (the
    // B16 model's shells leave the OP grid between 0.70 and 0.71 R_sun).
    assert!(err.starts_with("error: --radii: "), "{err}");
    assert!(
        err.contains(
            "the Opacity Project tables cover this model's shells from r = 0.0005 to 0.70"
        ),
        "{err}"
    );
}

#[test]
#[ignore = "needs ../shared/solar/: scripts/test.sh runs it (`-- --ignored shared_solar_`) where it is, and CI fails without it"]
fn shared_solar_an_emission_table_cites_the_model_it_was_computed_from() {
    // Before: every table made with --model cited B16-AGSS09met, whatever the
    // file (GS98 for the solar-model systematic among them).
    let gs98 = repo().join("../shared/solar/SolarModel_B16-GS98.dat");
    assert!(gs98.exists(), "../shared/solar/ is not here");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("gs98");
    crate::common::run_ok(
        crate::common::traxer()
            .args(["solar-flux", "--model"])
            .arg(&gs98)
            .args(["--radii", "0.1,0.2", "--energies", "1,2", "-q", "-o"])
            .arg(&out),
    );
    let table = std::fs::read_to_string(out.join("emission.csv")).unwrap();
    assert!(table.contains("# B16-GS98, N. Vinyoles"), "{table}");
    assert!(!table.contains("AGSS09met"), "{table}");
}

#[test]
fn the_gs98_tables_are_the_hotter_model_and_its_primakoff_flux_is_cast_2007s() {
    // B16-GS98's higher metal abundances make the core more opaque and hotter
    // than B16-AGSS09met's: both emissions rise, by a few per cent (a wrong
    // table, unit or coupling would be off by far more). And the CAST 2007
    // parameterisation fitted the Primakoff flux of BP04, a model with the same
    // GS98 abundances: GS98's total is within 2 % of it, and every 1 keV bin
    // from 1 to 10 keV within 5 % (AGSS09met is 5.3 % below in total).
    use traxer::source::sun::builtin::{builtin_emission_of, BuiltinModel};
    let flux = |m: BuiltinModel, p: Option<f64>, a: Option<f64>| {
        band_flux(&builtin_emission_of(m, p, a).unwrap().table, 0.0, 30.0)
    };
    for (p, a) in [(Some(1e-10), None), (None, Some(1e-13))] {
        let ratio = flux(BuiltinModel::B16Gs98, p, a) / flux(BuiltinModel::B16Agss09met, p, a);
        assert!((1.02..1.10).contains(&ratio), "GS98 / AGSS09met = {ratio}");
    }
    let gs98 = builtin_emission_of(BuiltinModel::B16Gs98, Some(1e-10), None)
        .unwrap()
        .table;
    let cast = |lo: f64, hi: f64| {
        let n = 10_000;
        (0..n)
            .map(|k| cast2007_flux(lo + (hi - lo) * (k as f64 + 0.5) / n as f64))
            .sum::<f64>()
            * (hi - lo)
            / n as f64
    };
    let total = band_flux(&gs98, 0.0, 30.0) / cast(0.0, 20.0);
    assert!((total - 1.0).abs() < 0.02, "total ratio {total}");
    for k in 1..10 {
        let lo = k as f64;
        let r = band_flux(&gs98, lo, lo + 1.0) / cast(lo, lo + 1.0);
        assert!((r - 1.0).abs() < 0.05, "{lo}–{} keV: ratio {r}", lo + 1.0);
    }
}

#[test]
#[ignore = "needs ../shared/solar/: scripts/test.sh runs it (`-- --ignored shared_solar_`) where it is, and CI fails without it"]
fn shared_solar_the_gs98_tables_are_the_computation_of_the_gs98_model() {
    // The shipped B16-GS98 tables are what `traxer solar-flux --model
    // SolarModel_B16-GS98.dat` computes on their grid (the CSV keeps 7 digits):
    // the same script and code as AGSS09met's, checked as AGSS09met's are.
    use traxer::source::sun::tables::{tables, BuiltinModel};
    let dir = model_path().expect("../shared/solar/ is not here");
    let path = dir.with_file_name("SolarModel_B16-GS98.dat");
    let model = SolarModel::read(&path).unwrap();
    let op = OpacityTables::read(&op_dir().expect("../shared/solar/op is not here")).unwrap();
    let shipped = tables(BuiltinModel::B16Gs98);
    let p = &shipped.primakoff;
    let again =
        model_emission(&model, "m", None, &p.radii, &p.energies, Some(1e-10), None).unwrap();
    for (k, (a, b)) in p.rates.iter().zip(&again.table.rates).enumerate() {
        assert!(
            (a - b).abs() <= 6e-7 * b.abs(),
            "Primakoff rate {k}: {a:e} vs {b:e}"
        );
    }
    let a = &shipped.abc;
    let again = model_emission(
        &model,
        "m",
        Some(&op),
        &a.radii,
        &a.energies,
        None,
        Some(1e-13),
    )
    .unwrap();
    for (k, (x, y)) in a.rates.iter().zip(&again.table.rates).enumerate() {
        assert!(
            (x - y).abs() <= 6e-7 * y.abs(),
            "ABC rate {k}: {x:e} vs {y:e}"
        );
    }
    for (p, s) in shipped.abc_spectra.iter().enumerate() {
        for (j, (x, y)) in s.iter().zip(&again.parts[p].spectrum_1au).enumerate() {
            assert!(
                (x - y).abs() <= 6e-7 * y.abs(),
                "process {p}, energy {j}: {x:e} vs {y:e}"
            );
        }
    }
    // And the models differ: the test would see AGSS09met's tables shipped as GS98's.
    let agss = tables(BuiltinModel::B16Agss09met);
    assert!(agss
        .abc
        .rates
        .iter()
        .zip(&a.rates)
        .any(|(x, y)| (x / y - 1.0).abs() > 0.01));
}

#[test]
fn a_couplings_table_scales_the_emissions_it_has_and_names_the_one_it_does_not_use() {
    // `couplings = {...}` for a scene whose emission is a variable: with
    // emission "primakoff" the image equals that of `g_agamma` alone (same
    // photons, the same factor), and g_ae is reported as not used; both forms
    // together, or couplings with an emission table file, are refused.
    let dir = tempfile::tempdir().unwrap();
    let scene = |source_keys: &str| {
        format!(
            "[[sources]]\ntype = \"sun\"\nemission = \"primakoff\"\n{source_keys}\ndirection = [0.0, 0.0, 1.0]\ntarget = {{ center = [0, 0, 100], radius = 20.0 }}\n\n[materials.s]\ntype = \"sensor\"\nsize = [60.0, 60.0]\npixels = [30, 30]\n\n[[objects]]\nname = \"s\"\nmaterial = \"s\"\nshape = {{ type = \"rectangle\", size = [60.0, 60.0] }}\n"
        )
    };
    let trace = |text: &str, name: &str| {
        let path = crate::common::write(dir.path(), name, text);
        let out = dir.path().join(format!("{name}.out"));
        crate::common::run_ok(
            crate::common::traxer()
                .arg("trace")
                .arg(&path)
                .args(["-n", "20000", "-q", "-o"])
                .arg(&out),
        );
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        (std::fs::read(out.join("s.npy")).unwrap(), summary)
    };
    let (direct, _) = trace(&scene("g_agamma = 3e-11"), "direct.toml");
    let (table, summary) = trace(
        &scene("couplings = { g_agamma = 3e-11, g_ae = 2e-13 }"),
        "table.toml",
    );
    assert!(direct == table, "the same image");
    let unused = &summary["sources"][0]["couplings_not_used"];
    assert_eq!(unused.as_array().unwrap().len(), 1, "{unused}");
    assert!(
        unused[0].as_str().unwrap().contains("g_ae = 2e-13"),
        "{unused}"
    );
    let err = crate::common::load_error(
        dir.path(),
        &scene("g_agamma = 3e-11\ncouplings = { g_ae = 2e-13 }"),
    );
    assert!(err.contains("not both"), "{err}");
}
