//! One rank's MPS solver in a distributed run: the fully built solver restricted to the rank's
//! owned particles and halo ([`sph_core::distributed::Domain`]).
//!
//! The force on an owned particle reads `T_j` (eq 7) of its neighbours, and `T_j` reads `F_j`
//! (eq 4), the positions of `j`'s neighbours: a rank keeps two halo layers, computes `F` and
//! `T` for its owned particles and layer 1 (whose neighbour rows are complete), and at the end
//! of each step receives the velocities and accelerations of both layers (and of the probe
//! particles) from their owners, in one message per neighbouring rank. Its halo then kicks and
//! drifts exactly as the owners do, so every owned particle sees the neighbour values of the
//! single-process run in the same order: positions are bit-identical for any rank count.
//! The blow-up guard's maxima, the finiteness check, energies and momentum are reduced over
//! the ranks.

use super::MpsSolver;
use sph_core::distributed::{vector_of, DistributedSolver, Domain};
use sph_core::{Dim, Error};
use sph_materials::Material;
use std::sync::Arc;

/// Distributes a built MPS solver (constraints, loads, surface pressures and probes attached)
/// over `comm`'s ranks: recursive coordinate bisection of the reference configuration weighted
/// by neighbour count ([`sph_core::decomposition`]), then this rank's share. Collective: every
/// rank calls it with the same solver. On one rank the result steps exactly as `solver` would.
///
/// # Errors
/// Contact attached (its search is over the current configuration; not distributed yet);
/// more ranks than particles.
pub fn distribute<D: Dim, M: Material<D>>(
    solver: MpsSolver<D, M>,
    comm: Arc<dyn sph_core::comm::Communicator>,
) -> Result<DistributedSolver<D, MpsSolver<D, M>>, Error> {
    if !solver.tools.is_empty() {
        return Err(Error::invalid(
            "ranks",
            comm.size(),
            "1 for an MPS run with rigid tools (not distributed yet)",
        ));
    }
    if solver.contact.is_some() {
        return Err(Error::invalid(
            "ranks",
            comm.size(),
            "1 for an MPS run with contact (not distributed yet)",
        ));
    }
    let domain = Domain::for_body::<D>(comm, &solver.reference, &solver.list, &solver.probes)?;
    let local = solver.into_local(domain.clone())?;
    Ok(DistributedSolver::new(local, domain))
}

impl<D: Dim, M: Material<D>> MpsSolver<D, M> {
    /// This solver restricted to `domain`'s particles (see the module documentation).
    fn into_local(mut self, domain: Arc<Domain>) -> Result<Self, Error> {
        let (list, pair_ids) = domain.local_rows(&self.list)?;
        let d = &*domain;
        let pairs = |v: &[D::Vector]| pair_ids.iter().map(|&k| v[k]).collect::<Vec<_>>();
        self.g = pairs(&self.g);
        self.g_rev = pairs(&self.g_rev);
        self.ref_weights = pair_ids.iter().map(|&k| self.ref_weights[k]).collect();
        if let Some(st) = &mut self.stabilisation {
            st.restrict(d, &pair_ids);
        }
        self.list = list;
        self.reference = d.pick(&self.reference);
        self.volumes = d.pick(&self.volumes);
        self.masses = d.pick(&self.masses);
        self.material = d.pick(&self.material);
        self.inv_masses = d.pick(&self.inv_masses);
        self.a_inv = d.pick(&self.a_inv);
        self.positions = d.pick(&self.positions);
        self.velocities = d.pick(&self.velocities);
        self.deformation = d.pick(&self.deformation);
        self.stress_term = d.pick(&self.stress_term);
        self.forces = d.pick(&self.forces);
        self.accelerations = d.pick(&self.accelerations);
        self.scratch = d.pick(&self.scratch);
        let inv = d.local_of();
        self.constraints.restrict(inv);
        self.loads.restrict(inv);
        for sp in &mut self.pressures {
            sp.restrict(inv);
        }
        for p in &mut self.probes {
            p.remap(inv);
        }
        self.domain = Some(domain);
        Ok(self)
    }

    /// Overwrites the halo's velocities and accelerations with their owners' (the step's one
    /// message per neighbouring rank).
    pub(super) fn exchange_halo(&mut self) {
        let Some(d) = &self.domain else {
            return;
        };
        let w = D::D;
        let (v, a) = (&mut self.velocities, &mut self.accelerations);
        let got = d.send_halo(2 * w, |l, buf| {
            buf.extend((0..w).map(|k| D::component(v[l], k)));
            buf.extend((0..w).map(|k| D::component(a[l], k)));
        });
        d.unpack_halo(2 * w, &got, |l, c| {
            v[l] = vector_of::<D>(&c[..w]);
            a[l] = vector_of::<D>(&c[w..]);
        });
    }
}
