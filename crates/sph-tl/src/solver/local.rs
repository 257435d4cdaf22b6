//! One rank's TL solver in a distributed run: the fully built solver restricted to the rank's
//! owned particles and halo ([`sph_core::distributed::Domain`]).
//!
//! Per step the rank exchanges one message with each neighbouring rank: the velocities of its
//! two halo layers (and probe particles), right after the velocity update. With them it
//! computes `Ḟ` (eq 22) of its owned particles and of halo layer 1, whose neighbours are all
//! local, and the half-drifts of `F` and `x` follow for both, so the next force pass (eq 20–29)
//! of an owned particle reads exactly the neighbour values the single-process run reads, in
//! the same order: the positions are bit-identical for any rank count. Layer 2's rows are left
//! empty (its `Ḟ` stays zero and `F` the identity; only its velocities and positions are read).
//! Time-step maxima, the finiteness check, energies and momentum are reduced over the ranks.

use super::TlSolver;
use sph_core::distributed::{DistributedSolver, Domain};
use sph_core::{Dim, Error};
use sph_materials::Material;
use std::sync::Arc;

/// Distributes a built TL solver (constraints, loads and probes attached) over `comm`'s ranks:
/// recursive coordinate bisection of the reference configuration weighted by neighbour count
/// ([`sph_core::decomposition`]), then this rank's share. Collective: every rank calls it with
/// the same solver. On one rank the result steps exactly as `solver` would.
///
/// # Errors
/// Tools, the pairwise relaxation, a held centre of mass or named constraints (grips) attached:
/// these reduce over particles in ways not distributed yet; more ranks than particles.
pub fn distribute<D: Dim, M: Material<D>>(
    solver: TlSolver<D, M>,
    comm: Arc<dyn sph_core::comm::Communicator>,
) -> Result<DistributedSolver<D, TlSolver<D, M>>, Error> {
    let domain = Domain::for_body::<D>(comm, &solver.reference, &solver.list, &solver.probes)?;
    let local = solver.into_local(domain.clone())?;
    Ok(DistributedSolver::new(local, domain))
}

impl<D: Dim, M: Material<D>> TlSolver<D, M> {
    /// This solver restricted to `domain`'s particles (see the module documentation).
    fn into_local(mut self, domain: Arc<Domain>) -> Result<Self, Error> {
        let refuse = |what: &str| {
            Err(Error::invalid(
                "ranks",
                domain.comm().size(),
                &format!("1 for a TL run with {what} (not distributed yet)"),
            ))
        };
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
        let (list, pair_ids) = domain.local_rows(&self.list)?;
        self.pairs.pick_slots(&pair_ids);
        self.list = list;
        let (global, inv, d) = (domain.global(), domain.local_of(), &*domain);
        let pick = |v: &[D::Vector]| d.pick(v);
        let pick_m = |v: &[D::Matrix]| d.pick(v);
        let pick_f = |v: &[f64]| d.pick(v);
        self.reference = pick(&self.reference);
        self.positions = pick(&self.positions);
        self.velocities = pick(&self.velocities);
        self.accelerations = pick(&self.accelerations);
        self.volumes = pick_f(&self.volumes);
        self.masses = pick_f(&self.masses);
        self.correction = pick_m(&self.correction);
        self.deformation = pick_m(&self.deformation);
        self.deformation_rate = pick_m(&self.deformation_rate);
        self.stress = pick_m(&self.stress);
        if !self.isochoric.is_empty() {
            self.isochoric = pick_f(&self.isochoric);
        }
        // Time-step maxima over the owned unconstrained particles only.
        self.free = global
            .iter()
            .zip(domain.owned())
            .map(|(&g, &o)| o && self.free[g as usize])
            .collect();
        self.constraints.restrict(inv);
        self.loads.restrict(inv);
        for p in &mut self.probes {
            p.remap(inv);
        }
        self.domain = Some(domain);
        Ok(self)
    }

    /// Overwrites the halo's velocities with their owners' (the step's one message per
    /// neighbouring rank).
    pub(super) fn exchange_velocities(&mut self) {
        if let Some(d) = &self.domain {
            d.exchange_vectors::<D>(&mut self.velocities);
        }
    }
}
