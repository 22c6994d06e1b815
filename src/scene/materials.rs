//! The `[materials]` of a scene file and their resolution into `Material`s: the
//! two built-in names, the coatings (built once each, in order of first use, and
//! later turned into reflectivity tables), figure-error presets, and the sensors
//! that sensor materials create (one per object that uses one).

use super::mirror_surface::MirrorSurfaceDesc;
use crate::material::{Material, Side};
use crate::sensor::{SensorDesc, SensorSpec};
use crate::xray::figure_presets::FigureErrorLibrary;
use crate::xray::{Coating, CoatingLibrary, Foil};
use serde::Deserialize;
use std::collections::{BTreeMap, BTreeSet};
use std::ops::Range;

/// What happens to a photon that hits an object.
///
/// ```toml
/// [materials.shell]
/// type = "mirror"      # specular reflection
/// side = "front"       # "front", "back" or "both" (default): the other side absorbs
/// coating = "llnl_recipe_3"   # optional: weight × R(E, θ); without it R = 1
///
/// [materials.baffle]
/// type = "absorber"
///
/// [materials.window]
/// type = "foil"        # photons pass, weight × exp(−μ t / cos θ) (Henke μ = 4πβ/λ)
/// material = "Si3N4"   # an optical material (data/coatings.toml or [optical_materials])
/// thickness_nm = 300.0
///
/// [materials.detector]
/// type = "sensor"      # records and absorbs every photon
/// size = [14.0, 14.0]  # mm, along the object's local x and y, centred on its origin
/// pixels = [1000, 1000]
/// energy_bins = [0.5, 10.0, 19]   # optional: keV min, max, number of bands
/// focal_length = 1500.0  # optional, mm: HPD etc. also in arcseconds
/// ```
#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum MaterialDesc {
    Mirror(MirrorDesc),
    Absorber(AbsorberDesc),
    Foil(FoilDesc),
    Sensor(SensorDesc),
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FoilDesc {
    /// An optical material: formula or mass fractions and density.
    pub material: String,
    pub thickness_nm: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MirrorDesc {
    #[serde(default)]
    pub side: SideDesc,
    /// Its coating, figure errors and roughness.
    #[serde(flatten)]
    pub surface: MirrorSurfaceDesc,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AbsorberDesc {}

/// Which side of a surface reflects. The front is the side the shape's normal
/// points to: towards the axis for cones, cylinders, paraboloids and hyperboloids;
/// local +z for disks and rectangles; outwards for boxes and spheres; for meshes
/// the side from which the triangles are counter-clockwise.
#[derive(Debug, Deserialize, Default, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SideDesc {
    Front,
    Back,
    #[default]
    Both,
}

impl From<SideDesc> for Side {
    fn from(s: SideDesc) -> Side {
        match s {
            SideDesc::Front => Side::Front,
            SideDesc::Back => Side::Back,
            SideDesc::Both => Side::Both,
        }
    }
}

/// A named material with where it was written.
struct Entry {
    desc: MaterialDesc,
    /// Its table in the file (the assembly that made it; 0..0 if built in).
    span: Range<usize>,
    /// Declared by the user: an error if no object uses it.
    declared: bool,
}

/// The thickest foil accepted (nm): 10 mm.
pub const MAX_FOIL_NM: f64 = 1e7;

/// A foil's `thickness_nm`: finite, ≥ 0 and at most [`MAX_FOIL_NM`]. A foil
/// is thin (windows are nm to µm): a value above 10 mm is a unit slip (mm or µm
/// meant); a thick absorber is a shape of an absorber material.
fn check_foil_thickness(nm: f64) -> Result<(), String> {
    let said = crate::text::number(nm);
    if !(nm.is_finite() && nm >= 0.0) {
        return Err(format!(
            "thickness_nm = {said}: expected a thickness ≥ 0 (nm)"
        ));
    }
    if nm > MAX_FOIL_NM {
        return Err(format!(
            "thickness_nm = {said}: at most {MAX_FOIL_NM:e} nm (10 mm) for a foil; thickness_nm is in nanometres (4 µm of Mylar is 4000)"
        ));
    }
    Ok(())
}

/// A problem with a material: the message, where, and whether that place is a
/// line of the file (built-in materials have none).
pub struct MaterialError {
    pub span: Range<usize>,
    pub message: String,
}

impl MaterialError {
    /// The span narrowed from the material's table to the line of the key
    /// its message is about ("material `chip`: pixel_grid: ..." points at the
    /// `pixel_grid = ...` line), when the table writes that key on a line of
    /// its own.
    pub fn narrowed(self, text: &str) -> MaterialError {
        let about = self.message.split_once("`: ").map_or("", |(_, rest)| rest);
        let key: String = about
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        let Some(table) = text.get(self.span.clone()).filter(|_| !key.is_empty()) else {
            return self;
        };
        let mut offset = self.span.start;
        for line in table.split_inclusive('\n') {
            let rest = line.trim_start().strip_prefix(key.as_str());
            if rest.is_some_and(|r| r.trim_start().starts_with('=')) {
                let start = offset + line.len() - line.trim_start().len();
                return MaterialError {
                    span: start..offset + line.trim_end().len(),
                    ..self
                };
            }
            offset += line.len();
        }
        self
    }
}

/// The scene's materials while objects are built: resolves names, builds each
/// coating once and creates the sensors.
pub struct Materials {
    entries: BTreeMap<String, Entry>,
    used: BTreeSet<String>,
    coating_library: CoatingLibrary,
    figure_errors: FigureErrorLibrary,
    /// Coatings of coated mirrors in order of first use
    /// (`Material::Mirror::reflectivity` indexes this).
    pub coatings: Vec<Coating>,
    /// Sensors in object order (`Material::Sensor::sensor` indexes this).
    pub sensors: Vec<SensorSpec>,
    /// Foils in order of first use (`Material::Foil::foil` indexes this).
    pub foils: Vec<Foil>,
    /// Roughness models in order of first use (`Material::Mirror::roughness`).
    pub roughness: Vec<crate::xray::roughness::Roughness>,
    /// The source's processes each sensor records an image of
    /// ([`crate::source::Source::process_names`]).
    pub processes: Vec<String>,
    /// The magnet's mass scan (eV), recorded by every sensor.
    pub masses: Vec<f64>,
}

impl Materials {
    /// The file's materials and libraries, plus the built-in `mirror` (perfect,
    /// both sides) and `absorber`.
    pub fn new(
        declared: BTreeMap<String, toml::Spanned<MaterialDesc>>,
        coating_library: CoatingLibrary,
        figure_errors: FigureErrorLibrary,
    ) -> Materials {
        let mut entries = BTreeMap::new();
        let builtin = |desc| Entry {
            desc,
            span: 0..0,
            declared: false,
        };
        entries.insert(
            "mirror".into(),
            builtin(MaterialDesc::Mirror(MirrorDesc {
                side: SideDesc::Both,
                surface: MirrorSurfaceDesc::default(),
            })),
        );
        entries.insert(
            "absorber".into(),
            builtin(MaterialDesc::Absorber(AbsorberDesc {})),
        );
        for (name, m) in declared {
            let span = m.span();
            entries.insert(
                name,
                Entry {
                    desc: m.into_inner(),
                    span,
                    declared: true,
                },
            );
        }
        Materials {
            entries,
            used: BTreeSet::new(),
            coating_library,
            figure_errors,
            coatings: Vec::new(),
            sensors: Vec::new(),
            foils: Vec::new(),
            roughness: Vec::new(),
            processes: Vec::new(),
            masses: Vec::new(),
        }
    }

    /// Adds a material an assembly needs (written at `span`), unless one of that
    /// name exists.
    pub fn add_generated(&mut self, name: &str, desc: MaterialDesc, span: Range<usize>) {
        self.entries.entry(name.to_string()).or_insert(Entry {
            desc,
            span,
            declared: false,
        });
    }

    /// The names known so far (for "unknown material" messages).
    pub fn names(&self) -> Vec<&String> {
        self.entries.keys().collect()
    }

    /// The material `name` for object number `object` called `object_name`;
    /// `None` if no material has that name.
    pub fn resolve(
        &mut self,
        name: &str,
        object: usize,
        object_name: &str,
    ) -> Option<Result<Material, MaterialError>> {
        let entry = self.entries.get(name)?;
        self.used.insert(name.to_string());
        let fail = |message: String| MaterialError {
            span: entry.span.clone(),
            message: format!("material `{name}`: {message}"),
        };
        Some(match &entry.desc {
            MaterialDesc::Absorber(_) => Ok(Material::Absorber),
            MaterialDesc::Foil(f) => {
                if let Err(e) = check_foil_thickness(f.thickness_nm) {
                    return Some(Err(fail(e)));
                }
                let foil = match self.coating_library.material(&f.material) {
                    Ok(material) => Foil {
                        material,
                        thickness_nm: f.thickness_nm,
                    },
                    Err(e) => return Some(Err(fail(e.to_string()))),
                };
                let index = match self.foils.iter().position(|k| *k == foil) {
                    Some(i) => i,
                    None => {
                        self.foils.push(foil);
                        self.foils.len() - 1
                    }
                };
                Ok(Material::Foil { foil: index })
            }
            MaterialDesc::Sensor(s) => match s.spec(object_name, object) {
                Ok(mut spec) => {
                    spec.processes = self.processes.clone();
                    spec.masses = self.masses.clone();
                    self.sensors.push(spec);
                    Ok(Material::Sensor {
                        sensor: self.sensors.len() - 1,
                    })
                }
                Err(m) => Err(fail(m.to_string())),
            },
            MaterialDesc::Mirror(mirror) => {
                let m = &mirror.surface;
                let figure_error = match &m.figure_error {
                    None => None,
                    Some(spec) => match self.figure_errors.resolve(spec) {
                        Ok(f) => f,
                        Err(e) => return Some(Err(fail(format!("figure_error: {e}")))),
                    },
                };
                let reflectivity = match &m.coating {
                    None => None,
                    Some(c) if self.coating_library.is_perfect(c) => None,
                    Some(c) => match self.coatings.iter().position(|k| &k.name == c) {
                        Some(i) => Some(i),
                        None => match self.coating_library.coating(c) {
                            Ok(built) => {
                                self.coatings.push(built);
                                Some(self.coatings.len() - 1)
                            }
                            Err(e) => return Some(Err(fail(e.to_string()))),
                        },
                    },
                };
                let desc = match m.roughness.as_ref().map(|r| r.resolve()).transpose() {
                    Ok(d) => d.flatten(),
                    Err(e) => return Some(Err(fail(format!("roughness: {e}")))),
                };
                let roughness = match desc {
                    None => None,
                    Some(d) => match self.roughness.iter().position(|r| r.desc == d) {
                        Some(i) => Some(i),
                        None => match crate::xray::roughness::Roughness::new(d) {
                            Ok(r) => {
                                self.roughness.push(r);
                                Some(self.roughness.len() - 1)
                            }
                            Err(e) => return Some(Err(fail(e))),
                        },
                    },
                };
                Ok(Material::Mirror {
                    side: mirror.side.into(),
                    reflectivity,
                    figure_error,
                    roughness,
                })
            }
        })
    }

    /// The first declared material no object used, with where it is declared.
    pub fn unused(&self) -> Option<(&str, Range<usize>)> {
        self.entries
            .iter()
            .find(|(name, e)| e.declared && !self.used.contains(*name))
            .map(|(name, e)| (name.as_str(), e.span.clone()))
    }
}
