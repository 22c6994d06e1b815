//! Scatter from a mirror's microroughness, described by its power spectral
//! density (PSD): the energy-dependent part of an imperfect mirror, beside the
//! geometric figure errors (`figure_error`), which stay for the low spatial
//! frequencies below the PSD's band. A mirror material's `roughness` selects
//! it; the photon loop turns a scattered reflection to its new grazing angle
//! ([`to_grazing_angle`]) before the figure error tilts it.
//!
//! Model (first-order vector perturbation theory in the smooth-surface limit,
//! Church & Takacs; for grazing-incidence X-ray mirrors as in Spiga, A&A 468
//! (2007) 775, and Stover, "Optical Scattering", 3rd ed., ch. 4–5):
//!
//! - The surface's 1-D PSD along the plane of incidence, one-sided P(f) in
//!   nm²·µm for spatial frequencies f (µm⁻¹) in the band [f₁, f₂] it is given
//!   for; σ² = ∫ P df over the band. A ripple of frequency f scatters as a
//!   grating: cos θs = cos θi − λ f, i.e. θs² = θi² + 2λf at grazing angles
//!   (f > 0 away from the surface, f < 0 towards it, each with half of P).
//! - The scattered intensity per unit frequency is (16π²/λ²) θi θs W(f), W =
//!   P/2 the two-sided PSD, so the total integrated scatter is
//!   TIS = (4π θi/λ)² J(a), J(a) = ∫ √(1 + a f) W(f) df over the frequencies
//!   that leave the surface (f ≥ −1/a), a = 2λ/θi². For a → 0 (scattering
//!   angles small against θi) J → σ² and TIS → (4π σ sin θi/λ)², the classic
//!   formula; at low energies and small angles the backward branch is cut off
//!   and the forward one weighs more.
//! - The specular reflectivity is R·exp(−TIS) (Debye–Waller, which is what
//!   TIS is the first order of) and the scattered part R·(1 − exp(−TIS)): the
//!   two add up to the smooth mirror's R, so no power is made or lost by the
//!   split; the multilayer's own R(E, θ) (Parratt, no interface roughness in the
//!   LLNL recipes) stays as it is.
//!
//! Approximations: smooth surface (4πσ θi/λ ≪ 1; beyond that the angular
//! distribution is only indicative, the split stays energy-conserving); small
//! angles (θs ≪ 1 rad); in-plane scattering only (the out-of-plane angle of a
//! ripple is λ f_y, smaller than the in-plane one, λ f/θi, by the factor θi);
//! the scattered photon keeps the reflectivity at θi (the Q factor of the
//! theory taken as R(θi)).
//!
//! For the photon loop everything depends on (λ, θi) through a = 2λ/θi² alone,
//! so J(a) and the inverse cumulative distribution of f are tabulated once on
//! a logarithmic grid of a: a reflection then needs two uniform numbers, always
//! two, so that photons keep their random streams aligned.

use crate::constants::HC_KEV_UM;
use serde::Deserialize;

/// A one-sided 1-D PSD P(f), nm²·µm, f in µm⁻¹.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, serde::Serialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Psd {
    /// Fractal: P(f) = k / f^n (k in nm²·µm^(1−n)).
    PowerLaw { k: f64, n: f64 },
    /// K-correlation (ABC) model: P(f) = a / (1 + (b f)²)^(c/2), a in nm²·µm,
    /// b in µm.
    KCorrelation { a: f64, b: f64, c: f64 },
}

impl Psd {
    /// P(f), nm²·µm.
    pub fn at(&self, f: f64) -> f64 {
        match *self {
            Psd::PowerLaw { k, n } => k * f.powf(-n),
            Psd::KCorrelation { a, b, c } => a / (1.0 + (b * f).powi(2)).powf(0.5 * c),
        }
    }
}

/// A surface's roughness: its PSD over the band of frequencies it describes
/// (the figure errors take the frequencies below it).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct RoughnessDesc {
    pub psd: Psd,
    /// The band [f₁, f₂], µm⁻¹.
    pub band_per_um: [f64; 2],
}

/// How a scene gives a mirror's roughness: a preset of data/roughness.toml,
/// `"none"` (a smooth surface, so a scene variable can switch the scatter off)
/// or the PSD inline.
#[derive(Clone, Debug, PartialEq)]
pub enum RoughnessSpec {
    Named(String),
    Inline(RoughnessDesc),
}

/// The forms `roughness` takes, for messages.
pub const ROUGHNESS_FORMS: &str = "a preset name of data/roughness.toml (e.g. \"slumped_glass_limit\"), \"none\", or a table { psd = { type = \"power_law\", k = …, n = … } or { type = \"k_correlation\", a = …, b = …, c = … }, band_per_um = [f1, f2] }";

impl<'de> Deserialize<'de> for RoughnessSpec {
    /// A string is a preset's name; a table is the PSD inline, whose own
    /// mistakes (a missing key, a misspelt PSD type) are named with the forms
    /// accepted, instead of serde's "did not match any variant".
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        match toml::Value::deserialize(d)? {
            toml::Value::String(name) => Ok(RoughnessSpec::Named(name)),
            table @ toml::Value::Table(_) => RoughnessDesc::deserialize(table)
                .map(RoughnessSpec::Inline)
                .map_err(|e| {
                    D::Error::custom(format!(
                        "roughness: {}; expected {ROUGHNESS_FORMS}",
                        e.message().trim_end()
                    ))
                }),
            other => Err(D::Error::custom(format!(
                "roughness = {other}: expected {ROUGHNESS_FORMS}"
            ))),
        }
    }
}

const SHIPPED: &str = include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/data/roughness.toml"));

/// A preset of data/roughness.toml: the PSD, the σ it states (checked against
/// the PSD by a test) and where its numbers come from.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoughnessPreset {
    pub psd: Psd,
    pub band_per_um: [f64; 2],
    pub sigma_nm: f64,
    pub source: String,
}

/// The shipped presets by name.
pub fn presets() -> std::collections::BTreeMap<String, RoughnessPreset> {
    #[derive(Deserialize)]
    struct File {
        roughness: std::collections::BTreeMap<String, RoughnessPreset>,
    }
    toml::from_str::<File>(SHIPPED)
        .expect("data/roughness.toml is valid (tested)")
        .roughness
}

impl RoughnessSpec {
    /// The PSD to scatter from; `None` for a smooth surface.
    pub fn resolve(&self) -> Result<Option<RoughnessDesc>, String> {
        match self {
            RoughnessSpec::Inline(d) => Ok(Some(*d)),
            RoughnessSpec::Named(n) if n == "none" => Ok(None),
            RoughnessSpec::Named(n) => {
                let all = presets();
                match all.get(n) {
                    Some(p) => Ok(Some(RoughnessDesc {
                        psd: p.psd,
                        band_per_um: p.band_per_um,
                    })),
                    None => Err(format!(
                        "unknown roughness `{n}`: expected \"none\", a preset of data/roughness.toml ({}) or a PSD inline, {{ psd = {{ type = \"power_law\", k = ..., n = ... }}, band_per_um = [f1, f2] }}",
                        all.keys().map(|k| k.as_str()).collect::<Vec<_>>().join(", ")
                    )),
                }
            }
        }
    }
}

/// Points of the log-spaced frequency grid the integrals are taken on.
const F_POINTS: usize = 4097;
/// The table's grid in log₁₀ a (a in µm): from 1e-6 to 1e8 µm covers λ of
/// 0.05–30 keV at grazing angles from 0.06° to 30°.
const LOG_A: (f64, f64) = (-6.0, 8.0);
const A_POINTS: usize = 561;
/// Quantiles stored per a.
const U_POINTS: usize = 257;

/// The roughness, tabulated for the photon loop.
#[derive(Clone, Debug)]
pub struct Roughness {
    pub desc: RoughnessDesc,
    /// σ² over the band, nm².
    pub sigma2_nm2: f64,
    /// J(a) at the grid's a, nm².
    j: Vec<f64>,
    /// For each a, the share of the scattered power on the backward branch
    /// (towards the surface, f < 0).
    backward: Vec<f64>,
    /// For each a, ln(|f|/f₁) at quantiles u = k/(U_POINTS − 1) of each branch
    /// on its own (so that interpolating between two a never mixes branches).
    quantiles_fwd: Vec<f64>,
    quantiles_bwd: Vec<f64>,
}

/// What becomes of one reflection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scatter {
    /// Specular (the weight keeps R·exp(−TIS) on average).
    Specular,
    /// Scattered to grazing angle θs (rad) in the plane of incidence.
    Scattered { theta_s: f64 },
}

impl Roughness {
    /// The tables of `desc`; what is wrong with it otherwise.
    pub fn new(desc: RoughnessDesc) -> Result<Roughness, String> {
        let [f1, f2] = desc.band_per_um;
        if !(f1.is_finite() && f2.is_finite() && f1 > 0.0 && f2 > f1) {
            return Err(format!(
                "roughness band_per_um = [{f1}, {f2}]: expected 0 < f₁ < f₂ (µm⁻¹)"
            ));
        }
        let grid = log_grid(f1, f2, F_POINTS);
        let p: Vec<f64> = grid.iter().map(|&f| desc.psd.at(f)).collect();
        if p.iter().any(|v| !v.is_finite() || *v < 0.0) {
            return Err("roughness psd: P(f) must be finite and ≥ 0 over the band".into());
        }
        let sigma2_nm2 = integrate(&grid, &p, |_| 1.0);
        let mut r = Roughness {
            desc,
            sigma2_nm2,
            j: Vec::with_capacity(A_POINTS),
            backward: Vec::with_capacity(A_POINTS),
            quantiles_fwd: Vec::with_capacity(A_POINTS * U_POINTS),
            quantiles_bwd: Vec::with_capacity(A_POINTS * U_POINTS),
        };
        for i in 0..A_POINTS {
            let a = 10f64.powf(LOG_A.0 + (LOG_A.1 - LOG_A.0) * i as f64 / (A_POINTS - 1) as f64);
            let b = Branches::of(&grid, &p, a);
            r.j.push(b.fwd_total + b.bwd_total);
            r.backward.push(b.bwd_total / (b.fwd_total + b.bwd_total));
            r.quantiles_fwd
                .extend(quantiles(&b.fwd_cumulative, f1, &grid));
            r.quantiles_bwd
                .extend(quantiles(&b.bwd_cumulative, f1, &grid));
        }
        Ok(r)
    }

    /// J(a) in nm² (interpolated in log a; a beyond the grid takes its end).
    pub fn j(&self, a: f64) -> f64 {
        let (i, t) = a_cell(a);
        self.j[i] * (1.0 - t) + self.j[i + 1] * t
    }

    /// The total integrated scatter at `energy_kev` and grazing angle `theta`
    /// (rad): (4π θ/λ)² J(2λ/θ²), with λ and σ in the same unit.
    pub fn tis(&self, energy_kev: f64, theta: f64) -> f64 {
        let lambda_um = HC_KEV_UM / energy_kev;
        let a = 2.0 * lambda_um / (theta * theta);
        // J in nm², λ in µm: (4π θ/λ)² J needs λ in nm.
        let lambda_nm = lambda_um * 1e3;
        (4.0 * std::f64::consts::PI * theta / lambda_nm).powi(2) * self.j(a)
    }

    /// One reflection at `energy_kev` and grazing angle `theta` (rad), from two
    /// uniform numbers: `u_scatter` decides (scattered with probability
    /// 1 − exp(−TIS)), `u_angle` draws the frequency.
    pub fn draw(&self, energy_kev: f64, theta: f64, u_scatter: f64, u_angle: f64) -> Scatter {
        let p = 1.0 - (-self.tis(energy_kev, theta)).exp();
        if u_scatter >= p {
            return Scatter::Specular;
        }
        let lambda_um = HC_KEV_UM / energy_kev;
        let f = self.frequency(2.0 * lambda_um / (theta * theta), u_angle);
        let theta_s2 = theta * theta + 2.0 * lambda_um * f;
        Scatter::Scattered {
            theta_s: theta_s2.max(0.0).sqrt(),
        }
    }

    /// The signed frequency (µm⁻¹) at quantile `u` of the scattered
    /// distribution at `a`: the backward branch for u below its share.
    pub fn frequency(&self, a: f64, u: f64) -> f64 {
        let (i, t) = a_cell(a);
        let u = u.clamp(0.0, 1.0);
        let back = self.backward[i] * (1.0 - t) + self.backward[i + 1] * t;
        let (table, v, sign) = if u < back {
            (&self.quantiles_bwd, u / back, -1.0)
        } else {
            (&self.quantiles_fwd, (u - back) / (1.0 - back), 1.0)
        };
        let x = v.clamp(0.0, 1.0) * (U_POINTS - 1) as f64;
        let k = (x as usize).min(U_POINTS - 2);
        let s = x - k as f64;
        let row = |r: usize| {
            let q = &table[r * U_POINTS..(r + 1) * U_POINTS];
            q[k] * (1.0 - s) + q[k + 1] * s
        };
        let ln = row(i) * (1.0 - t) + row(i + 1) * t;
        let f = self.desc.band_per_um[0] * ln.exp();
        if sign < 0.0 {
            // Towards the surface no further than grazing (θs ≥ 0).
            -f.min(1.0 / a)
        } else {
            f
        }
    }
}

/// The reflected unit direction `reflected` turned in its plane of incidence
/// (the plane of it and the surface normal `normal`) to the grazing angle
/// `theta_s` from the surface, on the same side.
#[inline]
pub fn to_grazing_angle(reflected: glam::DVec3, normal: glam::DVec3, theta_s: f64) -> glam::DVec3 {
    let n = if reflected.dot(normal) >= 0.0 {
        normal
    } else {
        -normal
    };
    let along = reflected - n * reflected.dot(n);
    let Some(t) = along.try_normalize() else {
        return reflected;
    };
    let (s, c) = theta_s.sin_cos();
    t * c + n * s
}

/// The grid cell of log a and the position in it.
fn a_cell(a: f64) -> (usize, f64) {
    let x = ((a.log10() - LOG_A.0) / (LOG_A.1 - LOG_A.0) * (A_POINTS - 1) as f64)
        .clamp(0.0, (A_POINTS - 1) as f64);
    let i = (x as usize).min(A_POINTS - 2);
    (i, x - i as f64)
}

/// `n` frequencies from f1 to f2, equally spaced in log.
fn log_grid(f1: f64, f2: f64, n: usize) -> Vec<f64> {
    let r = (f2 / f1).ln();
    (0..n)
        .map(|i| f1 * (r * i as f64 / (n - 1) as f64).exp())
        .collect()
}

/// ∫ p(f)·g(f) df over the grid (trapezoids in ln f: ∫ p g f d ln f).
fn integrate(grid: &[f64], p: &[f64], g: impl Fn(f64) -> f64) -> f64 {
    let h = (grid[1] / grid[0]).ln();
    let y: Vec<f64> = grid.iter().zip(p).map(|(&f, &v)| v * g(f) * f).collect();
    h * (y.iter().sum::<f64>() - 0.5 * (y[0] + y[y.len() - 1]))
}

/// The scattered distribution ∝ √(1 ± a f) W(f) on each branch, W = P/2:
/// forward (away from the surface) f ∈ [f₁, f₂], backward f ∈ [f₁,
/// min(f₂, 1/a)]; cumulative integrals over the grid (trapezoids in ln f).
struct Branches {
    fwd_cumulative: Vec<f64>,
    bwd_cumulative: Vec<f64>,
    fwd_total: f64,
    bwd_total: f64,
}

impl Branches {
    fn of(grid: &[f64], p: &[f64], a: f64) -> Branches {
        let h = (grid[1] / grid[0]).ln();
        let cumulative = |sign: f64| {
            let d: Vec<f64> = grid
                .iter()
                .zip(p)
                .map(|(&f, &v)| 0.5 * v * f * (1.0 + sign * a * f).max(0.0).sqrt())
                .collect();
            let mut c = vec![0.0];
            for k in 1..d.len() {
                c.push(c[k - 1] + 0.5 * h * (d[k] + d[k - 1]));
            }
            c
        };
        let (fwd_cumulative, bwd_cumulative) = (cumulative(1.0), cumulative(-1.0));
        Branches {
            fwd_total: *fwd_cumulative.last().expect("a grid"),
            bwd_total: *bwd_cumulative.last().expect("a grid"),
            fwd_cumulative,
            bwd_cumulative,
        }
    }
}

/// ln(f/f₁) at the quantiles of one branch's cumulative distribution (all 0,
/// i.e. f₁, for a branch without power).
fn quantiles(cumulative: &[f64], f1: f64, grid: &[f64]) -> Vec<f64> {
    let total = cumulative[cumulative.len() - 1];
    (0..U_POINTS)
        .map(|q| {
            if total <= 0.0 {
                return 0.0;
            }
            let target = total * q as f64 / (U_POINTS - 1) as f64;
            let i = cumulative
                .partition_point(|&c| c < target)
                .clamp(1, cumulative.len() - 1);
            let (c0, c1) = (cumulative[i - 1], cumulative[i]);
            let (l0, l1) = ((grid[i - 1] / f1).ln(), (grid[i] / f1).ln());
            if c1 > c0 {
                l0 + (l1 - l0) * (target - c0) / (c1 - c0)
            } else {
                l1
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn llnl_like() -> Roughness {
        Roughness::new(RoughnessDesc {
            psd: Psd::PowerLaw { k: 0.01, n: 1.8 },
            band_per_um: [1e-3, 1.0],
        })
        .unwrap()
    }

    /// Every shipped preset builds, and its PSD has the σ it states (for a
    /// power law, against the closed form ∫ k f^-n df as well).
    #[test]
    fn shipped_presets_have_the_sigma_they_state() {
        let all = presets();
        assert!(all.contains_key("slumped_glass_limit"));
        for (name, p) in all {
            let r = Roughness::new(RoughnessDesc {
                psd: p.psd,
                band_per_um: p.band_per_um,
            })
            .unwrap();
            let sigma = r.sigma2_nm2.sqrt();
            assert!(
                (sigma / p.sigma_nm - 1.0).abs() < 1e-4,
                "{name}: σ {sigma} nm"
            );
            if let Psd::PowerLaw { k, n } = p.psd {
                let [f1, f2] = p.band_per_um;
                let exact = (k / (1.0 - n) * (f2.powf(1.0 - n) - f1.powf(1.0 - n))).sqrt();
                assert!(
                    (exact / p.sigma_nm - 1.0).abs() < 1e-4,
                    "{name}: {exact} nm"
                );
            }
            assert!(!p.source.is_empty());
        }
    }

    /// σ² of a power law against its closed form ∫ k f^-n df.
    #[test]
    fn sigma_of_a_power_law() {
        let r = llnl_like();
        let exact = 0.01 / (1.0 - 1.8) * (1.0f64.powf(-0.8) - 1e-3f64.powf(-0.8));
        assert!(
            (r.sigma2_nm2 / exact - 1.0).abs() < 1e-5,
            "{} vs {exact}",
            r.sigma2_nm2
        );
    }

    /// J(a) of P = k f^-1.5 in closed form: with t = √f,
    /// ∫ √(1 + a f) f^-1.5 df = 2[−√(1 + a t²)/t + √a asinh(√a t)] and
    /// ∫ √(1 − a f) f^-1.5 df = 2[−√(1 − a t²)/t − √a asin(√a t)].
    fn j_closed(k: f64, [f1, f2]: [f64; 2], a: f64) -> f64 {
        let fwd = |f: f64| {
            let t = f.sqrt();
            2.0 * (-(1.0 + a * t * t).sqrt() / t + a.sqrt() * (a.sqrt() * t).asinh())
        };
        let bwd = |f: f64| {
            let t = f.sqrt();
            2.0 * (-(1.0 - a * t * t).max(0.0).sqrt() / t
                - a.sqrt() * (a.sqrt() * t).min(1.0).asin())
        };
        let mut j = 0.5 * k * (fwd(f2) - fwd(f1));
        let top = f2.min(1.0 / a);
        if top > f1 {
            j += 0.5 * k * (bwd(top) - bwd(f1));
        }
        j
    }

    /// The total integrated scatter against its formula over energy and
    /// grazing angle: (4π θ/λ)² J(2λ/θ²) with J in closed form, within 2e-3
    /// (the table's interpolation in log a); and the classic (4π σ θ/λ)² where
    /// the scattering angles are small against θ (a f₂ ≪ 1).
    #[test]
    fn total_integrated_scatter_follows_its_formula() {
        let (k, band) = (0.02, [1e-3, 1.0]);
        let r = Roughness::new(RoughnessDesc {
            psd: Psd::PowerLaw { k, n: 1.5 },
            band_per_um: band,
        })
        .unwrap();
        for e in [1.0, 3.0, 5.0, 8.0, 20.0] {
            for deg in [0.2, 0.5, 1.0, 3.0] {
                let theta = f64::to_radians(deg);
                let lambda_um = HC_KEV_UM / e;
                let a = 2.0 * lambda_um / (theta * theta);
                let expect = (4.0 * std::f64::consts::PI * theta / (lambda_um * 1e3)).powi(2)
                    * j_closed(k, band, a);
                let got = r.tis(e, theta);
                assert!(
                    (got / expect - 1.0).abs() < 2e-3,
                    "{e} keV, {deg}°: {got} vs {expect}"
                );
            }
        }
        // Small angles against θ: a band of 1e-4–1e-3 µm⁻¹ at 20 keV, 3°.
        let low = Roughness::new(RoughnessDesc {
            psd: Psd::PowerLaw { k, n: 1.5 },
            band_per_um: [1e-4, 1e-3],
        })
        .unwrap();
        let (e, theta) = (20.0, 3f64.to_radians());
        let lambda_nm = HC_KEV_UM / e * 1e3;
        let classic =
            (4.0 * std::f64::consts::PI * low.sigma2_nm2.sqrt() * theta.sin() / lambda_nm).powi(2);
        assert!((low.tis(e, theta) / classic - 1.0).abs() < 1e-3);
    }

    /// The scattered frequencies (hence angles, θs² = θ² + 2λf) follow the
    /// PSD-weighted density √(1 + a f) W(|f|) at two energies: the fraction
    /// drawn into each of 12 log-spaced bins of |f| on each branch against the
    /// closed-form integral, within 5 binomial standard deviations of 400 000
    /// draws (the quantile table's interpolation is far below that).
    #[test]
    fn scattering_angles_follow_the_psd() {
        let (k, band) = (0.02, [1e-3, 1.0]);
        let r = Roughness::new(RoughnessDesc {
            psd: Psd::PowerLaw { k, n: 1.5 },
            band_per_um: band,
        })
        .unwrap();
        let theta = 0.5f64.to_radians();
        for e in [1.0, 8.0] {
            let lambda_um = HC_KEV_UM / e;
            let a = 2.0 * lambda_um / (theta * theta);
            let total = j_closed(k, band, a);
            let edges: Vec<f64> = (0..=12)
                .map(|i| 1e-3 * 10f64.powf(i as f64 * 0.25))
                .collect();
            let n = 400_000;
            let mut fwd = [0usize; 12];
            let mut bwd = [0usize; 12];
            let mut rng = crate::random::PhotonRng::new(9, e as u64);
            for _ in 0..n {
                let f = r.frequency(a, rng.uniform());
                let bin = edges.partition_point(|&x| x <= f.abs()).clamp(1, 12) - 1;
                if f > 0.0 {
                    fwd[bin] += 1;
                } else {
                    bwd[bin] += 1;
                }
                // Every drawn frequency leaves the surface.
                assert!(1.0 + a * f >= -1e-9, "{f} at a = {a}");
            }
            for b in 0..12 {
                let (lo, hi) = (edges[b], edges[b + 1]);
                let p_fwd = j_closed(k, [lo, hi], a) - j_closed_bwd_only(k, [lo, hi], a);
                let p_bwd = j_closed_bwd_only(k, [lo, hi], a);
                for (count, p) in [(fwd[b], p_fwd / total), (bwd[b], p_bwd / total)] {
                    let expect = p * n as f64;
                    let sd = (n as f64 * p * (1.0 - p)).sqrt().max(1.0);
                    assert!(
                        (count as f64 - expect).abs() < 5.0 * sd + 2e-3 * expect,
                        "{e} keV, bin {b}: {count} vs {expect:.1}"
                    );
                }
            }
        }
    }

    fn j_closed_bwd_only(k: f64, [f1, f2]: [f64; 2], a: f64) -> f64 {
        j_closed(k, [f1, f2], a) - {
            let t = |f: f64| f.sqrt();
            let fwd = |f: f64| {
                2.0 * (-(1.0 + a * t(f) * t(f)).sqrt() / t(f)
                    + a.sqrt() * (a.sqrt() * t(f)).asinh())
            };
            0.5 * k * (fwd(f2) - fwd(f1))
        }
    }

    /// The split conserves the mirror's reflected power: a reflection is
    /// scattered with probability 1 − exp(−TIS), specular otherwise, and the
    /// two fractions add up to 1 (here checked against the draws' frequency).
    #[test]
    fn specular_and_scattered_add_up() {
        let r = llnl_like();
        let (e, theta) = (3.0, 0.4f64.to_radians());
        let tis = r.tis(e, theta);
        assert!(tis > 0.01 && tis < 0.5, "{tis}");
        let mut rng = crate::random::PhotonRng::new(3, 0);
        let n = 200_000;
        let scattered = (0..n)
            .filter(|_| {
                matches!(
                    r.draw(e, theta, rng.uniform(), rng.uniform()),
                    Scatter::Scattered { .. }
                )
            })
            .count() as f64
            / n as f64;
        let p = 1.0 - (-tis).exp();
        assert!((scattered - p).abs() < 5.0 * (p * (1.0 - p) / n as f64).sqrt());
    }
}
