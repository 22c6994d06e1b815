//! Refusals and messages that point at the cause (issue 39, part 3): a FITS
//! header's sizes checked before allocating, a study running in a folder, the
//! forms roughness takes, predictions that cannot work, a lab table's file
//! line, a gas mixture's bad part, the CLI's own option names and readable
//! numbers. Each test failed before.

use crate::common::{repo, run_fails, run_ok, traxer, write};
use crate::silently_wrong::GAS_SCENE;

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
fn a_psf_library_refuses_a_negative_off_axis_angle() {
    // Before: psf.fits got THETA = −5, a point SIXTE never looks up.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p");
    let err = crate::common::run_fails(
        crate::common::traxer()
            .arg("psf")
            .arg(crate::common::repo().join("scenes/xmm_effective_area.toml"))
            .args(["--angles", "-5", "-n", "100", "-q", "-o"])
            .arg(&out),
        2,
    );
    assert!(
        err.contains("-5′ is negative") && err.contains("--angles 5"),
        "{err}"
    );
    assert!(!out.exists(), "nothing written");
}
