//! Validation runs: each runs cases through `sph-cases`, stores its figures as JSON under
//! `validation/results/` (so the report can be regenerated, and long runs spread over several
//! sittings) and keeps its HDF5 file under `target/validation-results/`, and `report` turns the
//! stored results into `docs/validation.md` with PNG plots and
//! `target/validation-results/validation.h5` with the same tables and the plotted curves.
#![deny(missing_docs)]

pub mod contact;
pub mod cost;
pub mod extreme;
pub mod features;
pub mod fem_plate;
pub mod folding;
pub mod frames;
pub mod geometry;
pub mod h5report;
pub mod hertz;
pub mod hf_laplacian;
pub mod impacts;
pub mod mesh_physics;
pub mod mps;
pub mod mps_stab;
pub use sph_plot as plot;
pub mod store;
pub mod taylor;
pub mod tl;
pub mod tradeoff;
pub mod ul;

use std::path::PathBuf;

/// The workspace root.
pub fn workspace_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("validation/ sits in the workspace root")
        .to_path_buf()
}
