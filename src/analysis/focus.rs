//! Best focus from a sweep: the image diameter measured at several sensor
//! positions z, fitted with the defocus curve of a converging beam,
//! D(z)² = D₀² + k² (z − z₀)² (a blur of intrinsic size D₀ plus a cone of rays
//! opening with slope k; for a sum of the two in quadrature the curve is exactly
//! this hyperbola). z₀ is the
//! best focus. The fit is linear least squares on D² = c₀ + c₁z + c₂z², weighted by
//! 1/D² so that every point counts by its relative error in D, not in D².
//!
//! Data flow: `traxer focus` traces the scene once per position (same seed, so the
//! points share their random numbers and the curve is smooth), computes each
//! image's diameters with [`super::analyse`] and hands them to [`fit_defocus`].

use glam::{DMat3, DVec3};

/// The fitted defocus curve.
#[derive(Clone, Debug, serde::Serialize)]
pub struct DefocusFit {
    /// Best-focus position (same unit as the positions given).
    pub z0: f64,
    /// Standard error of `z0` from the fit residuals (includes model mismatch).
    pub z0_std_error: f64,
    /// Diameter at best focus on the fitted curve.
    pub d0: f64,
    /// Slope of the asymptotes (diameter per unit of z).
    pub slope: f64,
    /// Root-mean-square of the residuals, relative to the diameter.
    pub rms_relative_residual: f64,
    /// The smallest diameter measured in the sweep.
    pub smallest_measured: f64,
    /// Whether the sweep measured D₀: a point lies where D₀ dominates the
    /// curve (its diameter within twice D₀). A sweep coarser than the depth
    /// of focus sees only the asymptotes, whose fit puts D₀ anywhere below
    /// the smallest measured diameter (often 0): then D₀ is not a result.
    pub d0_resolved: bool,
}

impl DefocusFit {
    /// Diameter on the fitted curve at `z`.
    pub fn diameter_at(&self, z: f64) -> f64 {
        (self.d0 * self.d0 + self.slope * self.slope * (z - self.z0).powi(2)).sqrt()
    }
}

/// Why no defocus curve could be fitted.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DefocusFitError {
    #[error("need at least 4 positions with an image to fit the focus, have {0}")]
    TooFewPoints(usize),
    #[error("the positions must not all be equal")]
    EqualPositions,
    #[error("the positions do not determine a curve (need 3 distinct ones)")]
    Undetermined,
    #[error("the diameter does not grow on both sides of the sweep: widen the range")]
    DoesNotOpen,
    #[error(
        "the fitted focus {z0:.3} lies outside the sweep [{zmin}, {zmax}]: move or widen the range"
    )]
    Outside { z0: f64, zmin: f64, zmax: f64 },
}

/// Fits `points` = (z, diameter). Needs at least 4 points with positive
/// diameters, and a curve that opens upwards with its minimum inside the range
/// of z (otherwise the sweep did not bracket the focus: an error says so).
pub fn fit_defocus(points: &[(f64, f64)]) -> Result<DefocusFit, DefocusFitError> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|&(z, d)| z.is_finite() && d.is_finite() && d > 0.0)
        .collect();
    if pts.len() < 4 {
        return Err(DefocusFitError::TooFewPoints(pts.len()));
    }
    let (zmin, zmax) = pts.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
        (a.0.min(p.0), a.1.max(p.0))
    });
    // Centre and scale z so that the normal equations are well conditioned.
    let zc = 0.5 * (zmin + zmax);
    let zs = 0.5 * (zmax - zmin);
    if zs <= 0.0 {
        return Err(DefocusFitError::EqualPositions);
    }
    let mut ata = DMat3::ZERO;
    let mut atb = DVec3::ZERO;
    for &(z, d) in &pts {
        let u = (z - zc) / zs;
        let row = DVec3::new(1.0, u, u * u);
        let w = 1.0 / (d * d);
        ata += DMat3::from_cols(row * row.x, row * row.y, row * row.z) * w;
        atb += row * (w * d * d);
    }
    if ata.determinant().abs() < 1e-12 * ata.abs().to_cols_array().iter().sum::<f64>() {
        return Err(DefocusFitError::Undetermined);
    }
    let inv = ata.inverse();
    let c = inv * atb;
    if c.z <= 0.0 {
        return Err(DefocusFitError::DoesNotOpen);
    }
    let u0 = -c.y / (2.0 * c.z);
    let z0 = zc + zs * u0;
    if !(zmin..=zmax).contains(&z0) {
        return Err(DefocusFitError::Outside { z0, zmin, zmax });
    }
    let d0sq = c.x - c.y * c.y / (4.0 * c.z);
    // Residuals, relative to the diameter (the quantity the weights equalise).
    let mut chi2 = 0.0;
    for &(z, d) in &pts {
        let u = (z - zc) / zs;
        let model = c.x + c.y * u + c.z * u * u;
        chi2 += ((d * d - model) / (d * d)).powi(2);
    }
    let dof = (pts.len() - 3).max(1) as f64;
    let s2 = chi2 / dof;
    // Error propagation for u0 = −c1 / (2 c2) with Cov(c) = s² (AᵀWA)⁻¹.
    let grad = DVec3::new(0.0, -1.0 / (2.0 * c.z), c.y / (2.0 * c.z * c.z));
    let var_u0 = s2 * grad.dot(inv * grad);
    let d0 = d0sq.max(0.0).sqrt();
    let smallest_measured = pts.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    Ok(DefocusFit {
        z0,
        z0_std_error: zs * var_u0.max(0.0).sqrt(),
        d0,
        slope: c.z.sqrt() / zs,
        rms_relative_residual: (chi2 / pts.len() as f64).sqrt() / 2.0,
        smallest_measured,
        d0_resolved: smallest_measured <= 2.0 * d0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_an_exact_hyperbola() {
        let (z0, d0, k) = (-1517.3, 1.3, 0.07);
        let pts: Vec<(f64, f64)> = (0..13)
            .map(|i| {
                let z = -1460.0 - 10.0 * i as f64;
                (z, (d0 * d0 + k * k * (z - z0) * (z - z0)).sqrt())
            })
            .collect();
        let f = fit_defocus(&pts).unwrap();
        assert!((f.z0 - z0).abs() < 1e-9, "{f:?}");
        assert!(
            (f.d0 - d0).abs() < 1e-9 && (f.slope - k).abs() < 1e-12,
            "{f:?}"
        );
        assert!(f.rms_relative_residual < 1e-12 && f.z0_std_error < 1e-6);
    }

    #[test]
    fn refuses_a_sweep_that_misses_the_focus() {
        let pts: Vec<(f64, f64)> = (0..6)
            .map(|i| (i as f64, (1.0 + (i as f64 - 20.0).powi(2)).sqrt()))
            .collect();
        let e = fit_defocus(&pts).unwrap_err().to_string();
        assert!(e.contains("outside the sweep"), "{e}");
        let down: Vec<(f64, f64)> = (0..6)
            .map(|i| (i as f64, 5.0 - 0.1 * (i * i) as f64))
            .collect();
        assert!(fit_defocus(&down)
            .unwrap_err()
            .to_string()
            .contains("widen"));
        assert!(fit_defocus(&pts[..3]).is_err());
    }

    #[test]
    fn a_sweep_coarser_than_the_depth_of_focus_does_not_claim_the_diameter_there() {
        // The HPD (mm) of scenes/xmm_point_source.toml every 5 mm (traxer focus
        // --from -7990 --to -7930, 200 000 photons): a V whose bottom, between
        // two samples, the sweep never saw. Its fit puts D₀ at 0; a scan every
        // 1 mm around the focus measured 0.072 mm there.
        let hpd = [
            2.22903, 1.89484, 1.56009, 1.22510, 0.88758, 0.54983, 0.22131, 0.11038, 0.43007,
            0.76527, 1.10080, 1.43572, 1.76965,
        ];
        let coarse: Vec<(f64, f64)> = hpd
            .iter()
            .enumerate()
            .map(|(i, &d)| (-7990.0 + 5.0 * i as f64, d))
            .collect();
        let f = fit_defocus(&coarse).unwrap();
        assert!((f.z0 + 7956.6).abs() < 0.5, "{f:?}");
        assert!(!f.d0_resolved && f.smallest_measured == 0.11038, "{f:?}");
        // The exact hyperbola sampled as coarsely is resolved: its samples
        // reach down to twice D₀.
        let (z0, d0, k) = (-7956.6, 0.3, 0.067);
        let exact: Vec<(f64, f64)> = (0..13)
            .map(|i| -7990.0 + 5.0 * i as f64)
            .map(|z| (z, (d0 * d0 + (k * (z - z0)).powi(2)).sqrt()))
            .collect();
        let f = fit_defocus(&exact).unwrap();
        assert!(f.d0_resolved && (f.d0 - d0).abs() < 1e-9, "{f:?}");
    }
}
