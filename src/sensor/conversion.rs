//! Where the X-rays of a gas detector converted: the flux-weighted distribution
//! of conversion depths below the gas entrance, the depth-resolved spectrum of
//! the converted photons, and the flux that crossed the gas unconverted. Exact
//! sums, like the image, so shards and resumed runs add up to the same bits.
//!
//! Data flow: the photon loop attaches a [`ConversionRecord`] to each record of
//! a sensor with a gas; [`super::SensorImage`] adds it here; `output` writes the
//! histogram, the spectrum and the summary numbers ([`DepthSummary`]).

use super::exact::{add_all, values, WeightSum};
use crate::xray::gas::GasDesc;

/// What the photon loop knows of one converted photon.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ConversionRecord {
    /// The photon's weight on entering the gas (its record's weight is this
    /// times the conversion probability).
    pub entered: f64,
    /// Depth of the conversion point below the gas entrance (mm).
    pub depth_mm: f64,
}

/// Conversion depths and spectra of one sensor's photons (those converting over
/// its active area).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ConversionTally {
    /// Converted flux per depth bin of `step_mm` from the entrance.
    pub depth_flux: Vec<WeightSum>,
    pub step_mm: f64,
    pub drift_mm: f64,
    /// Σ weight · depth (mm), for the mean depth.
    pub depth_moment: WeightSum,
    /// Flux that entered the gas, and the part of it that converted.
    pub entered: WeightSum,
    pub converted: WeightSum,
    /// Converted flux per [depth slice][energy bin].
    pub spectrum: Vec<WeightSum>,
    pub energy_bins: (f64, f64, u32),
    pub depth_slices: u32,
    /// Converted flux outside the spectrum's energy range.
    pub spectrum_outside: WeightSum,
}

impl ConversionTally {
    /// An empty tally with the bins of `gas`.
    pub fn new(gas: &GasDesc) -> ConversionTally {
        let bins = (gas.drift_mm / gas.depth_step_mm).ceil().max(1.0) as usize;
        let (_, _, n) = gas.spectrum_energy_bins;
        ConversionTally {
            depth_flux: vec![WeightSum::ZERO; bins],
            step_mm: gas.depth_step_mm,
            drift_mm: gas.drift_mm,
            depth_moment: WeightSum::ZERO,
            entered: WeightSum::ZERO,
            converted: WeightSum::ZERO,
            spectrum: vec![WeightSum::ZERO; n as usize * gas.spectrum_depth_slices as usize],
            energy_bins: gas.spectrum_energy_bins,
            depth_slices: gas.spectrum_depth_slices,
            spectrum_outside: WeightSum::ZERO,
        }
    }

    /// One converted photon of record weight `weight` and energy `energy_kev`.
    #[inline]
    pub fn record(&mut self, weight: f64, energy_kev: f64, c: &ConversionRecord) {
        let w = WeightSum::of(weight);
        self.entered.add(WeightSum::of(c.entered));
        self.converted.add(w);
        self.depth_moment.add(WeightSum::of(weight * c.depth_mm));
        let last = self.depth_flux.len() - 1;
        let bin = ((c.depth_mm / self.step_mm).max(0.0) as usize).min(last);
        self.depth_flux[bin].add(w);
        let (lo, hi, n) = self.energy_bins;
        if energy_kev >= lo && energy_kev < hi {
            let e = (((energy_kev - lo) / (hi - lo) * n as f64) as usize).min(n as usize - 1);
            let slices = self.depth_slices as usize;
            let s =
                ((c.depth_mm / self.drift_mm * slices as f64).max(0.0) as usize).min(slices - 1);
            self.spectrum[s * n as usize + e].add(w);
        } else {
            self.spectrum_outside.add(w);
        }
    }

    /// Adds another tally of the same sensor (exact, in any order).
    pub fn add(&mut self, other: &ConversionTally) {
        add_all(&mut self.depth_flux, &other.depth_flux);
        add_all(&mut self.spectrum, &other.spectrum);
        for (a, b) in [
            (&mut self.depth_moment, other.depth_moment),
            (&mut self.entered, other.entered),
            (&mut self.converted, other.converted),
            (&mut self.spectrum_outside, other.spectrum_outside),
        ] {
            a.add(b);
        }
    }

    /// The converted flux per depth bin.
    pub fn depth_histogram(&self) -> Vec<f64> {
        values(&self.depth_flux)
    }

    /// The depth-resolved spectrum, [slice][energy bin].
    pub fn spectrum(&self) -> Vec<f64> {
        values(&self.spectrum)
    }

    /// The edges (mm below the gas entrance) of [`Self::depth_histogram`]'s
    /// bins: every `step_mm`, the last bin ending at the drift length. The one
    /// definition the CSV, the plot and Python share.
    pub fn depth_edges_mm(&self) -> Vec<f64> {
        (0..=self.depth_flux.len())
            .map(|i| (i as f64 * self.step_mm).min(self.drift_mm))
            .collect()
    }

    /// The edges of the spectrum's depth slices (mm): the drift cut evenly.
    pub fn spectrum_depth_edges_mm(&self) -> Vec<f64> {
        let slice = self.drift_mm / self.depth_slices as f64;
        (0..=self.depth_slices).map(|i| i as f64 * slice).collect()
    }

    /// The edges of the spectrum's energy bins (keV).
    pub fn spectrum_energy_edges_kev(&self) -> Vec<f64> {
        let (lo, hi, n) = self.energy_bins;
        let de = (hi - lo) / n as f64;
        (0..=n).map(|i| lo + i as f64 * de).collect()
    }

    /// Mean, quantiles and fractions of the conversion depth.
    pub fn summary(&self) -> DepthSummary {
        let hist = self.depth_histogram();
        let converted = self.converted.value();
        let entered = self.entered.value();
        let quantile = |q: f64| quantile(&hist, self.step_mm, self.drift_mm, q);
        DepthSummary {
            entered_flux: entered,
            converted_flux: converted,
            converted_fraction: if entered > 0.0 {
                converted / entered
            } else {
                f64::NAN
            },
            mean_depth_mm: if converted > 0.0 {
                self.depth_moment.value() / converted
            } else {
                f64::NAN
            },
            quantiles_mm: DEPTH_QUANTILES.map(|q| (q, quantile(q))),
        }
    }
}

/// The depth quantiles the summary reports.
pub const DEPTH_QUANTILES: [f64; 5] = [0.1, 0.25, 0.5, 0.75, 0.9];

/// The numbers of a conversion-depth distribution.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct DepthSummary {
    /// Flux that entered the gas over the active area, and the part that
    /// converted there (the rest crossed the whole gas).
    pub entered_flux: f64,
    pub converted_flux: f64,
    pub converted_fraction: f64,
    pub mean_depth_mm: f64,
    /// (q, depth below the entrance in mm) for each of [`DEPTH_QUANTILES`];
    /// linear within a histogram bin, so good to a fraction of the bin width.
    pub quantiles_mm: [(f64, f64); 5],
}

impl DepthSummary {
    /// The median depth (mm).
    pub fn median_mm(&self) -> f64 {
        self.quantiles_mm[2].1
    }
}

/// The depth below which the fraction `q` of the histogram's flux lies, linear
/// within the bin it falls in; NaN for an empty histogram.
fn quantile(hist: &[f64], step: f64, drift: f64, q: f64) -> f64 {
    let total: f64 = hist.iter().sum();
    if total <= 0.0 {
        return f64::NAN;
    }
    let target = q * total;
    let mut below = 0.0;
    for (i, &f) in hist.iter().enumerate() {
        if below + f >= target && f > 0.0 {
            let lo = i as f64 * step;
            let hi = ((i + 1) as f64 * step).min(drift);
            return lo + (hi - lo) * ((target - below) / f).clamp(0.0, 1.0);
        }
        below += f;
    }
    drift
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_of_a_uniform_histogram_are_linear() {
        let hist = vec![1.0; 300];
        for q in [0.1, 0.5, 0.9] {
            let d = quantile(&hist, 0.1, 30.0, q);
            assert!((d - 30.0 * q).abs() < 1e-9, "q {q}: {d}");
        }
        assert!(quantile(&[0.0; 4], 0.1, 0.4, 0.5).is_nan());
    }
}
