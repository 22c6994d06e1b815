//! Sources against closed forms: a point source's weights reproduce isotropic
//! emission; a parallel beam fills its aperture uniformly.

use crate::common::scene;
use traxer::random::PhotonRng;

#[test]
fn point_source_weights_equal_isotropic_emission_through_the_target() {
    // On-axis point source at distance D from a target disk of radius R: the
    // fraction of isotropic emission through the disk is (1 − D/√(D² + R²)) / 2.
    for (dist, radius, src_radius) in [
        (130_297.0, 110.0, 0.0),
        (1000.0, 300.0, 0.0),
        (14_200.0, 21.5, 3.0),
    ] {
        let s = scene(&format!(
            r#"
[[sources]]
type = "point"
position = [0, 0, {dist}]
radius = {src_radius}
target = {{ center = [0, 0, 0], radius = {radius} }}
energy = {{ band = [1.48, 1.50] }}
"#
        ));
        let n = 200_000;
        let mut sum = 0.0;
        for i in 0..n {
            let p = s.sources[0].emit(&mut PhotonRng::new(1, i));
            assert!(p.energy >= 1.48 && p.energy <= 1.50);
            assert!(
                p.origin.z.abs() < 1e-9 && p.origin.truncate().length() <= radius + 1e-9,
                "starts on the target"
            );
            assert!((p.dir.length() - 1.0).abs() < 1e-12);
            sum += p.weight;
        }
        let expected = 0.5 * (1.0 - dist / (dist * dist + radius * radius).sqrt());
        let got = sum / n as f64;
        // The weights vary only with cos θ / d² across the target, so the estimate is
        // nearly exact; 0.5 % covers the finite source size (3 mm at 14 m) too.
        assert!(
            (got / expected - 1.0).abs() < 5e-3,
            "D {dist} R {radius}: {got} vs {expected}"
        );
    }
}

#[test]
fn parallel_beam_fills_its_annulus_uniformly() {
    let s = scene(
        r#"
[[sources]]
type = "parallel"
direction = [0, 0, -1]
off_axis = 0.5
off_axis_azimuth = 90.0
aperture = { center = [0, 0, 100], radius = 10.0, inner_radius = 4.0 }
energy = { line = 6.4 }
"#,
    );
    let n = 100_000u64;
    let (mut r2, mut min_r, mut max_r) = (0.0, f64::INFINITY, 0.0f64);
    let mut dir = glam::DVec3::ZERO;
    for i in 0..n {
        let p = s.sources[0].emit(&mut PhotonRng::new(2, i));
        let r = p.origin.truncate().length();
        r2 += r * r;
        min_r = min_r.min(r);
        max_r = max_r.max(r);
        assert_eq!(p.weight, 1.0);
        assert_eq!(p.energy, 6.4);
        dir = p.dir;
    }
    // Uniform over area: ⟨r²⟩ = (R² + r²)/2 = 58; standard error ~0.05.
    assert!(
        (r2 / n as f64 - 58.0).abs() < 0.2,
        "<r²> = {}",
        r2 / n as f64
    );
    assert!(min_r >= 4.0 && max_r <= 10.0);
    // Tilted by 0.5° from −z towards e2 = e1 × axis = x × (−z) = +y.
    assert!((dir.angle_between(glam::DVec3::NEG_Z).to_degrees() - 0.5).abs() < 1e-12);
    assert!(dir.y > 0.0 && dir.x.abs() < 1e-15);
}

#[test]
fn target_sectors_keep_the_isotropic_normalisation() {
    // Aiming only at a 30° sector of the target annulus: the summed weights are
    // 30/360 of those for the full annulus, and every photon starts in the sector
    // (azimuth from +x towards +y for photons travelling along −z).
    let text = |az: &str| {
        format!(
            r#"
[[sources]]
type = "point"
position = [0, 0, 130297.0]
radius = 0.42
target = {{ center = [0, 0, 240], radius = 106.0, inner_radius = 58.0 {az} }}
energy = {{ line = 1.49 }}
"#
        )
    };
    let full = scene(&text(""));
    let sector = scene(&text(", azimuth = [-15.0, 15.0]"));
    let n = 100_000;
    let (mut wf, mut ws) = (0.0, 0.0);
    for i in 0..n {
        wf += full.sources[0].emit(&mut PhotonRng::new(3, i)).weight;
        let p = sector.sources[0].emit(&mut PhotonRng::new(3, i));
        ws += p.weight;
        let phi = p.origin.y.atan2(p.origin.x).to_degrees();
        assert!(phi.abs() <= 15.0 + 1e-9, "photon at azimuth {phi}");
    }
    assert!((ws / wf - 30.0 / 360.0).abs() < 1e-4, "ratio {}", ws / wf);
}

/// A lab source's spectrum from a table (SPEC: "a single line, a uniform band,
/// or a table"): an X-ray-tube-like density, a ramp 1–5 keV rising from 1 to 3
/// with a line-like triangle at 6.4 keV, read from the scene's folder. The
/// source's energies follow it (the mean and the line's share against their
/// closed forms, within 4 standard errors); a trace through the CLI runs with
/// it, and the table file is among the run's inputs.
#[test]
fn a_lab_source_draws_its_energies_from_a_spectrum_table() {
    use crate::common::{repo, run_ok, traxer};
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(
        tmp.path().join("tube.csv"),
        "# a made-up tube spectrum\nenergy_keV,density\n1.0,1.0\n5.0,3.0\n5.5,0.0\n6.3,0.0\n6.4,20.0\n6.5,0.0\n",
    )
    .unwrap();
    let text = std::fs::read_to_string(repo().join("scenes/wolter1_parallel.toml"))
        .unwrap()
        .replace("\"../meshes/", &format!("\"{}/meshes/", repo().display()))
        .replace(
            "energy = { line = \"$energy\" }",
            "energy = { table = \"tube.csv\" }",
        );
    assert!(text.contains("tube.csv"));
    let scene = tmp.path().join("tube.toml");
    std::fs::write(&scene, text).unwrap();
    let out = tmp.path().join("out");
    run_ok(
        traxer()
            .arg("trace")
            .arg(&scene)
            .args(["-n", "400000", "--photon-list", "20000", "-q", "--out"])
            .arg(&out),
    );
    let csv = std::fs::read_to_string(out.join("photons.csv")).unwrap();
    let mut rows = csv.lines();
    let header: Vec<&str> = rows.next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == "energy_keV").unwrap();
    let energies: Vec<f64> = rows
        .map(|r| r.split(',').nth(col).unwrap().parse().unwrap())
        .collect();
    assert_eq!(energies.len(), 20000);
    // The density: ramp 1→3 on [1, 5] (area 8, mean (∫E f) = 4·(1·3 + 2·4.333...)),
    // fall 3→0 on [5, 5.5] (area 0.75), triangle of area 2 at 6.4 keV.
    // ∫E f dE on each piece, by Simpson's rule (exact for quadratics):
    let simpson = |a: f64, b: f64, f: &dyn Fn(f64) -> f64| {
        (b - a) / 6.0 * (f(a) + 4.0 * f(0.5 * (a + b)) + f(b))
    };
    let ramp = |e: f64| 1.0 + 0.5 * (e - 1.0);
    let fall = |e: f64| 3.0 * (5.5 - e) / 0.5;
    let up = |e: f64| 20.0 * (e - 6.3) / 0.1;
    let down = |e: f64| 20.0 * (6.5 - e) / 0.1;
    type Piece<'a> = (f64, f64, &'a dyn Fn(f64) -> f64);
    let pieces: [Piece; 4] = [
        (1.0, 5.0, &ramp),
        (5.0, 5.5, &fall),
        (6.3, 6.4, &up),
        (6.4, 6.5, &down),
    ];
    let area: f64 = pieces.iter().map(|(a, b, f)| simpson(*a, *b, *f)).sum();
    let mean: f64 = pieces
        .iter()
        .map(|(a, b, f)| simpson(*a, *b, &|e| e * f(e)))
        .sum::<f64>()
        / area;
    let above = pieces[2..]
        .iter()
        .map(|(a, b, f)| simpson(*a, *b, *f))
        .sum::<f64>()
        / area;
    assert!((area - 10.75).abs() < 1e-12);
    // The source itself: 200 000 energies drawn against the closed forms
    // (standard errors: σ_E/√n ≈ 0.003 keV, √(p(1−p)/n) ≈ 0.0008).
    let s = crate::common::scene_in(
        tmp.path(),
        r#"
[[sources]]
type = "point"
position = [0, 0, 1000]
target = { center = [0, 0, 0], radius = 10.0 }
energy = { table = "tube.csv" }
"#,
    );
    let n = 200_000u64;
    let drawn: Vec<f64> = (0..n)
        .map(|i| s.sources[0].emit(&mut PhotonRng::new(5, i)).energy)
        .collect();
    let m = drawn.iter().sum::<f64>() / n as f64;
    let frac = drawn.iter().filter(|&&e| e > 6.3).count() as f64 / n as f64;
    assert!((m - mean).abs() < 0.012, "mean {m} vs the table's {mean}");
    assert!(
        (frac - above).abs() < 0.0035,
        "line share {frac} vs {above}"
    );
    assert!(
        !drawn.iter().any(|&e| e > 5.5 && e < 6.3),
        "energies where the density is 0"
    );
    // Photons that reached the sensor through the gold telescope: inside the
    // table's range, none where it is zero.
    assert!(energies.iter().all(|&e| (1.0..=6.5).contains(&e)));
    assert!(!energies.iter().any(|&e| e > 5.5 && e < 6.3));
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(
        summary.contains("tube.csv"),
        "the table is among the run's inputs"
    );
}
