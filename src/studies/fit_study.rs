//! The figure-error fit as the study job runs it ([`crate::studies::StudyKind`]):
//! the fit's settings (its identity: what a resumed fit must share with the
//! stopped one), its points (the evaluations, recorded one by one), and what
//! follows the fit — the Monte Carlo spread of the best parameters over other
//! seeds, the parameters' errors and the predictions for other scenes. The
//! front end (`traxer fit-figure-error`) only parses its arguments into a
//! [`FitStudy`] and prints the [`FitOutput`].

use super::fit::{fit, seed_spread, Evaluation, FitResult, FitSettings, Spread};
use super::fit_errors::{parameter_errors, predict, sensitivity, ParameterErrors, Prediction};
use super::{Diameters, PointOrigin, Sampling, SceneLoader, StudyError, StudyKind};
use crate::material::Material;
use crate::progress::Progress;
use crate::scene::Scene;
use serde::Serialize;
use std::sync::Mutex;
use std::time::Instant;

/// What the fit does after its evaluations, none of it part of its identity
/// (a resumed fit may ask for other seeds or predictions).
#[derive(Clone, Debug)]
pub struct AfterFit {
    /// Extra seeds traced with the best parameters (seed + 1 …).
    pub check_seeds: u64,
    /// The assumed 1σ uncertainty of each target, as a fraction of it.
    pub target_fraction: f64,
    /// Seeds traced for each prediction.
    pub predict_seeds: u64,
    /// The preset's name in figure_error.toml.
    pub preset_name: String,
}

/// The fit as a study.
#[derive(Serialize)]
pub struct FitStudy<'a> {
    /// Photons, seed and the sensor's name (as the scene names it).
    #[serde(flatten)]
    pub sampling: Sampling,
    pub target_arcsec: Diameters,
    pub bounds_lower: [f64; 4],
    pub bounds_upper: [f64; 4],
    pub global_evaluations: u32,
    pub local_evaluations: u32,
    pub local_algorithm: String,
    #[serde(skip)]
    pub settings: FitSettings,
    #[serde(skip)]
    pub after: AfterFit,
    /// Loads the fit's scene (whose mirrors the fit changes in place).
    #[serde(skip)]
    load: SceneLoader<'a>,
    /// The scenes to predict, each with the sensor to measure.
    #[serde(skip)]
    predicted: Mutex<Vec<(Scene, usize)>>,
    /// What the line of each evaluation needs: the best so far, the start,
    /// how many evaluations were taken from the record.
    #[serde(skip)]
    shown: Mutex<(Option<Evaluation>, Instant, usize)>,
}

/// What the fit returns.
pub struct FitOutput {
    pub result: FitResult,
    /// The spread of the best parameters' diameters over seeds.
    pub spread: Spread,
    pub errors: ParameterErrors,
    pub predictions: Vec<Prediction>,
    /// Seconds the fit's evaluations took (not what follows).
    pub fit_seconds: f64,
}

impl<'a> FitStudy<'a> {
    /// The fit of `settings` on the scene that `load` loads (`scene` is one
    /// load of it), followed by `after`, predicting the scenes of `predicted`;
    /// the settings are checked, then each scene to predict (see
    /// [`check_predictable`]: a trial trace).
    pub fn new(
        scene: &Scene,
        settings: FitSettings,
        after: AfterFit,
        load: SceneLoader<'a>,
        predicted: Vec<(Scene, usize)>,
    ) -> Result<FitStudy<'a>, StudyError> {
        let sensor = &scene.sensors[settings.sensor];
        if sensor.focal_length.is_none() {
            return Err(StudyError::Input(format!(
                "sensor `{}` has no focal_length: the diameters in arcseconds need one",
                sensor.name
            )));
        }
        let study = FitStudy {
            sampling: Sampling {
                photons: settings.run.photons,
                seed: settings.run.seed,
                threads: settings.run.threads,
                sensor: Some(sensor.name.clone()),
            },
            target_arcsec: settings.target,
            bounds_lower: settings.bounds.lower,
            bounds_upper: settings.bounds.upper,
            global_evaluations: settings.global_evaluations,
            local_evaluations: settings.local_evaluations,
            local_algorithm: format!("{:?}", settings.local_algorithm),
            settings,
            after,
            load,
            predicted: Mutex::new(predicted),
            shown: Mutex::new((None, Instant::now(), 0)),
        };
        study.check()?;
        for (s, i) in study.predicted.lock().iter().flat_map(|p| p.iter()) {
            check_predictable(s, *i)?;
        }
        Ok(study)
    }

    /// The free parameters' indices.
    fn free(&self) -> Vec<usize> {
        let b = &self.settings.bounds;
        (0..4).filter(|&i| b.upper[i] > b.lower[i]).collect()
    }

    /// The traces planned: the fit's budget, the seed check, the sensitivity
    /// (two traces per free parameter) and each prediction's seeds and
    /// sensitivity. DIRECT-L may stop early, ending the count short.
    pub fn traces_planned(&self) -> u64 {
        let free = self.free().len() as u64;
        let predictions = self.predicted.lock().map_or(0, |p| p.len()) as u64;
        let a = &self.after;
        self.settings.global_evaluations as u64
            + self.settings.local_evaluations as u64
            + a.check_seeds
            + 2 * free
            + predictions * (a.predict_seeds.max(2) + 2 * free)
    }

    /// After the fit: the Monte Carlo spread of the best parameters over
    /// other seeds (the fit saw one), then the parameters' errors and the
    /// predictions.
    fn after_fit(
        &self,
        scene: &mut Scene,
        result: &FitResult,
        progress: &dyn Progress,
    ) -> Result<(Spread, ParameterErrors, Vec<Prediction>), StudyError> {
        let (settings, after) = (&self.settings, &self.after);
        let best = &result.best.parameters;
        let spread = seed_spread(scene, settings, &result.best, after.check_seeds, progress)?;
        let j = sensitivity(scene, settings, best, progress)?;
        let mc_sd =
            [spread.hpd.1, spread.d80.1, spread.d90.1].map(|v| if v.is_finite() { v } else { 0.0 });
        let mut errors =
            parameter_errors(&j, best, mc_sd, &settings.target, after.target_fraction)?;
        let mut predicted = self.predicted.lock().unwrap_or_else(|e| e.into_inner());
        let predictions = predicted
            .iter_mut()
            .map(|(s, sensor)| {
                let here = FitSettings {
                    sensor: *sensor,
                    ..settings.clone()
                };
                predict(s, &here, best, &errors, after.predict_seeds, progress).map_err(|e| match e
                {
                    StudyError::Input(m) => {
                        StudyError::Input(format!("--predict {}: {m}", s.path.display()))
                    }
                    other => other,
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        errors.assess(&self.free(), &settings.bounds, &result.history);
        Ok((spread, errors, predictions))
    }
}

impl StudyKind for FitStudy<'_> {
    type Point = Evaluation;
    type Output = FitOutput;
    const NAME: &'static str = "fit";
    const POINTS: &'static str = "evaluations";

    fn sampling(&self) -> &Sampling {
        &self.sampling
    }

    fn check(&self) -> Result<(), StudyError> {
        let t = &self.settings.target;
        if ![t.hpd, t.d80, t.d90]
            .iter()
            .all(|v| v.is_finite() && *v > 0.0)
        {
            return Err(StudyError::Input(
                "the targets must be positive diameters (arcsec)".into(),
            ));
        }
        let f = self.after.target_fraction;
        if !(f.is_finite() && f > 0.0 && f < 1.0) {
            return Err(StudyError::Input(format!(
                "--target-error {}: expected a percentage between 0 and 100",
                100.0 * f
            )));
        }
        // The name becomes a key of figure_error.toml: a dot would nest tables.
        let name = &self.after.preset_name;
        let bare = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
        if name.is_empty() || !name.chars().all(bare) {
            return Err(StudyError::Input(format!(
                "--name {name:?}: a preset name is a bare TOML key: letters, digits, _ and - (e.g. llnl_panter_sigma_0p5)"
            )));
        }
        Ok(())
    }

    fn photons_total(&self, _scene: &Scene) -> u64 {
        self.settings
            .run
            .photons
            .saturating_mul(self.traces_planned())
    }

    /// Fits on a scene of its own (the evaluations change its mirrors in
    /// place), loaded as the front end's, then assesses the best point.
    fn run(
        &self,
        _scene: &Scene,
        replay: &[Evaluation],
        progress: &dyn Progress,
        on_point: &mut dyn FnMut(&Evaluation, PointOrigin),
    ) -> Result<FitOutput, StudyError> {
        let mut scene = (self.load)(&[])?;
        let started = Instant::now();
        if let Ok(mut shown) = self.shown.lock() {
            *shown = (None, started, replay.len());
        }
        let photons = self.settings.run.photons;
        let result = fit(
            &mut scene,
            &self.settings,
            replay,
            progress,
            |e, _, origin| {
                if origin == PointOrigin::Record {
                    // Taken from the record, not traced: the bar moves on as if.
                    progress.advance(photons);
                }
                on_point(e, origin);
            },
        )?;
        let fit_seconds = started.elapsed().as_secs_f64();
        let (spread, errors, predictions) = self.after_fit(&mut scene, &result, progress)?;
        Ok(FitOutput {
            result,
            spread,
            errors,
            predictions,
            fit_seconds,
        })
    }

    fn threads_used(output: &FitOutput) -> usize {
        output.result.threads
    }

    /// Each traced evaluation: its parameters and diameters, and the best so far.
    fn describe(&self, e: &Evaluation) -> Option<String> {
        let mut shown = self.shown.lock().ok()?;
        let (best, started, replayed) = &mut *shown;
        if best.as_ref().is_none_or(|b| e.error < b.error) {
            *best = Some(e.clone());
        }
        if e.index <= *replayed {
            return None;
        }
        let best = best.as_ref()?;
        let p = &e.parameters;
        let d = e.diameters.map_or("no image".into(), |d| {
            format!("{:.1}″ {:.1}″ {:.1}″", d.hpd, d.d80, d.d90)
        });
        Some(format!(
            "eval {:>4} ({}, {:.0} s): narrow {:.2}″ wide {:.2}″ fraction {:.4} out {:.2}″ → {d}, error {:.3e} | best {:.3e} (eval {})",
            e.index,
            e.stage,
            started.elapsed().as_secs_f64(),
            p.in_plane_narrow,
            p.in_plane_wide,
            p.wide_fraction,
            p.out_of_plane,
            e.error,
            best.error,
            best.index
        ))
    }
}

/// Photons of the trial trace that checks a scene to predict before the fit.
const TRIAL_PHOTONS: u64 = 20_000;

/// Refuses, before the fit runs, a scene to predict whose diameters the
/// fitted figure errors cannot predict: one without a mirror for them to act
/// on, without a focal length for diameters in arcseconds, or where no photon
/// of a short trial trace reaches the sensor.
pub fn check_predictable(scene: &Scene, sensor: usize) -> Result<(), StudyError> {
    let path = scene.path.display();
    let mirrors = scene
        .objects
        .iter()
        .any(|o| matches!(o.material, Material::Mirror { .. }));
    if !mirrors {
        return Err(StudyError::Input(format!(
            "--predict {path}: the scene has no mirror for the fitted figure errors to act on"
        )));
    }
    let name = &scene.sensors[sensor].name;
    if scene.sensors[sensor].focal_length.is_none() {
        return Err(StudyError::Input(format!(
            "{path}: sensor `{name}` has no focal_length, which the diameters in arcseconds need"
        )));
    }
    let trial = crate::trace::run(scene, &crate::trace::RunConfig::new(TRIAL_PHOTONS, 1))?;
    if trial.images[sensor].total_flux() <= 0.0 {
        return Err(StudyError::Input(format!(
            "--predict {path}: no photon of a {TRIAL_PHOTONS}-photon trial trace reaches sensor `{name}`, so its diameters cannot be predicted (check the sensor's place and the sources)"
        )));
    }
    Ok(())
}
