//! Errors of the case layer: one clear line naming the problem.

use thiserror::Error;

/// An error from selecting, configuring or running a case.
#[derive(Debug, Error)]
pub enum CaseError {
    /// No case of that name.
    #[error("unknown case `{name}`; known cases: {known}")]
    UnknownCase {
        /// What was asked for.
        name: String,
        /// The known names, comma-separated.
        known: String,
    },
    /// The case does not support that method.
    #[error("case `{case}` does not run method `{method}`; its methods: {allowed}")]
    UnknownMethod {
        /// The case.
        case: String,
        /// What was asked for.
        method: String,
        /// The supported methods.
        allowed: String,
    },
    /// No parameter of that name.
    #[error("case `{case}` has no parameter `{key}`; its parameters: {known}")]
    UnknownKey {
        /// The case.
        case: String,
        /// The unknown key.
        key: String,
        /// The known keys.
        known: String,
    },
    /// A parameter value that does not parse or is out of range.
    #[error("invalid {key} = {value}: {allowed}")]
    InvalidValue {
        /// The key.
        key: String,
        /// The value as given.
        value: String,
        /// What is allowed.
        allowed: String,
    },
    /// A malformed `--set` argument or case file.
    #[error("{0}")]
    Config(String),
    /// Invalid set-up or a failure while running (from the solver).
    #[error(transparent)]
    Core(#[from] sph_core::Error),
    /// Writing results failed.
    #[error(transparent)]
    Output(#[from] sph_output::OutputError),
    /// The run driver refused or failed the run.
    #[error(transparent)]
    Driver(#[from] sph_driver::DriverError),
    /// File-system error.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
}
