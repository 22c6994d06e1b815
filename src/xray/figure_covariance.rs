//! The uncertainty of a fitted figure-error preset: the covariance of its free
//! parameters, as `traxer fit-figure-error` estimates it (Monte Carlo and the
//! targets' uncertainty, `studies::fit_errors`), saved with the preset and read
//! back, and parameter sets drawn from it for a study of the image's systematic
//! uncertainty.
//!
//! In a preset (data/figure_errors.toml, a scene's `[figure_errors]`, the
//! `figure_error.toml` a fit writes):
//!
//! ```toml
//! [figure_errors.my_fit.covariance]
//! parameters = ["in_plane_narrow", "in_plane_wide", "wide_fraction"]
//! matrix = [[169.0, 10.0, 0.1], [10.0, 9.0e6, 30.0], [0.1, 30.0, 0.017]]
//! ```
//!
//! in the parameters' units squared (arcsec², and 1 for the fraction); the
//! parameters not named are held at the preset's values.

use super::figure_error::FigureError;
use crate::random::PhotonRng;
use serde::{Deserialize, Serialize};

/// The names of a figure error's parameters, in the order of [`values`].
pub const PARAMETERS: [&str; 4] = [
    "in_plane_narrow",
    "in_plane_wide",
    "wide_fraction",
    "out_of_plane",
];

/// A figure error's parameters in the order of [`PARAMETERS`].
pub fn values(f: &FigureError) -> [f64; 4] {
    [
        f.in_plane_narrow,
        f.in_plane_wide,
        f.wide_fraction,
        f.out_of_plane,
    ]
}

fn with_values(v: [f64; 4]) -> FigureError {
    FigureError {
        in_plane_narrow: v[0],
        in_plane_wide: v[1],
        wide_fraction: v[2],
        out_of_plane: v[3],
    }
}

/// The covariance of some of a preset's parameters.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FigureCovariance {
    /// The parameters it covers (names of [`PARAMETERS`], each once).
    pub parameters: Vec<String>,
    /// Their covariance, one row per parameter.
    pub matrix: Vec<Vec<f64>>,
    /// The parameters the fit found unconstrained (their 1σ spans half their
    /// search range or more: the value is where the optimiser stopped). A
    /// systematics study holds them at the preset's values and draws the
    /// others given them, since a normal distribution of such a parameter
    /// says nothing about the telescope.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub unconstrained: Vec<String>,
}

impl FigureCovariance {
    /// Checks the names, the shape, symmetry and that the matrix is a
    /// covariance (positive semi-definite); returns the parameters' indices in
    /// [`PARAMETERS`] and the Cholesky factor L (C = L Lᵀ) to draw with.
    pub fn checked(&self) -> Result<(Vec<usize>, Vec<Vec<f64>>), String> {
        let mut index = Vec::new();
        for p in &self.parameters {
            let k = PARAMETERS.iter().position(|n| n == p).ok_or_else(|| {
                format!("covariance: unknown parameter `{p}` (expected {PARAMETERS:?})")
            })?;
            if index.contains(&k) {
                return Err(format!("covariance: `{p}` is named twice"));
            }
            index.push(k);
        }
        let n = index.len();
        if n == 0 || self.matrix.len() != n || self.matrix.iter().any(|r| r.len() != n) {
            return Err(format!(
                "covariance: matrix must be {n} × {n}, one row and column per parameter named"
            ));
        }
        let c = &self.matrix;
        for (a, b) in (0..n).flat_map(|a| (0..n).map(move |b| (a, b))) {
            let (x, y) = (c[a][b], c[b][a]);
            if !x.is_finite() || (x - y).abs() > 1e-9 * (x.abs() + y.abs()) {
                return Err(format!(
                    "covariance: matrix must be finite and symmetric (row {}, column {})",
                    a + 1,
                    b + 1
                ));
            }
        }
        Ok((index, cholesky(c)?))
    }

    /// The distribution of the other parameters when those named in `held`
    /// are fixed at their preset values: the conditional covariance (the
    /// Schur complement, C_oo − C_oh C_hh⁻¹ C_ho, taken one held parameter at
    /// a time). `None` when every parameter is held.
    pub fn given(&self, held: &[String]) -> Result<Option<FigureCovariance>, String> {
        self.checked()?;
        if let Some(h) = held.iter().find(|h| !PARAMETERS.contains(&h.as_str())) {
            return Err(format!(
                "unknown figure parameter `{h}` (expected {PARAMETERS:?})"
            ));
        }
        let mut names = self.parameters.clone();
        let mut c = self.matrix.clone();
        for h in held {
            let Some(k) = names.iter().position(|n| n == h) else {
                continue; // not in the covariance: held already
            };
            let ckk = c[k][k];
            let keep: Vec<usize> = (0..names.len()).filter(|&i| i != k).collect();
            c = keep
                .iter()
                .map(|&a| {
                    keep.iter()
                        .map(|&b| match ckk > 0.0 {
                            true => c[a][b] - c[a][k] * c[k][b] / ckk,
                            false => c[a][b],
                        })
                        .collect()
                })
                .collect();
            names.remove(k);
        }
        if names.is_empty() {
            return Ok(None);
        }
        Ok(Some(FigureCovariance {
            parameters: names,
            matrix: c,
            unconstrained: Vec::new(),
        }))
    }

    /// `count` parameter sets drawn from the normal distribution around
    /// `nominal` with this covariance (draw k from the stream (seed, k)). A
    /// draw outside the parameters' domain (a negative width, a fraction
    /// outside [0, 1]) is moved onto its edge; returns the draws and how many
    /// were so moved.
    pub fn draw(
        &self,
        nominal: &FigureError,
        count: usize,
        seed: u64,
    ) -> Result<(Vec<FigureError>, usize), String> {
        let (index, l) = self.checked()?;
        let mut clipped = 0;
        let draws = (0..count)
            .map(|k| {
                let mut rng = PhotonRng::new(seed, k as u64);
                let z: Vec<f64> = (0..index.len()).map(|_| rng.normal()).collect();
                let mut v = values(nominal);
                for (a, &p) in index.iter().enumerate() {
                    v[p] += (0..=a).map(|b| l[a][b] * z[b]).sum::<f64>();
                }
                let inside = [
                    v[0].max(0.0),
                    v[1].max(0.0),
                    v[2].clamp(0.0, 1.0),
                    v[3].max(0.0),
                ];
                if inside != v {
                    clipped += 1;
                }
                with_values(inside)
            })
            .collect();
        Ok((draws, clipped))
    }
}

/// L with C = L Lᵀ for a positive semi-definite C (a zero pivot, a parameter
/// fully fixed by the others, gives a zero column), or what is wrong.
fn cholesky(c: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, String> {
    let n = c.len();
    let mut l = vec![vec![0.0; n]; n];
    for a in 0..n {
        for b in 0..=a {
            let s: f64 = (0..b).map(|k| l[a][k] * l[b][k]).sum();
            if a == b {
                let d = c[a][a] - s;
                if d < -1e-9 * c[a][a].abs().max(f64::MIN_POSITIVE) {
                    return Err(
                        "covariance: the matrix is not positive semi-definite (not a covariance)"
                            .into(),
                    );
                }
                l[a][a] = d.max(0.0).sqrt();
            } else {
                l[a][b] = if l[b][b] > 0.0 {
                    (c[a][b] - s) / l[b][b]
                } else {
                    0.0
                };
            }
        }
    }
    Ok(l)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cov(parameters: &[&str], matrix: Vec<Vec<f64>>) -> FigureCovariance {
        FigureCovariance {
            parameters: parameters.iter().map(|s| s.to_string()).collect(),
            matrix,
            unconstrained: Vec::new(),
        }
    }

    #[test]
    fn draws_have_the_mean_and_covariance_asked_for() {
        // 40 000 draws: the sample covariance's elements have a relative 1σ of
        // about √(2/n) = 0.7 %; required within 4 %.
        let c = cov(
            &["in_plane_narrow", "wide_fraction"],
            vec![vec![169.0, 0.26], vec![0.26, 0.0016]],
        );
        let nominal = FigureError {
            in_plane_narrow: 55.0,
            in_plane_wide: 800.0,
            wide_fraction: 0.3,
            out_of_plane: 0.0,
        };
        let (d, clipped) = c.draw(&nominal, 40_000, 3).unwrap();
        assert_eq!(clipped, 0, "7σ from every edge");
        let n = d.len() as f64;
        let x: Vec<[f64; 2]> = d
            .iter()
            .map(|f| [f.in_plane_narrow, f.wide_fraction])
            .collect();
        let mean = [0, 1].map(|k| x.iter().map(|v| v[k]).sum::<f64>() / n);
        assert!((mean[0] - 55.0).abs() < 4.0 * 13.0 / n.sqrt());
        assert!((mean[1] - 0.3).abs() < 4.0 * 0.04 / n.sqrt());
        let s = |a: usize, b: usize| {
            x.iter()
                .map(|v| (v[a] - mean[a]) * (v[b] - mean[b]))
                .sum::<f64>()
                / (n - 1.0)
        };
        assert!((s(0, 0) / 169.0 - 1.0).abs() < 0.04);
        assert!((s(1, 1) / 0.0016 - 1.0).abs() < 0.04);
        assert!((s(0, 1) / 0.26 - 1.0).abs() < 0.06, "{}", s(0, 1));
        // The others stay at the nominal values.
        assert!(d
            .iter()
            .all(|f| f.in_plane_wide == 800.0 && f.out_of_plane == 0.0));
    }

    #[test]
    fn bad_covariances_are_refused() {
        for (c, expect) in [
            (cov(&["width"], vec![vec![1.0]]), "unknown parameter"),
            (
                cov(
                    &["in_plane_narrow", "in_plane_narrow"],
                    vec![vec![1.0, 0.0], vec![0.0, 1.0]],
                ),
                "twice",
            ),
            (cov(&["in_plane_narrow"], vec![vec![1.0, 0.0]]), "1 × 1"),
            (
                cov(
                    &["in_plane_narrow", "in_plane_wide"],
                    vec![vec![1.0, 2.0], vec![0.0, 1.0]],
                ),
                "symmetric",
            ),
            (
                cov(
                    &["in_plane_narrow", "in_plane_wide"],
                    vec![vec![1.0, 2.0], vec![2.0, 1.0]],
                ),
                "positive semi-definite",
            ),
        ] {
            let e = c.checked().unwrap_err();
            assert!(e.contains(expect), "{e}");
        }
        // Fully correlated (the fit's degenerate pair) is a covariance.
        assert!(cov(
            &["in_plane_wide", "wide_fraction"],
            vec![vec![4.0, 0.2], vec![0.2, 0.01]]
        )
        .checked()
        .is_ok());
    }

    #[test]
    fn holding_a_parameter_leaves_the_others_conditional_variance() {
        // Closed form for three normal variables: holding x3 leaves the
        // covariance C_ab − C_a3 C_3b / C_33; for a pair, σ₁²(1 − ρ²).
        let c = cov(
            &["in_plane_narrow", "in_plane_wide", "wide_fraction"],
            vec![
                vec![225.0, 40.0, 0.6],
                vec![40.0, 400.0, 1.5],
                vec![0.6, 1.5, 0.01],
            ],
        );
        let g = c.given(&["in_plane_wide".into()]).unwrap().unwrap();
        assert_eq!(g.parameters, ["in_plane_narrow", "wide_fraction"]);
        let want = [
            [225.0 - 40.0 * 40.0 / 400.0, 0.6 - 40.0 * 1.5 / 400.0],
            [0.6 - 1.5 * 40.0 / 400.0, 0.01 - 1.5 * 1.5 / 400.0],
        ];
        for (a, row) in want.iter().enumerate() {
            for (b, w) in row.iter().enumerate() {
                assert!((g.matrix[a][b] - w).abs() < 1e-12 * w.abs().max(1.0));
            }
        }
        // Holding both in turn equals holding them together: narrow alone
        // with C_11 − c Σ⁻¹ cᵀ over the pair (2 × 2 inverse by hand).
        let both = c
            .given(&["in_plane_wide".into(), "wide_fraction".into()])
            .unwrap()
            .unwrap();
        let (a, b, d) = (400.0, 1.5, 0.01);
        let det = a * d - b * b;
        let (u, v) = (40.0, 0.6);
        let quad = (u * u * d - 2.0 * u * v * b + v * v * a) / det;
        assert!((both.matrix[0][0] - (225.0 - quad)).abs() < 1e-9);
        // Every parameter held: nothing left to draw; an unknown name refused.
        let all: Vec<String> = c.parameters.clone();
        assert!(c.given(&all).unwrap().is_none());
        assert!(c.given(&["width".into()]).unwrap_err().contains("unknown"));
    }
}
