//! Analytic versus meshed: one scene traced with its analytic objects exact and
//! tessellated at several resolutions (and other scene files, e.g. one built from
//! exported meshes), all with the same seed, so that differences in image quality,
//! photons on the sensor and speed are not Monte Carlo noise. A study the job
//! runs ([`CompareStudy`]): each variant's row is recorded as it is done, so a
//! stopped comparison resumes at the next variant.

use super::{
    pick_sensor, require_sources, trace_and_measure, Measured, PointOrigin, Sampling, StudyError,
    StudyKind,
};
use crate::geometry::Resolution;
use crate::progress::Progress;
use crate::scene::{Representation, Scene};
use crate::trace::RunConfig;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The tessellations compared by default (`traxer compare`, Python's
/// `Scene.compare`): from coarse to converged on the shipped telescopes.
pub const DEFAULT_RESOLUTIONS: &str = "4x1,8x1,15x1,30x1,60x2,120x4";

/// Photons per variant by default (the same as `traxer compare -n`'s).
pub const DEFAULT_PHOTONS: u64 = 2_000_000;

/// One traced variant: its label, scene file and representation.
#[derive(Clone, Debug)]
pub struct Variant {
    pub label: String,
    pub path: PathBuf,
    pub representation: Representation,
}

/// The variants of a comparison: `scene` exact ("analytic", the reference), then
/// tessellated at each resolution ("mesh SxR"), then each of `also` as written.
pub fn variants(scene: &Path, resolutions: &[Resolution], also: &[PathBuf]) -> Vec<Variant> {
    let mut v = vec![Variant {
        label: "analytic".into(),
        path: scene.to_path_buf(),
        representation: Representation::Analytic,
    }];
    for r in resolutions {
        v.push(Variant {
            label: format!("mesh {}x{}", r.segments, r.rings),
            path: scene.to_path_buf(),
            representation: Representation::Tessellated(*r),
        });
    }
    for f in also {
        v.push(Variant {
            label: f.display().to_string(),
            path: f.clone(),
            representation: Representation::AsWritten,
        });
    }
    v
}

/// One variant traced and measured: the study's point.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Row {
    pub label: String,
    pub path: PathBuf,
    pub triangles: usize,
    pub measured: Measured,
}

/// Builds a scene file in a representation (with the front end's variables).
pub type VariantLoader<'a> =
    &'a (dyn Fn(&Path, Representation) -> Result<Scene, StudyError> + Sync);

/// The comparison as a study: its sampling and variants (by label) are its
/// identity.
#[derive(Serialize)]
pub struct CompareStudy<'a> {
    #[serde(flatten)]
    pub sampling: Sampling,
    #[serde(serialize_with = "labels")]
    pub variants: Vec<Variant>,
    #[serde(skip)]
    cfg: RunConfig,
    #[serde(skip)]
    load: VariantLoader<'a>,
}

fn labels<S: serde::Serializer>(variants: &[Variant], s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(variants.iter().map(|v| &v.label))
}

impl<'a> CompareStudy<'a> {
    /// `variants` traced with `sampling`'s photons, seed and threads, measured
    /// on its sensor (default: each scene's only one); `load` builds each.
    pub fn new(
        variants: Vec<Variant>,
        sampling: Sampling,
        load: VariantLoader<'a>,
    ) -> CompareStudy<'a> {
        let mut cfg = RunConfig::new(sampling.photons, sampling.seed);
        cfg.threads = sampling.threads;
        CompareStudy {
            sampling,
            variants,
            cfg,
            load,
        }
    }
}

impl StudyKind for CompareStudy<'_> {
    type Point = Row;
    type Output = Vec<Row>;
    const NAME: &'static str = "compare";
    const POINTS: &'static str = "variants";

    fn sampling(&self) -> &Sampling {
        &self.sampling
    }

    fn check(&self) -> Result<(), StudyError> {
        Ok(())
    }

    fn photons_total(&self, _scene: &Scene) -> u64 {
        let n = self.variants.len() as u64;
        self.cfg.photons.saturating_mul(n)
    }

    /// Traces every variant and measures its sensor. The first row (the
    /// analytic scene) is the reference and must have an image.
    fn run(
        &self,
        scene: &Scene,
        replay: &[Row],
        progress: &dyn Progress,
        on_point: &mut dyn FnMut(&Row, PointOrigin),
    ) -> Result<Vec<Row>, StudyError> {
        let mut rows = Vec::with_capacity(self.variants.len());
        for (k, v) in self.variants.iter().enumerate() {
            let (row, origin) = match replay.get(k).filter(|r| r.label == v.label) {
                Some(r) => {
                    progress.advance(self.cfg.photons);
                    (r.clone(), PointOrigin::Record)
                }
                None => (self.trace(scene, v, progress)?, PointOrigin::Traced),
            };
            on_point(&row, origin);
            if k == 0 && row.measured.quality.is_none() {
                return Err(StudyError::Input(
                    "no photon reached the sensor in the analytic run: nothing to compare".into(),
                ));
            }
            rows.push(row);
            if progress.stop_requested() && rows.len() < self.variants.len() {
                return Err(StudyError::Stopped);
            }
        }
        Ok(rows)
    }

    fn threads_used(rows: &Vec<Row>) -> usize {
        rows.first().map_or(0, |r| r.measured.threads)
    }

    fn describe(&self, r: &Row) -> Option<String> {
        let hpd = r
            .measured
            .quality
            .as_ref()
            .map_or("-".into(), |q| format!("{:.4} mm", q.hpd_mm));
        Some(format!(
            "{}: {} triangles, {:.2} s, HPD {hpd}",
            r.label, r.triangles, r.measured.seconds
        ))
    }
}

impl CompareStudy<'_> {
    /// One variant traced: on `shown` (the front end's load) when it is that
    /// variant, else on a scene loaded here.
    fn trace(
        &self,
        shown: &Scene,
        v: &Variant,
        progress: &dyn Progress,
    ) -> Result<Row, StudyError> {
        let loaded;
        let scene = if v.representation == shown.representation && v.path == shown.path {
            shown
        } else {
            loaded = (self.load)(&v.path, v.representation)?;
            &loaded
        };
        require_sources(scene)?;
        let sensor = pick_sensor(scene, self.sampling.sensor.as_deref())?;
        Ok(Row {
            label: v.label.clone(),
            path: v.path.clone(),
            triangles: scene.triangle_count,
            measured: trace_and_measure(scene, sensor, &self.cfg, progress)?,
        })
    }
}
