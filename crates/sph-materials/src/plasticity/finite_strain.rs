//! Finite-strain J2 plasticity for total-Lagrangian solvers: the multiplicative split
//! `F = Fe Fp` with a Hencky (logarithmic) elastic law and the exponential-map return in
//! principal logarithmic strains (Simo 1992, "Algorithms for static and dynamic multiplicative
//! plasticity that preserve the classical return mapping schemes of the infinitesimal theory",
//! CMAME 99; de Souza Neto, Perić & Owen 2008, *Computational Methods for Plasticity*, Box 14.3).
//!
//! Per particle the history is the inverse plastic right Cauchy–Green tensor `Cp⁻¹ = Fp⁻¹ Fp⁻ᵀ`
//! with the equivalent plastic strain (and the temperature rise of Johnson–Cook heating,
//! [`PlasticState`]). One return from `F_{n+1}`:
//!
//! 1. elastic trial `be* = F Cp⁻¹ Fᵀ`, its eigen-pairs `(λ_a², n_a)`, trial log strains
//!    `ε_a* = ln λ_a`;
//! 2. Hencky stress in the principal frame: `p = K Σ ε_a`, `s_a* = 2G (ε_a* − Σε/3)`;
//! 3. the radial return of the principal deviator `diag(s_a*)` — the small-strain return of
//!    Box 3.2 of Simo & Hughes (1998), the same function ([`Plasticity::return_stress`]) with the
//!    same flow stress (linear or saturation hardening, Johnson–Cook with rate and thermal
//!    factors) and the same heating: with the Hencky law and isotropy the finite-strain return is
//!    exactly the infinitesimal one in the log strains (Box 14.3, step 3);
//! 4. elastic log strains `ε_a = s_a/2G + Σε/3` (the volumetric part is elastic), Kirchhoff
//!    stress `τ = Σ (p + s_a) n_a⊗n_a`, `be = Σ exp(2ε_a) n_a⊗n_a`,
//!    `Cp⁻¹ = F⁻¹ be F⁻ᵀ`; first Piola `P = τ F⁻ᵀ`.
//!
//! Plastic incompressibility holds by construction: `det be = exp(2 Σε) = J²`, so
//! `det Cp⁻¹ = 1` (to round-off). Everything is 3×3: in 2D (plane strain) the solver embeds `F`
//! with `F_zz = 1` and the out-of-plane elastic and plastic stretches evolve freely.

use super::{PlasticLaw, PlasticState, Plasticity};
use crate::ElasticConstants;
use glam::{DMat3, DVec3};
use serde::{Deserialize, Serialize};
use sph_core::{Dim, Error, D3};

/// The history of one particle of a finite-strain plastic body.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FinitePlasticState {
    /// `Cp⁻¹ = Fp⁻¹ Fp⁻ᵀ` (symmetric, `det = 1`; the identity before any plastic flow).
    pub inverse_plastic_cauchy_green: DMat3,
    /// Equivalent plastic strain and temperature rise.
    pub state: PlasticState,
}

impl Default for FinitePlasticState {
    fn default() -> Self {
        Self {
            inverse_plastic_cauchy_green: DMat3::IDENTITY,
            state: PlasticState::default(),
        }
    }
}

/// The outcome of one exponential-map return.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HenckyReturn {
    /// Kirchhoff stress `τ` (3×3).
    pub kirchhoff: DMat3,
    /// The history after the return.
    pub history: FinitePlasticState,
    /// Equivalent plastic strain increment `Δε̄p` (0: elastic).
    pub delta_eps_p: f64,
    /// Plastic work of the return per unit reference volume, `τ:Δεp = q Δε̄p` (the returned
    /// von Mises stress `q` times the increment: the Kirchhoff deviator and the flow direction
    /// are coaxial; J/m³).
    pub plastic_work: f64,
}

/// J2 plasticity on a Hencky elastic law: what a TL solver holds for a plastic body.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct HenckyPlasticity {
    /// The flow law with the shear modulus and density (shared with the hypoelastic return).
    pub plasticity: Plasticity,
    /// Bulk modulus `K` of the Hencky law (Pa).
    pub bulk_modulus: f64,
}

impl HenckyPlasticity {
    /// The law with the elastic constants `K`, `G` and `ρ0` of `constants`, validated.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first constant out of range.
    pub fn new(law: PlasticLaw, constants: &ElasticConstants) -> Result<Self, Error> {
        sph_core::error::check_positive("bulk_modulus", constants.bulk_modulus)?;
        Ok(Self {
            plasticity: Plasticity::new(law, constants)?,
            bulk_modulus: constants.bulk_modulus,
        })
    }

    /// The exponential-map return of the module docs from the deformation gradient `f` (3×3)
    /// and the history at the start of the increment, over the time `dt` (the plastic strain
    /// rate is `Δε̄p/dt`; `dt` infinite: the rate-independent limit). A singular or inverted
    /// `f` gives a non-finite stress (the solver's non-finite check reports it).
    #[inline]
    pub fn return_mapping(&self, f: DMat3, history: &FinitePlasticState, dt: f64) -> HenckyReturn {
        let det = f.determinant();
        if det.is_nan() || det <= 0.0 {
            // Inverted, singular or non-finite: no elastic state; NaN surfaces in the step.
            return HenckyReturn {
                kirchhoff: DMat3::from_cols_array(&[f64::NAN; 9]),
                history: *history,
                delta_eps_p: 0.0,
                plastic_work: 0.0,
            };
        }
        let g = self.plasticity.shear_modulus;
        let be_trial = f * history.inverse_plastic_cauchy_green * f.transpose();
        let (lambda2, n) = D3::symmetric_eigen(be_trial);
        let eps = DVec3::new(
            0.5 * lambda2.x.ln(),
            0.5 * lambda2.y.ln(),
            0.5 * lambda2.z.ln(),
        );
        let volumetric = eps.x + eps.y + eps.z;
        let pressure = self.bulk_modulus * volumetric;
        let mut s = DMat3::from_diagonal((eps - DVec3::splat(volumetric / 3.0)) * (2.0 * g));
        let mut state = history.state;
        let delta = self.plasticity.return_stress::<D3>(&mut s, &mut state, dt);
        let s_a = DVec3::new(s.x_axis.x, s.y_axis.y, s.z_axis.z);
        let tau_a = s_a + DVec3::splat(pressure);
        let kirchhoff = D3::from_eigen(tau_a, n);
        let cp_inv = if delta > 0.0 {
            let e = s_a / (2.0 * g) + DVec3::splat(volumetric / 3.0);
            let be = D3::from_eigen(
                DVec3::new((2.0 * e.x).exp(), (2.0 * e.y).exp(), (2.0 * e.z).exp()),
                n,
            );
            let f_inv = f.inverse();
            symmetric_part(f_inv * be * f_inv.transpose())
        } else {
            history.inverse_plastic_cauchy_green
        };
        let plastic_work = if delta > 0.0 {
            super::equivalent_stress::<D3>(s) * delta
        } else {
            0.0
        };
        HenckyReturn {
            kirchhoff,
            history: FinitePlasticState {
                inverse_plastic_cauchy_green: cp_inv,
                state,
            },
            delta_eps_p: delta,
            plastic_work,
        }
    }

    /// Elastic strain energy per unit reference volume of the Hencky law at `f` with the plastic
    /// history `history` (no return): `ψ = K (Σε)²/2 + G Σ (ε_a − Σε/3)²`, `ε_a` the principal
    /// log strains of `be = F Cp⁻¹ Fᵀ` (de Souza Neto et al. 2008, eq. 14.61).
    pub fn strain_energy_density(&self, f: DMat3, history: &FinitePlasticState) -> f64 {
        let be = f * history.inverse_plastic_cauchy_green * f.transpose();
        let (lambda2, _) = D3::symmetric_eigen(be);
        let eps = DVec3::new(
            0.5 * lambda2.x.ln(),
            0.5 * lambda2.y.ln(),
            0.5 * lambda2.z.ln(),
        );
        let v = eps.x + eps.y + eps.z;
        let dev = eps - DVec3::splat(v / 3.0);
        0.5 * self.bulk_modulus * v * v + self.plasticity.shear_modulus * dev.length_squared()
    }
}

/// First Piola–Kirchhoff stress `P = τ F⁻ᵀ` of a Kirchhoff stress (de Souza Neto et al. 2008,
/// eq. 3.73 read backwards).
#[inline]
pub fn first_piola_of_kirchhoff(kirchhoff: DMat3, f: DMat3) -> DMat3 {
    kirchhoff * f.inverse().transpose()
}

/// `(m + mᵀ)/2`: removes the round-off asymmetry of a product that is symmetric in exact
/// arithmetic, so that `Cp⁻¹` stays symmetric over millions of steps.
#[inline]
fn symmetric_part(m: DMat3) -> DMat3 {
    (m + m.transpose()) * 0.5
}

#[cfg(test)]
mod tests;
