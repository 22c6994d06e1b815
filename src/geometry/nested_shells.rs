//! A nested telescope's shells found without a BVH. A Wolter or conical
//! telescope is a stack of surfaces of revolution about one axis; a ray in it
//! spans a small range of radii (grazing rays run nearly along the axis), so it
//! can meet only the few shells whose radii overlap that range. They are found
//! by a binary search over the shells sorted by radius and intersected exactly
//! (the same quadric code Embree calls back into), with no box traversal.
//!
//! Data flow: built from a scene's analytic objects ([`NestedShells::of`]) when
//! the scene is built; `scene::ShellSearch` asks it first and Embree (holding
//! the scene's other objects) for anything nearer, for every query of the
//! photon loop and the renders. `bench` answers the rays a trace asked both
//! ways and times them (docs/speed.md, "A nested-shell intersector": 2.3–2.6 ×
//! Embree's rate on XMM-Newton's and BabyIAXO's rays).

use super::{AnalyticObject, RevolutionQuadric, Shape, Surface};
use glam::DVec3;

/// Surfaces of revolution about the world z axis, sorted by smallest radius.
pub struct NestedShells {
    /// (object id, surface), by smallest radius.
    shells: Vec<(u32, RevolutionQuadric)>,
    r_min: Vec<f64>,
    r_max: Vec<f64>,
    /// Largest r_max among shells[..=i]: a downward walk stops once it is
    /// below the ray's smallest radius.
    r_max_so_far: Vec<f64>,
    z_lo: f64,
    z_hi: f64,
}

impl NestedShells {
    /// The surfaces of revolution placed by the identity (a telescope's shells
    /// sit in the world frame) among `objects` (id, object); `None` with fewer
    /// than two (nothing nested to find).
    pub fn of<'a>(
        objects: impl Iterator<Item = (u32, &'a AnalyticObject)>,
    ) -> Option<NestedShells> {
        let mut shells: Vec<(u32, RevolutionQuadric)> = objects
            .filter_map(|(id, o)| match o.shape {
                Shape::Revolution(q) if o.transform.is_identity() => Some((id, q)),
                _ => None,
            })
            .collect();
        if shells.len() < 2 {
            return None;
        }
        shells.sort_by(|a, b| a.1.radius_range().0.total_cmp(&b.1.radius_range().0));
        let (r_min, r_max): (Vec<f64>, Vec<f64>) =
            shells.iter().map(|(_, q)| q.radius_range()).unzip();
        let r_max_so_far = r_max
            .iter()
            .scan(0.0f64, |m, &r| {
                *m = m.max(r);
                Some(*m)
            })
            .collect();
        let z_lo = shells
            .iter()
            .map(|s| s.1.z_min)
            .fold(f64::INFINITY, f64::min);
        let z_hi = shells
            .iter()
            .map(|s| s.1.z_max)
            .fold(f64::NEG_INFINITY, f64::max);
        Some(NestedShells {
            shells,
            r_min,
            r_max,
            r_max_so_far,
            z_lo,
            z_hi,
        })
    }

    /// The object ids of the shells.
    pub fn ids(&self) -> impl Iterator<Item = u32> + '_ {
        self.shells.iter().map(|s| s.0)
    }

    /// The nearest shell hit with t < `t_max` of the ray o + t d: (object id,
    /// t). `start` is the object the ray leaves (its root at t ≈ 0 is skipped,
    /// as Embree's callbacks do).
    pub fn nearest(&self, o: DVec3, d: DVec3, t_max: f64, start: u32) -> Option<(u32, f64)> {
        let (rho_lo, rho_hi) = self.radii_on(o, d, t_max)?;
        // Shells with r_min ≤ ρ_max, walked down until none below can reach ρ_min.
        let mut i = self.r_min.partition_point(|&r| r <= rho_hi);
        let mut best: Option<(u32, f64)> = None;
        while i > 0 {
            i -= 1;
            if self.r_max_so_far[i] < rho_lo {
                break;
            }
            if self.r_max[i] < rho_lo {
                continue;
            }
            let (id, q) = &self.shells[i];
            let limit = best.map_or(t_max, |b| b.1);
            if let Some(t) = q.intersect(o, d, limit, *id == start) {
                best = Some((*id, t));
            }
        }
        best
    }

    /// The smallest and largest distance from the axis of the ray's part inside
    /// the shells' z range (t in [0, t_max)), padded for rounding; `None` when
    /// the ray misses that range.
    fn radii_on(&self, o: DVec3, d: DVec3, t_max: f64) -> Option<(f64, f64)> {
        let (ta, tb) = if d.z != 0.0 {
            let (t1, t2) = ((self.z_lo - o.z) / d.z, (self.z_hi - o.z) / d.z);
            (t1.min(t2).max(0.0), t1.max(t2).min(t_max))
        } else if o.z >= self.z_lo && o.z <= self.z_hi {
            (0.0, t_max)
        } else {
            return None;
        };
        if ta > tb {
            return None;
        }
        let rho2 = |t: f64| (o.x + t * d.x).powi(2) + (o.y + t * d.y).powi(2);
        let dxy2 = d.x * d.x + d.y * d.y;
        let closest = if dxy2 > 0.0 {
            (-(o.x * d.x + o.y * d.y) / dxy2).clamp(ta, tb)
        } else {
            ta
        };
        let hi = rho2(ta).max(rho2(tb)).sqrt();
        let lo = rho2(closest).min(rho2(ta)).min(rho2(tb)).sqrt();
        let pad = 1e-9 * (1.0 + hi);
        Some(((lo - pad).max(0.0), hi + pad))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{AzimuthRange, Transform};

    /// Every hit the nested search reports is the nearest among all shells,
    /// found by trying each shell in turn, on rays of every kind.
    #[test]
    fn finds_what_trying_every_shell_finds() {
        let objects: Vec<AnalyticObject> = (0..20)
            .map(|k| {
                let r = 50.0 + 10.0 * k as f64;
                let q = if k % 2 == 0 {
                    RevolutionQuadric::cone(r, 0.0, r - 2.0, 300.0, AzimuthRange::FULL)
                } else {
                    RevolutionQuadric::cylinder(r, -100.0, 200.0, AzimuthRange::FULL)
                };
                AnalyticObject {
                    shape: Shape::Revolution(q),
                    transform: Transform::default(),
                }
            })
            .collect();
        let nested =
            NestedShells::of(objects.iter().enumerate().map(|(i, o)| (i as u32, o))).unwrap();
        let mut rng = crate::random::PhotonRng::new(3, 0);
        let mut hits = 0;
        for _ in 0..20_000 {
            let o = DVec3::new(
                400.0 * rng.uniform() - 200.0,
                400.0 * rng.uniform() - 200.0,
                600.0 * rng.uniform() - 200.0,
            );
            // Half nearly along the axis (grazing), half in any direction.
            let d = if rng.uniform() < 0.5 {
                DVec3::new(
                    0.02 * rng.uniform() - 0.01,
                    0.02 * rng.uniform() - 0.01,
                    -1.0,
                )
            } else {
                DVec3::new(
                    rng.uniform() - 0.5,
                    rng.uniform() - 0.5,
                    rng.uniform() - 0.5,
                )
            };
            let brute = objects
                .iter()
                .enumerate()
                .filter_map(|(i, ob)| {
                    ob.intersect_world(o, d, f64::INFINITY, false)
                        .map(|t| (i as u32, t))
                })
                .min_by(|a, b| a.1.total_cmp(&b.1));
            let found = nested.nearest(o, d, f64::INFINITY, u32::MAX);
            assert_eq!(found, brute, "ray {o} + t {d}");
            hits += found.is_some() as usize;
        }
        assert!(
            hits > 2000,
            "only {hits} rays met a shell: the test rays miss"
        );
    }
}
