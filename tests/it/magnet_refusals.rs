//! Issue 59: nothing silently wrong in the magnet, `signal` and `reach`. Each
//! test here failed on the main before it: NaN, infinity and P > 1 passed,
//! two commands deleted the run they read, a background of 1e300 never
//! ended, and careless inputs got no word.

use crate::common::{repo, run_fails, run_ok, traxer, write};
use std::path::Path;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// `traxer conversion ARGS --energies 4` must fail with exit 2 and a message
/// holding every one of `said`.
fn conversion_refuses(args: &[&str], said: &[&str]) {
    let err = run_fails(
        traxer()
            .arg("conversion")
            .args(args)
            .args(["--energies", "4"]),
        2,
    );
    for s in said {
        assert!(err.contains(s), "{args:?}: {s:?} not in {err}");
    }
}

#[test]
fn no_probability_is_nan_infinite_or_above_one() {
    let cast = ["--field-t", "9", "--length-m", "9.26"];
    let with = |extra: &[&'static str]| [&cast[..], extra].concat();
    // g = 0.1 already makes the weak-mixing P (0.198) overshoot the exact
    // sin²(½ g B L) (0.186); 1e10 gave P = 2e21.
    conversion_refuses(&with(&["--g-agamma", "0.1"]), &["g_agamma", "P above 1e-6"]);
    conversion_refuses(&with(&["--g-agamma", "1e10"]), &["g_agamma"]);
    // A mass of 1e153 eV made q L overflow: P was NaN.
    conversion_refuses(
        &with(&["--masses", "1e153"]),
        &["--masses", "1e153", "10 eV"],
    );
    conversion_refuses(&with(&["--masses", "0.01,0.01"]), &["0.01 is given twice"]);
    // Gases the ideal gas law makes infinitely dense.
    for (p, t) in [("1e300", "1.8"), ("10", "1e-300")] {
        conversion_refuses(
            &with(&["--gas", "He", "--pressure-mbar", p, "--temperature-k", t]),
            &["pressure_mbar", "denser than a liquid"],
        );
    }
    conversion_refuses(
        &["--field-t", "1e200", "--length-m", "9.26"],
        &["field_t = 1e200"],
    );
    // 1e-9 mm steps once tried to allocate 16 TB.
    conversion_refuses(
        &["--field-map", "bykovskiy_201906", "--step-mm", "1e-9"],
        &["step_mm = 1e-9", "10000"],
    );
    // A field map of 1e200 T.
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::new();
    for x in [-100, 0, 100] {
        for y in [-100, 0, 100] {
            for z in [-1000, 0, 1000] {
                text.push_str(&format!("{x} {y} {z} 0 1e200 0\n"));
            }
        }
    }
    let map = write(dir.path(), "huge.dat", &text);
    conversion_refuses(
        &["--field-map", map.to_str().unwrap()],
        &["huge.dat", "1e200 T", "in tesla"],
    );
    // A scene says which override made the value, and writes nothing.
    let scene = repo().join("scenes/babyiaxo_axion_image.toml");
    let out = dir.path().join("trace");
    let err = run_fails(
        traxer()
            .arg("trace")
            .arg(&scene)
            .args([
                "-n",
                "100",
                "-D",
                "magnet=true",
                "-D",
                "g_agamma=1e10",
                "-o",
            ])
            .arg(&out),
        2,
    );
    assert!(
        err.contains("(from the variable override g_agamma=1e10)"),
        "{err}"
    );
    let err = run_fails(
        traxer()
            .arg("trace")
            .arg(&scene)
            .args(["-n", "100", "-D", "magnet=true", "-D", "helium_mbar=10"])
            .args(["-D", "helium_k=-271", "-o"])
            .arg(&out),
        2,
    );
    assert!(
        err.contains("(from the variable override helium_k=-271)"),
        "{err}"
    );
    assert!(!out.exists());
}

/// P of `traxer conversion` for a uniform 9 T over 9.26 m.
fn cast_p(energies: &str, masses: &str) -> Vec<[f64; 3]> {
    let out = run_ok(traxer().args([
        "conversion",
        "--field-t",
        "9",
        "--length-m",
        "9.26",
        "--energies",
        energies,
        "--masses",
        masses,
        "-q",
    ]));
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

#[test]
fn a_map_with_no_transverse_field_is_named_not_blamed_on_the_coupling() {
    // Issue 59 §4: a map of Bz only got advice to change the coupling and no
    // file name.
    let dir = tempfile::tempdir().unwrap();
    let mut rows = String::new();
    for x in [-10, 0, 10] {
        for y in [-10, 0, 10] {
            for z in [-100, 0, 100] {
                rows.push_str(&format!("{x} {y} {z} 0 0 2.0\n"));
            }
        }
    }
    let map = write(dir.path(), "bz.txt", &rows);
    let map = map.to_string_lossy().to_string();
    conversion_refuses(
        &["--field-map", &map],
        &[
            "the field map",
            "bz.txt",
            "has no component across the bore",
        ],
    );
}

#[test]
fn the_mass_dependence_is_the_closed_form_written_from_m_and_e() {
    // P = (g B L / 2)² sinc²(m² L / 4E), everything written here from m and
    // E (not the code's momentum_transfer): 1 T = 195.35 eV² and
    // 1 m = 1 / (ħc = 1.97327e-7 eV m) = 5.06773e6 eV⁻¹ (the literature's
    // Heaviside–Lorentz natural units). A factor 2 in q or a keV/eV slip
    // moves P by far more than the 1e-4 asked (the constants' digits).
    let (g, b, l) = (1e-19, 9.0 * 195.353, 9.26 / 1.973_27e-7);
    for [e_kev, m, p] in cast_p("1,4,8", "0.01,0.02,0.05") {
        let e = e_kev * 1e3;
        let x = m * m * l / (4.0 * e);
        let want = (g * b * l / 2.0).powi(2) * (x.sin() / x).powi(2);
        assert!(
            rel(p, want) < 1e-4,
            "E {e_kev} keV, m {m} eV: {p:e} vs {want:e}"
        );
    }
}

/// A CAST run with the magnet: Primakoff, 10 bands of 1 keV, two masses.
fn cast_run(out: &Path, extra: &[&str]) {
    cast_run_in_bands(out, "[0,10,10]", extra)
}

fn cast_run_in_bands(out: &Path, bins: &str, extra: &[&str]) {
    let scene = repo().join("scenes/cast_axion_image.toml");
    run_ok(
        traxer()
            .arg("trace")
            .arg(&scene)
            .args(["-n", "20000", "-q", "-D", "magnet=true", "-D", "pixels=100"])
            .args([
                "-D",
                &format!("energy_bins={bins}"),
                "--masses",
                "0,0.02",
                "-o",
            ])
            .arg(out)
            .args(extra),
    );
}

/// Every file under `dir` with its bytes, to see that nothing changed.
fn contents(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .map(|p| (p.display().to_string(), std::fs::read(&p).unwrap()))
        .collect();
    v.sort();
    v
}

#[test]
fn signal_and_reach_never_replace_the_folder_they_read() {
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("run");
    cast_run(&run, &[]);
    let before = contents(&run);
    for out in [run.clone(), dir.path().to_path_buf()] {
        let err = run_fails(
            traxer()
                .arg("signal")
                .arg(&run)
                .args(["--radius-mm", "3", "-q", "-o"])
                .arg(&out),
            2,
        );
        assert!(err.contains("a folder this command reads"), "{err}");
        let err = run_fails(
            traxer()
                .arg("reach")
                .arg(&run)
                .args(["--radius-mm", "3", "--background", "0"])
                .args(["--tracking-hours", "1000", "-q", "-o"])
                .arg(&out),
            2,
        );
        assert!(err.contains("a folder this command reads"), "{err}");
    }
    assert_eq!(before, contents(&run), "the run was changed");
    // The default, a folder inside the run, still works.
    run_ok(
        traxer()
            .arg("signal")
            .arg(&run)
            .args(["--radius-mm", "3", "-q"]),
    );
    assert!(run.join("signal/signal.json").is_file());
}

/// The reach.csv rows of `traxer reach RUNS ARGS`: the setting, and the
/// numbers from the mass on (mass, signal, background, counts limit,
/// coupling limit).
fn reach_rows(runs: &[&Path], args: &[&str], out: &Path) -> Vec<(String, Vec<f64>)> {
    let mut c = traxer();
    c.arg("reach")
        .args(runs)
        .args(args)
        .arg("-q")
        .arg("-o")
        .arg(out);
    run_ok(&mut c);
    std::fs::read_to_string(out.join("reach.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                f[1].to_string(),
                f[3..]
                    .iter()
                    .map(|x| x.parse().unwrap_or(f64::NAN))
                    .collect(),
            )
        })
        .collect()
}

#[test]
fn reach_with_a_background_is_the_hand_product_and_an_independent_cls() {
    // b = B · area · width · time · bores, by hand, and the median-count CLs
    // limit against scipy's Poisson (independent: computed once with
    // scipy.stats.poisson for the median n of Poisson(b)).
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("run");
    cast_run(&run, &[]);
    let area_cm2 = std::f64::consts::PI * 0.3 * 0.3; // 3 mm, inside the 14 mm chip
    let (width_kev, hours, bores) = (5.0, 1000.0, 2.0);
    for (k, (b, scipy)) in [
        (3.0, 5.39545),
        (10.0, 8.08253),
        (100.0, 21.37421),
        (1e4, 197.72162),
    ]
    .into_iter()
    .enumerate()
    {
        let per = b / (area_cm2 * width_kev * hours * 3600.0 * bores);
        let rows = reach_rows(
            &[&run],
            &[
                "--radius-mm",
                "3",
                "--center",
                "0,0",
                "--window",
                "2,7",
                "--background",
                &format!("{per:e}"),
                "--tracking-hours",
                "1000",
                "--bores",
                "2",
            ],
            &dir.path().join(format!("reach{k}")),
        );
        for (_, v) in &rows {
            // v: mass, signal, background, counts limit, coupling limit.
            assert!(rel(v[2], b) < 1e-9, "b {b}: {}", v[2]);
            assert!(rel(v[3], scipy) < 2e-5, "b {b}: {} vs {scipy}", v[3]);
            assert!(rel(v[4], 1e-10 * (scipy / v[1]).powf(0.25)) < 1e-4);
        }
    }
}

#[test]
fn reach_refuses_what_never_ends_and_what_it_cannot_compare() {
    let dir = tempfile::tempdir().unwrap();
    let (run, other) = (dir.path().join("run"), dir.path().join("other"));
    cast_run(&run, &[]);
    cast_run_in_bands(&other, "[1,9,8]", &[]);
    let reach = |runs: &[&Path], extra: &[&str]| {
        let mut c = traxer();
        c.arg("reach").args(runs).args(["--radius-mm", "3", "-o"]);
        c.arg(dir.path().join("out")).args(extra);
        run_fails(&mut c, 2)
    };
    // 1e300 walked √b Poisson terms for ever.
    let e = reach(
        &[&run],
        &["--background", "1e300", "--tracking-hours", "1000"],
    );
    assert!(e.contains("counts per keV per cm² per second"), "{e}");
    let e = reach(&[&run], &["--background", "0", "--tracking-hours", "1e300"]);
    assert!(e.contains("tracking hours 1e300"), "{e}");
    // Runs of different energy bands, without a window valid for both.
    let e = reach(
        &[&run, &other],
        &["--background", "1e-6", "--tracking-hours", "100"],
    );
    assert!(
        e.contains("energy windows differ") && e.contains("--window"),
        "{e}"
    );
    assert!(!dir.path().join("out").exists());
    // With one, each curve counts 2–7 keV, and the two vacuum curves are
    // told apart by their runs.
    let rows = reach_rows(
        &[&run, &other],
        &[
            "--radius-mm",
            "3",
            "--window",
            "2,7",
            "--background",
            "1e-6",
            "--tracking-hours",
            "100",
        ],
        &dir.path().join("both"),
    );
    let labels: std::collections::BTreeSet<&str> = rows.iter().map(|r| r.0.as_str()).collect();
    assert!(
        labels.contains("vacuum (run)") && labels.contains("vacuum (other)"),
        "{labels:?}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("both/reach.json")).unwrap())
            .unwrap();
    assert!(json.to_string().contains("vacuum (other)"), "{json}");
}

#[test]
fn careless_inputs_get_a_word() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/cast_axion_image.toml");
    let stderr_of = |defines: &[&str], name: &str| {
        let mut c = traxer();
        c.arg("trace")
            .arg(&scene)
            .args(["-n", "200", "-D", "pixels=20"]);
        for d in defines {
            c.args(["-D", d]);
        }
        let out = run_ok(c.arg("-o").arg(dir.path().join(name)));
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let e = stderr_of(&["magnet=false", "helium_mbar=10"], "off");
    assert!(
        e.contains("warning: magnet: the buffer gas") && e.contains("is ignored"),
        "{e}"
    );
    let e = stderr_of(&["magnet=true", "helium_mbar=1000"], "liquid");
    assert!(e.contains("would be liquid"), "{e}");
    let e = stderr_of(&["magnet=true", "axion_masses_ev=[0.01,2,5]"], "far");
    assert!(e.contains("masses 2, 5 eV are far from coherence"), "{e}");
    // Duplicate masses, and masses meant in meV, are refused.
    let err = run_fails(
        traxer()
            .arg("trace")
            .arg(&scene)
            .args(["-n", "200", "-D", "magnet=true", "--masses", "0,10,20,50"])
            .arg("-o")
            .arg(dir.path().join("no")),
        2,
    );
    assert!(
        err.contains("20") && err.contains("masses are in eV"),
        "{err}"
    );
    // A signal region off the sensor, and none at all.
    let run = dir.path().join("run");
    cast_run(&run, &[]);
    let err = run_fails(
        traxer()
            .arg("signal")
            .arg(&run)
            .args(["--radius-mm", "1", "--center", "50,50"]),
        2,
    );
    assert!(err.contains("lies off the sensor"), "{err}");
    let err = run_fails(traxer().arg("signal").arg(&run), 2);
    assert!(
        err.contains("--radius-mm") && err.contains("--fraction"),
        "{err}"
    );
    // Hours meant as years.
    let out = run_ok(
        traxer()
            .arg("reach")
            .arg(&run)
            .args([
                "--radius-mm",
                "3",
                "--background",
                "0",
                "--tracking-hours",
                "1.5",
            ])
            .arg("-o")
            .arg(dir.path().join("short")),
    );
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(e.contains("warning: --tracking-hours"), "{e}");
}

#[test]
fn loose_ends_say_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    // A mass of 1e19 eV reached the scene as a 20-digit TOML integer; now it
    // is the magnet's bound that speaks, naming the mass.
    let scene = repo().join("scenes/cast_axion_image.toml");
    let err = run_fails(
        traxer()
            .arg("trace")
            .arg(&scene)
            .args(["-n", "100", "-D", "magnet=true", "--masses", "0,1e19", "-o"])
            .arg(dir.path().join("t")),
        2,
    );
    assert!(err.contains("masses_ev: 1e19"), "{err}");
    // Environment settings that were silently replaced by defaults.
    let err = run_fails(
        traxer()
            .args([
                "conversion",
                "--field-t",
                "9",
                "--length-m",
                "9.26",
                "--energies",
                "4",
            ])
            .env("TRAXER_CACHE_MAX_MB", "lots"),
        2,
    );
    assert!(err.contains("TRAXER_CACHE_MAX_MB=lots"), "{err}");
    let file = write(dir.path(), "a_file", "x");
    let err = run_fails(
        traxer()
            .args([
                "conversion",
                "--field-t",
                "9",
                "--length-m",
                "9.26",
                "--energies",
                "4",
            ])
            .env("TRAXER_CACHE", &file),
        2,
    );
    assert!(
        err.contains("not a folder") && err.contains("a_file"),
        "{err}"
    );
    // A huge radius is printed in a few characters.
    let run = dir.path().join("run");
    cast_run(&run, &[]);
    let out = run_ok(
        traxer()
            .arg("signal")
            .arg(&run)
            .args(["--radius-mm", "1e300", "-o"])
            .arg(dir.path().join("s")),
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let first = text.lines().next().unwrap();
    assert!(
        first.len() < 200 && first.contains("1.0000e300 mm"),
        "{first}"
    );
}

/// The flux of `image` (nx × ny pixels of `pitch` mm, the sensor centred on
/// its origin) inside the circle of `r` about `c`, by 20 × 20 sub-points per
/// pixel (each pixel's flux spread over its area): an estimate independent of
/// `signal`'s exact pixel–disk overlap, good to ~1e-3 for r ≫ pitch.
fn flux_in_circle(image: &[f64], n: usize, pitch: f64, c: [f64; 2], r: f64) -> f64 {
    let sub = 20;
    let half = 0.5 * n as f64 * pitch;
    let mut sum = 0.0;
    for iy in 0..n {
        for ix in 0..n {
            let v = image[iy * n + ix];
            if v == 0.0 {
                continue;
            }
            let mut inside = 0;
            for sy in 0..sub {
                for sx in 0..sub {
                    let x = -half + (ix as f64 + (sx as f64 + 0.5) / sub as f64) * pitch;
                    let y = -half + (iy as f64 + (sy as f64 + 0.5) / sub as f64) * pitch;
                    if (x - c[0]).powi(2) + (y - c[1]).powi(2) <= r * r {
                        inside += 1;
                    }
                }
            }
            sum += v * inside as f64 / (sub * sub) as f64;
        }
    }
    sum
}

#[test]
fn an_off_centre_circle_holds_what_the_image_holds_there() {
    // A 1 mm circle off the image's centre, inside CAST's 14 mm chip: the
    // rate `signal` reports against the traced image summed over the circle
    // here (1 %: the sub-point estimate's error is ~1e-3). A flipped
    // --center (y → −y) moves the rate by far more, which the test checks
    // too, so it can see that bug.
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("run");
    cast_run(&run, &[]);
    let bytes = std::fs::read(run.join("chip.npy")).unwrap();
    let npy = npyz::NpyFile::new(&bytes[..]).unwrap();
    let shape: Vec<usize> = npy.shape().iter().map(|&s| s as usize).collect();
    let data: Vec<f64> = npy.into_vec().unwrap();
    let (bands, n) = (shape[0], shape[1]);
    assert_eq!((shape[1], shape[2]), (100, 100));
    let image: Vec<f64> = (0..n * n)
        .map(|k| (0..bands).map(|b| data[b * n * n + k]).sum())
        .collect();
    let pitch = 14.0 / n as f64;
    let rate_at = |c: &str| {
        let out = dir.path().join(format!("s{c}"));
        run_ok(
            traxer()
                .arg("signal")
                .arg(&run)
                .args(["--radius-mm", "1", "--center", c, "-q", "-o"])
                .arg(&out),
        );
        let j: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("signal.json")).unwrap())
                .unwrap();
        j["masses"][0]["x_rays_per_s"].as_f64().unwrap()
    };
    let (here, flipped) = (rate_at("0.9,-0.4"), rate_at("0.9,0.4"));
    let want = flux_in_circle(&image, n, pitch, [0.9, -0.4], 1.0);
    assert!(rel(here, want) < 0.01, "{here:e} vs {want:e}");
    assert!(
        rel(flipped, want) > 0.03,
        "the flip is not seen: {flipped:e} vs {want:e}"
    );
}
