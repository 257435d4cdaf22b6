//! What the run driver does differently on more than one rank ([`crate::RunOptions::ranks`]):
//! every rank runs the same loop (the time step is global, so the ranks take the same steps and
//! gather the same output at the same times); only rank 0 writes the results file, the others
//! write into a [`Discard`] writer; failures, interruptions and checkpoint times are agreed
//! between the ranks so that none waits for a partner that stopped; each rank writes its own
//! checkpoint ([`crate::checkpoint::rank_path`]), rank 0's with the snapshots.

use crate::error::DriverError;
use sph_core::comm::Communicator;
use sph_core::{Dim, Solver};
use sph_output::{Dataset, OutputError, ResultWriter};
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

    fn write_series(
        &mut self,
        _: &str,
        _: &[f64],
        _: &[(&str, &[f64])],
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
