//! A campaign's reach as files: `reach.csv` (per mass: the combined limit,
//! how many settings it combines, the signal and background counts, the best
//! single setting's limit), `reach_settings.csv` (per mass and setting: its
//! counts and its limit alone), `reach.png` (one curve: the vacuum plateau
//! and the gas phase, the settings' photon masses marked along the bottom,
//! the best single setting's limit beside it) and `reach.json` (the
//! statistic, the exposure, the region, every setting and every part).
//!
//! Data flow: `cli::reach` calls [`write_campaign_reach`] with what
//! `studies::campaign_reach::reach` returns.

use super::csv_table::write_csv;
use super::plot::register_font;
use super::reach::limit_chart;
use super::reference_curve::ReferenceCurve;
use super::Provenance;
use crate::studies::campaign_reach::CampaignReach;
use plotters::prelude::*;
use serde_json::json;
use std::path::Path;

/// The files `traxer reach` writes for a campaign.
pub const CAMPAIGN_REACH_FILES: [&str; 4] =
    ["reach.csv", "reach_settings.csv", "reach.png", "reach.json"];

/// What the combined limit is, in words.
pub const COMBINED_STATISTIC: &str = "the median expected 95 % CL upper limit under the background-only hypothesis: CLs (Read 2002) with the likelihood ratio Q = L(s+b)/L(b) of all channels of the settings that recorded the mass (LEP's combination), its distribution exact by Fourier transform (Hu & Nielsen 1999) on a grid of 512 steps of the largest weight, T normal above ~6e4 expected counts; one channel is the one-bin exact-Poisson CLs (3.0 counts without background); the observed statistic at the median of the background-only distribution; the coupling from the counts as the signal's power law";

pub fn write_campaign_reach(
    dir: &Path,
    r: &CampaignReach,
    provenance: &Provenance,
    reference: &[ReferenceCurve],
) -> std::io::Result<()> {
    let f = |v: f64| format!("{v:e}");
    let opt = |v: Option<f64>| v.map_or("inf".into(), f);
    let limit_column = format!("{}_limit_per_gev", r.coupling);
    write_csv(
        &dir.join(CAMPAIGN_REACH_FILES[0]),
        &[
            "axion_mass_ev",
            &limit_column,
            "settings_combined",
            "signal_counts_at_run_couplings",
            "background_counts",
            "best_single_setting",
            "best_single_limit_per_gev",
        ],
        r.limits.iter().map(|l| {
            let best = l.best_alone();
            vec![
                f(l.mass_ev),
                opt(l.coupling_limit),
                l.parts.len().to_string(),
                f(l.parts.iter().map(|p| p.signal).sum()),
                f(l.parts.iter().map(|p| p.background).sum()),
                best.map_or(String::new(), |b| r.settings[b.0].label.clone()),
                opt(best.map(|b| b.1)),
            ]
        }),
    )?;
    write_csv(
        &dir.join(CAMPAIGN_REACH_FILES[1]),
        &[
            "axion_mass_ev",
            "setting",
            "label",
            "pressure_mbar",
            "photon_mass_ev",
            "tracking_hours",
            "signal_counts_at_run_couplings",
            "background_counts",
            "alone_limit_per_gev",
        ],
        r.limits.iter().flat_map(|l| {
            l.parts.iter().map(move |p| {
                let s = &r.settings[p.setting];
                vec![
                    f(l.mass_ev),
                    p.setting.to_string(),
                    s.label.clone(),
                    f(s.pressure_mbar),
                    f(s.photon_mass_ev),
                    f(s.tracking_hours),
                    f(p.signal),
                    f(p.background),
                    opt(p.alone),
                ]
            })
        }),
    )?;
    write_plot(&dir.join(CAMPAIGN_REACH_FILES[2]), r, reference)?;
    let mut doc = campaign_reach_json(r);
    doc["provenance"] = json!(provenance);
    doc["files"] = json!(CAMPAIGN_REACH_FILES);
    doc["reference_curves"] = reference
        .iter()
        .map(|c| json!({"file": c.file, "points": c.points.len(), "drawn_in": CAMPAIGN_REACH_FILES[2]}))
        .collect();
    super::run_files::write_json(&dir.join(CAMPAIGN_REACH_FILES[3]), &doc)
}

/// reach.json's content (without its provenance and file list): what
/// Python's `traxer.reach` returns for a campaign.
pub fn campaign_reach_json(r: &CampaignReach) -> serde_json::Value {
    json!({
        "what": COMBINED_STATISTIC,
        "channels": if r.binned { "each setting's energy bins × rings inside the region and window" } else { "one per setting: its region and window" },
        "coupling": r.coupling,
        "exposure": r.exposure,
        "exposure_note": "bores, efficiency and background for every setting; each setting's hours under settings[]",
        "energy_window_keV": r.window,
        "region": {"center_mm": r.centre_mm, "radius_mm": r.radius_mm, "area_cm2": r.area_cm2},
        "settings": r.settings,
        "masses": r.limits.iter().map(|l| json!({
            "axion_mass_ev": l.mass_ev,
            "limit_per_gev": l.coupling_limit,
            "method": l.method,
            "parts": l.parts.iter().map(|p| json!({"setting": p.setting, "signal_counts": p.signal, "background_counts": p.background, "alone_limit_per_gev": p.alone})).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
    })
}

/// The coupling's symbol for the axis and caption.
fn coupling_symbol(coupling: &str) -> &'static str {
    match coupling {
        "g_agamma" => "g_aγ",
        _ => "g_ae·g_aγ",
    }
}

/// The combined curve, the best single setting's, and a tick per gas
/// setting at its photon mass along the bottom.
fn write_plot(path: &Path, r: &CampaignReach, reference: &[ReferenceCurve]) -> std::io::Result<()> {
    register_font();
    let (w, h) = (900u32, 620u32);
    let PlotData {
        curve,
        alone,
        gas,
        x: (x0, x1),
        y: (y0, y1),
        reference,
    } = plot_data(r, reference);
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        let draw = || -> Result<(), Box<dyn std::error::Error + '_>> {
            root.fill(&WHITE)?;
            let what = coupling_symbol(r.coupling);
            let title = format!("median expected 95 % CL limit on {what}: the campaign");
            let mut chart = limit_chart(&root, &title, what, (x0, x1), (y0, y1))?;
            let grey = RGBColor(120, 120, 120);
            chart
                .draw_series(LineSeries::new(alone.iter().copied(), grey.stroke_width(1)))?
                .label("the best single setting")
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], grey));
            let blue = RGBColor(31, 90, 180);
            chart
                .draw_series(LineSeries::new(curve.iter().copied(), blue.stroke_width(2)))?
                .label(format!(
                    "{} settings combined per mass",
                    if r.settings.len() > 1 { "the" } else { "its" }
                ))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], blue.stroke_width(2))
                });
            for (k, (label, points)) in reference.into_iter().enumerate() {
                // Green, then purple, brown and grey-blue.
                let colour = [(30, 140, 60), (130, 50, 160), (150, 90, 40), (70, 110, 140)][k % 4];
                let c = RGBColor(colour.0, colour.1, colour.2);
                chart
                    .draw_series(DashedLineSeries::new(points, 6, 4, c.stroke_width(2)))?
                    .label(label)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
                    });
            }
            let orange = RGBColor(220, 110, 20);
            let tick = y0 * (y1 / y0).powf(0.035);
            chart
                .draw_series(
                    gas.iter().map(|&m| {
                        PathElement::new(vec![(m, y0), (m, tick)], orange.stroke_width(1))
                    }),
                )?
                .label(format!(
                    "a gas setting's photon mass ({} settings)",
                    gas.len()
                ))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x + 10, y - 6), (x + 10, y + 6)], orange)
                });
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

/// What the plot draws: the combined curve, the best single setting's, the
/// gas settings' photon masses, and the axes' ranges.
struct PlotData {
    curve: Vec<(f64, f64)>,
    alone: Vec<(f64, f64)>,
    gas: Vec<f64>,
    x: (f64, f64),
    y: (f64, f64),
    /// Each reference curve's label and its points inside the mass range.
    reference: Vec<(String, Vec<(f64, f64)>)>,
}

fn plot_data(r: &CampaignReach, reference: &[ReferenceCurve]) -> PlotData {
    let curve: Vec<(f64, f64)> = r
        .limits
        .iter()
        .filter_map(|l| Some((l.mass_ev, l.coupling_limit?)))
        .filter(|p| p.0 > 0.0 && p.1.is_finite())
        .collect();
    let alone: Vec<(f64, f64)> = r
        .limits
        .iter()
        .filter_map(|l| Some((l.mass_ev, l.best_alone()?.1)))
        .filter(|p| p.0 > 0.0 && p.1.is_finite())
        .collect();
    let gas: Vec<f64> = r
        .settings
        .iter()
        .map(|s| s.photon_mass_ev)
        .filter(|m| *m > 0.0)
        .collect();
    let xs = curve.iter().map(|p| p.0).chain(gas.iter().copied());
    let (x0, x1) = xs.fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
    let (x0, x1) = if x0.is_finite() {
        (x0 / 1.5, x1 * 1.5)
    } else {
        (1e-4, 1.0)
    };
    let reference: Vec<_> = reference
        .iter()
        .map(|c| {
            let inside = c
                .points
                .iter()
                .copied()
                .filter(|p| (x0..=x1).contains(&p.0));
            (c.label.clone(), inside.collect::<Vec<_>>())
        })
        .collect();
    let drawn = reference.iter().flat_map(|c| &c.1);
    let ys = curve.iter().chain(&alone).chain(drawn).map(|p| p.1);
    let (y0, y1) = ys.fold((f64::INFINITY, 0.0f64), |(a, b), y| (a.min(y), b.max(y)));
    let (y0, y1) = if y0.is_finite() {
        (y0 / 2.0, (y1 * 2.0).min(y0 * 1e3))
    } else {
        (1e-12, 1e-9)
    };
    PlotData {
        curve,
        alone,
        gas,
        x: (x0, x1),
        y: (y0, y1),
        reference,
    }
}
