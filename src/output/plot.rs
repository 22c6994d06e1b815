//! Line plots (PNG) with plotters: reflectivity, encircled energy, spectra,
//! effective area, focus and fit curves. The font is compiled in (data/fonts),
//! so plots look the same on every machine; files are written atomically.
//! Every plot follows the same rules: tick labels in scientific notation
//! (2×10¹⁰) when the numbers are large or small, the legend in the corner that
//! hides the fewest points, and markers on curves with few points (five angles
//! are not a curve).

use super::write_rgb_png;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;
use std::sync::Once;

const FONT: &[u8] = include_bytes!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/data/fonts/DejaVuSans.ttf"
));

pub(super) fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // Cannot fail for a valid TTF; a failure would only lose the text.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// One curve: legend label and (x, y) points.
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    /// Draw the points as dots (measurements) instead of joining them (curves).
    pub dots: bool,
    /// Palette colour index (default: the series' position), so that a fit and
    /// its measurements can share a colour.
    pub color: Option<usize>,
    /// Mark the points of a curve with few of them (off for guide lines).
    pub markers: bool,
    /// An uncertainty band: (low, high) at each point's x, shaded in the
    /// curve's colour.
    pub band: Option<Vec<(f64, f64)>>,
    /// Drawn dashed (a reference line, not a result).
    pub dashed: bool,
}

/// Line colours readable on white and told apart with the common colour-vision
/// deficiencies: the Okabe–Ito palette (Okabe & Ito, "Color Universal Design",
/// 2008) without its yellow, which vanishes on white, then black.
const PALETTE: [(u8, u8, u8); 7] = [
    (0, 114, 178),   // blue
    (213, 94, 0),    // vermillion
    (0, 158, 115),   // bluish green
    (204, 121, 167), // reddish purple
    (86, 180, 233),  // sky blue
    (230, 159, 0),   // orange
    (0, 0, 0),       // black
];

/// Colour number `i` of [`PALETTE`] (repeating).
pub(super) fn palette(i: usize) -> RGBColor {
    let (r, g, b) = PALETTE[i % PALETTE.len()];
    RGBColor(r, g, b)
}

/// A curve with at most this many points also marks them.
const SPARSE: usize = 12;

impl Series {
    /// A curve through `points`.
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series {
            label: label.into(),
            points,
            dots: false,
            color: None,
            markers: true,
            band: None,
            dashed: false,
        }
    }

    /// The same curve with a shaded band from `low_high[i].0` to `.1` at the
    /// x of point i (one pair per point).
    pub fn with_band(self, low_high: Vec<(f64, f64)>) -> Series {
        Series {
            band: Some(low_high),
            ..self
        }
    }

    /// The same curve dashed and without markers: a reference line.
    pub fn dashed(self) -> Series {
        Series {
            dashed: true,
            markers: false,
            ..self
        }
    }

    /// The same curve without point markers (a guide line, a fitted curve).
    pub fn without_markers(self) -> Series {
        Series {
            markers: false,
            ..self
        }
    }

    /// The same series drawn in palette colour `index`.
    pub fn with_color(self, index: usize) -> Series {
        Series {
            color: Some(index),
            ..self
        }
    }

    /// Points drawn as dots, not joined (measurements, simulated points).
    pub fn dots(label: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series {
            dots: true,
            ..Series::line(label, points)
        }
    }
}

/// The x and y ranges of the series' finite points, widened to a unit when
/// empty or a single value.
fn data_ranges(series: &[Series]) -> ((f64, f64), (f64, f64)) {
    // A band's edges count as points (the band is not clipped).
    let band_points: Vec<(f64, f64)> = series
        .iter()
        .filter_map(|s| Some((s, s.band.as_ref()?)))
        .flat_map(|(s, b)| {
            s.points
                .iter()
                .zip(b)
                .flat_map(|(p, &(lo, hi))| [(p.0, lo), (p.0, hi)])
        })
        .collect();
    let finite = || {
        series
            .iter()
            .flat_map(|s| s.points.iter())
            .chain(&band_points)
            .filter(|p| p.0.is_finite() && p.1.is_finite())
    };
    let (mut x0, mut x1) = finite().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
        (a.min(p.0), b.max(p.0))
    });
    let (mut y0, mut y1) = finite().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
        (a.min(p.1), b.max(p.1))
    });
    // No points, or all on one value: give the axis some extent.
    if !x0.is_finite() {
        (x0, x1) = (0.0, 1.0);
    } else if x0 >= x1 {
        (x0, x1) = (x0 - 0.5, x0 + 0.5);
    }
    if !y0.is_finite() {
        (y0, y1) = (0.0, 1.0);
    } else if y0 >= y1 {
        (y0, y1) = (y0 - 0.5, y0 + 0.5);
    }
    ((x0, x1), (y0, y1))
}

/// Draws `series` into a `width × height` PNG with axis labels and a legend.
pub fn line_plot(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    size: (u32, u32),
) -> std::io::Result<()> {
    line_plot_with_top_axis(path, (title, x_label, y_label), series, size, None)
}

/// A second x axis along the top of a line plot: the bottom axis's values
/// times `scale`, under `label` (an EEF in arcsec gets mm on top).
pub struct TopAxis<'a> {
    pub label: &'a str,
    pub scale: f64,
}

/// [`line_plot`] with, if given, a second x axis along the top.
pub fn line_plot_with_top_axis(
    path: &Path,
    (title, x_label, y_label): (&str, &str, &str),
    series: &[Series],
    size: (u32, u32),
    top: Option<TopAxis>,
) -> std::io::Result<()> {
    register_font();
    let (w, h) = size;
    let mut buf = vec![0u8; (w * h * 3) as usize];
    let ((x0, x1), (y0, y1)) = data_ranges(series);
    let pad = 0.04 * (y1 - y0);
    // Quantities that cannot be negative (fluxes, areas, fractions) start at 0.
    let floor = if y0 >= 0.0 { 0.0 } else { y0 - pad };
    let (mut y_lo, mut y_hi) = (floor.min(y0), y1 + pad);
    let show_legend = series.len() > 1 || !series.first().is_some_and(|s| s.label.is_empty());
    let corner = if show_legend {
        let (corner, top) = place_legend(series, size, (x0, x1), (y_lo, y_hi));
        y_hi = top;
        corner
    } else {
        SeriesLabelPosition::UpperRight
    };
    if y_lo >= y_hi {
        y_lo = y_hi - 1.0;
    }
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        let draw = || -> Result<(), Box<dyn std::error::Error + '_>> {
            root.fill(&WHITE)?;
            // With a top axis (drawn by hand: the mesh would put the bottom
            // axis's labels there too) the title goes above the room it needs.
            let titled;
            let mut builder = match top {
                None => {
                    let mut b = ChartBuilder::on(&root);
                    b.caption(typeset(title), ("sans-serif", 22)).margin(12);
                    b
                }
                Some(_) => {
                    titled = root.titled(&typeset(title), ("sans-serif", 22))?;
                    let mut b = ChartBuilder::on(&titled);
                    b.margin(12).margin_top(50);
                    b
                }
            };
            let mut chart = builder
                .x_label_area_size(45)
                .y_label_area_size(85)
                .build_cartesian_2d(x0..x1, y_lo..y_hi)?;
            let (x_span, y_span) = (x0.abs().max(x1.abs()), y0.abs().max(y1.abs()));
            chart
                .configure_mesh()
                .x_desc(typeset(x_label))
                .y_desc(typeset(y_label))
                .x_label_formatter(&|v| tick_label(*v, x_span))
                .y_label_formatter(&|v| tick_label(*v, y_span))
                .label_style(("sans-serif", 15))
                .draw()?;
            draw_curves(&mut chart, series)?;
            if show_legend {
                chart
                    .configure_series_labels()
                    .position(corner)
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK)
                    .label_font(("sans-serif", 15))
                    .draw()?;
            }
            if let Some(t) = &top {
                draw_top_axis(&root, &chart, t, (x0, x1), y_hi)?;
            }
            root.present()?;
            Ok(())
        };
        draw().map_err(|e| std::io::Error::other(format!("plot {}: {e}", path.display())))?;
    }
    let img = image::RgbImage::from_raw(w, h, buf).expect("buffer of the right size");
    write_rgb_png(path, &img)
}

/// The top axis: ticks at round values of the top quantity along the plot's
/// upper edge, their labels above and the axis name above them.
fn draw_top_axis<'b>(
    root: &DrawingArea<BitMapBackend<'b>, plotters::coord::Shift>,
    chart: &Chart<'_, 'b>,
    top: &TopAxis,
    (x0, x1): (f64, f64),
    y_hi: f64,
) -> Result<(), Box<dyn std::error::Error + 'b>> {
    let (a, b) = (x0 * top.scale, x1 * top.scale);
    let span = a.abs().max(b.abs());
    let rough = (b - a) / 8.0;
    let decade = 10f64.powf(rough.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * decade)
        .find(|s| *s >= rough)
        .unwrap_or(10.0 * decade);
    let style =
        TextStyle::from(("sans-serif", 15).into_font()).pos(Pos::new(HPos::Center, VPos::Bottom));
    let mut k = (a / step).ceil();
    let mut edge = 0;
    while k * step <= b + 1e-9 * step {
        let v = k * step;
        let (px, py) = chart.backend_coord(&(v / top.scale, y_hi));
        root.draw(&PathElement::new(vec![(px, py), (px, py - 5)], BLACK))?;
        root.draw(&Text::new(tick_label(v, span), (px, py - 7), style.clone()))?;
        edge = py;
        k += 1.0;
    }
    let (lo, _) = chart.backend_coord(&(x0, y_hi));
    let (hi, _) = chart.backend_coord(&(x1, y_hi));
    root.draw(&PathElement::new(vec![(lo, edge), (hi, edge)], BLACK))?;
    root.draw(&Text::new(
        typeset(top.label),
        ((lo + hi) / 2, edge - 26),
        style,
    ))?;
    Ok(())
}

type Chart<'a, 'b> = ChartContext<
    'a,
    BitMapBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// The series onto the chart: every band first (under every curve), then the
/// curves, dashed lines and dots, each with its legend entry.
fn draw_curves<'b>(
    chart: &mut Chart<'_, 'b>,
    series: &[Series],
) -> Result<(), Box<dyn std::error::Error + 'b>> {
    for (i, s) in series.iter().enumerate() {
        let Some(band) = &s.band else { continue };
        let color = palette(s.color.unwrap_or(i)).mix(0.25);
        let upper = s.points.iter().zip(band).map(|(p, b)| (p.0, b.1));
        let lower = s.points.iter().zip(band).rev().map(|(p, b)| (p.0, b.0));
        chart.draw_series(std::iter::once(Polygon::new(
            upper.chain(lower).collect::<Vec<_>>(),
            color.filled(),
        )))?;
    }
    for (i, s) in series.iter().enumerate() {
        let color = palette(s.color.unwrap_or(i)).to_rgba();
        if s.dashed {
            chart
                .draw_series(DashedLineSeries::new(
                    s.points.iter().copied(),
                    8,
                    5,
                    color.stroke_width(2),
                ))?
                .label(typeset(&s.label))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 8, y)], color.stroke_width(2))
                });
        } else if s.dots {
            chart
                .draw_series(s.points.iter().map(|&p| Circle::new(p, 4, color.filled())))?
                .label(typeset(&s.label))
                .legend(move |(x, y)| Circle::new((x + 10, y), 4, color.filled()));
        } else {
            chart
                .draw_series(LineSeries::new(
                    s.points.iter().copied(),
                    color.stroke_width(2),
                ))?
                .label(typeset(&s.label))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
            if s.points.len() <= SPARSE && s.markers {
                chart.draw_series(s.points.iter().map(|&p| Circle::new(p, 4, color.filled())))?;
            }
        }
    }
    Ok(())
}

/// A tick label: plain for moderate numbers, a×10ⁿ when the axis spans large
/// or small magnitudes (`span`: the largest absolute value on the axis).
pub fn tick_label(v: f64, span: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if (1e-2..1e5).contains(&span) {
        let text = format!("{v:.4}");
        let text = text.trim_end_matches('0').trim_end_matches('.');
        return if text == "-0" {
            "0".into()
        } else {
            text.into()
        };
    }
    let exponent = v.abs().log10().floor() as i32;
    let mantissa = v / 10f64.powi(exponent);
    let m = format!("{mantissa:.2}");
    let m = m.trim_end_matches('0').trim_end_matches('.');
    let power = format!("10{}", superscript(exponent));
    if m == "1" {
        power
    } else if m == "-1" {
        format!("-{power}")
    } else {
        format!("{m}×{power}")
    }
}

/// An integer in superscript digits (⁻¹⁰).
pub fn superscript(n: i32) -> String {
    n.to_string()
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            _ => '⁹',
        })
        .collect()
}

/// Text for a plot: couplings with subscripts (g_aγ → gₐᵧ, g_ae → gₐₑ) and
/// numbers written as 1e-10 as powers of ten (10⁻¹⁰, 2.5×10⁻¹³).
pub fn typeset(text: &str) -> String {
    let text = text
        .replace("g_aγ", "gₐᵧ")
        .replace("g_ae", "gₐₑ")
        .replace("R_sun", "R☉");
    text.split(' ')
        .map(|word| {
            let core = word.trim_end_matches([',', ')', ';']);
            let tail = &word[core.len()..];
            let (lead, number) = match core.strip_prefix('(') {
                Some(n) => ("(", n),
                None => ("", core),
            };
            match number.parse::<f64>() {
                Ok(v) if number.contains('e') && v != 0.0 => {
                    format!("{lead}{}{tail}", tick_label(v, v.abs().max(1e6)))
                }
                _ => word.to_string(),
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// Where the legend goes: the corner (of four) under which no point of any
/// series lies; if every corner covers data, the upper right with the y axis
/// raised so that the legend sits above the data. Returns the corner and the
/// y axis' upper end. The legend's size is estimated from its text (15 px
/// font: about 8.5 px per character, 20 px per line) and the plot's size.
fn place_legend(
    series: &[Series],
    (w, h): (u32, u32),
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> (SeriesLabelPosition, f64) {
    let chars = series
        .iter()
        .map(|s| typeset(&s.label).chars().count())
        .max()
        .unwrap_or(0);
    let (plot_w, plot_h) = (
        (w as f64 - 85.0 - 24.0).max(1.0),
        (h as f64 - 45.0 - 64.0).max(1.0),
    );
    let fw = ((chars as f64 * 8.5 + 50.0) / plot_w).min(1.0);
    let fh = ((series.len() as f64 * 20.0 + 24.0) / plot_h).min(0.9);
    let corners = [
        (
            SeriesLabelPosition::UpperRight,
            (1.0 - fw, 1.0),
            (1.0 - fh, 1.0),
        ),
        (SeriesLabelPosition::UpperLeft, (0.0, fw), (1.0 - fh, 1.0)),
        (SeriesLabelPosition::LowerRight, (1.0 - fw, 1.0), (0.0, fh)),
        (SeriesLabelPosition::LowerLeft, (0.0, fw), (0.0, fh)),
    ];
    let fraction = |v: f64, lo: f64, hi: f64| (v - lo) / (hi - lo);
    let covered = |fx: (f64, f64), fy: (f64, f64)| {
        series
            .iter()
            .flat_map(|s| {
                // A joined curve also passes between its points: sample it.
                let dense = if s.dots { 1 } else { 8 };
                let between = s.points.windows(2).flat_map(move |p| {
                    (1..dense).map(move |k| {
                        let t = k as f64 / dense as f64;
                        (
                            p[0].0 + t * (p[1].0 - p[0].0),
                            p[0].1 + t * (p[1].1 - p[0].1),
                        )
                    })
                });
                s.points.iter().copied().chain(between)
            })
            .filter(|&(x, y)| {
                let (u, v) = (fraction(x, x0, x1), fraction(y, y0, y1));
                (fx.0..=fx.1).contains(&u) && (fy.0..=fy.1).contains(&v)
            })
            .count()
    };
    if let Some((corner, _, _)) = corners.iter().find(|(_, fx, fy)| covered(*fx, *fy) == 0) {
        return (corner.clone(), y1);
    }
    // Raise the top so that the data keeps below the legend's lower edge.
    let raised = y0 + (y1 - y0) / (1.0 - fh - 0.02);
    (SeriesLabelPosition::UpperRight, raised)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_band_is_inside_the_axes() {
        // The curve reaches 5, its band 7 and −1: the axes must show the band.
        let s = Series::line("a", vec![(0.0, 2.0), (1.0, 5.0)])
            .with_band(vec![(-1.0, 3.0), (4.0, 7.0)]);
        let (_, (y0, y1)) = data_ranges(&[s]);
        assert_eq!((y0, y1), (-1.0, 7.0));
    }
}
