//! # sph-driver: the run loop
//!
//! [`drive`] steps any [`sph_core::Solver`] to its end time, landing exactly on snapshot and
//! monitor times; samples the disorder indicator and the energies; writes the HDF5 results
//! (`sph-output`: snapshots, probes, series, summary); and on a failure or an interruption
//! mid-run still completes the file with everything computed so far and the diagnostic in its
//! summary. Before anything is written it estimates the run and checks it ([`guard`]). With
//! [`RunOptions::checkpoint`] it writes the full state of the run every so often
//! ([`checkpoint`]); with [`RunOptions::resume`] it continues such a state, bit-identically.
//!
//! It depends only on the core and the output crates, so a scene built in Rust gets the same
//! results files as the `sph` command without the command line's dependencies. Progress is
//! reported to an optional callback ([`RunOptions::progress`]); the `sph` command draws it as a
//! progress bar or log lines.
//!
//! ```
//! use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
//! use sph_core::{glam::DVec2, Body, Constraints, Probe, D2};
//! use sph_driver::Run;
//! use sph_materials::{ElasticConstants, NeoHookean};
//! use sph_tl::{Shear, TlParams, TlSolver};
//!
//! // A 20 × 4 mm plate clamped at its left end, its right end thrown upward: TL-HF for 2 ms.
//! let dp = 1e-3;
//! let plate = Aabb::<D2>::new(DVec2::ZERO, DVec2::new(0.02, 0.004))?;
//! let set = ParticleSet::fill(&Lattice::new(dp, DVec2::ZERO)?, &plate)?;
//! let (clamp, n) = (set.select(|x| x.x < dp), set.len());
//! let body = Body::from(set).with_velocity(|x| DVec2::new(0.0, 50.0 * x.x));
//! let tip = Probe::at("tip", DVec2::new(0.02, 0.002), &body)?.with_fields(&["von_mises"]);
//! let law = NeoHookean::new(ElasticConstants::from_youngs(1e6, 0.3, 1000.0)?);
//! let mut solver = TlSolver::new(body, law, Shear::hourglass_free(), TlParams::default())?
//!     .with_constraints(Constraints::fixed(clamp, n)?)
//!     .with_probes(vec![tip], 0.0)?;
//! let dir = std::env::temp_dir().join(format!("sph-driver-doc-{}", std::process::id()));
//! let (record, summary) = Run::until(2e-3)
//!     .named("plate")
//!     .write_to(dir.join("plate"))    // plate.h5 and plate.xmf
//!     .execute(&mut solver)?;
//! assert_eq!(summary["status"], "completed");
//! assert!(record.file.is_some() && record.steps > 0);
//! # std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]

pub mod checkpoint;
pub mod convergence;
pub mod error;
pub mod guard;
mod ranks;
pub mod run;

pub use checkpoint::{Checkpoint, CheckpointPlan, Every};
pub use error::DriverError;
pub use run::{
    drive, field_dataset, finite_or_null, signal_name, Interrupt, MonitorSample, Progress,
    ProgressSink, Run, RunOptions, RunRecord, Schedule, DEFAULT_SNAPSHOTS,
};
