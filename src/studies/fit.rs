//! Fitting the figure-error model (SPEC §5) to measured image quality: every
//! candidate parameter set is traced through the same built scene with the same
//! photons (common random numbers: the objective is a smooth function of the
//! parameters, not a noisy one), the 50/80/90 % diameters are measured, and NLopt
//! minimises their squared relative errors to the targets — DIRECT-L (a global,
//! derivative-free search over the bounds, as TrAXer used) followed by a local
//! Sbplx polish from the best point.
//!
//! Data flow: `traxer fit-figure-error` builds the scene once, calls [`fit`] with
//! the bounds and targets, checks the Monte Carlo spread with [`seed_spread`], and
//! `output` writes the history and the preset.

use super::{measure_arcsec, trace_and_measure, Diameters, PointOrigin, StudyError};
use crate::material::Material;
use crate::progress::Progress;
use crate::scene::Scene;
use crate::trace::RunConfig;
use crate::xray::figure_error::FigureError;

/// The parameters in the order of [`FigureError`]'s fields.
pub const PARAMETERS: [&str; 4] = [
    "in_plane_narrow",
    "in_plane_wide",
    "wide_fraction",
    "out_of_plane",
];

/// Search range of each parameter (equal ends: held fixed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    pub lower: [f64; 4],
    pub upper: [f64; 4],
}

impl Default for Bounds {
    /// Narrow 0–120″, wide 0–900″, fraction 0–0.6, out of plane fixed at 0: at
    /// grazing incidence an azimuthal slope error s tilts the ray by only
    /// ≈ 2·s·sin α (α < 1°), and three targets determine three parameters.
    fn default() -> Self {
        Bounds {
            lower: [0.0, 0.0, 0.0, 0.0],
            upper: [120.0, 900.0, 0.6, 0.0],
        }
    }
}

/// One objective evaluation.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Evaluation {
    pub index: usize,
    pub parameters: FigureError,
    /// `None` when no flux reached the sensor.
    pub diameters: Option<Diameters>,
    pub error: f64,
    /// Which stage asked: "global" (DIRECT-L) or "local" (Sbplx).
    pub stage: String,
}

/// Gives every mirror of the scene the figure error `fe` (`None`: perfect).
pub fn set_figure_error(scene: &mut Scene, fe: Option<FigureError>) {
    for o in &mut scene.objects {
        if let Material::Mirror { figure_error, .. } = &mut o.material {
            *figure_error = fe.filter(|f| !f.is_perfect());
        }
    }
}

/// Gives the mirrors whose figure error is `from` the figure error `to` (the
/// others keep theirs).
pub fn set_figure_error_where(
    scene: &mut Scene,
    from: Option<FigureError>,
    to: Option<FigureError>,
) {
    for o in &mut scene.objects {
        if let Material::Mirror { figure_error, .. } = &mut o.material {
            if *figure_error == from {
                *figure_error = to.filter(|f| !f.is_perfect());
            }
        }
    }
}

/// Budget and settings of a fit.
#[derive(Clone, Debug)]
pub struct FitSettings {
    pub bounds: Bounds,
    pub target: Diameters,
    pub run: RunConfig,
    pub sensor: usize,
    /// Evaluations for DIRECT-L, then for the local polish.
    pub global_evaluations: u32,
    pub local_evaluations: u32,
    /// The local polish: NLopt's Sbplx (the command's default), BOBYQA or Nelder–Mead.
    pub local_algorithm: LocalAlgorithm,
}

/// Derivative-free local optimisers of NLopt for the polish.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LocalAlgorithm {
    Bobyqa,
    Sbplx,
    NelderMead,
}

impl LocalAlgorithm {
    fn nlopt(self) -> nlopt::Algorithm {
        match self {
            LocalAlgorithm::Bobyqa => nlopt::Algorithm::Bobyqa,
            LocalAlgorithm::Sbplx => nlopt::Algorithm::Sbplx,
            LocalAlgorithm::NelderMead => nlopt::Algorithm::Neldermead,
        }
    }
}

/// The outcome: the best parameters and every evaluation in order.
#[derive(Clone, Debug)]
pub struct FitResult {
    pub best: Evaluation,
    pub history: Vec<Evaluation>,
    /// How many of them were taken from the evaluations of an earlier, stopped
    /// fit instead of traced (see [`fit`]).
    pub replayed: usize,
    /// Worker threads the traces used.
    pub threads: usize,
}

struct State<'a, P: FnMut(&Evaluation, &Evaluation, PointOrigin)> {
    scene: &'a mut Scene,
    settings: &'a FitSettings,
    replay: &'a [Evaluation],
    replayed: usize,
    trace_progress: &'a dyn Progress,
    free: Vec<usize>,
    history: Vec<Evaluation>,
    best: Option<Evaluation>,
    stage: &'static str,
    progress: P,
    failure: Option<StudyError>,
    threads: usize,
}

impl<P: FnMut(&Evaluation, &Evaluation, PointOrigin)> State<'_, P> {
    fn parameters(&self, x: &[f64]) -> FigureError {
        let mut p = self.settings.bounds.lower;
        for (&i, &v) in self.free.iter().zip(x) {
            p[i] = v;
        }
        FigureError {
            in_plane_narrow: p[0],
            in_plane_wide: p[1],
            wide_fraction: p[2],
            out_of_plane: p[3],
        }
    }

    /// The recorded evaluation at this point of an earlier fit, if its parameters
    /// are bit for bit those asked for now (the optimisers are deterministic, so
    /// they are until the earlier fit stopped).
    fn recorded(&self, fe: &FigureError) -> Option<Option<Diameters>> {
        let r = self.replay.get(self.history.len())?;
        let same = |a: &FigureError| {
            [
                a.in_plane_narrow,
                a.in_plane_wide,
                a.wide_fraction,
                a.out_of_plane,
            ]
            .map(f64::to_bits)
        };
        (self.replayed == self.history.len() && same(&r.parameters) == same(fe))
            .then_some(r.diameters)
    }

    fn evaluate(&mut self, x: &[f64]) -> f64 {
        // After a failure or a stop the optimiser may still ask: it is
        // answered without a trace, and nothing is recorded.
        if self.failure.is_none()
            && self.history.len() >= self.replay.len()
            && self.trace_progress.stop_requested()
        {
            self.failure = Some(StudyError::Stopped);
        }
        if self.failure.is_some() {
            return 1e6;
        }
        let fe = self.parameters(x);
        let mut origin = PointOrigin::Record;
        let diameters = if let Some(d) = self.recorded(&fe) {
            self.replayed += 1;
            d
        } else {
            origin = PointOrigin::Traced;
            set_figure_error(self.scene, Some(fe));
            let measured = trace_and_measure(
                self.scene,
                self.settings.sensor,
                &self.settings.run,
                self.trace_progress,
            );
            match measured {
                Ok(m) => {
                    self.threads = m.threads;
                    m.quality.as_ref().and_then(Diameters::of)
                }
                Err(e) => {
                    self.failure = Some(e);
                    return 1e6;
                }
            }
        };
        // No image at all is the worst possible outcome, not an error.
        let error = diameters.map_or(1e6, |d| d.error_to(&self.settings.target));
        let e = Evaluation {
            index: self.history.len() + 1,
            parameters: fe,
            diameters,
            error,
            stage: self.stage.into(),
        };
        if self.best.as_ref().is_none_or(|b| e.error < b.error) {
            self.best = Some(e.clone());
        }
        (self.progress)(&e, self.best.as_ref().expect("set above"), origin);
        self.history.push(e);
        error
    }
}

/// Runs the fit on `scene` (whose mirrors' figure errors it overwrites; they hold
/// the best parameters afterwards). `on_evaluation` sees each evaluation and the
/// best so far; `trace_progress` the photons of every evaluation's trace.
///
/// `replay`: the evaluations of an earlier run of the same fit that was stopped.
/// Each evaluation takes their diameters instead of tracing, for as long as the
/// optimisers ask for the same parameters (bit for bit) in the same order, which
/// they do, being deterministic: the resumed fit is the uninterrupted one.
pub fn fit(
    scene: &mut Scene,
    settings: &FitSettings,
    replay: &[Evaluation],
    trace_progress: &dyn Progress,
    on_evaluation: impl FnMut(&Evaluation, &Evaluation, PointOrigin),
) -> Result<FitResult, StudyError> {
    let b = &settings.bounds;
    for ((name, lo), hi) in PARAMETERS.iter().zip(b.lower).zip(b.upper) {
        if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
            return Err(StudyError::Input(format!(
                "bounds of {name}: expected lower ≤ upper, got {lo}:{hi}"
            )));
        }
    }
    let free: Vec<usize> = (0..4).filter(|&i| b.upper[i] > b.lower[i]).collect();
    let mut state = State {
        scene,
        settings,
        replay,
        replayed: 0,
        free: free.clone(),
        history: Vec::new(),
        best: None,
        stage: "global",
        progress: on_evaluation,
        trace_progress,
        failure: None,
        threads: 0,
    };
    if free.is_empty() {
        state.evaluate(&[]);
    } else {
        let lower: Vec<f64> = free.iter().map(|&i| b.lower[i]).collect();
        let upper: Vec<f64> = free.iter().map(|&i| b.upper[i]).collect();
        let mut x: Vec<f64> = lower
            .iter()
            .zip(&upper)
            .map(|(l, u)| 0.5 * (l + u))
            .collect();
        for (stage, algorithm, evaluations) in [
            (
                "global",
                nlopt::Algorithm::DirectL,
                settings.global_evaluations,
            ),
            (
                "local",
                settings.local_algorithm.nlopt(),
                settings.local_evaluations,
            ),
        ] {
            if evaluations == 0 {
                continue;
            }
            state.stage = stage;
            optimise(&mut state, algorithm, evaluations, (&lower, &upper), &mut x)?;
            if let Some(best) = &state.best {
                x = free.iter().map(|&i| field(&best.parameters, i)).collect();
            }
        }
    }
    if let Some(e) = state.failure.take() {
        return Err(e);
    }
    let best = state.best.clone().expect("at least one evaluation");
    set_figure_error(state.scene, Some(best.parameters));
    Ok(FitResult {
        best,
        history: state.history,
        replayed: state.replayed,
        threads: state.threads,
    })
}

/// One NLopt stage over the free parameters within `(lower, upper)`, from `x`
/// (updated in place), for at most `evaluations` evaluations.
fn optimise<P: FnMut(&Evaluation, &Evaluation, PointOrigin)>(
    state: &mut State<P>,
    algorithm: nlopt::Algorithm,
    evaluations: u32,
    (lower, upper): (&[f64], &[f64]),
    x: &mut [f64],
) -> Result<(), StudyError> {
    let stage = state.stage;
    let mut opt = nlopt::Nlopt::new(
        algorithm,
        lower.len(),
        |x: &[f64], _grad: Option<&mut [f64]>, s: &mut &mut State<P>| s.evaluate(x),
        nlopt::Target::Minimize,
        state,
    );
    // The polish starts with steps of 2 % of each range: DIRECT-L has already
    // located the basin to a few % (its cells at this budget).
    let steps: Vec<f64> = lower
        .iter()
        .zip(upper)
        .map(|(l, u)| 0.02 * (u - l))
        .collect();
    let setup = opt
        .set_lower_bounds(lower)
        .and_then(|_| opt.set_upper_bounds(upper))
        .and_then(|_| opt.set_maxeval(evaluations))
        .and_then(|_| opt.set_xtol_rel(1e-4))
        .and_then(|_| match stage {
            "local" => opt.set_initial_step(&steps),
            _ => Ok(nlopt::SuccessState::Success),
        });
    if setup.is_err() {
        return Err(StudyError::Optimiser(format!(
            "NLopt refused the {stage} settings"
        )));
    }
    // Stopping at the evaluation budget is the normal end; the best point is
    // tracked by the state either way.
    let _ = opt.optimize(x);
    Ok(())
}

/// Parameter `i` (in [`PARAMETERS`] order) of `f`.
pub(super) fn field(f: &FigureError, i: usize) -> f64 {
    [
        f.in_plane_narrow,
        f.in_plane_wide,
        f.wide_fraction,
        f.out_of_plane,
    ][i]
}

/// Mean and sample standard deviation of each diameter over several seeds.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct Spread {
    /// Seeds measured (with an image).
    pub seeds: usize,
    pub hpd: (f64, f64),
    pub d80: (f64, f64),
    pub d90: (f64, f64),
}

/// The Monte Carlo spread of the best parameters: `best` (the fit's own seed)
/// and `extra_seeds` more runs with seeds seed + 1, seed + 2, ...
pub fn seed_spread(
    scene: &mut Scene,
    settings: &FitSettings,
    best: &Evaluation,
    extra_seeds: u64,
    progress: &dyn Progress,
) -> Result<Spread, StudyError> {
    set_figure_error(scene, Some(best.parameters));
    let mut spread = Vec::new();
    for k in 1..=extra_seeds {
        let cfg = RunConfig {
            seed: settings.run.seed.wrapping_add(k),
            ..settings.run.clone()
        };
        if let Some(d) = measure_arcsec(scene, settings.sensor, &cfg, progress)? {
            spread.push(d);
        }
    }
    let stats = |f: fn(&Diameters) -> f64| -> (f64, f64) {
        let all: Vec<f64> = std::iter::once(best.diameters.as_ref().map_or(f64::NAN, f))
            .chain(spread.iter().map(f))
            .collect();
        let n = all.len() as f64;
        let mean = all.iter().sum::<f64>() / n;
        let sd = if all.len() > 1 {
            (all.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
        } else {
            f64::NAN
        };
        (mean, sd)
    };
    Ok(Spread {
        seeds: spread.len() + 1,
        hpd: stats(|d| d.hpd),
        d80: stats(|d| d.d80),
        d90: stats(|d| d.d90),
    })
}
