//! Figure errors of imperfect mirrors (SPEC §5): after the specular reflection the
//! direction is tilted in the plane of incidence by an angle drawn from a mixture
//! of a narrow and a wide normal distribution, and out of that plane by an angle
//! from one normal distribution. A photon tilted below the surface is absorbed.
//!
//! The widths are standard deviations of the *reflected direction* (not of the
//! surface slope: a slope error s in the plane of incidence tilts the ray by 2s).
//! Presets live in data/figure_errors.toml (with how they were obtained); a scene
//! adds its own in `[figure_errors]` or writes the numbers inline
//! ([`super::figure_presets`]).
//!
//! Data flow: `scene::build` resolves a mirror material's `figure_error` to a
//! [`FigureError`]; the photon loop calls [`FigureError::perturb`] after each
//! reflection on such a mirror with the photon's own random stream.

use crate::constants::RAD_PER_ARCSEC as ARCSEC;
use crate::random::PhotonRng;
use glam::DVec3;
use serde::Deserialize;

/// Widths (arcseconds, 1σ of the reflected direction) and mixture weight.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct FigureError {
    /// σ of the narrow in-plane component.
    pub in_plane_narrow: f64,
    /// σ of the wide in-plane component.
    pub in_plane_wide: f64,
    /// Probability that a reflection draws from the wide component (0–1).
    pub wide_fraction: f64,
    /// σ of the out-of-plane tilt.
    pub out_of_plane: f64,
}

message_error!(
    /// Figure-error parameters out of range, or an unknown preset.
    InvalidFigureError
);

/// What became of a reflected direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Perturbed {
    Direction(DVec3),
    /// Tilted below the surface: the photon is absorbed.
    BelowSurface,
}

impl FigureError {
    /// A perfect figure.
    pub const NONE: FigureError = FigureError {
        in_plane_narrow: 0.0,
        in_plane_wide: 0.0,
        wide_fraction: 0.0,
        out_of_plane: 0.0,
    };

    /// Checks the ranges; the message names the offending key.
    pub fn validate(&self) -> Result<(), InvalidFigureError> {
        for (k, v) in [
            ("in_plane_narrow", self.in_plane_narrow),
            ("in_plane_wide", self.in_plane_wide),
            ("out_of_plane", self.out_of_plane),
        ] {
            if !(v.is_finite() && (0.0..=36_000.0).contains(&v)) {
                return Err(InvalidFigureError::from(format!(
                    "{k} = {v}: expected a width in arcseconds, 0 to 36000"
                )));
            }
        }
        if !(0.0..=1.0).contains(&self.wide_fraction) {
            return Err(InvalidFigureError::from(format!(
                "wide_fraction = {}: expected a probability, 0 to 1",
                self.wide_fraction
            )));
        }
        Ok(())
    }

    /// Whether every reflection stays exactly specular.
    pub fn is_perfect(&self) -> bool {
        self.out_of_plane == 0.0
            && (self.in_plane_narrow == 0.0 || self.wide_fraction == 1.0)
            && (self.in_plane_wide == 0.0 || self.wide_fraction == 0.0)
    }

    /// Tilts the specular direction `reflected` (unit) off the surface with unit
    /// normal `normal`. Always draws the mixture choice and two normal deviates
    /// from `rng`, whose number of draws depends on the stream alone, so that
    /// photons keep their streams aligned whatever the parameters: runs with
    /// different widths share their random numbers (the fit relies on it).
    #[inline]
    pub fn perturb(&self, reflected: DVec3, normal: DVec3, rng: &mut PhotonRng) -> Perturbed {
        let choose_wide = rng.uniform() < self.wide_fraction;
        let (g_in, g_out) = (rng.normal(), rng.normal());
        let sigma_in = if choose_wide {
            self.in_plane_wide
        } else {
            self.in_plane_narrow
        };
        let a_in = sigma_in * ARCSEC * g_in;
        let a_out = self.out_of_plane * ARCSEC * g_out;
        if a_in == 0.0 && a_out == 0.0 {
            return Perturbed::Direction(reflected);
        }
        // n⊥ is normal to the plane of incidence, s lies in it, perpendicular to
        // the reflected ray.
        let n_perp = normal
            .cross(reflected)
            .try_normalize()
            .unwrap_or_else(|| reflected.any_orthonormal_vector());
        let s = n_perp.cross(reflected);
        let out = (reflected + s * tan(a_in) + n_perp * tan(a_out)).normalize();
        // Below the surface: on the other side of it than the specular ray.
        if out.dot(normal) * reflected.dot(normal) <= 0.0 {
            Perturbed::BelowSurface
        } else {
            Perturbed::Direction(out)
        }
    }
}

/// tan x, to within an ulp or so: figure-error tilts are a few arcminutes at
/// most, where the Taylor series to x⁷ is exact in f64 (the next term is below
/// 2e-18 x for |x| < 0.01 rad = 34′) and far cheaper than libm's `tan`.
#[inline]
fn tan(x: f64) -> f64 {
    if x.abs() < 0.01 {
        let x2 = x * x;
        x + x * x2 * (1.0 / 3.0 + x2 * (2.0 / 15.0 + x2 * (17.0 / 315.0)))
    } else {
        x.tan()
    }
}

#[cfg(test)]
mod tests {
    /// The short series agrees with libm's tan to a few ulps where it is used
    /// (and is libm's tan beyond).
    #[test]
    fn series_tangent_matches_libm() {
        let mut worst: f64 = 0.0;
        for i in -20_000..=20_000 {
            let x = i as f64 * 0.0099 / 20_000.0 + 1e-9;
            let rel = (super::tan(x) / x.tan() - 1.0).abs();
            worst = worst.max(rel);
        }
        assert!(worst < 4.0 * f64::EPSILON, "relative error {worst:e}");
        for x in [0.01, -0.02, 0.3, 1.2] {
            assert_eq!(super::tan(x), x.tan());
        }
    }
}
