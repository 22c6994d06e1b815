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

/// The effective-area sweep traces a rough mirror at each energy on its own:
/// the area within 0.3 mm of the image centre on the screen 200 mm below (a
/// scattered photon lands 200·|θs − θ| from the specular spot, so it counts
/// within δ = 1.5 mrad) over the smooth mirror's, which is R(E, θ) for both,
/// against e^−TIS + (1 − e^−TIS)·(share of the scattered within δ) in closed
/// form, at 1 and 8 keV in one sweep (one path per photon for every energy
/// would give both energies the same ratio). Tolerance: 5 standard errors of
/// the sweep, and 1 % for the beam's 10 µm radius blurring the edge at δ and
/// the counting centre moved by the one-sided scatter.
#[test]
fn effective_area_traces_rough_mirrors_at_each_energy() {
    let graze = 0.5f64.to_radians();
    let sweep = |m: &str| {
        let text = bench(0.5, m, 1.5, None).replace("radius = 0.2", "radius = 0.01");
        let s = crate::common::scene(&text);
        let sweep = traxer::studies::effective_area::AreaSweep {
            energies: vec![1.0, 8.0],
            angles_arcmin: vec![0.0],
            sampling: traxer::studies::Sampling {
                photons: 200_000,
                seed: 1,
                threads: 0,
                sensor: None,
            },
            radius_mm: Some(0.3),
        };
        traxer::studies::effective_area::sweep(&s, &sweep, &[], &(), |_, _| {})
            .unwrap()
            .angles
            .remove(0)
            .points
    };
    let smooth = sweep("type = \"mirror\"\ncoating = \"gold\"");
    let rough = sweep(&format!("{ROUGH}\ncoating = \"gold\""));
    let delta = 0.3 / 200.0;
    let mut ratios = Vec::new();
    for (s, r) in smooth.iter().zip(&rough) {
        let e = s.energy_kev;
        let lambda = HC_KEV_UM / e;
        let a = 2.0 * lambda / (graze * graze);
        let top = BAND[1].min(1.0 / a);
        let j = branch(a, 1.0, BAND[0], BAND[1]) + branch(a, -1.0, BAND[0], top);
        let tis = (4.0 * std::f64::consts::PI * graze / (lambda * 1e3)).powi(2) * j;
        let f_fwd = ((graze + delta).powi(2) - graze * graze) / (2.0 * lambda);
        let f_bwd = (graze * graze - (graze - delta).powi(2)) / (2.0 * lambda);
        let j_far =
            branch(a, 1.0, f_fwd.max(BAND[0]), BAND[1]) + branch(a, -1.0, f_bwd.max(BAND[0]), top);
        let expect = (-tis).exp() + (1.0 - (-tis).exp()) * (1.0 - j_far / j);
        let got = r.area_cm2 / s.area_cm2;
        let sd = r.error_cm2 / s.area_cm2;
        eprintln!("{e} keV: rough/smooth {got:.5} ± {sd:.5}, expected {expect:.5} (TIS {tis:.4})");
        assert!(
            (got - expect).abs() < 5.0 * sd + 0.01 * (1.0 - expect),
            "{e} keV: rough/smooth area {got:.5} ± {sd:.5}, expected {expect:.5}"
        );
        ratios.push(got);
    }
    // The test sees the energy dependence: 8 keV loses several times 1 keV's share.
    assert!(1.0 - ratios[1] > 3.0 * (1.0 - ratios[0]), "{ratios:?}");
}

/// `roughness = "none"` is the smooth mirror (the same image bit for bit: no
/// draws are made), and the LLNL scenes switch the scatter with their
/// `roughness` variable; an unknown name is refused naming the value.
#[test]
fn roughness_none_is_smooth_and_a_variable_switches_it() {
    let smooth = crate::common::scene(&bench(0.5, "type = \"mirror\"", 3.0, None));
    let none = crate::common::scene(&bench(
        0.5,
        "type = \"mirror\"\nroughness = \"none\"",
        3.0,
        None,
    ));
    let cfg = RunConfig::new(20_000, 4);
    let a = trace::run(&smooth, &cfg).unwrap();
    let b = trace::run(&none, &cfg).unwrap();
    assert_eq!(a.images[0].flux(), b.images[0].flux());
    assert!(none.roughness.is_empty());

    let dir = tempfile::tempdir().unwrap();
    let p = crate::common::write(
        dir.path(),
        "s.toml",
        &bench(0.5, "type = \"mirror\"\nroughness = \"smooth\"", 3.0, None),
    );
    let Err(e) = traxer::scene::Scene::load(&crate::common::device(), &p, &[]) else {
        panic!("an unknown roughness name should be refused")
    };
    let msg = e.to_string();
    assert!(
        msg.contains("unknown roughness `smooth`") && msg.contains("\"none\""),
        "{msg}"
    );

    let scene = crate::common::repo().join("scenes/panter_al_ka.toml");
    let rough = "roughness={ psd = { type = \"power_law\", k = 0.02, n = 1.5 }, band_per_um = [1e-3, 1.0] }";
    let s = traxer::scene::Scene::load(&crate::common::device(), &scene, &[rough.into()]).unwrap();
    assert_eq!(s.roughness.len(), 1);
    assert_eq!(s.roughness[0].desc.band_per_um, [1e-3, 1.0]);
    let s = traxer::scene::Scene::load(&crate::common::device(), &scene, &[]).unwrap();
    assert!(
        s.roughness.is_empty(),
        "the shipped PANTER scene is smooth by default"
    );
    // The combined model: the roughness preset (σ = 0.5 nm) with its figure errors.
    let combined = [
        "roughness=slumped_glass_limit".to_string(),
        "figure_error=llnl_panter_rough".to_string(),
    ];
    let s = traxer::scene::Scene::load(&crate::common::device(), &scene, &combined).unwrap();
    assert_eq!(s.roughness.len(), 1);
    assert!((s.roughness[0].sigma2_nm2.sqrt() - 0.5).abs() < 1e-4);
}
