//! Per-rank results of a distributed run.
//!
//! With per-rank output no rank ever holds the whole body's snapshot:
//!
//! * every rank `r` writes `<base>.rank<r>.h5` (and its own sidecar `<base>.rank<r>.xmf`) with
//!   the particles it owns: per snapshot `position`, `id` (the row, `0..n_r`, which is the
//!   XDMF connectivity), `global_id` (the particle's index in the whole body) and the fields;
//! * rank 0 also writes `<base>.h5` with `/meta`, `/probes`, `/series` and `/summary` (no
//!   snapshots), and `<base>.xmf` ([`RankCollection`]): per snapshot a spatial collection of
//!   the ranks' grids, which ParaView and VisIt open as one body.
//!
//! [`read_ranks`] reads the files back as one body in global particle order, the same contents
//! a single results file of the run would have.

use std::path::{Path, PathBuf};

use crate::data::{Dataset, DatasetData};
use crate::read::{read_file, FileContents, Snapshot};
use crate::safety::TempFile;
use crate::writer::snapshot_name;
use crate::xdmf::{self, XdmfSnapshot};
use crate::{with_suffix, OutputError};

/// The results path (without extension) of rank `rank`'s file: `<base>.rank<rank>`.
pub fn rank_base(base: &Path, rank: usize) -> PathBuf {
    with_suffix(base, &format!(".rank{rank}"))
}

/// The snapshots of a run with per-rank output as rank 0 wrote them, for the XDMF file that
/// presents the ranks' files as one body.
#[derive(Debug, Default, Clone)]
pub struct RankCollection {
    snapshots: Vec<XdmfSnapshot>,
}

impl RankCollection {
    /// No snapshots yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Records the next snapshot, with the datasets rank 0 wrote for it (every rank writes the
    /// same datasets for its own particles).
    pub fn add(&mut self, time: f64, datasets: &[Dataset]) {
        let name = snapshot_name(self.snapshots.len());
        self.snapshots.push(XdmfSnapshot::of(name, time, datasets));
    }

    /// Writes `<base>.xmf` (through a temporary file) for ranks owning `counts[r]` particles:
    /// their files are referenced by bare name, so the set can be moved together. Returns the
    /// path written.
    pub fn write(&self, base: &Path, counts: &[usize]) -> Result<PathBuf, OutputError> {
        let files: Vec<String> = (0..counts.len())
            .map(|r| {
                crate::h5_path(&rank_base(base, r))
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default()
            })
            .collect();
        let text = xdmf::render_ranks(&files, counts, &self.snapshots);
        let xmf = crate::xmf_path(base);
        let mut tmp = TempFile::beside(&xmf, true)?;
        tmp.write_all(text.as_bytes())?;
        tmp.persist(&xmf)?;
        Ok(xmf)
    }
}

/// Reads a run with per-rank output back as one body: `/meta`, probes, series and summary from
/// `<base>.h5`, the snapshots from the `summary["ranks"]` files `<base>.rank<r>.h5`, each
/// snapshot's per-particle datasets put in global particle order (by `global_id`, which is then
/// dropped; `id` becomes `0..n`, as in a single file).
///
/// # Errors
/// A missing or unreadable file, ranks with different snapshots or datasets, or global ids
/// that are not a permutation of the body's particles.
pub fn read_ranks(base: &Path) -> Result<FileContents, OutputError> {
    let main_path = crate::h5_path(base);
    let mut main = read_file(&main_path)?;
    let bad = |m: String| OutputError::invalid(&main_path, m);
    let ranks =
        main.summary
            .get("ranks")
            .and_then(serde_json::Value::as_u64)
            .ok_or_else(|| bad("the summary has no rank count `ranks`".into()))? as usize;
    let files: Vec<FileContents> = (0..ranks)
        .map(|r| read_file(crate::h5_path(&rank_base(base, r))))
        .collect::<Result<_, _>>()?;
    let count = files[0].snapshots.len();
    if files.iter().any(|f| f.snapshots.len() != count) {
        return Err(bad(
            "the ranks' files hold different numbers of snapshots".into()
        ));
    }
    main.snapshots = (0..count)
        .map(|k| merge_snapshot(files.iter().map(|f| &f.snapshots[k]).collect()).map_err(&bad))
        .collect::<Result<_, _>>()?;
    Ok(main)
}

/// One snapshot of the whole body from the ranks' snapshots.
fn merge_snapshot(parts: Vec<&Snapshot>) -> Result<Snapshot, String> {
    let first = parts[0];
    let mut ids: Vec<u64> = Vec::new();
    for p in &parts {
        if p.time != first.time || p.step != first.step {
            return Err(format!("snapshot {}: the ranks differ in time", first.name));
        }
        match p.dataset("global_id").map(|d| &d.data) {
            Some(DatasetData::U64 { values, .. }) => ids.extend(values),
            _ => return Err(format!("snapshot {}: a rank has no global_id", first.name)),
        }
    }
    let n = ids.len();
    if !xdmf::is_permutation(&ids, n) {
        return Err(format!(
            "snapshot {}: the global ids are not a permutation of 0..{n}",
            first.name
        ));
    }
    let mut datasets = Vec::new();
    for d in &first.datasets {
        match d.name.as_str() {
            "global_id" => continue,
            "id" => {
                datasets.push(Dataset::u64_scalars(
                    "id",
                    &(0..n as u64).collect::<Vec<_>>(),
                ));
                continue;
            }
            _ => {}
        }
        let pieces: Vec<&Dataset> = parts
            .iter()
            .map(|p| p.dataset(&d.name))
            .collect::<Option<_>>()
            .ok_or_else(|| format!("snapshot {}: a rank has no {}", first.name, d.name))?;
        datasets.push(in_global_order(&d.name, &pieces, &ids)?);
    }
    Ok(Snapshot {
        name: first.name.clone(),
        time: first.time,
        step: first.step,
        datasets,
    })
}

/// The rows of the ranks' pieces of one dataset, placed at their global ids.
fn in_global_order(name: &str, pieces: &[&Dataset], ids: &[u64]) -> Result<Dataset, String> {
    let rest: Vec<usize> = pieces[0].shape().get(1..).unwrap_or_default().to_vec();
    let row: usize = rest.iter().product();
    let rows: usize = pieces.iter().map(|p| p.shape()[0]).sum();
    if rows != ids.len() || pieces.iter().any(|p| p.shape().get(1..) != Some(&rest[..])) {
        return Err(format!(
            "{name}: the ranks' shapes do not add up to the body"
        ));
    }
    let mut shape = vec![rows];
    shape.extend(&rest);
    let data = match &pieces[0].data {
        DatasetData::F64 { .. } => DatasetData::F64 {
            values: place(pieces, ids, row, name, |d| match d {
                DatasetData::F64 { values, .. } => Some(values),
                _ => None,
            })?,
            shape,
        },
        DatasetData::U64 { .. } => DatasetData::U64 {
            values: place(pieces, ids, row, name, |d| match d {
                DatasetData::U64 { values, .. } => Some(values),
                _ => None,
            })?,
            shape,
        },
    };
    Ok(Dataset {
        name: name.to_string(),
        data,
    })
}

/// The rows (`row` values each) of the ranks' `pieces` of the dataset `name`, as `values` reads
/// them (`None`: a piece of another type), placed at their global ids.
fn place<T: Copy + Default>(
    pieces: &[&Dataset],
    ids: &[u64],
    row: usize,
    name: &str,
    values: impl Fn(&DatasetData) -> Option<&Vec<T>>,
) -> Result<Vec<T>, String> {
    let mut out = vec![T::default(); ids.len() * row];
    let mut id = ids.iter();
    for p in pieces {
        let v = values(&p.data).ok_or_else(|| format!("{name}: the ranks' types differ"))?;
        for (chunk, &g) in v.chunks_exact(row.max(1)).zip(&mut id) {
            out[g as usize * row..(g as usize + 1) * row].copy_from_slice(chunk);
        }
    }
    Ok(out)
}
