//! What a Sun draws its axions from: one emission table, or — when the emission
//! has two couplings (Primakoff ∝ g_aγ², ABC ∝ g_ae²) — each coupling's table at
//! its reference coupling, chosen with equal probability and weighted by its
//! share of the flux.
//!
//! Why not the sum of the two: drawn from the sum, where a photon goes would
//! depend on the ratio of the couplings, and the image for other couplings would
//! need another trace. Drawn from fixed tables, the photons' paths are the same
//! for every choice of couplings and only their weights change: the image of each
//! coupling's emission is recorded beside the total ([`SunEmission::process_names`],
//! the trace's images per process), and the image for couplings (g_aγ, g_ae) is
//! (g_aγ/g_aγ₀)² image_primakoff + (g_ae/g_ae₀)² image_abc, equal to a trace with
//! those couplings to rounding. Each coupling's image has the statistics of half
//! the photons whatever the couplings; the price is that the total image, when
//! one coupling dominates the flux, has the statistics of about half the run.
//!
//! Data flow: [`super::SunDesc::build`] makes it from the emission's
//! [`super::builtin::CouplingPart`]s (or the one table of a CSV);
//! [`super::SunSource::emit`] draws from it.

use super::builtin::CouplingPart;
use super::emission::EmissionTable;
use super::sampler::EmissionSampler;
use super::shares::ProcessShares;
use crate::random::PhotonRng;

/// One table photons are drawn from.
#[derive(Clone, Debug)]
struct Draw {
    name: String,
    sampler: EmissionSampler,
    /// Axions per second of this part at the scene's couplings.
    luminosity: f64,
    /// The weight a photon drawn from it carries: its share of the luminosity
    /// over the probability of drawing it.
    weight: f64,
    /// ABC's four processes' shares in each cell of its table, if it is ABC.
    shares: Option<ProcessShares>,
}

/// The process images one photon adds to, with the share of its weight each
/// takes: its coupling's image (share 1) and ABC's four processes.
#[derive(Clone, Copy, Debug, Default)]
pub struct ProcessWeights {
    pub len: usize,
    /// (image index in [`SunEmission::process_names`], share of the weight).
    pub entries: [(u8, f64); 5],
}

impl ProcessWeights {
    fn push(&mut self, image: usize, share: f64) {
        self.entries[self.len] = (image as u8, share);
        self.len += 1;
    }

    /// The entries in use.
    pub fn iter(&self) -> impl Iterator<Item = &(u8, f64)> {
        self.entries[..self.len].iter()
    }
}

/// The emission a Sun draws from, restricted to its energy range.
#[derive(Clone, Debug)]
pub struct SunEmission {
    draws: Vec<Draw>,
    /// Axions per second emitted in the energy range, all parts.
    pub luminosity: f64,
}

impl SunEmission {
    /// One table drawn from directly (an emission table file, or one
    /// coupling, with ABC's `shares` if it is ABC); `None` if it emits nothing
    /// in [e_min, e_max].
    pub fn single(
        table: &EmissionTable,
        (e_min, e_max): (f64, f64),
        shares: Option<ProcessShares>,
    ) -> Option<SunEmission> {
        let sampler = EmissionSampler::new(table, e_min, e_max)?;
        let luminosity = sampler.luminosity;
        Some(SunEmission {
            draws: vec![Draw {
                name: String::new(),
                sampler,
                luminosity,
                weight: 1.0,
                shares,
            }],
            luminosity,
        })
    }

    /// Each coupling's table drawn with equal probability (those emitting nothing
    /// in the range left out); `None` if none emits there.
    pub fn by_coupling(parts: &[CouplingPart], e_min: f64, e_max: f64) -> Option<SunEmission> {
        let mut draws: Vec<Draw> = parts
            .iter()
            .filter_map(|p| {
                let sampler = EmissionSampler::new(&p.reference, e_min, e_max)?;
                let luminosity = sampler.luminosity * p.factor;
                Some(Draw {
                    name: p.name.clone(),
                    sampler,
                    luminosity,
                    weight: 0.0,
                    shares: p.shares.clone(),
                })
            })
            .filter(|d| d.luminosity > 0.0 && d.luminosity.is_finite())
            .collect();
        let luminosity: f64 = draws.iter().map(|d| d.luminosity).sum();
        if draws.is_empty() || !luminosity.is_finite() {
            return None;
        }
        let n = draws.len() as f64;
        for d in &mut draws {
            d.weight = d.luminosity / luminosity * n;
        }
        Some(SunEmission { draws, luminosity })
    }

    /// The processes whose images a trace records beside the total: the
    /// couplings drawn separately (when there are two), then ABC's four
    /// processes (when ABC's shares are known); empty for a table alone.
    pub fn process_names(&self) -> Vec<String> {
        let mut names: Vec<String> = match self.draws.len() {
            1 => Vec::new(),
            _ => self.draws.iter().map(|d| d.name.clone()).collect(),
        };
        if self.draws.iter().any(|d| d.shares.is_some()) {
            names.extend(super::abc::PROCESSES.iter().map(|p| p.to_string()));
        }
        names
    }

    /// The images a photon drawn from part `process`, cell `cell`, adds to.
    #[inline]
    pub fn process_weights(&self, process: u8, cell: u32) -> ProcessWeights {
        let mut w = ProcessWeights::default();
        let n = self.draws.len();
        let Some(d) = self.draws.get(process as usize) else {
            return w;
        };
        if n > 1 {
            w.push(process as usize, 1.0);
        }
        if let Some(share) = d.shares.as_ref().and_then(|s| s.get(cell as usize)) {
            let first = if n > 1 { n } else { 0 };
            for (k, &s) in share.iter().enumerate() {
                w.push(first + k, s);
            }
        }
        w
    }

    /// Each part's axions per second in the energy range, in the order of
    /// [`SunEmission::process_names`].
    pub fn process_luminosities(&self) -> Vec<f64> {
        self.draws.iter().map(|d| d.luminosity).collect()
    }

    /// (radius as a fraction of R_sun, energy in keV), the weight the photon
    /// carries, and the index of the part and the cell it was drawn from. The
    /// first uniform number both picks the part and, rescaled (exactly, for
    /// two parts), the cell: a photon takes as many random numbers as with one
    /// table.
    #[inline]
    pub fn sample(&self, rng: &mut PhotonRng) -> ((f64, f64), f64, (u8, u32)) {
        let u = rng.uniform();
        let n = self.draws.len();
        let (k, u) = match n {
            1 => (0, u),
            _ => {
                let scaled = u * n as f64;
                let k = (scaled as usize).min(n - 1);
                (k, (scaled - k as f64).clamp(0.0, 1.0f64.next_down()))
            }
        };
        let d = &self.draws[k];
        let (point, cell) = d.sampler.sample_from(u, rng);
        (point, d.weight, (k as u8, cell as u32))
    }

    /// Fraction of the emission seen within projected radius `rho` (fraction of
    /// R_sun) of the disk centre (see [`EmissionSampler::enclosed_projected`]).
    pub fn enclosed_projected(&self, rho: f64) -> f64 {
        self.draws
            .iter()
            .map(|d| d.luminosity * d.sampler.enclosed_projected(rho))
            .sum::<f64>()
            / self.luminosity
    }
}
