//! Building an MPS solver ([`MpsSolver::new`]): neighbours within `r_e`, the weights of eq 6
//! and `A_i⁻¹` of eq 5 in the reference configuration, and the forces of the initial state.

use super::{MpsParams, MpsSolver};
use crate::stabilisation::Stabilisation;
use crate::wls::{self, weight, Fit};
use rayon::prelude::*;
use sph_core::neighbor::CellGrid;
use sph_core::scene::ProbeSchedule;
use sph_core::tool::ToolSet;
use sph_core::{Body, Constraints, Dim, Error, Loads};
use sph_materials::Material;

impl<D: Dim, M: Material<D>> MpsSolver<D, M> {
    /// Builds the solver: neighbours within `r_e`, the weights of eq 6 and `A_i⁻¹` of eq 5 in
    /// the reference configuration, and the forces of the initial state.
    ///
    /// # Errors
    /// Empty body, mismatched array lengths, non-positive `dp`/volumes, `re_over_l0 ≤ 1`,
    /// `courant ≤ 0`, negative damping, non-finite or coincident positions, a material without
    /// strain energy, or a particle with fewer than `D + 1` neighbours
    /// ([`Error::TooFewNeighbours`]: its `A_i` is singular or nearly so).
    pub fn new(body: impl Into<Body<D>>, material: M, params: MpsParams) -> Result<Self, Error> {
        Self::with_materials(body, vec![material], Vec::new(), params)
    }

    /// [`MpsSolver::new`] with a material per particle: `material_of[i]` indexes `materials`
    /// for particle `i` (empty: every particle the first). The energy is
    /// `U = Σ_i V_i ψ_i(F_i)` with each particle's own strain energy `ψ_i`, so the forces of
    /// eq 7 stay `−∂U/∂x` and the model Hamiltonian whether the materials meet through contact
    /// (separate bodies) or are bonded (one body of several materials). Masses are `ρ0 V` of
    /// each particle's material, the stabilisation takes each particle's shear modulus, and
    /// the step `C l0 / c` the largest sound speed. `M` is one type for every particle: a
    /// scene's [`sph_materials::MaterialModel`] (an enum of the laws) lets bodies differ in law
    /// as well as in constants, without dynamic dispatch in the force loop.
    ///
    /// # Errors
    /// As [`MpsSolver::new`]; no material or more than 65 536; `material_of` neither empty nor
    /// one index below `materials.len()` per particle.
    pub fn with_materials(
        body: impl Into<Body<D>>,
        materials: Vec<M>,
        material_of: Vec<u32>,
        params: MpsParams,
    ) -> Result<Self, Error> {
        let body: Body<D> = body.into();
        body.validate("mps body")?;
        body.reject_densities("mps")?;
        params.validate()?;
        let n = body.len();
        let velocities = body.velocities_or_rest();
        let material = sph_core::body::material_indices(materials.len(), &material_of, n)?;
        for material in &materials {
            if material.strain_energy_density(D::identity()).is_none() {
                return Err(Error::invalid(
                    "material",
                    material.name(),
                    "a hyperelastic law with a strain energy (the Hamiltonian needs ψ)",
                ));
            }
        }
        let constants_of = |i: usize| *materials[material[i] as usize].constants();
        let sound_speed = materials
            .iter()
            .map(|m| m.constants().sound_speed)
            .fold(0.0, f64::max);
        let re = params.re_over_l0 * body.dp;
        let reference = body.positions;
        let list = CellGrid::<D>::build(&reference, re)?.neighbor_list(&reference, re)?;
        if let Some(i) = (0..n).find(|&i| list.count(i) < D::D + 1) {
            return Err(Error::TooFewNeighbours {
                particle: i,
                found: list.count(i),
                required: D::D + 1,
            });
        }
        // Per-pair reference data (eq 6), in list order: (w_ij, X_ij).
        let mut pairs = vec![(0.0, D::zero()); list.num_pairs()];
        for i in 0..n {
            for (k, &j) in list.range(i).zip(list.neighbors(i)) {
                let xij = reference[j as usize] - reference[i];
                let r = D::norm(xij);
                if r <= 0.0 {
                    return Err(Error::invalid(
                        "positions",
                        format!("particle {i} coincides with particle {j}"),
                        "distinct reference positions",
                    ));
                }
                pairs[k] = (weight(r, re), xij);
            }
        }
        let ref_weights: Vec<f64> = pairs.iter().map(|&(w, _)| w).collect();
        let inv: Vec<(D::Matrix, bool)> = (0..n)
            .into_par_iter()
            .map(|i| {
                wls::moment_inverse::<D>(
                    pairs[list.range(i)].iter().copied(),
                    params.moment_min_eigenvalue,
                )
            })
            .collect();
        let a_inv: Vec<D::Matrix> = inv.iter().map(|r| r.0).collect();
        let fits: Vec<(Vec<D::Vector>, bool)> = (0..n)
            .into_par_iter()
            .map(|i| {
                let own = &pairs[list.range(i)];
                match params.fit {
                    Fit::Linear => (
                        own.iter().map(|&(w, x)| a_inv[i] * (x * w)).collect(),
                        inv[i].1,
                    ),
                    Fit::Quadratic => {
                        wls::quadratic_gradient_vectors::<D>(own, re, params.moment_min_eigenvalue)
                    }
                }
            })
            .collect();
        let guarded = fits.iter().filter(|r| r.1).count();
        let g: Vec<D::Vector> = fits.into_iter().flat_map(|r| r.0).collect();
        let g_rev = wls::reverse_pairs(&list).iter().map(|&k| g[k]).collect();
        let volumes = body.volumes;
        let stabilisation = if params.stabilisation > 0.0 {
            let mu: Vec<f64> = (0..n).map(|i| constants_of(i).shear_modulus).collect();
            Some(Stabilisation::new(
                params.stabilisation,
                &mu,
                &list,
                &pairs,
                &volumes,
            )?)
        } else {
            None
        };
        let masses: Vec<f64> = volumes
            .iter()
            .enumerate()
            .map(|(i, v)| v * constants_of(i).density)
            .collect();
        let mut solver = Self {
            materials,
            material,
            params,
            dp: body.dp,
            re,
            sound_speed,
            positions: reference.clone(),
            reference,
            inv_masses: masses.iter().map(|m| 1.0 / m).collect(),
            volumes,
            masses,
            list,
            g,
            g_rev,
            a_inv,
            guarded,
            ref_weights,
            velocities,
            deformation: vec![D::identity(); n],
            stress_term: vec![D::zero_matrix(); n],
            forces: vec![D::zero(); n],
            accelerations: vec![D::zero(); n],
            scratch: vec![D::zero(); n],
            constraints: Constraints::new(),
            loads: Loads::new(),
            pressures: Vec::new(),
            contact: None,
            contact_energy: 0.0,
            tools: ToolSet::default(),
            free: vec![true; n],
            stabilisation,
            stabilisation_energy: 0.0,
            probes: Vec::new(),
            schedule: ProbeSchedule::every(0.0)?,
            time: 0.0,
            steps: 0,
            domain: None,
        };
        solver.refresh();
        Ok(solver)
    }
}
