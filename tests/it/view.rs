//! `traxer view`, the live window: under a virtual X server (Xvfb) it opens,
//! renders and saves; without a display it says so (exit code 2).

use crate::common::{repo, run_fails, run_ok, traxer};
use std::path::Path;
use std::time::{Duration, Instant};

/// A virtual X server for the test's lifetime.
struct Xvfb {
    child: std::process::Child,
    display: String,
}

impl Xvfb {
    fn start() -> Xvfb {
        assert!(
            std::process::Command::new("sh")
                .args(["-c", "command -v Xvfb"])
                .output()
                .is_ok_and(|o| o.status.success()),
            "Xvfb is missing: scripts/setup.sh installs it (package xvfb)"
        );
        // A display number no other test run uses at the same time.
        let n = 50 + std::process::id() % 400;
        let display = format!(":{n}");
        let child = std::process::Command::new("Xvfb")
            .args([
                display.as_str(),
                "-screen",
                "0",
                "1024x768x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let socket = format!("/tmp/.X11-unix/X{n}");
        let start = Instant::now();
        while !Path::new(&socket).exists() && start.elapsed() < Duration::from_secs(20) {
            std::thread::sleep(Duration::from_millis(20));
        }
        assert!(
            Path::new(&socket).exists(),
            "Xvfb did not start on {display}"
        );
        Xvfb { child, display }
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[test]
fn without_a_display_view_says_so_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let save = dir.path().join("saved");
    let err = run_fails(
        traxer()
            .arg("view")
            .arg(repo().join("scenes/panter_al_ka.toml"))
            .args(["--frames", "2", "--save"])
            .arg(&save)
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY"),
        2,
    );
    assert!(err.contains("no display"), "{err}");
    assert!(!save.exists());
}

#[test]
fn under_xvfb_the_window_renders_and_saves_the_trace_of_its_photons() {
    let x = Xvfb::start();
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/panter_al_ka.toml");
    let save = dir.path().join("saved");
    let out = run_ok(
        traxer()
            .arg("view")
            .arg(&scene)
            .args([
                "--frames",
                "12",
                "--photons",
                "300000",
                "--width",
                "320",
                "--height",
                "200",
            ])
            .args(["--show-help", "--save"])
            .arg(&save)
            .env("DISPLAY", &x.display)
            .env_remove("WAYLAND_DISPLAY"),
    );
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(said.contains("frames in"), "{said}");
    // The frame: the window's size, not blank, with the help's white text and the
    // sensor's viridis (its darkest colour, where no photon arrived).
    let frame = image::open(save.join("frame.png")).unwrap().to_rgb8();
    assert_eq!(frame.dimensions(), (320, 200));
    let px: Vec<[u8; 3]> = frame.pixels().map(|p| p.0).collect();
    assert!(px.iter().any(|p| *p != px[0]), "a blank frame");
    assert!(px.contains(&[255, 255, 255]), "no help text");
    let viridis_dark = |p: &[u8; 3]| p[0] < 90 && p[1] < 40 && p[2] > 60 && p[2] < 130;
    assert!(
        px.iter().filter(|p| viridis_dark(p)).count() > 500,
        "no sensor on screen"
    );
    // The sensor images are those of `traxer trace` with as many photons.
    let reference = dir.path().join("trace");
    run_ok(
        traxer()
            .arg("trace")
            .arg(&scene)
            .args(["-n", "300000", "-q", "-o"])
            .arg(&reference),
    );
    for f in [
        "sensor.npy",
        "sensor_counts.npy",
        "sensor.png",
        "sensor_projections.csv",
    ] {
        assert!(
            std::fs::read(save.join(f)).unwrap() == std::fs::read(reference.join(f)).unwrap(),
            "{f} differs from the trace's"
        );
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(save.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["provenance"]["photons"], 300000);
    assert_eq!(summary["statistics"]["photons_emitted"], 300000);
}
