//! The reach as files: `reach.csv` (per run and mass: the signal and
//! background counts, the median expected limit on the counts and on the
//! coupling), `reach.png` (log m_a against log of the coupling, one curve per
//! run — per buffer-gas setting — with the vacuum plateau marked) and
//! `reach.json` (settings, region, provenance).
//!
//! Data flow: `cli::reach` computes the limits with `analysis::reach` and
//! calls [`write_reach`].

use super::csv_table::write_csv;
use super::plot::{palette, register_font, superscript, typeset};
use super::Provenance;
use crate::analysis::reach::Exposure;
use crate::studies::reach::ReachCurve;
use plotters::prelude::*;
use serde_json::json;
use std::path::Path;

/// The files `traxer reach` writes.
pub const REACH_FILES: [&str; 3] = ["reach.csv", "reach.png", "reach.json"];

/// Writes the reach of `curves` into `dir`; `coupling` names what is limited
/// ("g_agamma" or "g_ae_g_agamma").
pub fn write_reach(
    dir: &Path,
    curves: &[ReachCurve],
    coupling: &str,
    (exposure, window): (&Exposure, [f64; 2]),
    provenance: &Provenance,
) -> std::io::Result<()> {
    let f = |v: f64| format!("{v:e}");
    let limit_column = format!("{coupling}_limit_per_gev");
    write_csv(
        &dir.join(REACH_FILES[0]),
        &[
            "run",
            "setting",
            "tracking_hours",
            "axion_mass_ev",
            "signal_counts_at_run_couplings",
            "background_counts",
            "counts_limit",
            &limit_column,
        ],
        curves.iter().flat_map(|c| {
            c.limits.iter().map(move |l| {
                vec![
                    c.run.clone(),
                    c.label.clone(),
                    f(c.tracking_hours),
                    f(l.mass_ev),
                    f(l.signal),
                    f(l.background),
                    f(l.counts_limit),
                    l.coupling_limit.map_or("inf".into(), f),
                ]
            })
        }),
    )?;
    write_plot(&dir.join(REACH_FILES[1]), curves, coupling)?;
    let doc = json!({
        "provenance": provenance,
        "what": "the median expected 95 % CL upper limit under the background-only hypothesis: CLs (Read 2002), exact Poisson up to 1e6 background counts and the normal limit above, one bin (the signal region and energy window); n = the median of Poisson(background); the coupling from the counts as the signal's power law (Primakoff: s ∝ g_aγ⁴; ABC: s ∝ (g_ae g_aγ)²)",
        "coupling": coupling,
        "exposure": exposure,
        "exposure_note": "tracking_hours of the first run; each run's own under runs[]",
        "energy_window_keV": window,
        "runs": curves.iter().map(|c| json!({"run": c.run, "setting": c.label, "region": c.region, "tracking_hours": c.tracking_hours})).collect::<Vec<_>>(),
        "files": REACH_FILES,
    });
    super::run_files::write_json(&dir.join(REACH_FILES[2]), &doc)
}

/// Each curve's points with a mass (m_a > 0 on a log axis), the vacuum
/// plateau (the least limit at m_a = 0) and the axes' ranges.
type PlotData = (Vec<Vec<(f64, f64)>>, Option<f64>, ((f64, f64), (f64, f64)));

fn plot_data(curves: &[ReachCurve]) -> PlotData {
    let points: Vec<Vec<(f64, f64)>> = curves
        .iter()
        .map(|c| {
            c.limits
                .iter()
                .filter_map(|l| Some((l.mass_ev, l.coupling_limit?)))
                .filter(|p| p.0 > 0.0 && p.1.is_finite())
                .collect()
        })
        .collect();
    let plateau: Option<f64> = curves
        .iter()
        .flat_map(|c| &c.limits)
        .filter(|l| l.mass_ev == 0.0)
        .filter_map(|l| l.coupling_limit)
        .reduce(f64::min);
    let all = points.iter().flatten();
    let (x0, x1) = all.clone().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
        (a.min(p.0), b.max(p.0))
    });
    let (x0, x1) = if x0.is_finite() {
        (x0 / 2.0, x1 * 2.0)
    } else {
        (1e-4, 1.0)
    };
    let ys = all.map(|p| p.1).chain(plateau);
    let (y0, y1) = ys.fold((f64::INFINITY, 0.0f64), |(a, b), y| (a.min(y), b.max(y)));
    let (y0, y1) = if y0.is_finite() {
        (y0 / 1.5, y1 * 3.0)
    } else {
        (1e-12, 1e-9)
    };
    (points, plateau, ((x0, x1), (y0, y1)))
}

/// 1, 2 and 5 × 10ⁿ within [lo, hi] (every decade's 1 alone beyond three
/// decades).
pub(super) fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    let (a, b) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let steps: &[f64] = if b - a > 3 { &[1.0] } else { &[1.0, 2.0, 5.0] };
    (a..=b)
        .flat_map(|e| steps.iter().map(move |k| k * 10f64.powi(e)))
        .filter(|v| *v >= lo && *v <= hi)
        .collect()
}

/// A tick at 1, 2 or 5 × 10ⁿ labelled (2×10⁻¹¹): a limit curve spans a
/// decade or two; other ticks unlabelled.
pub(super) fn power(v: f64) -> String {
    let e = v.log10().floor();
    let m = v / 10f64.powf(e);
    match [1.0, 2.0, 5.0].iter().find(|k| (m / *k - 1.0).abs() < 1e-6) {
        Some(1.0) => format!("10{}", superscript(e as i32)),
        Some(k) => format!("{k}×10{}", superscript(e as i32)),
        None => String::new(),
    }
}

/// A limit plot's titled axes, log m_a against log `what` (the coupling's
/// symbol) over the ranges given, with its light mesh drawn.
pub(super) type LimitChart<'a, 'b> =
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<KeyPoints, KeyPoints>>;

/// A log axis with the ticks of [`ticks`].
type KeyPoints = plotters::coord::combinators::WithKeyPoints<LogCoord<f64>>;

/// [`LimitChart`] on `root`.
pub(super) fn limit_chart<'a, 'b>(
    root: &'a DrawingArea<BitMapBackend<'b>, plotters::coord::Shift>,
    title: &str,
    what: &str,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> Result<LimitChart<'a, 'b>, Box<dyn std::error::Error + 'a>> {
    let mut chart = ChartBuilder::on(root)
        .caption(typeset(title), ("sans-serif", 22))
        .margin(14)
        .margin_right(40)
        .x_label_area_size(48)
        .y_label_area_size(90)
        .build_cartesian_2d(
            (x0..x1).log_scale().with_key_points(ticks(x0, x1)),
            (y0..y1).log_scale().with_key_points(ticks(y0, y1)),
        )?;
    chart
        .configure_mesh()
        .x_desc("mₐ (eV)")
        .y_desc(typeset(&format!("{what} (GeV⁻¹)")))
        .x_label_formatter(&|v| power(*v))
        .y_label_formatter(&|v| power(*v))
        .label_style(("sans-serif", 15))
        .light_line_style(RGBColor(238, 238, 238))
        .draw()?;
    Ok(chart)
}

/// log m_a against log coupling; massless points (m_a = 0) set the dashed
/// vacuum plateau across the plot instead of a point.
fn write_plot(path: &Path, curves: &[ReachCurve], coupling: &str) -> std::io::Result<()> {
    register_font();
    let (w, h) = (900u32, 620u32);
    let (points, plateau, ranges) = plot_data(curves);
    let ((x0, x1), (y0, y1)) = ranges;
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        let draw = || -> Result<(), Box<dyn std::error::Error + '_>> {
            root.fill(&WHITE)?;
            let what = if coupling == "g_agamma" {
                "g_aγ"
            } else {
                "g_ae·g_aγ"
            };
            let title = format!("median expected 95 % CL limit on {what}");
            let mut chart = limit_chart(&root, &title, what, (x0, x1), (y0, y1))?;
            if let Some(p) = plateau {
                let grey = RGBColor(110, 110, 110);
                chart
                    .draw_series(DashedLineSeries::new(
                        [(x0, p), (x1, p)],
                        8,
                        5,
                        grey.stroke_width(1),
                    ))?
                    .label(typeset(&format!(
                        "vacuum plateau (mₐ → 0): {}",
                        crate::text::number(p)
                    )))
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], grey));
            }
            for (i, c) in curves.iter().enumerate() {
                let color = palette(i).to_rgba();
                let pts = &points[i];
                chart
                    .draw_series(LineSeries::new(pts.iter().copied(), color.stroke_width(2)))?
                    .label(c.label.clone())
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
                chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))?;
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperLeft)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 15))
                .draw()?;
            root.present()?;
            Ok(())
        };
        draw().map_err(|e| std::io::Error::other(format!("plot {}: {e}", path.display())))?;
    }
    let img = image::RgbImage::from_raw(w, h, buf).expect("buffer of the right size");
    super::write_rgb_png(path, &img)
}
