//! What the solver reports about its state: momentum and its balance, energies and the
//! energy budget, the disorder indicator, the Cauchy stress of the output fields.

use super::*;

impl<D: Dim> UlSolver<D> {
    /// Total linear momentum `Σ m v`.
    pub fn linear_momentum(&self) -> D::Vector {
        self.velocities
            .iter()
            .zip(&self.masses)
            .fold(D::zero(), |s, (&v, &m)| s + v * m)
    }

    /// The momentum balance `Σ m v − (Σ m v)(t = 0) + J_c`, with `J_c` the impulse the
    /// constraints removed (the supports' reaction) less the impulse the rigid tools gave (and
    /// the friction with fixed partners): zero up to round-off for any scene without loads,
    /// since every internal and contact pair term is antisymmetric. (ENOG drops the
    /// accumulated `A_s` of a particle that loses all its neighbours, which breaks the balance
    /// by that particle's share.)
    pub fn momentum_balance(&self) -> D::Vector {
        self.linear_momentum() - self.initial_momentum + self.constraint_impulse
    }

    /// Total angular momentum `Σ m x × v` about the origin (3-vector; only `z` in 2D).
    pub fn angular_momentum(&self) -> glam::DVec3 {
        self.positions
            .iter()
            .zip(&self.velocities)
            .zip(&self.masses)
            .fold(glam::DVec3::ZERO, |s, ((&x, &v), &m)| {
                s + D::to_vec3(x).cross(D::to_vec3(v)) * m
            })
    }

    /// Kinetic, volumetric and shear energy.
    pub fn energy(&self) -> Energy {
        let kinetic = 0.5
            * self
                .velocities
                .iter()
                .zip(&self.masses)
                .map(|(&v, &m)| m * D::norm_squared(v))
                .sum::<f64>();
        let volumetric = self
            .densities
            .iter()
            .zip(&self.masses)
            .zip(&self.material)
            .map(|((&rho, &m), &k)| {
                let c = &self.materials[k as usize];
                pressure_energy(m, rho, c.density, c.sound_speed)
            })
            .sum();
        let shear = if self.tracks_stress {
            self.stress
                .iter()
                .zip(&self.masses)
                .zip(&self.densities)
                .zip(&self.material)
                .map(|(((&t, &m), &rho), &k)| {
                    shear_energy::<D>(t, m / rho, self.materials[k as usize].shear_modulus)
                })
                .sum()
        } else if self.params.energy_budget {
            // ENOG without its output-only τ: the energy stored by the shear acceleration is
            // the work done against it, which the budget accumulates exactly.
            -self.work.shear
        } else {
            // Neither τ nor the shear work is kept: not known (the summary shows null).
            f64::NAN
        };
        Energy {
            kinetic,
            volumetric,
            shear,
        }
    }

    /// Work accumulated since `t = 0` by the force parts the budget tracks (zero without
    /// [`UlParams::energy_budget`]).
    pub fn accumulated_work(&self) -> AccumulatedWork {
        self.work
    }

    /// The energy budget now (see [`crate::energy`]): meaningful with
    /// [`UlParams::energy_budget`] (otherwise the accumulated work stays zero).
    pub(super) fn energy_budget_now(&self) -> EnergyBudget {
        let contact = self.contact.as_ref().map_or(0.0, |c| {
            c.energy(&self.positions, &self.masses, &self.kernel)
        });
        let mut budget = ul_budget(
            &self.energy(),
            contact,
            &self.work,
            matches!(self.variant, Variant::NonNested { .. }),
            self.tracks_stress,
            self.initial_total,
        );
        // The tools' terms (minus their work on the body), only where there are tools.
        if matches!(self.variant, Variant::Generalized { .. }) {
            // GNOG's penalty: minus its work (kept in `shear` with the accumulated acceleration).
            budget.terms.push(("hourglass_penalty", -self.work.shear));
        }
        if self.plasticity.is_some() {
            budget.terms.push(("plastic", self.plastic_work()));
        }
        budget.terms.extend(self.tools.budget_terms());
        if let Some(f) = &self.contact_friction {
            budget.terms.push(("contact_friction", -f.work()));
        }
        if !self.tools.is_empty() {
            budget
                .notes
                .push(("friction_dissipated", self.tools.work().friction_dissipated));
        }
        budget
    }

    /// The disorder indicator of docs/methods.md per particle (current order), accumulated since
    /// the start: Ganzenmüller's error of the weighted least-squares affine fit from the initial
    /// configuration to the current one, over the current neighbours with weights `W⁰` of the
    /// initial distances (neighbours that were not neighbours initially get `W⁰ = 0`).
    ///
    /// docs/methods.md suggests the fit over the last advection step for UL; that measures the
    /// non-affine *increment* of one step (≤ 3·10⁻⁴ on the plate whether or not it is ordered)
    /// and misses a zigzag pattern once it has formed, so the accumulated form is reported;
    /// [`UlSolver::disorder_increment`] gives the per-step form.
    pub fn disorder(&self) -> Vec<f64> {
        // Evaluated pair by pair: the initial configuration's kernel data of today's list
        // would be a whole pair list per monitor sample (127 MB for the 3D ball-plate).
        let reference = ReferenceWeights::Kernel(&self.kernel);
        let f = affine_fit::<D>(
            &self.list,
            reference,
            &self.initial_positions,
            &self.positions,
        );
        disorder_indicator::<D>(
            &self.list,
            reference,
            &self.initial_positions,
            &self.positions,
            &f,
        )
    }

    /// The per-step disorder indicator: the affine fit of the motion since the last rebuild
    /// (the last advection step for dual stepping, the last acoustic step for single stepping)
    /// over the neighbours of that rebuild, weighted with the kernel at the rebuild's distances
    /// (docs/methods.md's UL form).
    pub fn disorder_increment(&self) -> Vec<f64> {
        let reference = ReferenceWeights::Kernel(&self.kernel);
        let f = affine_fit::<D>(
            &self.list,
            reference,
            &self.rebuild_positions,
            &self.positions,
        );
        disorder_indicator::<D>(
            &self.list,
            reference,
            &self.rebuild_positions,
            &self.positions,
            &f,
        )
    }

    /// Cauchy stress `σ = τ − p I` (3×3; the out-of-plane entry is `−p` in 2D).
    pub(super) fn cauchy_3d(&self, i: usize) -> glam::DMat3 {
        let c = self.material_of(i);
        let p = pressure(self.densities[i], c.density, c.sound_speed);
        let tau = self.stress.get(i).copied().unwrap_or(D::zero_matrix());
        D::to_mat3(tau - D::identity() * p, -p)
    }
}
