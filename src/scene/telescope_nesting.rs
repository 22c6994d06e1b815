//! How a prescription's shells sit together: listed innermost first, none
//! twice, no wall reaching through the next shell's mirror, no shell whose
//! whole aperture the inner shell's wall covers. A prescription is a list of
//! numbers typed by hand or converted from another tool's table, and each of
//! these mistakes traces without a word otherwise: shells listed outermost
//! first put the central stop and the spider's inner radius on the outermost
//! shell (−64 % flux in a trial), a duplicated shell counts its area twice.
//!
//! Data flow: `Telescope::validate` calls [`Telescope::check_nesting`] after
//! each shell's own checks; `scene::assemblies` reports
//! [`Telescope::nesting_warnings`] (a partly shadowed aperture, which real
//! designs have by a few µm) with the scene's other warnings.

use super::telescope::{Profile, Telescope};
use crate::text::number;

/// Two shells whose front mirrors start within this radius (mm) of each other
/// are the same shell listed twice: no real nested optic packs shells closer
/// than a wall's thickness (tenths of a mm).
const SAME_SHELL_MM: f64 = 1e-6;

/// Points along each mirror where adjacent shells are compared.
const SAMPLES: usize = 64;

/// A shadowed share of a shell's on-axis aperture above which a warning is
/// given: LLNL's inner walls cover 0.06 % of the next aperture, XMM's none.
const SHADOW_WARNING: f64 = 0.1;

/// One mirror's reflecting face and the back of its wall between two heights.
struct Face {
    z: [f64; 2],
    /// Radius of the reflecting face at height z.
    surface: Box<dyn Fn(f64) -> f64>,
    /// Radius of the wall's back at height z (the cone through the ends'
    /// backs, as the traced back is).
    back: Box<dyn Fn(f64) -> f64>,
}

impl Telescope {
    /// Refuses shells out of order, listed twice, or intersecting, naming
    /// them. Needs each shell validated.
    pub(super) fn check_nesting(&self) -> Result<(), String> {
        let key: Vec<f64> = (0..self.shells.len())
            .map(|i| self.front_inner_radius(i))
            .collect();
        let mut order: Vec<usize> = (0..key.len()).collect();
        order.sort_by(|&a, &b| key[a].total_cmp(&key[b]));
        for w in order.windows(2) {
            let (a, b) = (w[0].min(w[1]), w[0].max(w[1]));
            if (key[a] - key[b]).abs() < SAME_SHELL_MM {
                return Err(format!(
                    "shells {} and {} are the same shell (both start their front mirror at r = {} mm): a shell listed twice counts its area twice; remove one",
                    a + 1,
                    b + 1,
                    number(key[a])
                ));
            }
        }
        if let Some(i) = (1..key.len()).find(|&i| key[i] < key[i - 1]) {
            let reversed = (1..key.len()).all(|i| key[i] < key[i - 1]);
            return Err(format!(
                "shells must be listed innermost first, and shell {} (front mirror from r = {} mm) lies inside shell {} (r = {} mm){}: traxer numbers shells from the axis outwards, and the central stop and the spider's inner radius follow from shell 1",
                i + 1,
                number(key[i]),
                i,
                number(key[i - 1]),
                if reversed { "; the list runs outermost first: reverse it" } else { "" }
            ));
        }
        for i in 1..key.len() {
            for (inner, outer, which) in [
                (self.front_face(i - 1), self.front_face(i), "front"),
                (self.rear_face(i - 1), self.rear_face(i), "rear"),
            ] {
                let lo = inner.z[0].max(outer.z[0]);
                let hi = inner.z[1].min(outer.z[1]);
                for k in 0..=SAMPLES {
                    let z = lo + (hi - lo) * k as f64 / SAMPLES as f64;
                    let (back, mirror) = ((inner.back)(z), (outer.surface)(z));
                    if back >= mirror {
                        return Err(format!(
                            "shells {i} and {} intersect: at z = {} mm shell {i}'s {which} wall reaches r = {} mm, through shell {}'s {which} mirror at r = {} mm (check the radii and the wall thickness)",
                            i + 1,
                            round(z),
                            round(back),
                            i + 1,
                            round(mirror)
                        ));
                    }
                }
            }
            let shadow = self.shadowed_aperture(i);
            if shadow >= 1.0 {
                return Err(format!(
                    "shell {}'s front mirror receives no on-axis X-rays: shell {i}'s wall at the entrance (out to r = {} mm) covers its whole aperture (r = {} – {} mm)",
                    i + 1,
                    round(self.entrance_wall(i - 1)),
                    round((self.front_face(i).surface)(self.front_face(i).z[0])),
                    round((self.front_face(i).surface)(self.front_face(i).z[1])),
                ));
            }
        }
        Ok(())
    }

    /// What is legal but probably not meant: a shell whose on-axis aperture
    /// the inner shell's wall shadows by more than a tenth.
    pub fn nesting_warnings(&self) -> Vec<String> {
        (1..self.shells.len())
            .filter_map(|i| {
                let s = self.shadowed_aperture(i);
                (s > SHADOW_WARNING).then(|| {
                    format!(
                        "shell {i}'s wall at the entrance shadows {:.0} % of shell {}'s on-axis aperture (is its thickness or R1 right?)",
                        100.0 * s,
                        i + 1
                    )
                })
            })
            .collect()
    }

    /// The share of shell i's on-axis aperture (the annulus its front mirror
    /// spans, by area) behind shell i − 1's wall end at the entrance.
    fn shadowed_aperture(&self, i: usize) -> f64 {
        let f = self.front_face(i);
        let (r_lo, r_hi) = ((f.surface)(f.z[0]), (f.surface)(f.z[1]));
        let wall = self.entrance_wall(i - 1).clamp(r_lo, r_hi);
        (wall * wall - r_lo * r_lo) / (r_hi * r_hi - r_lo * r_lo)
    }

    /// The outer radius of shell i's wall at the entrance (mm).
    fn entrance_wall(&self, i: usize) -> f64 {
        let f = self.front_face(i);
        (f.back)(f.z[1])
    }

    /// Shell i's front mirror, from the intersection-plane side (z[0]) to the
    /// entrance (z[1]).
    fn front_face(&self, i: usize) -> Face {
        let z0 = 0.5 * self.gap_mm;
        let t = self.thickness(i);
        match self.profile {
            Profile::Cone => {
                let [r1, r2, _, _] = self.cone_radii(i);
                let a = self.alpha(i);
                cone_face([z0, z0 + self.length(i) * a.cos()], [r2, r1], t / a.cos())
            }
            Profile::Wolter1 => {
                let w = self.wolter(i);
                let z = [z0, z0 + self.length(i)];
                let back = z.map(|z| w.paraboloid_radius(z) + t * w.paraboloid_slope(z).hypot(1.0));
                Face {
                    z,
                    surface: Box::new(move |z| w.paraboloid_radius(z)),
                    back: linear(z, back),
                }
            }
        }
    }

    /// Shell i's rear mirror, from its far end (z[0], towards the focus) to
    /// the intersection-plane side (z[1]).
    fn rear_face(&self, i: usize) -> Face {
        let z0 = 0.5 * self.gap_mm;
        let t = self.thickness(i);
        match self.profile {
            Profile::Cone => {
                let [_, _, r4, r5] = self.cone_radii(i);
                let a = self.alpha_rear(i);
                cone_face([-z0 - self.length(i) * a.cos(), -z0], [r5, r4], t / a.cos())
            }
            Profile::Wolter1 => {
                let w = self.wolter(i);
                let z = [-z0 - self.length(i), -z0];
                let back =
                    z.map(|z| w.hyperboloid_radius(z) + t * w.hyperboloid_slope(z).hypot(1.0));
                Face {
                    z,
                    surface: Box::new(move |z| w.hyperboloid_radius(z)),
                    back: linear(z, back),
                }
            }
        }
    }
}

/// A cone from radius r[0] at z[0] to r[1] at z[1], its wall `dr` thick
/// radially.
fn cone_face(z: [f64; 2], r: [f64; 2], dr: f64) -> Face {
    Face {
        z,
        surface: linear(z, r),
        back: linear(z, r.map(|r| r + dr)),
    }
}

/// The straight line through (z[0], v[0]) and (z[1], v[1]).
fn linear(z: [f64; 2], v: [f64; 2]) -> Box<dyn Fn(f64) -> f64> {
    Box::new(move |x| v[0] + (v[1] - v[0]) * (x - z[0]) / (z[1] - z[0]))
}

/// A length in mm for a message: to the µm.
fn round(x: f64) -> String {
    number((x * 1e3).round() / 1e3)
}
