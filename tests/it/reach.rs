//! `traxer signal` and `traxer reach` on traced magnet runs: the region's
//! area and counts against closed forms and the run's own images, the limit
//! without background against the classical 3.0 counts, and refusals.

use crate::common::{repo, run_fails, run_ok, traxer};
use std::path::Path;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// A CAST run with the magnet: Primakoff, 9 energy bands, two masses.
fn cast_run(out: &Path, extra: &[&str]) {
    let scene = repo().join("scenes/cast_axion_image.toml");
    run_ok(
        traxer()
            .arg("trace")
            .arg(&scene)
            .args(["-n", "20000", "-q", "-D", "magnet=true", "-D", "pixels=200"])
            .args(["-D", "energy_bins=[1,10,9]", "--masses", "0,0.02", "-o"])
            .arg(out)
            .args(extra),
    );
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn the_signal_region_holds_what_the_images_hold() {
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("run");
    cast_run(&run, &[]);
    let signal = |args: &[&str], out: &str| {
        run_ok(
            traxer()
                .arg("signal")
                .arg(&run)
                .args(args)
                .arg("-o")
                .arg(dir.path().join(out))
                .arg("-q"),
        );
        json(&dir.path().join(out).join("signal.json"))
    };
    // A 1 mm circle inside the 14 mm sensor: π r² exactly.
    let small = signal(&["--radius-mm", "1", "--center", "0.3,-0.2"], "small");
    let area = small["region"]["area_cm2"].as_f64().unwrap();
    assert!(rel(area, std::f64::consts::PI * 0.01) < 1e-9, "{area}");
    // A circle over the whole sensor: its area and every X-ray of each mass.
    let all = signal(&["--radius-mm", "100"], "all");
    assert!(rel(all["region"]["area_cm2"].as_f64().unwrap(), 1.96) < 1e-9);
    let by_mass = json(&run.join("chip.json"))["sensor"]["by_mass"]["masses"].clone();
    for (k, m) in all["masses"].as_array().unwrap().iter().enumerate() {
        let rate = m["x_rays_per_s"].as_f64().unwrap();
        let spectrum: f64 = m["spectrum_x_rays_per_s"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .sum();
        let traced = by_mass[k]["total_flux"].as_f64().unwrap();
        assert!(
            rel(rate, traced) < 1e-9 && rel(spectrum, rate) < 1e-12,
            "{rate:e} {spectrum:e} {traced:e}"
        );
    }
    // The circle holding 80 % of the scene mass's flux holds 80 % of it.
    let f = signal(&["--fraction", "0.8"], "f");
    assert!(
        (f["region"]["fraction_of_flux_at_that_mass"]
            .as_f64()
            .unwrap()
            - 0.8)
            .abs()
            < 1e-9
    );
    // The files a spectral tool reads.
    for file in ["signal.csv", "signal_spectrum.csv", "signal_spectrum.fits"] {
        assert!(dir.path().join("f").join(file).is_file(), "{file}");
    }
}

#[test]
fn without_background_the_limit_is_three_counts() {
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("run");
    cast_run(&run, &[]);
    let out = dir.path().join("reach");
    run_ok(
        traxer()
            .arg("reach")
            .arg(&run)
            .args(["--radius-mm", "3", "--window", "2,7", "--background", "0"])
            .args([
                "--tracking-hours",
                "1000",
                "--bores",
                "2",
                "--efficiency",
                "0.5",
                "-q",
                "-o",
            ])
            .arg(&out),
    );
    // The signal in the window from the spectrum, by hand.
    run_ok(
        traxer()
            .arg("signal")
            .arg(&run)
            .args(["--radius-mm", "3", "-q", "-o"])
            .arg(dir.path().join("s")),
    );
    let spectrum = std::fs::read_to_string(dir.path().join("s/signal_spectrum.csv")).unwrap();
    let csv = std::fs::read_to_string(out.join("reach.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 2);
    for (row, mass) in rows.iter().zip([0.0, 0.02]) {
        let rate: f64 = spectrum
            .lines()
            .skip(1)
            .map(|l| {
                l.split(',')
                    .map(|v| v.parse::<f64>().unwrap())
                    .collect::<Vec<_>>()
            })
            .filter(|r| r[0] == mass && r[1] >= 2.0 - 1e-9 && r[2] <= 7.0 + 1e-9)
            .map(|r| r[3])
            .sum();
        let s0 = rate * 1000.0 * 3600.0 * 2.0 * 0.5;
        let limit: f64 = row[6].parse().unwrap();
        let g: f64 = row[7].parse().unwrap();
        assert!(rel(limit, 20f64.ln()) < 1e-9, "{limit}");
        assert!(rel(row[4].parse().unwrap(), s0) < 1e-9);
        assert!(rel(g, 1e-10 * (20f64.ln() / s0).powf(0.25)) < 1e-9, "{g:e}");
    }
    assert!(out.join("reach.png").is_file() && out.join("reach.json").is_file());
}

#[test]
fn an_abc_run_limits_the_product_of_the_couplings() {
    // ABC's signal is ∝ g_ae² g_aγ²: without background the limit on
    // g_ae·g_aγ is (g_ae g_aγ)₀ √(ln 20 / s₀), s₀ from the run's own counts.
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("abc");
    cast_run(&run, &["-D", "emission=abc", "-D", "g_ae=1e-13"]);
    let out = dir.path().join("reach");
    run_ok(
        traxer()
            .arg("reach")
            .arg(&run)
            .args([
                "--radius-mm",
                "3",
                "--background",
                "0",
                "--tracking-hours",
                "500",
                "-q",
                "-o",
            ])
            .arg(&out),
    );
    let csv = std::fs::read_to_string(out.join("reach.csv")).unwrap();
    assert!(
        csv.lines()
            .next()
            .unwrap()
            .ends_with("g_ae_g_agamma_limit_per_gev"),
        "{csv}"
    );
    for row in csv.lines().skip(1) {
        let v: Vec<f64> = row.split(',').skip(3).map(|x| x.parse().unwrap()).collect();
        let (s0, limit) = (v[1], v[4]);
        assert!(
            rel(limit, 1e-13 * 1e-10 * (20f64.ln() / s0).sqrt()) < 1e-9,
            "{row}"
        );
    }
}

#[test]
fn runs_the_reach_cannot_use_are_refused_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let (run, both, plain) = (
        dir.path().join("run"),
        dir.path().join("both"),
        dir.path().join("plain"),
    );
    cast_run(&run, &[]);
    cast_run(&both, &["-D", "emission=primakoff+abc"]);
    let scene = repo().join("scenes/cast_axion_image.toml");
    run_ok(
        traxer()
            .arg("trace")
            .arg(&scene)
            .args(["-n", "2000", "-q", "-D", "magnet=false", "-o"])
            .arg(&plain),
    );
    let reach = |r: &Path, extra: &[&str]| {
        let mut c = traxer();
        c.arg("reach")
            .arg(r)
            .args(["--radius-mm", "3", "--background", "1e-6", "-o"]);
        c.arg(dir.path().join("out")).args(extra);
        if !extra.contains(&"--tracking-hours") {
            c.args(["--tracking-hours", "100"]);
        }
        run_fails(&mut c, 2)
    };
    assert!(
        reach(&plain, &[]).contains("no magnet"),
        "{}",
        reach(&plain, &[])
    );
    assert!(reach(&both, &[]).contains("emission=primakoff"));
    assert!(reach(&run, &["--window", "1.5,7"]).contains("edges of the run's energy bands"));
    assert!(reach(&run, &["--efficiency", "1.5"]).contains("efficiency 1.5"));
    let hours = reach(&run, &["--tracking-hours", "0"]);
    assert!(hours.contains("tracking hours 0"), "{hours}");
    let two = reach(&run, &["--tracking-hours", "1,2"]);
    assert!(two.contains("one for all, or one per run"), "{two}");
    assert!(!dir.path().join("out").exists());
}

#[test]
fn the_region_lies_on_the_brightest_mass_or_the_one_named() {
    // Issue 59 §5: the region was placed on the scene's mass whatever the
    // scan. Here the scene's mass is 0.02 eV, where coherence is partly lost
    // (qL/2 ≈ 1.2 at 4 keV), and the scan 0, 0.02: the brightest is 0.
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("run");
    cast_run(&run, &["-D", "axion_mass_ev=0.02"]);
    let signal = |args: &[&str], out: &str| {
        let o = dir.path().join(out);
        let said = run_ok(
            traxer()
                .arg("signal")
                .arg(&run)
                .args(args)
                .arg("-o")
                .arg(&o),
        );
        (
            json(&o.join("signal.json")),
            String::from_utf8_lossy(&said.stdout).to_string(),
        )
    };
    // The share of mass `k`'s flux on the sensor inside the region, from
    // signal.csv (the per-mass rates, not the region's own fraction).
    let inside = |out: &str, k: usize| -> f64 {
        let text = std::fs::read_to_string(dir.path().join(out).join("signal.csv")).unwrap();
        let row: Vec<f64> = text
            .lines()
            .nth(k + 1)
            .unwrap()
            .split(',')
            .map(|c| c.parse().unwrap())
            .collect();
        row[1] / row[3]
    };
    let (brightest, said) = signal(&["--fraction", "0.8"], "brightest");
    assert_eq!(brightest["region"]["placed_on_mass_ev"].as_f64(), Some(0.0));
    assert!(said.contains("of the flux at m_a = 0 eV"), "{said}");
    assert!((inside("brightest", 0) - 0.8).abs() < 1e-9);
    let (named, said) = signal(&["--fraction", "0.8", "--region-mass", "0.02"], "named");
    assert_eq!(named["region"]["placed_on_mass_ev"].as_f64(), Some(0.02));
    assert!(said.contains("of the flux at m_a = 0.02 eV"), "{said}");
    assert!((inside("named", 1) - 0.8).abs() < 1e-9);
    // The two images differ in shape: the circles differ.
    let r = |v: &serde_json::Value| v["region"]["radius_mm"].as_f64().unwrap();
    assert!(
        rel(r(&brightest), r(&named)) > 1e-6,
        "{} {}",
        r(&brightest),
        r(&named)
    );
    // A mass the run does not hold is refused, naming those it holds.
    let err = run_fails(
        traxer()
            .arg("signal")
            .arg(&run)
            .args(["--fraction", "0.8", "--region-mass", "0.05", "-q", "-o"])
            .arg(dir.path().join("refused")),
        2,
    );
    assert!(
        err.contains("--region-mass 0.05: not one of the run's masses (0, 0.02 eV)"),
        "{err}"
    );
    assert!(!dir.path().join("refused").exists());
    // reach names the mass of each run's region.
    let out = run_ok(
        traxer()
            .arg("reach")
            .arg(&run)
            .args([
                "--fraction",
                "0.8",
                "--background",
                "0",
                "--tracking-hours",
                "1000",
            ])
            .args(["--region-mass", "0.02", "-o"])
            .arg(dir.path().join("reach")),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("of its flux at m_a = 0.02 eV"), "{err}");
}
