//! How surfaces look in visible light, and the sky that lights the scene.

use glam::DVec3;

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
    pub fn default_for(material: &crate::material::Material) -> Appearance {
        use crate::material::Material;
        match material {
            Material::Mirror { .. } => Appearance::Metal {
                color: DVec3::new(0.85, 0.85, 0.88),
                roughness: 0.05,
            },
            Material::Absorber => Appearance::Diffuse {
                color: DVec3::splat(0.5),
            },
            Material::Sensor { .. } => Appearance::Diffuse {
                color: DVec3::splat(0.05),
            },
        }
    }
}

/// Light from directions where nothing is hit: a blend from `horizon` to `zenith`
/// with the direction's component along `up` (equal colours: a uniform sky).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sky {
    pub zenith: DVec3,
    pub horizon: DVec3,
    pub up: DVec3,
}

impl Default for Sky {
    /// The classic white-to-blue sky, +y up.
    fn default() -> Sky {
        Sky {
            zenith: DVec3::new(0.5, 0.7, 1.0),
            horizon: DVec3::ONE,
            up: DVec3::Y,
        }
    }
}

impl Sky {
    #[inline]
    pub fn radiance(&self, dir: DVec3) -> DVec3 {
        let t = 0.5 * (dir.dot(self.up) + 1.0);
        self.horizon.lerp(self.zenith, t)
    }
}
