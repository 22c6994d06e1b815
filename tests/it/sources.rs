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
