//! Every PNG a physicist reads carries its axes: a trace's sensor figures
//! (linear, log, grid), its EEF and conversion-depth plots, and the plots of
//! solar-flux, effective-area and focus are checked for a frame around the data
//! (dark text and tick pixels in the left and bottom margins, where axis labels
//! go), a size beyond the bare image, and, for the sensor figures, a colour bar
//! (a column of many viridis colours right of the image). The bare pixel image
//! keeps exactly one PNG pixel per sensor pixel.

use crate::common::{repo, run_ok, traxer};
use std::path::Path;

/// Dark pixels (text, ticks, axis lines) in a strip of the picture.
fn dark_pixels(img: &image::RgbImage, xs: std::ops::Range<u32>, ys: std::ops::Range<u32>) -> usize {
    let mut n = 0;
    for y in ys {
        for x in xs.clone() {
            let p = img.get_pixel(x, y).0;
            let lum = 0.3 * p[0] as f64 + 0.59 * p[1] as f64 + 0.11 * p[2] as f64;
            let spread = p.iter().max().unwrap() - p.iter().min().unwrap();
            // Grey and dark: text and axes, not the dark end of viridis.
            if lum < 110.0 && spread < 30 {
                n += 1;
            }
        }
    }
    n
}

/// Whether `path` is a framed plot: labels left and below, a title above.
fn has_axes(path: &Path) -> Result<(), String> {
    let img = image::open(path)
        .map_err(|e| format!("{}: {e}", path.display()))?
        .to_rgb8();
    let (w, h) = img.dimensions();
    let name = path.display();
    if w < 600 || h < 400 {
        return Err(format!("{name}: {w}×{h} is too small for a figure"));
    }
    let left = dark_pixels(&img, 0..w / 8, h / 5..4 * h / 5);
    let bottom = dark_pixels(&img, w / 5..4 * w / 5, h - h / 8..h);
    let top = dark_pixels(&img, 0..w, 0..h / 12);
    if left < 50 || bottom < 50 || top < 50 {
        return Err(format!(
            "{name}: dark (text) pixels left {left}, below {bottom}, in the title {top}: an axis or the title is missing"
        ));
    }
    Ok(())
}

fn assert_has_axes(path: &Path) {
    if let Err(e) = has_axes(path) {
        panic!("{e}");
    }
}

/// Distinct colours in a column strip (a colour bar has dozens).
fn distinct_colours(img: &image::RgbImage, x: u32, ys: std::ops::Range<u32>) -> usize {
    let mut seen = std::collections::BTreeSet::new();
    for y in ys {
        seen.insert(img.get_pixel(x, y).0);
    }
    seen.len()
}

#[test]
fn every_picture_has_axes_a_title_and_sensor_figures_a_colour_bar() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("cast");
    run_ok(
        traxer()
            .arg("trace")
            .arg(repo().join("scenes/cast_axion_image.toml"))
            .args(["-n", "30000", "-q", "--out"])
            .arg(&out),
    );
    for name in [
        "chip.png",
        "chip_log.png",
        "chip_grid.png",
        "chip_eef.png",
        "chip_conversion_depth.png",
    ] {
        assert_has_axes(&out.join(name));
    }
    // The sensor figures: a colour bar right of the image.
    for name in ["chip.png", "chip_log.png", "chip_grid.png"] {
        let img = image::open(out.join(name)).unwrap().to_rgb8();
        let (w, h) = img.dimensions();
        let best = (w * 3 / 4..w)
            .map(|x| distinct_colours(&img, x, h / 4..3 * h / 4))
            .max()
            .unwrap();
        assert!(
            best > 60,
            "{name}: no colour bar ({best} colours in a column)"
        );
    }
    let spec: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("chip.json")).unwrap()).unwrap();
    let pixels = &spec["sensor"]["pixels"];
    let bare = image::open(out.join("chip_pixels.png")).unwrap().to_rgb8();
    assert_eq!(
        [bare.width() as u64, bare.height() as u64],
        [pixels[0].as_u64().unwrap(), pixels[1].as_u64().unwrap()],
        "the bare image is one PNG pixel per sensor pixel"
    );
    // The check tells a bare image from a figure.
    assert!(has_axes(&out.join("chip_pixels.png")).is_err());
    let sf = tmp.path().join("sf");
    run_ok(traxer().args(["solar-flux", "-q", "--out"]).arg(&sf));
    assert_has_axes(&sf.join("spectrum.png"));
    assert_has_axes(&sf.join("profiles.png"));
    let ea = tmp.path().join("ea");
    run_ok(
        traxer()
            .arg("effective-area")
            .arg(repo().join("scenes/llnl_effective_area.toml"))
            .args([
                "--energies",
                "1,3,5",
                "--angles",
                "0,5,10",
                "-n",
                "4000",
                "-q",
                "--out",
            ])
            .arg(&ea),
    );
    for name in ["effective_area.png", "vignetting.png", "off_axis.png"] {
        assert_has_axes(&ea.join(name));
    }
    let fo = tmp.path().join("fo");
    run_ok(
        traxer()
            .arg("focus")
            .arg(repo().join("scenes/wolter1_parallel.toml"))
            .args([
                "--var",
                "focus_shift",
                "--from",
                "-20",
                "--to",
                "20",
                "--steps",
                "4",
            ])
            .args(["-n", "3000", "-q", "--out"])
            .arg(&fo),
    );
    assert_has_axes(&fo.join("focus.png"));
    let r = tmp.path().join("r.png");
    run_ok(
        traxer()
            .args([
                "reflectivity",
                "--coating",
                "gold",
                "--energy",
                "1,3",
                "--angle",
                "0:2:0.05",
                "-q",
                "--plot",
            ])
            .arg(&r),
    );
    assert_has_axes(&r);
}

#[test]
fn sensor_figures_mark_the_centroid_and_tell_no_flux_from_the_lowest_decade() {
    // The PANTER image: the linear figure carries the centroid's red cross; the
    // log figure paints pixels without flux light grey (225, 225, 225), a
    // colour viridis never takes, so that the lowest decade is not read as
    // nothing.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p");
    run_ok(
        traxer()
            .arg("trace")
            .arg(repo().join("scenes/panter_al_ka.toml"))
            .args(["-n", "20000", "-q", "-o"])
            .arg(&out),
    );
    let count = |file: &str, colour: [u8; 3]| {
        let img = image::open(out.join(file)).unwrap().to_rgb8();
        img.pixels().filter(|p| p.0 == colour).count()
    };
    assert!(
        count("sensor.png", [230, 40, 40]) >= 12,
        "the centroid's cross"
    );
    let grey_log = count("sensor_log.png", [225, 225, 225]);
    // (The linear figure has that grey only in a few anti-aliased letters.)
    let grey_linear = count("sensor.png", [225, 225, 225]);
    assert!(
        grey_log > 10_000 && grey_log > 50 * grey_linear,
        "{grey_log} vs {grey_linear}"
    );
}

#[test]
fn the_parts_that_stop_the_focused_beam_are_counted() {
    // At CAST the detector body around the 14 mm window stops reflected photons
    // (it cuts the image's edge), the bore only photons on their way in: it
    // must not be counted. No part stops more reflected photons than it was
    // hit by.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c");
    run_ok(
        traxer()
            .arg("trace")
            .arg(repo().join("scenes/cast_axion_image.toml"))
            .args(["-n", "100000", "-q", "-o"])
            .arg(&out),
    );
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    let stats = &summary["statistics"];
    let stopped = stats["stopped_after_reflection"].as_object().unwrap();
    assert!(
        stopped["detector_body"].as_u64().unwrap() > 100,
        "{stopped:?}"
    );
    assert!(!stopped.contains_key("bore"), "{stopped:?}");
    assert!(stats["hits_per_object"]["bore"].as_u64().unwrap() > 1000);
    for (name, n) in stopped {
        let hits = stats["hits_per_object"][name].as_u64().unwrap();
        assert!(n.as_u64().unwrap() <= hits, "{name}: {n} > {hits}");
    }
}
