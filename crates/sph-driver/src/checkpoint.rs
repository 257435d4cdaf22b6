//! Checkpoints: the full state of a run, written atomically every so often, from which a run
//! continues bit-identically ([`crate::RunOptions::checkpoint`], [`crate::RunOptions::resume`]).
//!
//! A checkpoint holds the solver's state ([`sph_core::Solver::save_state`]: positions,
//! velocities, each method's evolving fields, time, step count; never the neighbour list), the
//! driver's (the next snapshot and monitor times, the monitor samples, and the snapshots already
//! written, so that a resumed run re-creates the results file whole), the run's `/meta` (case,
//! method, parameters: a resumed run must build the same) and a description of how to build
//! the run again ([`Checkpoint::run`], the command line's business).
//!
//! File format (little-endian): the 8 bytes `SPHCKPT\0`, the format version (u32,
//! [`FORMAT_VERSION`]), 4 zero bytes, the length of the body (u64), its FNV-1a 64-bit checksum
//! (u64), then the body: the run description and the meta as JSON strings, the driver state
//! and the solver state, each a section of [`sph_core::state`]. A file is written to a temporary
//! name created exclusively beside it, synced, then renamed over the previous checkpoint, which
//! therefore stays complete until the new one is.

use crate::error::DriverError;
use crate::run::MonitorSample;
use serde_json::{Map, Value as Json};
use sph_core::disorder::DisorderStats;
use sph_core::state::fnv1a64;
use sph_core::{EnergyBudget, StateReader, StateWriter};
use sph_output::safety::TempFile;
use sph_output::{Dataset, DatasetData};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The checkpoint format version this build writes (it also reads version 1, which has no
/// probe fields: version 2 added the output fields sampled at the probes).
pub const FORMAT_VERSION: u32 = 2;

const MAGIC: &[u8; 8] = b"SPHCKPT\0";
const HEADER_LEN: usize = 32;

/// How often a checkpoint is written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Every {
    /// Every this much simulated time (s).
    SimulatedTime(f64),
    /// Every this much wall time.
    WallTime(Duration),
}

impl std::str::FromStr for Every {
    type Err = DriverError;

    /// `0.01` (simulated seconds), `5min` or `90s` (wall time).
    fn from_str(s: &str) -> Result<Self, DriverError> {
        let invalid = || DriverError::InvalidValue {
            key: "--checkpoint-every".into(),
            value: s.into(),
            allowed: "simulated seconds > 0 (e.g. 0.01) or wall time > 0 as <minutes>min or \
                      <seconds>s (e.g. 5min)"
                .into(),
        };
        let t = s.trim();
        let (number, wall_scale) = if let Some(m) = t.strip_suffix("min") {
            (m, Some(60.0))
        } else if let Some(x) = t.strip_suffix('s') {
            (x, Some(1.0))
        } else {
            (t, None)
        };
        let x: f64 = number.trim().parse().map_err(|_| invalid())?;
        if !(x.is_finite() && x > 0.0) {
            return Err(invalid());
        }
        Ok(match wall_scale {
            Some(scale) => Every::WallTime(
                Duration::try_from_secs_f64(x * scale)
                    .ok()
                    .filter(|d| !d.is_zero())
                    .ok_or_else(invalid)?,
            ),
            None => Every::SimulatedTime(x),
        })
    }
}

impl std::fmt::Display for Every {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Every::SimulatedTime(t) => write!(f, "{t}"),
            Every::WallTime(d) => write!(f, "{}s", d.as_secs_f64()),
        }
    }
}

/// Where and how often a run writes checkpoints.
#[derive(Clone, Debug)]
pub struct CheckpointPlan {
    /// The checkpoint file (replaced by each new checkpoint).
    pub path: PathBuf,
    /// How often.
    pub every: Every,
    /// How to build the run again (stored as is, returned by [`Checkpoint::run`]): the
    /// command line stores its case, method, parameters and files.
    pub run: Json,
}

/// A snapshot as written to the results (kept to re-create the file on resume).
#[derive(Clone, Debug, PartialEq)]
pub struct SavedSnapshot {
    /// Simulated time.
    pub time: f64,
    /// Step count.
    pub step: u64,
    /// The datasets written.
    pub datasets: Vec<Dataset>,
}

/// The driver's part of a checkpoint: where its schedule stands and what it has written.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DriverState {
    /// Time of the next snapshot.
    pub next_snapshot: f64,
    /// Time of the next monitor sample.
    pub next_monitor: f64,
    /// Time of the last snapshot written.
    pub last_snapshot: f64,
    /// Wall seconds spent in `Solver::step` before the checkpoint.
    pub solver_seconds: f64,
    /// Monitor samples so far.
    pub monitor: Vec<MonitorSample>,
    /// Snapshots written so far (all of them: the results file is re-created on resume).
    pub snapshots: Vec<SavedSnapshot>,
    /// The monitor samples' energy budgets as read from a checkpoint, until the restored
    /// solver supplies the budget's term names ([`PendingBudgets::resolve`]).
    pub pending_budgets: Option<PendingBudgets>,
}

/// Energy budgets of the monitor samples read back from a checkpoint: values in the order of
/// the budget's terms, then its notes, then the initial total, per sample that had one.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PendingBudgets {
    /// The names of the terms and notes, comma-separated, as written.
    pub names: String,
    /// Number of terms (the notes follow).
    pub terms: usize,
    /// Number of notes.
    pub notes: usize,
    /// Which samples had a budget.
    pub present: Vec<bool>,
    /// The values, `terms + notes + 1` per sample that had a budget.
    pub values: Vec<f64>,
}

impl PendingBudgets {
    /// Puts the budgets into `monitor`, with the term names of `template` (the restored
    /// solver's budget), which must be the ones written.
    ///
    /// # Errors
    /// The solver keeps no budget, or another one than the checkpoint's.
    pub fn resolve(
        &self,
        template: Option<EnergyBudget>,
        monitor: &mut [MonitorSample],
    ) -> Result<(), String> {
        if !self.present.iter().any(|&p| p) {
            return Ok(());
        }
        let t = template.ok_or("the checkpoint has an energy budget, the run keeps none")?;
        let names: Vec<&str> = t.terms.iter().chain(&t.notes).map(|x| x.0).collect();
        if names.join(",") != self.names || t.terms.len() != self.terms {
            return Err(format!(
                "the energy budget's terms differ (checkpoint: {}; run: {})",
                self.names,
                names.join(",")
            ));
        }
        let width = self.terms + self.notes + 1;
        let mut chunks = self.values.chunks_exact(width);
        for (m, &present) in monitor.iter_mut().zip(&self.present) {
            if !present {
                continue;
            }
            let v = chunks.next().ok_or("energy budget values missing")?;
            m.budget = Some(EnergyBudget {
                terms: t.terms.iter().zip(v).map(|(a, &x)| (a.0, x)).collect(),
                notes: t
                    .notes
                    .iter()
                    .zip(&v[self.terms..])
                    .map(|(a, &x)| (a.0, x))
                    .collect(),
                initial_total: v[width - 1],
            });
        }
        Ok(())
    }
}

/// A checkpoint read back and checked (header, version, checksum).
#[derive(Clone, Debug)]
pub struct Checkpoint {
    /// The file it was read from.
    pub path: PathBuf,
    /// How to build the run again ([`CheckpointPlan::run`]).
    pub run: Json,
    /// The run's `/meta` (a resumed run must build the same).
    pub meta: Map<String, Json>,
    /// The meta as written (compared as text: the same values serialise to the same text,
    /// while parsing JSON floats back need not be exact).
    pub meta_text: String,
    /// The driver's state.
    pub driver: DriverState,
    /// The solver's state ([`sph_core::Solver::restore_state`] reads it).
    pub solver: Vec<u8>,
}

fn corrupt(path: &Path, what: impl std::fmt::Display) -> DriverError {
    DriverError::Config(format!("checkpoint {}: {what}", path.display()))
}

impl Checkpoint {
    /// Reads and checks `path`: an sph checkpoint of this format version, complete, with a
    /// matching checksum, and a readable run description. Every problem is one line naming the
    /// file; nothing else is read or written.
    pub fn load(path: &Path) -> Result<Self, DriverError> {
        use std::io::Read;
        // A regular file only (a FIFO or device is refused at once); its header first, so
        // that a file the size of the disk is never read to find it is not a checkpoint.
        let (file, size) =
            sph_output::input::open_input(path, u64::MAX).map_err(|e| corrupt(path, e.reason))?;
        let mut file = file;
        let mut header = Vec::with_capacity(HEADER_LEN);
        (&mut file)
            .take(HEADER_LEN as u64)
            .read_to_end(&mut header)
            .map_err(|e| corrupt(path, format!("cannot read it: {e}")))?;
        if header.len() < HEADER_LEN || &header[..8] != MAGIC {
            let short =
                header.len() < HEADER_LEN && MAGIC.starts_with(&header[..header.len().min(8)]);
            return Err(corrupt(
                path,
                if short {
                    format!(
                        "truncated ({} bytes; the header alone has {HEADER_LEN})",
                        header.len()
                    )
                } else {
                    "not an sph checkpoint (it does not start with SPHCKPT)".into()
                },
            ));
        }
        let word = |k: usize| u64::from_le_bytes(header[k..k + 8].try_into().expect("8 bytes"));
        let version = u32::from_le_bytes(header[8..12].try_into().expect("4 bytes"));
        if !(1..=FORMAT_VERSION).contains(&version) {
            return Err(corrupt(
                path,
                format!(
                    "format version {version}; this sph ({}) reads versions 1 to {FORMAT_VERSION}",
                    env!("CARGO_PKG_VERSION")
                ),
            ));
        }
        if header[12..16] != [0; 4] {
            return Err(corrupt(
                path,
                "corrupt: its header's reserved bytes 12-15 are not zero",
            ));
        }
        let (len, sum) = (word(16), word(24));
        let held = size.saturating_sub(HEADER_LEN as u64);
        if held != len {
            return Err(corrupt(
                path,
                format!(
                    "truncated or extended: the header announces {len} bytes of state, the file \
                     holds {held}"
                ),
            ));
        }
        let limit = sph_core::budget::current().max_bytes;
        if limit.is_some_and(|l| len > l) {
            return Err(corrupt(
                path,
                format!(
                    "its {} of state exceed the memory limit of {}",
                    sph_core::budget::format_bytes(len as f64),
                    sph_core::budget::format_bytes(limit.unwrap_or(0) as f64)
                ),
            ));
        }
        let mut body = Vec::with_capacity(len as usize);
        file.take(len)
            .read_to_end(&mut body)
            .map_err(|e| corrupt(path, format!("cannot read it: {e}")))?;
        if body.len() as u64 != len {
            return Err(corrupt(path, "truncated while it was read"));
        }
        if fnv1a64(&body) != sum {
            return Err(corrupt(
                path,
                "corrupt: the checksum does not match its contents",
            ));
        }
        Self::decode(path, &body, version).map_err(|e| corrupt(path, e))
    }

    fn decode(path: &Path, body: &[u8], version: u32) -> Result<Self, sph_core::Error> {
        let mut r = StateReader::new(body);
        let json = |r: &mut StateReader<'_>, what: &str| -> Result<Json, sph_core::Error> {
            serde_json::from_str(r.str()?)
                .map_err(|e| sph_core::Error::Checkpoint(format!("{what}: {e}")))
        };
        let run = json(&mut r, "the run description")?;
        let meta_text = r.str()?.to_string();
        let meta = match serde_json::from_str(&meta_text) {
            Ok(Json::Object(m)) => m,
            _ => {
                return Err(sph_core::Error::Checkpoint(
                    "the meta is not a JSON object".into(),
                ))
            }
        };
        let driver = read_driver(&mut r, version)?;
        let solver = r.bytes()?.to_vec();
        if !r.is_at_end() {
            return Err(sph_core::Error::Checkpoint(
                "bytes after the solver state".into(),
            ));
        }
        Ok(Self {
            path: path.to_path_buf(),
            run,
            meta,
            meta_text,
            driver,
            solver,
        })
    }
}

/// Writes a checkpoint to `path` atomically (see the module documentation).
pub fn write(
    path: &Path,
    run: &Json,
    meta: &Map<String, Json>,
    driver: &DriverState,
    solver: &[u8],
) -> Result<(), DriverError> {
    let mut w = StateWriter::new();
    w.str(&run.to_string());
    w.str(&serde_json::to_string(meta).unwrap_or_default());
    write_driver(&mut w, driver);
    w.bytes(solver);
    let body = w.into_bytes();
    let mut bytes = Vec::with_capacity(HEADER_LEN + body.len());
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    bytes.extend_from_slice(&[0; 4]);
    bytes.extend_from_slice(&(body.len() as u64).to_le_bytes());
    bytes.extend_from_slice(&fnv1a64(&body).to_le_bytes());
    bytes.extend_from_slice(&body);
    sph_output::safety::check_destination(path)?;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| DriverError::Io {
            path: dir.display().to_string(),
            source: e,
        })?;
    }
    let mut tmp = TempFile::beside(path, true)?;
    tmp.write_all(&bytes)?;
    tmp.persist(path)?;
    // The rename itself is durable once the directory is synced.
    #[cfg(unix)]
    {
        let dir = match path.parent().filter(|d| !d.as_os_str().is_empty()) {
            Some(d) => d.to_path_buf(),
            None => PathBuf::from("."),
        };
        std::fs::File::open(&dir)
            .and_then(|d| d.sync_all())
            .map_err(|e| DriverError::Io {
                path: dir.display().to_string(),
                source: e,
            })?;
    }
    Ok(())
}

fn write_driver(w: &mut StateWriter, d: &DriverState) {
    w.f64s(
        "driver",
        &[
            d.next_snapshot,
            d.next_monitor,
            d.last_snapshot,
            d.solver_seconds,
        ],
    );
    let col = |f: fn(&MonitorSample) -> f64| d.monitor.iter().map(f).collect::<Vec<_>>();
    w.f64s("monitor_time", &col(|m| m.time));
    w.f64s("monitor_disorder_max", &col(|m| m.disorder.max));
    w.f64s("monitor_disorder_p99", &col(|m| m.disorder.p99));
    w.f64s("monitor_disorder_mean", &col(|m| m.disorder.mean));
    w.f64s("monitor_kinetic", &col(|m| m.kinetic));
    w.f64s("monitor_strain", &col(|m| m.strain));
    let pieces: Vec<u64> = d
        .monitor
        .iter()
        .map(|m| m.pieces.map_or(u64::MAX, |p| p as u64))
        .collect();
    w.u64s("monitor_pieces", &pieces);
    let budgets: Vec<&EnergyBudget> = d.monitor.iter().filter_map(|m| m.budget.as_ref()).collect();
    let present: Vec<u64> = d
        .monitor
        .iter()
        .map(|m| u64::from(m.budget.is_some()))
        .collect();
    w.u64s("monitor_budget_present", &present);
    let first = budgets.first();
    let names = first.map_or(String::new(), |b| {
        b.terms
            .iter()
            .chain(&b.notes)
            .map(|t| t.0)
            .collect::<Vec<_>>()
            .join(",")
    });
    w.str(&names);
    let shape = first.map_or([0, 0], |b| [b.terms.len() as u64, b.notes.len() as u64]);
    w.u64s("monitor_budget_shape", &shape);
    let values: Vec<f64> = budgets
        .iter()
        .flat_map(|b| {
            b.terms
                .iter()
                .chain(&b.notes)
                .map(|t| t.1)
                .chain(std::iter::once(b.initial_total))
        })
        .collect();
    w.f64s("monitor_budget_values", &values);
    let counts: Vec<u64> = d
        .monitor
        .iter()
        .map(|m| m.probe_fields.len() as u64)
        .collect();
    w.u64s("monitor_probe_counts", &counts);
    let values: Vec<f64> = d
        .monitor
        .iter()
        .flat_map(|m| m.probe_fields.iter().copied())
        .collect();
    w.f64s("monitor_probe_values", &values);
    w.begin("snapshots", d.snapshots.len());
    for s in &d.snapshots {
        w.f64s("snapshot", &[s.time]);
        w.u64s("step", &[s.step]);
        w.begin("datasets", s.datasets.len());
        for set in &s.datasets {
            w.str(&set.name);
            let shape: Vec<u64> = set.data.shape().iter().map(|&n| n as u64).collect();
            w.u64s("shape", &shape);
            match &set.data {
                DatasetData::F64 { values, .. } => w.f64s("f64", values),
                DatasetData::U64 { values, .. } => w.u64s("u64", values),
            }
        }
    }
}

fn read_driver(r: &mut StateReader<'_>, version: u32) -> Result<DriverState, sph_core::Error> {
    let [next_snapshot, next_monitor, last_snapshot, solver_seconds] = r.scalars::<4>("driver")?;
    let time = r.f64s("monitor_time", None)?;
    let n = Some(time.len());
    let max = r.f64s("monitor_disorder_max", n)?;
    let p99 = r.f64s("monitor_disorder_p99", n)?;
    let mean = r.f64s("monitor_disorder_mean", n)?;
    let kinetic = r.f64s("monitor_kinetic", n)?;
    let strain = r.f64s("monitor_strain", n)?;
    let monitor = (0..time.len())
        .map(|k| MonitorSample {
            time: time[k],
            disorder: DisorderStats {
                max: max[k],
                p99: p99[k],
                mean: mean[k],
            },
            kinetic: kinetic[k],
            strain: strain[k],
            budget: None,
            pieces: None,
            probe_fields: Vec::new(),
        })
        .collect::<Vec<_>>();
    let mut monitor = monitor;
    let pieces = r.u64s("monitor_pieces", n)?;
    for (m, &p) in monitor.iter_mut().zip(&pieces) {
        m.pieces = (p != u64::MAX).then_some(p as usize);
    }
    let present: Vec<bool> = r
        .u64s("monitor_budget_present", n)?
        .iter()
        .map(|&p| p != 0)
        .collect();
    let names = r.str()?.to_string();
    let shape = r.u64s("monitor_budget_shape", Some(2))?;
    let (terms, notes) = (shape[0] as usize, shape[1] as usize);
    let count = present.iter().filter(|&&p| p).count();
    let values = r.f64s("monitor_budget_values", Some(count * (terms + notes + 1)))?;
    if version >= 2 {
        let counts = r.u64s("monitor_probe_counts", n)?;
        let total = counts
            .iter()
            .try_fold(0usize, |a, &c| a.checked_add(usize::try_from(c).ok()?))
            .ok_or_else(|| sph_core::Error::Checkpoint("probe field counts overflow".into()))?;
        let values = r.f64s("monitor_probe_values", Some(total))?;
        let mut rest = values.as_slice();
        for (m, &c) in monitor.iter_mut().zip(&counts) {
            let (mine, others) = rest.split_at(c as usize);
            m.probe_fields = mine.to_vec();
            rest = others;
        }
    }
    let pending_budgets = Some(PendingBudgets {
        names,
        terms,
        notes,
        present,
        values,
    });
    let count = r.begin("snapshots", None)?;
    let mut snapshots = Vec::with_capacity(count);
    for _ in 0..count {
        let [time] = r.scalars::<1>("snapshot")?;
        let step = r.u64s("step", Some(1))?[0];
        let sets = r.begin("datasets", None)?;
        let mut datasets = Vec::with_capacity(sets);
        for _ in 0..sets {
            let name = r.str()?.to_string();
            let shape: Vec<usize> = r
                .u64s("shape", None)?
                .into_iter()
                .map(|n| n as usize)
                .collect();
            let len = shape.iter().try_fold(1usize, |a, &n| a.checked_mul(n));
            let section = r.str()?;
            let count = r.u64()? as usize;
            if Some(count) != len {
                return Err(sph_core::Error::Checkpoint(format!(
                    "dataset `{name}`: {count} values for the shape {shape:?}"
                )));
            }
            let mut take = |k: usize| -> Result<Vec<u64>, sph_core::Error> {
                (0..k).map(|_| r.u64()).collect()
            };
            let data = match section {
                "f64" => DatasetData::F64 {
                    values: take(count)?.into_iter().map(f64::from_bits).collect(),
                    shape,
                },
                "u64" => DatasetData::U64 {
                    values: take(count)?,
                    shape,
                },
                other => {
                    return Err(sph_core::Error::Checkpoint(format!(
                        "dataset `{name}`: unknown value type `{other}`"
                    )))
                }
            };
            datasets.push(Dataset { name, data });
        }
        snapshots.push(SavedSnapshot {
            time,
            step,
            datasets,
        });
    }
    Ok(DriverState {
        next_snapshot,
        next_monitor,
        last_snapshot,
        solver_seconds,
        monitor,
        snapshots,
        pending_budgets,
    })
}

/// The checkpoint file of rank `rank` of a distributed run whose checkpoint is `path`: `path`
/// itself for rank 0 (it also holds the snapshots and is what `sph resume` is given),
/// `<path>.rank<r>` for the others.
pub fn rank_path(path: &Path, rank: usize) -> std::path::PathBuf {
    if rank == 0 {
        return path.to_path_buf();
    }
    let mut s = path.as_os_str().to_os_string();
    s.push(format!(".rank{rank}"));
    s.into()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_parses_simulated_and_wall_time() {
        assert_eq!("0.01".parse::<Every>().unwrap(), Every::SimulatedTime(0.01));
        assert_eq!(
            "5min".parse::<Every>().unwrap(),
            Every::WallTime(Duration::from_secs(300))
        );
        assert_eq!(
            "90s".parse::<Every>().unwrap(),
            Every::WallTime(Duration::from_secs(90))
        );
        for bad in ["0", "-1", "nan", "inf", "min", "5 minutes", "1e300min", ""] {
            let e = bad.parse::<Every>().unwrap_err().to_string();
            assert!(e.contains("--checkpoint-every"), "{bad}: {e}");
        }
    }

    #[test]
    fn a_checkpoint_reads_back_and_damage_is_refused() {
        let dir = std::env::temp_dir().join(format!("sph-ckpt-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("run.ckpt");
        let mut meta = Map::new();
        meta.insert("case".into(), Json::from("demo"));
        let driver = DriverState {
            next_snapshot: 0.5,
            next_monitor: 0.25,
            last_snapshot: 0.0,
            solver_seconds: 1.5,
            monitor: vec![
                MonitorSample {
                    time: 0.0,
                    kinetic: f64::NAN,
                    probe_fields: vec![1.5, -2.0],
                    ..Default::default()
                },
                MonitorSample {
                    time: 0.1,
                    probe_fields: vec![3.0, 4.0],
                    ..Default::default()
                },
            ],
            snapshots: vec![SavedSnapshot {
                time: 0.0,
                step: 0,
                datasets: vec![Dataset::f64("position", vec![1.0, 2.0, 3.0], vec![1, 3])],
            }],
            pending_budgets: None,
        };
        let run = serde_json::json!({"case": "demo"});
        write(&path, &run, &meta, &driver, b"solver").unwrap();
        let c = Checkpoint::load(&path).unwrap();
        assert_eq!((c.run, c.meta, c.solver), (run, meta, b"solver".to_vec()));
        assert!(c.driver.monitor[0].kinetic.is_nan());
        let probes: Vec<_> = c.driver.monitor.iter().map(|m| &m.probe_fields).collect();
        assert_eq!(probes, [&vec![1.5, -2.0], &vec![3.0, 4.0]]);
        assert_eq!(c.driver.snapshots, driver.snapshots);
        let bytes = std::fs::read(&path).unwrap();
        let damaged = |b: &[u8]| {
            std::fs::write(&path, b).unwrap();
            Checkpoint::load(&path).unwrap_err().to_string()
        };
        assert!(damaged(&bytes[..bytes.len() - 3]).contains("truncated"));
        assert!(damaged(&bytes[..10]).contains("truncated"));
        let mut flipped = bytes.clone();
        *flipped.last_mut().unwrap() ^= 1;
        assert!(damaged(&flipped).contains("checksum"));
        let mut version = bytes.clone();
        version[8] = 9;
        assert!(damaged(&version).contains("format version 9"));
        assert!(damaged(b"{\"not\": \"a checkpoint\"}").contains("not an sph checkpoint"));
        std::fs::remove_file(&path).unwrap();
        assert!(Checkpoint::load(&path)
            .unwrap_err()
            .to_string()
            .contains("cannot read"));
        std::fs::remove_dir(&dir).unwrap();
    }
}
