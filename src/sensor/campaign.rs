//! A sensor's tallies for a data-taking campaign ([`crate::magnet::campaign`]):
//! for each (setting, mass) pair, the X-rays in bins of energy and of radius
//! about the image centre, each recorded photon adding its axion weight × its
//! own P at that pair / P_max. Sums are exact ([`super::exact`]), so shards
//! and resumed runs add up to the bits of one run.
//!
//! Data flow: `trace` computes each recorded photon's factors with
//! [`crate::magnet::campaign::Campaign::factors`] and adds them here per
//! chunk; `trace::Tally` adds the chunks; `output` writes the tallies.

use super::exact::{self, WeightSum};

/// The sums of one sensor: [pair][bin], bins energy-major then ring.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CampaignTally {
    pub sums: Vec<WeightSum>,
    /// Bins per pair.
    pub bins: usize,
}

impl CampaignTally {
    /// Zeroed sums for `pairs` pairs of `bins` bins.
    pub fn new(pairs: usize, bins: usize) -> CampaignTally {
        CampaignTally {
            sums: vec![WeightSum::ZERO; pairs * bins],
            bins,
        }
    }

    /// A photon in `bin` with axion weight `weight`: pair k gets
    /// `weight × factors[k]`.
    #[inline]
    pub fn record(&mut self, bin: usize, weight: f64, factors: &[f64]) {
        for (k, &f) in factors.iter().enumerate() {
            self.sums[k * self.bins + bin].add(WeightSum::of(weight * f));
        }
    }

    /// Adds another part of the same run.
    pub fn add(&mut self, other: &CampaignTally) {
        exact::add_all(&mut self.sums, &other.sums);
    }

    /// The sums as numbers, [pair][bin].
    pub fn values(&self) -> Vec<f64> {
        exact::values(&self.sums)
    }
}
