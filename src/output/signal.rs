//! The expected signal in a signal region, per axion mass, as files: the
//! counts (`signal.csv`), their spectrum in the sensor's energy bands
//! (`signal_spectrum.csv`, and `signal_spectrum.fits`: one BINTABLE
//! `SPECTRUM` per mass with ENERG_LO, ENERG_HI in keV like an OGIP ARF
//! (CAL/GEN/92-002) and RATE in X-rays per second; a model spectrum in energy
//! bins, not a PHA file of detector channels), and `signal.json` (region,
//! run, provenance).
//!
//! Data flow: `cli::signal` measures with `analysis::signal` and calls
//! [`write_signal`].

use super::csv_table::write_csv;
use super::fits::{provenance_keys, write_keys, Keys};
use super::Provenance;
use crate::analysis::signal::{RunSignal, Signal};
use crate::files::atomic_write;
use fitsio::tables::{ColumnDataType, ColumnDescription};
use fitsio::FitsFile;
use serde_json::json;
use std::path::Path;

/// The files `traxer signal` writes.
pub const SIGNAL_FILES: [&str; 4] = [
    "signal.csv",
    "signal_spectrum.csv",
    "signal_spectrum.fits",
    "signal.json",
];

const HOUR: f64 = 3600.0;

/// Writes the signal of `run` into `dir`.
pub fn write_signal(
    dir: &Path,
    run: &RunSignal,
    s: &Signal,
    provenance: &Provenance,
) -> std::io::Result<()> {
    let f = |v: f64| format!("{v:e}");
    write_csv(
        &dir.join(SIGNAL_FILES[0]),
        &[
            "axion_mass_ev",
            "x_rays_per_s",
            "x_rays_per_hour_of_tracking",
            "x_rays_per_s_on_sensor",
            "fraction_of_sensor",
        ],
        s.masses.iter().map(|m| {
            vec![
                f(m.mass_ev),
                f(m.rate),
                f(m.rate * HOUR),
                f(m.sensor_rate),
                f(if m.sensor_rate > 0.0 {
                    m.rate / m.sensor_rate
                } else {
                    0.0
                }),
            ]
        }),
    )?;
    let edges = &s.band_edges;
    write_csv(
        &dir.join(SIGNAL_FILES[1]),
        &[
            "axion_mass_ev",
            "energy_lo_kev",
            "energy_hi_kev",
            "x_rays_per_s",
            "x_rays_per_hour_of_tracking",
        ],
        s.masses.iter().flat_map(|m| {
            m.spectrum.iter().enumerate().map(move |(b, r)| {
                vec![
                    f(m.mass_ev),
                    f(edges[b]),
                    f(edges[b + 1]),
                    f(*r),
                    f(r * HOUR),
                ]
            })
        }),
    )?;
    write_spectrum_fits(&dir.join(SIGNAL_FILES[2]), run, s, provenance)?;
    let doc = json!({
        "provenance": provenance,
        "what": "the X-rays per second expected in a circle on the sensor (converting in the detector's gas for a gas detector), for each axion mass of the run at its couplings; each pixel's flux spread over its area (no lattice bias); one region for every mass, placed on the image of the mass region.placed_on_mass_ev (the one asked for, or the run's brightest)",
        "sensor": run.sensor,
        "region": {
            "center_mm": s.centre_mm,
            "radius_mm": s.radius_mm,
            "area_cm2": s.area_cm2,
            "placed_on_mass_ev": s.placed_on_mass_ev,
            "fraction_of_flux_at_that_mass": s.fraction,
        },
        "run": {
            "emission": run.emission,
            "g_agamma_per_gev": run.g_agamma,
            "g_ae": run.g_ae,
            "buffer_gas": run.gas,
        },
        "energy_band_edges_keV": s.band_edges,
        "masses": s.masses.iter().map(|m| json!({
            "axion_mass_ev": m.mass_ev,
            "x_rays_per_s": m.rate,
            "x_rays_per_hour_of_tracking": m.rate * HOUR,
            "spectrum_x_rays_per_s": m.spectrum,
        })).collect::<Vec<_>>(),
        "files": SIGNAL_FILES,
    });
    super::run_files::write_json(&dir.join(SIGNAL_FILES[3]), &doc)
}

/// The spectra as FITS, written to a temporary file and moved into place.
fn write_spectrum_fits(
    path: &Path,
    run: &RunSignal,
    s: &Signal,
    provenance: &Provenance,
) -> std::io::Result<()> {
    let tmp = tempfile::Builder::new()
        .prefix("traxer-signal-")
        .tempdir()?;
    let file = tmp.path().join("signal.fits");
    spectrum_fits(&file, run, s, provenance).map_err(|e| {
        std::io::Error::other(format!("{}: writing the spectrum: {e}", path.display()))
    })?;
    atomic_write(path, &std::fs::read(&file)?)
}

fn spectrum_fits(
    path: &Path,
    run: &RunSignal,
    s: &Signal,
    provenance: &Provenance,
) -> fitsio::errors::Result<()> {
    let mut f = FitsFile::create(path).open()?;
    let column = |name: &str| {
        ColumnDescription::new(name)
            .with_type(ColumnDataType::Double)
            .create()
    };
    let (lo, hi) = (&s.band_edges[..s.band_edges.len() - 1], &s.band_edges[1..]);
    for (k, m) in s.masses.iter().enumerate() {
        let columns = [column("ENERG_LO")?, column("ENERG_HI")?, column("RATE")?];
        let hdu = f.create_table("SPECTRUM", &columns)?;
        hdu.write_col(&mut f, "ENERG_LO", lo)?;
        hdu.write_col(&mut f, "ENERG_HI", hi)?;
        hdu.write_col(&mut f, "RATE", &m.spectrum)?;
        let mut keys = Keys::default();
        keys.text("TUNIT1", "keV", "");
        keys.text("TUNIT2", "keV", "");
        keys.text("TUNIT3", "ct / s", "X-rays per second in the region");
        keys.int("EXTVER", k as i64 + 1, "one extension per axion mass");
        keys.float("MASS_EV", m.mass_ev, "[eV] axion mass");
        keys.float("G_AGAMMA", run.g_agamma, "[GeV-1] the run's g_agamma");
        if let Some(g) = run.g_ae {
            keys.float("G_AE", g, "the run's g_ae");
        }
        keys.float(
            "REG_X",
            s.centre_mm[0],
            "[mm] signal region centre, sensor x",
        );
        keys.float(
            "REG_Y",
            s.centre_mm[1],
            "[mm] signal region centre, sensor y",
        );
        keys.float("REG_R", s.radius_mm, "[mm] signal region radius");
        keys.float(
            "REG_AREA",
            s.area_cm2,
            "[cm2] signal region area on the sensor",
        );
        keys.text("HDUCLASS", "OGIP", "energy bins as in an OGIP ARF");
        keys.text(
            "HDUCLAS1",
            "SPECTRUM",
            "a model rate spectrum, not channels",
        );
        keys.text("HDUCLAS3", "RATE", "");
        keys.text("TELESCOP", &run.sensor, "the sensor of the run");
        keys.text("INSTRUME", "traxer", "a raytrace, not a measurement");
        provenance_keys(&mut keys, provenance, "signal.json");
        write_keys(&mut f, &hdu, keys)?;
    }
    Ok(())
}
