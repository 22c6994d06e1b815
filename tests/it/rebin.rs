//! Rebinning to the detector's pixel grid (GridPix: 256 × 256 × 55 µm): flux is
//! conserved, a uniform image gives the exact overlap areas, a single fine pixel
//! lands where it lies — also through a trace with `pixel_grid` on a sensor.

use crate::common::{run_ok, traxer, write};
use traxer::sensor::{rebin, PixelGrid};

fn gridpix(rotation_deg: f64) -> PixelGrid {
    PixelGrid {
        pixels: [256, 256],
        pitch_mm: 0.055,
        rotation_deg,
        center_mm: [0.0, 0.0],
    }
}

#[test]
fn flux_is_conserved_to_rounding_at_any_rotation() {
    // A lumpy image (deterministic pseudo-random values) on 14 × 14 mm, 500 px.
    let n = 500;
    let image: Vec<f64> = (0..n * n)
        .map(|k| ((k * 7919 % 1000) as f64).powi(2) * 1e-3)
        .collect();
    let total: f64 = image.iter().sum();
    for rotation in [0.0, 14.0, 30.0, 45.0, -77.0] {
        let r = rebin(
            &image,
            [14.0, 14.0],
            [n as u32, n as u32],
            &gridpix(rotation),
        );
        let placed: f64 = r.flux.iter().sum();
        assert!(
            ((placed + r.outside) / total - 1.0).abs() < 1e-12,
            "rotation {rotation}"
        );
        if rotation == 0.0 {
            // The 14.08 mm grid covers the 14 mm sensor: nothing outside.
            assert!(r.outside.abs() < 1e-9 * total, "outside {}", r.outside);
        } else {
            // Turned, the sensor's corners stick out of the grid.
            assert!(r.outside > 0.0);
        }
    }
}

#[test]
fn a_uniform_image_rebins_to_the_exact_overlap_areas() {
    // 1 per fine pixel of 0.014 mm: a grid pixel gets its area on the sensor
    // divided by 0.014².
    let n = 1000;
    let image = vec![1.0; n * n];
    let fine = 0.014f64 * 0.014;
    for rotation in [0.0, 30.0] {
        let g = gridpix(rotation);
        let r = rebin(&image, [14.0, 14.0], [n as u32, n as u32], &g);
        // A pixel near the centre lies wholly on the sensor.
        let inner = r.flux[128 * 256 + 100];
        assert!(
            (inner - 0.055 * 0.055 / fine).abs() < 1e-9,
            "rotation {rotation}: {inner}"
        );
    }
    // Unrotated, the edge column overlaps the sensor over [6.985, 7.0] mm in x.
    let r = rebin(&image, [14.0, 14.0], [n as u32, n as u32], &gridpix(0.0));
    let edge = r.flux[100 * 256 + 255];
    assert!((edge - 0.015 * 0.055 / fine).abs() < 1e-9, "edge {edge}");
    let corner = r.flux[255 * 256 + 255];
    assert!(
        (corner - 0.015 * 0.015 / fine).abs() < 1e-9,
        "corner {corner}"
    );
}

#[test]
fn a_single_fine_pixel_lands_in_the_right_grid_pixels() {
    // 0.01 mm pixels on a 2.2 × 2.2 mm sensor; a 40 × 40 grid of 0.055 mm.
    let n = 220usize;
    let g = PixelGrid {
        pixels: [40, 40],
        pitch_mm: 0.055,
        rotation_deg: 0.0,
        center_mm: [0.0, 0.0],
    };
    let mut image = vec![0.0; n * n];
    // Fine pixel (ix, iy) = (120, 60): x ∈ [0.10, 0.11] mm lies wholly in grid
    // column 21 (grid units 21.82 … 22.00); y ∈ [−0.50, −0.49] mm straddles rows
    // 10 and 11 (10.91 … 11.09): half-and-half by area, from the grid lines at
    // multiples of 0.055 mm from the corner at −1.1 mm.
    image[60 * n + 120] = 2.0;
    let r = rebin(&image, [2.2, 2.2], [n as u32, n as u32], &g);
    let split = |a: f64, b: f64| {
        let edge = ((a + 1.1) / 0.055).ceil() * 0.055 - 1.1;
        if edge < b {
            ((edge - a) / (b - a), ((a + 1.1) / 0.055).floor() as usize)
        } else {
            (1.0, ((a + 1.1) / 0.055).floor() as usize)
        }
    };
    let (fx, cx) = split(0.10, 0.11);
    let (fy, cy) = split(-0.50, -0.49);
    let want = |ix: usize, iy: usize| {
        let wx = if ix == cx {
            fx
        } else if ix == cx + 1 {
            1.0 - fx
        } else {
            0.0
        };
        let wy = if iy == cy {
            fy
        } else if iy == cy + 1 {
            1.0 - fy
        } else {
            0.0
        };
        2.0 * wx * wy
    };
    for iy in 0..40 {
        for ix in 0..40 {
            let got = r.flux[iy * 40 + ix];
            assert!(
                (got - want(ix, iy)).abs() < 1e-12,
                "({ix}, {iy}): {got} vs {}",
                want(ix, iy)
            );
        }
    }
    assert!(r.flux.iter().filter(|v| **v > 0.0).count() >= 1);
}

#[test]
fn trace_writes_the_grid_image_as_npy_and_csv() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(
        dir.path(),
        "s.toml",
        r#"
[materials.detector]
type = "sensor"
size = [14.0, 14.0]
pixels = [700, 700]
pixel_grid = { rotation = 14.0 }

[[sources]]
type = "parallel"
aperture = { center = [1.0, -2.0, 10], radius = 3.0 }
energy = { line = 3.0 }

[[objects]]
name = "chip"
material = "detector"
shape = { type = "rectangle", size = [14.0, 14.0] }
"#,
    );
    let out = dir.path().join("out");
    run_ok(
        traxer()
            .arg("trace")
            .arg(&scene)
            .args(["--photons", "20000", "--quiet", "--out"])
            .arg(&out),
    );
    let grid = traxer::output::read_image(&out.join("chip_grid.npy")).unwrap();
    assert_eq!((grid.nx, grid.ny), (256, 256));
    let fine = traxer::output::read_image(&out.join("chip.npy")).unwrap();
    let (a, b): (f64, f64) = (grid.summed.iter().sum(), fine.summed.iter().sum());
    // The beam (radius 3 mm around (1, −2)) lies inside the turned grid.
    assert!((a / b - 1.0).abs() < 1e-12, "{a} vs {b}");
    let csv = std::fs::read_to_string(out.join("chip_grid.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("ix,iy,x_mm,y_mm,flux"));
    assert_eq!(lines.count(), 256 * 256);
    // The flux-weighted centre of the grid image is the beam's centre (1, −2).
    let (mut w, mut x, mut y) = (0.0, 0.0, 0.0);
    for l in csv.lines().skip(1) {
        let f: Vec<f64> = l.split(',').map(|v| v.parse().unwrap()).collect();
        w += f[4];
        x += f[4] * f[2];
        y += f[4] * f[3];
    }
    assert!(
        (x / w - 1.0).abs() < 0.05 && (y / w + 2.0).abs() < 0.05,
        "centre ({}, {})",
        x / w,
        y / w
    );
}
