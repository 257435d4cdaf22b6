//! What the run driver does differently on more than one rank ([`crate::RunOptions::ranks`]):
//! every rank runs the same loop (the time step is global, so the ranks take the same steps and
//! gather the same output at the same times); only rank 0 writes the results file, the others
//! write into a [`Discard`] writer; failures, interruptions and checkpoint times are agreed
//! between the ranks so that none waits for a partner that stopped; each rank writes its own
//! checkpoint ([`crate::checkpoint::rank_path`]), rank 0's with the snapshots. With per-rank
//! output ([`crate::RunOptions::per_rank_output`]) each rank instead writes its own particles
//! to its own file ([`RankOutput`]) and keeps its own snapshots in its checkpoint.

use crate::error::DriverError;
use crate::run::RunOptions;
use serde_json::{json, Map, Value as Json};
use sph_core::comm::Communicator;
use sph_core::{Dim, Solver};
use sph_output::{create_writer_with, Dataset, OutputError, ResultWriter};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Checks that `solver` is distributed over `comm`'s ranks.
pub(crate) fn check<D: Dim>(
    solver: &dyn Solver<D>,
    comm: &Arc<dyn Communicator>,
) -> Result<(), DriverError> {
    let n = comm.size();
    if n > 1 && solver.ranks() != n {
        return Err(DriverError::Config(format!(
            "the method {} does not run distributed: it was started on {n} ranks (run it on one; \
             tl, tl-hf, tl-gm and mps run on several)",
            solver.method()
        )));
    }
    Ok(())
}

/// A results writer that writes nothing: the ranks other than 0 of a distributed run go through
/// the same output calls (whose gathers are collective) without writing a file.
pub(crate) struct Discard(pub PathBuf);

impl ResultWriter for Discard {
    fn write_meta(
        &mut self,
        _meta: &serde_json::Map<String, serde_json::Value>,
    ) -> Result<(), OutputError> {
        Ok(())
    }

    fn write_snapshot(&mut self, _: f64, _: u64, _: &[Dataset]) -> Result<(), OutputError> {
        Ok(())
    }

    fn write_probe(
        &mut self,
        _: &str,
        _: &[f64],
        _: &[[f64; 3]],
        _: &[[f64; 3]],
    ) -> Result<(), OutputError> {
        Ok(())
    }

    fn write_probe_fields(&mut self, _: &str, _: &[f64], _: &[Dataset]) -> Result<(), OutputError> {
        Ok(())
    }

    fn write_series(
        &mut self,
        _: &str,
        _: &[f64],
        _: &[(&str, &[f64])],
        _: &str,
    ) -> Result<(), OutputError> {
        Ok(())
    }

    fn write_summary(
        &mut self,
        _: &serde_json::Map<String, serde_json::Value>,
    ) -> Result<(), OutputError> {
        Ok(())
    }

    fn finish(self: Box<Self>) -> Result<PathBuf, OutputError> {
        Ok(self.0)
    }

    fn final_path(&self) -> &Path {
        &self.0
    }

    fn temp_path(&self) -> &Path {
        &self.0
    }
}

/// A rank's own results file in a run with per-rank output ([`RunOptions::per_rank_output`]),
/// and on rank 0 the record of its snapshots for the XDMF file of the whole body.
pub(crate) struct RankOutput {
    writer: Box<dyn ResultWriter>,
    rank: usize,
    collection: sph_output::RankCollection,
}

impl RankOutput {
    /// Starts `<base>.rank<rank>.h5` with the run's `/meta` plus `rank`.
    pub(crate) fn create(
        base: &std::path::Path,
        rank: usize,
        meta: &Map<String, Json>,
        options: &RunOptions,
    ) -> Result<Self, DriverError> {
        let path = sph_output::rank_base(base, rank);
        // Every rank: on a cluster the ranks may write to their own nodes' disks.
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| DriverError::Io {
                path: dir.display().to_string(),
                source: e,
            })?;
        }
        let mut writer = create_writer_with(&path, options.backend, options.compression)?;
        let mut meta = meta.clone();
        meta.insert("rank".into(), json!(rank));
        writer.write_meta(&meta)?;
        Ok(Self {
            writer,
            rank,
            collection: sph_output::RankCollection::new(),
        })
    }

    pub(crate) fn write(
        &mut self,
        time: f64,
        step: u64,
        sets: &[Dataset],
    ) -> Result<(), sph_output::OutputError> {
        self.writer.write_snapshot(time, step, sets)?;
        if self.rank == 0 {
            self.collection.add(time, sets);
        }
        Ok(())
    }

    /// Completes the file with the run's status and this rank's particle count; returns the
    /// snapshots' record.
    pub(crate) fn complete(
        mut self,
        summary: &Map<String, Json>,
    ) -> Result<sph_output::RankCollection, sph_output::OutputError> {
        let mut own = Map::new();
        for key in ["case", "method", "status", "time_reached", "steps", "ranks"] {
            if let Some(v) = summary.get(key) {
                own.insert(key.into(), v.clone());
            }
        }
        own.insert("rank".into(), json!(self.rank));
        self.writer.write_summary(&own)?;
        self.writer.finish()?;
        Ok(self.collection)
    }
}

/// The datasets of a snapshot of the particles this process owns (per-rank output): the
/// positions, `id` (the row in this file, the XDMF connectivity), `global_id` (the particle's
/// index in the body) and the requested fields the solver offers. Nothing is gathered.
pub(crate) fn owned_snapshot_datasets<D: Dim>(
    solver: &dyn Solver<D>,
    fields: &[&str],
) -> Vec<Dataset> {
    let Some(share) = solver.owned_share() else {
        // One process: its share is the whole body.
        let mut sets = crate::run::snapshot_datasets(solver, fields);
        let ids = sets[1].clone();
        sets[1] = Dataset::u64_scalars("id", &(0..solver.len() as u64).collect::<Vec<_>>());
        sets.insert(
            2,
            Dataset {
                name: "global_id".into(),
                ..ids
            },
        );
        return sets;
    };
    let pos: Vec<[f64; 3]> = share
        .positions()
        .iter()
        .map(|&x| D::to_vec3(x).to_array())
        .collect();
    let ids: Vec<u64> = share.ids().iter().map(|&i| u64::from(i)).collect();
    let mut sets = vec![
        Dataset::vectors("position", &pos),
        Dataset::u64_scalars("id", &(0..ids.len() as u64).collect::<Vec<_>>()),
        Dataset::u64_scalars("global_id", &ids),
    ];
    for &name in fields {
        if name == "id" || name == "global_id" {
            continue;
        }
        if let Some(f) = share.field(name) {
            sets.push(crate::run::field_dataset::<D>(name, f));
        }
    }
    sets
}
