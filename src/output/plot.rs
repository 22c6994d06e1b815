//! Line plots (PNG) with plotters: reflectivity curves now, encircled-energy
//! curves later. The font is compiled in (data/fonts), so plots look the same on
//! every machine; files are written atomically.

use super::write_rgb_png;
use plotters::prelude::*;
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
}

impl Series {
    /// A curve through `points`.
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series {
            label: label.into(),
            points,
            dots: false,
            color: None,
        }
    }

    /// The same series drawn in palette colour `index`.
    pub fn with_color(self, index: usize) -> Series {
        Series {
            color: Some(index),
            ..self
        }
    }

    /// Measured points, drawn as dots.
    pub fn dots(label: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series {
            dots: true,
            ..Series::line(label, points)
        }
    }
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
    register_font();
    let (w, h) = size;
    let mut buf = vec![0u8; (w * h * 3) as usize];
    let finite = || {
        series
            .iter()
            .flat_map(|s| s.points.iter())
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
    let pad = 0.04 * (y1 - y0);
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        let draw = || -> Result<(), Box<dyn std::error::Error + '_>> {
            root.fill(&WHITE)?;
            let mut chart = ChartBuilder::on(&root)
                .caption(title, ("sans-serif", 22))
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(60)
                .build_cartesian_2d(x0..x1, (y0 - pad)..(y1 + pad))?;
            chart
                .configure_mesh()
                .x_desc(x_label)
                .y_desc(y_label)
                .label_style(("sans-serif", 15))
                .draw()?;
            for (i, s) in series.iter().enumerate() {
                let color = Palette99::pick(s.color.unwrap_or(i)).to_rgba();
                if s.dots {
                    chart
                        .draw_series(s.points.iter().map(|&p| Circle::new(p, 4, color.filled())))?
                        .label(s.label.clone())
                        .legend(move |(x, y)| Circle::new((x + 10, y), 4, color.filled()));
                } else {
                    chart
                        .draw_series(LineSeries::new(
                            s.points.iter().copied(),
                            color.stroke_width(2),
                        ))?
                        .label(s.label.clone())
                        .legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                        });
                }
            }
            if series.len() > 1 || !series.first().is_some_and(|s| s.label.is_empty()) {
                chart
                    .configure_series_labels()
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK)
                    .label_font(("sans-serif", 15))
                    .draw()?;
            }
            root.present()?;
            Ok(())
        };
        draw().map_err(|e| std::io::Error::other(format!("plot {}: {e}", path.display())))?;
    }
    let img = image::RgbImage::from_raw(w, h, buf).expect("buffer of the right size");
    write_rgb_png(path, &img)
}
