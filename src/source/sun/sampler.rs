//! Drawing emission points and energies from an emission table: a cell (i, j) with
//! probability proportional to its axion rate, then a radius in the cell's shell
//! uniformly in volume (density ∝ r²) and an energy uniformly in the cell's energy
//! interval (clipped to the source's energy range). The emissivity is thereby
//! piecewise constant in shells; [`EmissionSampler::enclosed_projected`] is the
//! exact projection of that model onto the solar disk.

use super::emission::EmissionTable;
use crate::random::PhotonRng;

#[derive(Clone, Debug)]
pub struct EmissionSampler {
    /// Cumulative cell probabilities, the last exactly 1.
    cumulative: Vec<f64>,
    /// guide[g]: how many cumulative values are ≤ g / GUIDE_CELLS, so that a draw
    /// searches only between two neighbouring entries (Chen's guide table: the
    /// same cell as a search of the whole list, without its cache misses).
    guide: Vec<u32>,
    radius_edges: Vec<f64>,
    /// Energy interval of each energy cell, clipped to the range.
    energy_cells: Vec<(f64, f64)>,
    /// Axions per second of each radial shell (energies in range).
    shell_rates: Vec<f64>,
    /// Axions per second emitted in the energy range.
    pub luminosity: f64,
}

/// Cells of the guide table (a power of two, so that g / GUIDE_CELLS is exact).
const GUIDE_CELLS: usize = 4096;

impl EmissionSampler {
    /// The sampler of `table` restricted to energies in [e_min, e_max] keV; `None`
    /// if nothing is emitted there.
    pub fn new(table: &EmissionTable, e_min: f64, e_max: f64) -> Option<EmissionSampler> {
        let cells = table.cell_rates(e_min, e_max);
        let luminosity: f64 = cells.iter().sum();
        if luminosity <= 0.0 || !luminosity.is_finite() {
            return None;
        }
        let mut acc = 0.0;
        let mut cumulative: Vec<f64> = cells
            .iter()
            .map(|c| {
                acc += c;
                acc / luminosity
            })
            .collect();
        // Cells with no rate at the end must never be drawn.
        let last = cumulative
            .iter()
            .rposition(|&c| c < 1.0)
            .map_or(0, |k| k + 1);
        for c in &mut cumulative[last.min(cells.len() - 1)..] {
            *c = 1.0;
        }
        let n_e = table.energies.len();
        let ee = table.energy_edges();
        let guide = (0..=GUIDE_CELLS)
            .map(|g| {
                let u = g as f64 / GUIDE_CELLS as f64;
                cumulative.partition_point(|&c| c <= u) as u32
            })
            .collect();
        Some(EmissionSampler {
            cumulative,
            guide,
            radius_edges: table.radius_edges(),
            energy_cells: (0..n_e)
                .map(|j| (ee[j].max(e_min), ee[j + 1].min(e_max)))
                .collect(),
            shell_rates: cells.chunks(n_e).map(|c| c.iter().sum()).collect(),
            luminosity,
        })
    }

    /// The cell drawn by u in [0, 1): the first whose cumulative probability
    /// exceeds u.
    #[inline]
    fn cell(&self, u: f64) -> usize {
        // u · 4096 is exact, so g / 4096 ≤ u < (g + 1) / 4096: the number of
        // cumulative values ≤ u lies between guide[g] and guide[g + 1].
        let g = (u * GUIDE_CELLS as f64) as usize;
        let (lo, hi) = (self.guide[g] as usize, self.guide[g + 1] as usize);
        (lo + self.cumulative[lo..hi].partition_point(|&c| c <= u)).min(self.cumulative.len() - 1)
    }

    /// (radius as a fraction of R_sun, energy in keV) of one emitted axion.
    #[inline]
    pub fn sample(&self, rng: &mut PhotonRng) -> (f64, f64) {
        self.sample_from(rng.uniform(), rng).0
    }

    /// As [`EmissionSampler::sample`], with `u` (uniform in [0, 1)) choosing the
    /// cell; also returns the cell's index (radius-major).
    #[inline]
    pub fn sample_from(&self, u: f64, rng: &mut PhotonRng) -> ((f64, f64), usize) {
        let k = self.cell(u);
        let n_e = self.energy_cells.len();
        let (i, j) = (k / n_e, k % n_e);
        let (a, b) = (self.radius_edges[i], self.radius_edges[i + 1]);
        let (a3, b3) = (a * a * a, b * b * b);
        let r = (a3 + rng.uniform() * (b3 - a3)).cbrt();
        let (lo, hi) = self.energy_cells[j];
        ((r, lo + rng.uniform() * (hi - lo)), k)
    }

    /// Fraction of the emission seen within projected radius `rho` (fraction of
    /// R_sun) of the disk centre: for each shell [a, b] of uniform emissivity, the
    /// part of its volume inside the cylinder of radius ρ along the line of sight,
    /// (b³ − (b² − ρ²)₊^{3/2}) − (a³ − (a² − ρ²)₊^{3/2}), over b³ − a³.
    pub fn enclosed_projected(&self, rho: f64) -> f64 {
        let inside = |r: f64| {
            let outside = (r * r - rho * rho).max(0.0);
            r * r * r - outside * outside.sqrt()
        };
        let sum: f64 = self
            .shell_rates
            .iter()
            .enumerate()
            .map(|(i, &l)| {
                let (a, b) = (self.radius_edges[i], self.radius_edges[i + 1]);
                l * (inside(b) - inside(a)) / (b * b * b - a * a * a)
            })
            .sum();
        sum / self.luminosity
    }

    /// Fraction of the emission from radii below `r` (fraction of R_sun).
    pub fn enclosed_3d(&self, r: f64) -> f64 {
        let sum: f64 = self
            .shell_rates
            .iter()
            .enumerate()
            .map(|(i, &l)| {
                let (a, b) = (self.radius_edges[i], self.radius_edges[i + 1]);
                let c = r.clamp(a, b);
                l * (c * c * c - a * a * a) / (b * b * b - a * a * a)
            })
            .sum();
        sum / self.luminosity
    }
}

#[cfg(test)]
mod tests {
    use super::{EmissionSampler, GUIDE_CELLS};
    use crate::source::sun::emission::EmissionTable;

    /// The guide table finds the cell a search of the whole cumulative list
    /// finds, for a table with strongly uneven rates (many cells inside one guide
    /// cell, and empty cells), at random u, at every guide boundary and at every
    /// cumulative value itself and its neighbours.
    #[test]
    fn guide_table_finds_the_cell_of_a_full_search() {
        let radii: Vec<f64> = (1..=60).map(|i| i as f64 / 60.0).collect();
        let energies: Vec<f64> = (0..50).map(|j| 1.0 + 0.15 * j as f64).collect();
        let rates = (0..radii.len() * energies.len())
            .map(|k| {
                if k % 7 == 3 {
                    0.0
                } else {
                    ((k * 7919) % 1000) as f64 * (-(k as f64) / 300.0).exp()
                }
            })
            .collect();
        let table = EmissionTable::new(radii, energies, rates).unwrap();
        let s = EmissionSampler::new(&table, 1.0, 8.0).unwrap();
        let full = |u: f64| {
            s.cumulative
                .partition_point(|&c| c <= u)
                .min(s.cumulative.len() - 1)
        };
        let mut us: Vec<f64> = (0..GUIDE_CELLS)
            .map(|g| g as f64 / GUIDE_CELLS as f64)
            .collect();
        for &c in &s.cumulative {
            us.extend(
                [c, c.next_down(), c.next_up()]
                    .into_iter()
                    .filter(|u| (0.0..1.0).contains(u)),
            );
        }
        let mut rng = crate::random::PhotonRng::new(9, 0);
        us.extend((0..100_000).map(|_| rng.uniform()));
        us.push(1.0f64.next_down());
        for u in us {
            assert_eq!(s.cell(u), full(u), "u = {u}");
        }
    }
}
