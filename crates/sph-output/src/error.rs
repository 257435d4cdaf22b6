//! The error type.

use std::path::PathBuf;

/// What went wrong writing or reading a results file. Every variant names the file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OutputError {
    /// A file-system operation (create, rename, write, read) failed.
    #[error("{path}: {op} failed: {source}", path = .path.display())]
    Io {
        /// The file concerned.
        path: PathBuf,
        /// What was being done.
        op: &'static str,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// The HDF5 library (either backend) reported an error.
    #[error("{path}: HDF5 ({backend}) failed to {context}: {message}", path = .path.display())]
    Hdf5 {
        /// The file concerned.
        path: PathBuf,
        /// Which backend (`hdf5-pure` or `hdf5-metno`).
        backend: &'static str,
        /// What was being done.
        context: String,
        /// The library's message.
        message: String,
    },
    /// The data handed to a writer was rejected (nothing was written for that call).
    #[error("{path}: invalid data: {message}", path = .path.display())]
    InvalidData {
        /// The file concerned.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// A file read back does not have the expected layout.
    #[error("{path}: unexpected layout: {message}", path = .path.display())]
    Layout {
        /// The file concerned.
        path: PathBuf,
        /// What is missing or wrong.
        message: String,
    },
    /// A destination that a run must not replace (a link, device, FIFO, directory, or a file
    /// the run did not write); nothing was written.
    #[error("{path}: will not write there: {reason}", path = .path.display())]
    Refused {
        /// The destination.
        path: PathBuf,
        /// Why not.
        reason: String,
    },
    /// Another writer (this process or another) is writing the same results.
    #[error("{path}: another run{holder} is writing these results; wait for it to finish or write elsewhere", path = .path.display(), holder = .holder.map(|p| format!(" (process {p})")).unwrap_or_default())]
    Locked {
        /// The results file.
        path: PathBuf,
        /// The process holding the lock, if it could be read.
        holder: Option<u32>,
    },
    /// The requested backend is not compiled in (or unknown).
    #[error("output backend `{backend}` is not available: {reason}")]
    BackendUnavailable {
        /// The backend asked for.
        backend: String,
        /// Why it is unavailable.
        reason: String,
    },
    /// A deflate level outside 1..=9 ([`crate::Compression::deflate`]).
    #[error("invalid deflate level {level}: allowed are 1 (fastest) to 9 (smallest)")]
    InvalidCompression {
        /// The level asked for.
        level: u8,
    },
}

impl OutputError {
    pub(crate) fn io(path: impl Into<PathBuf>, op: &'static str, source: std::io::Error) -> Self {
        OutputError::Io {
            path: path.into(),
            op,
            source,
        }
    }

    pub(crate) fn refused(path: impl Into<PathBuf>, reason: impl Into<String>) -> Self {
        OutputError::Refused {
            path: path.into(),
            reason: reason.into(),
        }
    }

    pub(crate) fn invalid(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        OutputError::InvalidData {
            path: path.into(),
            message: message.into(),
        }
    }

    pub(crate) fn layout(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        OutputError::Layout {
            path: path.into(),
            message: message.into(),
        }
    }
}
