//! X-ray mirror physics: optical constants from the Henke tables, Fresnel
//! coefficients and the Parratt recursion, coatings (single layers, stacks,
//! depth-graded multilayers such as the LLNL Pt/C recipes), reflectivity tables,
//! the mirrors' figure errors, thin foils and detector gases.
//!
//! Data flow: the scene build builds a [`Coating`] for each coated mirror from
//! data/coatings.toml and the scene's own entries, and resolves figure-error
//! presets from data/figure_errors.toml; the photon loop multiplies a photon's
//! weight by R(E, θ) at each reflection and tilts the reflected ray by the figure
//! error; `traxer reflectivity` prints and plots R. Tables are kept on disk
//! between builds ([`table_cache`]).

pub mod coating;
pub mod coating_spec;
pub mod compound;
pub mod elements;
pub mod figure_covariance;
pub mod figure_error;
pub mod figure_presets;
pub mod foil;
pub mod gas;
pub mod optical;
pub mod parratt;
pub mod roughness;
pub mod scattering;
pub mod table;
pub mod table_cache;
pub mod table_grid;

pub use coating::{Coating, CoatingLibrary};
pub use coating_spec::{coating_from_spec, CoatingSpecError};
pub use figure_error::FigureError;
pub use figure_presets::FigureErrorLibrary;
pub use foil::Foil;
pub use optical::OpticalMaterial;
pub use table::{AngleCell, EnergyCell, ReflectivityTable};
