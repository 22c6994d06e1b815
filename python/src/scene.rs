//! `traxer.Scene`: a scene file loaded and built with Embree, as the CLI loads it,
//! and `Scene.trace`, the run of `traxer trace` (same photons, same sums, so the
//! images are bit for bit the CLI's), with the GIL released while it traces.

use crate::convert::{defines, threads, to_json};
use crate::errors::{input, lib, to_py};
use crate::result::TraceResult;
use crate::run::{finished_result, PyControl};
use crate::units::{numbers, optional, Unit};
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;
use traxer::embree::Device;
use traxer::run::{FrontEnd, Invocation, RunSettings, Shard, TraceJob};
use traxer::trace::RunConfig;

/// A scene and the Embree device it was built on (the device must outlive it).
pub struct Loaded {
    pub scene: traxer::scene::Scene,
    pub device: Device,
}

/// The Embree version, e.g. "3.13.5".
pub fn embree_version() -> PyResult<String> {
    Ok(Device::new().map_err(lib)?.info().version)
}

/// A scene file (TOML, see docs/scene-format.md), loaded and built for tracing.
///
/// Scene(path, defines=None)
///
/// `defines` sets scene variables declared in the file's [vars], like the CLI's
/// `-D name=value`: a dict {"name": value} (bool, number, string, list, or a
/// dict for an inline table such as a roughness PSD) or a list of "name=value"
/// strings. A missing file raises `FileNotFoundError`; a
/// scene that cannot be loaded raises `traxer.SceneError` with `file`, `line`,
/// `key` and `message`.
#[pyclass(module = "traxer", frozen)]
pub struct Scene {
    pub loaded: Arc<Loaded>,
}

#[pymethods]
impl Scene {
    #[new]
    #[pyo3(signature = (path, defines = None))]
    fn new(py: Python<'_>, path: PathBuf, defines: Option<&Bound<'_, PyAny>>) -> PyResult<Scene> {
        if !path.exists() {
            return Err(pyo3::exceptions::PyFileNotFoundError::new_err((
                2,
                "No such scene file",
                path.display().to_string(),
            )));
        }
        let overrides = self::defines(defines)?;
        let loaded = py
            .detach(|| -> anyhow::Result<Loaded> {
                let device = Device::new()?;
                let scene = traxer::scene::Scene::load(&device, &path, &overrides)?;
                Ok(Loaded { scene, device })
            })
            .map_err(to_py)?;
        Ok(Scene {
            loaded: Arc::new(loaded),
        })
    }

    /// The scene file's path.
    #[getter]
    fn path(&self) -> PathBuf {
        self.loaded.scene.path.clone()
    }

    /// SHA-256 of the scene file's bytes.
    #[getter]
    fn sha256(&self) -> String {
        self.loaded.scene.text_sha256.clone()
    }

    /// The sensors' names, in the scene's order.
    #[getter]
    fn sensors(&self) -> Vec<String> {
        self.loaded
            .scene
            .sensors
            .iter()
            .map(|s| s.name.clone())
            .collect()
    }

    /// The objects' names, in the scene's order (photon lists index them).
    #[getter]
    fn objects(&self) -> Vec<String> {
        self.loaded
            .scene
            .objects
            .iter()
            .map(|o| o.name.clone())
            .collect()
    }

    /// The scene's variables after `defines`: {name: value}.
    #[getter]
    fn variables<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_json(py, &self.loaded.scene.vars)
    }

    /// The warnings the scene gave when it was loaded.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.loaded.scene.warnings.clone()
    }

    /// Number of triangles of the meshed objects.
    #[getter]
    fn triangle_count(&self) -> usize {
        self.loaded.scene.triangle_count
    }

    fn __repr__(&self) -> String {
        let s = &self.loaded.scene;
        let count = |n: usize, one: &str| match n {
            1 => format!("1 {one}"),
            n => format!("{n} {one}s"),
        };
        format!(
            "traxer.Scene({:?}: {}, {}, {})",
            s.path.display().to_string(),
            count(s.objects.len(), "object"),
            count(s.sensors.len(), "sensor"),
            count(s.sources.len(), "source")
        )
    }

    /// Traces `photons` photons, as `traxer trace SCENE --photons N --seed S`.
    ///
    /// Photon i uses the random stream (seed, i), so the images are the same for
    /// any `threads` (0: one per core) and equal the CLI's bit for bit.
    /// `photon_list`: also keep the first N photons recorded on a sensor
    /// (`TraceResult.photons`). `progress`: draw a progress bar on stderr. The
    /// GIL is released while tracing; Ctrl-C (KeyboardInterrupt) stops the run
    /// after the current batch of about a million photons.
    ///
    /// `out`: also write the results folder as `traxer trace --out` does (the
    /// same files, bit for bit), all at once when the run ends. With
    /// `checkpoint_every` (seconds; needs `out`) the run keeps a checkpoint there,
    /// and a run stopped by Ctrl-C or killed is continued by `traxer.resume(out)`
    /// (or `traxer trace --resume out`) to the result of an uninterrupted run.
    /// A folder holding the results of a run with other inputs (scene,
    /// variables, seed, photons) is refused unless `replace=True`.
    #[pyo3(signature = (photons, seed = 1, threads = 0, photon_list = 0, progress = false, out = None, checkpoint_every = None, replace = false))]
    #[allow(clippy::too_many_arguments)]
    fn trace(
        &self,
        py: Python<'_>,
        photons: &Bound<'_, PyAny>,
        seed: u64,
        threads: usize,
        photon_list: usize,
        progress: bool,
        out: Option<PathBuf>,
        checkpoint_every: Option<&Bound<'_, PyAny>>,
        replace: bool,
    ) -> PyResult<TraceResult> {
        let checkpoint_every = optional("checkpoint_every", checkpoint_every, Unit::Second)?;
        let photons = crate::convert::count("photons", photons, 1)?;
        let cfg = traxer::run::run_config(photons, seed, threads, photon_list, FrontEnd::Python)
            .map_err(|e| input(e.0))?;
        let scene = &self.loaded.scene;
        traxer::studies::require_sources(scene).map_err(lib)?;
        let invocation = Invocation::new([
            "python".to_string(),
            format!(
                "traxer.Scene({:?}, defines={:?}).trace({photons}, seed={seed}, threads={threads}, photon_list={photon_list}, out={out:?}, checkpoint_every={checkpoint_every:?})",
                scene.path.display().to_string(),
                scene.overrides
            ),
        ]);
        let every = crate::run::checkpoint_interval(checkpoint_every)?;
        match out {
            Some(out) => {
                return self.trace_to_folder(
                    py,
                    (cfg, &out),
                    (every, replace),
                    progress,
                    &invocation,
                )
            }
            None if every.is_some() => return Err(input(
                "checkpoint_every needs out=FOLDER: the checkpoint is kept in the results folder",
            )),
            None => {}
        }
        // Traced in memory by `run`, as the CLI's runs are; Ctrl-C is seen
        // between batches (the control checks Python's signals).
        let job = TraceJob {
            scene,
            embree_version: self.loaded.device.info().version,
            cfg,
            shard: Shard::whole(photons),
        };
        let control = PyControl::new(photons, progress);
        let ran = py.detach(|| job.run_in_memory(&invocation, &control));
        control.bar.finish_and_clear();
        let run = ran.map_err(|e| control.error(e))?;
        let loaded = self.loaded.clone();
        TraceResult::new(
            py,
            loaded,
            run.header,
            run.tally,
            run.threads,
            run.provenance,
        )
    }

    /// The telescope's effective area A_eff(E, θ), as `traxer effective-area`.
    ///
    /// The scene's only source must be a parallel beam covering the telescope's
    /// entrance; it is tilted to each of `angles_arcmin` (None: on axis only). At
    /// each angle `photons` photons (default 200 000; an int or a whole float
    /// such as 2e5) are traced once and each photon's weight is evaluated at
    /// every energy of `energies_keV`. Energies, angles and `radius_mm` may be
    /// astropy Quantities (a wavelength converts to its energy). `sensor`: the sensor to count on (default: the
    /// only one); `radius_mm`: count only within this radius of the image
    /// centroid. With `out` (a folder) the sweep writes the files of `traxer
    /// effective-area --out` there and records each angle as it finishes: Ctrl-C
    /// stops it after the current angle (KeyboardInterrupt, with a note), and
    /// the same call with `resume=True` takes up the recorded angles. Returns a
    /// `traxer.EffectiveArea`.
    #[pyo3(signature = (energies_keV, angles_arcmin = None, photons = None, seed = 1, threads = 0, sensor = None, radius_mm = None, progress = false, out = None, resume = false))]
    #[allow(non_snake_case, clippy::too_many_arguments)]
    fn effective_area(
        &self,
        py: Python<'_>,
        energies_keV: &Bound<'_, PyAny>,
        angles_arcmin: Option<&Bound<'_, PyAny>>,
        photons: Option<&Bound<'_, PyAny>>,
        seed: u64,
        threads: usize,
        sensor: Option<String>,
        radius_mm: Option<&Bound<'_, PyAny>>,
        progress: bool,
        out: Option<PathBuf>,
        resume: bool,
    ) -> PyResult<crate::effective_area::EffectiveArea> {
        let sweep = traxer::studies::effective_area::AreaSweep {
            energies: numbers("energies_keV", energies_keV, Unit::KeV)?,
            angles_arcmin: match angles_arcmin.filter(|a| !a.is_none()) {
                Some(a) => numbers("angles_arcmin", a, Unit::Arcmin)?,
                None => vec![0.0],
            },
            sampling: sampling((photons, 200_000), seed, threads, sensor)?,
            radius_mm: optional("radius_mm", radius_mm, Unit::Mm)?,
        };
        let place = (out, resume);
        crate::effective_area::run(py, self.loaded.clone(), sweep, place, progress)
    }

    /// The PSF library, as `traxer psf`: the scene's parallel beam (its only
    /// source) tilted to each of `angles_arcmin` towards each of `azimuths_deg`
    /// at each of `energies_keV`, `photons` photons per point (default 200 000)
    /// with the trace's random streams, so that a point equals a trace of the
    /// scene set to that angle and energy; a window of `window` pixels around
    /// each image's centroid, normalised to 1. Energies and angles may be
    /// astropy Quantities. With `out` (a folder) the library writes the files
    /// of `traxer psf --out` there and records each point as it finishes:
    /// Ctrl-C stops it after the current point (KeyboardInterrupt, with a
    /// note), and the same call with `resume=True` takes up the recorded
    /// points. Returns a `traxer.PsfLibrary`.
    #[pyo3(signature = (energies_keV, angles_arcmin = None, azimuths_deg = None, photons = None, seed = 1, threads = 0, sensor = None, window = 101, progress = false, out = None, resume = false))]
    #[allow(non_snake_case, clippy::too_many_arguments)]
    fn psf_library(
        &self,
        py: Python<'_>,
        energies_keV: &Bound<'_, PyAny>,
        angles_arcmin: Option<&Bound<'_, PyAny>>,
        azimuths_deg: Option<&Bound<'_, PyAny>>,
        photons: Option<&Bound<'_, PyAny>>,
        seed: u64,
        threads: usize,
        sensor: Option<String>,
        window: u32,
        progress: bool,
        out: Option<PathBuf>,
        resume: bool,
    ) -> PyResult<crate::psf::PsfLibrary> {
        let listed = |name: &str, v: Option<&Bound<'_, PyAny>>, unit: Unit| match v
            .filter(|a| !a.is_none())
        {
            Some(a) => numbers(name, a, unit),
            None => Ok(vec![0.0]),
        };
        let grid = traxer::studies::psf::PsfGrid {
            energies: numbers("energies_keV", energies_keV, Unit::KeV)?,
            angles_arcmin: listed("angles_arcmin", angles_arcmin, Unit::Arcmin)?,
            azimuths_deg: listed("azimuths_deg", azimuths_deg, Unit::Degree)?,
            sampling: sampling((photons, 200_000), seed, threads, sensor)?,
            window,
        };
        crate::psf::run(py, self.loaded.clone(), grid, (out, resume), progress)
    }

    /// The figure-error fit, as `traxer fit-figure-error`: the figure-error
    /// parameters of every mirror fitted to the measured `target_hpd`,
    /// `target_c80` and `target_c90` (arcsec), each evaluation traced with the
    /// same `photons` (default 1 000 000) and `seed`; DIRECT-L over `bounds`
    /// ({name: (low, high)} or {name: value} to hold it; defaults
    /// in_plane_narrow 0–120, in_plane_wide 0–900, wide_fraction 0–0.6,
    /// out_of_plane 0) for `global_evals`, then `local_algorithm` ("sbplx",
    /// "bobyqa" or "nelder_mead") for `local_evals`; then the spread over
    /// `check_seeds` more seeds, the parameters' errors for a `target_error`
    /// (per cent) and each scene of `predict` with `predict_seeds` seeds. With
    /// `out` (a folder) the fit writes the files of `traxer fit-figure-error
    /// --out` there and records each evaluation: Ctrl-C stops it, and
    /// `resume=True` takes up the recorded evaluations. Returns a
    /// `traxer.FigureErrorFit`.
    #[pyo3(signature = (target_hpd, target_c80, target_c90, bounds = None, global_evals = 150, local_evals = 60, local_algorithm = "sbplx", check_seeds = 3, target_error = 2.0, predict = None, predict_seeds = 4, name = "fitted", photons = None, seed = 1, threads = 0, sensor = None, progress = false, out = None, resume = false))]
    #[allow(clippy::too_many_arguments)]
    fn fit_figure_error(
        &self,
        py: Python<'_>,
        target_hpd: f64,
        target_c80: f64,
        target_c90: f64,
        bounds: Option<std::collections::BTreeMap<String, Bound<'_, PyAny>>>,
        global_evals: u32,
        local_evals: u32,
        local_algorithm: &str,
        check_seeds: u64,
        target_error: f64,
        predict: Option<Vec<PathBuf>>,
        predict_seeds: u64,
        name: &str,
        photons: Option<&Bound<'_, PyAny>>,
        seed: u64,
        threads: usize,
        sensor: Option<String>,
        progress: bool,
        out: Option<PathBuf>,
        resume: bool,
    ) -> PyResult<crate::fit::FigureErrorFit> {
        use traxer::studies::fit::{Bounds, LocalAlgorithm, PARAMETERS};
        let run = run_config(&sampling((photons, 1_000_000), seed, threads, None)?);
        let mut b = Bounds::default();
        for (key, value) in bounds.unwrap_or_default() {
            let Some(i) = PARAMETERS.iter().position(|p| *p == key) else {
                return Err(crate::errors::input(format!(
                    "bounds: {key:?} is not a parameter (expected one of {})",
                    PARAMETERS.join(", ")
                )));
            };
            let (lo, hi) = match value.extract::<(f64, f64)>() {
                Ok(pair) => pair,
                Err(_) => {
                    let v: f64 = value.extract().map_err(|_| {
                        crate::errors::input(format!(
                            "bounds[{key:?}]: expected (low, high) or a value"
                        ))
                    })?;
                    (v, v)
                }
            };
            b.lower[i] = lo;
            b.upper[i] = hi;
        }
        let local_algorithm = match local_algorithm {
            "sbplx" => LocalAlgorithm::Sbplx,
            "bobyqa" => LocalAlgorithm::Bobyqa,
            "nelder_mead" => LocalAlgorithm::NelderMead,
            other => {
                return Err(crate::errors::input(format!(
                    "local_algorithm {other:?}: expected \"sbplx\", \"bobyqa\" or \"nelder_mead\""
                )))
            }
        };
        let scene = &self.loaded.scene;
        let settings = traxer::studies::fit::FitSettings {
            bounds: b,
            target: traxer::studies::Diameters {
                hpd: target_hpd,
                d80: target_c80,
                d90: target_c90,
            },
            run,
            sensor: traxer::studies::pick_sensor(scene, sensor.as_deref())
                .map_err(crate::errors::lib)?,
            global_evaluations: global_evals,
            local_evaluations: local_evals,
            local_algorithm,
        };
        let after = traxer::studies::fit_study::AfterFit {
            check_seeds,
            target_fraction: target_error / 100.0,
            predict_seeds,
            preset_name: name.to_string(),
        };
        let predict = (predict.unwrap_or_default(), sensor);
        crate::fit::run(
            py,
            self.loaded.clone(),
            (settings, after),
            predict,
            (out, resume),
            progress,
        )
    }

    /// The focus scan, as `traxer focus`: the scene traced at `steps` values
    /// of the variable `var` (declared in its [vars], e.g. "sensor_z"),
    /// evenly spaced from `start` to `stop`, `photons` photons each (default
    /// 1 000 000), the diameters measured and a defocus curve fitted to each.
    /// With `out` (a folder) the scan writes the files of `traxer focus --out`
    /// there and records each position: Ctrl-C stops it after the current
    /// position, and `resume=True` takes up the recorded ones. Returns a
    /// `traxer.FocusScan`.
    #[pyo3(signature = (start, stop, var = "sensor_z", steps = 13, photons = None, seed = 1, threads = 0, sensor = None, progress = false, out = None, resume = false))]
    #[allow(clippy::too_many_arguments)]
    fn focus(
        &self,
        py: Python<'_>,
        start: f64,
        stop: f64,
        var: &str,
        steps: usize,
        photons: Option<&Bound<'_, PyAny>>,
        seed: u64,
        threads: usize,
        sensor: Option<String>,
        progress: bool,
        out: Option<PathBuf>,
        resume: bool,
    ) -> PyResult<crate::focus::FocusScan> {
        let s = sampling((photons, 1_000_000), seed, threads, sensor)?;
        let cfg = run_config(&s);
        let sweep = traxer::studies::focus::FocusSweep {
            var: var.to_string(),
            from: start,
            to: stop,
            steps,
            sensor: s.sensor,
        };
        crate::focus::run(
            py,
            self.loaded.clone(),
            (sweep, cfg),
            (out, resume),
            progress,
        )
    }

    /// The analytic scene against meshes of it, as `traxer compare`: the scene
    /// traced with its analytic objects exact, then tessellated at each of
    /// `resolutions` ("SEGMENTSxRINGS" strings, e.g. "120x4"; default those of
    /// the command), then each scene file of `also` as written (with this
    /// scene's variables), all with the same photons (default 2 000 000 per
    /// run). With `out` (a folder) the comparison writes the files of `traxer
    /// compare --out` there and records each row: Ctrl-C stops it after the
    /// current row, and `resume=True` takes up the recorded ones. Returns a
    /// `traxer.Comparison`.
    #[pyo3(signature = (resolutions = None, also = None, photons = None, seed = 1, threads = 0, sensor = None, progress = false, out = None, resume = false))]
    #[allow(clippy::too_many_arguments)]
    fn compare(
        &self,
        py: Python<'_>,
        resolutions: Option<Vec<String>>,
        also: Option<Vec<PathBuf>>,
        photons: Option<&Bound<'_, PyAny>>,
        seed: u64,
        threads: usize,
        sensor: Option<String>,
        progress: bool,
        out: Option<PathBuf>,
        resume: bool,
    ) -> PyResult<crate::compare::Comparison> {
        use traxer::studies::compare::{DEFAULT_PHOTONS, DEFAULT_RESOLUTIONS};
        let resolutions = resolutions
            .unwrap_or_else(|| DEFAULT_RESOLUTIONS.split(',').map(String::from).collect())
            .iter()
            .map(|r| {
                r.parse()
                    .map_err(|e: String| crate::errors::input(format!("resolutions: {e}")))
            })
            .collect::<PyResult<Vec<_>>>()?;
        let runs = crate::compare::Variants {
            resolutions,
            also: also.unwrap_or_default(),
        };
        let sampling = sampling((photons, DEFAULT_PHOTONS), seed, threads, sensor)?;
        crate::compare::run(
            py,
            self.loaded.clone(),
            runs,
            sampling,
            (out, resume),
            progress,
        )
    }

    /// The image's systematic uncertainty, as `traxer systematics`: the scene
    /// traced under each source of uncertainty with the same photons. Sources
    /// (default: every one the scene's variables support): "figure" (
    /// `figure_draws` parameter sets from the preset's covariance),
    /// "optical_constants" (the coatings' f1, f2 from Chantler's table instead
    /// of Henke's), "solar_model", "pointing_x"/"pointing_y" (± `pointing_arcmin`),
    /// "tilt_x"/"tilt_y" (± `tilt_arcmin`), "gas_pressure"/"gas_temperature"
    /// (ranges (low, high), default the scene's ± 50 mbar, ± 10 K); `vary`: a
    /// dict of other scene variables and their (low, high). The table's
    /// "central" flux is in the `central_mm` square about the sensor's centre,
    /// or with `central_radius_mm` in that circle (a signal region). With
    /// `out` (a folder) the study writes the files of `traxer systematics
    /// --out` there and records each variation: Ctrl-C stops it after the
    /// current variation, and `resume=True` takes up the recorded ones. Returns
    /// a `traxer.Systematics`.
    #[pyo3(signature = (photons = None, seed = 1, threads = 0, sensor = None, sources = None, figure_draws = 20, figure_preset = None, figure_hold = None, pointing_arcmin = 1.0, tilt_arcmin = 1.0, solar_model = "b16_gs98", gas_pressure_mbar = None, gas_temperature_k = None, vary = None, central_mm = 5.0, central_radius_mm = None, progress = false, out = None, resume = false))]
    #[allow(clippy::too_many_arguments)]
    fn systematics(
        &self,
        py: Python<'_>,
        photons: Option<&Bound<'_, PyAny>>,
        seed: u64,
        threads: usize,
        sensor: Option<String>,
        sources: Option<Vec<String>>,
        figure_draws: usize,
        figure_preset: Option<String>,
        figure_hold: Option<Vec<String>>,
        pointing_arcmin: f64,
        tilt_arcmin: f64,
        solar_model: &str,
        gas_pressure_mbar: Option<(f64, f64)>,
        gas_temperature_k: Option<(f64, f64)>,
        vary: Option<std::collections::BTreeMap<String, (f64, f64)>>,
        central_mm: f64,
        central_radius_mm: Option<f64>,
        progress: bool,
        out: Option<PathBuf>,
        resume: bool,
    ) -> PyResult<crate::systematics::Systematics> {
        let pair = |p: (f64, f64)| [p.0, p.1];
        for (what, x) in [
            ("pointing_arcmin", pointing_arcmin),
            ("tilt_arcmin", tilt_arcmin),
        ] {
            if !(x.is_finite() && x > 0.0) {
                return Err(crate::errors::input(format!(
                    "{what} = {x}: expected a positive angle in arcmin"
                )));
            }
        }
        for (what, r) in [
            ("gas_pressure_mbar", gas_pressure_mbar),
            ("gas_temperature_k", gas_temperature_k),
        ] {
            if let Some((l, h)) = r {
                if !(l.is_finite() && h.is_finite() && l < h) {
                    return Err(crate::errors::input(format!(
                        "{what} = ({l}, {h}): expected (low, high) with low < high"
                    )));
                }
            }
        }
        let req = traxer::studies::systematics::Request {
            sources,
            figure_draws,
            figure_preset,
            figure_hold,
            pointing_arcmin,
            tilt_arcmin,
            solar_model: solar_model.to_string(),
            gas_pressure_mbar: gas_pressure_mbar.map(pair),
            gas_temperature_k: gas_temperature_k.map(pair),
            vary: vary
                .unwrap_or_default()
                .into_iter()
                .map(|(k, v)| (k, pair(v)))
                .collect(),
            seed,
        };
        let settings = traxer::studies::systematics::Settings {
            sampling: traxer::studies::Sampling {
                photons: match photons {
                    Some(p) => crate::convert::count("photons", p, 1)?,
                    None => 1_000_000,
                },
                seed,
                threads: self::threads(threads)?,
                sensor,
            },
            central_mm: central_radius_mm.unwrap_or(central_mm),
            central_circle: central_radius_mm.is_some(),
        };
        let place = (out, resume);
        crate::systematics::run(py, self.loaded.clone(), (req, settings), place, progress)
    }
}

impl Scene {
    /// `trace` into the results folder `out` (`traxer::run::TraceJob`), keeping
    /// a checkpoint there every `every` and replacing a run of other inputs
    /// only if `replace`.
    fn trace_to_folder(
        &self,
        py: Python<'_>,
        (cfg, out): (RunConfig, &std::path::Path),
        (every, replace): (Option<std::time::Duration>, bool),
        progress: bool,
        invocation: &Invocation,
    ) -> PyResult<TraceResult> {
        let job = TraceJob {
            scene: &self.loaded.scene,
            embree_version: self.loaded.device.info().version,
            shard: Shard::whole(cfg.photons),
            cfg,
        };
        let settings = RunSettings {
            threads: job.cfg.threads,
            checkpoint_every: every,
            fits: false,
            replace,
        };
        let control = PyControl::new(job.cfg.photons, progress);
        let finished = py.detach(|| job.run(out, &settings, invocation, &control));
        control.bar.finish_and_clear();
        let finished = finished.map_err(|e| control.error(e))?;
        let threads = finished.result.threads;
        finished_result(py, self.loaded.clone(), out, invocation, threads)
    }
}

/// A study's sampling block from its keyword arguments (photons: an int or a
/// whole float; `default` when not given).
fn sampling(
    (photons, default): (Option<&Bound<'_, PyAny>>, u64),
    seed: u64,
    threads: usize,
    sensor: Option<String>,
) -> PyResult<traxer::studies::Sampling> {
    Ok(traxer::studies::Sampling {
        photons: match photons {
            Some(p) => crate::convert::count("photons", p, 2)?,
            None => default,
        },
        seed,
        threads: self::threads(threads)?,
        sensor,
    })
}

/// The run of each point of a study that traces whole runs (focus, fit).
fn run_config(s: &traxer::studies::Sampling) -> traxer::trace::RunConfig {
    let mut cfg = traxer::trace::RunConfig::new(s.photons, s.seed);
    cfg.threads = s.threads;
    cfg
}
