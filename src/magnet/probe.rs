//! P(E) of a magnet without tracing: along an axial line of the bore, or
//! averaged over the bore's cross-section, for lists of energies and axion
//! masses (`traxer conversion`, Python's `conversion_probability`).
//!
//! Data flow: the command builds a [`super::Magnet`] (a scene's, or one from
//! its options) and asks [`table`] for the rows it prints and writes.

use super::Magnet;
use glam::DVec3;

/// The rings of the bore average (× 2 rings sectors: 8 192 axial lines).
/// Through BabyIAXO's map at 4 keV the average at 64 rings is within 1.6e-4
/// of that at 512 (16 rings, the old default, were 4.7e-3 high; 32, 2.2e-3
/// low): the map's kinks between nodes make the midpoint rule converge
/// slowly, so the default is chosen by measuring, and
/// tests/it/magnet.rs `the_bore_average_is_converged_to_1e_3` keeps it so.
pub const BORE_AVERAGE_RINGS: usize = 64;

/// Where the probability is taken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Where {
    /// The axial line through (x, y) mm of the bore's cross-section.
    Line([f64; 2]),
    /// The mean over `rings` × 2·`rings` axial lines at the centres of
    /// equal-area cells of the bore's cross-section (each line stands for the
    /// same area: the mean is the average over the aperture).
    BoreAverage { rings: usize },
}

/// One row: energy (keV), axion mass (eV), P.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row {
    pub energy_kev: f64,
    pub mass_ev: f64,
    pub probability: f64,
}

/// The axial lines (origin, unit direction, world) `at` stands for. Axions
/// travel towards the bore's −z end, as in traxer's scenes (the Sun on +z).
pub fn lines(magnet: &Magnet, at: Where) -> Vec<(DVec3, DVec3)> {
    let dir = magnet.frame.vector(DVec3::NEG_Z).normalize();
    let line = |x: f64, y: f64| (magnet.frame.point(DVec3::new(x, y, 0.0)), dir);
    match at {
        Where::Line([x, y]) => vec![line(x, y)],
        Where::BoreAverage { rings } => {
            let mut out = Vec::new();
            let sectors = 2 * rings;
            for i in 0..rings {
                // Ring i spans the radii holding the area fractions i/n … (i+1)/n;
                // its lines sit at the radius halving the ring's area.
                let r = magnet.radius_mm * ((i as f64 + 0.5) / rings as f64).sqrt();
                for j in 0..sectors {
                    let phi = std::f64::consts::TAU * (j as f64 + 0.5) / sectors as f64;
                    out.push(line(r * phi.cos(), r * phi.sin()));
                }
            }
            out
        }
    }
}

/// P for every (energy, mass), energies outer, masses inner, averaged over
/// the lines of `at`.
pub fn table(magnet: &Magnet, at: Where, energies_kev: &[f64], masses_ev: &[f64]) -> Vec<Row> {
    let paths: Vec<_> = lines(magnet, at)
        .into_iter()
        .map(|(o, d)| magnet.path_of(o, d))
        .collect();
    let mut rows = Vec::with_capacity(energies_kev.len() * masses_ev.len());
    for &e in energies_kev {
        for &m in masses_ev {
            let sum: f64 = paths.iter().map(|p| p.probability(magnet, e, m)).sum();
            rows.push(Row {
                energy_kev: e,
                mass_ev: m,
                probability: sum / paths.len() as f64,
            });
        }
    }
    rows
}
