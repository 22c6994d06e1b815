//! What a photon does when it hits an object. A closed set (an enum, matched in the
//! photon loop); coatings, figure errors and more sensor kinds extend it.
//!
//! Data flow: `scene::build` resolves every object's material name to a
//! [`Material`]; `trace` matches on it at each hit.

/// Which side of a surface reflects (the other side absorbs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    Front,
    Back,
    Both,
}

impl Side {
    /// Whether a photon arriving from the front (`from_front`) or the back reflects.
    #[inline]
    pub fn reflects(self, from_front: bool) -> bool {
        match self {
            Side::Both => true,
            Side::Front => from_front,
            Side::Back => !from_front,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Material {
    /// Specular reflection on the reflecting side(s); the weight is multiplied by
    /// the coating's R(E, θ) (`reflectivity` indexes `Scene::reflectivity`), or
    /// by 1 for a perfect mirror (`None`); then the direction is perturbed by the
    /// figure error, if any.
    Mirror {
        side: Side,
        reflectivity: Option<usize>,
        /// `None` for a perfect figure (exactly specular).
        figure_error: Option<crate::xray::figure_error::FigureError>,
        /// Scatter from microroughness (indexes `Scene::roughness`); `None`
        /// for a surface without it.
        roughness: Option<usize>,
    },
    /// Stops the photon.
    Absorber,
    /// A thin foil (window, filter): the photon goes straight on with its weight
    /// multiplied by the transmission T(E, θ) of `Scene::foils[foil]`.
    Foil { foil: usize },
    /// Records the photon in image sensor number `sensor` and stops it.
    Sensor { sensor: usize },
}
