//! The expected signal of a helioscope run in a signal region: for each axion
//! mass of the run (its scene's mass, or the masses of a mass scan), the
//! X-rays per second converting in the detector within a circle on the
//! sensor, in all and per energy band. The circle is placed on the image of
//! one mass — the one the user names, or the run's brightest (for a helium
//! setting its resonance, in vacuum the lightest mass) — centred on a given
//! point or on that image's centroid, with a given radius or the radius
//! holding a given fraction of that image's flux; one region serves every
//! mass, so that the masses compare like for like. Each
//! pixel's flux is spread over its area, as for the encircled energy
//! ([`super::eef`]): no lattice bias.
//!
//! Data flow: `output::run_read` reads a results folder into a [`RunSignal`];
//! [`signal`] measures it; `output::signal` writes the tables and `reach`
//! turns them into limits.

use super::eef::rectangle_in_disk;
use super::ImageGeometry;

/// What a finished magnet run holds for one sensor, in X-rays per second.
#[derive(Clone, Debug)]
pub struct RunSignal {
    /// The sensor's name and its geometry.
    pub sensor: String,
    pub geometry: ImageGeometry,
    /// The energy bands' edges (keV), bands + 1 values (one band over the
    /// source's range without energy bins).
    pub band_edges: Vec<f64>,
    /// The axion masses (eV) with their images [band][iy][ix] (X-rays/s).
    pub masses: Vec<f64>,
    pub images: Vec<Vec<f64>>,
    /// The run's couplings (GeV⁻¹; g_ae dimensionless) and emission.
    pub g_agamma: f64,
    pub g_ae: Option<f64>,
    pub emission: String,
    /// The buffer gas, as the run's summary describes it (`None`: vacuum).
    pub gas: Option<String>,
}

/// Where the signal region's circle lies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Centre {
    /// The centroid of the image that places the region.
    Centroid,
    /// A point (mm) in the sensor's frame.
    At([f64; 2]),
}

/// How large it is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Size {
    RadiusMm(f64),
    /// The radius holding this fraction of the image that places the region.
    Fraction(f64),
}

/// A signal region: a circle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    pub centre: Centre,
    pub size: Size,
    /// The mass (eV) whose image places the circle; `None`: the run's
    /// brightest (the most X-rays per second on the sensor).
    pub on_mass: Option<f64>,
}

/// The signal of one mass.
#[derive(Clone, Debug, PartialEq)]
pub struct MassSignal {
    pub mass_ev: f64,
    /// X-rays per second in the region, in all and per band.
    pub rate: f64,
    pub spectrum: Vec<f64>,
    /// X-rays per second on the whole sensor.
    pub sensor_rate: f64,
}

/// The signal of every mass in one region.
#[derive(Clone, Debug, PartialEq)]
pub struct Signal {
    pub centre_mm: [f64; 2],
    pub radius_mm: f64,
    /// The circle's area on the sensor (cm²): the background's area.
    pub area_cm2: f64,
    /// The mass (eV) whose image placed the circle.
    pub placed_on_mass_ev: f64,
    /// The fraction of that image's flux inside.
    pub fraction: f64,
    pub band_edges: Vec<f64>,
    pub masses: Vec<MassSignal>,
}

/// Why a region cannot be measured.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct RegionError(pub String);

/// The index of the mass whose image places the region: `on_mass` (one of
/// the run's masses, to 1e-9 relative), or the brightest on the sensor.
fn placing_image(run: &RunSignal, on_mass: Option<f64>) -> Result<usize, RegionError> {
    match on_mass {
        Some(m) => run
            .masses
            .iter()
            .position(|&r| (r - m).abs() <= 1e-9 * r.abs().max(m.abs()))
            .ok_or_else(|| {
                let known: Vec<String> = run.masses.iter().map(|&m| crate::text::number(m)).collect();
                RegionError(format!(
                    "--region-mass {}: not one of the run's masses ({} eV); the region is placed on the image of one of them",
                    crate::text::number(m),
                    crate::text::shorten(&known.join(", "), 200)
                ))
            }),
        None => {
            let rates: Vec<f64> = run.images.iter().map(|i| i.iter().sum()).collect();
            // The first of equal ones: a vacuum scan's lightest masses can
            // tie to the last digit.
            Ok((0..rates.len()).fold(0, |best, k| if rates[k] > rates[best] { k } else { best }))
        }
    }
}

/// The signal of `run` in `region`.
pub fn signal(run: &RunSignal, region: &Region) -> Result<Signal, RegionError> {
    let g = &run.geometry;
    let plane = g.nx * g.ny;
    let placing = placing_image(run, region.on_mass)?;
    let mass = run.masses[placing];
    let reference = crate::sensor::sum_bands(&run.images[placing], plane);
    let empty = || {
        RegionError(format!(
            "the image at m_a = {} eV, which places the region, holds no flux: name another with --region-mass (region_mass in Python)",
            crate::text::number(mass)
        ))
    };
    let centre = match region.centre {
        Centre::At(c) => c,
        Centre::Centroid => {
            super::analyse(&reference, g, None)
                .ok_or_else(empty)?
                .0
                .centroid_mm
        }
    };
    let radius = match region.size {
        Size::RadiusMm(r) if r.is_finite() && r > 0.0 => r,
        Size::Fraction(f) if f > 0.0 && f < 1.0 => {
            super::radius_holding(&reference, g, centre, f).ok_or_else(empty)?
        }
        Size::RadiusMm(r) => {
            return Err(RegionError(format!(
                "--radius-mm {}: a radius is > 0 (mm)",
                crate::text::number(r)
            )))
        }
        Size::Fraction(f) => {
            return Err(RegionError(format!(
                "--fraction {}: the region holds a fraction in (0, 1) of the flux",
                crate::text::number(f)
            )))
        }
    };
    let within = |img: &[f64]| super::flux_within(img, g, centre, &[radius])[0];
    let masses = run
        .masses
        .iter()
        .zip(&run.images)
        .map(|(&m, img)| {
            let spectrum: Vec<f64> = img.chunks_exact(plane).map(within).collect();
            MassSignal {
                mass_ev: m,
                rate: spectrum.iter().sum(),
                spectrum,
                sensor_rate: img.iter().sum(),
            }
        })
        .collect();
    // The circle's area on the sensor: the sensor's rectangle inside it.
    let (x0, y0) = (g.origin_mm[0] - centre[0], g.origin_mm[1] - centre[1]);
    let (x1, y1) = (x0 + g.nx as f64 * g.pitch[0], y0 + g.ny as f64 * g.pitch[1]);
    let total: f64 = reference.iter().sum();
    let area_mm2 = rectangle_in_disk(x0, x1, y0, y1, radius);
    if area_mm2.is_nan() || area_mm2 <= 0.0 {
        // A region off the sensor counts nothing and no background: its
        // zeros would read as a result.
        return Err(RegionError(format!(
            "the circle of {} mm about ({}, {}) mm lies off the sensor (x {} to {} mm, y {} to {} mm in its frame): give --center inside it",
            crate::text::number(radius),
            crate::text::number(centre[0]),
            crate::text::number(centre[1]),
            crate::text::number(g.origin_mm[0]),
            crate::text::number(g.origin_mm[0] + g.nx as f64 * g.pitch[0]),
            crate::text::number(g.origin_mm[1]),
            crate::text::number(g.origin_mm[1] + g.ny as f64 * g.pitch[1]),
        )));
    }
    Ok(Signal {
        centre_mm: centre,
        radius_mm: radius,
        area_cm2: area_mm2 * 1e-2,
        placed_on_mass_ev: mass,
        fraction: if total > 0.0 {
            within(&reference) / total
        } else {
            0.0
        },
        band_edges: run.band_edges.clone(),
        masses,
    })
}
