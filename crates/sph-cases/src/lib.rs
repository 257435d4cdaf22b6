//! # sph-cases: the benchmark scenes and the `sph` command
//!
//! Every benchmark case of the three papers is a scene builder ([`Case`]) with defaults from its
//! paper and every value overridable ([`params::Params`]: `--set key=value` or a TOML file).
//! The run loop is `sph-driver`'s ([`runner::drive`], re-exported here): it runs any solver to
//! its end time, writes HDF5 results through `sph-output`, and returns the summary figures.
//!
//! ```
//! use sph_cases::{find_case, RunOptions};
//!
//! // The TL paper's oscillating plate, coarse and short, from Rust (`sph run` does the same).
//! let case = find_case("oscillating-plate-2d")?;
//! let mut params = case.params_for("tl-hf");
//! params.apply_assignment("resolution=4")?;
//! params.apply_assignment("end_time=0.01")?;
//! let (record, summary) = case.run("tl-hf", &params, &RunOptions::default())?;
//! assert!(record.failure.is_none());
//! println!("{} steps; figures: {:?}", record.steps, summary.keys().collect::<Vec<_>>());
//! # Ok::<(), sph_cases::CaseError>(())
//! ```
#![deny(missing_docs)]

pub mod advise;
pub mod analysis;
pub mod cases;
pub mod converge;
pub mod error;
#[cfg(feature = "mpi")]
pub mod mpi_ranks;
pub mod params;
pub mod preflight;
pub mod preview;
pub mod process;
pub mod runner;

/// Error estimates from a resolution ladder (`sph-driver`'s; `sph converge`).
pub use sph_driver::convergence;
/// The checks and estimates made before a run (`sph-driver`'s).
pub use sph_driver::guard;

pub use error::CaseError;
pub use params::{Param, Params, Range, Value};
pub use runner::{RunOptions, RunRecord, Schedule};

use serde_json::{Map, Value as Json};

/// What a case is and which methods it runs.
#[derive(Clone, Copy, Debug)]
pub struct CaseInfo {
    /// Name as the command line spells it.
    pub name: &'static str,
    /// One line.
    pub description: &'static str,
    /// Methods it supports (the first is the default).
    pub methods: &'static [&'static str],
}

/// A benchmark case: parameters with defaults, and a run.
pub trait Case: Sync {
    /// Name, description, methods.
    fn info(&self) -> CaseInfo;

    /// The parameters with the defaults every method of the case shares. A method whose paper
    /// sets other defaults (TL-HF's own law in the oscillation cases, the MPS paper's set-up
    /// of a case both papers run) gets them from [`Case::params_for`], as `sph run` does: run
    /// a method with `params_for(method)`, not with these.
    fn params(&self) -> Params;

    /// The parameters with the defaults of `method`'s paper, where a case's method families
    /// come from papers with different set-ups (same keys, other defaults). Default:
    /// [`Case::params`].
    fn params_for(&self, method: &str) -> Params {
        let _ = method;
        self.params()
    }

    /// Builds the scene for `method` with `params` and runs it. On a failure mid-run the
    /// results file is still completed and `record.failure` says what happened.
    fn run(
        &self,
        method: &str,
        params: &Params,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), CaseError>;
}

/// Every case.
pub fn all_cases() -> Vec<&'static dyn Case> {
    cases::ALL.to_vec()
}

/// The case of that name.
pub fn find_case(name: &str) -> Result<&'static dyn Case, CaseError> {
    cases::ALL
        .iter()
        .copied()
        .find(|c| c.info().name == name)
        .ok_or_else(|| CaseError::UnknownCase {
            name: name.into(),
            known: cases::ALL
                .iter()
                .map(|c| c.info().name)
                .collect::<Vec<_>>()
                .join(", "),
        })
}

/// Checks that `case` runs `method` (or picks its default when `None`).
pub fn resolve_method(case: &dyn Case, method: Option<&str>) -> Result<&'static str, CaseError> {
    let info = case.info();
    match method {
        None => Ok(info.methods[0]),
        Some(m) => info
            .methods
            .iter()
            .copied()
            .find(|&x| x == m)
            .ok_or_else(|| CaseError::UnknownMethod {
                case: info.name.into(),
                method: m.into(),
                allowed: info.methods.join(", "),
            }),
    }
}
