//! Precomputed reflectivity R(E, θ) of one coating for the photon loop: a grid over
//! the scene's energy range and grazing angles 0 … θ_max; cubic (Catmull–Rom)
//! interpolation in angle, linear in energy.
//!
//! The grid is chosen from the physics so that the interpolation error stays below
//! 1e-3 (tested in tests/it/xray.rs, which measures it against direct evaluation):
//! * angle step: a fraction of the shortest Kiessig fringe period λ_min / (2 D) of
//!   the whole stack (thickness D), and of the critical angle;
//! * energy nodes: a uniform step that resolves the fringes in energy at θ_max,
//!   then cells are halved where R(E) bends more than the linear interpolation
//!   allows (absorption edges such as Pt M at 2.1–2.2 keV).
//!
//! Grazing angles above θ_max (rare in X-ray optics) are evaluated directly.

use super::coating::Coating;
use super::optical::EnergyOutOfRange;
use super::parratt::reflectance;
use crate::constants::HC_KEV_NM;
use rayon::prelude::*;

/// An energy located in a table's energy nodes ([`ReflectivityTable::energy_cell`]).
#[derive(Clone, Copy, Debug)]
pub struct EnergyCell {
    energy_kev: f64,
    /// Index of the node above (≥ 1), and the weight of that node.
    upper: usize,
    weight: f64,
}

/// A grazing angle located in a table's angle nodes
/// ([`ReflectivityTable::angle_cell`]).
#[derive(Clone, Copy, Debug)]
pub struct AngleCell {
    theta: f64,
    /// Index of the node below, or `usize::MAX` beyond the table.
    node: usize,
    /// Position between that node and the next (0–1).
    t: f64,
}

/// Tabulated unpolarised reflectivity of one coating.
#[derive(Clone, Debug)]
pub struct ReflectivityTable {
    pub coating: Coating,
    /// Energy nodes (keV), ascending; one node for a single line.
    pub energies: Vec<f64>,
    /// Angle step (rad); nodes are 0, Δθ, …, θ_max.
    pub theta_step: f64,
    pub theta_max: f64,
    n_theta: usize,
    /// R at [energy index][angle index], row-major.
    values: Vec<f32>,
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
        let stack = &coating.stack;
        let depth: f64 = stack.layers.iter().map(|l| l.thickness_nm).sum();
        let (n_theta, theta_step) = angle_grid(coating, depth, e_min, e_max, theta_max)?;
        let mut energies = energy_grid(depth, e_min, e_max, theta_max);
        let sigma = stack.substrate_roughness_nm;
        let row = |e: f64| -> Vec<f32> {
            let (layers, sub) = coating.layers_at(e).expect("range checked");
            (0..n_theta)
                .map(|j| {
                    reflectance(e, j as f64 * theta_step, &layers, sub, sigma).unpolarised() as f32
                })
                .collect()
        };
        let mut rows: Vec<Vec<f32>> = energies.par_iter().map(|&e| row(e)).collect();
        refine_in_energy(&mut energies, &mut rows, row);
        let values: Vec<f32> = rows.concat();
        Ok(ReflectivityTable {
            coating: coating.clone(),
            energies,
            theta_step,
            theta_max,
            n_theta,
            values,
        })
    }

    /// The table's grid and values, for the disk cache.
    pub(super) fn parts(&self) -> (&[f64], f64, f64, usize, &[f32]) {
        let t = self;
        (&t.energies, t.theta_step, t.theta_max, t.n_theta, &t.values)
    }

    /// A table from the cache's parts, if they make a table.
    pub(super) fn from_parts(
        coating: &Coating,
        energies: Vec<f64>,
        theta_step: f64,
        theta_max: f64,
        n_theta: usize,
        values: Vec<f32>,
    ) -> Option<ReflectivityTable> {
        let grid_ok = !energies.is_empty()
            && n_theta >= 2
            && theta_step > 0.0
            && theta_max > 0.0
            && values.len() == energies.len() * n_theta;
        grid_ok.then(|| ReflectivityTable {
            coating: coating.clone(),
            energies,
            theta_step,
            theta_max,
            n_theta,
            values,
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
        if e.len() == 1 {
            return EnergyCell {
                energy_kev,
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
            upper: i,
            weight,
        }
    }

    /// Where `theta` (rad) falls between the angle nodes, with its interpolation
    /// weights (for [`Self::at`]: one reflection evaluated at many energies
    /// computes them once).
    #[inline]
    pub fn angle_cell(&self, theta: f64) -> AngleCell {
        if theta > self.theta_max {
            return AngleCell {
                theta,
                node: usize::MAX,
                t: 0.0,
            };
        }
        let ft = theta / self.theta_step;
        let node = (ft as usize).min(self.n_theta - 2);
        AngleCell {
            theta,
            node,
            t: ft - node as f64,
        }
    }

    /// R at an energy and an angle located by [`Self::energy_cell`] and
    /// [`Self::angle_cell`]: cubic (Catmull–Rom) in angle, linear in energy.
    #[inline]
    pub fn at(&self, energy: &EnergyCell, angle: &AngleCell) -> f64 {
        if angle.node == usize::MAX {
            // Beyond the table (rare in X-ray optics): evaluated directly.
            return self
                .coating
                .reflectivity(energy.energy_kev, angle.theta)
                .unwrap_or(0.0);
        }
        let (j, t) = (angle.node, angle.t);
        // Catmull–Rom through nodes j−1 … j+2 (mirrored at θ = 0: R is even in θ
        // only approximately, so clamp instead; the end cells fall back to linear).
        let (t2, t3) = (t * t, t * t * t);
        let row = |i: usize| {
            let r = &self.values[i * self.n_theta..(i + 1) * self.n_theta];
            let (p1, p2) = (r[j] as f64, r[j + 1] as f64);
            if j == 0 || j + 2 >= r.len() {
                return p1 + (p2 - p1) * t;
            }
            let (p0, p3) = (r[j - 1] as f64, r[j + 2] as f64);
            0.5 * (2.0 * p1
                + (p2 - p0) * t
                + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2
                + (3.0 * p1 - p0 - 3.0 * p2 + p3) * t3)
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

/// The angle grid: `n_theta` angles from 0 to θ_max in equal steps, fine enough
/// for the critical angle of the densest material (√(2δ), 60 steps, at whichever
/// end of the energy range it is smaller: beyond it R falls as θ⁻⁴, and a grid
/// made for 1 keV errs by 1 % of R per reflection on gold at 8 keV) and for the
/// multilayer's angular fringes (λ_min / 2D, 40 steps).
fn angle_grid(
    coating: &Coating,
    depth: f64,
    e_min: f64,
    e_max: f64,
    theta_max: f64,
) -> Result<(usize, f64), EnergyOutOfRange> {
    let stack = &coating.stack;
    let lambda_min = HC_KEV_NM / e_max;
    let mut theta_c = f64::INFINITY;
    for e in [e_min, e_max] {
        let mut delta_max: f64 = 0.0;
        for m in stack
            .layers
            .iter()
            .map(|l| l.material.as_ref())
            .chain([&stack.substrate])
        {
            delta_max = delta_max.max(m.delta_beta(e)?.0);
        }
        theta_c = theta_c.min((2.0 * delta_max).sqrt());
    }
    let mut theta_step = theta_c / 60.0;
    if depth > 0.0 {
        theta_step = theta_step.min(lambda_min / (2.0 * depth) / 40.0);
    }
    let n_theta = (theta_max / theta_step).ceil() as usize + 1;
    Ok((n_theta, theta_max / (n_theta - 1) as f64))
}

/// The initial energy grid: equal steps of at most 1/16 of the multilayer's
/// fringe period at θ_max and 1/4 of the range.
fn energy_grid(depth: f64, e_min: f64, e_max: f64, theta_max: f64) -> Vec<f64> {
    if e_max <= e_min {
        return vec![e_min];
    }
    // Fringes in energy at θ_max have period ≈ hc / (2 D sin θ_max).
    let fringe = if depth > 0.0 {
        HC_KEV_NM / (2.0 * depth * theta_max.sin())
    } else {
        f64::INFINITY
    };
    let step = (fringe / 16.0).min((e_max - e_min) / 4.0);
    let n = ((e_max - e_min) / step).ceil() as usize;
    (0..=n)
        .map(|i| e_min + (e_max - e_min) * i as f64 / n as f64)
        .collect()
}

/// Inserts energies (and their rows, from `row`) where linear interpolation
/// between the nodes would be too coarse.
fn refine_in_energy(
    energies: &mut Vec<f64>,
    rows: &mut Vec<Vec<f32>>,
    row: impl Fn(f64) -> Vec<f32> + Sync,
) {
    // Adaptive refinement in energy: near absorption edges (e.g. the Pt M
    // edges at 2.1–2.2 keV) R(E) bends within a few eV. Linear interpolation
    // over a cell of width h errs by ≈ h²|R''|/8 at its middle; R'' is
    // estimated from the neighbouring nodes, and cells above REFINE_TOL are
    // halved (no extra evaluations where R(E) is smooth).
    const REFINE_TOL: f64 = 1e-4;
    for _ in 0..14 {
        let n = energies.len();
        if n < 3 {
            break;
        }
        // Largest |R''| over angles at each interior node.
        let curvature: Vec<f64> = (1..n - 1)
            .into_par_iter()
            .map(|i| {
                let (h0, h1) = (energies[i] - energies[i - 1], energies[i + 1] - energies[i]);
                rows[i]
                    .iter()
                    .zip(rows[i - 1].iter().zip(&rows[i + 1]))
                    .map(|(&m, (&l, &r))| {
                        let d = ((r - m) as f64 / h1 - (m - l) as f64 / h0) * 2.0 / (h0 + h1);
                        d.abs()
                    })
                    .fold(0.0, f64::max)
            })
            .collect();
        let split: Vec<usize> = (0..n - 1)
            .filter(|&i| {
                let h = energies[i + 1] - energies[i];
                // 0.1 eV: finer than the Henke tables themselves.
                let c = curvature
                    .get(i.wrapping_sub(1))
                    .copied()
                    .unwrap_or(0.0)
                    .max(curvature.get(i).copied().unwrap_or(0.0));
                h > 1e-4 && h * h * c / 8.0 > REFINE_TOL
            })
            .collect();
        if split.is_empty() {
            break;
        }
        let new_rows: Vec<(f64, Vec<f32>)> = split
            .par_iter()
            .map(|&i| {
                let e = 0.5 * (energies[i] + energies[i + 1]);
                (e, row(e))
            })
            .collect();
        for (k, (&i, (e, r))) in split.iter().zip(new_rows).enumerate() {
            energies.insert(i + 1 + k, e);
            rows.insert(i + 1 + k, r);
        }
    }
}
