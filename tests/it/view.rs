//! `traxer view`, the live window: under a virtual X server (Xvfb) it opens,
//! renders and saves; without a display it says so (exit code 2).

use crate::common::{repo, run_fails, run_ok, traxer};
use std::time::{Duration, Instant};

/// A virtual X server for the test's lifetime.
struct Xvfb {
    child: std::process::Child,
    display: String,
    /// Kept open: Xvfb dies of SIGPIPE if it writes to a closed pipe.
    _out: std::io::BufReader<std::process::ChildStdout>,
}

impl Xvfb {
    fn start() -> Xvfb {
        use std::io::BufRead;
        // Xvfb picks a free display itself and writes its number to fd 1.
        let mut child = std::process::Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1024x768x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("Xvfb is missing: scripts/setup.sh installs it (package xvfb)");
        let mut line = String::new();
        let mut out = std::io::BufReader::new(child.stdout.take().unwrap());
        out.read_line(&mut line).unwrap();
        let n: u32 = line.trim().parse().expect("Xvfb did not say its display");
        Xvfb {
            child,
            display: format!(":{n}"),
            _out: out,
        }
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

/// `xdotool` with the test's display.
fn xdotool(x: &Xvfb, args: &[&str]) {
    let out = std::process::Command::new("xdotool")
        .args(args)
        .env("DISPLAY", &x.display)
        .output()
        .expect("xdotool is missing: scripts/setup.sh installs it (package xdotool)");
    assert!(
        out.status.success(),
        "xdotool {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The `look_from` and `look_at` lines of each camera printed with P.
fn printed_cameras(stdout: &str) -> Vec<(String, String)> {
    let lines: Vec<&str> = stdout.lines().collect();
    lines
        .windows(3)
        .filter(|w| w[0] == "[cameras.view]")
        .map(|w| (w[1].to_string(), w[2].to_string()))
        .collect()
}

#[test]
fn keys_and_the_mouse_fly_print_the_camera_save_and_quit() {
    let x = Xvfb::start();
    let dir = tempfile::tempdir().unwrap();
    let save = dir.path().join("saved");
    let child = traxer()
        .arg("view")
        .arg(repo().join("scenes/panter_al_ka.toml"))
        .arg("--save")
        .arg(&save)
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Synthetic input as a user gives it (XTEST), to the focused window.
    let pause = |ms| std::thread::sleep(Duration::from_millis(ms));
    let wid = {
        let out = std::process::Command::new("xdotool")
            .args(["search", "--sync", "--name", "traxer view"])
            .env("DISPLAY", &x.display)
            .output()
            .unwrap();
        String::from_utf8_lossy(&out.stdout)
            .lines()
            .next()
            .unwrap()
            .to_string()
    };
    xdotool(&x, &["windowfocus", "--sync", &wid]);
    pause(300);
    xdotool(&x, &["key", "p"]);
    xdotool(&x, &["keydown", "w"]);
    pause(400);
    xdotool(&x, &["keyup", "w"]);
    pause(200);
    xdotool(&x, &["key", "p"]);
    xdotool(
        &x,
        &[
            "mousemove",
            "--window",
            &wid,
            "300",
            "200",
            "mousedown",
            "1",
        ],
    );
    pause(200);
    xdotool(&x, &["mousemove", "--window", &wid, "360", "180"]);
    pause(200);
    xdotool(&x, &["mouseup", "1"]);
    pause(200);
    // L names the parts (drawn into the frame F2 saves).
    xdotool(&x, &["key", "l"]);
    pause(300);
    xdotool(&x, &["key", "p", "F2"]);
    let start = Instant::now();
    while !save.join("frame.png").exists() && start.elapsed() < Duration::from_secs(30) {
        pause(50);
    }
    xdotool(&x, &["key", "Escape"]);
    // A window that does not close is a failure, not a hung test.
    let mut child = child;
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(30) {
            let _ = child.kill();
            panic!("traxer view did not close on Escape");
        }
        pause(50);
    }
    let out = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let cams = printed_cameras(&stdout);
    assert_eq!(cams.len(), 3, "{stdout}");
    // W moved the camera (both points), the drag turned it (only the look-at).
    assert_ne!(cams[0].0, cams[1].0, "W did not move: {stdout}");
    assert_eq!(cams[1].0, cams[2].0, "the drag moved the camera: {stdout}");
    assert_ne!(cams[1].1, cams[2].1, "the drag did not turn: {stdout}");
    // F2 saved the sensor images and the frame.
    for f in ["sensor.npy", "summary.json", "frame.png"] {
        assert!(save.join(f).is_file(), "F2 did not save {f}");
    }
    assert!(stdout.contains("frames in"), "{stdout}");
}
