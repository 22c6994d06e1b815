//! Image figures a physicist can read: a sensor image (or its detector-grid
//! image) with axes in mm, a second pair of axes in arcsec when the focal length
//! is known, a colour bar with the unit (and, on a log scale, the decades shown),
//! a title with the scene, energies and photon count, and a line saying which
//! way the axes point. The picture is drawn by plotters; the image itself is
//! copied into the plot area afterwards, each screen pixel the mean of the image
//! pixels it covers (so a large image is shown faithfully, a small one in blocks).
//!
//! Data flow: `run_files` (NAME.png, NAME_log.png, NAME_grid.png) → here →
//! [`write_rgb_png`].

use super::plot::register_font;
use super::write_rgb_png;
use crate::colormap::{max_value, viridis, Scale};
use crate::constants::ARCSEC_PER_RAD;
use plotters::prelude::*;
use std::path::Path;

/// What is drawn over the image: the centroid, the HPD / 80 % / 90 % circles
/// and a message (for an empty image).
#[derive(Clone, Debug, Default)]
pub struct Overlay {
    /// The flux-weighted centroid (mm, the figure's axes).
    pub centroid_mm: Option<[f64; 2]>,
    /// Circles around the centroid: radius (mm) and label.
    pub circles_mm: Vec<(f64, String)>,
    /// Written across the image (e.g. "no photons reached this sensor").
    pub message: Option<String>,
    /// Written in the image's lower left corner (e.g. how the scale is clipped).
    pub corner: Option<String>,
}

/// The second pair of axes, above and right of the image: the mm axes mapped
/// linearly, `value = (mm − zero_mm) × per_mm`.
#[derive(Clone, Debug)]
pub struct SecondaryAxes {
    pub per_mm: f64,
    pub zero_mm: [f64; 2],
    /// Axis names with their unit.
    pub x_desc: String,
    pub y_desc: String,
}

impl SecondaryAxes {
    /// Angles x / f in arcsec (small-angle), for a sensor at focal length `f`.
    pub fn arcsec(focal_length_mm: f64) -> SecondaryAxes {
        SecondaryAxes {
            per_mm: ARCSEC_PER_RAD / focal_length_mm,
            zero_mm: [0.0, 0.0],
            x_desc: "angle x [arcsec] (x / focal length)".into(),
            y_desc: "angle y [arcsec]".into(),
        }
    }

    /// Pixel indices of a grid of `pitch_mm` pixels whose lower-left corner is
    /// at `corner_mm`: index k spans [k, k + 1).
    pub fn pixel_index(pitch_mm: f64, corner_mm: [f64; 2]) -> SecondaryAxes {
        SecondaryAxes {
            per_mm: 1.0 / pitch_mm,
            zero_mm: corner_mm,
            x_desc: "grid pixel ix".into(),
            y_desc: "grid pixel iy".into(),
        }
    }
}

/// One image figure.
pub struct ImageFigure<'a> {
    /// First title line (scene and sensor).
    pub title: String,
    /// Second title line (energies, photons, total flux).
    pub subtitle: String,
    /// [iy][ix], row 0 at the bottom (lowest y), as the `.npy` files hold it.
    pub values: std::borrow::Cow<'a, [f64]>,
    pub pixels: [usize; 2],
    /// The x and y extent of the image's pixel edges, mm.
    pub extent_mm: [[f64; 2]; 2],
    /// Axes above and right (arcsec for a sensor with a focal length).
    pub secondary: Option<SecondaryAxes>,
    /// What a pixel value is, e.g. "axions s⁻¹ per pixel".
    pub unit: String,
    pub scale: Scale,
    /// Axis names without the unit, e.g. ["sensor x", "sensor y"].
    pub axes: [String; 2],
    /// Which way is which, printed under the image.
    pub orientation: String,
    /// Lines under the orientation line (what the run assumed, what stopped
    /// photons before the sensor), one per `\n`.
    pub note: Option<String>,
    /// Marks over the image.
    pub overlay: Overlay,
    /// The top of a linear scale, where not the brightest pixel (a few hot
    /// pixels would leave the image blank); brighter pixels take the top
    /// colour, and `unit` says so.
    pub top: Option<f64>,
}

/// Room around the image for labels, in screen pixels.
const LEFT: u32 = 80;
const BOTTOM: u32 = 60;
const TOP_TITLE: u32 = 62;
const ARCSEC_AXIS: u32 = 50;
/// The arcsec axis on the right needs room for its tick labels and name.
const ARCSEC_RIGHT: u32 = 82;
const COLOUR_BAR: u32 = 150;
const MARGIN: u32 = 14;
/// The image's longer side on screen.
const IMAGE_SIDE: f64 = 560.0;

/// The circles' dashes, inner first: (drawn, period) in screen pixels along
/// the circle (solid, dashed, dotted), and their marks in the legend.
const CIRCLE_DASHES: [(f64, f64); 3] = [(1.0, 1.0), (9.0, 14.0), (2.5, 6.0)];
const CIRCLE_MARKS: [&str; 3] = ["—", "– –", "···"];

/// The height of the note's line under the orientation line.
const NOTE_LINE: u32 = 18;

/// The room the note's lines take under the orientation line.
fn note_height(fig: &ImageFigure) -> u32 {
    NOTE_LINE * fig.note.as_deref().map_or(0, |n| n.lines().count()) as u32
}

/// The colour of pixels without flux on a log scale.
const NO_FLUX: [u8; 3] = [225, 225, 225];

/// Writes the figure as a PNG.
pub fn write_image_figure(path: &Path, fig: &ImageFigure) -> std::io::Result<()> {
    register_font();
    let [[x0, x1], [y0, y1]] = fig.extent_mm;
    let (sx, sy) = ((x1 - x0).abs().max(1e-12), (y1 - y0).abs().max(1e-12));
    // Keep the physical aspect ratio, within reason for strip-like sensors.
    let k = IMAGE_SIDE / sx.max(sy);
    let (iw, ih) = ((sx * k).max(160.0) as u32, (sy * k).max(160.0) as u32);
    let arcsec = if fig.secondary.is_some() {
        ARCSEC_AXIS
    } else {
        0
    };
    let right = if fig.secondary.is_some() {
        ARCSEC_RIGHT
    } else {
        0
    };
    let w = MARGIN + LEFT + iw + right + COLOUR_BAR + MARGIN;
    let note = note_height(fig);
    let h = TOP_TITLE + arcsec + ih + BOTTOM + 24 + MARGIN + note;
    let mut buf = vec![0u8; (w * h * 3) as usize];
    let max = fig.top.unwrap_or_else(|| max_value(&fig.values));
    let plot_area = {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        let r = draw_frame(&root, fig, h, (iw, ih), arcsec, max);
        let plot_area = r.map_err(|e| std::io::Error::other(format!("{}: {e}", path.display())))?;
        root.present()
            .map_err(|e| std::io::Error::other(format!("{}: {e}", path.display())))?;
        plot_area
    };
    let mut img = image::RgbImage::from_raw(w, h, buf).expect("buffer of the right size");
    blit(&mut img, fig, plot_area.clone(), max);
    draw_overlay(&mut img, fig, plot_area)
        .map_err(|e| std::io::Error::other(format!("{}: {e}", path.display())))?;
    write_rgb_png(path, &img)
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;
type Error = Box<dyn std::error::Error>;

/// Title, axes, colour bar and orientation line; returns the plot area's
/// screen rectangle (x range, y range) for the image.
fn draw_frame(
    root: &Area,
    fig: &ImageFigure,
    h: u32,
    (iw, ih): (u32, u32),
    arcsec: u32,
    max: f64,
) -> Result<(std::ops::Range<i32>, std::ops::Range<i32>), Error> {
    root.fill(&WHITE)?;
    let title = ("sans-serif", 20).into_font();
    root.draw(&Text::new(fig.title.clone(), (MARGIN as i32, 8), title))?;
    let sub = ("sans-serif", 15).into_font();
    root.draw(&Text::new(
        fig.subtitle.clone(),
        (MARGIN as i32, 34),
        sub.clone(),
    ))?;
    let foot = ("sans-serif", 13).into_font().color(&RGBColor(80, 80, 80));
    let note = note_height(fig);
    root.draw(&Text::new(
        fig.orientation.clone(),
        (MARGIN as i32, (h - MARGIN - 14 - note) as i32),
        foot.clone(),
    ))?;
    for (k, line) in fig.note.iter().flat_map(|n| n.lines()).enumerate() {
        let y = h - MARGIN - 14 - note + NOTE_LINE * (k as u32 + 1);
        root.draw(&Text::new(
            line.to_string(),
            (MARGIN as i32, y as i32),
            foot.clone(),
        ))?;
    }
    let right_axis = if arcsec > 0 { ARCSEC_RIGHT } else { 0 };
    let chart_w = MARGIN + LEFT + iw + right_axis;
    let (left, right) = root.split_horizontally(chart_w);
    let (body, _) = left.split_vertically(h - 24 - MARGIN - note);
    let (_, body) = body.split_vertically(TOP_TITLE - 6);
    let [[x0, x1], [y0, y1]] = fig.extent_mm;
    // The mm axes left and below; the arcsec axes (a second chart with the
    // same plot rectangle) above and right.
    let mut chart = ChartBuilder::on(&body)
        .margin_left(MARGIN)
        .margin_top(6 + arcsec)
        .margin_right(right_axis)
        .set_label_area_size(LabelAreaPosition::Left, LEFT)
        .set_label_area_size(LabelAreaPosition::Bottom, BOTTOM)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    let label = ("sans-serif", 14);
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(format!("{} [mm]", fig.axes[0]))
        .y_desc(format!("{} [mm]", fig.axes[1]))
        .label_style(label)
        .axis_desc_style(("sans-serif", 15))
        .draw()?;
    let plot_area = chart.plotting_area().get_pixel_range();
    if let Some(s) = &fig.secondary {
        let ax = |mm: f64| (mm - s.zero_mm[0]) * s.per_mm;
        let ay = |mm: f64| (mm - s.zero_mm[1]) * s.per_mm;
        let mut angles = ChartBuilder::on(&body)
            .margin_left(MARGIN + LEFT)
            .margin_top(6)
            .margin_bottom(BOTTOM)
            .set_label_area_size(LabelAreaPosition::Top, arcsec)
            .set_label_area_size(LabelAreaPosition::Right, right_axis)
            .build_cartesian_2d(ax(x0)..ax(x1), ay(y0)..ay(y1))?;
        angles
            .configure_mesh()
            .disable_mesh()
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(&|v| format!("{v:.0}"))
            .x_desc(s.x_desc.as_str())
            .y_desc(s.y_desc.as_str())
            .label_style(label)
            .axis_desc_style(("sans-serif", 14))
            .draw()?;
    }
    let top = TOP_TITLE as i32 + arcsec as i32;
    let bar_area = right.shrink((36, top), (26 + 62, ih.min(h)));
    draw_colour_bar(&bar_area, fig, max)?;
    Ok(plot_area)
}

/// The colour bar: the map from value to colour, labelled with the unit.
fn draw_colour_bar(area: &Area, fig: &ImageFigure, max: f64) -> Result<(), Error> {
    let (lo, hi, name) = match fig.scale {
        Scale::Linear => (0.0, max.max(f64::MIN_POSITIVE), fig.unit.clone()),
        Scale::Log { decades } => {
            let top = if max > 0.0 { max.log10() } else { 0.0 };
            (
                top - decades.max(1) as f64,
                top,
                format!("log₁₀ ({}), {} decades", fig.unit, decades.max(1)),
            )
        }
    };
    // Room for the widest tick label (2.00e8 fits 62 px; 2.50e-14, an X-ray
    // rate through a magnet, needs more, or the unit overlaps it).
    let widest = match fig.scale {
        Scale::Linear => [lo, hi, 0.5 * hi].map(|v| scientific(v).chars().count()),
        Scale::Log { .. } => [lo, hi, 0.5 * (lo + hi)].map(|v| format!("{v:.1}").chars().count()),
    }
    .into_iter()
    .max()
    .unwrap_or(6);
    let mut bar = ChartBuilder::on(area)
        .set_label_area_size(LabelAreaPosition::Right, (8 * widest as u32 + 14).max(62))
        .build_cartesian_2d(0.0..1.0, lo..hi)?;
    bar.configure_mesh()
        .disable_mesh()
        .set_tick_mark_size(LabelAreaPosition::Right, 6)
        .disable_x_axis()
        .y_desc(name)
        .y_label_formatter(&|v| match fig.scale {
            Scale::Linear => scientific(*v),
            Scale::Log { .. } => format!("{v:.1}"),
        })
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 14))
        .draw()?;
    let steps = 256;
    bar.draw_series((0..steps).map(|i| {
        let (a, b) = (i as f64 / steps as f64, (i + 1) as f64 / steps as f64);
        let value = match fig.scale {
            Scale::Linear => a.max(1e-9) * max,
            Scale::Log { .. } => 10f64.powf(lo + a * (hi - lo)),
        };
        let c = viridis(value, max, fig.scale);
        Rectangle::new(
            [(0.0, lo + a * (hi - lo)), (1.0, lo + b * (hi - lo))],
            RGBColor(c[0], c[1], c[2]).filled(),
        )
    }))?;
    Ok(())
}

/// A tick label in scientific notation (2.5e11), plain for 0.
fn scientific(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if (1e-2..1e4).contains(&v.abs()) {
        format!("{v:.3}")
            .trim_end_matches('0')
            .trim_end_matches('.')
            .into()
    } else {
        format!("{v:.2e}")
    }
}

/// Copies the image into the plot area: each screen pixel the mean of the image
/// pixels under it, row 0 of the image at the bottom.
fn blit(
    img: &mut image::RgbImage,
    fig: &ImageFigure,
    (xs, ys): (std::ops::Range<i32>, std::ops::Range<i32>),
    max: f64,
) {
    let [nx, ny] = fig.pixels;
    let (dw, dh) = (
        (xs.end - xs.start).max(1) as usize,
        (ys.end - ys.start).max(1) as usize,
    );
    for j in 0..dh {
        // Screen row j (from the top) covers image rows [r0, r1) from the bottom.
        let r1 = ny - (j * ny) / dh;
        let r0 = (ny - ((j + 1) * ny).div_ceil(dh)).min(r1 - 1);
        for i in 0..dw {
            let c0 = (i * nx) / dw;
            let c1 = ((i + 1) * nx).div_ceil(dw).max(c0 + 1).min(nx);
            let mut sum = 0.0;
            for r in r0..r1 {
                sum += fig.values[r * nx + c0..r * nx + c1].iter().sum::<f64>();
            }
            let mean = sum / ((r1 - r0) * (c1 - c0)) as f64;
            // On a log scale the lowest decade must not pass for nothing.
            let c = match fig.scale {
                Scale::Log { .. } if mean <= 0.0 => NO_FLUX,
                _ => viridis(mean, max, fig.scale),
            };
            let (x, y) = (xs.start + i as i32, ys.start + j as i32);
            if x >= 0 && y >= 0 && (x as u32) < img.width() && (y as u32) < img.height() {
                img.put_pixel(x as u32, y as u32, image::Rgb(c));
            }
        }
    }
}

/// Draws the overlay over the image in the plot area `(xs, ys)` (screen
/// pixels): circles in white over a dark edge (seen on any colour), the
/// centroid as a red cross, labels beside the circles, a message centred.
fn draw_overlay(
    img: &mut image::RgbImage,
    fig: &ImageFigure,
    (xs, ys): (std::ops::Range<i32>, std::ops::Range<i32>),
) -> Result<(), Error> {
    let o = &fig.overlay;
    if o.centroid_mm.is_none() && o.message.is_none() && o.corner.is_none() {
        return Ok(());
    }
    let (w, h) = img.dimensions();
    let root = BitMapBackend::with_buffer(img.as_mut(), (w, h)).into_drawing_area();
    let [[x0, x1], [y0, y1]] = fig.extent_mm;
    let sx = (xs.end - xs.start) as f64 / (x1 - x0);
    let sy = (ys.end - ys.start) as f64 / (y1 - y0);
    let at = |x: f64, y: f64| {
        (
            xs.start + ((x - x0) * sx).round() as i32,
            ys.start + ((y1 - y) * sy).round() as i32,
        )
    };
    let inside = |(px, py): (i32, i32)| xs.contains(&px) && ys.contains(&py);
    if let Some([cx, cy]) = o.centroid_mm {
        // Solid, dashed, dotted: the circles tell themselves apart where
        // they come close, and the legend says which is which.
        for (k, (r, _)) in o.circles_mm.iter().enumerate() {
            let (on, period) = CIRCLE_DASHES[k.min(CIRCLE_DASHES.len() - 1)];
            let points: Vec<(i32, i32)> = (0..=1440)
                .map(|d| {
                    let t = (d as f64 / 4.0).to_radians();
                    at(cx + r * t.cos(), cy + r * t.sin())
                })
                .collect();
            // Arc length along the circle on screen, for the dashes.
            let mut s = 0.0;
            let mut drawn = Vec::with_capacity(points.len());
            for (i, p) in points.iter().enumerate() {
                if i > 0 {
                    let q = points[i - 1];
                    s += f64::from(p.0 - q.0).hypot(f64::from(p.1 - q.1));
                }
                drawn.push(inside(*p) && s % period < on);
            }
            let mut start = 0;
            while start < points.len() {
                let end = (start..points.len())
                    .find(|&i| drawn[i] != drawn[start])
                    .unwrap_or(points.len());
                if drawn[start] && end - start > 1 {
                    let run = points[start..end].to_vec();
                    root.draw(&PathElement::new(run.clone(), BLACK.stroke_width(3)))?;
                    root.draw(&PathElement::new(run, WHITE.stroke_width(1)))?;
                }
                start = end;
            }
        }
        // The legend in the plot's top left corner: the circles, inner first.
        let labels: Vec<String> = o
            .circles_mm
            .iter()
            .enumerate()
            .map(|(k, (_, l))| format!("{} {l}", CIRCLE_MARKS[k.min(CIRCLE_MARKS.len() - 1)]))
            .collect();
        let legend = format!("+ centroid;  circles: {}", labels.join(", "));
        boxed(&root, &legend, (xs.start + 8, ys.start + 6), 14)?;
        let c = at(cx, cy);
        if inside(c) {
            let red = RGBColor(230, 40, 40).stroke_width(2);
            root.draw(&PathElement::new(vec![(c.0 - 6, c.1), (c.0 + 6, c.1)], red))?;
            root.draw(&PathElement::new(vec![(c.0, c.1 - 6), (c.0, c.1 + 6)], red))?;
        }
    }
    if let Some(c) = &o.corner {
        boxed(&root, c, (xs.start + 8, ys.end - 26), 14)?;
    }
    if let Some(m) = &o.message {
        // Centred on the image.
        let style: TextStyle = ("sans-serif", 20).into_font().into();
        let (tw, _) = root.estimate_text_size(m, &style)?;
        let x = ((xs.start + xs.end) / 2 - tw as i32 / 2).max(xs.start + 8);
        boxed(&root, m, (x, (ys.start + ys.end) / 2 - 10), 20)?;
    }
    root.present()?;
    Ok(())
}

/// Haloed text on a pale box: a halo alone does not read on a speckled log
/// image.
fn boxed(root: &Area, text: &str, (x, y): (i32, i32), size: u32) -> Result<(), Error> {
    let style: TextStyle = ("sans-serif", size).into_font().into();
    let (tw, th) = root.estimate_text_size(text, &style)?;
    root.draw(&Rectangle::new(
        [(x - 4, y - 3), (x + tw as i32 + 4, y + th as i32 + 3)],
        WHITE.mix(0.8).filled(),
    ))?;
    haloed(root, text, (x, y), size)
}

/// Black text in a white halo: readable on any colour of the map.
pub(super) fn haloed(root: &Area, text: &str, (x, y): (i32, i32), size: u32) -> Result<(), Error> {
    let halo = ("sans-serif", size).into_font().color(&WHITE);
    for (dx, dy) in [
        (-1, -1),
        (-1, 1),
        (1, -1),
        (1, 1),
        (0, -1),
        (0, 1),
        (-1, 0),
        (1, 0),
    ] {
        root.draw(&Text::new(text.to_string(), (x + dx, y + dy), halo.clone()))?;
    }
    let font = ("sans-serif", size).into_font().color(&BLACK);
    root.draw(&Text::new(text.to_string(), (x, y), font))?;
    Ok(())
}
