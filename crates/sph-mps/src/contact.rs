//! Penalty contact between separate bodies held in one solver.
//!
//! The MPS paper's colliding rings collide, but the paper does not describe a contact
//! treatment, and the Hamiltonian model's neighbours are fixed in the reference configuration,
//! so without one the rings would pass through each other. This adds the simplest treatment
//! that keeps the model Hamiltonian: a pair potential between particles of different bodies,
//!
//! `φ(r) = ½ k (r_c − r)²` for `r < r_c`, force on i `k (r_c − r) e_ij` (repulsive, central),
//!
//! with `r_c` the contact distance (default `dp`: lattice neighbours of two touching bodies
//! start to push at the spacing they would have inside one body) and `k = κ E dp^(d−2)` (κ the
//! stiffness factor, E the small-strain Young's modulus; between bodies of different materials
//! the softer one's: a penalty stiffer than the softer body adds nothing but a shorter stable
//! step). Being central and derived from a
//! potential, it conserves linear and angular momentum and total energy (the contact energy is
//! reported with the strain energy). Contact pairs are found every step from the current
//! positions with the core's cell list; a scene without contact never searches.

use sph_core::neighbor::CellGrid;
use sph_core::parallel::gather2;
use sph_core::{Dim, Error};

/// Contact between the bodies of one solver.
#[derive(Clone, Debug)]
pub struct Contact {
    /// Body index of each particle (particles of the same body never interact by contact).
    pub body_of: Vec<u32>,
    /// Contact distance `r_c` as a multiple of `dp` (default 1).
    pub distance_over_dp: f64,
    /// Stiffness factor κ in `k = κ E dp^(d−2)` (default 1).
    pub stiffness_factor: f64,
}

impl Contact {
    /// Contact between the bodies given per particle, with the default distance and stiffness.
    pub fn between(body_of: Vec<u32>) -> Self {
        Self {
            body_of,
            distance_over_dp: 1.0,
            stiffness_factor: 1.0,
        }
    }
}

/// A validated contact model with its dimensional constants.
#[derive(Clone, Debug)]
pub(crate) struct ResolvedContact {
    pub body_of: Vec<u32>,
    pub distance: f64,
    /// `κ E dp^(d−2)` per body.
    pub stiffness: Vec<f64>,
}

impl ResolvedContact {
    /// `youngs[b]`: body `b`'s Young's modulus.
    pub fn new<D: Dim>(c: Contact, n: usize, dp: f64, youngs: &[f64]) -> Result<Self, Error> {
        if c.body_of.len() != n {
            return Err(Error::invalid(
                "contact.body_of",
                c.body_of.len(),
                &format!("one entry per particle ({n})"),
            ));
        }
        sph_core::error::check_positive("contact.distance_over_dp", c.distance_over_dp)?;
        sph_core::error::check_positive("contact.stiffness_factor", c.stiffness_factor)?;
        Ok(Self {
            body_of: c.body_of,
            distance: c.distance_over_dp * dp,
            stiffness: youngs
                .iter()
                .map(|&e| c.stiffness_factor * e * dp.powi(D::D as i32 - 2))
                .collect(),
        })
    }

    /// Adds the contact forces of `positions` to `forces` and returns the contact energy.
    pub fn add_forces<D: Dim>(
        &self,
        positions: &[D::Vector],
        forces: &mut [D::Vector],
    ) -> Result<f64, Error> {
        let grid = CellGrid::<D>::build(positions, self.distance)?;
        let rc = self.distance;
        let body = &self.body_of;
        let stiffness = &self.stiffness;
        // Per-particle energies summed in index order: the same for every thread count.
        let mut energies = vec![0.0; positions.len()];
        gather2(
            forces,
            &mut energies,
            #[inline(always)]
            |i, f, energy| {
                let xi = positions[i];
                let k_i = stiffness[body[i] as usize];
                let mut sum = D::zero();
                let mut e = 0.0;
                // Gather over the candidates in the order the grid gives them (deterministic).
                grid.for_each_candidate_at(xi, |j, xj| {
                    if body[j as usize] == body[i] {
                        return;
                    }
                    let k = k_i.min(stiffness[body[j as usize] as usize]);
                    let d = xi - xj;
                    let r = D::norm(d);
                    if r < rc && r > 0.0 {
                        sum += d * (k * (rc - r) / r);
                        e += 0.25 * k * (rc - r) * (rc - r);
                    }
                });
                *f += sum;
                *energy = e;
            },
        );
        Ok(energies.iter().sum())
    }
}
