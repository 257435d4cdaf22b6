//! The MPI transport of distributed runs (feature `mpi`): [`MpiRanks`] implements
//! [`Communicator`](RankCommunicator) over `MPI_COMM_WORLD` with rsmpi. Halo exchanges are non-blocking sends and
//! blocking receives matched by source (MPI keeps the order of messages between two ranks);
//! gathers are `MPI_Allgather` of the counts and `MPI_Allgatherv` of the values; reductions
//! are made from the gathered values in rank order (the trait's defaults), so they do not
//! depend on MPI's reduction tree.

use mpi::datatype::PartitionMut;
use mpi::environment::Universe;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use mpi::Threading;
use sph_core::comm::Communicator as RankCommunicator;
use std::sync::Arc;

/// MPI, initialised for the life of the process (finalised when the last handle is dropped).
pub struct MpiRanks {
    // Dropped after `world` (field order): the universe finalises MPI.
    world: SimpleCommunicator,
    _universe: Arc<Universe>,
}

impl std::fmt::Debug for MpiRanks {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "MpiRanks(rank {} of {})",
            self.world.rank(),
            self.world.size()
        )
    }
}

// SAFETY: MPI is initialised with MPI_THREAD_SERIALIZED (checked in `initialize`): any thread
// may call MPI as long as no two do at once. A run has one thread of control that makes all
// MPI calls (the solver's step may run on a rayon worker, but the rayon tasks themselves never
// touch the communicator), so calls never overlap.
unsafe impl Send for MpiRanks {}
unsafe impl Sync for MpiRanks {}

impl MpiRanks {
    /// Initialises MPI. `None` if it was initialised already.
    ///
    /// # Errors
    /// A message when the MPI library cannot give `MPI_THREAD_SERIALIZED`.
    pub fn initialize() -> Result<Option<Self>, String> {
        let Some((universe, level)) = mpi::initialize_with_threading(Threading::Serialized) else {
            return Ok(None);
        };
        if level < Threading::Serialized {
            return Err(format!(
                "the MPI library gives the thread level {level:?}; a distributed run needs Serialized"
            ));
        }
        Ok(Some(Self {
            world: universe.world(),
            _universe: Arc::new(universe),
        }))
    }
}

impl MpiRanks {
    /// Ends the processes of every rank (`MPI_Abort` with `code`): the way out of a rank that
    /// fails while the others may be waiting for it in a collective (a normal exit would wait
    /// in `MPI_Finalize` for ranks that wait for it).
    pub fn abort(&self, code: i32) -> ! {
        self.world.abort(code)
    }
}

impl RankCommunicator for MpiRanks {
    fn rank(&self) -> usize {
        self.world.rank() as usize
    }

    fn size(&self) -> usize {
        self.world.size() as usize
    }

    fn exchange(&self, sends: &[(usize, &[f64])], from: &[usize]) -> Vec<Vec<f64>> {
        mpi::request::scope(|scope| {
            let requests: Vec<_> = sends
                .iter()
                .map(|(to, data)| {
                    self.world
                        .process_at_rank(*to as i32)
                        .immediate_send(scope, *data)
                })
                .collect();
            let received = from
                .iter()
                .map(|&r| self.world.process_at_rank(r as i32).receive_vec::<f64>().0)
                .collect();
            for r in requests {
                r.wait();
            }
            received
        })
    }

    fn all_gather(&self, local: &[f64]) -> Vec<Vec<f64>> {
        let n = self.size();
        let mut counts = vec![0i32; n];
        self.world
            .all_gather_into(&(local.len() as i32), &mut counts[..]);
        let displs: Vec<i32> = counts
            .iter()
            .scan(0, |acc, &c| {
                let d = *acc;
                *acc += c;
                Some(d)
            })
            .collect();
        let total: i32 = counts.iter().sum();
        let mut buf = vec![0.0f64; total as usize];
        {
            let mut part = PartitionMut::new(&mut buf[..], &counts[..], &displs[..]);
            self.world.all_gather_varcount_into(local, &mut part);
        }
        counts
            .iter()
            .zip(&displs)
            .map(|(&c, &d)| buf[d as usize..(d + c) as usize].to_vec())
            .collect()
    }
}
