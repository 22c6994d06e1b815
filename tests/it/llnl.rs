//! The LLNL telescope built from data/telescopes/llnl.toml: the construction checks
//! of SPEC §2 (cone angles, virtual radius, Wolter equation) and a ray through the
//! middle of each shell.

use glam::DVec3;
use traxer::raycast::{intersect, reflect};
use traxer::scene::telescope::Telescope;

fn llnl() -> Telescope {
    Telescope::shipped("llnl").unwrap()
}

#[test]
fn cone_angles_radii_and_focal_length_follow_from_the_data() {
    let t = llnl();
    t.validate().unwrap();
    assert_eq!(t.shells.len(), 13);
    let deg = |x: f64| x.to_degrees();
    // SPEC §2: α runs 0.5924° … 0.9581°, α_rear 1.7780° … 2.8778° (≈ 3α).
    assert!((deg(t.alpha(0)) - 0.5924).abs() < 1e-4 && (deg(t.alpha(12)) - 0.9581).abs() < 1e-4);
    assert!(
        (deg(t.alpha_rear(0)) - 1.7780).abs() < 1e-4
            && (deg(t.alpha_rear(12)) - 2.8778).abs() < 1e-4
    );
    let l = t.mirror_length_mm;
    for i in 0..t.shells.len() {
        let [r1, r2, _, _] = t.cone_radii(i);
        let a = t.alpha(i);
        assert!(
            (t.alpha_rear(i) / a - 3.0).abs() < 0.005,
            "shell {}: α_rear/α = {}",
            i + 1,
            t.alpha_rear(i) / a
        );
        // Virtual radius R3 = R2 − (x_sep/2) tan α: 60.891 … 98.585 mm.
        let r3 = r2 - 0.5 * t.gap_mm * a.tan();
        if i == 0 {
            assert!((r3 - 60.891).abs() < 1e-3);
        }
        if i == 12 {
            assert!((r3 - 98.585).abs() < 1e-3);
        }
        // Wolter equation tan(4α) = R/f: ≈ 1500.1 mm with the front mirror's
        // mid-length radius, ≈ 1471.5 mm with R3.
        let f_mid = (r1 - 0.5 * l * a.sin()) / (4.0 * a).tan();
        let f_r3 = r3 / (4.0 * a).tan();
        assert!((f_mid - 1500.1).abs() < 0.6, "shell {}: f = {f_mid}", i + 1);
        assert!(
            (f_r3 - 1471.5).abs() < 0.6,
            "shell {}: f(R3) = {f_r3}",
            i + 1
        );
    }
    // Every shell names a shipped coating, as SPEC §2 maps them.
    let lib = traxer::xray::CoatingLibrary::shipped();
    let recipes: Vec<&str> = (0..13).map(|i| t.coating(i)).collect();
    assert_eq!(recipes[..3], ["llnl_recipe_1"; 3]);
    assert_eq!(recipes[3..7], ["llnl_recipe_2"; 4]);
    assert_eq!(recipes[7..11], ["llnl_recipe_3"; 4]);
    assert_eq!(recipes[11..], ["llnl_recipe_4"; 2]);
    for r in recipes {
        lib.coating(r).unwrap();
    }
}

/// The LLNL telescope (perfect coating; `extra` lines in its table) in a wide
/// parallel beam.
fn telescope_in_a_beam(extra: &str) -> traxer::scene::Scene {
    crate::common::scene(&format!(
        r#"
[[sources]]
type = "parallel"
aperture = {{ center = [0, 0, 300], radius = 110.0 }}
energy = {{ line = 1.49 }}

[[assemblies]]
type = "llnl_telescope"
coating = "perfect"
{extra}
"#
    ))
}

/// An axial ray (travelling −z) from `o` through shell i (0-based): it must meet
/// front_{i+1} at grazing angle α, then rear_{i+1}; returns the rear hit point and
/// the direction leaving it.
fn through_shell(
    scene: &traxer::scene::Scene,
    t: &Telescope,
    i: usize,
    o: DVec3,
) -> (traxer::raycast::SurfaceHit, DVec3) {
    let d = DVec3::NEG_Z;
    let h1 = intersect(scene, o, d, None).expect("front mirror");
    assert_eq!(
        scene.objects[h1.object].name,
        format!("llnl_front_{}", i + 1)
    );
    // Grazing angle at the front mirror = α.
    assert!((d.dot(h1.shading_normal).abs().asin() - t.alpha(i)).abs() < 1e-9);
    let d1 = reflect(d, h1.shading_normal);
    let h2 = intersect(scene, h1.point, d1, Some(&h1)).expect("rear mirror");
    assert_eq!(
        scene.objects[h2.object].name,
        format!("llnl_rear_{}", i + 1)
    );
    let d2 = reflect(d1, h2.shading_normal);
    (h2, d2)
}

#[test]
fn a_ray_through_the_middle_of_each_front_shell_reaches_the_axis_near_the_focus() {
    let scene = telescope_in_a_beam("");
    let t = llnl();
    for i in 0..t.shells.len() {
        // Axial ray at the radius of the front mirror's middle, in the segment's
        // centre (azimuth 0).
        let a = t.alpha(i);
        let r_mid = t.cone_radii(i)[0] - 0.5 * t.mirror_length_mm * a.sin();
        let (h2, d2) = through_shell(&scene, &t, i, DVec3::new(r_mid, 0.0, 400.0));
        assert!(
            intersect(&scene, h2.point, d2, Some(&h2)).is_none(),
            "shell {}: nothing else in the way",
            i + 1
        );
        // Where it crosses the axis (x = 0).
        let z = h2.point.z - h2.point.x / d2.x * d2.z;
        // The as-built radii are not an exact design: the rays cross between
        // −1497.1 and −1500.8 mm. A misplaced cone would miss by tens of mm.
        assert!(
            (z + 1500.1).abs() < 3.5,
            "shell {}: crosses the axis at z = {z}",
            i + 1
        );
    }
}

#[test]
fn panter_best_focus_is_where_panter_measured_it() {
    let out_dir = tempfile::tempdir().unwrap();
    // Perfect mirrors (the focus is geometric; coatings only reweight the shells),
    // 13 positions over ±60 mm, the same 300 000 photons at each.
    crate::common::run_ok(
        crate::common::traxer()
            .arg("focus")
            .arg(crate::common::repo().join("scenes/panter_al_ka.toml"))
            .args(["--from=-1460", "--to=-1580", "--steps=13", "-n", "300000"])
            .args([
                "-D",
                "coating=perfect",
                "-D",
                "figure_error=none",
                "-q",
                "-o",
            ])
            .arg(out_dir.path()),
    );
    let fit: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out_dir.path().join("focus.json")).unwrap()).unwrap();
    let z0 = fit["fit_hpd"]["z0"].as_f64().expect("an HPD fit");
    // The whole image lands on the 14 mm sensor at every position.
    assert_eq!(fit["clipped_positions"].as_array().map(Vec::len), Some(0));
    // PANTER measured the best focus 1519 mm behind the centre plane (SPEC §3);
    // the issue asks for ±2 mm.
    assert!((z0 + 1519.0).abs() <= 2.0, "best focus at {z0} mm");
    // Independently, the thin-lens image distance f·D/(D − f) of a source at
    // D = 130 297 mm with the Wolter-equation f = 1500.1 mm is 1517.57 mm; the cone
    // approximation may shift the best HPD by a fraction of a mm, not more.
    let (f, d) = (1500.1, 130_297.0);
    assert!((z0 + f * d / (d - f)).abs() < 1.0, "best focus at {z0} mm");
    // All three diameters agree on the focus.
    for k in ["fit_d80", "fit_d90"] {
        let z = fit[k]["z0"].as_f64().unwrap();
        assert!((z - z0).abs() < 1.0, "{k}: {z} vs {z0}");
    }
}

#[test]
fn focus_sweep_that_misses_the_focus_says_so() {
    let out_dir = tempfile::tempdir().unwrap();
    let scene = crate::common::repo().join("scenes/panter_al_ka.toml");
    let err = crate::common::run_fails(
        crate::common::traxer()
            .arg("focus")
            .arg(&scene)
            .args(["--from=-1380", "--to=-1440", "--steps=5", "-n", "20000"])
            .args(["-D", "coating=perfect", "-q", "-o"])
            .arg(out_dir.path()),
        1,
    );
    // (Either the curve has no minimum there or it lies outside: both say
    // to move or widen the range.)
    assert!(err.contains("range"), "{err}");
    // The measurements are still written.
    assert!(out_dir.path().join("focus.csv").is_file());
    // An unknown variable is a usage error.
    let err = crate::common::run_fails(
        crate::common::traxer()
            .arg("focus")
            .arg(&scene)
            .args(["--var", "nosuch", "--from=0", "--to=1", "-o"])
            .arg(out_dir.path()),
        2,
    );
    assert!(err.contains("nosuch"), "{err}");
}

#[test]
fn traxer_placement_moves_each_shell_axis_outwards_by_half_the_front_height_difference() {
    // Segments centred on azimuth 90°: the axes move along +y.
    let scene = telescope_in_a_beam("azimuth_center = 90.0\nshell_axes = \"traxer\"");
    let t = llnl();
    let (d_first, d_last) = (
        t.cone_radii(0)[0] - t.cone_radii(0)[1],
        t.cone_radii(12)[0] - t.cone_radii(12)[1],
    );
    // The issue's numbers: 0 for shell 1, 0.72 mm for shell 13.
    assert_eq!(t.traxer_axis_offset(0), 0.0);
    assert!((t.traxer_axis_offset(12) - 0.5 * (d_last - d_first)).abs() < 1e-12);
    assert!((t.traxer_axis_offset(12) - 0.718).abs() < 1e-3);
    for i in 0..t.shells.len() {
        let shift = t.traxer_axis_offset(i);
        let a = t.alpha(i);
        // An axial ray at the front mirror's mid-length radius from the shell's own
        // (moved) axis: grazing at α, then the rear mirror, then it crosses that
        // axis (y = shift) near the focal plane, as a coaxial shell crosses y = 0.
        let r_mid = t.cone_radii(i)[0] - 0.5 * t.mirror_length_mm * a.sin();
        let (h2, d2) = through_shell(&scene, &t, i, DVec3::new(0.0, r_mid + shift, 400.0));
        let z = h2.point.z - (h2.point.y - shift) / d2.y * d2.z;
        assert!((z + 1500.1).abs() < 3.5, "shell {}: z = {z}", i + 1);
    }
}

#[test]
fn traxer_placement_reproduces_traxer_perfect_mirror_panter_image() {
    // TrAXer's perfect-mirror PANTER Al Kα image at 1519.5 mm (SPEC, issue 15):
    // HPD 184″, 80 % 307″, 90 % 354″ in photon counts. With perfect mirrors every
    // photon carries the same weight, so flux and counts give the same diameters.
    // 400 000 photons scatter the diameters by ≈ 0.5″ between seeds; 1 % (≥ 1.8″)
    // leaves room for that and for TrAXer's own noise. The coaxial telescope is
    // 3 / 6 / 5 % smaller and must fail the same check.
    let traxer_numbers = [184.0, 307.0, 354.0];
    let run = |axes: &str| {
        let out = tempfile::tempdir().unwrap();
        crate::common::run_ok(
            crate::common::traxer()
                .arg("trace")
                .arg(crate::common::repo().join("scenes/panter_al_ka.toml"))
                .args(["-D", "coating=perfect", "-D", "figure_error=none"])
                .args(["-D", "sensor_z=-1519.5", "-D"])
                .arg(format!("shell_axes={axes}"))
                .args(["-n", "400000", "-q", "-o"])
                .arg(out.path()),
        );
        let json: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.path().join("sensor.json")).unwrap())
                .unwrap();
        let q = &json["sensor"]["image_quality"];
        ["hpd_arcsec", "d80_arcsec", "d90_arcsec"].map(|k| q[k].as_f64().unwrap())
    };
    let traxer = run("traxer");
    for (got, want) in traxer.iter().zip(traxer_numbers) {
        assert!(
            (got / want - 1.0).abs() < 0.01,
            "traxer placement: {traxer:?}"
        );
    }
    let coaxial = run("coaxial");
    for (got, want) in coaxial.iter().zip(traxer_numbers) {
        assert!(got / want < 0.985, "coaxial: {coaxial:?}");
    }
}
