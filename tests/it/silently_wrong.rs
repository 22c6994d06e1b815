//! Places where traxer once returned a plausible number that was wrong, or
//! ignored what it was told (issue 39): each is now computed right or refused by
//! name, and each test here failed before.

use crate::common::{repo, run_fails, run_ok, traxer, write};
use std::path::Path;

/// A parallel beam of radius 3 mm falling straight onto a gas detector (the
/// CAST GridPix's argon/isobutane at 1050 mbar, 30 mm drift): no mirror, no
/// window, so the area for X-rays converting in the gas is π r² · P(E).
const GAS_SCENE: &str = r#"
[vars]
energy = 3.0
[materials.chip]
type = "sensor"
size = [14.0, 14.0]
pixels = [70, 70]
gas = { mixture = { Ar = 0.977, C4H10 = 0.023 }, pressure_mbar = 1050.0, temperature_k = 293.15, drift_mm = 30.0 }

[[sources]]
type = "parallel"
direction = [0, 0, -1]
aperture = { center = [0, 0, 10], radius = 3.0 }
energy = { line = "$energy" }

[[objects]]
name = "chip"
material = "chip"
shape = { type = "rectangle", size = [14.0, 14.0] }
"#;

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn effective_area_of_a_gas_detector_counts_conversions_as_a_trace_does() {
    // Before: the sweep left the conversion probability out, and gave the same
    // 0.283 cm² (the beam) at 3 and 8 keV, where traces convert 59 % and 45 %.
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "gas.toml", GAS_SCENE);
    let photons = 20_000u64;
    let out = dir.path().join("ea");
    run_ok(
        traxer()
            .arg("effective-area")
            .arg(&scene)
            .args([
                "--energies",
                "3,8",
                "--angles",
                "0",
                "-n",
                &photons.to_string(),
                "-q",
                "-o",
            ])
            .arg(&out),
    );
    let ea = json(&out.join("effective_area.json"));
    assert!(
        ea["counts"]
            .as_str()
            .unwrap()
            .contains("converting in the gas"),
        "{}",
        ea["counts"]
    );
    let aperture = ea["aperture_cm2"].as_f64().unwrap();
    let points = ea["angles"][0]["points"].as_array().unwrap().clone();
    for (k, energy) in ["3", "8"].iter().enumerate() {
        let o = dir.path().join(format!("t{energy}"));
        run_ok(
            traxer()
                .arg("trace")
                .arg(&scene)
                .args(["-D", &format!("energy={energy}"), "-n"])
                .arg(photons.to_string())
                .args(["-q", "-o"])
                .arg(&o),
        );
        let chip = json(&o.join("chip.json"));
        // Every photon reaches the gas at normal incidence and carries P(E):
        // the trace's converted flux per photon times the beam is the area,
        // exactly (no Monte Carlo difference: the same photons, the same P).
        let converted = chip["sensor"]["conversion"]["converted_flux"]
            .as_f64()
            .unwrap();
        let from_trace = aperture * converted / photons as f64;
        let area = points[k]["area_cm2"].as_f64().unwrap();
        assert!(
            (area / from_trace - 1.0).abs() < 1e-9,
            "{energy} keV: effective area {area} cm², trace {from_trace} cm²"
        );
        assert!(area < 0.95 * aperture, "{energy} keV: {area} of {aperture}");
    }
    let (a3, a8) = (
        points[0]["area_cm2"].as_f64().unwrap(),
        points[1]["area_cm2"].as_f64().unwrap(),
    );
    assert!(a8 < 0.85 * a3, "argon converts less at 8 keV: {a3} vs {a8}");
}

#[test]
fn a_gas_detector_refuses_sources_beyond_its_photoabsorption_data() {
    // Before: a 40 keV source gave an all-zero image without a word.
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "gas.toml", GAS_SCENE);
    let err = run_fails(
        traxer()
            .arg("trace")
            .arg(&scene)
            .args(["-D", "energy=40", "-n", "100", "-q", "-o"])
            .arg(dir.path().join("o")),
        2,
    );
    assert!(
        err.contains("sensor `chip`") && err.contains("30 keV"),
        "{err}"
    );
    assert!(!dir.path().join("o").exists());
}

#[test]
fn effective_area_refuses_unsorted_or_repeated_energies_and_angles() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "gas.toml", GAS_SCENE);
    for (energies, angles, expect) in [
        ("3,8,5", "0", "5 keV (number 3) follows 8 keV"),
        ("3,3", "0", "3 keV (number 2) follows 3 keV"),
        ("3", "0,2,0", "0′ is given twice"),
    ] {
        let err = run_fails(
            traxer()
                .arg("effective-area")
                .arg(&scene)
                .args(["--energies", energies, "--angles", angles, "-n", "100"])
                .args(["-q", "-o"])
                .arg(dir.path().join("o")),
            2,
        );
        assert!(err.contains(expect), "{energies} / {angles}: {err}");
    }
}

#[test]
fn solar_flux_refuses_couplings_and_options_it_would_ignore() {
    let dir = tempfile::tempdir().unwrap();
    let table = repo().join("data/solar/primakoff_b16_agss09met.csv");
    let table = table.to_str().unwrap();
    for (args, expect) in [
        // A table's fluxes were printed unscaled whatever the coupling.
        (
            vec!["--table", table, "--g-agamma", "1e-11"],
            "--g-agamma cannot be used with a table",
        ),
        (
            vec!["--table", table, "--g-ae", "1e-12"],
            "--g-ae cannot be used with a table",
        ),
        (
            vec!["--table", table, "--emission", "abc"],
            "--emission cannot be used with a table",
        ),
        // A coupling of a process the emission does not have was dropped.
        (
            vec!["--emission", "primakoff", "--g-ae", "1e-12"],
            "--g-ae is the coupling of the ABC emission",
        ),
        (
            vec!["--emission", "abc", "--g-agamma", "1e-11"],
            "--g-agamma is the coupling of the Primakoff emission",
        ),
        // A coupling whose square underflows: one refusal naming it (before:
        // "the table emits nothing", exit 1).
        (
            vec!["--emission", "abc", "--g-ae", "1e-200"],
            "--g-ae 1e-200: the emission scales as the coupling squared",
        ),
        (vec!["--g-agamma", "1e-180"], "--g-agamma 1e-180"),
        // A misspelt name lists the built-in ones.
        (vec!["--emission", "ABC"], "names are lower case: \"abc\""),
    ] {
        let err = run_fails(
            traxer()
                .arg("solar-flux")
                .args(&args)
                .args(["-q", "--out"])
                .arg(dir.path().join("o")),
            2,
        );
        assert!(err.contains(expect), "{args:?}: {err}");
        assert!(err.len() < 600, "a readable message: {err}");
        assert!(!dir.path().join("o").exists());
    }
}

#[test]
fn scenes_refuse_an_underflowing_coupling_and_a_misspelt_emission_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let shipped = repo().join("scenes/cast_axion_electron_image.toml");
    let err = run_fails(
        traxer()
            .arg("trace")
            .arg(&shipped)
            .args(["-D", "g_ae=1e-200", "-n", "10", "-q", "-o"])
            .arg(dir.path().join("o")),
        2,
    );
    assert!(
        err.contains("g_ae = 1e-200") && err.contains("underflow"),
        "{err}"
    );
    let text = std::fs::read_to_string(&shipped).unwrap();
    for (name, expect) in [
        ("ABC", "names are lower case: \"abc\""),
        (
            "primakof",
            "expected \"primakoff\", \"abc\" or \"primakoff+abc\"",
        ),
    ] {
        let typo = text.replace(
            "emission = \"primakoff+abc\"",
            &format!("emission = \"{name}\""),
        );
        assert_ne!(typo, text);
        let path = write(dir.path(), "typo.toml", &typo);
        let err = run_fails(
            traxer()
                .arg("trace")
                .arg(&path)
                .args(["-n", "10", "-q", "-o"])
                .arg(dir.path().join("o")),
            2,
        );
        assert!(err.contains(expect), "{name}: {err}");
    }
}

#[test]
fn runs_with_other_inputs_never_replace_each_other_silently() {
    // Before: `trace SCENE -D x=…` wrote into the default run's out/NAME, and a
    // run with other photons or seed into the same --out replaced it unasked.
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "gas.toml", GAS_SCENE);
    let trace = |extra: &[&str]| {
        let mut c = traxer();
        c.current_dir(dir.path())
            .arg("trace")
            .arg(&scene)
            .arg("-q")
            .args(extra);
        if !extra.contains(&"-n") {
            c.args(["-n", "1000"]);
        }
        c
    };
    let flux = |folder: &str| {
        json(&dir.path().join(folder).join("chip.json"))["sensor"]["total_flux"]
            .as_f64()
            .unwrap()
    };
    run_ok(&mut trace(&[]));
    let first = flux("out/gas");
    // Overrides: a folder of their own, named after them.
    run_ok(&mut trace(&["-D", "energy=8"]));
    assert!(flux("out/gas@energy=8") < first);
    assert_eq!(flux("out/gas"), first, "the default run is kept");
    // Other photons or seed into a folder of another run: refused, kept.
    for (extra, says) in [
        (&["-n", "2000"][..], "2000 photons, not 1000"),
        (&["--seed", "7"][..], "seed 7, not 1"),
        (
            &["-D", "energy=5", "-o", "out/gas"][..],
            "variable energy = 5",
        ),
    ] {
        let err = run_fails(&mut trace(extra), 2);
        assert!(
            err.contains("other inputs") && err.contains(says),
            "{extra:?}: {err}"
        );
        assert!(err.contains("--replace"), "{err}");
        assert_eq!(flux("out/gas"), first, "{extra:?}: the folder is kept");
    }
    // The same inputs again: the same results, so nothing is lost.
    run_ok(&mut trace(&[]));
    // Asked to replace: replaced.
    run_ok(&mut trace(&[
        "-D",
        "energy=8",
        "-o",
        "out/gas",
        "--replace",
    ]));
    assert_eq!(flux("out/gas"), flux("out/gas@energy=8"));
}

/// A FITS file of 80-character cards `cards` and `data` (big-endian, padded to
/// 2880-byte blocks, as the standard asks).
fn fits_bytes(cards: &[String], data: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    for c in cards.iter().map(String::as_str).chain(["END"]) {
        out.extend(format!("{c:<80}").bytes());
    }
    out.resize(out.len().div_ceil(2880) * 2880, b' ');
    out.extend_from_slice(data);
    out.resize(out.len().div_ceil(2880) * 2880, 0);
    out
}

fn card(key: &str, value: &str) -> String {
    format!("{key:<8}= {value:>20}")
}

#[test]
fn eef_checks_a_fits_headers_sizes_before_allocating_and_names_a_zero_pitch() {
    // Before: a header claiming 10^5 × 10^5 float64 values (80 GB) was
    // allocated before anything was checked: SIGABRT.
    let dir = tempfile::tempdir().unwrap();
    let huge = fits_bytes(
        &[
            card("SIMPLE", "T"),
            card("BITPIX", "-64"),
            card("NAXIS", "2"),
            card("NAXIS1", "100000"),
            card("NAXIS2", "100000"),
        ],
        &[0; 64],
    );
    let path = dir.path().join("huge.fits");
    std::fs::write(&path, huge).unwrap();
    let err = run_fails(
        traxer()
            .arg("eef")
            .arg(&path)
            .args(["--pixel-pitch", "0.1"]),
        2,
    );
    assert!(
        err.contains("huge.fits") && err.contains("100000 × 100000") && err.contains("truncated"),
        "{err}"
    );
    // A pitch of zero in the header: the file and the key are named.
    let data: Vec<u8> = (0..16).flat_map(|_| 1.0f64.to_be_bytes()).collect();
    let zero = fits_bytes(
        &[
            card("SIMPLE", "T"),
            card("BITPIX", "-64"),
            card("NAXIS", "2"),
            card("NAXIS1", "4"),
            card("NAXIS2", "4"),
            card("CDELT1", "0.0"),
            card("CDELT2", "0.1"),
            card("CUNIT1", "'mm      '"),
            card("CUNIT2", "'mm      '"),
        ],
        &data,
    );
    let path = dir.path().join("zero.fits");
    std::fs::write(&path, zero).unwrap();
    let err = run_fails(traxer().arg("eef").arg(&path), 2);
    assert!(err.contains("zero.fits") && err.contains("CDELT1"), "{err}");
    // With the pitch given, the same file is measured.
    run_ok(
        traxer()
            .arg("eef")
            .arg(&path)
            .args(["--pixel-pitch", "0.1", "-q", "--plot"])
            .arg(dir.path().join("p.png")),
    );
}

#[test]
fn a_trace_while_a_study_writes_into_its_folder_says_a_study_is_running() {
    // Before: "holds files traxer did not write (focus) … move them", harmful
    // advice while the study runs.
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/wolter1_parallel.toml");
    let mut focus = traxer()
        .current_dir(dir.path())
        .arg("focus")
        .arg(&scene)
        .args([
            "--var",
            "focus_shift",
            "--from=-2",
            "--to=2",
            "--steps",
            "40",
        ])
        .args(["-n", "2e6", "-q"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let study = dir.path().join("out/wolter1_parallel/focus");
    let start = std::time::Instant::now();
    while !study.exists() && start.elapsed().as_secs() < 60 {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let err = run_fails(
        traxer()
            .current_dir(dir.path())
            .arg("trace")
            .arg(&scene)
            .args(["-n", "1000", "-q"]),
        2,
    );
    let still_running = focus.try_wait().unwrap().is_none();
    focus.kill().ok();
    focus.wait().unwrap();
    if still_running {
        assert!(err.contains("writing its results here right now"), "{err}");
        assert!(!err.contains("move them"), "{err}");
    }
}

#[test]
fn roughness_mistakes_name_the_key_and_the_forms_accepted() {
    // Before: "data did not match any variant of untagged enum RoughnessSpec".
    let dir = tempfile::tempdir().unwrap();
    for (value, says) in [
        (
            r#"roughness={psd={type="power",k=1,n=1.5},band_per_um=[0.001,1]}"#,
            "unknown variant `power`",
        ),
        (
            r#"roughness={psd={type="power_law",k=1},band_per_um=[0.001,1]}"#,
            "missing field `n`",
        ),
        ("roughness=3", "roughness = 3"),
    ] {
        let err = run_fails(
            traxer()
                .arg("trace")
                .arg(repo().join("scenes/panter_al_ka.toml"))
                .args(["-n", "100", "-q", "-D", value, "-o"])
                .arg(dir.path().join("o")),
            2,
        );
        assert!(
            err.contains(says)
                && err.contains("roughness")
                && err.contains("band_per_um = [f1, f2]"),
            "{value}: {err}"
        );
        assert!(!err.contains("untagged enum"), "{err}");
    }
}

#[test]
fn a_prediction_that_cannot_work_is_refused_before_the_fit_naming_its_scene() {
    let dir = tempfile::tempdir().unwrap();
    let gas = write(dir.path(), "gas.toml", GAS_SCENE);
    let start = std::time::Instant::now();
    let err = run_fails(
        traxer()
            .arg("fit-figure-error")
            .arg(repo().join("scenes/panter_al_ka.toml"))
            .args([
                "--target-hpd",
                "206",
                "--target-c80",
                "397",
                "--target-c90",
                "549",
            ])
            .arg("--predict")
            .arg(&gas)
            .args(["-q", "-o"])
            .arg(dir.path().join("fit")),
        2,
    );
    assert!(
        err.contains("--predict") && err.contains("gas.toml") && err.contains("no mirror"),
        "{err}"
    );
    // Refused before the fit (which takes minutes), and nothing written.
    assert!(start.elapsed().as_secs() < 30);
    assert!(!dir.path().join("fit").exists());
}

#[test]
fn lab_energy_tables_and_gas_mixtures_name_the_line_and_the_part() {
    let dir = tempfile::tempdir().unwrap();
    let trace_error = |scene: &str| {
        let path = write(dir.path(), "s.toml", scene);
        run_fails(
            traxer()
                .arg("trace")
                .arg(&path)
                .args(["-n", "10", "-q", "-o"])
                .arg(dir.path().join("o")),
            2,
        )
    };
    // The file's line 6 (after a comment, a blank line and the header), not the
    // data row 3.
    write(
        dir.path(),
        "t.csv",
        "# a tube spectrum\n\nenergy_keV,density\n1.0,1.0\n2.0,2.0\n1.5,1.0\n",
    );
    let table = GAS_SCENE.replace(
        "energy = { line = \"$energy\" }",
        "energy = { table = \"t.csv\" }",
    );
    let err = trace_error(&table);
    assert!(err.contains("t.csv") && err.contains("line 6"), "{err}");
    for (mixture, says) in [
        ("{ Ar = 0.0, C4H10 = 1.0 }", "Ar = 0: a part's fraction"),
        ("{ Ar = -0.5, C4H10 = 1.5 }", "Ar = -0.5: a part's fraction"),
        ("{}", "mixture is empty"),
    ] {
        let scene = GAS_SCENE.replace("{ Ar = 0.977, C4H10 = 0.023 }", mixture);
        let err = trace_error(&scene);
        assert!(err.contains(says), "{mixture}: {err}");
    }
}

#[test]
fn messages_name_the_cli_options_and_print_numbers_readably() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "gas.toml", GAS_SCENE);
    // The CLI's own option, not Python's `photon_list=`.
    let err = run_fails(
        traxer()
            .arg("trace")
            .arg(&scene)
            .args(["--photon-list", "99999999999", "-n", "10", "-q", "-o"])
            .arg(dir.path().join("o")),
        2,
    );
    assert!(err.contains("--photon-list 99999999999"), "{err}");
    assert!(!err.contains("photon_list="), "{err}");
    // Tiny and huge values as 1e-300, never as 300 digits.
    for (args, says) in [
        (
            vec![
                "trace",
                scene.to_str().unwrap(),
                "-D",
                "energy=1e-300",
                "-n",
                "10",
            ],
            "1e-300",
        ),
        (vec!["solar-flux", "--distance-au", "1e300"], "1e300"),
        (
            vec![
                "reflectivity",
                "--coating",
                "gold",
                "--energy",
                "1e-300",
                "--angle",
                "1",
                "--plot",
                "r.png",
            ],
            "1e-300 keV",
        ),
        (
            vec![
                "trace",
                scene.to_str().unwrap(),
                "--checkpoint-every",
                "1e300",
                "-n",
                "10",
            ],
            "1e300",
        ),
    ] {
        let err = run_fails(
            traxer()
                .current_dir(dir.path())
                .args(&args)
                .args(if args[0] == "reflectivity" {
                    vec!["-q"]
                } else {
                    vec!["-q", "-o", "o"]
                }),
            2,
        );
        assert!(err.contains(says) && err.len() < 600, "{args:?}: {err}");
    }
    // A grazing angle beyond 90° is refused (it gave R = 2.2e7 at 1e300°).
    let err = run_fails(
        traxer().current_dir(dir.path()).args([
            "reflectivity",
            "--coating",
            "gold",
            "--energy",
            "1",
            "--angle",
            "1e300",
        ]),
        2,
    );
    assert!(err.contains("a grazing angle is 0° to 90°"), "{err}");
}

#[test]
fn a_merge_keeps_the_results_of_another_run_unless_asked_to_replace_them() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "gas.toml", GAS_SCENE);
    let d = |n: &str| dir.path().join(n);
    for (seed, k) in [("1", "1"), ("1", "2"), ("2", "1"), ("2", "2")] {
        run_ok(
            traxer()
                .arg("trace")
                .arg(&scene)
                .args([
                    "-n",
                    "2000",
                    "-s",
                    seed,
                    "--shard",
                    &format!("{k}/2"),
                    "-q",
                    "-o",
                ])
                .arg(d(&format!("s{seed}_{k}"))),
        );
    }
    let merge = |seed: &str, extra: &[&str]| {
        let mut c = traxer();
        c.args(["merge", "-q", "-o"])
            .arg(d("merged"))
            .arg(d(&format!("s{seed}_1")))
            .arg(d(&format!("s{seed}_2")))
            .args(extra);
        c
    };
    run_ok(&mut merge("1", &[]));
    let err = run_fails(&mut merge("2", &[]), 2);
    assert!(
        err.contains("seed 2, not 1") && err.contains("--replace"),
        "{err}"
    );
    run_ok(&mut merge("1", &[]));
    run_ok(&mut merge("2", &["--replace"]));
}
