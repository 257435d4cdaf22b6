//! Contact between the bodies of one UL solver (docs/methods.md "Separate bodies", after SPHinXsys's
//! contact density and contact force), see [`crate::UlSolver::with_contact`].
//!
//! Each body keeps its own neighbours (pressure, shear, continuity and `B` see only the own
//! body). Particles of different bodies closer than the kernel support push each other apart
//! with the contact pressure of the contact density
//!
//! `ρ_c,i = Σ_{j ∈ other} max(W_ij − W(dp), 0) m_j`,  `p_c,i = κ c0,i² ρ_c,i`,
//! `a_i −= (2/m_i) Σ_j ½(p_c,i + p_c,j) V_i V_j W′_ij e_ij`,
//!
//! with the scale `κ` ([`crate::UlParams::contact_scale`], 1 = docs/methods.md) and `c0,i` the
//! sound speed of particle `i`'s body's material (the stiffness of each side, as SPHinXsys). Only pairs closer
//! than `dp` raise the contact density, so bodies whose surface particles (half a spacing inside
//! the surface) are further apart than `dp` do not interact: the contact starts when the
//! surfaces touch. Each pair term is antisymmetric, so linear momentum is conserved to
//! round-off; repulsive only (bodies separate freely).
//!
//! **Contact energy.** With `V = m/ρ0` the force is `−∂U_c/∂x_i` of
//! `U_c = Σ_i κ c0,i² m_i ρ_c,i² / (2 ρ0,i²)` ([`contact_energy`]) for pairs closer than `dp`
//! and bodies of one density; beyond
//! `dp` a pair still carries the force of its partners' contact pressures through `W′`, which
//! `U_c` does not contain, and `V = m/ρ` differs from `m/ρ0` by the volumetric strain. So `U_c`
//! is an estimate of the stored contact energy, and the solver also accumulates the exact work
//! of the contact forces (see [`crate::energy`]); their difference after the bodies separate is
//! the energy the contact model took out or put in.

use crate::solver::gather;
use sph_core::contact_friction::ContactFriction;
use sph_core::pairs::fill_pair_kernels;
use sph_core::{Dim, Error, NeighborList, PairKernel, WendlandC2};
use sph_materials::ElasticConstants;

/// Contact state of a solver whose particles form several bodies.
#[derive(Clone, Debug)]
pub(crate) struct Contact<D: Dim> {
    /// Body id per particle (current order).
    pub body: Vec<u32>,
    /// Number of bodies (largest id + 1).
    pub bodies: usize,
    /// Inter-body pairs of the last rebuild.
    list: NeighborList,
    /// Their kernel data at the positions of the last force evaluation.
    pairs: Vec<PairKernel<D>>,
    /// `W(dp)`.
    w_dp: f64,
    /// `κ c0²` per body (`c0` of the body's material).
    stiffness: Vec<f64>,
    /// `ρ0` per body.
    rho0: Vec<f64>,
    /// Contact densities `ρ_c` of the last force evaluation.
    density: Vec<f64>,
    /// Contact accelerations of the last force evaluation.
    pub accelerations: Vec<D::Vector>,
}

impl<D: Dim> Contact<D> {
    /// `body` in the solver's current order; `κ` scales the contact pressure; `materials[b]`
    /// is body `b`'s material.
    pub fn new(body: Vec<u32>, w_dp: f64, scale: f64, materials: &[ElasticConstants]) -> Self {
        let n = body.len();
        let bodies = body.iter().map(|&b| b as usize + 1).max().unwrap_or(0);
        Self {
            body,
            bodies,
            list: NeighborList::default(),
            pairs: Vec::new(),
            w_dp,
            stiffness: materials
                .iter()
                .map(|c| scale * c.sound_speed * c.sound_speed)
                .collect(),
            rho0: materials.iter().map(|c| c.density).collect(),
            density: vec![0.0; n],
            accelerations: vec![D::zero(); n],
        }
    }

    /// Splits a neighbour list of all particles into the own-body list (returned) and the
    /// inter-body contact list (kept).
    pub fn split(&mut self, all: &NeighborList) -> Result<NeighborList, Error> {
        let n = self.body.len();
        let (mut own_off, mut own_ix) = (Vec::with_capacity(n + 1), Vec::new());
        let (mut con_off, mut con_ix) = (Vec::with_capacity(n + 1), Vec::new());
        own_off.push(0);
        con_off.push(0);
        for i in 0..n {
            for &j in all.neighbors(i) {
                if self.body[j as usize] == self.body[i] {
                    own_ix.push(j);
                } else {
                    con_ix.push(j);
                }
            }
            own_off.push(own_ix.len());
            con_off.push(con_ix.len());
        }
        self.list = NeighborList::from_parts(con_off, con_ix)?;
        NeighborList::from_parts(own_off, own_ix)
    }

    /// Cross-body pairs of the current contact list (directed, as the solver's own list).
    pub fn num_pairs(&self) -> usize {
        self.list.num_pairs()
    }

    /// Applies `perm[new] = old` to the per-particle fields.
    pub fn permute(&mut self, perm: &[u32]) {
        use sph_core::neighbor::apply_permutation;
        self.body = apply_permutation(perm, &self.body);
        self.accelerations = apply_permutation(perm, &self.accelerations);
    }

    /// Computes the contact accelerations at `positions` into [`Contact::accelerations`] and
    /// adds them to `out`.
    pub fn add_accelerations(
        &mut self,
        positions: &[D::Vector],
        masses: &[f64],
        densities: &[f64],
        kernel: &WendlandC2<D>,
        out: &mut [D::Vector],
    ) {
        if self.list.num_pairs() == 0 {
            self.accelerations.iter_mut().for_each(|a| *a = D::zero());
            return;
        }
        self.update_pairs(positions, kernel);
        contact_density(
            &self.list,
            &self.pairs,
            kernel,
            masses,
            self.w_dp,
            &mut self.density,
        );
        let (list, pairs, rho_c) = (&self.list, &self.pairs, &self.density);
        let (body, k) = (&self.body, &self.stiffness);
        gather(
            &mut self.accelerations,
            #[inline(always)]
            |i, a| {
                let v_i = masses[i] / densities[i];
                let k_i = k[body[i] as usize];
                let mut acc = D::zero();
                for (pk, &j) in pairs[list.range(i)].iter().zip(list.neighbors(i)) {
                    let j = j as usize;
                    let k_j = k[body[j] as usize];
                    let p_star = contact_pressure(k_i, rho_c[i], k_j, rho_c[j]);
                    acc += pk.e * contact_pair_factor(p_star, v_i, masses[j] / densities[j], pk.dw);
                }
                *a = acc / masses[i];
            },
        );
        out.iter_mut()
            .zip(&self.accelerations)
            .for_each(|(o, &a)| *o += a);
    }

    fn update_pairs(&mut self, positions: &[D::Vector], kernel: &WendlandC2<D>) {
        self.pairs.resize(self.list.num_pairs(), PairKernel::zero());
        fill_pair_kernels(positions, positions, &self.list, kernel, &mut self.pairs);
    }

    /// The contact energy estimate [`contact_energy`] at `positions` (allocates; for monitor
    /// samples).
    pub fn energy(&self, positions: &[D::Vector], masses: &[f64], kernel: &WendlandC2<D>) -> f64 {
        if self.list.num_pairs() == 0 {
            return 0.0;
        }
        let mut pairs = vec![PairKernel::<D>::zero(); self.list.num_pairs()];
        let mut density = vec![0.0; masses.len()];
        fill_pair_kernels(positions, positions, &self.list, kernel, &mut pairs);
        contact_density(&self.list, &pairs, kernel, masses, self.w_dp, &mut density);
        masses
            .iter()
            .zip(&density)
            .zip(&self.body)
            .map(|((&m, &rho_c), &b)| {
                let b = b as usize;
                contact_energy(m, rho_c, self.stiffness[b], self.rho0[b])
            })
            .sum()
    }

    /// The Coulomb friction pass of [`sph_core::contact_friction`] over the contact pairs of
    /// the last force evaluation (their kernel data and contact densities, `densities` those
    /// of that evaluation): each pair's normal force is the magnitude of its contact force,
    /// `−2 p* V_i V_j W′_ij` (the operands grouped symmetrically). Returns the momentum change.
    pub fn apply_friction(
        &self,
        friction: &mut ContactFriction<D>,
        velocities: &mut [D::Vector],
        masses: &[f64],
        densities: &[f64],
        free: &[bool],
        dt: f64,
    ) -> D::Vector {
        if self.list.num_pairs() == 0 {
            return D::zero();
        }
        let (pairs, rho_c, body, k) = (&self.pairs, &self.density, &self.body, &self.stiffness);
        let normal = |i: usize, p: usize, j: usize| {
            let pk = &pairs[p];
            let p_star =
                contact_pressure(k[body[i] as usize], rho_c[i], k[body[j] as usize], rho_c[j]);
            let vv = (masses[i] / densities[i]) * (masses[j] / densities[j]);
            (pk.e, -2.0 * p_star * vv * pk.dw)
        };
        friction.apply(
            &self.list,
            &self.body,
            normal,
            &self.accelerations,
            velocities,
            masses,
            free,
            dt,
        )
    }

    /// Total contact force on each body, `Σ_{i ∈ b} m_i a_c,i`, of the last force evaluation.
    pub fn body_forces(&self, masses: &[f64]) -> Vec<D::Vector> {
        let mut f = vec![D::zero(); self.bodies];
        for ((&b, &a), &m) in self.body.iter().zip(&self.accelerations).zip(masses) {
            f[b as usize] += a * m;
        }
        f
    }
}

/// The contact density of docs/methods.md: `ρ_c,i = Σ_{j ∈ other} max(W_ij − W(dp), 0) m_j` over the
/// inter-body pairs of `list`.
fn contact_density<D: Dim>(
    list: &NeighborList,
    pairs: &[PairKernel<D>],
    kernel: &WendlandC2<D>,
    masses: &[f64],
    w_dp: f64,
    out: &mut [f64],
) {
    gather(
        out,
        #[inline(always)]
        |i, rho_c| {
            *rho_c = pairs[list.range(i)]
                .iter()
                .zip(list.neighbors(i))
                .map(|(pk, &j)| (pk.w(kernel) - w_dp).max(0.0) * masses[j as usize])
                .sum();
        },
    );
}

/// The pair's contact pressure `p* = ½(p_c,i + p_c,j)` with `p_c = κ c0² ρ_c` of each side's
/// own stiffness `k = κ c0²` (SPHinXsys's contact force); for bodies of one stiffness written
/// `½ k (ρ_c,i + ρ_c,j)`, the form (and the bits) of the one-material contact.
#[inline(always)]
pub fn contact_pressure(k_i: f64, rho_c_i: f64, k_j: f64, rho_c_j: f64) -> f64 {
    if k_i == k_j {
        0.5 * k_i * (rho_c_i + rho_c_j)
    } else {
        0.5 * (k_i * rho_c_i + k_j * rho_c_j)
    }
}

/// Contact force of one pair (docs/methods.md, SPHinXsys's contact force), the factor of `e_ij` in
/// `m_i a_i`: `−2 p* V_i V_j W′_ij` with `p* = ½(p_c,i + p_c,j)`; positive (repulsive) for
/// `W′ < 0`.
#[inline(always)]
pub fn contact_pair_factor(p_star: f64, v_i: f64, v_j: f64, dw: f64) -> f64 {
    -2.0 * p_star * v_i * v_j * dw
}

/// Contact energy of one particle, `κ c0² m ρ_c² / (2 ρ0²)` (`stiffness = κ c0²`): the
/// potential whose gradient is the contact force of [`contact_pair_factor`] for pairs closer
/// than `dp` with `V = m/ρ0` (see the module documentation).
#[inline]
pub fn contact_energy(m: f64, rho_c: f64, stiffness: f64, rho0: f64) -> f64 {
    0.5 * stiffness * m * rho_c * rho_c / (rho0 * rho0)
}
