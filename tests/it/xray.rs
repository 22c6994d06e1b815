//! X-ray mirror physics against independent numbers: the depth-graded recipe's
//! published thicknesses, periodictable's optical constants, xraydb's Parratt
//! reflectivity, closed forms (total reflection, critical angle, Debye–Waller).

use num_complex::Complex64;
use traxer::xray::coating::depth_graded_thicknesses;
use traxer::xray::parratt::{reflectance, Layer};
use traxer::xray::CoatingLibrary;

fn csv(name: &str) -> Vec<Vec<String>> {
    let path = crate::common::repo().join("tests/data").join(name);
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

#[test]
fn depth_graded_thicknesses_match_the_recipe_table() {
    // LLNL recipe 3 (SPEC §4, the issue): 16.0, 9.7778, 7.04, 5.5 nm.
    let d = depth_graded_thicknesses(5.5, 16.0, 1.0, 4).unwrap();
    for (got, want) in d.iter().zip([16.0, 9.7778, 7.04, 5.5]) {
        assert!((got - want).abs() < 1e-4, "{d:?}");
    }
    // Every recipe starts at d_max and ends at d_min, decreasing.
    for (dmin, dmax, n) in [(11.5, 22.5, 2), (7.0, 19.0, 3), (5.0, 14.0, 5)] {
        let d = depth_graded_thicknesses(dmin, dmax, 1.0, n).unwrap();
        assert!((d[0] - dmax).abs() < 1e-12 && (d[n as usize - 1] - dmin).abs() < 1e-12);
        assert!(d.windows(2).all(|w| w[0] > w[1]));
    }
    // The shipped recipe 3 is built from exactly these layers: C 0.4·d, Pt 0.6·d.
    let c = CoatingLibrary::shipped().coating("llnl_recipe_3").unwrap();
    assert_eq!(c.stack.layers.len(), 8);
    assert!(
        (c.stack.layers[0].thickness_nm - 6.4).abs() < 1e-12
            && c.stack.layers[0].material.name == "C"
    );
    assert!(
        (c.stack.layers[1].thickness_nm - 9.6).abs() < 1e-12
            && c.stack.layers[1].material.name == "Pt"
    );
}

#[test]
fn optical_constants_agree_with_periodictable() {
    let lib = CoatingLibrary::shipped();
    let mut worst: f64 = 0.0;
    for row in csv("reference_optical_constants.csv") {
        let m = lib.material(&row[0]).unwrap();
        let e: f64 = row[1].parse().unwrap();
        let (d, b) = m.delta_beta(e).unwrap();
        let (rd, rb): (f64, f64) = (row[2].parse().unwrap(), row[3].parse().unwrap());
        let diff = (d / rd - 1.0).abs().max((b / rb - 1.0).abs());
        if diff > 1e-5 {
            eprintln!("{} {e} keV: δ {d:e} vs {rd:e}, β {b:e} vs {rb:e}", row[0]);
        }
        worst = worst.max(diff);
    }
    // Same tables and interpolation; the constants (r_e, N_A, hc) differ in the
    // last digits.
    eprintln!("worst relative δ, β difference to periodictable: {worst:e}");
    assert!(worst < 1e-6, "worst relative difference {worst}");
}

#[test]
fn multilayer_reflectivity_agrees_with_xraydb() {
    let lib = CoatingLibrary::shipped();
    let mut worst: f64 = 0.0;
    let mut n = 0;
    for row in csv("reference_reflectivity.csv") {
        let c = lib.coating(&row[0]).unwrap();
        let (e, t): (f64, f64) = (row[1].parse().unwrap(), row[2].parse().unwrap());
        let r = c.reflectance(e, t.to_radians()).unwrap().s;
        let want: f64 = row[3].parse().unwrap();
        if (r - want).abs() > 1e-5 {
            eprintln!("{} {e} keV {t}°: R_s {r} vs {want}", row[0]);
        }
        worst = worst.max((r - want).abs());
        n += 1;
    }
    assert_eq!(n, 1200);
    eprintln!("worst |R_s - xraydb|: {worst:e}");
    assert!(worst < 1e-6, "worst absolute difference in R_s: {worst}");
}

#[test]
fn gold_critical_angle_and_the_small_angle_limit() {
    let lib = CoatingLibrary::shipped();
    let au = lib.coating("bare_gold").unwrap();
    let gold = lib.material("Au").unwrap();
    // Literature: the critical angle of gold at Cu Kα (8.05 keV) is ≈ 0.55°; with
    // θ_c = √(2δ) it scales as 1/E away from edges.
    let (delta, _) = gold.delta_beta(8.048).unwrap();
    let theta_c = (2.0 * delta).sqrt().to_degrees();
    assert!((theta_c - 0.55).abs() < 0.02, "θ_c(8.05 keV) = {theta_c}°");
    for e in [2.0, 4.51, 8.048, 15.0] {
        let (delta, _) = gold.delta_beta(e).unwrap();
        let tc = (2.0 * delta).sqrt();
        // Below θ_c nearly total reflection, above it the reflectivity collapses.
        let below = au.reflectivity(e, 0.7 * tc).unwrap();
        let above = au.reflectivity(e, 1.5 * tc).unwrap();
        assert!(
            below > 0.6 && above < 0.1,
            "{e} keV: R(0.7θc) = {below}, R(1.5θc) = {above}"
        );
        // R → 1 as θ → 0.
        assert!(au.reflectivity(e, 1e-3 * tc).unwrap() > 0.99);
    }
    for name in [
        "llnl_recipe_1",
        "llnl_recipe_2",
        "llnl_recipe_3",
        "llnl_recipe_4",
        "gold",
    ] {
        let c = lib.coating(name).unwrap();
        for e in [0.5, 1.49, 6.41, 10.0] {
            let r = c.reflectivity(e, 1e-5).unwrap();
            assert!(r > 0.99 && r <= 1.0, "{name} {e} keV: R(θ→0) = {r}");
        }
    }
}

#[test]
fn fresnel_closed_forms() {
    // Lossless interface: total external reflection below θ_c, and above it the
    // plain Fresnel formula r = (sinθ − √(n² − cos²θ)) / (sinθ + √(…)).
    let n = Complex64::new(-1e-5, 0.0); // χ = n − 1
    let tc = (2e-5f64).sqrt();
    let r = reflectance(5.0, 0.5 * tc, &[], n, 0.0);
    assert!((r.s - 1.0).abs() < 1e-12 && (r.p - 1.0).abs() < 1e-12);
    let th = 2.0 * tc;
    let nn = n + 1.0;
    let q = (nn * nn - th.cos().powi(2)).sqrt();
    let rs = ((th.sin() - q) / (th.sin() + q)).norm_sqr();
    // (the reference formula itself loses ~1e-11 to the cancellation in n² − cos²θ)
    assert!((reflectance(5.0, th, &[], n, 0.0).s / rs - 1.0).abs() < 1e-9);
    // A layer of vacuum changes nothing.
    let vac = Layer {
        chi: Complex64::new(0.0, 0.0),
        thickness_nm: 37.0,
        roughness_nm: 0.0,
    };
    assert!(
        (reflectance(5.0, th, &[vac], n, 0.0).s / reflectance(5.0, th, &[], n, 0.0).s - 1.0).abs()
            < 1e-12
    );
    // Névot–Croce far above θ_c reduces to the Debye–Waller factor
    // exp(−(4π sinθ σ / λ)²).
    let pt = CoatingLibrary::shipped().material("Pt").unwrap();
    let (d, b) = pt.delta_beta(8.0).unwrap();
    let npt = Complex64::new(-d, b);
    let th = 8.0 * (2.0 * d).sqrt();
    let sigma = 0.12;
    let lambda = 1.239_841_984_332 / 8.0;
    let dw = (-(4.0 * std::f64::consts::PI * th.sin() * sigma / lambda).powi(2)).exp();
    let ratio = reflectance(8.0, th, &[], npt, sigma).s / reflectance(8.0, th, &[], npt, 0.0).s;
    assert!(
        (ratio / dw - 1.0).abs() < 0.03,
        "Névot–Croce {ratio} vs Debye–Waller {dw}"
    );
}

#[test]
fn energies_outside_the_tables_are_errors() {
    let lib = CoatingLibrary::shipped();
    let c = lib.coating("llnl_recipe_1").unwrap();
    assert!(c.reflectivity(0.01, 0.01).is_err());
    assert!(c.reflectivity(31.0, 0.01).is_err());
    assert!(c.reflectivity(30.0, 0.01).is_ok());
    assert!(lib
        .coating("nope")
        .unwrap_err()
        .to_string()
        .contains("unknown coating"));
    assert!(traxer::xray::compound::parse_formula("SiO2x").is_err());
    assert!(traxer::xray::compound::parse_formula("Xx2")
        .unwrap_err()
        .to_string()
        .contains("unknown element"));
    let f = traxer::xray::compound::parse_formula("Ca(OH)2").unwrap();
    assert_eq!(f["Ca"], 1.0);
    assert_eq!(f["O"], 2.0);
    assert_eq!(f["H"], 2.0);
}

#[test]
fn reflectivity_tables_interpolate_within_1e_4() {
    // The tables' promise (src/xray/table_grid.rs): |R_table − R_exact| ≤ 1e-4
    // anywhere in the table. Checked on the shipped mirror coatings over the
    // Sun's band as the scenes build them (0.1–15 keV, grazing angles 0–4°) at
    // random points, absorption edges included (Pt and Au M edges, O K, Si K,
    // C K: the nodes sit on the optical constants' own). Also: the gold table
    // is sized to the coating (a few MB, where a fixed rule for its 250 nm took
    // 470 MB).
    use crate::geometry::Lcg;
    let lib = CoatingLibrary::shipped();
    let mut rng = Lcg(99);
    let theta_max = 4f64.to_radians();
    for name in [
        "xmm_gold",
        "llnl_recipe_1",
        "llnl_recipe_2",
        "llnl_recipe_3",
        "llnl_recipe_4",
        "gold",
    ] {
        let c = lib.coating(name).unwrap();
        let t = traxer::xray::ReflectivityTable::new(&c, 0.1, 15.0, theta_max).unwrap();
        let mut worst: (f64, f64, f64) = (0.0, 0.0, 0.0);
        for _ in 0..20_000 {
            let e = rng.range(0.1, 15.0);
            let th = rng.range(0.0, theta_max);
            let d = (t.reflectivity(e, th) - c.reflectivity(e, th).unwrap()).abs();
            if d > worst.0 {
                worst = (d, e, th.to_degrees());
            }
        }
        let mb = t.len() as f64 * 4e-6;
        eprintln!(
            "{name} 0.1–15 keV, 0–4°: {} energies, {mb:.1} MB, worst |ΔR| = {:.2e} at {} keV, {}°",
            t.energies.len(),
            worst.0,
            worst.1,
            worst.2
        );
        assert!(
            worst.0 <= 1e-4,
            "{name}: worst interpolation error {worst:?}"
        );
        // A table is sized to its coating: 20 MB each at most here (the gold
        // layers' tables, 2–3 MB, were 470 MB on the old grid).
        assert!(mb < 20.0, "{name}: {mb} MB");
    }
}

pub fn coated_flat_mirror_scene(coating: &str, graze_deg: f64, energy: &str, bins: &str) -> String {
    let mirror = format!("type = \"mirror\"\ncoating = \"{coating}\"");
    crate::common::flat_mirror_bench(graze_deg, &mirror, energy, 60, bins, "")
}

#[test]
fn coated_mirror_multiplies_each_photon_by_its_reflectivity() {
    // Every photon meets the flat mirror at the same grazing angle, so the flux on
    // the screen per photon is R(E, θ): effective area = geometric area × R.
    use traxer::trace::{self, RunConfig};
    let lib = CoatingLibrary::shipped();
    for (coating, graze, e) in [
        ("bare_gold", 0.4, 8.0),
        ("llnl_recipe_3", 0.6, 1.49),
        ("llnl_recipe_1", 1.2, 6.41),
    ] {
        let s = crate::common::scene(&coated_flat_mirror_scene(
            coating,
            graze,
            &format!("{{ line = {e} }}"),
            "",
        ));
        let r = trace::run(&s, &RunConfig::new(2000, 1)).unwrap();
        assert_eq!(r.stats.reached_sensor, 2000);
        let per_photon = r.images[0].total_flux() / 2000.0;
        let direct = lib
            .coating(coating)
            .unwrap()
            .reflectivity(e, graze.to_radians())
            .unwrap();
        assert!(
            (per_photon - direct).abs() < 1e-3,
            "{coating}: {per_photon} vs R = {direct}"
        );
        assert!(
            direct < 0.999,
            "{coating}: the test needs R visibly below 1"
        );
    }
}

#[test]
fn sensors_bin_in_energy() {
    use traxer::trace::{self, RunConfig};
    // Uniform 1–9 keV band, 8 bins of 1 keV: counts split evenly; each band's flux
    // is the mean reflectivity over that band.
    let s = crate::common::scene(&coated_flat_mirror_scene(
        "bare_gold",
        0.5,
        "{ band = [1.0, 9.0] }",
        "energy_bins = [1.0, 9.0, 8]",
    ));
    let n = 40_000u64;
    let r = trace::run(&s, &RunConfig::new(n, 4)).unwrap();
    let img = &r.images[0];
    let px = 60 * 60;
    assert_eq!(img.flux().len(), 8 * px);
    let gold = CoatingLibrary::shipped().coating("bare_gold").unwrap();
    for b in 0..8 {
        let counts: u64 = img.counts.to_vec()[b * px..(b + 1) * px].iter().sum();
        let flux: f64 = img.flux()[b * px..(b + 1) * px].iter().sum();
        let expected = n as f64 / 8.0;
        assert!(
            (counts as f64 - expected).abs() < 4.0 * expected.sqrt(),
            "band {b}: {counts}"
        );
        // Mean of R over the band by the midpoint rule (R is smooth here).
        let mean_r: f64 = (0..100)
            .map(|k| {
                gold.reflectivity(
                    1.0 + b as f64 + (k as f64 + 0.5) / 100.0,
                    0.5f64.to_radians(),
                )
                .unwrap()
            })
            .sum::<f64>()
            / 100.0;
        assert!(
            (flux / counts as f64 - mean_r).abs() < 0.01,
            "band {b}: {} vs {mean_r}",
            flux / counts as f64
        );
    }
    // A line outside the bins is not recorded, but counted.
    let s = crate::common::scene(&coated_flat_mirror_scene(
        "bare_gold",
        0.5,
        "{ line = 9.5 }",
        "energy_bins = [1.0, 9.0, 8]",
    ));
    let r = trace::run(&s, &RunConfig::new(100, 4)).unwrap();
    assert_eq!(
        (r.stats.reached_sensor, r.stats.sensor_outside_energy_range),
        (0, 100)
    );
}

#[test]
fn coating_errors_name_the_material_line() {
    let dir = tempfile::tempdir().unwrap();
    let e = crate::common::load_error(
        dir.path(),
        &coated_flat_mirror_scene("llnl_recipe_9", 0.5, "{ line = 1.0 }", ""),
    );
    assert!(
        e.contains("s.toml:7") && e.contains("unknown coating `llnl_recipe_9`"),
        "{e}"
    );
    let e = crate::common::load_error(
        dir.path(),
        &coated_flat_mirror_scene("gold", 0.5, "{ line = 50.0 }", ""),
    );
    assert!(e.contains("outside the Henke tables"), "{e}");
}

#[test]
fn reflectivity_command_prints_csv_and_writes_a_plot() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("r.png");
    let out = crate::common::run_ok(
        crate::common::traxer()
            .args([
                "reflectivity",
                "--coating",
                "llnl_recipe_3",
                "--energy",
                "1.49,6.41",
                "--angle",
                "0:2:0.5",
                "--plot",
            ])
            .arg(&png),
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 2 * 5);
    let c = CoatingLibrary::shipped().coating("llnl_recipe_3").unwrap();
    for r in &rows {
        let want = c.reflectance(r[0], r[1].to_radians()).unwrap();
        assert!((r[2] - want.unpolarised()).abs() < 1e-12 && (r[3] - want.s).abs() < 1e-12);
    }
    let img = image::open(&png).unwrap();
    assert_eq!((img.width(), img.height()), (900, 600));
    // A user coating file, and bad input.
    let file = crate::common::write(
        dir.path(),
        "c.toml",
        "[materials.Ir]\nformula = \"Ir\"\ndensity = 22.56\n[coatings.iridium]\ntype = \"substrate\"\nsubstrate = \"Ir\"\n",
    );
    let out = crate::common::run_ok(
        crate::common::traxer()
            .args(["reflectivity", "--coating"])
            .arg(&file)
            .args(["--energy", "0.5:10:0.5", "--angle", "0.3", "--plot"])
            .arg(&png),
    );
    assert_eq!(
        String::from_utf8(out.stdout).unwrap().lines().count(),
        1 + 20
    );
    for args in [
        ["--coating", "unobtainium", "--energy", "1", "--angle", "1"],
        ["--coating", "gold", "--energy", "40", "--angle", "1"],
        ["--coating", "gold", "--energy", "1:0:1", "--angle", "1"],
    ] {
        let out = crate::common::traxer()
            .arg("reflectivity")
            .args(args)
            .arg("--plot")
            .arg(&png)
            .output()
            .unwrap();
        assert_eq!(
            out.status.code(),
            Some(2),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

#[test]
fn scene_defined_optical_materials_and_coatings_work() {
    // The example of docs/scene-format.md: a user material (mass fractions) and an
    // iridium layer on it; the traced flux per photon equals the direct R.
    use traxer::trace::{self, RunConfig};
    let extra = r#"
[optical_materials.Ir]
formula = "Ir"
density = 22.56

[optical_materials.glass]
mass_fractions = { SiO2 = 0.8, B2O3 = 0.13, Na2O = 0.04, Al2O3 = 0.03 }
density = 2.23

[coatings.iridium]
type = "layers"
layers = [ { material = "Ir", thickness_nm = 30.0, roughness_nm = 0.4 } ]
substrate = "glass"
substrate_roughness_nm = 0.4
"#;
    let text = format!(
        "{extra}\n{}",
        coated_flat_mirror_scene("iridium", 0.5, "{ line = 8.0 }", "")
    );
    let s = crate::common::scene(&text);
    let r = trace::run(&s, &RunConfig::new(500, 1)).unwrap();
    let lib: CoatingLibrary =
        toml::from_str(extra.replace("optical_materials", "materials").as_str()).unwrap();
    let direct = CoatingLibrary::shipped()
        .merged(&lib)
        .coating("iridium")
        .unwrap()
        .reflectivity(8.0, 0.5f64.to_radians())
        .unwrap();
    let per_photon = r.images[0].total_flux() / 500.0;
    assert!(
        (per_photon - direct).abs() < 1e-3 && direct > 0.3 && direct < 0.99,
        "{per_photon} vs {direct}"
    );
}

/// A material of the shipped library on the table `constants`, through a
/// one-layer coating of it (the library's only way to pick the table).
fn on_table(formula: &str, density: f64, constants: &str) -> traxer::xray::OpticalMaterial {
    let text = format!(
        "[materials.m]\nformula = \"{formula}\"\ndensity = {density}\n[coatings.c]\ntype = \"substrate\"\nsubstrate = \"m\"\n"
    );
    let mut lib: CoatingLibrary = toml::from_str(&text).unwrap();
    lib.mirror_constants = traxer::xray::elements::OpticalConstants::parse(constants).unwrap();
    lib.coating("c").unwrap().stack.substrate
}

#[test]
fn chantlers_table_agrees_with_henkes_where_both_are_sound() {
    // Two independent compilations (Henke/CXRO 1993, Chantler/NIST FFAST 2000)
    // of the same physics: away from absorption edges, where their models
    // differ most, δ of the mirror materials agrees within 3 % and β within
    // 15 % (their photoabsorption differs by up to ~10 %, gold at 6 keV).
    // A wrong convention (f1 without Z, f2 in other units, a shifted grid)
    // would miss by far more. Between 2 and 10 keV, clear of the edges of
    // these elements (Pt, Au M edges 2.1–3.4 keV, L edges 11.5–14.4 keV;
    // Ni K 8.33 keV).
    for (formula, density, energies) in [
        ("Au", 19.32, &[4.0, 6.0, 8.0, 10.0][..]),
        ("Pt", 21.41, &[4.0, 6.0, 8.0, 10.0][..]),
        ("Ni", 8.908, &[2.0, 4.0, 6.0, 7.5][..]),
        ("C", 2.26, &[2.0, 4.0, 8.0][..]),
        ("SiO2", 2.65, &[2.5, 4.0, 8.0][..]),
    ] {
        let (h, c) = (
            on_table(formula, density, "henke"),
            on_table(formula, density, "chantler"),
        );
        for &e in energies {
            let ((dh, bh), (dc, bc)) = (h.delta_beta(e).unwrap(), c.delta_beta(e).unwrap());
            assert!(
                (dc / dh - 1.0).abs() < 0.03 && (bc / bh - 1.0).abs() < 0.15,
                "{formula} {e} keV: δ {dh:e} (Henke) vs {dc:e} (Chantler), β {bh:e} vs {bc:e}"
            );
        }
    }
    // Both tables put gold's L3 edge at 11.92 keV (β more than doubles there).
    for table in ["henke", "chantler"] {
        let au = on_table("Au", 19.32, table);
        let (below, above) = (
            au.delta_beta(11.85).unwrap().1,
            au.delta_beta(11.99).unwrap().1,
        );
        assert!(above > 2.0 * below, "{table}: β {below:e} → {above:e}");
    }
}

#[test]
fn a_scene_picks_the_mirrors_table_and_a_wrong_name_is_refused() {
    // A flat gold mirror at 0.5°, 8 keV: each photon's weight is R, so the
    // flux per photon on each table is that table's R from the direct Parratt
    // sum (independent of the trace), and the two differ.
    use traxer::trace::{self, RunConfig};
    let scene = |table: &str| {
        format!(
            "mirror_optical_constants = \"{table}\"\n{}",
            coated_flat_mirror_scene("bare_gold", 0.5, "{ line = 8.0 }", "")
        )
    };
    let mut flux = Vec::new();
    for table in ["henke", "chantler"] {
        let s = crate::common::scene(&scene(table));
        let r = trace::run(&s, &RunConfig::new(1000, 1)).unwrap();
        let per_photon = r.images[0].total_flux() / 1000.0;
        let mut lib = CoatingLibrary::shipped();
        lib.mirror_constants = traxer::xray::elements::OpticalConstants::parse(table).unwrap();
        let direct = lib
            .coating("bare_gold")
            .unwrap()
            .reflectivity(8.0, 0.5f64.to_radians())
            .unwrap();
        assert!(
            (per_photon - direct).abs() < 1e-3,
            "{table}: {per_photon} vs R = {direct}"
        );
        flux.push(per_photon);
    }
    assert!(
        (flux[1] / flux[0] - 1.0).abs() > 1e-3,
        "the tables must give different R: {flux:?}"
    );
    let dir = tempfile::tempdir().unwrap();
    let path = crate::common::write(dir.path(), "bad.toml", &scene("cromer"));
    let err = crate::common::run_fails(
        crate::common::traxer()
            .arg("trace")
            .arg(&path)
            .args(["-n", "10", "-o"])
            .arg(dir.path().join("o")),
        2,
    );
    assert!(
        err.contains("mirror_optical_constants")
            && err.contains("chantler")
            && err.contains("bad.toml"),
        "{err}"
    );
}
