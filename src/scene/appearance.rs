//! How objects look in visible light and the sky that lights them: the
//! `appearance` of objects and the `[sky]` table, checked and built. Only renders
//! read these; the X-ray tracer ignores them.

use crate::material::Material;
use glam::DVec3;
use serde::Deserialize;

message_error!(
    /// An appearance or sky that cannot be rendered, with what is wrong.
    InvalidAppearance
);

/// The visible-light appearance of an object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Appearance {
    /// Lambertian reflector with this albedo (linear RGB, 0–1).
    Diffuse { color: DVec3 },
    /// Mirror-like metal: specular reflection blurred by `roughness` (0 = polished).
    Metal { color: DVec3, roughness: f64 },
    /// Clear dielectric with this index of refraction (Fresnel by Schlick).
    Glass { ior: f64 },
    /// A light source: emits this radiance, reflects nothing.
    Emitting { color: DVec3 },
}

impl Appearance {
    /// What an object looks like when the scene does not say: mirrors metallic,
    /// absorbers grey, sensors dark.
    pub fn default_for(material: &Material) -> Appearance {
        match material {
            Material::Mirror { .. } => Appearance::Metal {
                color: DVec3::new(0.85, 0.85, 0.88),
                roughness: 0.05,
            },
            Material::Absorber => Appearance::Diffuse {
                color: DVec3::splat(0.5),
            },
            Material::Foil { .. } => Appearance::Glass { ior: 1.02 },
            Material::Sensor { .. } => Appearance::Diffuse {
                color: DVec3::splat(0.05),
            },
        }
    }
}

/// Visible-light appearance of an object.
///
/// ```toml
/// appearance = { type = "diffuse", color = [0.8, 0.3, 0.3] }
/// appearance = { type = "metal", color = [0.9, 0.9, 0.9], roughness = 0.05 }
/// appearance = { type = "glass", ior = 1.5 }
/// appearance = { type = "emitting", color = [4.0, 4.0, 4.0] }
/// ```
#[derive(Debug, Deserialize, Clone)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum AppearanceDesc {
    Diffuse {
        color: [f64; 3],
    },
    Metal {
        color: [f64; 3],
        #[serde(default)]
        roughness: f64,
    },
    Glass {
        ior: f64,
    },
    Emitting {
        color: [f64; 3],
    },
}

impl AppearanceDesc {
    /// The appearance, or what is wrong with it ("appearance color must ...").
    pub fn build(&self) -> Result<Appearance, InvalidAppearance> {
        let colour = |c: [f64; 3], what: &str| {
            if c.iter().all(|v| v.is_finite() && *v >= 0.0) {
                Ok(DVec3::from(c))
            } else {
                Err(InvalidAppearance::from(format!(
                    "appearance {what} must be three numbers ≥ 0 (linear RGB)"
                )))
            }
        };
        Ok(match self {
            AppearanceDesc::Diffuse { color } => Appearance::Diffuse {
                color: colour(*color, "color")?,
            },
            AppearanceDesc::Metal { color, roughness } => {
                if !(0.0..=1.0).contains(roughness) {
                    return Err(InvalidAppearance::from(format!(
                        "roughness = {roughness}: expected 0 to 1"
                    )));
                }
                Appearance::Metal {
                    color: colour(*color, "color")?,
                    roughness: *roughness,
                }
            }
            AppearanceDesc::Glass { ior } => {
                if !(ior.is_finite() && *ior >= 1.0) {
                    return Err(InvalidAppearance::from(format!(
                        "ior = {ior}: expected an index of refraction ≥ 1"
                    )));
                }
                Appearance::Glass { ior: *ior }
            }
            AppearanceDesc::Emitting { color } => Appearance::Emitting {
                color: colour(*color, "color")?,
            },
        })
    }
}

/// Light from directions where nothing is hit: a blend from `horizon` to `zenith`
/// with the direction's component along `up` (equal colours: a uniform sky), and
/// the disk of a scene's Sun source where it stands.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sky {
    pub zenith: DVec3,
    pub horizon: DVec3,
    pub up: DVec3,
    pub sun: Option<SunDisk>,
}

/// The Sun as the sky shows it: a disk at infinity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunDisk {
    /// Unit vector towards the Sun's centre.
    pub direction: DVec3,
    /// Cosine of the disk's angular radius.
    pub cos_radius: f64,
    pub radiance: DVec3,
}

impl Default for Sky {
    /// The classic white-to-blue sky, +y up.
    fn default() -> Sky {
        Sky {
            zenith: DVec3::new(0.5, 0.7, 1.0),
            horizon: DVec3::ONE,
            up: DVec3::Y,
            sun: None,
        }
    }
}

impl Sky {
    /// Light arriving from direction `-dir` (`dir` a unit vector).
    #[inline]
    pub fn radiance(&self, dir: DVec3) -> DVec3 {
        if let Some(sun) = &self.sun {
            if dir.dot(sun.direction) >= sun.cos_radius {
                return sun.radiance;
            }
        }
        let t = 0.5 * (dir.dot(self.up) + 1.0);
        self.horizon.lerp(self.zenith, t)
    }

    /// The sky with the disk of a Sun `angular_radius` (radians) wide towards
    /// `direction`, drawn `scale` times larger (a true Sun is 0.27° across: a
    /// few pixels in a wide view) in the `[sky]`'s sun colour.
    pub fn with_sun(self, direction: DVec3, angular_radius: f64, desc: &SkyDesc) -> Sky {
        let radius = (angular_radius * desc.sun_scale).min(std::f64::consts::FRAC_PI_2);
        Sky {
            sun: Some(SunDisk {
                direction: direction.normalize(),
                cos_radius: radius.cos(),
                radiance: DVec3::from(desc.sun_color),
            }),
            ..self
        }
    }
}

/// The sky of visible-light renders: `zenith` colour along `up`, `horizon`
/// colour below, blended linearly (the same colour twice: a uniform sky). A scene
/// with a Sun source shows the Sun's disk in `sun_color`, `sun_scale` times its
/// true angular size.
#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct SkyDesc {
    #[serde(default = "sky_zenith")]
    pub zenith: [f64; 3],
    #[serde(default = "sky_horizon")]
    pub horizon: [f64; 3],
    #[serde(default = "super::camera::y_up")]
    pub up: [f64; 3],
    #[serde(default = "sun_color")]
    pub sun_color: [f64; 3],
    #[serde(default = "one")]
    pub sun_scale: f64,
}

impl Default for SkyDesc {
    fn default() -> SkyDesc {
        SkyDesc {
            zenith: sky_zenith(),
            horizon: sky_horizon(),
            up: super::camera::y_up(),
            sun_color: sun_color(),
            sun_scale: one(),
        }
    }
}

/// Linear RGB: a saturated yellow that stays yellow on the PNG's 0–1 scale.
fn sun_color() -> [f64; 3] {
    [1.0, 0.8, 0.12]
}

fn one() -> f64 {
    1.0
}

fn sky_zenith() -> [f64; 3] {
    [0.5, 0.7, 1.0]
}

fn sky_horizon() -> [f64; 3] {
    [1.0, 1.0, 1.0]
}

impl SkyDesc {
    pub fn build(&self) -> Result<Sky, InvalidAppearance> {
        let colours_ok = [self.zenith, self.horizon, self.sun_color]
            .iter()
            .flatten()
            .all(|v| v.is_finite() && *v >= 0.0);
        let up = DVec3::from(self.up);
        if !colours_ok || !up.is_finite() || up.length() == 0.0 {
            return Err(InvalidAppearance::from(
                "sky: zenith, horizon and sun_color are colours (≥ 0), up a non-zero direction",
            ));
        }
        if !(self.sun_scale.is_finite() && self.sun_scale > 0.0) {
            return Err(InvalidAppearance::from(format!(
                "sky: sun_scale = {}: expected a number > 0",
                self.sun_scale
            )));
        }
        Ok(Sky {
            zenith: DVec3::from(self.zenith),
            horizon: DVec3::from(self.horizon),
            up: up.normalize(),
            sun: None,
        })
    }
}
