//! Analytic versus meshed: one scene traced with its analytic objects exact and
//! tessellated at several resolutions (and other scene files, e.g. one built from
//! exported meshes), all with the same seed, so that differences in image quality,
//! photons on the sensor and speed are not Monte Carlo noise.

use super::{pick_sensor, require_sources, trace_and_measure, Measured, StudyError};
use crate::geometry::Resolution;
use crate::progress::Progress;
use crate::scene::{Representation, Scene};
use crate::trace::RunConfig;
use std::path::{Path, PathBuf};

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

/// One variant traced and measured.
#[derive(Clone, Debug)]
pub struct Row {
    pub label: String,
    pub path: PathBuf,
    pub triangles: usize,
    pub measured: Measured,
}

/// Traces every variant (`load` builds a scene file in a representation) and
/// measures `sensor` (default: the only one); `on_row` sees each row when done.
/// The first row is the reference and must have an image.
pub fn compare(
    mut load: impl FnMut(&Path, Representation) -> Result<Scene, StudyError>,
    variants: &[Variant],
    sensor: Option<&str>,
    cfg: &RunConfig,
    progress: &dyn Progress,
    mut on_row: impl FnMut(&Row),
) -> Result<Vec<Row>, StudyError> {
    let mut rows = Vec::with_capacity(variants.len());
    for v in variants {
        let scene = load(&v.path, v.representation)?;
        require_sources(&scene)?;
        let sensor = pick_sensor(&scene, sensor)?;
        let measured = trace_and_measure(&scene, sensor, cfg, progress)?;
        let row = Row {
            label: v.label.clone(),
            path: v.path.clone(),
            triangles: scene.triangle_count,
            measured,
        };
        on_row(&row);
        rows.push(row);
    }
    if rows.first().is_some_and(|r| r.measured.quality.is_none()) {
        return Err(StudyError::Input(
            "no photon reached the sensor in the analytic run: nothing to compare".into(),
        ));
    }
    Ok(rows)
}
