//! Reflectivity of a layered mirror: exact Fresnel coefficients for s and p
//! polarisation at each interface, combined from the substrate upwards by the
//! Parratt recursion, with optional Névot–Croce interface roughness.
//!
//! Conventions: medium 0 is vacuum; layers 1 … N from the top; the substrate is
//! semi-infinite. q_j = √(n_j² − cos²θ) is the normal wave-vector component in units
//! of k = 2π/λ (principal root: Im q ≥ 0, the wave decays into the material).

use crate::constants::HC_KEV_NM;
use num_complex::Complex64;

/// One layer: susceptibility-like χ = n − 1 = −δ + iβ (kept instead of n, because
/// 1 − δ rounds away most digits of δ ~ 1e-5), thickness, and the RMS roughness of
/// its top interface.
#[derive(Clone, Copy, Debug)]
pub struct Layer {
    pub chi: Complex64,
    pub thickness_nm: f64,
    pub roughness_nm: f64,
}

/// Reflected intensity for s and p polarisation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reflectance {
    pub s: f64,
    pub p: f64,
}

impl Reflectance {
    /// Unpolarised: (R_s + R_p) / 2.
    pub fn unpolarised(&self) -> f64 {
        0.5 * (self.s + self.p)
    }
}

/// Reflectance at grazing angle `theta_rad` and energy `energy_kev` of `layers`
/// (top first) on a substrate with χ = n − 1 = `substrate` whose top interface has
/// RMS roughness `substrate_roughness_nm`.
pub fn reflectance(
    energy_kev: f64,
    theta_rad: f64,
    layers: &[Layer],
    substrate: Complex64,
    substrate_roughness_nm: f64,
) -> Reflectance {
    let k = 2.0 * std::f64::consts::PI * energy_kev / HC_KEV_NM; // 1/nm
    let sin2 = theta_rad.sin().powi(2);
    // n² − cos²θ = (n² − 1) + sin²θ = χ(2 + χ) + sin²θ: no cancellation at grazing
    // angles, where n² and cos²θ agree to 5 digits.
    let q = |chi: Complex64| principal_sqrt(chi * (chi + 2.0) + sin2);
    let n2 = |chi: Complex64| chi * (chi + 2.0) + 1.0;
    let one = Complex64::new(1.0, 0.0);
    let zero = Complex64::new(0.0, 0.0);
    // Névot–Croce: r · exp(−2 k² q_a q_b σ²).
    let rough = |qa: Complex64, qb: Complex64, sigma: f64| {
        if sigma > 0.0 {
            (-2.0 * k * k * sigma * sigma * qa * qb).exp()
        } else {
            one
        }
    };
    let mut rs = Complex64::new(0.0, 0.0);
    let mut rp = Complex64::new(0.0, 0.0);
    // Walk interfaces from the bottom (last layer / substrate) to the top
    // (vacuum / first layer). `below` is the medium under the current interface.
    // A multilayer repeats a few materials and interfaces: q of each material
    // and the Fresnel coefficients of each kind of interface (materials above
    // and below, roughness) are computed once per call and looked up after
    // that: the very same numbers, fewer square roots, exponentials and
    // divisions.
    let mut q_seen = Recent::<Complex64, Complex64>::default();
    let mut q_of = |chi: Complex64| q_seen.get_or(chi, || q(chi));
    let mut fresnel_seen = Recent::<(Complex64, Complex64, f64), (Complex64, Complex64)>::default();
    let (mut chi_below, mut q_below) = (substrate, q_of(substrate));
    let mut sigma = substrate_roughness_nm;
    let mut first = true;
    for j in (0..=layers.len()).rev() {
        let chi_above = if j == 0 { zero } else { layers[j - 1].chi };
        let q_above = if j == 0 {
            Complex64::new(theta_rad.sin(), 0.0)
        } else {
            q_of(chi_above)
        };
        let fresnel = || {
            let f = rough(q_above, q_below, sigma);
            let fs = (q_above - q_below) / (q_above + q_below) * f;
            let (na2, nb2) = (n2(chi_above), n2(chi_below));
            let fp = (nb2 * q_above - na2 * q_below) / (nb2 * q_above + na2 * q_below) * f;
            (fs, fp)
        };
        // The top interface (vacuum above, q = sin θ) happens once.
        let (fs, fp) = if j == 0 {
            fresnel()
        } else {
            fresnel_seen.get_or((chi_above, chi_below, sigma), fresnel)
        };
        if first {
            rs = fs;
            rp = fp;
            first = false;
        } else {
            // Phase across the layer below this interface (layer j, 1-based).
            let d = layers[j].thickness_nm;
            let phase = (Complex64::new(0.0, 2.0 * k * d) * q_below).exp();
            rs = (fs + rs * phase) / (one + fs * rs * phase);
            rp = (fp + rp * phase) / (one + fp * rp * phase);
        }
        if j > 0 {
            chi_below = chi_above;
            q_below = q_above;
            sigma = layers[j - 1].roughness_nm;
        }
    }
    Reflectance {
        s: rs.norm_sqr(),
        p: rp.norm_sqr(),
    }
}

/// The principal square root (Re ≥ 0; Im of the sign of Im z) in algebraic form:
/// the same root as `Complex64::sqrt`, which goes through polar form (atan2,
/// hypot, sin and cos: most of the time of building a reflectivity table), to
/// within a few ulp. Stable for both signs of Re z: the root's larger component
/// comes from a sum without cancellation, the smaller one from Im z over it.
#[inline]
fn principal_sqrt(z: Complex64) -> Complex64 {
    let (x, y) = (z.re, z.im);
    if x == 0.0 && y == 0.0 {
        return Complex64::new(0.0, y);
    }
    // |z|: the components here lie between ~1e-12 and ~10, far from overflow.
    let t = (0.5 * ((x * x + y * y).sqrt() + x.abs())).sqrt();
    if x >= 0.0 {
        Complex64::new(t, y / (2.0 * t))
    } else {
        Complex64::new(y.abs() / (2.0 * t), t.copysign(y))
    }
}

/// The last few (key, value) pairs computed, compared bit for bit: a multilayer
/// has two or three materials and as many kinds of interface.
struct Recent<K, V> {
    entries: [Option<(K, V)>; 4],
    next: usize,
}

impl<K, V> Default for Recent<K, V> {
    fn default() -> Self {
        Recent {
            entries: [None, None, None, None],
            next: 0,
        }
    }
}

impl<K: SameBits + Copy, V: Copy> Recent<K, V> {
    #[inline]
    fn get_or(&mut self, key: K, compute: impl FnOnce() -> V) -> V {
        for (k, v) in self.entries.iter().flatten() {
            if k.same_bits(&key) {
                return *v;
            }
        }
        let v = compute();
        self.entries[self.next] = Some((key, v));
        self.next = (self.next + 1) % self.entries.len();
        v
    }
}

/// Equality of the bits (so that a cached value is exactly what computing it
/// again would give; NaN-safe).
trait SameBits {
    fn same_bits(&self, other: &Self) -> bool;
}

impl SameBits for Complex64 {
    fn same_bits(&self, o: &Self) -> bool {
        self.re.to_bits() == o.re.to_bits() && self.im.to_bits() == o.im.to_bits()
    }
}

impl SameBits for (Complex64, Complex64, f64) {
    fn same_bits(&self, o: &Self) -> bool {
        self.0.same_bits(&o.0) && self.1.same_bits(&o.1) && self.2.to_bits() == o.2.to_bits()
    }
}
