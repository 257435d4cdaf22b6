//! A Hamiltonian stabilisation of the WLS kinematics (beyond the MPS paper).
//!
//! The WLS deformation gradient of eq 4–5 has displacement modes in its null space (the
//! alternating-column mode: test `wls_gradient_has_the_alternating_column_zero_energy_mode`),
//! so `U = Σ V ψ(F)` does not resist them and a body under large tension clumps. This adds a
//! penalty *potential* on what the affine fit leaves over — the residual of the WLS fit,
//! `r_ij = x_ij − F_i X_ij` (Ganzenmüller's hourglass error, here as an energy) — so that the
//! model stays Hamiltonian:
//!
//! `U_s = Σ_i ½ s_i Σ_j k_ij |r_ij|²`, `s_i = α μ V_i / Σ_j w_ij`, `k_ij = w_ij / |X_ij|²`.
//!
//! Per particle this is an energy density `(α μ / 2) ⟨|r_ij|² / |X_ij|²⟩_w`: the shear modulus
//! times the weighted mean square of the relative residual, a strain-like quantity, so the
//! dimensionless `α` means the same in every case (the residual's stiffness relative to shear).
//! An affine displacement has `r_ij = 0` (the WLS fit reproduces it), so `U_s` does not touch
//! homogeneous deformation; a smooth non-affine one (bending) has `|r_ij| ~ κ |X_ij|²`, a
//! stiffening of relative size `O(α (r_e/H)²)` that vanishes with resolution; a zigzag has
//! `|r_ij| ~ δ`, which now costs `~ α μ (δ/l0)²`.
//!
//! Force. With `F_i = Σ_j x_ij ⊗ g_ij` (fixed gradient vectors, [`crate::wls`]),
//! `dU_s = Σ_k [Σ_j c_kj r_kj · dx_kj − Q_k : dF_k]`, `c_kj = s_k k_kj`,
//! `Q_k = Σ_j c_kj r_kj ⊗ X_kj`. The second part has the form of `Σ_k V_k P_k : dF_k`, so it enters
//! eq 7 as the stress term `−Q_k` added to `V_k P_k` (pass 1; whatever fit gives `F`); the first gives the
//! pair force `f_i = Σ_j (c_ij r_ij − c_ji r_ji)` (pass 2). Each pair term is
//! antisymmetric, so linear momentum is exact; `U_s` is invariant under rigid rotation
//! (`r_ij → R r_ij`), so angular momentum is conserved; and the force is `−∂U_s/∂x` exactly
//! (tests by finite differences), so the symplectic integrator keeps the energy as before.

use sph_core::parallel::{gather, gather2};
use sph_core::{Dim, Error, NeighborList};

/// The stabilisation's per-pair and per-particle constants (reference configuration).
#[derive(Clone, Debug)]
pub(crate) struct Stabilisation<D: Dim> {
    /// `s_i = α μ V_i / Σ_j w_ij`.
    scale: Vec<f64>,
    /// `k_ij = w_ij / |X_ij|²`, in list order.
    pair: Vec<f64>,
    /// `X_ij = X_j − X_i`, in list order.
    reference: Vec<D::Vector>,
}

impl<D: Dim> Stabilisation<D> {
    /// Constants for strength `alpha` (> 0) and each particle's small-strain shear modulus
    /// `mu[i]`, from the reference pairs `(w_ij, X_ij)` of every particle in list order.
    pub fn new(
        alpha: f64,
        mu: &[f64],
        list: &NeighborList,
        pairs: &[(f64, D::Vector)],
        volumes: &[f64],
    ) -> Result<Self, Error> {
        sph_core::error::check_positive("stabilisation", alpha)?;
        let pair: Vec<f64> = pairs.iter().map(|&(w, x)| w / D::norm_squared(x)).collect();
        let scale = (0..volumes.len())
            .map(|i| {
                let sum_w: f64 = pairs[list.range(i)].iter().map(|p| p.0).sum();
                alpha * mu[i] * volumes[i] / sum_w
            })
            .collect();
        Ok(Self {
            scale,
            pair,
            reference: pairs.iter().map(|p| p.1).collect(),
        })
    }

    /// The constants of one rank's particles ([`sph_core::distributed::Domain::pick`]) and
    /// pairs (`pair_ids`: the global pair of each local one).
    pub fn restrict(&mut self, domain: &sph_core::distributed::Domain, pair_ids: &[usize]) {
        self.scale = domain.pick(&self.scale);
        self.pair = pair_ids.iter().map(|&k| self.pair[k]).collect();
        self.reference = pair_ids.iter().map(|&k| self.reference[k]).collect();
    }

    /// `r_ij = x_ij − F_i X_ij` of pair `k` of particle `i` (neighbour `j`).
    #[inline(always)]
    fn residual(&self, k: usize, xi: D::Vector, xj: D::Vector, fi: D::Matrix) -> D::Vector {
        xj - xi - fi * self.reference[k]
    }

    /// Pass 1 for particle `i` (after `F_i`): the stress term `−Q_i` to add to `V_i P_i`, and
    /// the particle's energy `½ s_i Σ_j k_ij |r_ij|²`.
    #[inline]
    pub fn particle_terms(
        &self,
        i: usize,
        list: &NeighborList,
        x: &[D::Vector],
        fi: D::Matrix,
    ) -> (D::Matrix, f64) {
        let s = self.scale[i];
        let mut q = D::zero_matrix();
        let mut e = 0.0;
        for (k, &j) in list.range(i).zip(list.neighbors(i)) {
            let r = self.residual(k, x[i], x[j as usize], fi);
            let c = s * self.pair[k];
            q += D::outer(r * c, self.reference[k]);
            e += c * D::norm_squared(r);
        }
        (q * -1.0, 0.5 * e)
    }

    /// Pass 2 (gather): adds the pair part `f_i = Σ_j (c_ij r_ij − c_ji r_ji)` to `forces`.
    pub fn pair_forces(
        &self,
        list: &NeighborList,
        x: &[D::Vector],
        deformation: &[D::Matrix],
        forces: &mut [D::Vector],
    ) {
        let (x_j, f_j, s_j) = (
            list.values(x),
            list.values(deformation),
            list.values(&self.scale),
        );
        gather(
            forces,
            #[inline(always)]
            |i, out| {
                let (si, fi, xi) = (self.scale[i], deformation[i], x[i]);
                let mut f = D::zero();
                for (k, &j) in list.range(i).zip(list.neighbors(i)) {
                    let j = j as usize;
                    // SAFETY: `j` is an index of `list`, which made the views.
                    let (x_j, f_j, s_j) = unsafe { (x_j.at(j), f_j.at(j), s_j.at(j)) };
                    let xij = x_j - xi;
                    let r_ij = xij - fi * self.reference[k];
                    // r_ji = x_ji − F_j X_ji = −(x_ij − F_j X_ij).
                    let r_ji = (f_j * self.reference[k]) - xij;
                    f += (r_ij * si - r_ji * s_j) * self.pair[k];
                }
                *out += f;
            },
        );
    }

    /// The energy of every particle, `½ s_i Σ_j k_ij |r_ij|²` (diagnostics).
    pub fn energies(
        &self,
        list: &NeighborList,
        x: &[D::Vector],
        deformation: &[D::Matrix],
    ) -> Vec<f64> {
        (0..x.len())
            .map(|i| {
                let e: f64 = list
                    .range(i)
                    .zip(list.neighbors(i))
                    .map(|(k, &j)| {
                        self.pair[k]
                            * D::norm_squared(self.residual(k, x[i], x[j as usize], deformation[i]))
                    })
                    .sum();
                0.5 * self.scale[i] * e
            })
            .collect()
    }

    /// Adds the stress terms of pass 1 to `stress_term` and returns the total energy `U_s`.
    pub fn add_stress_terms(
        &self,
        list: &NeighborList,
        x: &[D::Vector],
        deformation: &[D::Matrix],
        stress_term: &mut [D::Matrix],
    ) -> f64 {
        // Per-particle energies summed in index order: the same for every thread count.
        let mut energy = vec![0.0; x.len()];
        gather2(
            stress_term,
            &mut energy,
            #[inline(always)]
            |i, g, e| {
                let (t, ei) = self.particle_terms(i, list, x, deformation[i]);
                *g += t;
                *e = ei;
            },
        );
        energy.iter().sum()
    }
}
