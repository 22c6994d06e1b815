//! The LLNL telescope of CAST as a built-in assembly: its data (radii, lengths,
//! coatings per shell, from data/llnl_telescope.toml) and its expansion into scene
//! objects — per shell a front and a rear mirror (cone segments reflecting on the
//! inside), the glass behind each (an absorbing cone `glass_thickness` further out)
//! and the glass edges at both ends of each mirror (absorbing annulus segments), so
//! photons that hit the back or the edges of the glass are lost as in reality.
//!
//! Data flow: `scene::assemblies` calls [`LlnlTelescope::parts`] for every
//! `[[assemblies]]` entry of type `llnl_telescope`; the scene build then builds
//! the parts like any other objects.

use super::placement::TransformStep;
use super::shapes::{ConeDesc, DiskDesc, ShapeDesc};
use crate::history::MirrorStage;
use serde::Deserialize;

const SHIPPED: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/data/llnl_telescope.toml"
));

message_error!(
    /// Telescope data (radii, lengths) that describe no telescope.
    InvalidTelescopeData
);

/// One shell: radii (mm) and the coating of both its mirrors.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Shell {
    pub r1: f64,
    pub r2: f64,
    pub r4: f64,
    pub r5: f64,
    pub coating: String,
}

/// The telescope data.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LlnlTelescope {
    pub focal_length_mm: f64,
    pub mirror_length_mm: f64,
    pub gap_mm: f64,
    pub azimuth_span_deg: f64,
    pub glass_thickness_mm: f64,
    pub shells: Vec<Shell>,
}

/// What an expanded object is made of.
#[derive(Clone, Debug, PartialEq)]
pub enum PartMaterial {
    /// A reflecting mirror face with this coating.
    Mirror(String),
    /// Glass back or edge.
    Absorber,
}

/// One object of the expanded assembly, in the telescope's frame.
#[derive(Clone, Debug)]
pub struct Part {
    pub name: String,
    pub shape: ShapeDesc,
    pub material: PartMaterial,
    /// Placement within the telescope frame (before the assembly's transform).
    pub transform: Vec<TransformStep>,
    /// The shell the part belongs to (0 = innermost).
    pub shell: usize,
    /// For a mirror face: front (primary) or rear (secondary).
    pub stage: Option<MirrorStage>,
}

impl LlnlTelescope {
    /// The shipped data (data/llnl_telescope.toml).
    pub fn shipped() -> LlnlTelescope {
        toml::from_str(SHIPPED).expect("data/llnl_telescope.toml is valid (tested)")
    }

    pub fn from_toml(text: &str) -> Result<LlnlTelescope, toml::de::Error> {
        toml::from_str(text)
    }

    /// Front cone angle α of shell i (0-based), radians.
    pub fn alpha(&self, i: usize) -> f64 {
        ((self.shells[i].r1 - self.shells[i].r2) / self.mirror_length_mm).asin()
    }

    /// Rear cone angle of shell i, radians.
    pub fn alpha_rear(&self, i: usize) -> f64 {
        ((self.shells[i].r4 - self.shells[i].r5) / self.mirror_length_mm).asin()
    }

    /// How far the predecessor TrAXer puts shell i's cone axis from shell 1's, in
    /// mm, outwards along the segment centre: ((R1 − R2)_i − (R1 − R2)_1)/2, 0 for
    /// shell 1 and 0.72 mm for shell 13 of the LLNL data. TrAXer offsets each shell
    /// by (R1 − R2)/2 from the common axis; the part all shells share only moves the
    /// whole image, so only the difference to shell 1 is applied. The foci of the
    /// shells then no longer coincide and the image grows: with this placement the
    /// perfect-mirror PANTER image reproduces TrAXer's HPD / 80 % / 90 % within 1″
    /// (README, "The solar axion image"); moving the axes inwards instead does not.
    pub fn traxer_axis_offset(&self, i: usize) -> f64 {
        let d = |s: &Shell| s.r1 - s.r2;
        0.5 * (d(&self.shells[i]) - d(&self.shells[0]))
    }

    /// Checks the numbers make a telescope.
    pub fn validate(&self) -> Result<(), InvalidTelescopeData> {
        let pos = |x: f64| x.is_finite() && x > 0.0;
        let valid = pos(self.focal_length_mm)
            && pos(self.mirror_length_mm)
            && self.gap_mm >= 0.0
            && pos(self.glass_thickness_mm)
            && self.azimuth_span_deg > 0.0
            && self.azimuth_span_deg <= 360.0;
        if !valid {
            return Err("focal length, mirror length and glass thickness must be > 0, gap ≥ 0, azimuth span in (0, 360]".into());
        }
        if self.shells.is_empty() {
            return Err("no shells".into());
        }
        for (i, s) in self.shells.iter().enumerate() {
            if !([s.r1, s.r2, s.r4, s.r5].into_iter().all(pos) && s.r1 > s.r2 && s.r4 > s.r5)
                || s.r1 - s.r2 >= self.mirror_length_mm
                || s.r4 - s.r5 >= self.mirror_length_mm
            {
                return Err(InvalidTelescopeData::from(format!("shell {}: need r1 > r2 > 0 and r4 > r5 > 0 with differences below the mirror length", i + 1)));
            }
        }
        Ok(())
    }

    /// The assembly's objects: per shell `front_i`, `front_i_back`, `front_i_edge_top`,
    /// `front_i_edge_bottom`, and the same for `rear_i` (i from 1). The segment is
    /// centred on azimuth `azimuth_center_deg`. `coating` overrides every shell's
    /// coating (e.g. "perfect").
    pub fn parts(&self, azimuth_center_deg: f64, coating: Option<&str>) -> Vec<Part> {
        let half = 0.5 * self.azimuth_span_deg;
        let az = Some([azimuth_center_deg - half, azimuth_center_deg + half]);
        let t = self.glass_thickness_mm;
        let l = self.mirror_length_mm;
        let mut parts = Vec::new();
        for (i, s) in self.shells.iter().enumerate() {
            let coat = coating.unwrap_or(&s.coating).to_string();
            let n = i + 1;
            // (name, radius at z_near, radius at z_far, z_near, z_far): z_near at
            // the centre plane side.
            let (a, ar) = (self.alpha(i), self.alpha_rear(i));
            let z0 = 0.5 * self.gap_mm;
            let mirrors = [
                (
                    format!("front_{n}"),
                    s.r2,
                    s.r1,
                    z0,
                    z0 + l * a.cos(),
                    a,
                    MirrorStage::Front,
                ),
                (
                    format!("rear_{n}"),
                    s.r4,
                    s.r5,
                    -z0,
                    -z0 - l * ar.cos(),
                    ar,
                    MirrorStage::Rear,
                ),
            ];
            for (name, r_near, r_far, z_near, z_far, angle, stage) in mirrors {
                // The glass lies outside the reflecting face; its thickness measured
                // perpendicular to the face is t, radially t / cos(angle).
                let dr = t / angle.cos();
                let cone = |r0: f64, r1: f64| {
                    ShapeDesc::Cone(ConeDesc {
                        radius_start: r0,
                        z_start: z_near,
                        radius_end: r1,
                        z_end: z_far,
                        azimuth: az,
                    })
                };
                parts.push(Part {
                    name: name.clone(),
                    shape: cone(r_near, r_far),
                    material: PartMaterial::Mirror(coat.clone()),
                    transform: vec![],
                    shell: i,
                    stage: Some(stage),
                });
                parts.push(Part {
                    name: format!("{name}_back"),
                    shape: cone(r_near + dr, r_far + dr),
                    material: PartMaterial::Absorber,
                    transform: vec![],
                    shell: i,
                    stage: None,
                });
                for (edge, r, z) in [("edge_far", r_far, z_far), ("edge_near", r_near, z_near)] {
                    parts.push(Part {
                        name: format!("{name}_{edge}"),
                        shape: ShapeDesc::Disk(DiskDesc {
                            radius: r + dr,
                            inner_radius: r,
                            azimuth: az,
                        }),
                        material: PartMaterial::Absorber,
                        transform: vec![TransformStep::Translate([0.0, 0.0, z])],
                        shell: i,
                        stage: None,
                    });
                }
            }
        }
        parts
    }
}
