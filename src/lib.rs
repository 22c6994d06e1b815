//! traxer: an X-ray raytracer for grazing-incidence telescopes, on Intel Embree.
//!
//! Data flow (see ARCHITECTURE in the README):
//! `scene` (file → description → built scene with Embree) → `source` (photons) →
//! `trace` (photon loop, materials) → `sensor` (images) → `output` (files).
#![deny(unsafe_code)]

pub mod analysis;
pub mod bench;
pub mod embree;
pub mod files;
pub mod geometry;
pub mod material;
pub mod mesh;
pub mod output;
pub mod progress;
pub mod random;
pub mod raycast;
pub mod render;
pub mod scene;
pub mod sensor;
pub mod source;
pub mod studies;
pub mod trace;
pub mod xray;
