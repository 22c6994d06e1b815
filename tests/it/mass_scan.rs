//! A magnet's mass scan: the images of a list of axion masses from one run
//! are the images of direct traces at those masses (the same photons, each
//! weight times its own path's P(m_k) / P(m_scene)), and each mass's
//! per-process images add up to its total.

use crate::common::{repo, run_fails, run_ok, traxer};
use traxer::scene::Scene;
use traxer::trace::{run, RunConfig};

fn traced(scene: &str, defines: &[String], photons: u64) -> (Scene, traxer::trace::RunResult) {
    let path = repo().join("scenes").join(scene);
    let s = Scene::load(&crate::common::device(), &path, defines).unwrap();
    let r = run(&s, &RunConfig::new(photons, 11)).unwrap();
    (s, r)
}

/// max |a − b| over the pixels, relative to the largest pixel of `b`.
fn worst(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let top = b.iter().cloned().fold(0.0, f64::max);
    assert!(top > 0.0, "an empty image proves nothing");
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / top
}

/// The scan of `masses` in a trace at `scene_mass` against direct traces.
fn check_scan(name: &str, base: &[&str], (scene_mass, masses): (f64, &[f64]), photons: u64) {
    let list: Vec<String> = masses.iter().map(|m| m.to_string()).collect();
    let mut defines: Vec<String> = base.iter().map(|d| d.to_string()).collect();
    defines.push(format!("axion_masses_ev=[{}]", list.join(",")));
    defines.push(format!("axion_mass_ev={scene_mass}"));
    let (scene, scan) = traced(name, &defines, photons);
    let unit = scene.rate_per_unit_weight(photons).unwrap();
    let image = &scan.images[0];
    assert_eq!(image.masses.images.len(), masses.len());
    for (k, m) in masses.iter().enumerate() {
        let mut direct = base.iter().map(|d| d.to_string()).collect::<Vec<_>>();
        direct.push(format!("axion_mass_ev={m}"));
        let (ds, d) = traced(
            scene.path.file_name().unwrap().to_str().unwrap(),
            &direct,
            photons,
        );
        // The same photons in the same pixels: only the order of the
        // multiplications differs (a few ulp per photon), and the units are
        // the same (P_max does not depend on the mass).
        assert_eq!(ds.rate_per_unit_weight(photons).unwrap(), unit);
        let mass = traxer::sensor::exact::values(&image.masses.images[k].flux_sum);
        let w = worst(&mass, &d.images[0].flux());
        assert!(w < 1e-12, "{name} m_a = {m} eV: scan vs direct {w:e}");
        // The mass's processes add up to its total, as the direct trace's do.
        let processes = &image.masses.images[k].processes;
        if !processes.images.is_empty() {
            // Primakoff and ABC add up to the total (ABC's four to ABC).
            let names = &scene.sensors[0].processes;
            let total: f64 = names
                .iter()
                .zip(processes.totals())
                .filter(|(n, _)| *n == "primakoff" || *n == "abc")
                .map(|(_, t)| t)
                .sum();
            let t = image.masses.totals()[k];
            assert!(
                (total - t).abs() <= 1e-12 * t,
                "m_a = {m}: {total:e} vs {t:e}"
            );
            for (a, b) in processes
                .totals()
                .iter()
                .zip(d.images[0].processes.totals())
            {
                assert!(
                    (a - b).abs() <= 1e-12 * b,
                    "m_a = {m}: process {a:e} vs {b:e}"
                );
            }
        }
    }
}

#[test]
fn a_mass_scan_of_babyiaxo_through_its_field_map_equals_direct_traces() {
    // The real map (each path its own P), Primakoff + ABC (two processes),
    // the scene's mass 0.01 eV, masses across the loss of coherence.
    check_scan(
        "babyiaxo_axion_image.toml",
        &["magnet=true", "emission=primakoff+abc"],
        (0.01, &[0.0, 0.02, 0.05, 0.2]),
        8000,
    );
}

#[test]
fn a_mass_scan_in_helium_equals_direct_traces() {
    // CAST's uniform field with helium: coherence restored at m_γ, the
    // X-rays absorbed on the way out.
    check_scan(
        "cast_axion_image.toml",
        &["magnet=true", "helium_mbar=10", "helium_k=1.8"],
        (0.0, &[0.3, 0.3331, 0.36]),
        20000,
    );
}

#[test]
fn masses_on_the_command_line_write_the_stack_and_bad_ones_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let scene = repo().join("scenes/cast_axion_image.toml");
    run_ok(
        traxer()
            .arg("trace")
            .arg(&scene)
            .args([
                "-n",
                "4000",
                "-q",
                "-D",
                "magnet=true",
                "--masses",
                "0,0.02",
                "-o",
            ])
            .arg(&out),
    );
    let stack = traxer::output::read_npy(&out.join("chip_by_mass.npy")).unwrap();
    let total = traxer::output::read_npy(&out.join("chip.npy")).unwrap();
    assert_eq!(stack.0[0], 2, "{:?}", stack.0);
    let first = &stack.1[..total.1.len()];
    assert!(
        worst(first, &total.1) < 1e-12,
        "m_a = 0 is the scene's own mass"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("chip.json")).unwrap()).unwrap();
    let masses = &v["sensor"]["by_mass"]["masses"];
    let (m0, m1) = (
        masses[0]["total_flux"].as_f64().unwrap(),
        masses[1]["total_flux"].as_f64().unwrap(),
    );
    assert!(
        m1 < m0 && m1 > 0.0,
        "0.02 eV loses coherence in CAST: {m1:e} vs {m0:e}"
    );
    for bad in [["--masses", "0,-1"], ["--masses", "a"]] {
        let err = run_fails(
            traxer()
                .arg("trace")
                .arg(&scene)
                .args(["-D", "magnet=true", "-o"])
                .arg(dir.path().join("bad"))
                .args(bad),
            2,
        );
        assert!(err.contains("--masses"), "{err}");
    }
    // Without the magnet a mass scan means nothing: refused, not ignored.
    let err = run_fails(
        traxer()
            .arg("trace")
            .arg(&scene)
            .args(["-D", "magnet=false", "--masses", "0.01", "-o"])
            .arg(dir.path().join("off")),
        2,
    );
    assert!(err.contains("needs the magnet on"), "{err}");
    assert!(!dir.path().join("bad").exists() && !dir.path().join("off").exists());
}

#[test]
fn a_mass_scan_cut_into_shards_merges_to_the_whole_run_bit_for_bit() {
    // The mass images are exact sums like the total: two shards merged give
    // the whole run's NAME_by_mass.npy to the bit.
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/cast_axion_image.toml");
    let trace = |out: &str, shard: Option<&str>| {
        let mut c = traxer();
        c.arg("trace")
            .arg(&scene)
            .args(["-n", "30000", "-q", "-D", "magnet=true"]);
        c.args(["--masses", "0,0.015,0.03", "-o"])
            .arg(dir.path().join(out));
        if let Some(s) = shard {
            c.args(["--shard", s]);
        }
        run_ok(&mut c);
    };
    trace("one", None);
    trace("s1", Some("1/2"));
    trace("s2", Some("2/2"));
    run_ok(
        traxer()
            .args(["merge", "-q", "-o"])
            .arg(dir.path().join("merged"))
            .arg(dir.path().join("s2"))
            .arg(dir.path().join("s1")),
    );
    let bytes = |d: &str| std::fs::read(dir.path().join(d).join("chip_by_mass.npy")).unwrap();
    assert_eq!(bytes("one"), bytes("merged"));
}
