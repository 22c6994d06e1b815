//! Studies: scene parameters → trace → measure, repeated — focus scans
//! ([`focus`]), analytic-versus-mesh comparisons ([`compare`]) and the
//! figure-error fit ([`fit`], its errors and predictions [`fit_errors`]), the effective area ([`effective_area`]), the PSF library ([`psf`]). Each
//! traces through `trace`, measures with `analysis`, reports progress through a
//! callback and returns plain results; `output` writes them and the binary
//! prints them.

mod area_sweep;
pub mod campaign_reach;
pub mod compare;
pub mod effective_area;
pub mod fit;
pub mod fit_errors;
pub mod fit_study;
pub mod focus;
pub mod kind;
mod measure;
mod parallel_beam;
pub mod psf;
pub mod reach;
pub mod sky;
pub mod systematics;

pub use kind::{PointOrigin, Sampling, SceneLoader, StudyKind};
pub use measure::{measure_arcsec, pick_sensor, trace_and_measure, Diameters, Measured};

use crate::scene::{Scene, SceneError};

/// Why a study could not run.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A problem with what the user asked (a sensor, a range, a setting).
    #[error("{0}")]
    Input(String),
    /// The fit's optimiser refused its settings.
    #[error("{0}")]
    Optimiser(String),
    #[error("cannot start the worker threads: {0}")]
    Threads(#[from] rayon::ThreadPoolBuildError),
    /// Stopped between points on request ([`crate::progress::Progress::stop_requested`]).
    #[error("stopped")]
    Stopped,
}

impl StudyError {
    /// Whether the user's input is at fault (rather than the machine).
    pub fn is_bad_input(&self) -> bool {
        match self {
            StudyError::Scene(e) => e.is_bad_input(),
            StudyError::Input(_) => true,
            _ => false,
        }
    }
}

/// Studies trace X-rays: a scene without sources (made for renders) is refused.
pub fn require_sources(scene: &Scene) -> Result<(), StudyError> {
    if scene.sources.is_empty() {
        return Err(StudyError::Input(format!(
            "{}: the scene has no [[sources]]: nothing to trace (a scene without sources can only be rendered)",
            scene.path.display()
        )));
    }
    Ok(())
}
