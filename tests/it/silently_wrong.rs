//! Places where traxer once returned a plausible number that was wrong, or
//! ignored what it was told (issue 39): each is now computed right or refused by
//! name, and each test here failed before.

use crate::common::{repo, run_fails, run_ok, traxer, write};
use std::path::Path;

/// A parallel beam of radius 3 mm falling straight onto a gas detector (the
/// CAST GridPix's argon/isobutane at 1050 mbar, 30 mm drift): no mirror, no
/// window, so the area for X-rays converting in the gas is π r² · P(E).
pub(crate) const GAS_SCENE: &str = r#"
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

#[test]
fn a_sensor_that_sees_the_source_past_the_mirrors_or_circles_beyond_its_edge_is_named() {
    // Before: both ran with exit 0 and nothing on stderr (a sensor in front of
    // the optic gave an "HPD" of 2479″ drawn beyond the sensor's edge).
    let dir = tempfile::tempdir().unwrap();
    // The beam falls 5 mm off the centre of the 14 mm chip; a mirror beside
    // it, which no photon reaches.
    let text = GAS_SCENE.replace("center = [0, 0, 10]", "center = [5, 0, 10]")
        + "\n[[objects]]\nname = \"flat\"\nmaterial = \"mirror\"\nshape = { type = \"rectangle\", size = [10.0, 10.0] }\ntransform = [ { translate = [50, 0, 0] } ]\n";
    let scene = write(dir.path(), "s.toml", &text);
    let out = run_ok(
        traxer()
            .args(["trace", "-n", "20000", "-q", "-o"])
            .arg(dir.path().join("o"))
            .arg(&scene),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("none of the") && err.contains("was reflected by a mirror"),
        "{err}"
    );
    assert!(
        err.contains("80 % circle") && err.contains("beyond the sensor"),
        "{err}"
    );
    // Centred and without the mirror: neither.
    let scene = write(dir.path(), "t.toml", GAS_SCENE);
    let out = run_ok(
        traxer()
            .args(["trace", "-n", "20000", "-q", "-o"])
            .arg(dir.path().join("p"))
            .arg(&scene),
    );
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_run_whose_weights_cannot_be_tallied_is_refused_and_writes_nothing() {
    // Before: WeightSum::of(NaN) counted 0 (and a huge weight saturated), so
    // a magnet whose P came out NaN gave empty-looking but plausible images.
    // Here the magnet's unit of weight is made NaN: every recorded photon's
    // weight is NaN, and the run must refuse, naming the count, in memory and
    // into a folder (left without results).
    use traxer::run::{Invocation, RunSettings, TraceJob};
    use traxer::trace::RunConfig;
    let device = traxer::embree::Device::new().unwrap();
    let defines = ["magnet=true".to_string(), "pixels=50".to_string()];
    let mut scene = traxer::scene::Scene::load(
        &device,
        &repo().join("scenes/cast_axion_image.toml"),
        &defines,
    )
    .unwrap();
    let mut magnet = (**scene.magnet.as_ref().unwrap()).clone();
    magnet.weight_scale = f64::NAN;
    scene.magnet = Some(std::sync::Arc::new(magnet));
    let job = TraceJob {
        scene: &scene,
        embree_version: String::new(),
        cfg: RunConfig::new(2000, 1),
        shard: traxer::run::Shard::whole(2000),
    };
    struct Quiet;
    impl traxer::run::RunControl for Quiet {
        fn advance(&self, _: u64) {}
    }
    let invocation = Invocation::new(["test"]);
    let e = job
        .run_in_memory(&invocation, &Quiet)
        .err()
        .expect("refused");
    let text = e.to_string();
    assert!(e.is_bad_input(), "{text}");
    assert!(
        text.contains("recorded photons carried a weight that is not a number"),
        "{text}"
    );
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let e = job
        .run(&out, &RunSettings::default(), &invocation, &Quiet)
        .err()
        .expect("refused");
    assert!(e.to_string().contains("nothing was written"), "{e}");
    let left: Vec<_> = std::fs::read_dir(&out)
        .map(|d| d.filter_map(|e| e.ok()).map(|e| e.file_name()).collect())
        .unwrap_or_default();
    assert!(
        !left.iter().any(|n| n == "summary.json" || n == "chip.npy"),
        "{left:?}"
    );
}
