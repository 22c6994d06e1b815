//! Photon histories: path classes of the LLNL telescope's photons, a telescope
//! with one rear mirror removed, per-shell fluxes, per-class images and the
//! photon list.

use traxer::history::PathClass;
use traxer::trace::{self, RunConfig};

/// The LLNL telescope (perfect coating, no figure errors) in an on-axis parallel
/// beam over its segments, a sensor of `size` mm at the focal plane; `extra` goes
/// into the assembly table.
fn llnl_scene(size: f64, extra: &str) -> String {
    format!(
        r#"
max_interactions = 8

[materials.detector]
type = "sensor"
size = [{size}, {size}]
pixels = [200, 200]
history_images = true

[[sources]]
type = "parallel"
aperture = {{ center = [0, 0, 300], radius = 106.0, inner_radius = 53.0, azimuth = [-16.0, 16.0] }}
energy = {{ line = 1.49 }}

[[assemblies]]
type = "llnl_telescope"
coating = "perfect"
{extra}

[[objects]]
name = "sensor"
material = "detector"
shape = {{ type = "rectangle", size = [{size}, {size}] }}
transform = [ {{ translate = [0.0, 0.0, -1500.0] }} ]
"#
    )
}

#[test]
fn on_axis_nearly_all_flux_at_the_focus_has_been_reflected_front_then_rear() {
    let s = crate::common::scene(&llnl_scene(14.0, ""));
    let r = trace::run(&s, &RunConfig::new(200_000, 3)).unwrap();
    let t = &r.images[0].paths;
    let total: f64 = t.class_flux().iter().sum();
    assert!((total - r.images[0].total_flux()).abs() <= 1e-12 * total);
    let share = t.class_flux()[PathClass::FrontRear as usize] / total;
    // Measured: all of them (569 857 photons of 1 M reach the sensor, every one
    // front then rear). Stray light that lands on the 14 mm sensor would lower
    // it; anything below 0.999 would mean misplaced mirrors.
    assert!(share > 0.999, "front_rear share {share}");
    // Every focused photon went front i → rear i of the same shell.
    for &(first, last) in t.paths.keys() {
        let (a, b) = (&s.objects[first as usize], &s.objects[last as usize]);
        assert_eq!(a.shell, b.shell, "{} → {}", a.name, b.name);
    }
    // The per-class images add up to the image.
    let images = t.class_images().expect("history_images = true");
    for (k, v) in r.images[0].flux().iter().enumerate() {
        let sum: f64 = images.iter().map(|im| im[k]).sum();
        assert!((sum - v).abs() <= 1e-12 * v.abs().max(1e-300), "pixel {k}");
    }
}

#[test]
fn without_its_rear_mirror_a_shell_sends_its_photons_front_only_far_from_the_focus() {
    // Shell 7's rear mirror is left out with its glass: the photons its front
    // mirror reflects go on inwards at 2α and reach the focal plane
    // ≈ R − 1500·tan 2α ≈ 77 − 41 = 36 mm from the axis, as "front only".
    // A few (measured 5 %), reflected near the front mirror's small end, now meet
    // the exit end of shell 8's rear mirror, which shell 7's rear mirror shadowed
    // before: a cross-shell path front_7 → rear_8 that lands near the focus.
    let s = crate::common::scene(&llnl_scene(120.0, r#"omit = ["rear_7"]"#));
    let name = |i: u32| s.objects[i as usize].name.as_str();
    let mut cfg = RunConfig::new(300_000, 5);
    cfg.photon_list = 1_000_000;
    let r = trace::run(&s, &cfg).unwrap();
    let (mut front_only, mut cross) = (0, 0);
    for p in &r.photons {
        let h = p.record.history;
        let r_mm = p.local.x.hypot(p.local.y);
        if h.class() == PathClass::Direct {
            // Through the gaps between the shells' glass, straight on: the beam
            // starts at 53 mm from the axis.
            assert!(r_mm > 50.0, "a direct photon {r_mm} mm from the axis");
            continue;
        }
        assert_ne!(name(h.last_mirror), "llnl_rear_7", "the mirror is gone");
        if name(h.first_mirror) == "llnl_front_7" {
            if h.class() == PathClass::FrontOnly {
                front_only += 1;
                assert!(r_mm > 20.0, "a front-only photon {r_mm} mm from the focus");
            } else {
                cross += 1;
                assert_eq!((h.reflections, name(h.last_mirror)), (2, "llnl_rear_8"));
            }
        } else if h.class() == PathClass::FrontRear && h.reflections == 2 {
            // The other shells focus as before.
            assert_eq!(
                s.objects[h.first_mirror as usize].shell,
                s.objects[h.last_mirror as usize].shell
            );
            assert!(r_mm < 3.0, "a focused photon {r_mm} mm from the focus");
        } else {
            // On this big sensor some stray light (one reflection on a rear
            // mirror, straight from the beam) lands far out too.
            assert!(r_mm > 20.0, "stray light {r_mm} mm from the focus: {h:?}");
        }
    }
    // Shell 7 collects about 1/13 of the light.
    let share = front_only as f64 / (front_only + cross) as f64;
    assert!(
        front_only > 10_000 && share > 0.9,
        "{front_only} front only, {cross} cross"
    );
    assert_eq!(r.photons.len() as u64, r.stats.reached_sensor);
}

#[test]
fn shell_fluxes_add_up_to_the_total_in_summary_json() {
    let dir = tempfile::tempdir().unwrap();
    let scene = crate::common::write(dir.path(), "llnl.toml", &llnl_scene(14.0, ""));
    crate::common::run_ok(
        crate::common::traxer()
            .arg("trace")
            .arg(&scene)
            .args(["-n", "100000", "-q", "--photon-list", "500", "-o"])
            .arg(dir.path().join("out")),
    );
    let out = dir.path().join("out");
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    let sensor = &summary["sensors"][0];
    let total = sensor["total_flux"].as_f64().unwrap();
    let h = &sensor["history"];
    let sum = |v: &serde_json::Value| -> (f64, f64) {
        let items: Vec<&serde_json::Value> = match v {
            serde_json::Value::Array(a) => a.iter().collect(),
            serde_json::Value::Object(m) => m.values().collect(),
            _ => panic!("{v}"),
        };
        (
            items.iter().map(|x| x["flux"].as_f64().unwrap()).sum(),
            items.iter().map(|x| x["fraction"].as_f64().unwrap()).sum(),
        )
    };
    for key in ["classes", "shells", "paths"] {
        let (flux, fraction) = sum(&h[key]);
        assert!(
            (flux / total - 1.0).abs() < 1e-12,
            "{key}: {flux} vs {total}"
        );
        assert!(
            (fraction - 1.0).abs() < 1e-12,
            "{key}: fractions {fraction}"
        );
    }
    // 13 shells, in order.
    let shells: Vec<&str> = h["shells"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["shell"].as_str().unwrap())
        .collect();
    assert_eq!(shells, (1..=13).map(|i| i.to_string()).collect::<Vec<_>>());
    // Per-class images and the photon list are written.
    for f in [
        "sensor_front_rear.npy",
        "sensor_direct.npy",
        "photons.npy",
        "photons.csv",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let csv = std::fs::read_to_string(out.join("photons.csv")).unwrap();
    assert_eq!(csv.lines().count(), 501);
    assert!(csv.lines().nth(1).unwrap().contains(",llnl_front_"));
}

#[test]
fn the_photon_list_is_the_same_for_any_number_of_threads() {
    let s = crate::common::scene(&llnl_scene(14.0, ""));
    let list = |threads: usize| {
        let mut cfg = RunConfig::new(50_000, 9);
        cfg.threads = threads;
        cfg.photon_list = 10_000;
        let r = trace::run(&s, &cfg).unwrap();
        r.photons
            .iter()
            .map(|p| (p.index, p.local.x.to_bits(), p.record.weight.to_bits()))
            .collect::<Vec<_>>()
    };
    let one = list(1);
    assert_eq!(one.len(), 10_000);
    assert!(one.windows(2).all(|w| w[0].0 < w[1].0), "photon order");
    assert_eq!(one, list(2));
    assert_eq!(one, list(3));
}
