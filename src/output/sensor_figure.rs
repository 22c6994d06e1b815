//! The figure of a sensor's image for NAME.png and NAME_log.png: what a
//! physicist looks for at a glance. The view is framed on the flux (a square
//! around the centroid of twice the 90 % diameter, when that is much smaller
//! than the sensor; NAME_pixels.png keeps the whole sensor), the
//! centroid is marked and the HPD, 80 % and 90 % circles drawn, and the title
//! says what the flux depends on: the source, its energies and, for the Sun,
//! the couplings.
//!
//! Data flow: `run_files::write_sensor` → [`sensor_figure`] → `image_plot`.

use super::image_plot::{ImageFigure, Overlay, SecondaryAxes};
use super::{Provenance, Scale};
use crate::analysis::FinishedImage;
use crate::scene::Scene;
use crate::sensor::SensorSpec;
use crate::source::Source;
use std::borrow::Cow;

/// Frame on the flux only when its square covers less than this share of the
/// sensor's width: otherwise the whole sensor is shown.
const ZOOM_BELOW: f64 = 0.7;
/// The framed square's half-side: the 90 % radius times this (a figure-error
/// halo can put the 99 % radius at the sensor's edge while the eye sees the
/// core: the 90 % circle then fills half the view).
const FRAME_PER_R90: f64 = 2.0;

/// The figure of `finished` on `spec`.
pub fn sensor_figure<'a>(
    scene: &Scene,
    spec: &SensorSpec,
    finished: &'a FinishedImage,
    (provenance, statistics): (&Provenance, &crate::trace::Statistics),
    scale: Scale,
) -> ImageFigure<'a> {
    let g = &finished.geometry;
    let photons = provenance
        .photons
        .map_or(String::new(), |n| format!(" · {n} photons traced"));
    let scene_name = scene.name_for_people();
    let unit = unit(scene, spec, finished.absolute);
    let mut fig = ImageFigure {
        title: format!("{scene_name}: {}", sensor_label(&spec.name)),
        subtitle: format!(
            "{}{photons} · total {:.4e} {}",
            source_words(scene, spec),
            finished.total_flux(),
            unit.split(" per pixel").next().unwrap_or_default()
        ),
        values: Cow::Borrowed(finished.summed()),
        pixels: [g.nx, g.ny],
        extent_mm: [
            [g.origin_mm[0], g.origin_mm[0] + g.nx as f64 * g.pitch[0]],
            [g.origin_mm[1], g.origin_mm[1] + g.ny as f64 * g.pitch[1]],
        ],
        secondary: spec.focal_length.map(SecondaryAxes::arcsec),
        unit,
        scale,
        axes: ["sensor x".into(), "sensor y".into()],
        orientation: format!(
            "Seen from the front (+z): local x right, y up; {}.npy row 0 at the bottom.",
            crate::sensor::file_stem(&spec.name)
        ),
        overlay: Overlay::default(),
        note: notes(scene, spec, statistics),
        top: None,
    };
    if scale == Scale::Linear {
        if let Some((top, above)) = linear_top(finished.summed()) {
            fig.top = Some(top);
            fig.overlay.corner = Some(format!(
                "colour scale up to the {TOP_PERCENTILE}th percentile of lit pixels: {above} brighter, up to {:.3e}, in yellow",
                crate::colormap::max_value(finished.summed())
            ));
        }
    }
    match &finished.quality {
        None => fig.overlay.message = Some("no photons reached this sensor".into()),
        Some((q, _)) => {
            let stem = crate::sensor::file_stem(&spec.name);
            // The linear image shows the core; the log image is for the wings,
            // which may reach the sensor's edge: it stays whole.
            if scale == Scale::Linear {
                frame_on_the_flux(&mut fig, finished, (q.centroid_mm, 0.5 * q.d90_mm), &stem);
            }
            fig.overlay.centroid_mm = Some(q.centroid_mm);
            fig.overlay.circles_mm = [
                (q.hpd_mm, "HPD", q.hpd_arcsec),
                (q.d80_mm, "80 %", q.d80_arcsec),
                (q.d90_mm, "90 %", q.d90_arcsec),
            ]
            .into_iter()
            .map(|(d, name, arcsec)| {
                let label = match arcsec {
                    Some(a) => format!("{name} {a:.0}″"),
                    None => format!("{name} {d:.2} mm"),
                };
                (0.5 * d, label)
            })
            .collect();
        }
    }
    if matches!(scale, Scale::Log { .. }) {
        fig.orientation.push_str(" Light grey: no flux.");
    }
    fig
}

/// The lines under the image: what a magnet run assumed, and what stopped
/// photons before the sensor.
fn notes(
    scene: &Scene,
    spec: &SensorSpec,
    statistics: &crate::trace::Statistics,
) -> Option<String> {
    let magnet = scene
        .converting_magnet()
        .map(|m| format!("Converted in the magnet: {}.", m.assumptions()));
    let lines: Vec<String> = magnet
        .into_iter()
        .chain(stopped_note(scene, spec, statistics))
        .collect();
    (!lines.is_empty()).then(|| lines.join("\n"))
}

/// Shows only the square of half-side 2 × the 90 % radius around the
/// centroid (whole pixels, within the sensor), when it is much smaller than
/// the sensor.
fn frame_on_the_flux(
    fig: &mut ImageFigure,
    f: &FinishedImage,
    (centre, r90): ([f64; 2], f64),
    stem: &str,
) {
    if frame_figure(fig, f.summed(), &f.geometry, (centre, r90)) {
        fig.orientation.push_str(&format!(
            " Framed: ±{FRAME_PER_R90} × the 90 % radius ({stem}_pixels.png: all of it)."
        ));
    }
}

/// Crops `fig` to ±2 × `r90` around `centre` on the image `values` of
/// geometry `g`, when that is much smaller than the image; whether it did.
pub(super) fn frame_figure(
    fig: &mut ImageFigure,
    values: &[f64],
    g: &crate::analysis::ImageGeometry,
    (centre, r90): ([f64; 2], f64),
) -> bool {
    let half = FRAME_PER_R90 * r90;
    let width = [g.nx as f64 * g.pitch[0], g.ny as f64 * g.pitch[1]];
    if half.is_nan() || half <= 0.0 || 2.0 * half > ZOOM_BELOW * width[0].min(width[1]) {
        return false;
    }
    let n = [g.nx, g.ny];
    let range: [[usize; 2]; 2] = std::array::from_fn(|k| {
        let lo = ((centre[k] - half - g.origin_mm[k]) / g.pitch[k])
            .floor()
            .max(0.0) as usize;
        let hi = ((centre[k] + half - g.origin_mm[k]) / g.pitch[k]).ceil() as usize;
        [lo.min(n[k] - 1), hi.clamp(lo + 1, n[k])]
    });
    let [[x0, x1], [y0, y1]] = range;
    let mut cropped = Vec::with_capacity((x1 - x0) * (y1 - y0));
    for iy in y0..y1 {
        cropped.extend_from_slice(&values[iy * g.nx + x0..iy * g.nx + x1]);
    }
    fig.values = Cow::Owned(cropped);
    fig.pixels = [x1 - x0, y1 - y0];
    fig.extent_mm = std::array::from_fn(|k| {
        let [a, b] = range[k];
        [
            g.origin_mm[k] + a as f64 * g.pitch[k],
            g.origin_mm[k] + b as f64 * g.pitch[k],
        ]
    });
    true
}

/// "the sensor" for a sensor named "sensor", else "sensor NAME".
fn sensor_label(name: &str) -> String {
    if name == "sensor" {
        "the sensor".into()
    } else {
        format!("sensor {name}")
    }
}

/// The percentile of the lit pixels a linear scale tops at when a few
/// pixels are far brighter than the rest.
const TOP_PERCENTILE: f64 = 99.5;

/// The top of a linear scale when a few hot pixels would set it: the
/// [`TOP_PERCENTILE`]th percentile of the lit pixels, if the brightest pixel
/// is over twice that, with how many pixels lie above it.
fn linear_top(values: &[f64]) -> Option<(f64, usize)> {
    let mut lit: Vec<f64> = values.iter().copied().filter(|v| *v > 0.0).collect();
    if lit.len() < 1000 {
        return None;
    }
    let k = (lit.len() as f64 * TOP_PERCENTILE / 100.0) as usize;
    let (_, top, _) = lit.select_nth_unstable_by(k, f64::total_cmp);
    let top = *top;
    let max = crate::colormap::max_value(values);
    (max > 2.0 * top).then(|| (top, values.iter().filter(|v| **v > top).count()))
}

/// What a pixel's value is, for the colour bar: with a Sun, that the
/// conversion in the magnet is not in it.
fn unit(scene: &Scene, spec: &SensorSpec, absolute: bool) -> String {
    if absolute {
        return match (scene.counted(), spec.gas.is_some()) {
            (crate::scene::Counted::XRays, true) => {
                "X-rays s⁻¹ per pixel converting in the gas (axions converted in the magnet)"
            }
            (crate::scene::Counted::XRays, false) => {
                "X-rays s⁻¹ per pixel (axions converted in the magnet)"
            }
            (_, true) => {
                "axions s⁻¹ per pixel converting in the gas (P(a→γ) in the magnet not applied)"
            }
            (_, false) => "axions s⁻¹ per pixel (P(a→γ) in the magnet not applied)",
        }
        .into();
    }
    match scene.sources.first() {
        Some(Source::Parallel(_)) => "photons per pixel (each traced photon weighs 1)".into(),
        Some(Source::Point(_)) => {
            "photons per pixel if the traced photons were emitted into 4π".into()
        }
        _ => "weighted photons per pixel".into(),
    }
}

/// The source and its energies in words: what the flux depends on.
fn source_words(scene: &Scene, spec: &SensorSpec) -> String {
    let (lo, hi) = scene.image_energy_range(spec);
    let energies = if lo == hi {
        format!("{lo} keV")
    } else {
        format!("{lo}–{hi} keV")
    };
    let source = match scene.sources.first() {
        Some(Source::Sun(sun)) => format!("Sun, {}", sun.coupling),
        Some(Source::Parallel(_)) => "parallel beam".into(),
        Some(Source::Point(p)) => {
            format!("point source {:.1} m away", p.position.length() / 1000.0)
        }
        None => String::new(),
    };
    match scene.sources.len() {
        0 | 1 => format!("{source}, {energies}"),
        n => format!("{source} and {} more sources, {energies}", n - 1),
    }
}

/// The photons each scene part stopped after a reflection, from the objects'
/// (part, name) and their counts: (part, whether it is an assembly of
/// several objects, count), parts without any left out. A telescope's
/// absorbers are its shells' backs and edges: a photon one shell reflected
/// that the next shell's back stops (the optic's own vignetting) is named by
/// the telescope. Summed in a map, in time linear in the objects (a search of
/// the parts for each object made a 100 000-object scene's figures take a
/// minute; `cargo bench --bench scaling` shows it).
pub fn stopped_by_part<'a>(
    objects: impl Iterator<Item = (&'a str, &'a str)>,
    counts: &[u64],
) -> Vec<(&'a str, bool, u64)> {
    let mut sums: std::collections::HashMap<&str, (bool, u64)> = Default::default();
    for ((part, name), &n) in objects.zip(counts) {
        if n > 0 {
            sums.entry(part).or_insert((part != name, 0)).1 += n;
        }
    }
    sums.into_iter().map(|(p, (t, n))| (p, t, n)).collect()
}

/// Parts that stopped reflected photons on their way, by name, as a share of the
/// photons this sensor recorded: the aperture or strongback whose edge cuts the
/// image is named here, so that the cut is not taken for the sensor's edge or a
/// fault. Shares below 0.1 % are left out; at most four parts.
fn stopped_note(
    scene: &Scene,
    spec: &SensorSpec,
    stats: &crate::trace::Statistics,
) -> Option<String> {
    let k = scene.sensors.iter().position(|s| s.name == spec.name)?;
    let recorded = *stats.recorded_per_sensor.get(k)? as f64;
    if recorded == 0.0 {
        return None;
    }
    let objects = scene
        .objects
        .iter()
        .map(|o| (o.part.as_str(), o.name.as_str()));
    let mut by_part = stopped_by_part(objects, &stats.stopped_after_reflection);
    by_part.retain(|(_, _, n)| *n as f64 >= 1e-3 * recorded);
    by_part.sort_by(|a, b| b.2.cmp(&a.2).then(a.0.cmp(b.0)));
    if by_part.is_empty() {
        return None;
    }
    let parts: Vec<String> = by_part
        .iter()
        .take(4)
        .map(|(p, telescope, n)| {
            let what = if *telescope {
                " (shell backs, edges)"
            } else {
                ""
            };
            format!("{p}{what} {:.1} %", 100.0 * *n as f64 / recorded)
        })
        .collect();
    Some(format!(
        "Reflected photons stopped before a sensor, per photon recorded here: {}{}.",
        parts.join(", "),
        if by_part.len() > 4 { ", …" } else { "" }
    ))
}
