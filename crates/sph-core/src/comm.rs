//! How ranks of a distributed run talk: the [`Communicator`] trait, and [`ThreadRanks`], an
//! in-process implementation (one thread per rank, channels between them) that lets ordinary
//! tests check a distributed run against a single-process one on a machine without MPI. The
//! MPI implementation lives in the `sph` command's crate behind its `mpi` feature.
//!
//! Every rank calls the same collective operations in the same order (the run is
//! deterministic and the time step global, so the code paths agree). Reductions are made
//! from gathered values in rank order, so their result does not depend on the transport's
//! reduction tree.

use std::fmt::Debug;
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::{Arc, Mutex};

/// Point-to-point and collective operations over the ranks of a run, on `f64` payloads.
pub trait Communicator: Send + Sync + Debug {
    /// This rank, in `0..size()`.
    fn rank(&self) -> usize;

    /// Number of ranks.
    fn size(&self) -> usize;

    /// Sends each `(to, data)` and receives one message from each rank of `from`, returned in
    /// the order of `from`. Every rank listed in `from` must send to this rank in the same
    /// call, and every `to` must list this rank in its `from`.
    fn exchange(&self, sends: &[(usize, &[f64])], from: &[usize]) -> Vec<Vec<f64>>;

    /// Every rank's `local` (lengths may differ), in rank order, on every rank.
    fn all_gather(&self, local: &[f64]) -> Vec<Vec<f64>>;

    /// The largest `x` over the ranks (NaN-ignoring, as [`f64::max`]).
    fn max(&self, x: f64) -> f64 {
        self.all_gather(&[x])
            .iter()
            .fold(f64::NEG_INFINITY, |m, v| m.max(v[0]))
    }

    /// The largest `x` over the ranks, or NaN if `x` is NaN on any rank.
    fn max_or_nan(&self, x: f64) -> f64 {
        self.all_gather(&[x])
            .iter()
            .fold(f64::NEG_INFINITY, |m, v| {
                if m.is_nan() || v[0].is_nan() {
                    f64::NAN
                } else {
                    m.max(v[0])
                }
            })
    }

    /// The smallest `x` over the ranks (NaN-ignoring, as [`f64::min`]).
    fn min(&self, x: f64) -> f64 {
        self.all_gather(&[x])
            .iter()
            .fold(f64::INFINITY, |m, v| m.min(v[0]))
    }

    /// Element-wise sums of `x` over the ranks, added in rank order (deterministic).
    fn sum(&self, x: &[f64]) -> Vec<f64> {
        let all = self.all_gather(x);
        let mut out = vec![0.0; x.len()];
        for v in &all {
            for (o, &y) in out.iter_mut().zip(v) {
                *o += y;
            }
        }
        out
    }

    /// Whether `ok` holds on every rank.
    fn all(&self, ok: bool) -> bool {
        self.min(if ok { 1.0 } else { 0.0 }) > 0.5
    }
}

/// One rank of a set of in-process ranks (see [`ThreadRanks::connected`]).
#[derive(Debug)]
pub struct ThreadRank {
    rank: usize,
    to: Vec<Sender<Vec<f64>>>,
    from: Vec<Mutex<Receiver<Vec<f64>>>>,
}

/// In-process ranks: each pair of ranks has a channel in each direction, messages between two
/// ranks arrive in the order they were sent (as MPI's non-overtaking rule for one tag).
pub struct ThreadRanks;

impl ThreadRanks {
    /// `n ≥ 1` connected ranks, to be moved one to each thread.
    pub fn connected(n: usize) -> Vec<ThreadRank> {
        let mut senders: Vec<Vec<Option<Sender<Vec<f64>>>>> = vec![vec![None; n]; n];
        let mut receivers: Vec<Vec<Option<Receiver<Vec<f64>>>>> =
            (0..n).map(|_| (0..n).map(|_| None).collect()).collect();
        for src in 0..n {
            for dst in 0..n {
                let (s, r) = channel();
                senders[src][dst] = Some(s);
                receivers[dst][src] = Some(r);
            }
        }
        senders
            .into_iter()
            .zip(receivers)
            .enumerate()
            .map(|(rank, (to, from))| ThreadRank {
                rank,
                to: to.into_iter().map(|s| s.expect("all pairs")).collect(),
                from: from
                    .into_iter()
                    .map(|r| Mutex::new(r.expect("all pairs")))
                    .collect(),
            })
            .collect()
    }

    /// Runs `f` on `n` in-process ranks, one thread each, and returns the results in rank
    /// order.
    ///
    /// # Panics
    /// If a rank panics.
    pub fn run<T: Send>(n: usize, f: impl Fn(Arc<dyn Communicator>) -> T + Sync) -> Vec<T> {
        let ranks = Self::connected(n);
        std::thread::scope(|scope| {
            let handles: Vec<_> = ranks
                .into_iter()
                .map(|r| {
                    let f = &f;
                    scope.spawn(move || f(Arc::new(r)))
                })
                .collect();
            handles
                .into_iter()
                .map(|h| h.join().expect("rank thread panicked"))
                .collect()
        })
    }
}

impl ThreadRank {
    fn send(&self, to: usize, data: Vec<f64>) {
        self.to[to].send(data).expect("rank hung up");
    }

    fn receive(&self, from: usize) -> Vec<f64> {
        self.from[from]
            .lock()
            .expect("receiver lock")
            .recv()
            .expect("rank hung up")
    }
}

impl Communicator for ThreadRank {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.to.len()
    }

    fn exchange(&self, sends: &[(usize, &[f64])], from: &[usize]) -> Vec<Vec<f64>> {
        for (to, data) in sends {
            self.send(*to, data.to_vec());
        }
        from.iter().map(|&r| self.receive(r)).collect()
    }

    fn all_gather(&self, local: &[f64]) -> Vec<Vec<f64>> {
        for r in 0..self.size() {
            if r != self.rank {
                self.send(r, local.to_vec());
            }
        }
        (0..self.size())
            .map(|r| {
                if r == self.rank {
                    local.to_vec()
                } else {
                    self.receive(r)
                }
            })
            .collect()
    }
}

/// The trivial communicator of a run on one rank.
#[derive(Clone, Copy, Debug, Default)]
pub struct SingleRank;

impl Communicator for SingleRank {
    fn rank(&self) -> usize {
        0
    }

    fn size(&self) -> usize {
        1
    }

    fn exchange(&self, sends: &[(usize, &[f64])], from: &[usize]) -> Vec<Vec<f64>> {
        // Only messages to itself are possible.
        from.iter()
            .map(|_| sends.first().map_or(Vec::new(), |s| s.1.to_vec()))
            .collect()
    }

    fn all_gather(&self, local: &[f64]) -> Vec<Vec<f64>> {
        vec![local.to_vec()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thread_ranks_gather_reduce_and_exchange() {
        let out = ThreadRanks::run(3, |c| {
            let r = c.rank() as f64;
            let gathered = c.all_gather(&vec![r; c.rank() + 1]);
            let (mx, mn, sum) = (c.max(r), c.min(r), c.sum(&[r, 1.0]));
            let nan = c.max_or_nan(if c.rank() == 1 { f64::NAN } else { r });
            assert!(nan.is_nan() && c.max_or_nan(r) == 2.0);
            // A ring: send to the next rank, receive from the previous.
            let next = (c.rank() + 1) % c.size();
            let prev = (c.rank() + c.size() - 1) % c.size();
            let got = c.exchange(&[(next, &[r])], &[prev]);
            (gathered, mx, mn, sum, got[0][0], c.all(c.rank() != 1))
        });
        for (rank, (g, mx, mn, sum, got, all)) in out.into_iter().enumerate() {
            assert_eq!(g, vec![vec![0.0], vec![1.0, 1.0], vec![2.0, 2.0, 2.0]]);
            assert_eq!((mx, mn), (2.0, 0.0));
            assert_eq!(sum, vec![3.0, 3.0]);
            assert_eq!(got, ((rank + 2) % 3) as f64);
            assert!(!all);
        }
    }
}
