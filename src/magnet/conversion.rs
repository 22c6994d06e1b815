//! The axion–photon conversion probability in a magnetic field, in natural
//! units (ħ = c = 1; energies and masses in eV, lengths in eV⁻¹, fields in eV²,
//! the coupling in eV⁻¹): pure physics, no scene.
//!
//! An axion of energy E crossing a transverse field B⊥(s) over a path of
//! length L converts into a photon with the amplitude
//!
//!   A = (g/2) ∫₀ᴸ B⊥(s) e^{iqs} e^{−Γ(L−s)/2} ds,   q = |m_a² − m_γ²| / 2E,
//!
//! a two-vector along the transverse field (P = |A_x|² + |A_y|²), where m_γ
//! is the photon's effective mass in a buffer gas and Γ the gas's X-ray
//! attenuation (the photon made at s is attenuated over the rest of the path).
//! For a uniform field it is the closed form of van Bibber et al., Phys. Rev.
//! D 39, 2089 (1989):
//!
//!   P = (gB/2)² [1 + e^{−ΓL} − 2 e^{−ΓL/2} cos qL] / (q² + Γ²/4),
//!
//! which is (gBL/2)² in vacuum at q → 0 and (gBL/2)² sinc²(qL/2) without gas.
//!
//! Data flow: `magnet` samples B⊥ along each photon's path ([`PathField`]) and
//! asks [`PathField::probability`] for each axion mass.

use num_complex::Complex64;

/// The momentum transfer q = |m_a² − m_γ²| / 2E (eV), from the axion mass
/// (eV), the photon's effective mass squared (eV²) and the energy (eV).
pub fn momentum_transfer(axion_mass_ev: f64, photon_mass2_ev2: f64, energy_ev: f64) -> f64 {
    (axion_mass_ev * axion_mass_ev - photon_mass2_ev2).abs() / (2.0 * energy_ev)
}

/// The closed form for a uniform transverse field `b_ev2` over `length` (eV⁻¹)
/// with momentum transfer `q` and attenuation `gamma` (eV), coupling `g`
/// (eV⁻¹). Written without cancellation: the bracket is
/// (1 − e^{−ΓL/2})² + 4 e^{−ΓL/2} sin²(qL/2), each term computed directly.
pub fn uniform_probability(g: f64, b_ev2: f64, length: f64, q: f64, gamma: f64) -> f64 {
    let amplitude = 0.5 * g * b_ev2;
    let half_absorbed = (-0.5 * gamma * length).exp();
    let denominator = q * q + 0.25 * gamma * gamma;
    if denominator == 0.0 {
        return (amplitude * length).powi(2);
    }
    let lost = (-0.5 * gamma * length).exp_m1();
    let sine = (0.5 * q * length).sin();
    amplitude * amplitude * (lost * lost + 4.0 * half_absorbed * sine * sine) / denominator
}

/// The transverse field along one path, sampled at `samples.len()` equally
/// spaced points s_k = k h from the path's start (k = 0 … N): the two
/// components of B⊥ (eV²) on two fixed axes perpendicular to the path.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PathField {
    /// The spacing h (eV⁻¹).
    pub step: f64,
    pub samples: Vec<[f64; 2]>,
}

impl PathField {
    /// The path's length L = N h (eV⁻¹).
    pub fn length(&self) -> f64 {
        self.step * self.samples.len().saturating_sub(1) as f64
    }

    /// P for coupling `g` (eV⁻¹), momentum transfer `q` and attenuation
    /// `gamma` (eV). B⊥ is taken linear between samples and the integral of
    /// each piece times e^{iqs} e^{−Γ(L−s)/2} is done exactly (Filon's
    /// method): exact for a field linear along the path — a uniform field, or
    /// a trilinearly interpolated map sampled at its node planes along the
    /// axis — and free of aliasing however fast the phase turns (a heavy axion).
    ///
    /// The sum over pieces is one Horner pass per component: with
    /// ζ = e^{−κh}, κ = Γ/2 + iq, the piece starting at s_j = jh carries
    /// e^{κ s_j − ΓL/2} = e^{iqL} ζ^{N−j}, so with H = Σ_j ζ^{N−j} b_j
    /// (j = 0 … N) the amplitude is
    /// h e^{iqL} [w₀ (H − b_N) + w₁ ζ (H − ζᴺ b₀)]. |ζ| ≤ 1: the pass never
    /// grows, however strong the attenuation; e^{iqL} drops out of |A|².
    pub fn probability(&self, g: f64, q: f64, gamma: f64) -> f64 {
        if self.samples.len() < 2 {
            return 0.0;
        }
        let lane = self.lane(q, gamma);
        let (hx, hy) = split_horner(&self.samples, lane.zeta);
        self.finish(g, &lane, hx, hy)
    }

    /// [`PathField::probability`] at each momentum transfer of `q` (replaced
    /// by its P), one attenuation `gamma` for all: the values of one call
    /// each to rounding (one plain Horner pass per transfer, where a single
    /// call splits its pass in four). The Horner passes of `LANES` transfers run side by
    /// side over the samples: a pass is a chain of dependent complex
    /// products, and independent chains fill the CPU's pipelines (about
    /// three times the speed of one pass after another).
    pub fn probabilities_in_place(&self, g: f64, gamma: f64, q: &mut [f64]) {
        const LANES: usize = 8;
        if self.samples.len() < 2 {
            q.fill(0.0);
            return;
        }
        let mut blocks = q.chunks_exact_mut(LANES);
        for block in &mut blocks {
            let lanes: [Lane; LANES] = std::array::from_fn(|l| self.lane(block[l], gamma));
            // Real and imaginary parts apart (the compiler's vectors take
            // them so), the operations of Complex64's product and sum.
            let zr: [f64; LANES] = std::array::from_fn(|l| lanes[l].zeta.re);
            let zi: [f64; LANES] = std::array::from_fn(|l| lanes[l].zeta.im);
            let (mut xr, mut xi, mut yr, mut yi) =
                ([0.0; LANES], [0.0; LANES], [0.0; LANES], [0.0; LANES]);
            for b in &self.samples {
                for l in 0..LANES {
                    let (r, i) = (xr[l] * zr[l] - xi[l] * zi[l], xr[l] * zi[l] + xi[l] * zr[l]);
                    (xr[l], xi[l]) = (r + b[0], i);
                    let (r, i) = (yr[l] * zr[l] - yi[l] * zi[l], yr[l] * zi[l] + yi[l] * zr[l]);
                    (yr[l], yi[l]) = (r + b[1], i);
                }
            }
            for l in 0..LANES {
                let (hx, hy) = (Complex64::new(xr[l], xi[l]), Complex64::new(yr[l], yi[l]));
                block[l] = self.finish(g, &lanes[l], hx, hy);
            }
        }
        for q in blocks.into_remainder() {
            *q = self.probability(g, *q, gamma);
        }
    }

    /// The constants of one pass at momentum transfer `q` and attenuation
    /// `gamma`.
    fn lane(&self, q: f64, gamma: f64) -> Lane {
        let kappa = Complex64::new(0.5 * gamma, q);
        let (w0, w1) = filon_weights(kappa * self.step);
        Lane {
            w0,
            w1,
            zeta: (-kappa * self.step).exp(),
            zeta_n: (-kappa * self.length()).exp(),
        }
    }

    /// P from the two components' Horner sums `hx`, `hy` of a pass.
    fn finish(&self, g: f64, lane: &Lane, hx: Complex64, hy: Complex64) -> f64 {
        let (first, last) = (self.samples[0], self.samples[self.samples.len() - 1]);
        let amplitude = |hc: Complex64, b0: f64, bn: f64| {
            lane.w0 * (hc - bn) + lane.w1 * lane.zeta * (hc - lane.zeta_n * b0)
        };
        let ax = amplitude(hx, first[0], last[0]);
        let ay = amplitude(hy, first[1], last[1]);
        let scale = 0.5 * g * self.step;
        (ax.norm_sqr() + ay.norm_sqr()) * scale * scale
    }
}

/// H = Σ_j ζ^{N−j} b_j for each of the two components, as four interleaved
/// Horner chains in ζ⁴ (samples j ≡ r mod 4, the sequence padded in front
/// with zeros, which leave a Horner sum unchanged) joined by
/// H = ζ³H₀ + ζ²H₁ + ζH₂ + H₃. One chain of dependent complex products is
/// bound by their latency; four independent ones fill the pipelines (the one
/// pass of a photon at one mass runs about three times faster). The sum
/// differs from one chain's only by rounding.
fn split_horner(samples: &[[f64; 2]], zeta: Complex64) -> (Complex64, Complex64) {
    let z2 = zeta * zeta;
    let z4 = z2 * z2;
    let zero = Complex64::new(0.0, 0.0);
    let pad = (4 - samples.len() % 4) % 4;
    let mut h = [[zero; 2]; 4];
    let mut step = |r: usize, b: [f64; 2]| {
        h[r][0] = h[r][0] * z4 + b[0];
        h[r][1] = h[r][1] * z4 + b[1];
    };
    // The padded sequence's first block holds `pad` zeros, then the first
    // samples (none when no padding is needed).
    let head = if pad == 0 { 0 } else { 4 - pad };
    for (r, b) in (pad..4).zip(&samples[..head.min(samples.len())]) {
        step(r, *b);
    }
    for block in samples[head.min(samples.len())..].chunks_exact(4) {
        for (r, b) in block.iter().enumerate() {
            step(r, *b);
        }
    }
    let join = |c: usize| ((h[0][c] * zeta + h[1][c]) * zeta + h[2][c]) * zeta + h[3][c];
    (join(0), join(1))
}

/// One Horner pass's constants: the Filon weights, ζ = e^{−κh} and ζᴺ.
struct Lane {
    w0: Complex64,
    w1: Complex64,
    zeta: Complex64,
    zeta_n: Complex64,
}

/// The weights of f(0) and f(h) in ∫₀ʰ f(t) e^{κt} dt / h for f linear, as
/// functions of x = κh: w1 = ∫₀¹ u e^{xu} du = (e^x (x − 1) + 1)/x² and
/// w0 = (e^x − 1)/x − w1; by their series Σ xⁿ/(n!(n+2)) and Σ xⁿ/(n+1)! for
/// small |x|, where the closed forms cancel.
fn filon_weights(x: Complex64) -> (Complex64, Complex64) {
    let (e1, e2) = if x.norm() < 0.05 {
        let (mut e1, mut e2) = (Complex64::new(0.0, 0.0), Complex64::new(0.0, 0.0));
        let mut power = Complex64::new(1.0, 0.0); // xⁿ / n!
        for n in 0..8 {
            let nf = n as f64;
            e1 += power / (nf + 1.0);
            e2 += power / (nf + 2.0);
            power = power * x / (nf + 1.0);
        }
        (e1, e2)
    } else {
        let ex = x.exp();
        ((ex - 1.0) / x, (ex * (x - 1.0) + 1.0) / (x * x))
    };
    (e1 - e2, e2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_natural_units_follow_from_codata() {
        use crate::constants::*;
        let tesla = (HBAR_C_EV_M.powi(3) / (MU_0 * ELEMENTARY_CHARGE_C)).sqrt();
        assert!((TESLA_EV2 / tesla - 1.0).abs() < 1e-15);
        assert!((INV_EV_PER_METRE * HBAR_C_EV_M - 1.0).abs() < 1e-15);
        // ħc in eV·m is the keV·cm constant in other units.
        assert!((HBAR_C_EV_M / (HBAR_C_KEV_CM * 10.0) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn the_split_horner_pass_is_the_plain_one() {
        // Four chains in ζ⁴ against one in ζ, for every padding (lengths 2
        // to 13) and a ζ inside and on the unit circle: the same sum to
        // rounding (1e-13 of the terms' size; a wrong padding or join gives
        // errors of order 1).
        for zeta in [
            Complex64::from_polar(0.97, 0.3),
            Complex64::from_polar(1.0, 2.1),
        ] {
            for n in 2..14 {
                let samples: Vec<[f64; 2]> = (0..n)
                    .map(|k| [1.0 + 0.3 * (k as f64).sin(), -0.5 + 0.01 * (k * k) as f64])
                    .collect();
                let (mut px, mut py) = (Complex64::new(0.0, 0.0), Complex64::new(0.0, 0.0));
                for b in &samples {
                    px = px * zeta + b[0];
                    py = py * zeta + b[1];
                }
                let (sx, sy) = split_horner(&samples, zeta);
                let size: f64 = samples.iter().map(|b| b[0].abs() + b[1].abs()).sum();
                assert!((sx - px).norm() < 1e-13 * size, "n = {n}: {sx} vs {px}");
                assert!((sy - py).norm() < 1e-13 * size, "n = {n}: {sy} vs {py}");
            }
        }
    }

    #[test]
    fn the_weights_series_and_closed_forms_meet() {
        // Just above and below the switch the two evaluations agree.
        for x in [
            Complex64::new(0.0499, 0.0),
            Complex64::new(0.0, 0.0499),
            Complex64::new(0.03, 0.039),
        ] {
            let (a0, a1) = filon_weights(x);
            let y = x * (0.0501 / 0.0499);
            let ex = x.exp();
            let e1 = (ex - 1.0) / x;
            let e2 = (ex * (x - 1.0) + 1.0) / (x * x);
            assert!((a1 - e2).norm() < 1e-12 && (a0 - (e1 - e2)).norm() < 1e-12);
            let (b0, b1) = filon_weights(y);
            assert!((a0 - b0).norm() < 1e-3 && (a1 - b1).norm() < 1e-3);
        }
    }
}
