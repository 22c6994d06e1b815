//! Precomputed reflectivity R(E, θ) of one coating for the photon loop: rows of
//! fixed energy over the scene's energy range, each along x = E sin θ up to
//! grazing angles θ_max; cubic (Catmull–Rom) interpolation in x (uniform step),
//! linear in energy (nodes where they are needed).
//!
//! The grid is sized to the coating (`table_grid.rs`): refined against the exact
//! Parratt value until the interpolation error is within 1e-4 (tested in
//! tests/it/xray.rs on random points over whole tables of the shipped coatings), so
//! a single gold layer takes a few MB and a multilayer what its fringes need.
//!
//! Grazing angles above θ_max (rare in X-ray optics) are evaluated directly.

use super::coating::Coating;
use super::optical::EnergyOutOfRange;
use super::table_grid::{build_grid, Row};

/// An energy located in a table's energy nodes ([`ReflectivityTable::energy_cell`]).
#[derive(Clone, Copy, Debug)]
pub struct EnergyCell {
    energy_kev: f64,
    /// The energy clamped to the table's range (where x is taken).
    clamped_kev: f64,
    /// Index of the node above (≥ 1), and the weight of that node.
    upper: usize,
    weight: f64,
}

/// A grazing angle for a table's lookups ([`ReflectivityTable::angle_cell`]).
#[derive(Clone, Copy, Debug)]
pub struct AngleCell {
    theta: f64,
    /// sin θ, or NaN beyond the table's θ_max.
    sin_theta: f64,
}

/// Tabulated unpolarised reflectivity of one coating: R on rows of fixed
/// energy along x = E sin θ (`table_grid.rs` says why x).
#[derive(Clone, Debug)]
pub struct ReflectivityTable {
    pub coating: Coating,
    /// Energy nodes (keV), ascending; one node for a single line.
    pub energies: Vec<f64>,
    pub theta_max: f64,
    /// Each row's step in x = E sin θ (keV): its nodes are x = 0, step, … .
    pub x_steps: Vec<f64>,
    /// Where each row starts in `values`, and where the last ends.
    row_starts: Vec<usize>,
    /// R along each row, rows one after the other.
    values: Vec<f32>,
}

/// A table's grid and values as the disk cache stores them.
pub struct TableParts {
    pub energies: Vec<f64>,
    pub x_steps: Vec<f64>,
    pub theta_max: f64,
    pub row_lengths: Vec<usize>,
    pub values: Vec<f32>,
}

impl ReflectivityTable {
    /// Builds the table for energies in [e_min, e_max] (keV) and grazing angles up
    /// to `theta_max` (rad).
    pub fn new(
        coating: &Coating,
        e_min: f64,
        e_max: f64,
        theta_max: f64,
    ) -> Result<Self, EnergyOutOfRange> {
        // Check the range once (direct evaluation errors outside the tables).
        coating.reflectivity(e_min, 0.0)?;
        coating.reflectivity(e_max, 0.0)?;
        let grid = build_grid(coating, e_min, e_max, theta_max)?;
        let parts = TableParts {
            row_lengths: grid.rows.iter().map(|r| r.values.len()).collect(),
            x_steps: grid.rows.iter().map(|r| r.x_step).collect(),
            values: grid.rows.into_iter().flat_map(|r| r.values).collect(),
            energies: grid.energies,
            theta_max,
        };
        Ok(Self::from_parts(coating, parts).expect("a grid covers its energies"))
    }

    /// The table's grid and values, for the disk cache.
    pub(super) fn parts(&self) -> TableParts {
        TableParts {
            energies: self.energies.clone(),
            x_steps: self.x_steps.clone(),
            theta_max: self.theta_max,
            row_lengths: self.row_starts.windows(2).map(|w| w[1] - w[0]).collect(),
            values: self.values.clone(),
        }
    }

    /// A table from the cache's parts, if they make a table: one row per
    /// energy, each long enough for every x its cells look up.
    pub(super) fn from_parts(coating: &Coating, p: TableParts) -> Option<ReflectivityTable> {
        let mut row_starts = vec![0];
        for &n in &p.row_lengths {
            row_starts.push(row_starts.last()? + n);
        }
        let sin_max = p.theta_max.sin();
        let covers = |i: usize, n: usize| {
            let e_next = p.energies.get(i + 1).unwrap_or(&p.energies[i]);
            n >= 2 && p.x_steps[i] > 0.0 && ((n - 1) as f64) * p.x_steps[i] >= e_next * sin_max
        };
        let grid_ok = !p.energies.is_empty()
            && p.energies.windows(2).all(|w| w[0] < w[1])
            && p.theta_max > 0.0
            && p.row_lengths.len() == p.energies.len()
            && p.x_steps.len() == p.energies.len()
            && p.row_lengths.iter().enumerate().all(|(i, &n)| covers(i, n))
            && row_starts.last() == Some(&p.values.len());
        grid_ok.then(|| ReflectivityTable {
            coating: coating.clone(),
            energies: p.energies,
            x_steps: p.x_steps,
            theta_max: p.theta_max,
            row_starts,
            values: p.values,
        })
    }

    /// Unpolarised R at `energy_kev` (inside the table's range; clamped to it) and
    /// grazing angle `theta` (rad, ≥ 0).
    #[inline]
    pub fn reflectivity(&self, energy_kev: f64, theta: f64) -> f64 {
        self.at(&self.energy_cell(energy_kev), &self.angle_cell(theta))
    }

    /// Where `energy_kev` falls between the energy nodes (for [`Self::at`]: a
    /// sweep over many energies looks each one up once).
    #[inline]
    pub fn energy_cell(&self, energy_kev: f64) -> EnergyCell {
        let e = &self.energies;
        let clamped_kev = energy_kev.clamp(e[0], e[e.len() - 1]);
        if e.len() == 1 {
            return EnergyCell {
                energy_kev,
                clamped_kev,
                upper: 0,
                weight: 0.0,
            };
        }
        let i = e
            .partition_point(|&x| x <= energy_kev)
            .clamp(1, e.len() - 1);
        let weight = ((energy_kev - e[i - 1]) / (e[i] - e[i - 1])).clamp(0.0, 1.0);
        EnergyCell {
            energy_kev,
            clamped_kev,
            upper: i,
            weight,
        }
    }

    /// A grazing angle `theta` (rad) ready for [`Self::at`] (its sine, taken
    /// once for one reflection evaluated at many energies).
    #[inline]
    pub fn angle_cell(&self, theta: f64) -> AngleCell {
        AngleCell {
            theta,
            sin_theta: if theta > self.theta_max {
                f64::NAN
            } else {
                theta.sin()
            },
        }
    }

    /// R at an energy and an angle from [`Self::energy_cell`] and
    /// [`Self::angle_cell`]: cubic (Catmull–Rom) in x = E sin θ along the two
    /// rows around the energy, linear between them.
    #[inline]
    pub fn at(&self, energy: &EnergyCell, angle: &AngleCell) -> f64 {
        if angle.sin_theta.is_nan() {
            // Beyond the table (rare in X-ray optics): evaluated directly.
            return self
                .coating
                .reflectivity(energy.energy_kev, angle.theta)
                .unwrap_or(0.0);
        }
        let x = energy.clamped_kev * angle.sin_theta;
        let row = |i: usize| {
            let r = &self.values[self.row_starts[i]..self.row_starts[i + 1]];
            Row::at(r, self.x_steps[i], x)
        };
        if self.energies.len() == 1 {
            return row(0);
        }
        let (i, we) = (energy.upper, energy.weight);
        row(i - 1) * (1.0 - we) + row(i) * we
    }

    /// Number of tabulated values.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }
}
