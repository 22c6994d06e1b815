//! A nested telescope's expansion into scene objects, in the telescope's frame
//! (optical axis z towards the source, intersection plane z = 0): per shell a
//! front and a rear mirror reflecting on the inside, the wall behind each (an
//! absorbing surface the wall's thickness further out) and the wall's end faces
//! (absorbing annuli), so photons that hit the back or the ends of a shell are
//! lost as in reality; then the entrance spider's arms and, if asked, a central
//! stop.
//!
//! Data flow: `scene::assemblies` calls [`Telescope::parts`] for every
//! `nested_telescope` assembly; the scene build then builds the parts like any
//! other objects.

use super::mirror_surface::MirrorSurfaceDesc;
use super::placement::TransformStep;
use super::shapes::{ConeDesc, DiskDesc, HyperboloidDesc, ParaboloidDesc, ShapeDesc};
use super::telescope::{Profile, Telescope};
use crate::history::MirrorStage;

/// What an expanded object is made of.
#[derive(Clone, Debug)]
pub enum PartMaterial {
    /// A reflecting mirror face with the shell's surface (its coating
    /// resolved: the scene's for every shell, the shell's or the telescope's;
    /// its own figure errors and roughness where the data gives them).
    Mirror(MirrorSurfaceDesc),
    /// A wall's back or end, a spider arm, the central stop.
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
    /// The shell the part belongs to (0 = innermost); none for the spider and
    /// the central stop.
    pub shell: Option<usize>,
    /// For a mirror face: front (primary) or rear (secondary).
    pub stage: Option<MirrorStage>,
}

/// What a scene chooses about the parts.
#[derive(Clone, Copy, Debug, Default)]
pub struct PartChoices<'a> {
    /// Azimuth (degrees) the segments are centred on.
    pub azimuth_center_deg: f64,
    /// One coating for every shell, replacing each shell's own.
    pub coating: Option<&'a str>,
    /// The spider's distance in front of the entrance (mm), when it has one;
    /// `None` leaves the spider out.
    pub spider_distance_mm: Option<f64>,
    /// An absorbing disk filling the innermost shell's opening at the entrance.
    pub central_stop: bool,
}

/// One mirror surface between z_near (the intersection-plane side) and z_far.
struct Mirror {
    name: String,
    shape: ShapeDesc,
    transform: Vec<TransformStep>,
    /// Radius, height and the wall's radial thickness at z_near and z_far.
    near: (f64, f64, f64),
    far: (f64, f64, f64),
    stage: MirrorStage,
}

impl Telescope {
    /// The assembly's objects: per shell `front_i`, `front_i_back`,
    /// `front_i_edge_far`, `front_i_edge_near` (only with a gap between the
    /// mirrors: without one the two walls meet), the same for `rear_i` (i from
    /// 1); then `spider_1` … and `central_stop` when chosen.
    pub fn parts(&self, choices: &PartChoices) -> Vec<Part> {
        let segment = |i: usize| {
            (self.span(i) < 360.0).then(|| {
                let half = 0.5 * self.span(i);
                [
                    choices.azimuth_center_deg - half,
                    choices.azimuth_center_deg + half,
                ]
            })
        };
        let mut parts = Vec::new();
        for i in 0..self.shells.len() {
            let az = segment(i);
            let material = PartMaterial::Mirror(MirrorSurfaceDesc {
                coating: Some(choices.coating.unwrap_or(self.coating(i)).to_string()),
                ..self.shells[i].surface.clone()
            });
            for m in self.mirrors(i, az) {
                self.push_mirror(&mut parts, i, m, &material, az);
            }
        }
        if let (Some(spider), Some(distance)) = (&self.spider, choices.spider_distance_mm) {
            let width = spider.arm_width_deg;
            let inner = spider
                .inner_radius_mm
                .unwrap_or_else(|| self.front_inner_radius(0));
            let outer = spider
                .outer_radius_mm
                .unwrap_or_else(|| self.outer_radius());
            for k in 0..spider.arms {
                let centre = choices.azimuth_center_deg
                    + spider.first_arm_deg
                    + 360.0 * k as f64 / spider.arms as f64;
                parts.push(absorber(
                    format!("spider_{}", k + 1),
                    ShapeDesc::Disk(DiskDesc {
                        radius: outer,
                        inner_radius: inner,
                        azimuth: Some([centre - 0.5 * width, centre + 0.5 * width]),
                    }),
                    self.entrance_z() + distance,
                ));
            }
        }
        if choices.central_stop {
            parts.push(absorber(
                "central_stop".into(),
                ShapeDesc::Disk(DiskDesc {
                    radius: self.front_inner_radius(0),
                    inner_radius: 0.0,
                    azimuth: segment(0),
                }),
                self.entrance_z(),
            ));
        }
        parts
    }

    /// The height of the entrance plane: the front mirrors' far end.
    pub fn entrance_z(&self) -> f64 {
        let z0 = 0.5 * self.gap_mm;
        match self.profile {
            Profile::Cone => (0..self.shells.len())
                .map(|i| z0 + self.length(i) * self.alpha(i).cos())
                .fold(f64::MIN, f64::max),
            Profile::Wolter1 => (0..self.shells.len())
                .map(|i| z0 + self.length(i))
                .fold(f64::MIN, f64::max),
        }
    }

    /// The outermost radius of the outermost shell's wall at the entrance (mm).
    pub fn outer_radius(&self) -> f64 {
        let i = self.shells.len() - 1;
        let r1 = match self.profile {
            Profile::Cone => self.cone_radii(i)[0],
            Profile::Wolter1 => self
                .wolter(i)
                .paraboloid_radius(0.5 * self.gap_mm + self.length(i)),
        };
        r1 + self.thickness(i) / self.alpha(i).cos()
    }

    /// Shell i's front and rear mirror surfaces. The wall lies outside the
    /// reflecting face; its thickness measured perpendicular to the face is t,
    /// radially t / cos(angle).
    fn mirrors(&self, i: usize, az: Option<[f64; 2]>) -> [Mirror; 2] {
        let n = i + 1;
        let t = self.thickness(i);
        let z0 = 0.5 * self.gap_mm;
        let l = self.length(i);
        match self.profile {
            Profile::Cone => {
                let [r1, r2, r4, r5] = self.cone_radii(i);
                let (a, ar) = (self.alpha(i), self.alpha_rear(i));
                let cone = |r_near: f64, r_far: f64, z_near: f64, z_far: f64| {
                    ShapeDesc::Cone(ConeDesc {
                        radius_start: r_near,
                        z_start: z_near,
                        radius_end: r_far,
                        z_end: z_far,
                        azimuth: az,
                    })
                };
                let (zf, zr) = (z0 + l * a.cos(), -z0 - l * ar.cos());
                let (dr, drr) = (t / a.cos(), t / ar.cos());
                [
                    Mirror {
                        name: format!("front_{n}"),
                        shape: cone(r2, r1, z0, zf),
                        transform: vec![],
                        near: (r2, z0, dr),
                        far: (r1, zf, dr),
                        stage: MirrorStage::Front,
                    },
                    Mirror {
                        name: format!("rear_{n}"),
                        shape: cone(r4, r5, -z0, zr),
                        transform: vec![],
                        near: (r4, -z0, drr),
                        far: (r5, zr, drr),
                        stage: MirrorStage::Rear,
                    },
                ]
            }
            Profile::Wolter1 => {
                let w = self.wolter(i);
                let d = w.paraboloid_focus_depth;
                let c = w.hyperboloid_centre;
                // Behind a curved mirror the wall's back is the cone through
                // both ends: it departs from the true offset surface by the
                // mirror's sag, a few µm on XMM-Newton's 0.5–1 mm walls.
                let p = |z: f64| {
                    let slope = w.paraboloid_slope(z);
                    (w.paraboloid_radius(z), z, t * slope.hypot(1.0))
                };
                let h = |z: f64| {
                    let slope = w.hyperboloid_slope(z);
                    (w.hyperboloid_radius(z), z, t * slope.hypot(1.0))
                };
                [
                    Mirror {
                        name: format!("front_{n}"),
                        // In place (no transform to apply per ray).
                        shape: ShapeDesc::Paraboloid(ParaboloidDesc {
                            focal_length: w.q,
                            focus_z: -d,
                            z_start: z0,
                            z_end: z0 + l,
                            azimuth: az,
                        }),
                        transform: vec![],
                        near: p(z0),
                        far: p(z0 + l),
                        stage: MirrorStage::Front,
                    },
                    Mirror {
                        name: format!("rear_{n}"),
                        shape: ShapeDesc::Hyperboloid(HyperboloidDesc {
                            semi_axis_a: w.a,
                            semi_axis_b: w.b,
                            center_z: c,
                            z_start: -z0,
                            z_end: -z0 - l,
                            azimuth: az,
                        }),
                        transform: vec![],
                        near: h(-z0),
                        far: h(-z0 - l),
                        stage: MirrorStage::Rear,
                    },
                ]
            }
        }
    }

    /// A mirror, the wall behind it and the wall's ends.
    fn push_mirror(
        &self,
        parts: &mut Vec<Part>,
        i: usize,
        m: Mirror,
        material: &PartMaterial,
        az: Option<[f64; 2]>,
    ) {
        let (r_near, z_near, dr_near) = m.near;
        let (r_far, z_far, dr_far) = m.far;
        let shell = Some(i);
        parts.push(Part {
            name: m.name.clone(),
            shape: m.shape,
            material: material.clone(),
            transform: m.transform,
            shell,
            stage: Some(m.stage),
        });
        parts.push(Part {
            name: format!("{}_back", m.name),
            shape: ShapeDesc::Cone(ConeDesc {
                radius_start: r_near + dr_near,
                z_start: z_near,
                radius_end: r_far + dr_far,
                z_end: z_far,
                azimuth: az,
            }),
            material: PartMaterial::Absorber,
            transform: vec![],
            shell,
            stage: None,
        });
        let mut edges = vec![("edge_far", r_far, dr_far, z_far)];
        if self.gap_mm > 0.0 {
            edges.push(("edge_near", r_near, dr_near, z_near));
        }
        for (edge, r, dr, z) in edges {
            parts.push(Part {
                name: format!("{}_{edge}", m.name),
                shape: ShapeDesc::Disk(DiskDesc {
                    radius: r + dr,
                    inner_radius: r,
                    azimuth: az,
                }),
                material: PartMaterial::Absorber,
                transform: vec![TransformStep::Translate([0.0, 0.0, z])],
                shell,
                stage: None,
            });
        }
    }
}

/// An absorbing disk at height z, belonging to no shell.
fn absorber(name: String, shape: ShapeDesc, z: f64) -> Part {
    Part {
        name,
        shape,
        material: PartMaterial::Absorber,
        transform: vec![TransformStep::Translate([0.0, 0.0, z])],
        shell: None,
        stage: None,
    }
}
