//! X-ray mirror physics: optical constants from the Henke tables, Fresnel
//! coefficients and the Parratt recursion, coatings (single layers, stacks,
//! depth-graded multilayers such as the LLNL Pt/C recipes).
//!
//! Data flow: `scene::build` builds a [`Coating`] for each coated mirror from
//! data/coatings.toml and the scene's own entries; the photon loop multiplies a
//! photon's weight by R(E, θ) at each reflection; `traxer reflectivity` prints and
//! plots R.

pub mod coating;
pub mod compound;
pub mod elements;
pub mod optical;
pub mod parratt;
pub mod table;

pub use coating::{Coating, CoatingLibrary};
pub use optical::OpticalMaterial;
pub use table::ReflectivityTable;
