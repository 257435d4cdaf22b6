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
