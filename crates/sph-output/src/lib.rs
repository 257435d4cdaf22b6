//! Results output for sph-solids: one HDF5 file per run plus an XDMF sidecar for ParaView.
//!
//! # Layout
//!
//! Every run writes one file `<name>.h5` with
//!
//! | path | contents |
//! | --- | --- |
//! | `/` | attributes `format = "sph-solids-output"`, `format_version = 1` (u64) |
//! | `/meta` | one attribute per key of the run's metadata (see [JSON values](#json-values)) plus `json`, the whole map as a JSON string |
//! | `/snapshots/<n>` | one group per snapshot, `n` = `000000`, `000001`, … (six digits, more only past 999 999, so the names sort lexically in time order), attributes `time` (f64) and `step` (u64), one dataset per field |
//! | `/probes/<name>` | datasets `time` `[m]`, `position` `[m, 3]`, `velocity` `[m, 3]` (all f64) |
//! | `/probes/<name>/fields` | output fields sampled at the probe (at the monitor times): `time` `[k]`, one dataset per field, `[k]`, `[k, 3]` or `[k, 3, 3]` |
//! | `/series/<name>` | dataset `time` `[m]` and one f64 dataset `[m]` per column (a tool's or grip's travel and reaction force, …), attribute `description` (the columns, their units and signs); since format version 2 |
//! | `/summary` | one attribute per key of the run's summary plus `json`, the whole map as a JSON string |
//!
//! and a sidecar `<name>.xmf` (XDMF 3): a temporal collection of the snapshots, each a
//! `Polyvertex` topology with its connectivity (the snapshot's `id` dataset when that is a
//! permutation of `0..n`, else an inline list), an `XYZ` geometry from the snapshot's
//! `position` dataset, and every per-particle dataset as a node attribute (`Scalar`, `Vector`,
//! `Tensor`, … by shape, see [`xdmf`]). ParaView ("XDMF Reader" / "Xdmf3 Reader S/T"), VTK and
//! meshio read it. The run driver (`sph-driver`) writes `position` and an integer `id` (u64,
//! the particle's index in the input body) in every snapshot.
//!
//! # Dimension conventions
//!
//! The file is dimension agnostic: a [`Dataset`] is a flat row-major buffer with a shape. The
//! solver's conventions, which the constructors on [`Dataset`] implement, are
//!
//! * per-particle scalars: shape `[n]`;
//! * vectors (position, velocity, displacement, …): shape `[n, 3]`. 2D runs pad `z = 0`
//!   ([`Dataset::vectors_2d`]) so ParaView's `XYZ` geometry and vector glyphs work unchanged;
//! * matrices (stress, deformation gradient, …): shape `[n, 3, 3]`, row-major, 2D runs padded
//!   with zeros in the third row and column ([`Dataset::matrices_2d`]), which XDMF calls a
//!   `Tensor` (9 components).
//!
//! The snapshot's `position` dataset must be f64 `[n, 3]` when present; it is the geometry.
//!
//! # JSON values
//!
//! `/meta` and `/summary` store each key of the JSON map as an attribute: integers as `u64`
//! (non-negative) or `i64`, other numbers as `f64`, strings as variable-length UTF-8 strings,
//! booleans as `u8` (0/1), arrays and objects as their JSON text (a string attribute); `null`
//! gets no attribute. The attribute `json` always holds the complete map as JSON text, which is
//! what [`read_file`] returns, so a round trip is exact; a key literally named `json`, or one
//! that is not a valid attribute name (empty, or containing `/` or `.` alone), is only in `json`.
//!
//! # Never half-written, never clobbering
//!
//! A writer writes to a temporary file of its own, `<name>.h5.<pid>-<k>.tmp`, created
//! exclusively ([`safety::TempFile`]); [`ResultWriter::finish`] closes it and renames it to
//! `<name>.h5`, then writes the sidecar the same way and renames it to `<name>.xmf`. A writer
//! dropped without `finish` (a panic, a crash) leaves only its `.tmp`, never a file that looks
//! finished. While it lives, a writer holds an exclusive lock on `<name>.h5.lock`
//! ([`safety::OutputLock`]), so a second writer of the same results fails at once with
//! [`OutputError::Locked`] instead of interleaving with the first. It replaces an existing
//! `<name>.h5` only if that is an sph-solids results file and `<name>.xmf` only if that is an
//! XDMF file, never a link, device, FIFO or directory ([`safety::check_results_destination`],
//! [`OutputError::Refused`]). Both backends write **incrementally**: each `write_*` call is durable in the
//! `.tmp` file when it returns (the pure backend commits and fsyncs it, the C backend flushes
//! it), so a `.tmp` left behind is a valid HDF5 file holding everything written until then,
//! and memory does not grow with the number of snapshots. Each call validates its input before
//! touching the file, so a rejected call leaves the writer usable: a simulation that fails can
//! still write its summary (carrying the failure status) and call `finish`, and everything
//! computed before the failure is kept.
//!
//! # Backends
//!
//! [`Backend::Pure`] (the default) uses the pure-Rust `hdf5-pure` crate (pinned exactly), so
//! nothing beyond the Rust toolchain is needed; it is also what [`read_file`] uses.
//! [`Backend::Metno`] uses the HDF5 C library through `hdf5-metno` and exists only with the
//! cargo feature `hdf5-metno`. Both write the same layout and the same datatypes, and both
//! honour [`Compression`] with the same chunks and filters ([`create_writer_with`]; the C
//! backend refuses it if its library lacks the deflate filter).
//!
//! # Example
//!
//! ```
//! use sph_output::{create_writer, read_file, Backend, Dataset};
//!
//! let dir = std::env::temp_dir().join(format!("sph-output-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir)?;
//! let mut w = create_writer(&dir.join("beam"), Backend::default())?;
//! let meta = serde_json::json!({"case": "beam", "dim": 2});
//! w.write_meta(meta.as_object().unwrap())?;
//! w.write_snapshot(0.0, 0, &[
//!     Dataset::vectors_2d("position", &[[0.0, 0.0], [0.1, 0.0]]),
//!     Dataset::scalars("density", &[1000.0, 1000.0]),
//! ])?;
//! let summary = serde_json::json!({"status": "ok", "steps": 0});
//! w.write_summary(summary.as_object().unwrap())?;
//! let h5 = w.finish()?; // beam.h5 and beam.xmf now exist; the temporary file is gone
//! let back = read_file(&h5)?;
//! assert_eq!(back.snapshots[0].dataset("position").unwrap().shape(), &[2, 3]);
//! # std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]

mod data;
mod error;
pub mod input;
#[cfg(feature = "hdf5-metno")]
mod metno;
mod pure;
mod ranks;
mod read;
pub mod safety;
pub mod vtu;
mod writer;
pub mod xdmf;

use std::path::{Path, PathBuf};

pub use data::{Dataset, DatasetData};
pub use error::OutputError;
pub use ranks::{rank_base, read_ranks, RankCollection};
pub use read::{read_file, FileContents, Probe, Series, Snapshot};

/// Value of the root attribute `format`.
pub const FORMAT_NAME: &str = "sph-solids-output";
/// Value of the root attribute `format_version`.
pub const FORMAT_VERSION: u64 = 2;

/// Writes one run's results file. Obtain one from [`create_writer`].
///
/// Writers are `Send`, so output can be handed to a background thread.
///
/// Calls may come in any order except that nothing may follow [`finish`](Self::finish). The
/// methods taking a JSON map replace what an earlier call of the same method wrote.
pub trait ResultWriter: Send {
    /// Writes the run's metadata to `/meta` (see the crate docs for how JSON values map to
    /// attributes), replacing earlier metadata.
    fn write_meta(
        &mut self,
        meta: &serde_json::Map<String, serde_json::Value>,
    ) -> Result<(), OutputError>;

    /// Writes the next snapshot `/snapshots/<n>` (n counts from 0) with attributes `time` and
    /// `step` and one dataset per entry of `datasets`. Dataset names must be unique, non-empty
    /// and free of `/`; `position`, if present, must be f64 `[n, 3]`.
    fn write_snapshot(
        &mut self,
        time: f64,
        step: u64,
        datasets: &[Dataset],
    ) -> Result<(), OutputError>;

    /// Writes probe `name` as `/probes/<name>/time|position|velocity`. The three slices must
    /// have the same length; a probe name may be written once.
    fn write_probe(
        &mut self,
        name: &str,
        times: &[f64],
        positions: &[[f64; 3]],
        velocities: &[[f64; 3]],
    ) -> Result<(), OutputError>;

    /// Writes output fields sampled at probe `name` (written before with
    /// [`write_probe`](Self::write_probe)) as `/probes/<name>/fields/time` plus one dataset per
    /// field: `[m]` for a scalar, `[m, 3]` for a vector, `[m, 3, 3]` for a matrix (row-major),
    /// each with `times.len()` rows.
    fn write_probe_fields(
        &mut self,
        name: &str,
        times: &[f64],
        fields: &[Dataset],
    ) -> Result<(), OutputError>;

    /// Writes series `name` as `/series/<name>/time` plus one f64 dataset per column (names
    /// unique, not `time`, free of `/`; each column as long as `times`), and `description`
    /// (what the columns are, their units and signs) as the group's attribute `description`
    /// when it is not empty. A series name may be written once.
    fn write_series(
        &mut self,
        name: &str,
        times: &[f64],
        columns: &[(&str, &[f64])],
        description: &str,
    ) -> Result<(), OutputError>;

    /// Writes the run's summary to `/summary`: one attribute per key plus the full map as the
    /// JSON string attribute `json`. Replaces an earlier summary.
    fn write_summary(
        &mut self,
        summary: &serde_json::Map<String, serde_json::Value>,
    ) -> Result<(), OutputError>;

    /// Completes the file: closes its temporary file, renames it to `<name>.h5`, and writes the
    /// XDMF sidecar `<name>.xmf` (through a temporary file too), then releases the lock.
    /// Returns the path of the `.h5` file.
    fn finish(self: Box<Self>) -> Result<PathBuf, OutputError>;

    /// The path of the `.h5` file this writer produces on [`finish`](Self::finish).
    fn final_path(&self) -> &Path;

    /// The temporary file the writer writes until [`finish`](Self::finish)
    /// (`<name>.h5.<pid>-<k>.tmp`; it stays, a valid HDF5 file, if the writer is dropped).
    fn temp_path(&self) -> &Path;
}

/// Which HDF5 implementation writes the file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Backend {
    /// Pure Rust (`hdf5-pure`); always available. The default.
    #[default]
    Pure,
    /// The HDF5 C library via `hdf5-metno`; only with the cargo feature `hdf5-metno`
    /// ([`create_writer`] returns [`OutputError::BackendUnavailable`] otherwise).
    Metno,
}

impl Backend {
    /// Whether this build can write with this backend.
    pub fn is_available(self) -> bool {
        match self {
            Backend::Pure => true,
            Backend::Metno => cfg!(feature = "hdf5-metno"),
        }
    }
}

impl std::fmt::Display for Backend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Backend::Pure => "pure",
            Backend::Metno => "hdf5-metno",
        })
    }
}

impl std::str::FromStr for Backend {
    type Err = OutputError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "pure" | "hdf5-pure" => Ok(Backend::Pure),
            "metno" | "hdf5-metno" => Ok(Backend::Metno),
            other => Err(OutputError::BackendUnavailable {
                backend: other.to_string(),
                reason: "unknown backend (expected `pure` or `hdf5-metno`)".to_string(),
            }),
        }
    }
}

/// The `.h5` path for `path_without_ext`: `.h5` appended to the file name (so a name that
/// contains dots, like `beam_dx0.01`, keeps them).
pub fn h5_path(path_without_ext: &Path) -> PathBuf {
    with_suffix(path_without_ext, ".h5")
}

/// The XDMF sidecar path for `path_without_ext`: `.xmf` appended to the file name.
pub fn xmf_path(path_without_ext: &Path) -> PathBuf {
    with_suffix(path_without_ext, ".xmf")
}

pub(crate) fn with_suffix(p: &Path, suffix: &str) -> PathBuf {
    let mut s = p.as_os_str().to_os_string();
    s.push(suffix);
    PathBuf::from(s)
}

/// How a writer stores datasets.
///
/// With [`Compression::Deflate`] every dataset of at least 1 KiB is stored in chunks of whole
/// rows (about 1 MiB each) through the HDF5 `shuffle` and `deflate` (zlib) filters, which
/// every HDF5 reader decodes transparently (h5py, the C library, hence ParaView and meshio);
/// smaller datasets stay contiguous. Values are unchanged, bit for bit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Compression {
    /// Contiguous, uncompressed datasets. The default.
    #[default]
    None,
    /// Shuffle + deflate at this zlib level, 1 (fastest) to 9 (smallest).
    Deflate(u8),
}

impl Compression {
    /// `Deflate(level)` for a level in 1..=9, else an error naming the allowed range.
    pub fn deflate(level: u8) -> Result<Self, OutputError> {
        if (1..=9).contains(&level) {
            Ok(Compression::Deflate(level))
        } else {
            Err(OutputError::InvalidCompression { level })
        }
    }
}

/// Starts a results file `<path_without_ext>.h5`, written to a temporary file of its own until
/// [`ResultWriter::finish`]. Fails before writing anything if the destination may not be
/// replaced ([`safety::check_results_destination`]) or another writer holds its lock. An
/// existing `.h5` is replaced only by `finish`. The parent directory must exist. Datasets are
/// stored uncompressed; see [`create_writer_with`].
pub fn create_writer(
    path_without_ext: &Path,
    backend: Backend,
) -> Result<Box<dyn ResultWriter>, OutputError> {
    create_writer_with(path_without_ext, backend, Compression::None)
}

/// [`create_writer`] with a choice of dataset [`Compression`].
pub fn create_writer_with(
    path_without_ext: &Path,
    backend: Backend,
    compression: Compression,
) -> Result<Box<dyn ResultWriter>, OutputError> {
    if let Compression::Deflate(level) = compression {
        Compression::deflate(level)?;
    }
    match backend {
        Backend::Pure => Ok(Box::new(writer::LayoutWriter::new(
            path_without_ext,
            pure::PureSink::create,
            compression,
        )?)),
        #[cfg(feature = "hdf5-metno")]
        Backend::Metno => Ok(Box::new(writer::LayoutWriter::new(
            path_without_ext,
            metno::MetnoSink::create,
            compression,
        )?)),
        #[cfg(not(feature = "hdf5-metno"))]
        Backend::Metno => Err(OutputError::BackendUnavailable {
            backend: backend.to_string(),
            reason: "sph-output was built without the cargo feature `hdf5-metno`".to_string(),
        }),
    }
}
