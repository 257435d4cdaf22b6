//! Errors of the run driver: one line naming the problem.

use thiserror::Error;

/// An error from checking, starting or finishing a run.
#[derive(Debug, Error)]
pub enum DriverError {
    /// A run parameter outside what the run can do (named as the user writes it).
    #[error("invalid {key} = {value}: {allowed}")]
    InvalidValue {
        /// The parameter.
        key: String,
        /// The value as given.
        value: String,
        /// What is allowed.
        allowed: String,
    },
    /// A run that cannot be made as set up (with the reason).
    #[error("{0}")]
    Config(String),
    /// Invalid set-up or a failure from the solver.
    #[error(transparent)]
    Core(#[from] sph_core::Error),
    /// Writing results failed.
    #[error(transparent)]
    Output(#[from] sph_output::OutputError),
    /// File-system error.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
}
