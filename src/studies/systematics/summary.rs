//! Each source's effect, from its traced variations: on the image quality,
//! the centroid and the flux (the table), and on each pixel of the map (the
//! standard-deviation images).
//!
//! A source's standard deviation σ: for random draws (the figure), their
//! sample standard deviation; for a low and a high value taken as ±1σ (the
//! pointing, the tilt, the gas, `--vary`), the root mean square of their two
//! differences to the nominal value (half their difference for a linear
//! effect; for an even one, such as the flux lost to a pointing offset either
//! way, the loss itself, where half the difference would say nothing); for one
//! alternative (the solar model), its difference to the nominal image. The
//! sources are independent: the total σ is their sum in quadrature. The mean
//! image is the nominal one plus each source's mean shift (the draws' mean,
//! the midpoint of a range; an alternative counts as symmetric, no shift).

use super::plan::{Kind, Plan};
use super::{MapFrame, Outcome};
use serde::Serialize;

/// The quantities of the table, in the order of [`metrics`].
pub const METRICS: [&str; 7] = [
    "flux",
    "central_flux",
    "hpd_arcsec",
    "d80_arcsec",
    "d90_arcsec",
    "centroid_x_mm",
    "centroid_y_mm",
];

/// Where each quantity sits in [`METRICS`] and in what [`metrics`] returns.
pub mod metric {
    pub const FLUX: usize = 0;
    pub const CENTRAL_FLUX: usize = 1;
    pub const HPD: usize = 2;
    pub const D80: usize = 3;
    pub const D90: usize = 4;
    pub const CENTROID_X: usize = 5;
    pub const CENTROID_Y: usize = 6;
}

/// An outcome's quantities in the order of [`METRICS`] (NaN where it has
/// none: no flux, or no focal length for the diameters).
pub fn metrics(o: &Outcome) -> [f64; 7] {
    let mut m = [f64::NAN; 7];
    m[metric::FLUX] = o.flux;
    m[metric::CENTRAL_FLUX] = o.central_flux;
    if let Some(d) = o.diameters {
        (m[metric::HPD], m[metric::D80], m[metric::D90]) = (d.hpd, d.d80, d.d90);
    }
    if let Some([x, y]) = o.centroid_mm {
        (m[metric::CENTROID_X], m[metric::CENTROID_Y]) = (x, y);
    }
    m
}

/// One quantity's change under a source.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Effect {
    /// The source's standard deviation of the quantity.
    pub sigma: f64,
    /// Its signed mean change: the draws' mean minus the nominal value; the
    /// mean of low and high minus the nominal; the alternative minus the
    /// nominal.
    pub shift: f64,
}

/// A source's effect on every quantity.
#[derive(Clone, Debug, Serialize)]
pub struct SourceEffect {
    pub name: String,
    pub kind: Kind,
    pub what: String,
    /// Indices of its variations among the outcomes.
    pub variations: Vec<usize>,
    /// One per [`METRICS`].
    pub effects: Vec<Effect>,
}

/// Facts of the run the summary carries.
#[derive(Clone, Debug, Serialize)]
pub struct RunFacts {
    pub sensor: String,
    /// The central region: a square's side, or with `central_circle` a
    /// circle's radius (mm), about the sensor's centre.
    pub central_mm: f64,
    pub central_circle: bool,
    /// Whether fluxes are per second (a Sun) or summed weights …
    pub absolute: bool,
    /// … and what they count (axions, or X-rays with a magnet).
    pub counted: crate::scene::Counted,
    pub seconds: f64,
    pub threads: usize,
}

/// The study's result.
#[derive(Clone, Debug)]
pub struct Systematics {
    pub plan: Plan,
    /// One per variation, in the plan's order (the nominal first).
    pub outcomes: Vec<Outcome>,
    pub frame: MapFrame,
    pub sources: Vec<SourceEffect>,
    /// The sources' σ in quadrature, one per [`METRICS`].
    pub total_sigma: Vec<f64>,
    /// Maps ([iy][ix]): the nominal image, the mean, the total σ and each
    /// source's σ (in the order of `sources`).
    pub nominal_map: Vec<f64>,
    pub mean_map: Vec<f64>,
    pub sigma_map: Vec<f64>,
    pub sigma_maps: Vec<Vec<f64>>,
    /// The total σ over the mean image, per pixel (NaN where the mean is not
    /// positive): what a limit takes as a relative uncertainty.
    pub relative_sigma_map: Vec<f64>,
    /// The Monte Carlo noise of `sigma_map`, per pixel: half the difference
    /// of the total σ computed from each half of the photons (two
    /// independent estimates); `None` for records without the halves.
    pub noise_map: Option<Vec<f64>>,
    /// √(Σ noise² / Σ σ²) over the map: well below 1 when the σ map shows
    /// the sources, not the photons' noise.
    pub noise_to_sigma: Option<f64>,
    pub facts: RunFacts,
}

/// The total σ per pixel of the maps `map_of` gives for each outcome.
fn total_sigma_map<'a>(
    plan: &Plan,
    outcomes: &'a [Outcome],
    map_of: impl Fn(&'a Outcome) -> &'a [f64],
) -> Vec<f64> {
    let nominal = map_of(&outcomes[0]);
    let mut sq = vec![0.0; nominal.len()];
    for sp in &plan.sources {
        let idx: Vec<usize> = (0..outcomes.len())
            .filter(|&k| outcomes[k].source == sp.name)
            .collect();
        let mut x = vec![0.0; idx.len()];
        for (p, s) in sq.iter_mut().enumerate() {
            for (j, &k) in idx.iter().enumerate() {
                x[j] = map_of(&outcomes[k])[p];
            }
            *s += effect(sp.kind, nominal[p], &x).sigma.powi(2);
        }
    }
    sq.into_iter().map(f64::sqrt).collect()
}

/// The σ maps' Monte Carlo noise from the two halves of the photons, and its
/// size against the σ map's, if every outcome kept its halves.
fn noise(plan: &Plan, outcomes: &[Outcome], sigma: &[f64]) -> (Option<Vec<f64>>, Option<f64>) {
    if outcomes.iter().any(|o| o.halves.len() != 2) {
        return (None, None);
    }
    let a = total_sigma_map(plan, outcomes, |o| &o.halves[0]);
    let b = total_sigma_map(plan, outcomes, |o| &o.halves[1]);
    let noise: Vec<f64> = a.iter().zip(&b).map(|(a, b)| 0.5 * (a - b).abs()).collect();
    let (n2, s2) = noise
        .iter()
        .zip(sigma)
        .fold((0.0, 0.0), |(n, s), (a, b)| (n + a * a, s + b * b));
    let ratio = (s2 > 0.0).then(|| (n2 / s2).sqrt());
    (Some(noise), ratio)
}

/// A source's σ and shift of the values `x` (its variations') against the
/// nominal `x0`.
fn effect(kind: Kind, x0: f64, x: &[f64]) -> Effect {
    match kind {
        Kind::Draws => {
            let n = x.len() as f64;
            let mean = x.iter().sum::<f64>() / n;
            let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
            Effect {
                sigma: var.sqrt(),
                shift: mean - x0,
            }
        }
        Kind::Range => {
            let (lo, hi) = (x[0] - x0, x[1] - x0);
            Effect {
                sigma: (0.5 * (lo * lo + hi * hi)).sqrt(),
                shift: 0.5 * (lo + hi),
            }
        }
        Kind::Alternative => Effect {
            sigma: (x[0] - x0).abs(),
            shift: x[0] - x0,
        },
    }
}

/// The summary of the traced variations.
pub fn summarise(
    plan: &Plan,
    outcomes: Vec<Outcome>,
    frame: MapFrame,
    facts: RunFacts,
) -> Systematics {
    let nominal = metrics(&outcomes[0]);
    let nominal_map = outcomes[0].map.clone();
    let n_pix = nominal_map.len();
    let mut mean_map = nominal_map.clone();
    let mut sigma_sq = vec![0.0; n_pix];
    let mut sigma_maps = Vec::new();
    let mut sources = Vec::new();
    for sp in &plan.sources {
        let idx: Vec<usize> = (0..outcomes.len())
            .filter(|&k| outcomes[k].source == sp.name)
            .collect();
        let values: Vec<[f64; 7]> = idx.iter().map(|&k| metrics(&outcomes[k])).collect();
        let effects = (0..METRICS.len())
            .map(|m| {
                let x: Vec<f64> = values.iter().map(|v| v[m]).collect();
                effect(sp.kind, nominal[m], &x)
            })
            .collect();
        let mut sigma = vec![0.0; n_pix];
        let mut x = vec![0.0; idx.len()];
        for p in 0..n_pix {
            for (j, &k) in idx.iter().enumerate() {
                x[j] = outcomes[k].map[p];
            }
            let e = effect(sp.kind, nominal_map[p], &x);
            sigma[p] = e.sigma;
            sigma_sq[p] += e.sigma * e.sigma;
            if sp.kind != Kind::Alternative {
                mean_map[p] += e.shift;
            }
        }
        sigma_maps.push(sigma);
        sources.push(SourceEffect {
            name: sp.name.clone(),
            kind: sp.kind,
            what: sp.what.clone(),
            variations: idx,
            effects,
        });
    }
    let total_sigma = (0..METRICS.len())
        .map(|m| {
            sources
                .iter()
                .map(|s| s.effects[m].sigma.powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .collect();
    let sigma_map: Vec<f64> = sigma_sq.into_iter().map(f64::sqrt).collect();
    let relative_sigma_map = sigma_map
        .iter()
        .zip(&mean_map)
        .map(|(s, m)| if *m > 0.0 { s / m } else { f64::NAN })
        .collect();
    let (noise_map, noise_to_sigma) = noise(plan, &outcomes, &sigma_map);
    Systematics {
        plan: plan.clone(),
        outcomes,
        frame,
        sources,
        total_sigma,
        nominal_map,
        mean_map,
        sigma_map,
        sigma_maps,
        relative_sigma_map,
        noise_map,
        noise_to_sigma,
        facts,
    }
}
