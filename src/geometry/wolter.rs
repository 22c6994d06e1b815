//! The prescription of one true Wolter-I shell: a paraboloid followed by a
//! confocal hyperboloid (Van Speybroeck & Chase, Appl. Opt. 11 (1972) 440),
//! computed from the radius R3 at the intersection plane and the focal length f
//! alone. The first step of telescopes as data (issue 40): a nested telescope
//! file gives R3 per shell; this gives each shell its two surfaces, which
//! `geometry::RevolutionQuadric` then traces.
//!
//! Frame: the optical axis is z, photons arrive travelling towards −z, the
//! intersection plane (where the two surfaces meet) is z = 0 and the telescope's
//! focus is at z = −f. With equal grazing angles on both mirrors for a ray
//! meeting them at the intersection plane, the paraboloid is inclined by
//! α = ¼·atan(R3/f) to the axis there and the hyperboloid by 3α: an axial ray
//! leaves the paraboloid at 2α towards the paraboloid's focus and the
//! hyperboloid at 4α towards the telescope's focus, tan 4α = R3/f.
//!
//! - Paraboloid, focus at z = −D on the axis, D = R3 / tan 2α (where the ray
//!   reflected at the intersection plane crosses the axis): r² = 4q(z + D + q),
//!   q fixed by r(0) = R3.
//! - Hyperboloid with foci at z = −D and z = −f (so the paraboloid's focus is
//!   its far focus and the telescope's focus its near one): centre
//!   z_c = −(D + f)/2, (z − z_c)²/a² − r²/b² = 1 on the branch towards the
//!   telescope, 2a = the difference of the distances from the intersection
//!   circle to the two foci, b² = c² − a² with c = (D − f)/2.

/// One shell's two surfaces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WolterShell {
    /// Focal length (mm): the focus lies at z = −f.
    pub focal_length: f64,
    /// Radius at the intersection plane z = 0 (mm).
    pub r3: f64,
    /// The paraboloid's inclination to the axis at z = 0 (rad), the grazing
    /// angle of an axial ray there.
    pub alpha: f64,
    /// The paraboloid's focus: z = −`paraboloid_focus_depth`.
    pub paraboloid_focus_depth: f64,
    /// The paraboloid's parameter q (mm): r² = 4q(z + D + q).
    pub q: f64,
    /// The hyperboloid's centre (z), semi-axes a (along z) and b (mm).
    pub hyperboloid_centre: f64,
    pub a: f64,
    pub b: f64,
}

impl WolterShell {
    /// The shell of radius `r3` (mm) at the intersection plane of a telescope of
    /// focal length `focal_length` (mm); both positive and finite.
    pub fn new(focal_length: f64, r3: f64) -> Result<WolterShell, String> {
        if !(focal_length.is_finite() && focal_length > 0.0 && r3.is_finite() && r3 > 0.0) {
            return Err(format!(
                "a Wolter-I shell needs a positive focal length and radius (mm), got f = {}, R3 = {}",
                crate::text::number(focal_length),
                crate::text::number(r3)
            ));
        }
        let alpha = (r3 / focal_length).atan() / 4.0;
        let d = r3 / (2.0 * alpha).tan();
        // r(0)² = 4q(D + q) = R3²: the positive root, written without the
        // cancellation of −D + √(D² + R3²) for small shells.
        let q = r3 * r3 / (2.0 * (d + d.hypot(r3)));
        let c = 0.5 * (d - focal_length);
        let far = d.hypot(r3);
        let near = focal_length.hypot(r3);
        let a = 0.5 * (far - near);
        let b = (c * c - a * a).sqrt();
        Ok(WolterShell {
            focal_length,
            r3,
            alpha,
            paraboloid_focus_depth: d,
            q,
            hyperboloid_centre: -0.5 * (d + focal_length),
            a,
            b,
        })
    }

    /// The paraboloid's radius at height z (mm).
    pub fn paraboloid_radius(&self, z: f64) -> f64 {
        (4.0 * self.q * (z + self.paraboloid_focus_depth + self.q)).sqrt()
    }

    /// dr/dz of the paraboloid at height z.
    pub fn paraboloid_slope(&self, z: f64) -> f64 {
        2.0 * self.q / self.paraboloid_radius(z)
    }

    /// The hyperboloid's radius at height z (mm).
    pub fn hyperboloid_radius(&self, z: f64) -> f64 {
        let u = (z - self.hyperboloid_centre) / self.a;
        self.b * (u * u - 1.0).sqrt()
    }

    /// dr/dz of the hyperboloid at height z.
    pub fn hyperboloid_slope(&self, z: f64) -> f64 {
        let dz = z - self.hyperboloid_centre;
        self.b * self.b * dz / (self.a * self.a * self.hyperboloid_radius(z))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    /// XMM-Newton's outermost and innermost shells (R3 ≈ 350 and 153 mm at
    /// f = 7500 mm) and an LLNL-sized one (R3 ≈ 60 mm at 1500 mm).
    const SHELLS: [(f64, f64); 3] = [(7500.0, 350.0), (7500.0, 153.0), (1500.0, 60.9)];

    #[test]
    fn the_surfaces_meet_at_r3_with_slopes_alpha_and_three_alpha() {
        for (f, r3) in SHELLS {
            let s = WolterShell::new(f, r3).unwrap();
            assert!((s.alpha - (r3 / f).atan() / 4.0).abs() < 1e-15);
            assert!((s.paraboloid_radius(0.0) / r3 - 1.0).abs() < 1e-12);
            assert!((s.hyperboloid_radius(0.0) / r3 - 1.0).abs() < 1e-12);
            assert!((s.paraboloid_slope(0.0) / s.alpha.tan() - 1.0).abs() < 1e-9);
            assert!((s.hyperboloid_slope(0.0) / (3.0 * s.alpha).tan() - 1.0).abs() < 1e-9);
            // The hyperboloid's foci: the paraboloid's focus and the telescope's.
            let c = (s.a * s.a + s.b * s.b).sqrt();
            assert!((s.hyperboloid_centre + c + s.focal_length).abs() < 1e-9 * f);
            assert!((s.hyperboloid_centre - c + s.paraboloid_focus_depth).abs() < 1e-9 * f);
        }
    }

    /// Where `p + t d` (t > 1e-9) first meets the surface g(r, z) = 0 whose
    /// gradient is `grad`, found by bisection between a point where g changes
    /// sign along the ray (the surfaces are smooth and met once here).
    fn hit(p: DVec2, d: DVec2, g: impl Fn(DVec2) -> f64, t_max: f64) -> DVec2 {
        let (mut lo, mut hi) = (1e-9, t_max);
        assert!(
            g(p + d * lo).signum() != g(p + d * hi).signum(),
            "no crossing"
        );
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if g(p + d * mid).signum() == g(p + d * lo).signum() {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        p + d * (0.5 * (lo + hi))
    }

    fn reflect(d: DVec2, normal: DVec2) -> DVec2 {
        let n = normal.normalize();
        d - n * (2.0 * d.dot(n))
    }

    /// Axial rays at any radius the paraboloid takes in (points x = r, y = z
    /// of the meridional plane) reflect off the paraboloid and then off the
    /// hyperboloid into the telescope's focus at z = −f: the confocal pair has
    /// no on-axis aberration.
    #[test]
    fn axial_rays_meet_the_focus_after_two_reflections() {
        for (f, r3) in SHELLS {
            let s = WolterShell::new(f, r3).unwrap();
            let length = 300.0;
            // The paraboloid spans z ∈ [0, L]: its radius there, the rays' range.
            let (r_lo, r_hi) = (s.paraboloid_radius(0.0), s.paraboloid_radius(length));
            // (From just above the intersection circle: a ray there touches both
            // surfaces at one point.)
            for k in 1..=8 {
                let r = r_lo + (r_hi - r_lo) * k as f64 / 8.0;
                let start = DVec2::new(r, 1000.0);
                let down = DVec2::new(0.0, -1.0);
                let para =
                    |p: DVec2| p.x * p.x - 4.0 * s.q * (p.y + s.paraboloid_focus_depth + s.q);
                let p1 = hit(start, down, para, 2000.0);
                let n1 = DVec2::new(2.0 * p1.x, -4.0 * s.q);
                let d1 = reflect(down, n1);
                let hyper = |p: DVec2| {
                    let u = (p.y - s.hyperboloid_centre) / s.a;
                    u * u - (p.x / s.b).powi(2) - 1.0
                };
                let p2 = hit(p1, d1, hyper, 2.0 * length / d1.y.abs());
                assert!(
                    p2.y < 0.0 && p2.y > -1.5 * length,
                    "{r}: the hyperboloid is met at z = {}",
                    p2.y
                );
                let n2 = DVec2::new(
                    -2.0 * p2.x / (s.b * s.b),
                    2.0 * (p2.y - s.hyperboloid_centre) / (s.a * s.a),
                );
                let d2 = reflect(d1, n2);
                let z_axis = p2.y - p2.x / d2.x * d2.y;
                assert!(
                    (z_axis + f).abs() < 1e-6,
                    "f {f}, R3 {r3}, ray at r = {r}: crosses the axis at z = {z_axis}"
                );
            }
        }
    }

    /// The tangent lines at the intersection circle: an axial ray reflected
    /// there by the paraboloid (inclined α) leaves at 2α and is reflected by
    /// the hyperboloid (inclined 3α) to 4α, which points at the focus:
    /// tan 4α = R3 / f.
    #[test]
    fn the_total_deflection_at_the_intersection_circle_is_four_alpha() {
        for (f, r3) in SHELLS {
            let s = WolterShell::new(f, r3).unwrap();
            let normal = |slope: f64| DVec2::new(1.0, -slope);
            let d1 = reflect(DVec2::new(0.0, -1.0), normal(s.paraboloid_slope(0.0)));
            let d2 = reflect(d1, normal(s.hyperboloid_slope(0.0)));
            let deflection = (-d2.x).atan2(-d2.y);
            assert!((deflection - 4.0 * s.alpha).abs() < 1e-12, "{deflection}");
            assert!(((4.0 * s.alpha).tan() - r3 / f).abs() < 1e-12);
        }
    }

    /// Shell 1 of the Wolter-I example scenes (f = 1500 mm, R3 = 50 mm) as the
    /// Python generator that wrote those scenes before the assembly existed
    /// (scripts/wolter1_shells.py, retired after commit 58782e4) computed it
    /// independently, by the other form of the quadratic's root.
    #[test]
    fn the_shell_of_the_shipped_wolter_scene_is_reproduced() {
        let s = WolterShell::new(1500.0, 50.0).unwrap();
        let close = |a: f64, b: f64| (a / b - 1.0).abs() < 1e-12;
        assert!(close(s.q, 0.20826104155094072), "{}", s.q);
        assert!(close(s.paraboloid_focus_depth, 3000.8331019803636));
        assert!(close(s.a, 750.2082610415508), "{}", s.a);
        assert!(close(s.b, 17.679509750341772), "{}", s.b);
        assert!(close(s.hyperboloid_centre, -2250.416550990182));
    }

    #[test]
    fn a_shell_needs_a_positive_radius_and_focal_length() {
        assert!(WolterShell::new(7500.0, 0.0).is_err());
        assert!(WolterShell::new(-1.0, 100.0).is_err());
        assert!(WolterShell::new(f64::NAN, 100.0).is_err());
    }
}
