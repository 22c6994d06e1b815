//! Effective area against closed forms: the LLNL telescope's collecting area from
//! a 2-D ray cast in the meridional plane (independent of the 3-D tracer), one
//! shell's area × R·R at its grazing angles, and the meshed telescope against the
//! analytic one.

use traxer::scene::telescope::Telescope;
use traxer::scene::Scene;
use traxer::studies::effective_area::{sweep, AreaResult, AreaSweep};
use traxer::xray::CoatingLibrary;

/// The shipped parallel-beam scene with `defines`, and an optional extra line in
/// the assembly table.
fn llnl_scene(defines: &[&str], assembly_extra: &str) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    let mut text =
        std::fs::read_to_string(crate::common::repo().join("scenes/llnl_effective_area.toml"))
            .unwrap();
    text = text.replace(
        "figure_error = \"$figure_error\"\n",
        &format!("figure_error = \"$figure_error\"\n{assembly_extra}\n"),
    );
    let path = crate::common::write(dir.path(), "scene.toml", &text);
    let defines: Vec<String> = defines.iter().map(|s| s.to_string()).collect();
    Scene::load(&crate::common::device(), &path, &defines).unwrap()
}

fn area(scene: &Scene, energies: &[f64], photons: u64, seed: u64) -> AreaResult {
    let s = AreaSweep {
        energies: energies.to_vec(),
        angles_arcmin: vec![0.0],
        sampling: traxer::studies::Sampling {
            photons,
            seed,
            threads: 0,
            sensor: None,
        },
        radius_mm: None,
    };
    sweep(scene, &s, &[], &(), |_, _| {}).unwrap()
}

/// One straight piece of a shell's cross-section in the meridional half-plane:
/// (r, z) ends, and whether it reflects (a mirror face) or absorbs.
struct Piece {
    a: (f64, f64),
    b: (f64, f64),
    mirror: Option<(usize, bool)>,
}

/// The cross-section of the telescope as traxer's assembly documents it
/// (data/telescopes/llnl.toml): per shell the front and rear mirror faces, the
/// glass behind them (t / cos α further out) and the glass edges.
fn cross_section(t: &Telescope, shells: &[usize]) -> Vec<Piece> {
    let mut pieces = Vec::new();
    let z0 = 0.5 * t.gap_mm;
    for &i in shells {
        let [r1, r2, r4, r5] = t.cone_radii(i);
        let (a, ar) = (t.alpha(i), t.alpha_rear(i));
        let l = t.mirror_length_mm;
        for (near, far, zn, zf, ang, front) in [
            (r2, r1, z0, z0 + l * a.cos(), a, true),
            (r4, r5, -z0, -z0 - l * ar.cos(), ar, false),
        ] {
            let dr = t.thickness(i) / ang.cos();
            pieces.push(Piece {
                a: (near, zn),
                b: (far, zf),
                mirror: Some((i, front)),
            });
            pieces.push(Piece {
                a: (near + dr, zn),
                b: (far + dr, zf),
                mirror: None,
            });
            pieces.push(Piece {
                a: (near, zn),
                b: (near + dr, zn),
                mirror: None,
            });
            pieces.push(Piece {
                a: (far, zf),
                b: (far + dr, zf),
                mirror: None,
            });
        }
    }
    pieces
}

/// Nearest piece hit by the ray p + s·d (s > 1e-9), with its parameter.
fn cast(
    pieces: &[Piece],
    p: (f64, f64),
    d: (f64, f64),
    skip: Option<usize>,
) -> Option<(usize, f64)> {
    let mut best: Option<(usize, f64)> = None;
    for (k, q) in pieces.iter().enumerate() {
        if Some(k) == skip {
            continue;
        }
        let e = (q.b.0 - q.a.0, q.b.1 - q.a.1);
        let den = d.0 * e.1 - d.1 * e.0;
        if den.abs() < 1e-300 {
            continue;
        }
        let w = (q.a.0 - p.0, q.a.1 - p.1);
        let s = (w.0 * e.1 - w.1 * e.0) / den;
        let u = (w.0 * d.1 - w.1 * d.0) / den;
        if s > 1e-9 && (0.0..=1.0).contains(&u) && best.is_none_or(|b| s < b.1) {
            best = Some((k, s));
        }
    }
    best
}

/// Whether an axial ray at radius ρ reflects front i → rear i and then leaves.
fn focused(pieces: &[Piece], rho: f64) -> bool {
    let (mut p, mut d) = ((rho, 300.0), (0.0, -1.0));
    let mut skip = None;
    let mut seen = Vec::new();
    while let Some((k, s)) = cast(pieces, p, d, skip) {
        let q = &pieces[k];
        let Some(m) = q.mirror else { return false };
        seen.push(m);
        p = (p.0 + s * d.0, p.1 + s * d.1);
        let e = (q.b.0 - q.a.0, q.b.1 - q.a.1);
        let n = {
            let len = e.0.hypot(e.1);
            (-e.1 / len, e.0 / len)
        };
        let dn = d.0 * n.0 + d.1 * n.1;
        d = (d.0 - 2.0 * dn * n.0, d.1 - 2.0 * dn * n.1);
        skip = Some(k);
        if seen.len() > 2 {
            return false;
        }
    }
    seen.len() == 2 && seen[0].1 && !seen[1].1 && seen[0].0 == seen[1].0
}

/// (π/6) ∫ focused(ρ) ρ dρ over the shells' entrance, in cm²: the 30° segments'
/// collecting area for two reflections, minus what the glass shadows.
fn closed_form_area(t: &Telescope, shells: &[usize]) -> f64 {
    let pieces = cross_section(t, shells);
    let (lo, hi, n) = (50.0, 108.0, 400_000);
    let h = (hi - lo) / n as f64;
    let mut sum = 0.0;
    for k in 0..n {
        let rho = lo + (k as f64 + 0.5) * h;
        if focused(&pieces, rho) {
            sum += rho * h;
        }
    }
    t.azimuth_span_deg.to_radians() * sum / 100.0
}

#[test]
fn perfect_mirrors_collect_the_closed_form_area_on_axis() {
    let t = Telescope::shipped("llnl").unwrap();
    let want = closed_form_area(&t, &(0..13).collect::<Vec<_>>());
    let scene = llnl_scene(&["coating=perfect", "figure_error=none"], "");
    let r = area(&scene, &[1.49], 400_000, 11);
    let a = &r.angles[0];
    let got = a.points[0].by_class_cm2[1]; // front then rear
                                           // Monte Carlo: σ = A_beam·√(p(1−p)/N) ≈ 0.023 cm²; 4σ.
    let sigma = r.aperture_cm2 * (got / r.aperture_cm2 * (1.0 - got / r.aperture_cm2) / 4e5).sqrt();
    assert!(
        (got - want).abs() < 4.0 * sigma,
        "front_rear area {got} cm², closed form {want} ± {sigma}"
    );
    // With R = 1 nearly all the area is the focused one.
    assert!(a.points[0].area_cm2 - got < 0.01 * got, "{:?}", a.points[0]);
}

#[test]
fn one_gold_shell_has_its_geometric_area_times_both_reflectivities() {
    // Shell 7 alone, bare gold. On axis every focused photon meets the front cone
    // at its angle α and the rear cone, whose surface makes α_rear with the axis,
    // at α_rear − 2α ≈ α (the ray leaves the front mirror at 2α to the axis): the
    // equal-angle design. (The rear cone's 3α is its angle to the axis, not the
    // grazing angle.) The area is the shell's geometric area × R(E, α)·R(E, α_r − 2α).
    let dir = tempfile::tempdir().unwrap();
    let mut t = Telescope::shipped("llnl").unwrap();
    t.shells = vec![t.shells[6].clone()];
    let data =
        std::fs::read_to_string(crate::common::repo().join("data/telescopes/llnl.toml")).unwrap();
    let head: String = data
        .lines()
        .take_while(|l| !l.starts_with("shells"))
        .map(|l| format!("{l}\n"))
        .collect();
    let [r1, r2, r4, r5] = t.cone_radii(0);
    let one = format!(
        "{head}shells = [ {{ r1_mm = {r1}, r2_mm = {r2}, r4_mm = {r4}, r5_mm = {r5}, coating = \"bare_gold\" }} ]\n"
    );
    let data_path = crate::common::write(dir.path(), "one_shell.toml", &one);
    let scene = llnl_scene(
        &["figure_error=none"],
        &format!("data = {:?}", data_path.display().to_string()),
    );
    let energies = [1.0, 2.0, 3.0, 5.0, 8.0];
    let r = area(&scene, &energies, 400_000, 12);
    let a = &r.angles[0];
    let geometric = a.geometric_area_cm2;
    let want_geometric = closed_form_area(&t, &[0]);
    let p = geometric / r.aperture_cm2;
    let sigma = r.aperture_cm2 * (p * (1.0 - p) / 4e5).sqrt();
    assert!(
        (geometric - want_geometric).abs() < 4.0 * sigma,
        "{geometric} vs {want_geometric}"
    );
    let gold = CoatingLibrary::shipped().coating("bare_gold").unwrap();
    let (alpha, rear) = (t.alpha(0), t.alpha_rear(0) - 2.0 * t.alpha(0));
    for pt in &a.points {
        let rr = gold.reflectivity(pt.energy_kev, alpha).unwrap()
            * gold.reflectivity(pt.energy_kev, rear).unwrap();
        // Only two-reflection photons reach the sensor here, so the ratio is exact
        // up to the reflectivity table's interpolation (below 1e-3, tested in
        // xray.rs): 2e-3.
        let ratio = pt.area_cm2 / geometric;
        assert!(
            (ratio / rr - 1.0).abs() < 2e-3,
            "{} keV: A/A_geo = {ratio}, R·R = {rr}",
            pt.energy_kev
        );
        // The R(E, α)·R(E, 3α) is a different number above the critical
        // angle: the test can tell them apart.
        let wrong = gold.reflectivity(pt.energy_kev, alpha).unwrap()
            * gold.reflectivity(pt.energy_kev, 3.0 * alpha).unwrap();
        if pt.energy_kev >= 3.0 {
            assert!((ratio / wrong - 1.0).abs() > 0.05, "{} keV", pt.energy_kev);
        }
    }
}

#[test]
fn the_meshed_telescope_has_the_area_of_the_analytic_one() {
    let mesh = crate::common::repo().join("meshes/llnl_telescope.glb");
    let meshed = llnl_scene(&[], &format!("mesh = {:?}", mesh.display().to_string()));
    let analytic = llnl_scene(&[], "");
    let energies = [1.5, 3.0, 4.5, 6.0, 8.0];
    let (a, m) = (
        area(&analytic, &energies, 300_000, 13),
        area(&meshed, &energies, 300_000, 13),
    );
    for (pa, pm) in a.angles[0].points.iter().zip(&m.angles[0].points) {
        // The same photons (same seed): the difference is the facets' (60 per
        // 30° segment) slightly different shadowing, well below 1 %; both errors
        // added as a bound for the rest.
        let bound = 0.01 * pa.area_cm2 + 3.0 * (pa.error_cm2 + pm.error_cm2);
        assert!(
            (pa.area_cm2 - pm.area_cm2).abs() < bound,
            "{pa:?} vs {pm:?}"
        );
    }
}

#[test]
fn effective_area_command_writes_its_files_the_same_on_any_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let scene = crate::common::repo().join("scenes/llnl_effective_area.toml");
    let run = |threads: &str, out: &str| {
        crate::common::run_ok(
            crate::common::traxer()
                .arg("effective-area")
                .arg(&scene)
                .args([
                    "--energies",
                    "1:3:0.5",
                    "--angles",
                    "0,6",
                    "-n",
                    "20000",
                    "-q",
                ])
                .args(["--radius", "2.0", "-j", threads, "-o"])
                .arg(dir.path().join(out)),
        );
        std::fs::read_to_string(dir.path().join(out).join("effective_area.csv")).unwrap()
    };
    let one = run("1", "a");
    assert_eq!(one, run("2", "b"));
    // A header and 5 energies × 2 angles.
    assert_eq!(one.lines().count(), 11);
    assert!(one.starts_with(
        "off_axis_arcmin,energy_keV,area_cm2,error_cm2,area_direct_cm2,area_front_rear_cm2"
    ));
    for f in traxer::output::EFFECTIVE_AREA_FILES.all() {
        assert!(dir.path().join("a").join(f).is_file(), "{f}");
    }
}

#[test]
fn effective_area_refuses_what_it_cannot_sweep() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let cases: [(&str, &[&str], &str); 5] = [
        (
            "scenes/panter_al_ka.toml",
            &[],
            "exactly one source, of type \"parallel\"",
        ),
        (
            "scenes/llnl_effective_area.toml",
            &["--energies", "0.01,5"],
            "0.03–30 keV",
        ),
        (
            "scenes/llnl_effective_area.toml",
            &["--radius=-1"],
            "(--radius, radius_mm in Python) is -1: it must be a positive length",
        ),
        (
            "scenes/llnl_effective_area.toml",
            &["--radius", "0"],
            "(--radius, radius_mm in Python) is 0:",
        ),
        (
            "scenes/llnl_effective_area.toml",
            &["--radius", "nan"],
            "(--radius, radius_mm in Python) is NaN:",
        ),
    ];
    for (scene, args, message) in cases {
        let err = crate::common::run_fails(
            crate::common::traxer()
                .arg("effective-area")
                .arg(crate::common::repo().join(scene))
                .args(args)
                .args(["-n", "1000", "-q", "-o"])
                .arg(&out),
            2,
        );
        assert!(err.contains(message), "{scene} {args:?}: {err}");
        assert!(!out.exists(), "nothing written");
    }
}

#[test]
fn a_range_of_energies_and_angles_holds_the_numbers_as_written() {
    // Before: 0.1:30:0.1 ended at 30.000000000000004 keV and was refused as
    // beyond the Henke tables; 0:0.3:0.1 named an ARF
    // effective_area_0.30000000000000004arcmin.arf.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a");
    let run = crate::common::run_ok(
        crate::common::traxer()
            .arg("effective-area")
            .arg(crate::common::repo().join("scenes/llnl_effective_area.toml"))
            .args(["--energies", "0.1:30:0.1", "--angles", "0:0.3:0.1"])
            .args(["-n", "200", "-o"])
            .arg(&out),
    );
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(!stdout.contains("0000000"), "{stdout}");
    for angle in ["0", "0.1", "0.2", "0.3"] {
        let arf = out.join(format!("effective_area_{angle}arcmin.arf"));
        assert!(arf.is_file(), "{}", arf.display());
    }
    let csv = std::fs::read_to_string(out.join("effective_area.csv")).unwrap();
    assert!(!csv.contains("0000000"), "{}", &csv[..csv.len().min(2000)]);
    assert!(
        csv.lines().any(|l| l.starts_with("0.3,30,")),
        "{}",
        &csv[..500]
    );
    assert!(
        csv.lines().any(|l| l.starts_with("0.1,12,")),
        "{}",
        &csv[..500]
    );
}
