//! Mirror coatings: their description (plain serde data, the same in
//! data/coatings.toml and in scene files), and the built form that evaluates the
//! reflectivity R(E, θ) of a layer stack.
//!
//! Data flow: `scene::build` resolves a mirror's `coating = "NAME"` against the
//! scene's own `[coatings]` and the shipped data/coatings.toml; `trace` asks the
//! built [`Coating`] (through its table) for R at each reflection.

use super::compound::{Composition, FormulaError};
use super::elements::OpticalConstants;
use super::optical::{EnergyOutOfRange, OpticalMaterial};
use super::parratt::{reflectance, Layer, Reflectance};
use num_complex::Complex64;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::sync::Arc;

const SHIPPED: &str = include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/data/coatings.toml"));

/// A material entry: `formula = "SiO2"` or `mass_fractions = { SiO2 = 0.64, ... }`,
/// and `density` in g/cm³.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialEntry {
    #[serde(default)]
    pub formula: Option<String>,
    #[serde(default)]
    pub mass_fractions: Option<BTreeMap<String, f64>>,
    pub density: f64,
}

/// One layer of a `layers` coating (top first).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LayerEntry {
    pub material: String,
    pub thickness_nm: f64,
    /// RMS roughness (Névot–Croce) of the layer's top interface.
    #[serde(default)]
    pub roughness_nm: f64,
}

/// A coating entry.
///
/// ```toml
/// [coatings.my_multilayer]
/// type = "depth_graded"      # N bilayers, d_i = a/(b+i)^c, top Γ·d_i on bottom (1−Γ)·d_i
/// top = "C"
/// bottom = "Pt"
/// d_min_nm = 5.5
/// d_max_nm = 16.0
/// gamma = 0.4
/// c = 1.0
/// bilayers = 4
/// substrate = "SiO2"
/// roughness_nm = 0.0         # optional, every interface
///
/// [coatings.my_gold]
/// type = "layers"            # any stack, top first
/// layers = [ { material = "Au", thickness_nm = 50.0, roughness_nm = 0.3 } ]
/// substrate = "SiO2"
/// substrate_roughness_nm = 0.3
///
/// [coatings.bare]
/// type = "substrate"         # a thick mirror of one material
/// substrate = "Au"
/// ```
#[derive(Clone, Debug, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum CoatingEntry {
    /// R = 1 at every energy and angle (a mirror material without a coating is
    /// the same).
    Perfect(PerfectEntry),
    DepthGraded(DepthGradedEntry),
    Layers(LayersEntry),
    Substrate(SubstrateEntry),
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PerfectEntry {}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DepthGradedEntry {
    pub top: String,
    pub bottom: String,
    pub d_min_nm: f64,
    pub d_max_nm: f64,
    pub gamma: f64,
    #[serde(default = "one")]
    pub c: f64,
    pub bilayers: u32,
    pub substrate: String,
    #[serde(default)]
    pub roughness_nm: f64,
}

fn one() -> f64 {
    1.0
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LayersEntry {
    pub layers: Vec<LayerEntry>,
    pub substrate: String,
    #[serde(default)]
    pub substrate_roughness_nm: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SubstrateEntry {
    pub substrate: String,
    #[serde(default)]
    pub roughness_nm: f64,
}

/// A file of materials and coatings (data/coatings.toml, or a scene's tables).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoatingLibrary {
    #[serde(default)]
    pub materials: BTreeMap<String, MaterialEntry>,
    #[serde(default)]
    pub coatings: BTreeMap<String, CoatingEntry>,
    /// The table of optical constants the coatings' layers take (a scene's
    /// `mirror_optical_constants`); plain materials (foils) keep Henke's.
    #[serde(skip)]
    pub mirror_constants: OpticalConstants,
}

impl CoatingLibrary {
    /// The coatings shipped in data/coatings.toml.
    pub fn shipped() -> CoatingLibrary {
        toml::from_str(SHIPPED).expect("data/coatings.toml is valid (tested)")
    }

    /// `self` with `other`'s entries added (`other` wins on equal names), and
    /// `other`'s choice of the mirrors' optical constants.
    pub fn merged(mut self, other: &CoatingLibrary) -> CoatingLibrary {
        self.mirror_constants = other.mirror_constants;
        self.materials.extend(other.materials.clone());
        self.coatings.extend(other.coatings.clone());
        self
    }

    /// The named optical material, on Henke's table.
    pub fn material(&self, name: &str) -> Result<OpticalMaterial, CoatingError> {
        self.material_with(name, OpticalConstants::Henke)
    }

    /// The named material on the table `constants`.
    fn material_with(
        &self,
        name: &str,
        constants: OpticalConstants,
    ) -> Result<OpticalMaterial, CoatingError> {
        let m = self.materials.get(name).ok_or_else(|| {
            format!(
                "unknown material `{name}` (known: {:?})",
                self.materials.keys().collect::<Vec<_>>()
            )
        })?;
        if !(m.density > 0.0 && m.density.is_finite()) {
            return Err(CoatingError::from(format!(
                "material `{name}`: density must be positive (g/cm³)"
            )));
        }
        let composition = match (&m.formula, &m.mass_fractions) {
            (Some(f), None) => Composition::formula(f),
            (None, Some(parts)) => Composition::mixture(
                &parts
                    .iter()
                    .map(|(k, v)| (k.clone(), *v))
                    .collect::<Vec<_>>(),
            ),
            _ => Err(FormulaError::from(
                "give exactly one of `formula` and `mass_fractions`",
            )),
        }
        .map_err(|e| CoatingError(format!("material `{name}`: {e}")))?;
        Ok(OpticalMaterial {
            name: name.to_string(),
            composition,
            density: m.density,
            constants,
        })
    }

    /// Whether the named coating is the perfect mirror (R = 1, nothing to build).
    pub fn is_perfect(&self, name: &str) -> bool {
        matches!(self.coatings.get(name), Some(CoatingEntry::Perfect(_)))
    }

    /// Builds the named coating (a `perfect` one is an error: check
    /// [`CoatingLibrary::is_perfect`] first).
    pub fn coating(&self, name: &str) -> Result<Coating, CoatingError> {
        let entry = self.coatings.get(name).ok_or_else(|| {
            format!(
                "unknown coating `{name}` (known: {:?})",
                self.coatings.keys().collect::<Vec<_>>()
            )
        })?;
        let err = |m: CoatingError| CoatingError(format!("coating `{name}`: {m}"));
        let k = self.mirror_constants;
        let stack = match entry {
            CoatingEntry::Perfect(_) => {
                return Err(err(CoatingError::from(
                    "a perfect mirror has no layers to evaluate (R = 1)",
                )))
            }
            CoatingEntry::DepthGraded(d) => {
                let thicknesses = depth_graded_thicknesses(d.d_min_nm, d.d_max_nm, d.c, d.bilayers)
                    .map_err(err)?;
                if !(d.gamma > 0.0 && d.gamma < 1.0 && non_negative(d.roughness_nm)) {
                    return Err(err(CoatingError::from(
                        "gamma must lie in (0, 1) and roughness_nm be ≥ 0",
                    )));
                }
                let top = Arc::new(self.material_with(&d.top, k).map_err(err)?);
                let bottom = Arc::new(self.material_with(&d.bottom, k).map_err(err)?);
                let mut layers = Vec::new();
                for di in thicknesses {
                    layers.push(StackLayer {
                        material: top.clone(),
                        thickness_nm: d.gamma * di,
                        roughness_nm: d.roughness_nm,
                    });
                    layers.push(StackLayer {
                        material: bottom.clone(),
                        thickness_nm: (1.0 - d.gamma) * di,
                        roughness_nm: d.roughness_nm,
                    });
                }
                Stack {
                    layers,
                    substrate: self.material_with(&d.substrate, k).map_err(err)?,
                    substrate_roughness_nm: d.roughness_nm,
                }
            }
            CoatingEntry::Layers(l) => {
                let mut layers = Vec::new();
                for e in &l.layers {
                    if !(e.thickness_nm > 0.0
                        && e.thickness_nm.is_finite()
                        && non_negative(e.roughness_nm))
                    {
                        return Err(err(CoatingError::from(format!(
                            "layer of `{}`: thickness_nm must be > 0 and roughness_nm ≥ 0",
                            e.material
                        ))));
                    }
                    layers.push(StackLayer {
                        material: Arc::new(self.material_with(&e.material, k).map_err(err)?),
                        thickness_nm: e.thickness_nm,
                        roughness_nm: e.roughness_nm,
                    });
                }
                Stack {
                    layers,
                    substrate: self.material_with(&l.substrate, k).map_err(err)?,
                    substrate_roughness_nm: l.substrate_roughness_nm,
                }
            }
            CoatingEntry::Substrate(s) => Stack {
                layers: Vec::new(),
                substrate: self.material_with(&s.substrate, k).map_err(err)?,
                substrate_roughness_nm: s.roughness_nm,
            },
        };
        Ok(Coating {
            name: name.to_string(),
            stack,
        })
    }
}

message_error!(
    /// A coating or optical material that cannot be built (unknown name, bad
    /// numbers), with what is wrong.
    CoatingError
);

/// Finite and ≥ 0 (false for NaN).
fn non_negative(x: f64) -> bool {
    x.is_finite() && x >= 0.0
}

/// Bilayer thicknesses d_1 (top, = d_max) … d_N (= d_min) of a depth-graded
/// multilayer: d_i = a/(b + i)^c, k = (d_min/d_max)^(1/c), b = (1 − N k)/(k − 1),
/// a = d_min (b + N)^c.
pub fn depth_graded_thicknesses(
    d_min: f64,
    d_max: f64,
    c: f64,
    n: u32,
) -> Result<Vec<f64>, CoatingError> {
    if !(d_min > 0.0 && d_max >= d_min && c > 0.0 && n >= 1 && d_max.is_finite()) {
        return Err(CoatingError::from(
            "need 0 < d_min_nm ≤ d_max_nm, c > 0 and at least one bilayer",
        ));
    }
    if n == 1 || d_min == d_max {
        return Ok(vec![d_max; n as usize]);
    }
    let nf = n as f64;
    let k = (d_min / d_max).powf(1.0 / c);
    let b = (1.0 - nf * k) / (k - 1.0);
    let a = d_min * (b + nf).powf(c);
    Ok((1..=n).map(|i| a / (b + i as f64).powf(c)).collect())
}

/// One layer of a built stack.
#[derive(Clone, Debug)]
pub struct StackLayer {
    pub material: Arc<OpticalMaterial>,
    pub thickness_nm: f64,
    pub roughness_nm: f64,
}

/// A layer stack on a substrate.
#[derive(Clone, Debug)]
pub struct Stack {
    pub layers: Vec<StackLayer>,
    pub substrate: OpticalMaterial,
    pub substrate_roughness_nm: f64,
}

/// A built coating: evaluates R(E, θ) directly (exact, slow); `ReflectivityTable`
/// precomputes it for the photon loop.
#[derive(Clone, Debug)]
pub struct Coating {
    pub name: String,
    pub stack: Stack,
}

impl Coating {
    /// The stack's layers (χ = n − 1 = −δ + iβ) and substrate χ at `energy_kev`,
    /// for evaluating many angles at one energy.
    pub fn layers_at(&self, energy_kev: f64) -> Result<(Vec<Layer>, Complex64), EnergyOutOfRange> {
        let chi = |m: &OpticalMaterial| -> Result<Complex64, EnergyOutOfRange> {
            let (d, b) = m.delta_beta(energy_kev)?;
            Ok(Complex64::new(-d, b))
        };
        let mut layers = Vec::with_capacity(self.stack.layers.len());
        for l in &self.stack.layers {
            layers.push(Layer {
                chi: chi(&l.material)?,
                thickness_nm: l.thickness_nm,
                roughness_nm: l.roughness_nm,
            });
        }
        Ok((layers, chi(&self.stack.substrate)?))
    }

    /// s and p reflectance at `energy_kev` and grazing angle `theta_rad`.
    pub fn reflectance(
        &self,
        energy_kev: f64,
        theta_rad: f64,
    ) -> Result<Reflectance, EnergyOutOfRange> {
        let (layers, sub) = self.layers_at(energy_kev)?;
        Ok(reflectance(
            energy_kev,
            theta_rad,
            &layers,
            sub,
            self.stack.substrate_roughness_nm,
        ))
    }

    /// Unpolarised reflectivity (R_s + R_p)/2.
    pub fn reflectivity(&self, energy_kev: f64, theta_rad: f64) -> Result<f64, EnergyOutOfRange> {
        Ok(self.reflectance(energy_kev, theta_rad)?.unpolarised())
    }
}
