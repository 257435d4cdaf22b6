//! One rank's share of a distributed run ([`Domain`]) and the view of the whole body a
//! distributed solver gives the run driver ([`DistributedSolver`]).
//!
//! A rank keeps its owned particles and the two halo layers of [`crate::decomposition`] (plus
//! the particles its probes read), numbered in ascending global order so that every neighbour
//! row of an owned or layer-1 particle lists the same neighbours in the same order as in the
//! single-process run: the sums, and with them the results, are bit-identical. The exchange
//! moves per-particle values of the halo from their owners, one message per neighbouring rank.

use crate::comm::Communicator;
use crate::decomposition::Partition;
use crate::dim::Dim;
use crate::error::Error;
use crate::neighbor::{NeighborList, Neighbours};
use crate::scene::{Probe, Series};
use crate::solver::{EnergyBudget, Field, Solver, StepInfo};
use rayon::prelude::*;
use std::cell::OnceCell;
use std::sync::Arc;

/// Marks a particle outside the rank's local set in [`Domain::local_of`].
pub const NOT_LOCAL: u32 = u32::MAX;

/// A rank's particles, halo and exchange plan.
#[derive(Debug)]
pub struct Domain {
    comm: Arc<dyn Communicator>,
    partition: Arc<Partition>,
    global: Vec<u32>,
    local_of: Vec<u32>,
    owned: Vec<bool>,
    complete: Vec<bool>,
    owned_local: Vec<u32>,
    recv: Vec<(usize, Vec<u32>)>,
    send: Vec<(usize, Vec<u32>)>,
    halo: [usize; 3],
    all_owned: Vec<Vec<u32>>,
}

impl Domain {
    /// This rank's domain for `partition` (over `comm`'s ranks) of a body with the fixed
    /// neighbours `list` (a stored list or a search on demand); `extra` particles (probes) are
    /// received every exchange too. Collective: every rank calls it.
    ///
    /// # Errors
    /// A partition over another number of ranks or particles than `comm` and `list`.
    pub fn new(
        comm: Arc<dyn Communicator>,
        partition: Arc<Partition>,
        list: &impl Neighbours,
        extra: &[u32],
    ) -> Result<Self, Error> {
        if partition.ranks() != comm.size() || partition.len() != list.len() {
            return Err(Error::invalid(
                "partition",
                format!("{} ranks, {} particles", partition.ranks(), partition.len()),
                &format!("{} ranks, {} particles", comm.size(), list.len()),
            ));
        }
        let (rank, n) = (comm.rank(), list.len());
        let (h1, h2) = partition.halo_layers(rank, list);
        let mut mark = vec![0u8; n];
        let all_owned: Vec<Vec<u32>> = (0..comm.size()).map(|r| partition.owned(r)).collect();
        all_owned[rank].iter().for_each(|&i| mark[i as usize] = 1);
        h1.iter().for_each(|&i| mark[i as usize] = 2);
        h2.iter().for_each(|&i| mark[i as usize] = 3);
        let mut n_extra = 0;
        for &i in extra {
            if mark[i as usize] == 0 {
                mark[i as usize] = 4;
                n_extra += 1;
            }
        }
        let global: Vec<u32> = (0..n as u32).filter(|&i| mark[i as usize] != 0).collect();
        let mut local_of = vec![NOT_LOCAL; n];
        for (l, &g) in global.iter().enumerate() {
            local_of[g as usize] = l as u32;
        }
        let owned: Vec<bool> = global.iter().map(|&g| mark[g as usize] == 1).collect();
        let complete = global.iter().map(|&g| mark[g as usize] <= 2).collect();
        let owned_local = (0..global.len() as u32)
            .filter(|&l| owned[l as usize])
            .collect();
        // What this rank needs, by owner (ascending global ids within each).
        let needed: Vec<u32> = global
            .iter()
            .copied()
            .filter(|&g| mark[g as usize] >= 2)
            .collect();
        let mut recv: Vec<(usize, Vec<u32>)> = Vec::new();
        for r in 0..comm.size() {
            let ids: Vec<u32> = needed
                .iter()
                .filter(|&&g| partition.owner(g as usize) == r)
                .map(|&g| local_of[g as usize])
                .collect();
            if !ids.is_empty() {
                recv.push((r, ids));
            }
        }
        // What the others need from this rank: everyone's needs, gathered once.
        let needs = comm.all_gather(&needed.iter().map(|&g| g as f64).collect::<Vec<_>>());
        let mut send = Vec::new();
        for (r, need) in needs.iter().enumerate() {
            if r == rank {
                continue;
            }
            let ids: Vec<u32> = need
                .iter()
                .map(|&g| g as usize)
                .filter(|&g| partition.owner(g) == rank)
                .map(|g| local_of[g])
                .collect();
            if !ids.is_empty() {
                send.push((r, ids));
            }
        }
        Ok(Self {
            comm,
            partition,
            global,
            local_of,
            owned,
            complete,
            owned_local,
            recv,
            send,
            halo: [h1.len(), h2.len(), n_extra],
            all_owned,
        })
    }

    /// The domain of this rank for a body with reference positions `reference` and the fixed
    /// neighbours `list` (a stored list, or [`crate::neighbor::GridNeighbours`] when the whole
    /// body's list is never built): RCB weighted by neighbour count
    /// ([`Partition::by_counts`]), the particles `probes` read received too. Collective.
    ///
    /// # Errors
    /// More ranks than particles.
    pub fn for_body<D: Dim>(
        comm: Arc<dyn Communicator>,
        reference: &[D::Vector],
        list: &impl Neighbours,
        probes: &[Probe<D>],
    ) -> Result<Arc<Self>, Error> {
        let counts = crate::neighbor::neighbour_counts(list);
        Self::for_body_counted(comm, reference, list, &counts, probes)
    }

    /// [`Domain::for_body`] with the neighbour counts of `list` already made (a caller that
    /// checked them need not search the whole body twice). Collective.
    ///
    /// # Errors
    /// More ranks than particles, or counts of another length.
    pub fn for_body_counted<D: Dim>(
        comm: Arc<dyn Communicator>,
        reference: &[D::Vector],
        list: &impl Neighbours,
        counts: &[u32],
        probes: &[Probe<D>],
    ) -> Result<Arc<Self>, Error> {
        let partition = Partition::by_counts::<D>(reference, counts, comm.size())?;
        let mut extra = Vec::new();
        for p in probes {
            match &p.target {
                crate::scene::ProbeTarget::Particle(i) => extra.push(*i),
                crate::scene::ProbeTarget::Point { weights, .. } => {
                    extra.extend(weights.iter().map(|w| w.0))
                }
            }
        }
        Ok(Arc::new(Self::new(
            comm,
            Arc::new(partition),
            list,
            &extra,
        )?))
    }

    /// The local rows of the global neighbour list `list`: the rows of the complete particles
    /// (owned and halo layer 1) relabelled to local indices (a monotone map, so each row keeps
    /// its order), empty rows for the others; and for each local pair the index of its global
    /// pair (to pick per-pair data with).
    pub fn local_rows(&self, list: &NeighborList) -> Result<(NeighborList, Vec<usize>), Error> {
        let mut offsets = vec![0usize];
        let mut indices = Vec::new();
        let mut pair_ids = Vec::new();
        for (l, &g) in self.global.iter().enumerate() {
            if self.complete[l] {
                for (k, &j) in list.range(g as usize).zip(list.neighbors(g as usize)) {
                    let lj = self.local_of[j as usize];
                    assert_ne!(lj, NOT_LOCAL, "halo layer 2 covers the rows of layer 1");
                    indices.push(lj);
                    pair_ids.push(k);
                }
            }
            offsets.push(indices.len());
        }
        Ok((NeighborList::from_parts(offsets, indices)?, pair_ids))
    }

    /// The local neighbour list searched from the whole body's neighbours `source` (row `i`
    /// of the whole body for each complete particle, relabelled; empty rows for the others):
    /// the list [`Domain::local_rows`] cuts from a stored list, built without one.
    ///
    /// # Errors
    /// `source` over another number of particles than the partition.
    pub fn local_list(&self, source: &impl Neighbours) -> Result<NeighborList, Error> {
        if source.len() != self.partition.len() {
            return Err(Error::invalid(
                "neighbours",
                source.len(),
                &format!("{} particles", self.partition.len()),
            ));
        }
        // Fixed blocks of rows, concatenated in order: the same list for every thread count.
        let ids: Vec<usize> = (0..self.global.len()).collect();
        let blocks: Vec<(Vec<usize>, Vec<u32>)> = ids
            .par_chunks(256)
            .map(|chunk| {
                let mut counts = Vec::with_capacity(chunk.len());
                let mut idx = Vec::new();
                for &l in chunk {
                    let start = idx.len();
                    if self.complete[l] {
                        source.for_each_neighbour(self.global[l] as usize, |j| {
                            let lj = self.local_of[j as usize];
                            assert_ne!(lj, NOT_LOCAL, "halo layer 2 covers the rows of layer 1");
                            idx.push(lj);
                        });
                    }
                    counts.push(idx.len() - start);
                }
                (counts, idx)
            })
            .collect();
        let mut offsets = Vec::with_capacity(ids.len() + 1);
        offsets.push(0);
        let mut indices = Vec::with_capacity(blocks.iter().map(|b| b.1.len()).sum());
        for (counts, idx) in blocks {
            for c in counts {
                offsets.push(offsets.last().unwrap() + c);
            }
            indices.extend_from_slice(&idx);
        }
        NeighborList::from_parts(offsets, indices)
    }

    /// The local particles' entries of a per-particle array of the whole body.
    pub fn pick<T: Copy>(&self, global: &[T]) -> Vec<T> {
        self.global.iter().map(|&i| global[i as usize]).collect()
    }

    /// The communicator.
    pub fn comm(&self) -> &dyn Communicator {
        &*self.comm
    }

    /// The partition.
    pub fn partition(&self) -> &Partition {
        &self.partition
    }

    /// Global index of each local particle (ascending).
    pub fn global(&self) -> &[u32] {
        &self.global
    }

    /// Local index of each global particle, or [`NOT_LOCAL`].
    pub fn local_of(&self) -> &[u32] {
        &self.local_of
    }

    /// Whether each local particle is owned by this rank.
    pub fn owned(&self) -> &[bool] {
        &self.owned
    }

    /// Whether each local particle's neighbour row is complete in the local set (owned and
    /// halo layer 1): the particles whose derived state (`F`, `Ḟ`) the rank computes.
    pub fn complete(&self) -> &[bool] {
        &self.complete
    }

    /// Local indices of the owned particles (ascending).
    pub fn owned_local(&self) -> &[u32] {
        &self.owned_local
    }

    /// Sizes of halo layer 1, layer 2 and the extra (probe) particles.
    pub fn halo_sizes(&self) -> [usize; 3] {
        self.halo
    }

    /// Particles received per exchange.
    pub fn received(&self) -> usize {
        self.recv.iter().map(|r| r.1.len()).sum()
    }

    /// Ranks this rank exchanges with (it receives from each; it sends to those that need
    /// its particles).
    pub fn neighbour_ranks(&self) -> Vec<usize> {
        let mut r: Vec<usize> = self.recv.iter().map(|r| r.0).collect();
        r.extend(self.send.iter().map(|s| s.0));
        r.sort_unstable();
        r.dedup();
        r
    }

    /// Overwrites the halo entries of `values` (`width` numbers per particle) with their
    /// owners' values: one message to and from each neighbouring rank. Collective.
    pub fn exchange(&self, width: usize, values: &mut [f64]) {
        let got = self.send_halo(width, |l, buf| {
            buf.extend_from_slice(&values[l * width..(l + 1) * width])
        });
        self.unpack_halo(width, &got, |l, c| {
            values[l * width..(l + 1) * width].copy_from_slice(c)
        });
    }

    /// The halo exchange, first half: `pack(l, buf)` appends the `width` numbers of local
    /// particle `l` (one this rank owns and a neighbour needs) to the message for that
    /// neighbour; returns the messages received, for [`Domain::unpack_halo`]. Only the
    /// particles that move are touched. Collective.
    pub fn send_halo(&self, width: usize, pack: impl Fn(usize, &mut Vec<f64>)) -> Vec<Vec<f64>> {
        let packed: Vec<Vec<f64>> = self
            .send
            .iter()
            .map(|(_, ids)| {
                let mut buf = Vec::with_capacity(ids.len() * width);
                ids.iter().for_each(|&l| pack(l as usize, &mut buf));
                buf
            })
            .collect();
        let sends: Vec<(usize, &[f64])> = self
            .send
            .iter()
            .zip(&packed)
            .map(|((r, _), b)| (*r, b.as_slice()))
            .collect();
        let from: Vec<usize> = self.recv.iter().map(|r| r.0).collect();
        self.comm.exchange(&sends, &from)
    }

    /// The halo exchange, second half: `unpack(l, numbers)` for each halo particle `l` with
    /// the `width` numbers received for it.
    ///
    /// # Panics
    /// If a message has the wrong length (the ranks disagree on the plan).
    pub fn unpack_halo(
        &self,
        width: usize,
        got: &[Vec<f64>],
        mut unpack: impl FnMut(usize, &[f64]),
    ) {
        for ((_, ids), buf) in self.recv.iter().zip(got) {
            assert_eq!(buf.len(), ids.len() * width, "halo message length");
            for (&l, numbers) in ids.iter().zip(buf.chunks_exact(width)) {
                unpack(l as usize, numbers);
            }
        }
    }

    /// [`Domain::exchange`] of vectors.
    pub fn exchange_vectors<D: Dim>(&self, v: &mut [D::Vector]) {
        let got = self.send_halo(D::D, |l, buf| {
            buf.extend((0..D::D).map(|k| D::component(v[l], k)))
        });
        self.unpack_halo(D::D, &got, |l, c| v[l] = vector_of::<D>(c));
    }

    /// The owned entries of a local field (`width` numbers per particle) from every rank, in
    /// global particle order. Collective.
    pub fn gather(&self, width: usize, local: &[f64]) -> Vec<f64> {
        let mut mine = Vec::with_capacity(self.owned_local.len() * width);
        for &l in &self.owned_local {
            let l = l as usize * width;
            mine.extend_from_slice(&local[l..l + width]);
        }
        let all = self.comm.all_gather(&mine);
        let mut out = vec![0.0; self.partition.len() * width];
        for (ids, vals) in self.all_owned.iter().zip(all) {
            for (k, &g) in ids.iter().enumerate() {
                let g = g as usize * width;
                out[g..g + width].copy_from_slice(&vals[k * width..(k + 1) * width]);
            }
        }
        out
    }

    /// [`Domain::gather`] of a field.
    pub fn gather_field<D: Dim>(&self, field: Field<D>) -> Field<D> {
        match field {
            Field::Scalar(s) => Field::Scalar(self.gather(1, &s)),
            Field::Vector(v) => Field::Vector(self.gather_vectors::<D>(&v)),
            Field::Matrix(m) => {
                let w = D::D * D::D;
                let flat: Vec<f64> = m
                    .iter()
                    .flat_map(|&a| (0..w).map(move |k| D::matrix_get(a, k / D::D, k % D::D)))
                    .collect();
                let all = self.gather(w, &flat);
                Field::Matrix(
                    all.chunks_exact(w)
                        .map(|c| D::matrix_from_fn(|r, k| c[r * D::D + k]))
                        .collect(),
                )
            }
        }
    }

    /// [`Domain::gather`] of vectors.
    pub fn gather_vectors<D: Dim>(&self, v: &[D::Vector]) -> Vec<D::Vector> {
        let flat: Vec<f64> = v
            .iter()
            .flat_map(|&x| (0..D::D).map(move |k| D::component(x, k)))
            .collect();
        self.gather(D::D, &flat)
            .chunks_exact(D::D)
            .map(vector_of::<D>)
            .collect()
    }
}

/// The reductions over the whole body that a solver makes when it may be one rank's share of
/// it (`Some` domain) or the whole body on one process (`None`: each is the identity), in one
/// place for every distributed method.
pub trait OverRanks {
    /// The largest `x` over the ranks.
    fn max_over_ranks(&self, x: f64) -> f64;
    /// The smallest `x` over the ranks.
    fn min_over_ranks(&self, x: f64) -> f64;
    /// The largest `x` over the ranks, NaN if it is NaN on any.
    fn max_or_nan_over_ranks(&self, x: f64) -> f64;
    /// Element-wise sums over the ranks.
    fn sum_over_ranks(&self, x: &[f64]) -> Vec<f64>;
    /// Whether particle `i` counts in sums over the body (the owned ones on a rank).
    fn counts(&self, i: usize) -> bool;
    /// Per-particle weights (e.g. masses) for sums over the body: `values` with the entries of
    /// the particles that do not count (a rank's halo) set to zero; borrowed when all count.
    fn counted<'a>(&self, values: &'a [f64]) -> std::borrow::Cow<'a, [f64]>;
    /// Total linear momentum `Σ m v` of the particles that count, summed over the ranks.
    fn linear_momentum<D: Dim>(&self, velocities: &[D::Vector], masses: &[f64]) -> D::Vector;
    /// Total angular momentum `Σ m x × v` about the origin (3-vector; only `z` in 2D) of the
    /// particles that count, summed over the ranks.
    fn angular_momentum<D: Dim>(
        &self,
        positions: &[D::Vector],
        velocities: &[D::Vector],
        masses: &[f64],
    ) -> glam::DVec3;
    /// A local result every rank must agree on: if another rank failed, this one fails too (so
    /// no rank waits for a partner that stopped).
    ///
    /// # Errors
    /// This rank's error, or one naming the other rank's failure.
    fn agree(&self, result: Result<(), Error>) -> Result<(), Error>;
}

impl OverRanks for Option<Arc<Domain>> {
    fn max_over_ranks(&self, x: f64) -> f64 {
        self.as_ref().map_or(x, |d| d.comm().max(x))
    }

    fn min_over_ranks(&self, x: f64) -> f64 {
        self.as_ref().map_or(x, |d| d.comm().min(x))
    }

    fn max_or_nan_over_ranks(&self, x: f64) -> f64 {
        self.as_ref().map_or(x, |d| d.comm().max_or_nan(x))
    }

    fn sum_over_ranks(&self, x: &[f64]) -> Vec<f64> {
        self.as_ref().map_or(x.to_vec(), |d| d.comm().sum(x))
    }

    fn counts(&self, i: usize) -> bool {
        self.as_ref().is_none_or(|d| d.owned()[i])
    }

    fn linear_momentum<D: Dim>(&self, velocities: &[D::Vector], masses: &[f64]) -> D::Vector {
        let p = crate::diagnostics::linear_momentum::<D>(velocities, &self.counted(masses));
        if self.is_none() {
            return p;
        }
        let v = D::to_vec3(p);
        let s = self.sum_over_ranks(&[v.x, v.y, v.z]);
        D::vector([s[0], s[1], s[2]])
    }

    fn angular_momentum<D: Dim>(
        &self,
        positions: &[D::Vector],
        velocities: &[D::Vector],
        masses: &[f64],
    ) -> glam::DVec3 {
        let l =
            crate::diagnostics::angular_momentum::<D>(positions, velocities, &self.counted(masses));
        let s = self.sum_over_ranks(&[l.x, l.y, l.z]);
        glam::DVec3::new(s[0], s[1], s[2])
    }

    fn counted<'a>(&self, values: &'a [f64]) -> std::borrow::Cow<'a, [f64]> {
        match self {
            None => std::borrow::Cow::Borrowed(values),
            Some(d) => std::borrow::Cow::Owned(
                values
                    .iter()
                    .zip(d.owned())
                    .map(|(&m, &o)| if o { m } else { 0.0 })
                    .collect(),
            ),
        }
    }

    fn agree(&self, result: Result<(), Error>) -> Result<(), Error> {
        let Some(d) = self else {
            return result;
        };
        if d.comm().all(result.is_ok()) {
            return result;
        }
        result?;
        Err(Error::invalid(
            "state",
            "another rank's state",
            "finite on every rank (another rank reported the failure)",
        ))
    }
}

/// The vector of `D::D` components.
pub fn vector_of<D: Dim>(c: &[f64]) -> D::Vector {
    D::vector([c[0], c[1], if D::D == 3 { c[2] } else { 0.0 }])
}

/// The particles one rank owns, read from its local solver without any communication: what
/// the rank's own results file holds in a run with per-rank output.
pub struct OwnedShare<'a, D: Dim> {
    local: &'a dyn Solver<D>,
    domain: &'a Domain,
}

impl<D: Dim> OwnedShare<'_, D> {
    /// This rank.
    pub fn rank(&self) -> usize {
        self.domain.comm.rank()
    }

    /// The number of particles each rank owns, in rank order (known to every rank).
    pub fn counts(&self) -> Vec<usize> {
        self.domain.all_owned.iter().map(Vec::len).collect()
    }

    /// The global index of each owned particle (ascending).
    pub fn ids(&self) -> Vec<u32> {
        self.domain.all_owned[self.rank()].clone()
    }

    /// Positions of the owned particles.
    pub fn positions(&self) -> Vec<D::Vector> {
        let p = self.local.positions();
        self.domain
            .owned_local
            .iter()
            .map(|&l| p[l as usize])
            .collect()
    }

    /// A named field of the owned particles ([`Solver::field`]), `None` for an unknown name.
    pub fn field(&self, name: &str) -> Option<Field<D>> {
        self.local
            .field(name)
            .map(|f| f.pick(&self.domain.owned_local))
    }
}

/// A solver of one rank's particles presented to the run driver as the whole body: positions,
/// velocities and fields are gathered from the ranks in global order when asked for (every rank
/// asks at the same points of the run, so the gathers match). The wrapped solver reduces its
/// time step, energies and momentum over the ranks itself.
pub struct DistributedSolver<D: Dim, S: Solver<D>> {
    inner: S,
    domain: Arc<Domain>,
    positions: OnceCell<Vec<D::Vector>>,
    velocities: OnceCell<Vec<D::Vector>>,
}

impl<D: Dim, S: Solver<D>> DistributedSolver<D, S> {
    /// Wraps the rank's solver `inner`, built on `domain`'s local particles.
    pub fn new(inner: S, domain: Arc<Domain>) -> Self {
        Self {
            inner,
            domain,
            positions: OnceCell::new(),
            velocities: OnceCell::new(),
        }
    }

    /// The rank's solver.
    pub fn local(&self) -> &S {
        &self.inner
    }

    /// The rank's domain.
    pub fn domain(&self) -> &Domain {
        &self.domain
    }
}

impl<D: Dim, S: Solver<D>> Solver<D> for DistributedSolver<D, S> {
    fn method(&self) -> &'static str {
        self.inner.method()
    }

    fn step(&mut self, max_dt: f64) -> Result<StepInfo, Error> {
        self.positions = OnceCell::new();
        self.velocities = OnceCell::new();
        self.inner.step(max_dt)
    }

    fn stable_dt(&self) -> f64 {
        self.inner.stable_dt()
    }

    fn check_time_step(&self) -> Result<(), Error> {
        self.inner.check_time_step()
    }

    fn substep_dt(&self) -> f64 {
        self.inner.substep_dt()
    }

    fn time(&self) -> f64 {
        self.inner.time()
    }

    fn step_count(&self) -> u64 {
        self.inner.step_count()
    }

    fn len(&self) -> usize {
        self.domain.partition.len()
    }

    fn positions(&self) -> &[D::Vector] {
        self.positions
            .get_or_init(|| self.domain.gather_vectors::<D>(self.inner.positions()))
    }

    fn velocities(&self) -> &[D::Vector] {
        self.velocities
            .get_or_init(|| self.domain.gather_vectors::<D>(self.inner.velocities()))
    }

    fn field_names(&self) -> Vec<&'static str> {
        self.inner.field_names()
    }

    fn field(&self, name: &str) -> Option<Field<D>> {
        self.inner
            .field(name)
            .map(|f| self.domain.gather_field::<D>(f))
    }

    fn probes(&self) -> &[Probe<D>] {
        self.inner.probes()
    }

    fn series(&self) -> Vec<Series> {
        self.inner.series()
    }

    fn energies(&self) -> Option<(f64, f64)> {
        self.inner.energies()
    }

    fn momentum(&self) -> Option<glam::DVec3> {
        self.inner.momentum()
    }

    fn energy_budget(&self) -> Option<EnergyBudget> {
        self.inner.energy_budget()
    }

    /// Pair visits summed over the ranks, the halo layer's rows included (the work done).
    fn pair_visits(&self) -> Option<u64> {
        let local = self.inner.pair_visits();
        let total = self
            .domain
            .comm
            .sum(&[local.map_or(f64::NAN, |v| v as f64)]);
        total[0].is_finite().then_some(total[0] as u64)
    }

    fn ranks(&self) -> usize {
        self.domain.comm.size()
    }

    fn owned_share(&self) -> Option<OwnedShare<'_, D>> {
        Some(OwnedShare {
            local: &self.inner,
            domain: &self.domain,
        })
    }

    /// This rank's state (its particles and halo), after its rank and the rank count: one
    /// checkpoint per rank, resumed on as many ranks (the decomposition of the same scene on
    /// the same count is the same).
    fn save_state(&self, out: &mut crate::StateWriter) -> Result<(), Error> {
        let c = &self.domain.comm;
        out.u64s("rank_of_ranks", &[c.rank() as u64, c.size() as u64]);
        self.inner.save_state(out)
    }

    fn restore_state(&mut self, input: &mut crate::StateReader<'_>) -> Result<(), Error> {
        let c = &self.domain.comm;
        let saved = input.u64s("rank_of_ranks", Some(2))?;
        if saved != [c.rank() as u64, c.size() as u64] {
            return Err(Error::Checkpoint(format!(
                "written by rank {} of {}; this is rank {} of {} (resume on as many ranks as \
                 the run had)",
                saved[0],
                saved[1],
                c.rank(),
                c.size()
            )));
        }
        self.positions = OnceCell::new();
        self.velocities = OnceCell::new();
        self.inner.restore_state(input)
    }
}
