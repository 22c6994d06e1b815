//! Image analysis against closed forms: the encircled energy of a uniform disk and
//! of a 2-D Gaussian, and the arcsecond conversion.

use traxer::analysis::{analyse, projections, ImageGeometry};

fn geometry(n: usize, pitch: f64) -> ImageGeometry {
    ImageGeometry {
        nx: n,
        ny: n,
        pitch: [pitch, pitch],
        origin_mm: [-0.5 * n as f64 * pitch, -0.5 * n as f64 * pitch],
    }
}

#[test]
fn uniform_disk_diameters() {
    // Disk of radius R = 3 mm, off centre: EEF(r) = (r/R)², so the 50/80/90 %
    // diameters are 2R·√0.5, 2R·√0.8, 2R·√0.9.
    let (n, pitch) = (1200, 0.01);
    let g = geometry(n, pitch);
    let (cx, cy, r) = (0.7, -1.1, 3.0);
    let mut img = vec![0.0; n * n];
    for iy in 0..n {
        for ix in 0..n {
            let x = -6.0 + (ix as f64 + 0.5) * pitch;
            let y = -6.0 + (iy as f64 + 0.5) * pitch;
            if (x - cx).hypot(y - cy) < r {
                img[iy * n + ix] = 2.5;
            }
        }
    }
    let (q, _) = analyse(&img, &g, Some(1500.0)).unwrap();
    assert!((q.centroid_mm[0] - cx).abs() < 1e-3 && (q.centroid_mm[1] - cy).abs() < 1e-3);
    for (got, f) in [(q.hpd_mm, 0.5f64), (q.d80_mm, 0.8), (q.d90_mm, 0.9)] {
        let want = 2.0 * r * f.sqrt();
        assert!((got / want - 1.0).abs() < 2e-3, "{f}: {got} vs {want}");
    }
    let want = 2.0 * (0.5 * q.hpd_mm / 1500.0).atan().to_degrees() * 3600.0;
    assert!((q.hpd_arcsec.unwrap() - want).abs() < 1e-9);
    // Projections conserve the flux.
    let (px, py) = projections(&img, &g);
    let total: f64 = img.iter().sum();
    assert!(
        (px.iter().sum::<f64>() - total).abs() < 1e-6 * total
            && (py.iter().sum::<f64>() - total).abs() < 1e-6 * total
    );
}

#[test]
fn gaussian_spot_diameters() {
    // 2-D Gaussian of σ = 0.2 mm: EEF = 1 − exp(−r²/2σ²), HPD = 2σ√(2 ln 2).
    let (n, pitch, s) = (800, 0.005, 0.2);
    let g = geometry(n, pitch);
    let mut img = vec![0.0; n * n];
    for iy in 0..n {
        for ix in 0..n {
            let x = -2.0 + (ix as f64 + 0.5) * pitch;
            let y = -2.0 + (iy as f64 + 0.5) * pitch;
            img[iy * n + ix] = (-(x * x + y * y) / (2.0 * s * s)).exp();
        }
    }
    let (q, eef) = analyse(&img, &g, None).unwrap();
    for (got, f) in [(q.hpd_mm, 0.5f64), (q.d80_mm, 0.8), (q.d90_mm, 0.9)] {
        let want = 2.0 * s * (-2.0 * (1.0 - f).ln()).sqrt();
        assert!((got / want - 1.0).abs() < 5e-3, "{f}: {got} vs {want}");
    }
    assert!(q.hpd_arcsec.is_none());
    assert!(
        eef.fraction.windows(2).all(|w| w[0] <= w[1])
            && (eef.fraction.last().unwrap() - 1.0).abs() < 1e-12
    );
    // An empty image has no quality.
    assert!(analyse(&[0.0; 16], &geometry(4, 1.0), None).is_none());
}

#[test]
fn eef_command_on_an_npy_from_elsewhere() {
    // A uniform disk of radius 100 px written as float32 by "another program".
    let dir = tempfile::tempdir().unwrap();
    let n = 400usize;
    let mut img = vec![0f32; n * n];
    for iy in 0..n {
        for ix in 0..n {
            if ((ix as f64 + 0.5 - 200.0).hypot(iy as f64 + 0.5 - 200.0)) < 100.0 {
                img[iy * n + ix] = 1.0;
            }
        }
    }
    let path = dir.path().join("disk.npy");
    {
        use npyz::WriterBuilder;
        let mut f = std::fs::File::create(&path).unwrap();
        let mut w = npyz::WriteOptions::new()
            .default_dtype()
            .shape(&[n as u64, n as u64])
            .writer(&mut f)
            .begin_nd()
            .unwrap();
        w.extend(img.iter().copied()).unwrap();
        w.finish().unwrap();
    }
    let out = crate::common::run_ok(
        crate::common::traxer()
            .args([
                "eef",
                "--json",
                "--pixel-pitch",
                "0.01",
                "--focal-length",
                "1500",
            ])
            .arg(&path),
    );
    let q: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // Radius 1 mm: HPD = 2·√0.5 mm.
    assert!(
        (q["hpd_mm"].as_f64().unwrap() / 2f64.sqrt() - 1.0).abs() < 5e-3,
        "{q}"
    );
    assert!(dir.path().join("disk_eef.png").is_file());
    // Without a pitch (and no sidecar), or with garbage, exit code 2.
    let err = crate::common::run_fails(crate::common::traxer().arg("eef").arg(&path), 2);
    assert!(err.contains("--pixel-pitch"), "{err}");
    std::fs::write(dir.path().join("junk.npy"), b"not numpy").unwrap();
    crate::common::run_fails(
        crate::common::traxer()
            .args(["eef", "--pixel-pitch", "1"])
            .arg(dir.path().join("junk.npy")),
        2,
    );
}
