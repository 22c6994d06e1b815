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
    // Signal regions: a circle of 0.5 mm about the centroid holds (0.5/1)² of
    // the uniform disk; one of 0.5 mm about (1, 0), on the disk's edge, the
    // lens where the two circles overlap over π·1²; pixels of 0.01 mm blur the
    // edges by about a pixel: 1 % allowed.
    let out = crate::common::run_ok(
        crate::common::traxer()
            .args(["eef", "--json", "--pixel-pitch", "0.01", "--radius", "0.5"])
            .arg("--plot")
            .arg(dir.path().join("r.png"))
            .arg(&path),
    );
    let q: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let f = q["signal_regions"]["regions"][0]["fraction"]
        .as_f64()
        .unwrap();
    assert!((f - 0.25).abs() < 0.01, "{q}");
    let out = crate::common::run_ok(
        crate::common::traxer()
            .args(["eef", "--json", "--pixel-pitch", "0.01", "--radius", "0.5"])
            .args(["--center", "1,0", "--plot"])
            .arg(dir.path().join("r.png"))
            .arg(&path),
    );
    let q: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let f = q["signal_regions"]["regions"][0]["fraction"]
        .as_f64()
        .unwrap();
    let lens = |big: f64, small: f64, d: f64| {
        let a = small * small * ((d * d + small * small - big * big) / (2.0 * d * small)).acos();
        let b = big * big * ((d * d + big * big - small * small) / (2.0 * d * big)).acos();
        let c = 0.5
            * ((-d + small + big) * (d + small - big) * (d - small + big) * (d + small + big))
                .sqrt();
        a + b - c
    };
    let expected = lens(1.0, 0.5, 1.0) / std::f64::consts::PI;
    assert!((f - expected).abs() < 0.01, "{f} vs {expected}");
    let err = crate::common::run_fails(
        crate::common::traxer()
            .args(["eef", "--pixel-pitch", "0.01", "--radius", "-1"])
            .arg(&path),
        2,
    );
    assert!(err.contains("--radius -1"), "{err}");
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

/// ∫ of a unit 1-D Gaussian of width σ centred at m over [a, b].
fn gauss_mass(a: f64, b: f64, m: f64, s: f64) -> f64 {
    let c = |x: f64| 0.5 * libm::erf((x - m) / (s * std::f64::consts::SQRT_2));
    c(b) - c(a)
}

/// A narrow core (σ = 4 pixels, 60 % of the flux) on a wider halo (σ = 20
/// pixels), centred at (dx, dy) pixels from the image centre, each pixel holding
/// exactly the flux that falls on it.
fn sliding_spot(n: usize, dx: f64, dy: f64) -> Vec<f64> {
    let mut img = vec![0.0; n * n];
    let c = 0.5 * n as f64;
    for iy in 0..n {
        for ix in 0..n {
            let (x0, y0) = (ix as f64 - c, iy as f64 - c);
            let comp = |s: f64| gauss_mass(x0, x0 + 1.0, dx, s) * gauss_mass(y0, y0 + 1.0, dy, s);
            img[iy * n + ix] = 0.6 * comp(4.0) + 0.4 * comp(20.0);
        }
    }
    img
}

#[test]
fn diameters_do_not_wobble_as_the_image_slides_across_the_pixels() {
    // The same spot shifted by tenths of a pixel in x and y: its true diameters
    // do not change. Counting each pixel's flux at its centre makes them jump with
    // which pixel centres a circle holds (measured for this spot, HPD ≈ 13 pixels:
    // 1.3 % peak to peak); spreading it over the pixel's area leaves 0.13 % for
    // the HPD and 0.003 % for the 80 % diameter (the uniform spread is not exact
    // for a core only 4 pixels wide; for the 100-pixel PANTER HPD it is far
    // smaller still). Bounds: 0.2 % and 0.01 %; the centre method must exceed 0.5 %.
    let n = 200;
    let g = geometry(n, 1.0);
    let mut hpd = Vec::new();
    let mut d80 = Vec::new();
    for k in 0..10 {
        let (dx, dy) = (0.1 * k as f64, 0.07 * k as f64);
        let (q, _) = analyse(&sliding_spot(n, dx, dy), &g, None).unwrap();
        assert!((q.centroid_mm[0] - dx).abs() < 1e-3 && (q.centroid_mm[1] - dy).abs() < 1e-3);
        hpd.push(q.hpd_mm);
        d80.push(q.d80_mm);
    }
    // The same by pixel centres, for comparison: it must wobble, or this test
    // could not tell the methods apart.
    let centre_hpd = |img: &[f64]| {
        let total: f64 = img.iter().sum();
        let c = 0.5 * n as f64;
        let pos = |k: usize| ((k % n) as f64 + 0.5 - c, (k / n) as f64 + 0.5 - c);
        let (cx, cy) = img.iter().enumerate().fold((0.0, 0.0), |(a, b), (k, &v)| {
            (a + v * pos(k).0 / total, b + v * pos(k).1 / total)
        });
        let mut r: Vec<(f64, f64)> = img
            .iter()
            .enumerate()
            .map(|(k, &v)| ((pos(k).0 - cx).hypot(pos(k).1 - cy), v))
            .collect();
        r.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut acc = 0.0;
        2.0 * r
            .iter()
            .find(|(_, v)| {
                acc += v;
                acc >= 0.5 * total
            })
            .unwrap()
            .0
    };
    let by_centres: Vec<f64> = (0..10)
        .map(|k| centre_hpd(&sliding_spot(n, 0.1 * k as f64, 0.07 * k as f64)))
        .collect();
    let spread = |v: &[f64]| {
        let (lo, hi) = v
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        (hi - lo) / (0.5 * (hi + lo))
    };
    assert!(
        spread(&by_centres) > 5e-3,
        "by pixel centres {by_centres:?}"
    );
    assert!(spread(&hpd) < 2e-3, "HPD {hpd:?}");
    assert!(spread(&d80) < 1e-4, "d80 {d80:?}");
}

#[test]
fn rectangle_and_disk_overlap_areas() {
    use traxer::analysis::eef::rectangle_in_disk;
    let pi = std::f64::consts::PI;
    // A rectangle holding the disk: the disk's area; inside the disk: its own.
    assert!((rectangle_in_disk(-3.0, 2.5, -2.2, 4.0, 2.0) - pi * 4.0).abs() < 1e-12);
    assert!((rectangle_in_disk(-0.5, 0.7, -0.3, 0.2, 2.0) - 0.6).abs() < 1e-12);
    // Half and quarter planes.
    assert!((rectangle_in_disk(0.0, 5.0, -5.0, 5.0, 1.5) - 0.5 * pi * 2.25).abs() < 1e-12);
    assert!((rectangle_in_disk(-5.0, 0.0, 0.0, 5.0, 1.5) - 0.25 * pi * 2.25).abs() < 1e-12);
    // A strip |x| < a through the middle: 2(a√(r²−a²) + r² asin(a/r)).
    let (a, r) = (0.6, 1.0f64);
    let strip = 2.0 * (a * (r * r - a * a).sqrt() + r * r * (a / r).asin());
    assert!((rectangle_in_disk(-a, a, -9.0, 9.0, r) - strip).abs() < 1e-12);
    // A circular segment beyond x = a: r² acos(a/r) − a√(r²−a²).
    let segment = r * r * (a / r).acos() - a * (r * r - a * a).sqrt();
    assert!((rectangle_in_disk(a, 9.0, -9.0, 9.0, r) - segment).abs() < 1e-12);
    assert_eq!(rectangle_in_disk(2.0, 3.0, 2.0, 3.0, 1.0), 0.0);
}

#[test]
fn eef_of_a_traced_image_leaves_the_results_folder_as_the_trace_wrote_it() {
    // Before: `traxer eef out/chip.npy` replaced the trace's own chip_eef.png
    // and chip_eef.json inside the results folder.
    use crate::common::{run_fails, run_ok, traxer, write};
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "gas.toml", crate::silently_wrong::GAS_SCENE);
    let out = dir.path().join("out");
    run_ok(
        traxer()
            .args(["trace", "-n", "2000", "-q", "-o"])
            .arg(&out)
            .arg(&scene),
    );
    let own = std::fs::read(out.join("chip_eef.png")).unwrap();
    let work = dir.path().join("work");
    std::fs::create_dir(&work).unwrap();
    run_ok(
        traxer()
            .current_dir(&work)
            .arg("eef")
            .arg(out.join("chip.npy"))
            .arg("-q"),
    );
    assert!(work.join("chip_eef.png").is_file() && work.join("chip_eef.json").is_file());
    assert_eq!(std::fs::read(out.join("chip_eef.png")).unwrap(), own);
    let err = run_fails(
        traxer()
            .arg("eef")
            .arg(out.join("chip.npy"))
            .arg("--plot")
            .arg(out.join("mine.png")),
        2,
    );
    assert!(err.contains("is a traxer results folder"), "{err}");
    // From inside the results folder, there is nowhere to put it unasked.
    let err = run_fails(traxer().current_dir(&out).args(["eef", "chip.npy"]), 2);
    assert!(err.contains("give --plot a place outside it"), "{err}");
    assert!(!out.join("mine.png").exists());
}
