//! The reach of a helioscope: the median expected 95 % CL upper limit on the
//! coupling under the background-only hypothesis, for a counting experiment
//! (the signal region and energy window of `signal`).
//!
//! The statistics: CLs (A. L. Read, J. Phys. G 28 (2002) 2693), exact
//! Poisson, one bin. For n observed counts and expected background b, the
//! signal s is excluded at 95 % CL when
//! CLs(s) = P(N ≤ n | s + b) / P(N ≤ n | b) ≤ 0.05. The median expected limit
//! takes n = the median of Poisson(b), the count half of the background-only
//! experiments stay at or below. With no background (n = 0) CLs = e^(−s)
//! and the limit is s = ln 20 = 2.996 counts, the classical 95 % limit for
//! no event; for large b it tends to 1.96 √b. Exact Poisson rather than the
//! asymptotic (Asimov) formula, which for b → 0 gives 1.35 counts instead of
//! 3.0: helioscope backgrounds are a few counts.
//!
//! The coupling: the run traced at couplings g₀ expects s₀ counts; every
//! term of the signal scales as a power of the couplings (production ∝ g²,
//! conversion P ∝ g_aγ² while P ≪ 1), so Primakoff's s = s₀ (g_aγ/g₀)⁴ gives
//! g_aγ = g₀ (s_up/s₀)^(1/4), and ABC's s = s₀ (g_ae g_aγ / g_ae₀ g₀)² gives
//! g_ae g_aγ = g_ae₀ g₀ (s_up/s₀)^(1/2): the limit is solved on the counts,
//! not on the coupling.
//!
//! Data flow: `cli::reach` reads runs (`output::run_read`), measures their
//! signal (`analysis::signal`) and calls [`limit`] per mass.

/// 1 − the confidence level.
pub const ALPHA: f64 = 0.05;

/// ln k! for k ≥ 0 (Stirling's series beyond a table of exact sums).
fn ln_factorial(k: u64) -> f64 {
    if k < 256 {
        return (2..=k).map(|i| (i as f64).ln()).sum();
    }
    let x = k as f64 + 1.0;
    // ln Γ(x) for x ≥ 257: the series' next term is below 1e-16.
    (x - 0.5) * x.ln() - x + 0.5 * (std::f64::consts::TAU).ln() + 1.0 / (12.0 * x)
        - 1.0 / (360.0 * x.powi(3))
        + 1.0 / (1260.0 * x.powi(5))
}

/// P(N ≤ n) for N ~ Poisson(mu): the terms summed from where they matter
/// (those more than 40 σ below the mean add nothing at double precision).
pub fn poisson_cdf(n: u64, mu: f64) -> f64 {
    if mu <= 0.0 {
        return 1.0;
    }
    let low = (mu - 40.0 * mu.sqrt() - 40.0).max(0.0) as u64;
    if n < low {
        return 0.0;
    }
    let ln_mu = mu.ln();
    (low..=n)
        .map(|k| (-mu + k as f64 * ln_mu - ln_factorial(k)).exp())
        .sum::<f64>()
        .min(1.0)
}

/// The median of Poisson(b): the least n with P(N ≤ n) ≥ 1/2.
pub fn poisson_median(b: f64) -> u64 {
    let mut n = (b - 1.0).max(0.0).floor() as u64;
    // The median lies within [b − ln 2, b + 1/3]; step up from below.
    while poisson_cdf(n, b) < 0.5 {
        n += 1;
    }
    n
}

/// The CLs upper limit on the signal counts for `observed` counts over an
/// expected background `b`.
pub fn cls_upper_limit(observed: u64, b: f64) -> f64 {
    let cl_b = poisson_cdf(observed, b);
    let cls = |s: f64| poisson_cdf(observed, s + b) / cl_b;
    let mut hi = 3.0 + observed as f64 + 10.0 * (observed as f64 + b).sqrt();
    while cls(hi) > ALPHA {
        hi *= 2.0;
    }
    let mut lo = 0.0;
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if cls(mid) > ALPHA {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// The largest background (counts) whose limit is computed with exact Poisson
/// sums; above it, the normal limit ([`normal_median_limit`]).
pub const EXACT_POISSON_MAX_COUNTS: f64 = 1e6;

/// The largest background (counts) traxer takes: 10¹⁵ counts is a detector
/// firing at 3 GHz for ten years; a larger one is a unit slip.
pub const MAX_BACKGROUND_COUNTS: f64 = 1e15;

/// The median expected upper limit on the signal counts for background `b`:
/// exact Poisson up to [`EXACT_POISSON_MAX_COUNTS`], the normal limit above
/// (they meet to 2e-4 there: the Poisson skew and the median's discreteness
/// fall as 1/√b; `the_normal_limit_meets_the_exact_one`).
pub fn median_expected_limit(b: f64) -> f64 {
    if b > EXACT_POISSON_MAX_COUNTS {
        return normal_median_limit(b);
    }
    cls_upper_limit(poisson_median(b), b)
}

/// The CLs limit for a background so large that N is normal: at the median
/// count CL_b = ½, so CLs = 0.05 asks CL_s+b = Φ(−s / √(s + b)) = 0.025,
/// i.e. s² = z² (s + b) with z = Φ⁻¹(0.975), solved in closed form.
pub fn normal_median_limit(b: f64) -> f64 {
    let z2 = Z_975 * Z_975;
    0.5 * (z2 + (z2 * z2 + 4.0 * z2 * b).sqrt())
}

/// Φ⁻¹(0.975): the two-sided 95 % normal quantile.
pub const Z_975: f64 = 1.959_963_984_540_054;

/// What the limit constrains.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Coupling {
    /// g_aγ (GeV⁻¹), from Primakoff: s ∝ g_aγ⁴.
    GAgamma(f64),
    /// g_ae · g_aγ (GeV⁻¹), from ABC: s ∝ (g_ae g_aγ)².
    GAeGAgamma(f64),
}

impl Coupling {
    /// The coupling at which `s_up` counts are expected, when `s0` are at
    /// this one; `None` without signal.
    pub fn at_counts(self, s0: f64, s_up: f64) -> Option<f64> {
        (s0 > 0.0).then(|| match self {
            Coupling::GAgamma(g) => g * (s_up / s0).powf(0.25),
            Coupling::GAeGAgamma(g) => g * (s_up / s0).sqrt(),
        })
    }

    pub fn name(self) -> &'static str {
        match self {
            Coupling::GAgamma(_) => "g_agamma",
            Coupling::GAeGAgamma(_) => "g_ae_g_agamma",
        }
    }
}

/// An experiment's exposure and background, per signal region.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Exposure {
    /// Hours of tracking the Sun.
    pub tracking_hours: f64,
    /// Identical magnet bores with their optics and detectors.
    pub bores: f64,
    /// Efficiency beyond what the run holds (the run's detector gas is in
    /// its counts already): software cuts, dead time.
    pub efficiency: f64,
    /// Background, counts per keV per cm² per second.
    pub background: f64,
}

/// One mass's limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limit {
    pub mass_ev: f64,
    /// Expected signal counts at the run's couplings, and the background.
    pub signal: f64,
    pub background: f64,
    /// The median expected limit on the counts, and on the coupling.
    pub counts_limit: f64,
    pub coupling_limit: Option<f64>,
}

impl Exposure {
    /// Seconds of tracking times the bores.
    pub fn seconds(&self) -> f64 {
        self.tracking_hours * 3600.0 * self.bores
    }

    /// The expected background counts in a region of `area_cm2` and a window
    /// `width_kev` wide.
    pub fn background_counts(&self, (area_cm2, width_kev): (f64, f64)) -> f64 {
        self.background * area_cm2 * width_kev * self.seconds()
    }
}

/// The background of one run's region and window, with its median expected
/// limit on the counts (the same for every mass of the run).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Background {
    pub counts: f64,
    pub counts_limit: f64,
}

impl Background {
    pub fn new(counts: f64) -> Background {
        Background {
            counts,
            counts_limit: median_expected_limit(counts),
        }
    }
}

/// The limit at one mass from the signal rate `rate` (X-rays/s in the
/// region and window at the run's `coupling`) over the region's background.
pub fn limit(
    mass_ev: f64,
    rate: f64,
    coupling: Coupling,
    background: Background,
    e: &Exposure,
) -> Limit {
    let signal = rate * e.seconds() * e.efficiency;
    Limit {
        mass_ev,
        signal,
        background: background.counts,
        counts_limit: background.counts_limit,
        coupling_limit: coupling.at_counts(signal, background.counts_limit),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_poisson_cdf_sums_to_the_closed_forms() {
        assert!((poisson_cdf(0, 2.0) - (-2.0f64).exp()).abs() < 1e-15);
        assert!((poisson_cdf(1, 2.0) - 3.0 * (-2.0f64).exp()).abs() < 1e-15);
        // Far beyond the table: the median of Poisson(1e6) is 1e6 (CDF ≈ ½).
        let c = poisson_cdf(1_000_000, 1e6);
        assert!((c - 0.5).abs() < 1e-3, "{c}");
        assert!((ln_factorial(300) - (2..=300).map(|i| (i as f64).ln()).sum::<f64>()).abs() < 1e-9);
    }

    #[test]
    fn no_background_gives_the_classical_three_counts() {
        // n = 0: CLs = e^(−s) whatever b, so s = ln 20 = 2.9957.
        for b in [0.0, 0.3, 0.69] {
            let s = median_expected_limit(b);
            assert!((s - 20f64.ln()).abs() < 1e-9, "b = {b}: {s}");
        }
    }

    #[test]
    fn one_count_over_one_expected_solves_the_hand_equation() {
        // b = 1: the median count is 1 (P(0) = 0.37 < ½ ≤ P(≤1) = 0.74), and
        // CLs = e^(−s) (2 + s) / 2 = 0.05, solved here by Newton's method.
        assert_eq!(poisson_median(1.0), 1);
        let mut s: f64 = 4.0;
        for _ in 0..50 {
            let f = (-s).exp() * (2.0 + s) / 2.0 - 0.05;
            let df = -(-s).exp() * (1.0 + s) / 2.0;
            s -= f / df;
        }
        assert!((median_expected_limit(1.0) - s).abs() < 1e-9, "{s}");
    }

    #[test]
    fn a_large_background_tends_to_1_96_sigma() {
        // CL_b ≈ ½ at the median, so CL_s+b = 0.025: s ≈ 1.96 √b (within a
        // few per cent: the Poisson skew and the median's discreteness).
        let b = 1e4;
        let s = median_expected_limit(b);
        assert!((s / b.sqrt() / 1.96 - 1.0).abs() < 0.03, "{}", s / b.sqrt());
    }

    #[test]
    fn the_normal_limit_meets_the_exact_one() {
        // Where the exact sums hand over to the normal limit, the two agree
        // to 2e-4 (the skew's share is ~ 1/√b = 1e-3, most of it cancels in
        // the ratio of the two CDFs).
        let b = EXACT_POISSON_MAX_COUNTS;
        let exact = cls_upper_limit(poisson_median(b), b);
        let normal = normal_median_limit(b);
        assert!((normal / exact - 1.0).abs() < 2e-4, "{exact} {normal}");
        // And for b → 0 the closed form gives z², not 3 counts: why it is
        // used for large backgrounds only.
        assert!((normal_median_limit(0.0) - Z_975 * Z_975).abs() < 1e-12);
    }

    #[test]
    fn the_coupling_follows_the_signal_power() {
        let g = Coupling::GAgamma(1e-10).at_counts(3000.0, 3.0).unwrap();
        assert!((g - 1e-10 * (1e-3f64).powf(0.25)).abs() < 1e-24);
        let p = Coupling::GAeGAgamma(1e-23).at_counts(400.0, 4.0).unwrap();
        assert!((p - 1e-24).abs() < 1e-36);
        assert!(Coupling::GAgamma(1e-10).at_counts(0.0, 3.0).is_none());
    }
}
