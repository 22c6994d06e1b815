//! Mirror microroughness scatter (src/xray/roughness.rs) through the photon loop,
//! on the flat-mirror bench (a pencil beam at grazing angle θ on a flat mirror, a
//! screen 200 mm below): the scattered share of the flux beyond a few pixels of
//! the specular direction (from each photon's direction) against the first-order formula in closed form (a power-law
//! PSD P = k f^-1.5, where ∫√(1 ± a f) f^-1.5 df is elementary) at two energies;
//! the mirror's reflected power conserved (specular + scattered = R); a meshed
//! and an analytic mirror agree; a scene without roughness draws nothing extra.

use traxer::trace::{self, RunConfig};

const K: f64 = 0.02;
const BAND: [f64; 2] = [1e-3, 1.0];
const HC_KEV_UM: f64 = 1.239_841_984_332_002_6e-3;

/// ∫ √(1 + s a f) W(f) df over [f1, f2] with W = k f^-1.5 / 2 (s = ±1).
fn branch(a: f64, s: f64, f1: f64, f2: f64) -> f64 {
    if f2 <= f1 {
        return 0.0;
    }
    let prim = |f: f64| {
        let t = f.sqrt();
        let g = (1.0 + s * a * t * t).max(0.0).sqrt();
        if s > 0.0 {
            2.0 * (-g / t + a.sqrt() * (a.sqrt() * t).asinh())
        } else {
            2.0 * (-g / t - a.sqrt() * (a.sqrt() * t).min(1.0).asin())
        }
    };
    0.5 * K * (prim(f2) - prim(f1))
}

fn bench(graze_deg: f64, mirror: &str, energy_kev: f64, shape: Option<&str>) -> String {
    let text = crate::common::flat_mirror_bench(
        graze_deg,
        mirror,
        &format!("{{ line = {energy_kev} }}"),
        600,
        "",
        "",
    );
    match shape {
        None => text,
        Some(s) => text.replace(
            "shape = { type = \"rectangle\", size = [20.0, 100.0] }",
            &format!("shape = {s}"),
        ),
    }
}

const ROUGH: &str = "type = \"mirror\"\nroughness = { psd = { type = \"power_law\", k = 0.02, n = 1.5 }, band_per_um = [1e-3, 1.0] }";

/// The photons' weights by the grazing angle θs they left the mirror at, from
/// their directions (the angle from −z is θ + θs): (total weight, weight with
/// |θs − θ| > δ).
fn far_share(scene: &traxer::scene::Scene, graze: f64, delta: f64, photons: u64) -> (f64, f64) {
    let cfg = RunConfig {
        photon_list: photons as usize,
        ..RunConfig::new(photons, 5)
    };
    let r = trace::run(scene, &cfg).unwrap();
    let (mut total, mut far) = (0.0, 0.0);
    for p in &r.photons {
        let theta_s = (-p.dir.z).clamp(-1.0, 1.0).acos() - graze;
        total += p.record.weight;
        if (theta_s - graze).abs() > delta {
            far += p.record.weight;
        }
    }
    (total, far)
}

#[test]
fn a_rough_flat_mirror_scatters_as_its_psd_says_at_two_energies() {
    let graze = 0.5f64.to_radians();
    // 4 pixels from the specular direction: |θs − θ| > 2 mrad.
    let delta = 4.0 * 0.1 / 200.0;
    let photons = 400_000u64;
    for e in [1.0, 8.0] {
        let s = crate::common::scene(&bench(0.5, ROUGH, e, None));
        let (total, far) = far_share(&s, graze, delta, photons);
        // A perfect coating: every photon reaches the screen, scattered or not.
        assert_eq!(total, photons as f64, "{e} keV: power lost or made");
        let lambda = HC_KEV_UM / e;
        let a = 2.0 * lambda / (graze * graze);
        let j = branch(a, 1.0, BAND[0], BAND[1]) + branch(a, -1.0, BAND[0], BAND[1].min(1.0 / a));
        let tis = (4.0 * std::f64::consts::PI * graze / (lambda * 1e3)).powi(2) * j;
        // Forward beyond θ + δ, backward below θ − δ, in frequency.
        let f_fwd = ((graze + delta).powi(2) - graze * graze) / (2.0 * lambda);
        let f_bwd = (graze * graze - (graze - delta).powi(2)) / (2.0 * lambda);
        let j_far = branch(a, 1.0, f_fwd.max(BAND[0]), BAND[1])
            + branch(a, -1.0, f_bwd.max(BAND[0]), BAND[1].min(1.0 / a));
        let p = (1.0 - (-tis).exp()) * j_far / j;
        let got = far / photons as f64;
        let sd = (p * (1.0 - p) / photons as f64).sqrt();
        eprintln!("{e} keV: beyond 2 mrad {got:.5} traced, {p:.5} expected; TIS {tis:.5}");
        // 5σ, and 0.5 % for the tables' interpolation.
        assert!(
            (got - p).abs() < 5.0 * sd + 0.005 * p,
            "{e} keV: {got:.5} of the flux beyond 2 mrad, expected {p:.5} (TIS {tis:.4})"
        );
        assert!(p > 0.002, "{e} keV: the test needs scatter to see ({p})");
    }
}

#[test]
fn scattered_and_specular_add_up_to_the_coatings_reflectivity() {
    let graze = 0.5;
    let with = |m: &str| {
        let s = crate::common::scene(&bench(graze, m, 3.0, None));
        trace::run(&s, &RunConfig::new(100_000, 2)).unwrap().images[0].total_flux()
    };
    let smooth = with("type = \"mirror\"\ncoating = \"gold\"");
    let rough = with(&format!("{ROUGH}\ncoating = \"gold\""));
    // Every photon carries R(E, θ) of the gold at its one reflection, wherever
    // the roughness sends it: the totals agree to round-off.
    assert!((rough / smooth - 1.0).abs() < 1e-12, "{rough} vs {smooth}");
    assert!(smooth < 100_000.0 * 0.99);
}

#[test]
fn meshed_and_analytic_rough_mirrors_agree() {
    let dir = tempfile::tempdir().unwrap();
    // The 20 × 100 mm rectangle as two triangles, counter-clockwise seen from +z.
    std::fs::write(
        dir.path().join("flat.obj"),
        "v -10 -50 0\nv 10 -50 0\nv 10 50 0\nv -10 50 0\nf 1 2 3\nf 1 3 4\n",
    )
    .unwrap();
    let graze = 0.5f64.to_radians();
    let delta = 2.0 * 0.1 / 200.0;
    let analytic = crate::common::scene(&bench(0.5, ROUGH, 1.5, None));
    let meshed = crate::common::scene_in(
        dir.path(),
        &bench(
            0.5,
            ROUGH,
            1.5,
            Some("{ type = \"mesh\", file = \"flat.obj\" }"),
        ),
    );
    let (ta, fa) = far_share(&analytic, graze, delta, 200_000);
    let (tm, fm) = far_share(&meshed, graze, delta, 200_000);
    assert_eq!(ta, tm);
    // The same photons, the same random numbers: the shares agree to a few
    // photons (hit points differ in the last bits between the two shapes).
    assert!((fa - fm).abs() <= 20.0, "analytic {fa}, meshed {fm}");
    assert!(fa > 1000.0);
}

#[test]
fn effective_area_refuses_rough_mirrors_for_now() {
    let s = crate::common::scene(&bench(0.5, ROUGH, 1.5, None));
    let sweep = traxer::studies::effective_area::AreaSweep {
        energies: vec![1.0, 2.0],
        angles_arcmin: vec![0.0],
        photons: 1000,
        seed: 1,
        threads: 1,
        sensor: None,
        radius_mm: None,
    };
    let e = traxer::studies::effective_area::sweep(&s, &sweep, &[], &(), |_| {}).unwrap_err();
    assert!(e.to_string().contains("roughness"), "{e}");
}
