//! `traxer.signal` and `traxer.reach`: the expected X-rays in a signal region
//! per axion mass, and the limit on the coupling versus the mass, from
//! finished magnet runs, as `traxer signal` and `traxer reach` compute them
//! (the same library calls).

use crate::convert::{array, json};
use crate::errors::input;
use crate::units::{number, numbers, optional, Unit};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use traxer::analysis::reach::Exposure;
use traxer::analysis::signal::{signal as measure, Centre, Region, Size};
use traxer::output::campaign_reach_json;
use traxer::output::campaign_read::{is_campaign_run, read_campaign_run};
use traxer::output::run_read::read_run_signal;
use traxer::studies::campaign_reach::{reach as campaign_reach_of, CampaignReachRequest};
use traxer::studies::reach::reach as reach_of;

/// The region from the keyword arguments (plain numbers in mm and eV, or
/// astropy Quantities).
fn region(
    radius_mm: Option<&Bound<'_, PyAny>>,
    fraction: Option<f64>,
    centre: Option<&Bound<'_, PyAny>>,
    region_mass: Option<&Bound<'_, PyAny>>,
) -> PyResult<Region> {
    let radius_mm = optional("radius_mm", radius_mm, Unit::Mm)?;
    let centre = match centre.filter(|c| !c.is_none()) {
        None => None,
        Some(c) => match numbers("center", c, Unit::Mm)?.as_slice() {
            [x, y] => Some((*x, *y)),
            _ => return Err(input("center: two coordinates (x, y) in mm")),
        },
    };
    let on_mass = optional("region_mass", region_mass, Unit::Ev)?;
    let size = match (radius_mm, fraction) {
        (Some(r), None) => Size::RadiusMm(r),
        (None, Some(f)) => Size::Fraction(f),
        _ => return Err(input("give radius_mm or fraction, one of them")),
    };
    Ok(Region {
        centre: centre.map_or(Centre::Centroid, |(x, y)| Centre::At([x, y])),
        size,
        on_mass,
    })
}

/// signal(run, radius_mm=None, fraction=None, center=None, sensor=None, region_mass=None)
///
/// The expected X-rays in a signal region per axion mass, as `traxer signal`,
/// from the results folder `run` of a trace with the magnet on: a circle of
/// `radius_mm`, or the one holding `fraction` of the flux of the image that
/// places it (that of `region_mass` in eV, default the run's brightest),
/// about `center` (mm, the sensor's frame) or that image's centroid. Returns a
/// dict: sensor, center_mm, radius_mm, area_cm2, placed_on_mass_eV, fraction, energy_band_edges_keV,
/// masses_eV, x_rays_per_s [mass], x_rays_per_hour [mass], spectrum_x_rays_per_s
/// [mass, band].
#[pyfunction]
#[pyo3(signature = (run, radius_mm = None, fraction = None, center = None, sensor = None, region_mass = None))]
pub fn signal<'py>(
    py: Python<'py>,
    run: PathBuf,
    radius_mm: Option<&Bound<'py, PyAny>>,
    fraction: Option<f64>,
    center: Option<&Bound<'py, PyAny>>,
    sensor: Option<String>,
    region_mass: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let region = region(radius_mm, fraction, center, region_mass)?;
    let r = read_run_signal(&run, sensor.as_deref()).map_err(|e| input(e.0))?;
    let s = measure(&r, &region).map_err(|e| input(e.0))?;
    let d = PyDict::new(py);
    let n = s.masses.len();
    let bands = s.band_edges.len() - 1;
    d.set_item("sensor", r.sensor)?;
    d.set_item("center_mm", (s.centre_mm[0], s.centre_mm[1]))?;
    d.set_item("radius_mm", s.radius_mm)?;
    d.set_item("area_cm2", s.area_cm2)?;
    d.set_item("placed_on_mass_eV", s.placed_on_mass_ev)?;
    d.set_item("fraction", s.fraction)?;
    d.set_item("energy_band_edges_keV", s.band_edges.clone())?;
    let each = |f: &dyn Fn(&traxer::analysis::signal::MassSignal) -> f64| {
        array(py, &[n], s.masses.iter().map(f).collect())
    };
    d.set_item("masses_eV", each(&|m| m.mass_ev)?)?;
    d.set_item("x_rays_per_s", each(&|m| m.rate)?)?;
    d.set_item("x_rays_per_hour", each(&|m| m.rate * 3600.0)?)?;
    let spectra = s.masses.iter().flat_map(|m| m.spectrum.clone()).collect();
    d.set_item("spectrum_x_rays_per_s", array(py, &[n, bands], spectra)?)?;
    Ok(d)
}

/// reach(runs, background, tracking_hours=None, radius_mm=None, fraction=None, center=None, window=None, bores=1.0, efficiency=1.0, sensor=None, region_mass=None, binned=False)
///
/// The median expected 95 % CL upper limit on g_aγ (Primakoff runs) or
/// g_ae·g_aγ (ABC runs) per axion mass, as `traxer reach`: CLs, exact
/// Poisson, one bin (the region and the energy `window` (lo, hi) keV, on the
/// run's band edges; default all), `background` in counts per keV per cm² per
/// second, `tracking_hours` for every run or a list with one per run, `bores` identical lines, `efficiency`
/// beyond the run's; each run's region placed on the image of `region_mass`
/// (eV) or its brightest. Quantities are taken for the background, hours,
/// lengths and masses. Returns a dict: coupling, window_keV and curves, one per
/// run: setting, run, region, tracking_hours, masses_eV, signal, background, counts_limit and
/// limit (NaN without signal).
///
/// A campaign run (one folder holding campaign.json) gives one combined
/// curve, as `traxer reach` on it: the settings that recorded each mass
/// combined, their tracking hours from the run unless `tracking_hours` lists
/// one per setting, `binned=True` for channels of energy bins × rings. Returns
/// reach.json's content as a dict (what, channels, coupling, exposure,
/// energy_window_keV, region, settings, masses [{axion_mass_ev,
/// limit_per_gev, method, parts}]) with `masses_eV` and `limit` as arrays
/// (NaN where no setting sees the mass).
#[pyfunction]
#[pyo3(signature = (runs, background, tracking_hours = None, radius_mm = None, fraction = None, center = None, window = None, bores = 1.0, efficiency = 1.0, sensor = None, region_mass = None, binned = false))]
#[allow(clippy::too_many_arguments)]
pub fn reach<'py>(
    py: Python<'py>,
    runs: &Bound<'py, PyAny>,
    background: &Bound<'py, PyAny>,
    tracking_hours: Option<&Bound<'py, PyAny>>,
    radius_mm: Option<&Bound<'py, PyAny>>,
    fraction: Option<f64>,
    center: Option<&Bound<'py, PyAny>>,
    window: Option<&Bound<'py, PyAny>>,
    bores: f64,
    efficiency: f64,
    sensor: Option<String>,
    region_mass: Option<&Bound<'py, PyAny>>,
    binned: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let background = number("background", background, Unit::BackgroundRate)?;
    // One folder (a str or a path) or a list of them.
    let runs: Vec<PathBuf> = match runs.extract::<PathBuf>() {
        Ok(one)
            if !runs.is_instance_of::<pyo3::types::PyList>()
                && !runs.is_instance_of::<pyo3::types::PyTuple>() =>
        {
            vec![one]
        }
        _ => runs
            .extract::<Vec<PathBuf>>()
            .map_err(|_| input("runs: a results folder (str or path) or a list of them"))?,
    };
    if runs.is_empty() {
        return Err(input("runs: give at least one results folder"));
    }
    let window = match window.filter(|w| !w.is_none()) {
        None => None,
        Some(w) => match numbers("window", w, Unit::KeV)?.as_slice() {
            [lo, hi] => Some((*lo, *hi)),
            _ => return Err(input("window: two energies (lo, hi) in keV")),
        },
    };
    let region = region(radius_mm, fraction, center, region_mass)?;
    let hours = match tracking_hours.filter(|h| !h.is_none()) {
        Some(h) => numbers("tracking_hours", h, Unit::Hour)?,
        None => Vec::new(),
    };
    if let [one] = &runs[..] {
        if is_campaign_run(one) {
            let campaign = CampaignQuery {
                background,
                hours,
                window,
                bores,
                efficiency,
                binned,
            };
            return campaign_reach(py, one, sensor.as_deref(), &region, campaign);
        }
    }
    if binned {
        return Err(input(
            "binned: channels of energy bins × rings need a campaign run (a trace with [magnet.campaign])",
        ));
    }
    if hours.is_empty() {
        return Err(input(
            "tracking_hours: give the hours of tracking, one for every run or one per run",
        ));
    }
    let exposures = hours
        .iter()
        .map(|&h| Exposure::checked(h, bores, efficiency, background))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| input(e.0))?;
    let runs = runs
        .iter()
        .map(|d| Ok((d.as_path(), read_run_signal(d, sensor.as_deref())?)))
        .collect::<Result<Vec<_>, traxer::output::run_read::RunReadError>>()
        .map_err(|e| input(e.0))?;
    let r = reach_of(&runs, &region, window.map(|(a, b)| [a, b]), &exposures)
        .map_err(|e| input(e.0))?;
    let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
    for w in &r.warnings {
        let message = std::ffi::CString::new(w.as_str()).unwrap_or_default();
        PyErr::warn(py, &category, &message, 1)?;
    }
    let curves = pyo3::types::PyList::empty(py);
    for c in &r.curves {
        let d = PyDict::new(py);
        let n = c.limits.len();
        let each = |f: &dyn Fn(&traxer::analysis::reach::Limit) -> f64| {
            array(py, &[n], c.limits.iter().map(f).collect())
        };
        d.set_item("setting", &c.label)?;
        d.set_item("run", &c.run)?;
        d.set_item("region", json(py, &c.region)?)?;
        d.set_item("tracking_hours", c.tracking_hours)?;
        d.set_item("masses_eV", each(&|l| l.mass_ev)?)?;
        d.set_item("signal", each(&|l| l.signal)?)?;
        d.set_item("background", each(&|l| l.background)?)?;
        d.set_item("counts_limit", each(&|l| l.counts_limit)?)?;
        d.set_item("limit", each(&|l| l.coupling_limit.unwrap_or(f64::NAN))?)?;
        curves.append(d)?;
    }
    let d = PyDict::new(py);
    d.set_item("coupling", r.coupling)?;
    d.set_item("window_keV", (r.window[0], r.window[1]))?;
    d.set_item("curves", curves)?;
    Ok(d)
}

/// What `reach` was asked, for a campaign run.
struct CampaignQuery {
    background: f64,
    hours: Vec<f64>,
    window: Option<(f64, f64)>,
    bores: f64,
    efficiency: f64,
    binned: bool,
}

/// `reach` on a campaign run: the combined curve, as `traxer reach`.
fn campaign_reach<'py>(
    py: Python<'py>,
    dir: &std::path::Path,
    sensor: Option<&str>,
    region: &Region,
    q: CampaignQuery,
) -> PyResult<Bound<'py, PyDict>> {
    if let Centre::At(_) = region.centre {
        return Err(input("center: a campaign's rings lie about the centre_mm it was traced with (campaign.json); trace with [magnet.campaign] centre_mm = [X, Y] to move them"));
    }
    let run = read_campaign_run(dir, sensor).map_err(|e| input(e.0))?;
    let request = CampaignReachRequest {
        size: region.size,
        on_mass: region.on_mass,
        window: q.window.map(|(a, b)| [a, b]),
        hours: (!q.hours.is_empty()).then_some(q.hours),
        bores: q.bores,
        efficiency: q.efficiency,
        background: q.background,
        binned: q.binned,
    };
    let r = campaign_reach_of(&run, &request).map_err(|e| input(e.0))?;
    let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
    for w in &r.warnings {
        let message = std::ffi::CString::new(w.as_str()).unwrap_or_default();
        PyErr::warn(py, &category, &message, 1)?;
    }
    let d = json(py, &campaign_reach_json(&r))?.cast_into::<PyDict>()?;
    let n = r.limits.len();
    let masses = r.limits.iter().map(|l| l.mass_ev).collect();
    let limits = r
        .limits
        .iter()
        .map(|l| l.coupling_limit.unwrap_or(f64::NAN))
        .collect();
    d.set_item("masses_eV", array(py, &[n], masses)?)?;
    d.set_item("limit", array(py, &[n], limits)?)?;
    Ok(d)
}
