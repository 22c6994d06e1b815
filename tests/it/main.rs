//! traxer's integration tests (one binary, as ripgrep does). Closed-form physics
//! checks, Embree-vs-brute-force parity, determinism, and the documented errors.

mod analysis;
mod common;
mod determinism;
mod docs;
mod effective_area;
mod embree_parity;
mod errors;
mod figure_error;
mod files;
mod focusing;
mod foil;
mod geometry;
mod history;
mod inspect;
mod layout;
mod limits;
mod llnl;
mod mesh_io;
mod meshed_telescope;
mod messages;
mod npy_read;
mod obj_faces;
mod output_location;
mod outputs;
mod photon_loop;
mod rebin;
mod render;
mod results_folder;
mod scenes;
mod shards;
mod solar;
mod sources;
mod streams;
mod toolchain;
mod xray;
