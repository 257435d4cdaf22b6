//! What the solver reports about its state: momentum, energies (kinetic, strain with
//! contact, stabilisation) and the disorder indicator.

use super::*;

impl<D: Dim, M: Material<D>> MpsSolver<D, M> {
    /// Total linear momentum `Σ m v`.
    pub fn linear_momentum(&self) -> D::Vector {
        self.domain
            .linear_momentum::<D>(&self.velocities, &self.masses)
    }

    /// Total angular momentum `Σ m x × v` about the origin (3-vector; only `z` in 2D).
    pub fn angular_momentum(&self) -> glam::DVec3 {
        self.domain
            .angular_momentum::<D>(&self.positions, &self.velocities, &self.masses)
    }

    /// Kinetic energy `Σ ½ m v²`, strain energy `Σ V ψ(F)` (with the contact potential) and the
    /// stabilisation potential of the current state.
    ///
    /// In a distributed run: summed over the ranks' owned particles.
    pub fn energy(&self) -> Energy {
        if self.domain.is_some() {
            return self.distributed_energy();
        }
        let kinetic = diagnostics::kinetic_energy::<D>(&self.velocities, &self.masses);
        let strain = self
            .deformation
            .iter()
            .zip(&self.volumes)
            .zip(&self.material)
            .map(|((&f, &v), &k)| {
                v * self.materials[k as usize]
                    .strain_energy_density(f)
                    .unwrap_or(f64::NAN)
            })
            .sum::<f64>()
            + self.contact_energy;
        Energy {
            kinetic,
            strain,
            stabilisation: self.stabilisation_energy,
        }
    }

    /// [`MpsSolver::energy`] over the owned particles of every rank (no contact: refused).
    fn distributed_energy(&self) -> Energy {
        let owned = |i: &usize| self.domain.counts(*i);
        let n = self.len();
        let kinetic: f64 = (0..n)
            .filter(owned)
            .map(|i| 0.5 * self.masses[i] * D::norm_squared(self.velocities[i]))
            .sum();
        let strain: f64 = (0..n)
            .filter(owned)
            .map(|i| {
                self.volumes[i]
                    * self
                        .material_of(i)
                        .strain_energy_density(self.deformation[i])
                        .unwrap_or(f64::NAN)
            })
            .sum();
        let stabilisation: f64 = self
            .stabilisation_energies()
            .map_or(0.0, |e| (0..n).filter(owned).map(|i| e[i]).sum());
        let s = self
            .domain
            .sum_over_ranks(&[kinetic, strain, stabilisation]);
        Energy {
            kinetic: s[0],
            strain: s[1],
            stabilisation: s[2],
        }
    }

    /// The stabilisation energy of every particle, `½ s_i Σ_j k_ij |x_ij − F_i X_ij|²`
    /// ([`crate::stabilisation`]); `None` when the stabilisation is off.
    pub fn stabilisation_energies(&self) -> Option<Vec<f64>> {
        self.stabilisation
            .as_ref()
            .map(|st| st.energies(&self.list, &self.positions, &self.deformation))
    }

    /// The disorder indicator of docs/methods.md per particle, with the MPS weights of eq 6 in
    /// place of the kernel (`e_i = Σ_j w_ij |F_i X_ij − x_ij| / Σ_j w_ij |X_ij|`).
    pub fn disorder(&self) -> Vec<f64> {
        disorder_indicator::<D>(
            &self.list,
            ReferenceWeights::Stored(&self.ref_weights),
            &self.reference,
            &self.positions,
            &self.deformation,
        )
    }
}
