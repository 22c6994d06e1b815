//! Errors of a figure-error fit and of what it predicts: after `fit` has found
//! the best parameters, how much they are uncertain, and how much that and the
//! Monte Carlo noise move the diameters predicted for other scenes (the PANTER
//! Ti Kα and Fe Kα lines from a fit to Al Kα).
//!
//! Linear error propagation around the best point p̂. The sensitivity J (3
//! diameters × k free parameters) is taken by central differences with the
//! fit's own photons (common random numbers: the difference is the parameters'
//! effect, not noise). Diameter errors S (diagonal, arcsec²) become parameter
//! errors C = (Jᵀ S⁻¹ J)⁻¹ (the weighted least-squares covariance; with three
//! diameters and three free parameters, J⁻¹ S J⁻ᵀ). Two sources are kept apart:
//!
//! - Monte Carlo: the spread of the diameters over seeds at p̂ (the fit saw one
//!   seed, so its p̂ carries that seed's noise);
//! - the fit: an uncertainty of the measured targets, a stated fraction of each
//!   (the PANTER numbers come without one), which also stands for the model's
//!   misfit (three diameters cannot all be met by the model, see docs/telescope.md).
//!
//! A prediction g(p̂) for another scene carries its own Monte Carlo error (the
//! standard error of its mean over seeds) and the fit error √(G C Gᵀ), G its
//! sensitivity to the parameters, taken the same way.
//!
//! Data flow: `traxer fit-figure-error --predict SCENE` calls [`sensitivity`],
//! [`parameter_errors`] and [`predict`] after the fit; `output::fit` writes them.

use super::fit::{field as get, set_figure_error, Bounds, Evaluation, FitSettings, PARAMETERS};
use super::{measure_arcsec, Diameters, StudyError};
use crate::progress::Progress;
use crate::scene::Scene;
use crate::trace::RunConfig;
use crate::xray::figure_error::FigureError;

/// ∂(HPD, 80 %, 90 %)/∂p at a point, arcsec per parameter unit.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Sensitivity {
    /// Indices of the free parameters (into `fit::PARAMETERS`).
    pub free: Vec<usize>,
    /// The step of each free parameter's difference.
    pub steps: Vec<f64>,
    /// One row per free parameter: the derivatives of the three diameters.
    pub rows: Vec<[f64; 3]>,
}

/// The parameters' uncertainties (1σ), by source and combined.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ParameterErrors {
    pub names: Vec<&'static str>,
    pub values: Vec<f64>,
    pub monte_carlo: Vec<f64>,
    pub fit: Vec<f64>,
    /// Monte Carlo and fit combined: the covariance (free × free).
    pub covariance: Vec<Vec<f64>>,
    /// The assumed uncertainty of each target, as a fraction of it.
    pub target_fraction: f64,
    /// The correlation coefficients of the combined covariance (free × free).
    pub correlation: Vec<Vec<f64>>,
    /// Per free parameter, what the targets say about it, in words: whether
    /// its error leaves it constrained, and whether the fit moved it at all
    /// (see [`ParameterErrors::assess`]); empty until assessed.
    pub verdicts: Vec<String>,
    /// Pairs of free parameters the targets cannot tell apart (|ρ| ≥ 0.9).
    pub degenerate: Vec<String>,
}

/// A parameter whose combined 1σ error reaches this share of its search range
/// is unconstrained: its value is where the optimiser stopped, not a
/// measurement.
pub const UNCONSTRAINED_RANGE_SHARE: f64 = 0.5;
/// A parameter whose combined 1σ error reaches this share of its value is
/// poorly constrained.
pub const POOR_RELATIVE_ERROR: f64 = 0.5;
/// Two parameters correlated at least this strongly are degenerate: the
/// targets fix a combination of them, not each.
pub const DEGENERATE_CORRELATION: f64 = 0.9;

impl ParameterErrors {
    /// The combined 1σ error of free parameter `k`.
    pub fn total(&self, k: usize) -> f64 {
        self.covariance[k][k].max(0.0).sqrt()
    }

    /// Says what the fit determined: each parameter is unconstrained (its
    /// error spans at least half its search range in `bounds`), poorly
    /// constrained (an error of at least half its value) or constrained; one
    /// the local stage never moved from the global search's grid point is
    /// said to be so (a grid sample is not a minimum); and strongly correlated
    /// pairs are named as degenerate. `history`: the fit's evaluations.
    pub fn assess(&mut self, free: &[usize], bounds: &Bounds, history: &[Evaluation]) {
        let k = self.names.len();
        let best_of = |stage: &str| {
            history
                .iter()
                .filter(|e| e.stage == stage && e.diameters.is_some())
                .min_by(|a, b| a.error.total_cmp(&b.error))
        };
        let (global, local) = (best_of("global"), best_of("local"));
        self.verdicts = (0..k)
            .map(|r| {
                let i = free[r];
                let (lo, hi) = (bounds.lower[i], bounds.upper[i]);
                let (v, s) = (self.values[r], self.total(r));
                let mut verdict = if s >= UNCONSTRAINED_RANGE_SHARE * (hi - lo) {
                    format!(
                        "unconstrained: its 1σ error ±{} spans {:.0} % of its search range {lo}–{hi}; the value is where the optimiser stopped, not a measurement",
                        significant(s),
                        100.0 * s / (hi - lo)
                    )
                } else if s >= POOR_RELATIVE_ERROR * v.abs() {
                    format!(
                        "poorly constrained: ±{:.0} % (1σ)",
                        100.0 * s / v.abs().max(f64::MIN_POSITIVE)
                    )
                } else {
                    format!("constrained: ±{:.1} % (1σ)", 100.0 * s / v.abs())
                };
                if let (Some(g), Some(l)) = (global, local) {
                    let (gv, lv) = (get(&g.parameters, i), get(&l.parameters, i));
                    if gv.to_bits() == lv.to_bits() && gv.to_bits() == v.to_bits() {
                        verdict.push_str(&format!(
                            "; the local fit left it at {}, a point of the global search's grid: the targets did not move it",
                            significant(v)
                        ));
                    }
                }
                verdict
            })
            .collect();
        self.degenerate = Vec::new();
        for a in 0..k {
            for b in a + 1..k {
                let rho = self.correlation[a][b];
                if rho.abs() >= DEGENERATE_CORRELATION {
                    self.degenerate.push(format!(
                        "{} and {} are degenerate (correlation {rho:+.2}): the targets fix a combination of the two, not each",
                        self.names[a], self.names[b]
                    ));
                }
            }
        }
    }

    /// The free parameters [`ParameterErrors::assess`] found unconstrained.
    pub fn unconstrained(&self) -> Vec<String> {
        self.names
            .iter()
            .zip(&self.verdicts)
            .filter(|(_, v)| v.starts_with("unconstrained"))
            .map(|(n, _)| n.to_string())
            .collect()
    }

    /// Parameter `k` as a physicist should quote it: value and errors to the
    /// precision of the combined error, with its verdict.
    pub fn quoted(&self, k: usize) -> String {
        let digits = decimals(self.total(k));
        format!(
            "{} = {:.digits$} ± {:.digits$} (Monte Carlo) ± {:.digits$} (fit, targets ± {} %) — {}",
            self.names[k],
            self.values[k],
            self.monte_carlo[k],
            self.fit[k],
            self.target_fraction * 100.0,
            self.verdicts.get(k).map_or("not assessed", String::as_str)
        )
    }
}

/// Decimal places that show `error` with two significant digits.
fn decimals(error: f64) -> usize {
    if !(error.is_finite() && error > 0.0) {
        return 4;
    }
    (1.0 - error.log10().floor()).clamp(0.0, 12.0) as usize
}

/// `x` with two significant digits.
fn significant(x: f64) -> String {
    format!("{:.*}", decimals(x), x)
}

/// What the fitted model predicts for another scene, with its errors (1σ).
#[derive(Clone, Debug, serde::Serialize)]
pub struct Prediction {
    /// The scene's path as given.
    pub scene: String,
    /// Mean over the seeds.
    pub diameters: Diameters,
    /// Standard errors of the means over the seeds.
    pub monte_carlo: [f64; 3],
    /// From the parameters' covariance.
    pub fit: [f64; 3],
    pub seeds: u64,
}

fn with(f: &FigureError, i: usize, v: f64) -> FigureError {
    let mut p = *f;
    match i {
        0 => p.in_plane_narrow = v,
        1 => p.in_plane_wide = v,
        2 => p.wide_fraction = v,
        _ => p.out_of_plane = v,
    }
    p
}

fn diameters(
    scene: &mut Scene,
    sensor: usize,
    run: &RunConfig,
    p: FigureError,
    progress: &dyn Progress,
) -> Result<[f64; 3], StudyError> {
    set_figure_error(scene, Some(p));
    let d = measure_arcsec(scene, sensor, run, progress)?.ok_or_else(|| {
        StudyError::Input("no flux reached the sensor near the fitted parameters".into())
    })?;
    Ok([d.hpd, d.d80, d.d90])
}

/// The sensitivity of the diameters of `scene` (on `s.sensor`) to the free
/// parameters of `s.bounds` at `p`, by central differences (one-sided at a
/// bound) with the photons of `s.run`. Steps: 5 % of the value, at least 1 % of
/// the parameter's range.
pub fn sensitivity(
    scene: &mut Scene,
    s: &FitSettings,
    p: &FigureError,
    progress: &dyn Progress,
) -> Result<Sensitivity, StudyError> {
    let (bounds, sensor, run) = (&s.bounds, s.sensor, &s.run);
    let free: Vec<usize> = (0..4)
        .filter(|&i| bounds.upper[i] > bounds.lower[i])
        .collect();
    let mut out = Sensitivity {
        free: free.clone(),
        steps: Vec::new(),
        rows: Vec::new(),
    };
    for &i in &free {
        let (lo, hi, v) = (bounds.lower[i], bounds.upper[i], get(p, i));
        let h = (0.05 * v.abs()).max(0.01 * (hi - lo));
        let (a, b) = ((v - h).max(lo), (v + h).min(hi));
        let da = diameters(scene, sensor, run, with(p, i, a), progress)?;
        let db = diameters(scene, sensor, run, with(p, i, b), progress)?;
        out.steps.push(h);
        out.rows.push([0, 1, 2].map(|k| (db[k] - da[k]) / (b - a)));
    }
    set_figure_error(scene, Some(*p));
    Ok(out)
}

/// The covariance (Jᵀ S⁻¹ J)⁻¹ for diameter variances `var` (arcsec²); `None`
/// when the diameters do not determine the parameters (a singular matrix).
fn covariance(j: &Sensitivity, var: [f64; 3]) -> Option<Vec<Vec<f64>>> {
    let k = j.rows.len();
    let a: Vec<Vec<f64>> = (0..k)
        .map(|r| {
            (0..k)
                .map(|c| (0..3).map(|d| j.rows[r][d] * j.rows[c][d] / var[d]).sum())
                .collect()
        })
        .collect();
    invert(a)
}

/// The inverse of a small symmetric positive matrix by Gauss–Jordan elimination
/// with partial pivoting; `None` if it is singular.
fn invert(mut a: Vec<Vec<f64>>) -> Option<Vec<Vec<f64>>> {
    let n = a.len();
    let scale = a.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut inv: Vec<Vec<f64>> = (0..n)
        .map(|r| (0..n).map(|c| f64::from(u8::from(r == c))).collect())
        .collect();
    for col in 0..n {
        let pivot = (col..n).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
        if a[pivot][col].abs() <= 1e-12 * scale {
            return None;
        }
        a.swap(col, pivot);
        inv.swap(col, pivot);
        let d = a[col][col];
        for c in 0..n {
            a[col][c] /= d;
            inv[col][c] /= d;
        }
        for r in (0..n).filter(|&r| r != col) {
            let f = a[r][col];
            for c in 0..n {
                a[r][c] -= f * a[col][c];
                inv[r][c] -= f * inv[col][c];
            }
        }
    }
    Some(inv)
}

/// The parameters' errors at `best` from its sensitivity `j`, the diameters'
/// Monte Carlo standard deviations `mc_sd` (arcsec) and a fractional
/// uncertainty `target_fraction` of the targets.
pub fn parameter_errors(
    j: &Sensitivity,
    best: &FigureError,
    mc_sd: [f64; 3],
    target: &Diameters,
    target_fraction: f64,
) -> Result<ParameterErrors, StudyError> {
    let t = [target.hpd, target.d80, target.d90];
    let fit_var = t.map(|v| (target_fraction * v).powi(2));
    let mc_var = mc_sd.map(|s| s.powi(2).max(1e-12));
    let singular = || {
        StudyError::Input(
            "the diameters do not determine the free parameters at the best point (their sensitivities are degenerate): hold one fixed with --bound".into(),
        )
    };
    let mc = covariance(j, mc_var).ok_or_else(singular)?;
    let fit = covariance(j, fit_var).ok_or_else(singular)?;
    let k = j.free.len();
    let total: Vec<Vec<f64>> = (0..k)
        .map(|r| (0..k).map(|c| mc[r][c] + fit[r][c]).collect())
        .collect();
    let correlation = (0..k)
        .map(|r| {
            (0..k)
                .map(|c| total[r][c] / (total[r][r] * total[c][c]).sqrt())
                .collect()
        })
        .collect();
    Ok(ParameterErrors {
        names: j.free.iter().map(|&i| PARAMETERS[i]).collect(),
        values: j.free.iter().map(|&i| get(best, i)).collect(),
        monte_carlo: (0..k).map(|i| mc[i][i].sqrt()).collect(),
        fit: (0..k).map(|i| fit[i][i].sqrt()).collect(),
        covariance: total,
        target_fraction,
        correlation,
        verdicts: Vec::new(),
        degenerate: Vec::new(),
    })
}

/// The diameters `scene` shows on `s.sensor` with the parameters `best`: the
/// mean over `seeds` seeds (s.run.seed, + 1, ...; at least 2), its standard
/// error, and the error the parameters' covariance gives it.
pub fn predict(
    scene: &mut Scene,
    s: &FitSettings,
    best: &FigureError,
    errors: &ParameterErrors,
    seeds: u64,
    progress: &dyn Progress,
) -> Result<Prediction, StudyError> {
    let (sensor, run) = (s.sensor, &s.run);
    let mut all = Vec::new();
    for k in 0..seeds.max(2) {
        let cfg = RunConfig {
            seed: run.seed.wrapping_add(k),
            ..run.clone()
        };
        all.push(diameters(scene, sensor, &cfg, *best, progress)?);
    }
    let n = all.len() as f64;
    let mean = [0, 1, 2].map(|d| all.iter().map(|v| v[d]).sum::<f64>() / n);
    let se = [0, 1, 2].map(|d| {
        let var = all.iter().map(|v| (v[d] - mean[d]).powi(2)).sum::<f64>() / (n - 1.0);
        (var / n).sqrt()
    });
    let g = sensitivity(scene, s, best, progress)?;
    let c = &errors.covariance;
    let fit = [0, 1, 2].map(|d| {
        let k = g.rows.len();
        (0..k)
            .flat_map(|r| (0..k).map(move |s| (r, s)))
            .map(|(r, s)| g.rows[r][d] * c[r][s] * g.rows[s][d])
            .sum::<f64>()
            .max(0.0)
            .sqrt()
    });
    Ok(Prediction {
        scene: scene.path.display().to_string(),
        diameters: Diameters {
            hpd: mean[0],
            d80: mean[1],
            d90: mean[2],
        },
        monte_carlo: se,
        fit,
        seeds: all.len() as u64,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The inverse of a known 3 × 3 matrix, and a singular one refused.
    #[test]
    fn inverts_small_matrices() {
        let a = vec![
            vec![4.0, 1.0, 0.5],
            vec![1.0, 3.0, 0.2],
            vec![0.5, 0.2, 2.0],
        ];
        let inv = invert(a.clone()).unwrap();
        for (r, row) in a.iter().enumerate() {
            for c in 0..3 {
                let v: f64 = row.iter().zip(&inv).map(|(x, i)| x * i[c]).sum();
                assert!(
                    (v - f64::from(u8::from(r == c))).abs() < 1e-12,
                    "{r},{c}: {v}"
                );
            }
        }
        assert!(invert(vec![vec![1.0, 2.0], vec![2.0, 4.0]]).is_none());
    }

    /// A parameter with an error beyond half its range is called unconstrained,
    /// one with an error beyond half its value poorly constrained, one the
    /// local stage left at the global grid's point is said to be so, and two
    /// parameters the targets see only together are degenerate.
    #[test]
    fn unconstrained_and_degenerate_parameters_are_named() {
        // Rows: narrow moves HPD alone; wide and fraction move 80 % and 90 %
        // almost alike (a near-degenerate pair).
        let j = Sensitivity {
            free: vec![0, 1, 2],
            steps: vec![1.0; 3],
            rows: vec![[2.0, 0.0, 0.0], [0.0, 0.10, 0.1001], [0.0, 100.0, 100.2]],
        };
        let best = FigureError {
            in_plane_narrow: 50.0,
            in_plane_wide: 500.0,
            wide_fraction: 0.1,
            out_of_plane: 0.0,
        };
        let target = Diameters {
            hpd: 200.0,
            d80: 400.0,
            d90: 500.0,
        };
        let mut e = parameter_errors(&j, &best, [0.1; 3], &target, 0.01).unwrap();
        let eval = |stage: &str, p: FigureError, error: f64| Evaluation {
            index: 0,
            parameters: p,
            diameters: Some(target),
            error,
            stage: stage.into(),
        };
        let history = [
            eval("global", best, 0.1),
            eval(
                "local",
                FigureError {
                    in_plane_narrow: 51.0,
                    ..best
                },
                0.2,
            ),
            eval("local", best, 0.05),
        ];
        e.assess(&[0, 1, 2], &Bounds::default(), &history);
        assert!(
            e.verdicts[0].starts_with("constrained"),
            "{}",
            e.verdicts[0]
        );
        assert!(
            e.verdicts[1].starts_with("unconstrained"),
            "{}",
            e.verdicts[1]
        );
        assert!(e.verdicts[2].contains("constrained"), "{}", e.verdicts[2]);
        assert!(
            e.verdicts[2].contains("did not move it"),
            "{}",
            e.verdicts[2]
        );
        assert_eq!(e.degenerate.len(), 1, "{:?}", e.degenerate);
        assert!(e.degenerate[0].starts_with("in_plane_wide and wide_fraction"));
        assert!(e.quoted(0).contains("50.0 ±"), "{}", e.quoted(0));
    }

    /// With as many diameters as parameters, the covariance is J⁻¹ S J⁻ᵀ: for a
    /// diagonal J the parameter errors are the diameter errors over the slopes.
    #[test]
    fn diagonal_sensitivity_gives_errors_over_slopes() {
        let j = Sensitivity {
            free: vec![0, 1, 2],
            steps: vec![1.0; 3],
            rows: vec![[2.0, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 10.0]],
        };
        let target = Diameters {
            hpd: 200.0,
            d80: 400.0,
            d90: 500.0,
        };
        let e = parameter_errors(&j, &FigureError::NONE, [1.0, 2.0, 3.0], &target, 0.01).unwrap();
        let expect_mc = [1.0 / 2.0, 2.0 / 0.5, 3.0 / 10.0];
        let expect_fit = [2.0 / 2.0, 4.0 / 0.5, 5.0 / 10.0];
        for i in 0..3 {
            assert!((e.monte_carlo[i] - expect_mc[i]).abs() < 1e-9);
            assert!((e.fit[i] - expect_fit[i]).abs() < 1e-9);
            let total = expect_mc[i].powi(2) + expect_fit[i].powi(2);
            assert!((e.covariance[i][i] - total).abs() < 1e-9);
        }
    }
}
