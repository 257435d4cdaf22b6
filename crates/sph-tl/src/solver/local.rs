//! One rank's TL solver in a distributed run: the rank's owned particles and halo
//! ([`sph_core::distributed::Domain`]), with the reference data of those only (built by the
//! rank from a deferred solver, or cut from a fully built one).
//!
//! Per step the rank exchanges one message with each neighbouring rank: the velocities of its
//! two halo layers (and probe particles), right after the velocity update. With them it
//! computes `Ḟ` (eq 22) of its owned particles and of halo layer 1, whose neighbours are all
//! local, and the half-drifts of `F` and `x` follow for both, so the next force pass (eq 20–29)
//! of an owned particle reads exactly the neighbour values the single-process run reads, in
//! the same order: the positions are bit-identical for any rank count. Layer 2's rows are left
//! empty (its `Ḟ` stays zero and `F` the identity; only its velocities and positions are read).
//! Time-step maxima, the finiteness check, energies and momentum are reduced over the ranks.

use super::{coincident_error, TlSolver};
use sph_core::distributed::{DistributedSolver, Domain, OverRanks};
use sph_core::neighbor::{neighbour_counts, CellGrid, GridNeighbours};
use sph_core::{Dim, Error, Kernel};
use sph_materials::Material;
use std::sync::Arc;

/// Distributes a TL solver (constraints, loads and probes attached) over `comm`'s ranks:
/// recursive coordinate bisection of the reference configuration weighted by neighbour count
/// ([`sph_core::decomposition`]), then this rank's share. Collective: every rank calls it with
/// the same solver. On one rank the result steps exactly as `solver` would.
///
/// A solver from [`TlSolver::for_ranks`] has no neighbour data yet: each rank searches the
/// neighbours of its own particles and halo only (a cell grid over the reference positions,
/// [`GridNeighbours`]) and builds the pair data and correction matrices of those, so the
/// whole body's are never held anywhere. A solver from [`TlSolver::new`] is cut down to the
/// rank's share. Both give the same local solver, bit for bit.
///
/// # Errors
/// Tools, the pairwise relaxation, a held centre of mass or named constraints (grips)
/// attached: these reduce over particles in ways not distributed yet; more ranks than
/// particles; for a deferred solver, the neighbour errors of [`TlSolver::new`] (found on every
/// rank alike).
pub fn distribute<D: Dim, M: Material<D>>(
    solver: TlSolver<D, M>,
    comm: Arc<dyn sph_core::comm::Communicator>,
) -> Result<DistributedSolver<D, TlSolver<D, M>>, Error> {
    solver.refuse_undistributed(comm.size())?;
    if !solver.deferred {
        let domain = Domain::for_body::<D>(comm, &solver.reference, &solver.list, &solver.probes)?;
        let local = solver.into_local(domain.clone())?;
        return Ok(DistributedSolver::new(local, domain));
    }
    let cutoff = solver.kernel.cutoff();
    let grid = CellGrid::<D>::build(&solver.reference, cutoff)?;
    let source = GridNeighbours::new(&grid, &solver.reference, cutoff)?;
    // The checks of `TlSolver::new`, on the whole body: every rank finds the same error. The
    // counts are the bisection's weights too.
    let counts = neighbour_counts(&source);
    if let Some(i) = counts.iter().position(|&c| (c as usize) < D::D) {
        return Err(Error::TooFewNeighbours {
            particle: i,
            found: counts[i] as usize,
            required: D::D,
        });
    }
    if let Some(i) = source.first_coincident() {
        return Err(coincident_error(i));
    }
    let domain =
        Domain::for_body_counted::<D>(comm, &solver.reference, &source, &counts, &solver.probes)?;
    drop(counts);
    let list = domain.local_list(&source)?;
    drop(grid);
    let local = solver.into_local_deferred(domain.clone(), list)?;
    Ok(DistributedSolver::new(local, domain))
}

impl<D: Dim, M: Material<D>> TlSolver<D, M> {
    /// Refuses, on more than one rank, what is not distributed yet.
    fn refuse_undistributed(&self, ranks: usize) -> Result<(), Error> {
        if ranks <= 1 {
            return Ok(());
        }
        let refuse = |what: &str| {
            Err(Error::invalid(
                "ranks",
                ranks,
                &format!("1 for a TL run with {what} (not distributed yet)"),
            ))
        };
        if self.contact.is_some() {
            return refuse("several bodies or self-contact");
        }
        if !self.tools.is_empty() {
            return refuse("rigid tools");
        }
        if self.relaxation.is_some() {
            return refuse("the pairwise relaxation");
        }
        if self.held_axes.iter().any(|&a| a) {
            return refuse("a held centre of mass");
        }
        if self.constraints.named().next().is_some() {
            return refuse("named constraints (grips)");
        }
        Ok(())
    }

    /// The rank's share of a deferred solver ([`TlSolver::for_ranks`]): its particles' state
    /// picked from the whole body, and its reference data built over `list` (the local rows
    /// of [`Domain::local_list`]). Collective (the guarded count and the rates reduce over the
    /// ranks).
    fn into_local_deferred(
        mut self,
        domain: Arc<Domain>,
        list: sph_core::NeighborList,
    ) -> Result<Self, Error> {
        self.pick_particles(&domain);
        let owned = domain.owned();
        let built = self.build_reference_data(list, |l| owned[l]);
        self.domain = Some(domain.clone());
        // The coincidence check ran on the whole body; a rank's rows are a part of it.
        self.domain.agree(built)?;
        self.guarded = self.domain.sum_over_ranks(&[self.guarded as f64])[0] as usize;
        self.refresh_rates();
        Ok(self)
    }

    /// This solver restricted to `domain`'s particles (see the module documentation).
    fn into_local(mut self, domain: Arc<Domain>) -> Result<Self, Error> {
        let (list, pair_ids) = domain.local_rows(&self.list)?;
        self.pairs.pick_slots(&pair_ids);
        self.list = list;
        self.pick_particles(&domain);
        let d = &*domain;
        self.accelerations = d.pick(&self.accelerations);
        self.correction = d.pick(&self.correction);
        self.deformation = d.pick(&self.deformation);
        self.deformation_rate = d.pick(&self.deformation_rate);
        self.stress = d.pick(&self.stress);
        if !self.isochoric.is_empty() {
            self.isochoric = d.pick(&self.isochoric);
        }
        if !self.hf_zeta.is_empty() {
            self.hf_zeta = d.pick(&self.hf_zeta);
        }
        self.domain = Some(domain);
        Ok(self)
    }

    /// Keeps `domain`'s particles of what every solver has, built or deferred: the reference
    /// and current positions, velocities, volumes and masses, the free mask (time-step maxima
    /// over the owned unconstrained particles only), and the scene's constraints, loads and
    /// probes relabelled to local indices.
    fn pick_particles(&mut self, domain: &Domain) {
        let (global, inv) = (domain.global(), domain.local_of());
        self.reference = domain.pick(&self.reference);
        self.positions = domain.pick(&self.positions);
        self.velocities = domain.pick(&self.velocities);
        self.volumes = domain.pick(&self.volumes);
        self.masses = domain.pick(&self.masses);
        if !self.plastic.is_empty() {
            self.plastic = domain.pick(&self.plastic);
        }
        self.free = global
            .iter()
            .zip(domain.owned())
            .map(|(&g, &o)| o && self.free[g as usize])
            .collect();
        self.constraints.restrict(inv);
        self.loads.restrict(inv);
        for sp in &mut self.pressures {
            sp.restrict(inv);
        }
        for p in &mut self.probes {
            p.remap(inv);
        }
    }

    /// Overwrites the halo's velocities with their owners' (the step's one message per
    /// neighbouring rank).
    pub(super) fn exchange_velocities(&mut self) {
        if let Some(d) = &self.domain {
            d.exchange_vectors::<D>(&mut self.velocities);
        }
    }
}
