//! Where objects are: the `transform = [ ... ]` steps of objects and assemblies,
//! checked and composed into a `geometry::Transform`.

use crate::geometry::{Transform, WORLD_LIMIT_MM};
use glam::{DAffine3, DVec3};
use serde::Deserialize;
use toml::Spanned;

/// A placement step; a list of them is applied in order (the first one acts on
/// the shape's local frame first).
///
/// ```toml
/// { translate = [x, y, z] }
/// { rotate = { axis = [x, y, z], angle = 30.0 } }   # degrees, right-handed
/// { scale = 2.0 }  or  { scale = [sx, sy, sz] }
/// ```
#[derive(Debug, Deserialize, Clone)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum TransformStep {
    Translate([f64; 3]),
    Rotate(RotateDesc),
    Scale(ScaleDesc),
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct RotateDesc {
    pub axis: [f64; 3],
    /// Degrees.
    pub angle: f64,
}

#[derive(Debug, Deserialize, Clone)]
#[serde(untagged)]
pub enum ScaleDesc {
    Uniform(f64),
    PerAxis([f64; 3]),
}

impl TransformStep {
    /// The step as an affine map, or what is wrong with it.
    fn affine(&self) -> Result<DAffine3, String> {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        match self {
            TransformStep::Translate(t) if finite(t) => {
                if let Some(i) = t.iter().position(|x| x.abs() > WORLD_LIMIT_MM) {
                    return Err(format!("translate[{i}] = {:e} mm: beyond ±{WORLD_LIMIT_MM:e} mm of the origin, where traxer traces (float32 geometry); check the units", t[i]));
                }
                Ok(DAffine3::from_translation(DVec3::from(*t)))
            }
            TransformStep::Rotate(r) if finite(&r.axis) && r.angle.is_finite() => {
                let Some(axis) = DVec3::from(r.axis).try_normalize() else {
                    return Err("rotate: axis must not be zero".into());
                };
                Ok(DAffine3::from_axis_angle(axis, r.angle.to_radians()))
            }
            TransformStep::Scale(s) => {
                let v = match s {
                    ScaleDesc::Uniform(k) => DVec3::splat(*k),
                    ScaleDesc::PerAxis(a) => DVec3::from(*a),
                };
                if !v.is_finite() || v.x * v.y * v.z == 0.0 {
                    return Err("scale: factors must be finite and non-zero".into());
                }
                Ok(DAffine3::from_scale(v))
            }
            _ => Err("transform values must be finite numbers".into()),
        }
    }
}

/// The steps composed in order; an error names the span of the bad step.
pub fn transform(
    steps: &[Spanned<TransformStep>],
) -> Result<Transform, (std::ops::Range<usize>, String)> {
    let mut m = DAffine3::IDENTITY;
    for step in steps {
        m = step.get_ref().affine().map_err(|e| (step.span(), e))? * m;
    }
    Ok(Transform::from_affine(m))
}
