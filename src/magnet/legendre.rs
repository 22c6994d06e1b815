//! The conversion amplitude of one path at many (q, Γ) at once, by the path
//! field's Legendre moments: the campaign's fast P (thousands of gas settings
//! and masses per photon, where [`super::conversion::PathField::probability`]
//! would make a 201-sample pass for each).
//!
//! With s = L(1 + t)/2 on the path and x = κL/2, κ = Γ/2 + iq, the plane-wave
//! expansion e^{xt} = Σₙ (2n+1) iₙ(x) Pₙ(t) (iₙ the modified spherical Bessel
//! functions of the first kind; DLMF 10.60.7 with x → ix) turns the amplitude
//! into a sum over the field's moments μₙ = ∫₋₁¹ B⊥(t) Pₙ(t) dt:
//!
//!   ∫₀ᴸ B⊥ e^{κs} ds = (L/2) eˣ Σₙ (2n+1) iₙ(x) μₙ.
//!
//! The moments are the path's, computed once per photon exactly for B⊥
//! linear between samples (the field `PathField` describes); the Bessel
//! values are each (q, Γ)'s, by Miller's backward recurrence
//! i_{n−1} = (2n+1)/x · iₙ + i_{n+1} (stable downwards for every x: iₙ is the
//! minimal solution), normalised by Σₙ (2n+1) iₙ(x) = eˣ (the expansion at
//! t = 1). Then |eˣ| cancels against the attenuation e^{−ΓL/2}:
//!
//!   P = (gL/4)² Σ_c |Σₙ (2n+1) fₙ μₙ,c|² / |Σₙ (2n+1) fₙ|²
//!
//! for the unnormalised recurrence values fₙ, with no exponential at all. The
//! sum ends past n = |x| by a few widths of the Airy transition there,
//! N = |x| + 6 |x|^⅓ + 10 (for |x| < 1, where iₙ ≈ xⁿ/(2n+1)!!, at the first
//! n with that term below 1e-14): P to 1e-10 of itself (tested against the
//! sample pass), and a campaign's typical |x| ≲ 30 needs ≲ 60 terms against
//! the path's 201 samples.
//!
//! Data flow: `campaign::Campaign::factors` takes [`Moments::of`] each
//! recorded photon's path field once and [`Moments::probability`] per (setting,
//! mass); beyond [`LARGEST_X`] it falls back to the sample pass.

use super::conversion::{uniform_probability, PathField};
use super::ConversionPath;
use num_complex::Complex64;

/// The largest |x| = |κ|L/2 the moments serve: beyond it the recurrence
/// needs as many terms as the path has samples, and the sample pass is as
/// fast.
pub const LARGEST_X: f64 = 120.0;

/// Below this |x| the n = 0 term alone is P to 1e-12: iₙ(x) ∝ xⁿ.
const SMALLEST_X: f64 = 1e-12;

/// The terms of the sum at |x| (see the module header).
pub fn terms(x: f64) -> usize {
    if x >= 1.0 {
        return (x + 6.0 * x.cbrt() + 10.0).ceil() as usize;
    }
    // iₙ(x) ≈ xⁿ/(2n+1)!!: the first n where that is below 1e-14.
    let (mut n, mut term) = (0usize, 1.0f64);
    while term >= 1e-14 {
        n += 1;
        term *= x / (2 * n + 1) as f64;
    }
    n.max(2)
}

/// [`terms`] at the next whole |x| up (it grows with |x|), from a table:
/// the recurrence asks for it per (q, Γ), and a cube root each costs more
/// than a tenth of the recurrence.
fn terms_fast(x: f64) -> usize {
    static TABLE: std::sync::OnceLock<Vec<usize>> = std::sync::OnceLock::new();
    let table = TABLE.get_or_init(|| {
        (0..=LARGEST_X as usize + 1)
            .map(|k| terms((k as f64).max(1e-3)))
            .collect()
    });
    match x < 1e-3 {
        true => terms(x),
        false => table[(x.ceil() as usize).min(table.len() - 1)],
    }
}

/// A path's field moments μₙ (both transverse components, eV²), n = 0 … N,
/// and its length L (eV⁻¹).
#[derive(Clone, Debug, Default)]
pub struct Moments {
    mu: Vec<[f64; 2]>,
    length: f64,
    /// Pₙ and Qₙ at a group of nodes (kept to save allocations a photon).
    legendre: Vec<[f64; 4]>,
    integrated: Vec<[f64; 4]>,
}

impl Moments {
    /// The moments of `field` up to the terms |x| = `largest_x` needs (at
    /// most [`LARGEST_X`]'s), into
    /// `self` (its buffers reused). For B linear between the nodes t_k,
    /// integrating by parts twice, μₙ = 2 b(1) δₙ₀ − Σ_k d_k Rₙ(t_k): d_k the
    /// jump of B's slope at node k (the slopes taken 0 outside the path) and
    /// Rₙ(t) = ∫₋₁ᵗ ∫₋₁ᵘ Pₙ, from Qₙ = ∫₋₁ᵗ Pₙ = (P_{n+1} − P_{n−1})/(2n+1)
    /// and Rₙ = (Q_{n+1} − Q_{n−1})/(2n+1) (Q₀ = t + 1, R₀ = (t + 1)²/2).
    pub fn of(&mut self, field: &PathField, largest_x: f64) {
        let top = terms_fast(largest_x.min(LARGEST_X));
        let samples = &field.samples;
        self.length = field.length();
        self.mu.clear();
        self.mu.resize(top + 1, [0.0; 2]);
        let nodes = samples.len();
        if nodes < 2 {
            return;
        }
        let dt = 2.0 / (nodes - 1) as f64;
        let slope = |k: usize, c: usize| match k {
            k if k + 1 < nodes => (samples[k + 1][c] - samples[k][c]) / dt,
            _ => 0.0,
        };
        // The nodes where the slope turns, NODES at a time: each node's
        // Legendre recurrence is a chain, and side by side they run at the
        // CPU's width.
        const NODES: usize = 4;
        let kinks = (1..nodes)
            .map(|k| (k, [0, 1].map(|c| slope(k - 1, c) - slope(k, c))))
            .filter(|(_, d)| *d != [0.0, 0.0]);
        let (p, q) = (&mut self.legendre, &mut self.integrated);
        p.resize(top + 3, [0.0; NODES]);
        q.resize(top + 2, [0.0; NODES]);
        let mut group = Vec::with_capacity(NODES);
        let mut kinks = kinks.peekable();
        while kinks.peek().is_some() {
            group.clear();
            group.extend(kinks.by_ref().take(NODES));
            // Padding nodes carry no kink.
            let t: [f64; NODES] = std::array::from_fn(|l| match group.get(l) {
                Some(&(k, _)) => -1.0 + k as f64 * dt,
                None => 0.0,
            });
            let d: [[f64; 2]; NODES] =
                std::array::from_fn(|l| group.get(l).map_or([0.0; 2], |g| g.1));
            legendre_values(&t, &mut p[..]);
            // Qₙ for n = 0 … top + 1, then Rₙ from them.
            q[0] = t.map(|t| t + 1.0);
            for n in 1..top + 2 {
                q[n] = std::array::from_fn(|l| (p[n + 1][l] - p[n - 1][l]) * inv_odd(n));
            }
            for l in 0..NODES {
                let r0 = 0.5 * (t[l] + 1.0) * (t[l] + 1.0);
                self.mu[0][0] -= d[l][0] * r0;
                self.mu[0][1] -= d[l][1] * r0;
            }
            for n in 1..=top {
                let (mut mx, mut my) = (0.0, 0.0);
                for l in 0..NODES {
                    let r = (q[n + 1][l] - q[n - 1][l]) * inv_odd(n);
                    mx += d[l][0] * r;
                    my += d[l][1] * r;
                }
                self.mu[n][0] -= mx;
                self.mu[n][1] -= my;
            }
        }
        let last = samples[nodes - 1];
        self.mu[0][0] += 2.0 * last[0];
        self.mu[0][1] += 2.0 * last[1];
    }

    /// P at coupling `g` (eV⁻¹), momentum transfer `q` and attenuation
    /// `gamma` (eV), or `None` where |x| > [`LARGEST_X`] or the moments
    /// stop short of its terms (the sample pass answers there).
    pub fn probability(&self, g: f64, q: f64, gamma: f64) -> Option<f64> {
        let mut one = [q];
        self.probabilities_in_place::<1>(g, gamma, &mut one)
            .then_some(one[0])
    }

    /// P at each momentum transfer of `q` (replaced by its P), one
    /// attenuation for all, `LANES` recurrences side by side (each a chain of
    /// dependent complex products: independent chains fill the CPU's
    /// pipelines). Returns false, leaving `q` as it was, where any |x| is
    /// beyond the moments.
    pub fn probabilities_in_place<const LANES: usize>(
        &self,
        g: f64,
        gamma: f64,
        q: &mut [f64; LANES],
    ) -> bool {
        let x: [Complex64; LANES] =
            std::array::from_fn(|l| Complex64::new(0.25 * gamma, 0.5 * q[l]) * self.length);
        let size: [f64; LANES] = std::array::from_fn(|l| x[l].norm_sqr().sqrt());
        let largest = size.iter().fold(0.0f64, |a, &b| a.max(b));
        if largest > LARGEST_X || size.iter().any(|s| s.is_nan()) {
            return false;
        }
        let tops: [usize; LANES] = std::array::from_fn(|l| terms_fast(size[l]));
        let n_top = tops.iter().copied().max().unwrap_or(0);
        let input = *q;
        if n_top >= self.mu.len() {
            return false;
        }
        let scale = 0.25 * g * self.length;
        let zero = Complex64::new(0.0, 0.0);
        // Below SMALLEST_X the n = 0 term alone (x⁻¹ would overflow).
        let r: [Complex64; LANES] = std::array::from_fn(|l| {
            if size[l] < SMALLEST_X {
                zero
            } else {
                x[l].inv()
            }
        });
        // Each lane from its own N: f_{N+1} = 0, f_N small (the values grow
        // downwards by ≲ 1e40 from there; from a longer lane's N, a tiny |x|
        // would overflow).
        let seed = Complex64::new(1e-30, 0.0);
        let mut above = [zero; LANES];
        let mut f = [zero; LANES];
        let (mut norm, mut sx, mut sy) = ([zero; LANES], [zero; LANES], [zero; LANES]);
        for n in (0..=n_top).rev() {
            let w = (2 * n + 1) as f64;
            let [mx, my] = self.mu[n];
            for l in 0..LANES {
                if n == tops[l] {
                    f[l] = seed;
                }
                let wf = f[l] * w;
                norm[l] += wf;
                sx[l] += wf * mx;
                sy[l] += wf * my;
                let below = r[l] * wf + above[l];
                (above[l], f[l]) = (f[l], below);
            }
        }
        for l in 0..LANES {
            q[l] = match size[l] < SMALLEST_X {
                true => {
                    let [bx, by] = self.mu[0];
                    scale * scale * (bx * bx + by * by)
                }
                false => {
                    scale * scale * ((sx[l] / norm[l]).norm_sqr() + (sy[l] / norm[l]).norm_sqr())
                }
            };
        }
        // Never a number it did not compute: the caller's sample pass
        // answers a block with any lane not finite.
        if !q.iter().all(|p| p.is_finite()) {
            *q = input;
            return false;
        }
        true
    }
}

/// P at each momentum transfer of `q` (replaced by its P) on `path` at
/// coupling `g` (eV⁻¹): `runs` the ranges of `q` that share an attenuation
/// Γ (eV), `largest_x` the largest |x| among them. A map's path by its
/// moments, four transfers at a time (the sample pass only where the phase
/// turns too fast for them); a uniform field by the closed form.
pub fn run_probabilities(
    path: &ConversionPath,
    g: f64,
    (runs, largest_x): (&[(std::ops::Range<usize>, f64)], f64),
    q: &mut [f64],
) {
    match path {
        ConversionPath::Uniform { b_ev2, length } => {
            for (range, gamma) in runs {
                for q in &mut q[range.clone()] {
                    *q = uniform_probability(g, *b_ev2, *length, *q, *gamma);
                }
            }
        }
        ConversionPath::Sampled(field) => {
            let mut moments = Moments::default();
            moments.of(field, largest_x);
            for (range, gamma) in runs {
                let gamma = *gamma;
                let mut blocks = q[range.clone()].chunks_exact_mut(4);
                for block in &mut blocks {
                    let block: &mut [f64; 4] = block.try_into().expect("a block of 4");
                    if !moments.probabilities_in_place(g, gamma, block) {
                        block
                            .iter_mut()
                            .for_each(|q| *q = field.probability(g, *q, gamma));
                    }
                }
                for q in blocks.into_remainder() {
                    *q = moments
                        .probability(g, *q, gamma)
                        .unwrap_or_else(|| field.probability(g, *q, gamma));
                }
            }
        }
    }
}

/// 1/(2n+1), from a table (a division costs as much as ten products).
#[inline]
fn inv_odd(n: usize) -> f64 {
    static TABLE: std::sync::OnceLock<Vec<f64>> = std::sync::OnceLock::new();
    let table = TABLE.get_or_init(|| (0..512).map(|n| 1.0 / (2 * n + 1) as f64).collect());
    table
        .get(n)
        .copied()
        .unwrap_or_else(|| 1.0 / (2 * n + 1) as f64)
}

/// P₀(t) … P_{len−1}(t) at each of the nodes `t` into `p`, by Bonnet's
/// recurrence (n+1) P_{n+1} = (2n+1) t Pₙ − n P_{n−1}.
fn legendre_values<const NODES: usize>(t: &[f64; NODES], p: &mut [[f64; NODES]]) {
    p[0] = [1.0; NODES];
    if p.len() > 1 {
        p[1] = *t;
    }
    for n in 1..p.len() - 1 {
        // (2n+1)/(n+1) = 1 + b, b = n/(n+1).
        let b = bonnet(n);
        p[n + 1] = std::array::from_fn(|l| (1.0 + b) * t[l] * p[n][l] - b * p[n - 1][l]);
    }
}

/// n/(n+1), from a table (the recurrence would divide at every step).
#[inline]
fn bonnet(n: usize) -> f64 {
    static TABLE: std::sync::OnceLock<Vec<f64>> = std::sync::OnceLock::new();
    let table = TABLE.get_or_init(|| (0..512).map(|n| n as f64 / (n + 1) as f64).collect());
    table
        .get(n)
        .copied()
        .unwrap_or_else(|| n as f64 / (n + 1) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A path field of `n` samples of a smooth field with sharp fringes
    /// (like a magnet's ends) and a second component, over `length` eV⁻¹.
    fn fringed(n: usize, length: f64) -> PathField {
        let samples = (0..n)
            .map(|k| {
                let u = k as f64 / (n - 1) as f64;
                let ends =
                    1.0 / (1.0 + (-(u - 0.05) * 80.0).exp()) / (1.0 + ((u - 0.93) * 120.0).exp());
                [1e3 * ends * (1.0 + 0.2 * u), 150.0 * (6.0 * u).sin() * ends]
            })
            .collect();
        PathField {
            step: length / (n - 1) as f64,
            samples,
        }
    }

    /// The moments give the sample pass's P (exact for the same piecewise
    /// linear field) to 1e-9 of the largest P over |x| from 0 to the
    /// largest served, in vacuum and strong attenuation.
    #[test]
    fn the_moments_give_the_sample_pass() {
        let field = fringed(201, 5.07e7);
        let mut m = Moments::default();
        m.of(&field, LARGEST_X);
        let l = field.length();
        let g = 1e-19;
        let top = field.probability(g, 0.0, 0.0);
        let (mut worst, mut relative): (f64, f64) = (0.0, 0.0);
        for &x_re in &[0.0, 0.3, 3.0, 20.0] {
            for k in 0..400 {
                let x_im = if k == 0 { 0.0 } else { 1e-14 * 1.1f64.powi(k) };
                if x_im > LARGEST_X * 0.99 {
                    break;
                }
                let (q, gamma) = (2.0 * x_im / l, 4.0 * x_re / l);
                let fast = m.probability(g, q, gamma).unwrap();
                let exact = field.probability(g, q, gamma);
                worst = worst.max((fast - exact).abs() / top);
                if exact > 1e-10 * top {
                    relative = relative.max((fast / exact - 1.0).abs());
                }
            }
        }
        assert!(worst < 1e-9, "worst {worst:e} of the largest P");
        // And each P to 1e-9 of itself down to 1e-10 of the largest.
        assert!(relative < 1e-9, "worst {relative:e} of itself");
        // Beyond the largest |x| the moments decline to answer.
        assert!(m.probability(g, 2.0 * (LARGEST_X + 1.0) / l, 0.0).is_none());
    }

    /// A uniform field's moments are 2B, 0, 0 …: P is the closed form.
    #[test]
    fn a_uniform_field_gives_the_closed_form() {
        let (b, l) = (1e3, 5.07e7);
        let field = PathField {
            step: l / 50.0,
            samples: vec![[b, 0.0]; 51],
        };
        let mut m = Moments::default();
        m.of(&field, LARGEST_X);
        for &(q, gamma) in &[(1e-8, 0.0), (3e-7, 1e-8), (1e-6, 0.0), (2e-9, 2e-7)] {
            let closed = super::super::conversion::uniform_probability(1e-19, b, l, q, gamma);
            let fast = m.probability(1e-19, q, gamma).unwrap();
            assert!(
                (fast / closed - 1.0).abs() < 1e-9,
                "{q} {gamma}: {fast} {closed}"
            );
        }
    }

    /// A block whose lanes need very different terms (a tiny |x| beside
    /// large ones, where a shared start would overflow) gives each lane its
    /// own P; a NaN attenuation is declined, not answered.
    #[test]
    fn a_block_of_mixed_transfers_is_each_lanes_own() {
        let field = fringed(201, 5.07e7);
        let mut m = Moments::default();
        m.of(&field, LARGEST_X);
        let l = field.length();
        let g = 1e-19;
        let top = field.probability(g, 0.0, 0.0);
        for gamma in [0.0, 1.0 / l] {
            let x = [3e-12, 80.0, 2e-5, 0.7];
            let mut block = x.map(|x| 2.0 * x / l);
            assert!(m.probabilities_in_place(g, gamma, &mut block));
            for (k, &x) in x.iter().enumerate() {
                let exact = field.probability(g, 2.0 * x / l, gamma);
                assert!(
                    (block[k] - exact).abs() < 1e-9 * top,
                    "lane {k}: {} vs {exact}",
                    block[k]
                );
            }
        }
        let mut block = [1e-7; 4];
        assert!(!m.probabilities_in_place(g, f64::NAN, &mut block));
        assert_eq!(block, [1e-7; 4], "a declined block is left as it was");
    }
}
