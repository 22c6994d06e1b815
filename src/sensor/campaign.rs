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

/// The sums of one sensor, stored [bin][pair] (bins energy-major then ring)
/// so that a photon's pairs, all in its one bin, are side by side in memory:
/// [pair][bin] would scatter its thousands of additions a bin row apart.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CampaignTally {
    /// [bin][pair] (a name unlike the former [pair][bin] `sums`: a
    /// checkpoint of that layout is refused, not misread).
    pub by_bin: Vec<WeightSum>,
    /// Pairs per bin.
    pub pairs: usize,
}

impl CampaignTally {
    /// Zeroed sums for `pairs` pairs of `bins` bins.
    pub fn new(pairs: usize, bins: usize) -> CampaignTally {
        CampaignTally {
            by_bin: vec![WeightSum::ZERO; pairs * bins],
            pairs,
        }
    }

    /// A photon in `bin` with axion weight `weight`: pair k gets
    /// `weight × factors[k]`.
    #[inline]
    pub fn record(&mut self, bin: usize, weight: f64, factors: &[f64]) {
        let row = &mut self.by_bin[bin * self.pairs..(bin + 1) * self.pairs];
        for (sum, &f) in row.iter_mut().zip(factors) {
            sum.add(WeightSum::of(weight * f));
        }
    }

    /// Adds another part of the same run.
    pub fn add(&mut self, other: &CampaignTally) {
        exact::add_all(&mut self.by_bin, &other.by_bin);
    }

    /// The number of sums.
    pub fn len(&self) -> usize {
        self.by_bin.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.by_bin.is_empty()
    }

    /// The sums as numbers, [pair][bin].
    pub fn values(&self) -> Vec<f64> {
        let bins = self.by_bin.len().checked_div(self.pairs).unwrap_or(0);
        let mut out = vec![0.0; self.by_bin.len()];
        for (b, row) in self.by_bin.chunks_exact(self.pairs.max(1)).enumerate() {
            for (k, sum) in row.iter().enumerate() {
                out[k * bins + b] = sum.value();
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A photon's pairs go to its bin; the values come out [pair][bin].
    #[test]
    fn the_values_are_by_pair_then_bin() {
        let mut t = CampaignTally::new(3, 2);
        t.record(1, 1.0, &[1.0, 2.0, 3.0]);
        t.record(0, 0.5, &[1.0, 0.0, 4.0]);
        assert_eq!(t.values(), vec![0.5, 1.0, 0.0, 2.0, 2.0, 3.0]);
    }
}
