//! Telescopes as data: the XMM-Newton prescription of
//! data/telescopes/xmm_newton.toml, its shells computed by
//! `geometry::wolter::WolterShell` from R3 and f alone, against the published
//! table they come from (tests/data/xmm_true_wolter.csv, from
//! rest-for-physics/axionlib-data); the traced module against its geometric
//! area and its focus; every shipped telescope's parts.

use crate::common::repo;
use traxer::geometry::wolter::WolterShell;

#[derive(serde::Deserialize)]
struct Telescope {
    focal_length_mm: f64,
    mirror_length_mm: f64,
    profile: String,
    shells: Vec<Shell>,
}

#[derive(serde::Deserialize)]
struct Shell {
    r3_mm: f64,
    thickness_mm: f64,
}

/// (shell, R1, R3, R5, angle) of the published XMM.trueWolter table.
fn published() -> Vec<(usize, f64, f64, f64, f64)> {
    let text = std::fs::read_to_string(repo().join("tests/data/xmm_true_wolter.csv")).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("shell"))
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            (v[0] as usize, v[1], v[2], v[3], v[4])
        })
        .collect()
}

#[test]
fn the_xmm_shells_reproduce_the_published_radii_and_angles() {
    let text = std::fs::read_to_string(repo().join("data/telescopes/xmm_newton.toml")).unwrap();
    let t: Telescope = toml::from_str(&text).unwrap();
    assert_eq!(t.profile, "wolter1");
    assert_eq!(t.shells.len(), 58);
    let table = published();
    assert_eq!(table.len(), 58);
    let mut r3_taken_from_the_other_file = Vec::new();
    for (shell, (number, r1, r3, r5, angle)) in t.shells.iter().zip(table) {
        assert!(shell.thickness_mm > 0.4 && shell.thickness_mm < 1.1);
        if shell.r3_mm != r3 {
            r3_taken_from_the_other_file.push(number);
        }
        let s = WolterShell::new(t.focal_length_mm, shell.r3_mm).unwrap();
        // The table's angles are rounded to 0.001°.
        assert!(
            (s.alpha.to_degrees() - angle).abs() <= 0.0005 + 1e-12,
            "shell {number}: α = {}° vs {angle}°",
            s.alpha.to_degrees()
        );
        // R1 and R5 at the ends of the 300 mm surfaces, to the table's
        // rounding (its last digit is 0.5 µm).
        let (p, h) = (
            s.paraboloid_radius(t.mirror_length_mm),
            s.hyperboloid_radius(-t.mirror_length_mm),
        );
        assert!((h - r5).abs() < 1e-3, "shell {number}: R5 {h} vs {r5}");
        if number == 46 {
            // The table's R1 of shell 46 is one digit off (294.178 for 294.278).
            assert!(((p - r1) - 0.1).abs() < 1e-3, "shell 46: R1 {p} vs {r1}");
        } else {
            assert!((p - r1).abs() < 1e-3, "shell {number}: R1 {p} vs {r1}");
        }
    }
    // Exactly the two shells whose R3 the table's own R1 and R5 contradict.
    assert_eq!(r3_taken_from_the_other_file, vec![12, 46]);
}

/// The XMM-Newton parallel-beam scene with `defines`.
fn xmm_scene(defines: &[&str]) -> traxer::scene::Scene {
    let defines: Vec<String> = defines.iter().map(|s| s.to_string()).collect();
    traxer::scene::Scene::load(
        &crate::common::device(),
        &repo().join("scenes/xmm_effective_area.toml"),
        &defines,
    )
    .unwrap()
}

/// The on-axis area (cm²) counting two reflections, and its Monte-Carlo error.
fn xmm_area(defines: &[&str], photons: u64) -> (f64, f64, f64) {
    use traxer::studies::effective_area::{sweep, AreaSweep};
    let s = AreaSweep {
        energies: vec![1.5],
        angles_arcmin: vec![0.0],
        sampling: traxer::studies::Sampling {
            photons,
            seed: 5,
            threads: 0,
            sensor: None,
        },
        radius_mm: None,
    };
    let r = sweep(&xmm_scene(defines), &s, &[], &(), |_, _| {}).unwrap();
    let p = &r.angles[0].points[0];
    let got = p.by_class_cm2[1]; // front then rear
                                 // Binomial error of a fraction of the beam's aperture.
    let f = got / r.aperture_cm2;
    let sigma = r.aperture_cm2 * (f * (1.0 - f) / photons as f64).sqrt();
    (got, sigma, p.area_cm2)
}

/// Σ π (R1² − R3²) over the 58 shells, cm², from the prescription alone: the
/// annulus of the entrance each paraboloid catches on axis.
fn xmm_geometric_area_cm2() -> f64 {
    let text = std::fs::read_to_string(repo().join("data/telescopes/xmm_newton.toml")).unwrap();
    let t: Telescope = toml::from_str(&text).unwrap();
    let f = t.focal_length_mm;
    t.shells
        .iter()
        .map(|s| {
            // The paraboloid through R3 with slope tan α there (α = ¼ atan(R3/f)),
            // r² = R3² + 2 R3 tan α · z, evaluated at the entrance z = 300 mm.
            let r3 = s.r3_mm;
            let alpha = (r3 / f).atan() / 4.0;
            let r1_sq = r3 * r3 + 2.0 * r3 * alpha.tan() * t.mirror_length_mm;
            std::f64::consts::PI * (r1_sq - r3 * r3)
        })
        .sum::<f64>()
        / 100.0
}

#[test]
fn perfect_xmm_shells_collect_their_geometric_area_and_the_spider_shades_its_share() {
    // R = 1, no spider: every X-ray entering between R3 and R1 of a shell is
    // reflected twice (the shells do not shade each other on axis), so the
    // traced area is Σπ(R1² − R3²) within the Monte-Carlo error (4σ: fails
    // once in ~16 000 seeds).
    let want = xmm_geometric_area_cm2();
    assert!((want - 2152.6).abs() < 0.5, "Σπ(R1² − R3²) = {want} cm²");
    let (open, sigma, all) = xmm_area(&["coating=perfect", "spider=false"], 400_000);
    assert!(
        (open - want).abs() < 4.0 * sigma,
        "traced {open} ± {sigma} cm², geometric {want} cm²"
    );
    // Nothing else reaches the sensor on axis (no single reflections).
    assert!(all - open < 1e-9 * all, "{all} vs {open}");
    // The spider's 16 arms of 2.29° block 16·2.29/360 = 10.18 % of every annulus.
    let (shaded, sigma_s, _) = xmm_area(&["coating=perfect"], 400_000);
    let blocked = 1.0 - 16.0 * 2.29 / 360.0;
    let err = (sigma_s * sigma_s + (blocked * sigma).powi(2)).sqrt();
    assert!(
        (shaded - blocked * open).abs() < 4.0 * err,
        "with the spider {shaded} ± {sigma_s} cm², expected {}",
        blocked * open
    );
}

#[test]
fn the_xmm_module_focuses_a_parallel_beam_at_7500_mm_to_a_point() {
    use traxer::trace::RunConfig;
    // A true Wolter-I shell images an axial beam to a point: at the design
    // focus every photon lands within a pixel or two of the axis (50 µm pixels),
    // 5 mm before or after it the image is a ring of radius 5 mm · tan 4α ≥ 0.1 mm.
    let rms_at = |z: f64| {
        let scene = xmm_scene(&["coating=perfect", &format!("sensor_z={z}")]);
        let r = traxer::trace::run(&scene, &RunConfig::new(100_000, 3)).unwrap();
        assert!(r.stats.reached_sensor > 40_000, "{:?}", r.stats);
        let flux = r.images[0].flux();
        let n = 2000;
        let (mut w, mut sx, mut sy, mut sr) = (0.0, 0.0, 0.0, 0.0);
        for (k, v) in flux.iter().enumerate() {
            let (x, y) = ((k % n) as f64 - 1000.0 + 0.5, (k / n) as f64 - 1000.0 + 0.5);
            w += v;
            sx += v * x;
            sy += v * y;
            sr += v * (x * x + y * y);
        }
        let (cx, cy) = (sx / w, sy / w);
        0.05 * (sr / w - cx * cx - cy * cy).sqrt()
    };
    let (focus, before, after) = (rms_at(-7500.0), rms_at(-7495.0), rms_at(-7505.0));
    assert!(
        focus < 0.05,
        "rms at 7500 mm: {focus} mm (one pixel is 0.05 mm)"
    );
    assert!(
        before > 0.1 && after > 0.1,
        "rms 5 mm off focus: {before} / {after} mm"
    );
}

#[test]
fn every_shipped_telescope_builds_with_its_parts_tagged() {
    // Each data/telescopes/*.toml parses, passes its checks and expands into
    // mirrors tagged with their shell and stage, walls and (XMM) the spider.
    use traxer::scene::telescope_parts::PartChoices;
    let mut names = Vec::new();
    for (name, _) in traxer::scene::telescope::SHIPPED {
        let t = traxer::scene::telescope::Telescope::shipped(name).unwrap();
        let parts = t.parts(&PartChoices {
            spider_distance_mm: Some(20.0),
            central_stop: true,
            ..Default::default()
        });
        let mirrors = parts.iter().filter(|p| p.stage.is_some()).count();
        assert_eq!(mirrors, 2 * t.shells.len(), "{name}");
        assert!(parts.iter().all(|p| p.stage.is_none() || p.shell.is_some()));
        let spider_arms = parts
            .iter()
            .filter(|p| p.name.starts_with("spider_"))
            .count();
        assert_eq!(
            spider_arms,
            t.spider.as_ref().map_or(0, |s| s.arms as usize)
        );
        assert_eq!(parts.last().unwrap().name, "central_stop");
        names.push(name);
    }
    assert_eq!(names, ["llnl", "wolter1_demo", "xmm_newton"]);
}

/// A two-shell Wolter-I prescription (`extra` lines per shell 2) as a data file
/// beside a scene using it with `assembly` lines; the scene loaded.
fn two_shell_scene(shell_2: &str, assembly: &str) -> traxer::scene::Scene {
    let dir = tempfile::tempdir().unwrap();
    let data = format!(
        "name = \"two shells\"\nprofile = \"wolter1\"\nfocal_length_mm = 1500.0\nmirror_length_mm = 100.0\nwall_thickness_mm = 0.5\ncoating = \"gold\"\nshells = [ {{ r3_mm = 50.0 }}, {{ r3_mm = 60.0{shell_2} }} ]\n"
    );
    crate::common::write(dir.path(), "two.toml", &data);
    let scene = format!(
        "[[sources]]\ntype = \"parallel\"\naperture = {{ center = [0, 0, 200], radius = 70.0 }}\nenergy = {{ line = 1.49 }}\n\n[[assemblies]]\ntype = \"nested_telescope\"\ndata = \"two.toml\"\nname = \"t\"\n{assembly}\n"
    );
    let path = crate::common::write(dir.path(), "scene.toml", &scene);
    traxer::scene::Scene::load(&crate::common::device(), &path, &[]).unwrap()
}

/// The figure errors of the mirror object `name`.
fn figure_of(
    scene: &traxer::scene::Scene,
    name: &str,
) -> Option<traxer::xray::figure_error::FigureError> {
    let o = scene.objects.iter().find(|o| o.name == name).unwrap();
    match o.material {
        traxer::material::Material::Mirror { figure_error, .. } => figure_error,
        other => panic!("{name} is no mirror: {other:?}"),
    }
}

#[test]
fn a_shell_keeps_its_own_figure_errors_unless_the_scene_gives_every_mirror_one() {
    let own = ", figure_error = { in_plane_narrow = 30.0, in_plane_wide = 0.0, wide_fraction = 0.0, out_of_plane = 0.0 }";
    let scene = two_shell_scene(own, "");
    assert!(figure_of(&scene, "t_front_1").is_none());
    let f2 = figure_of(&scene, "t_rear_2").expect("shell 2's own figure errors");
    assert_eq!(f2.in_plane_narrow, 30.0);
    // The scene's figure_error replaces the shells' own, on every mirror.
    let scene = two_shell_scene(own, "figure_error = \"llnl_panter\"");
    let lib = traxer::xray::figure_presets::FigureErrorLibrary::shipped();
    let panter = lib.get("llnl_panter").unwrap();
    for name in ["t_front_1", "t_rear_1", "t_front_2", "t_rear_2"] {
        assert_eq!(figure_of(&scene, name).unwrap(), panter, "{name}");
    }
}

/// Whether the mirror object `name` scatters from microroughness.
fn is_rough(scene: &traxer::scene::Scene, name: &str) -> bool {
    let o = scene.objects.iter().find(|o| o.name == name).unwrap();
    match o.material {
        traxer::material::Material::Mirror { roughness, .. } => roughness.is_some(),
        other => panic!("{name} is no mirror: {other:?}"),
    }
}

#[test]
fn a_shell_may_declare_its_whole_surface_and_the_scene_replaces_it_for_every_mirror() {
    // A shell declares the same surface as a mirror material: coating, figure
    // errors and roughness.
    let own = ", coating = \"perfect\", roughness = \"slumped_glass_limit\"";
    let scene = two_shell_scene(own, "");
    assert!(!is_rough(&scene, "t_front_1") && !is_rough(&scene, "t_rear_1"));
    assert!(is_rough(&scene, "t_front_2") && is_rough(&scene, "t_rear_2"));
    let reflectivity = |name: &str| {
        let o = scene.objects.iter().find(|o| o.name == name).unwrap();
        match o.material {
            traxer::material::Material::Mirror { reflectivity, .. } => reflectivity,
            _ => unreachable!(),
        }
    };
    assert!(
        reflectivity("t_front_1").is_some(),
        "shell 1: the telescope's gold"
    );
    assert!(
        reflectivity("t_front_2").is_none(),
        "shell 2: its own perfect coating"
    );
    // The scene's roughness = "none" replaces the shell's own on every mirror.
    let scene = two_shell_scene(own, "roughness = \"none\"");
    for name in ["t_front_1", "t_rear_1", "t_front_2", "t_rear_2"] {
        assert!(!is_rough(&scene, name), "{name}");
    }
}

#[test]
fn a_traxer_axis_placement_is_refused_for_full_circle_shells() {
    let dir = tempfile::tempdir().unwrap();
    let scene = "[[sources]]\ntype = \"parallel\"\naperture = { center = [0, 0, 400], radius = 360.0 }\nenergy = { line = 1.49 }\n\n[[assemblies]]\ntype = \"nested_telescope\"\ntelescope = \"xmm_newton\"\nspider = false\nshell_axes = \"traxer\"\n";
    let path = crate::common::write(dir.path(), "scene.toml", scene);
    let err = traxer::scene::Scene::load(&crate::common::device(), &path, &[])
        .err()
        .expect("refused")
        .to_string();
    assert!(
        err.contains("shell_axes") && err.contains("cone segments"),
        "{err}"
    );
    // The spider needs a distance the XMM data do not give.
    let scene = scene.replace("spider = false\nshell_axes = \"traxer\"\n", "");
    let path = crate::common::write(dir.path(), "scene.toml", &scene);
    let err = traxer::scene::Scene::load(&crate::common::device(), &path, &[])
        .err()
        .expect("refused")
        .to_string();
    assert!(err.contains("spider_distance"), "{err}");
}

#[test]
fn a_shell_may_have_its_own_length_and_azimuth_span() {
    use traxer::geometry::Shape;
    use traxer::scene::ObjectGeometry;
    let scene = two_shell_scene(", mirror_length_mm = 80.0, azimuth_span_deg = 90.0", "");
    let quadric = |name: &str| {
        let o = scene.objects.iter().find(|o| o.name == name).unwrap();
        match &o.geometry {
            ObjectGeometry::Analytic(a) => match a.shape {
                Shape::Revolution(q) => q,
                other => panic!("{name}: {other:?}"),
            },
            ObjectGeometry::Mesh(_) => panic!("{name} is a mesh"),
        }
    };
    let (p1, p2, h2) = (
        quadric("t_front_1"),
        quadric("t_front_2"),
        quadric("t_rear_2"),
    );
    assert_eq!((p1.z_min, p1.z_max), (0.0, 100.0));
    assert_eq!((p2.z_min, p2.z_max), (0.0, 80.0));
    assert_eq!((h2.z_min, h2.z_max), (-80.0, 0.0));
    assert!(p1.azimuth.is_full());
    assert_eq!(
        (p2.azimuth.start_deg(), p2.azimuth.span_deg()),
        (-45.0, 90.0)
    );
}

/// A user's prescription (`profile`, then the `shells = [...]` body) beside a
/// scene that uses it: the scene's load result.
fn prescription(
    head: &str,
    shells: &str,
) -> Result<traxer::scene::Scene, traxer::scene::SceneError> {
    let dir = tempfile::tempdir().unwrap();
    let data = format!(
        "name = \"mine\"\n{head}\nmirror_length_mm = 100.0\nwall_thickness_mm = 0.5\ncoating = \"gold\"\nshells = [ {shells} ]\n"
    );
    crate::common::write(dir.path(), "mine.toml", &data);
    let scene = "[[sources]]\ntype = \"parallel\"\naperture = { center = [0, 0, 200], radius = 90.0 }\nenergy = { line = 1.49 }\n\n[[assemblies]]\ntype = \"nested_telescope\"\ndata = \"mine.toml\"\ncentral_stop = true\n";
    let path = crate::common::write(dir.path(), "scene.toml", scene);
    traxer::scene::Scene::load(&crate::common::device(), &path, &[])
}

fn refusal(head: &str, shells: &str) -> String {
    match prescription(head, shells) {
        Ok(_) => panic!("{shells}: the prescription should be refused"),
        Err(e) => e.to_string(),
    }
}

const WOLTER: &str = "profile = \"wolter1\"\nfocal_length_mm = 1500.0";

#[test]
fn a_prescription_listed_outermost_first_or_twice_or_with_intersecting_walls_is_refused() {
    // Before: each of these traced without a word (the central stop on the
    // outermost shell took 64 % of the flux in a trial).
    assert!(prescription(
        WOLTER,
        "{ r3_mm = 50.0 }, { r3_mm = 60.0 }, { r3_mm = 70.0 }"
    )
    .is_ok());
    let e = refusal(
        WOLTER,
        "{ r3_mm = 70.0 }, { r3_mm = 60.0 }, { r3_mm = 50.0 }",
    );
    assert!(
        e.contains("innermost first") && e.contains("shell 2") && e.contains("reverse it"),
        "{e}"
    );
    let e = refusal(
        WOLTER,
        "{ r3_mm = 50.0 }, { r3_mm = 70.0 }, { r3_mm = 60.0 }",
    );
    assert!(
        e.contains("innermost first") && e.contains("shell 3") && !e.contains("reverse"),
        "{e}"
    );
    let e = refusal(
        WOLTER,
        "{ r3_mm = 50.0 }, { r3_mm = 60.0 }, { r3_mm = 50.0 }",
    );
    assert!(e.contains("shells 1 and 3 are the same shell"), "{e}");
    // Shell 1's 12 mm wall reaches through shell 2's mirror 10 mm further out.
    let e = refusal(
        WOLTER,
        "{ r3_mm = 50.0, thickness_mm = 12.0 }, { r3_mm = 60.0 }",
    );
    assert!(e.contains("shells 1 and 2 intersect"), "{e}");
    // Two cones whose mirrors cross: shell 2 starts inside shell 1's entrance.
    let cone = "profile = \"cone\"\nfocal_length_mm = 1500.0";
    let e = refusal(
        cone,
        "{ r1_mm = 60.0, r2_mm = 59.0, r4_mm = 58.9, r5_mm = 56.0 }, { r1_mm = 60.4, r2_mm = 59.2, r4_mm = 59.1, r5_mm = 55.5 }",
    );
    assert!(e.contains("shells 1 and 2 intersect"), "{e}");
}

#[test]
fn a_shell_behind_the_inner_wall_or_steeper_than_a_grazing_angle_is_named() {
    // R3 > f: a mirror at 11° to the axis reflects no X-rays.
    let e = refusal(WOLTER, "{ r3_mm = 1600.0 }");
    assert!(
        e.contains("not at a grazing angle") && e.contains("shell 1"),
        "{e}"
    );
    // Shell 1, 300 mm long with an 8 mm wall, rises above shell 2 (100 mm):
    // its wall ends at r = 60.44 mm at its entrance, beyond shell 2's whole
    // aperture (r = 59.0 … 59.97 mm), while everywhere beside shell 2 it
    // stays 0.56 mm or more inside shell 2's mirrors. No wall crosses a
    // mirror, but shell 2 gets no on-axis light.
    let e = refusal(
        WOLTER,
        "{ r3_mm = 50.0, thickness_mm = 8.0, mirror_length_mm = 300.0 }, { r3_mm = 59.0 }",
    );
    assert!(
        e.contains("shell 2's front mirror receives no on-axis X-rays"),
        "{e}"
    );
    // 200 mm long, the wall shadows 65 % of shell 2's aperture: legal, with a
    // warning; the shipped optics have none.
    let scene = prescription(
        WOLTER,
        "{ r3_mm = 50.0, thickness_mm = 8.0, mirror_length_mm = 200.0 }, { r3_mm = 59.0 }",
    )
    .unwrap();
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("shadows") && w.contains("shell 2")),
        "{:?}",
        scene.warnings
    );
    for name in ["llnl", "wolter1_demo", "xmm_newton"] {
        let t = traxer::scene::telescope::Telescope::shipped(name).unwrap();
        assert!(
            t.nesting_warnings().is_empty(),
            "{name}: {:?}",
            t.nesting_warnings()
        );
    }
}

#[test]
fn a_prescription_out_of_bounds_is_refused_by_its_key_not_by_a_part() {
    // Before: a spider whose radii cross was "shape: disk needs 0 ≤
    // inner_radius < radius", naming no file or key; 1e308 mm printed 309
    // digits; 10 000 shells ran Embree out of memory after 11 GB.
    let dir = tempfile::tempdir().unwrap();
    let data = "name = \"mine\"\nprofile = \"wolter1\"\nfocal_length_mm = 1500.0\nmirror_length_mm = 100.0\nwall_thickness_mm = 0.5\ncoating = \"gold\"\nspider = { arms = 4, arm_width_deg = 2.0, inner_radius_mm = 80.0 }\nshells = [ { r3_mm = 50.0 }, { r3_mm = 60.0 } ]\n";
    crate::common::write(dir.path(), "mine.toml", data);
    let scene = "[[sources]]\ntype = \"parallel\"\naperture = { center = [0, 0, 200], radius = 90.0 }\nenergy = { line = 1.49 }\n\n[[assemblies]]\ntype = \"nested_telescope\"\ndata = \"mine.toml\"\nspider_distance = 10.0\n";
    let path = crate::common::write(dir.path(), "scene.toml", scene);
    let load = || match traxer::scene::Scene::load(&crate::common::device(), &path, &[]) {
        Ok(_) => panic!("refused"),
        Err(e) => e.to_string(),
    };
    let e = load();
    assert!(
        e.contains("mine.toml")
            && e.contains("spider")
            && e.contains("inner_radius_mm = 80")
            && e.contains("outermost wall"),
        "{e}"
    );
    let long = data.replace("mirror_length_mm = 100.0", "mirror_length_mm = 1e308");
    crate::common::write(dir.path(), "mine.toml", &long);
    let e = load();
    assert!(
        e.contains("mirror_length_mm = 1e308 mm") && e.len() < 400,
        "{e}"
    );
    let many: Vec<String> = (0..1001)
        .map(|k| format!("{{ r3_mm = {} }}", 50.0 + 0.6 * k as f64))
        .collect();
    let many = data.replace("{ r3_mm = 50.0 }, { r3_mm = 60.0 }", &many.join(", "));
    crate::common::write(dir.path(), "mine.toml", &many);
    let e = load();
    assert!(e.contains("1001 shells: at most 1000"), "{e}");
}

#[test]
fn babyiaxo_takes_a_users_optic_through_one_variable() {
    // docs/telescopes.md's recipe: the optic's file in `telescope`, its focal
    // length, the window in front of its focus; spider = false keeps the
    // scene's spider_distance unused.
    let dir = tempfile::tempdir().unwrap();
    let data = "name = \"my optic\"\nprofile = \"wolter1\"\nfocal_length_mm = 1600.0\nmirror_length_mm = 150.0\nwall_thickness_mm = 0.3\ncoating = \"gold\"\nshells = [ { r3_mm = 60.0 }, { r3_mm = 63.0 }, { r3_mm = 66.0 } ]\n";
    let file = crate::common::write(dir.path(), "my_optic.toml", data);
    let defines: Vec<String> = [
        format!("telescope={}", file.display()),
        "focal_length=1600".into(),
        "window_z=-1585".into(),
        "spider=false".into(),
        "central_stop=true".into(),
    ]
    .into();
    let scene = traxer::scene::Scene::load(
        &crate::common::device(),
        &crate::common::repo().join("scenes/babyiaxo_axion_image.toml"),
        &defines,
    )
    .unwrap();
    let mirrors = scene
        .objects
        .iter()
        .filter(|o| o.name.starts_with("xmm_front_"))
        .count();
    assert_eq!(
        mirrors,
        3 * 3,
        "front_i, its back and its far edge (no gap), per shell"
    );
    assert_eq!(scene.sensors[0].focal_length, Some(1600.0));
    assert!(
        scene.inputs.keys().any(|f| f.ends_with("my_optic.toml")),
        "the file is a run input: {:?}",
        scene.inputs
    );
}
