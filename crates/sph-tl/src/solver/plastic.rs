//! Plastic TL bodies: J2 or Johnson–Cook plasticity at finite strain, `F = Fe Fp` with a Hencky
//! elastic law and the exponential-map return ([`sph_materials::plasticity::finite_strain`]).
//!
//! Each step evaluates the stress once, at the half step `F^{n+1/2}` of eq 30: the return maps
//! the trial `be* = F Cp⁻¹ Fᵀ` (with the history of the previous evaluation) to the yield surface,
//! over the step's `Δt` (the plastic strain rate of Johnson–Cook is `Δε̄p/Δt`), and the history
//! (`Cp⁻¹`, `ε̄p`, temperature rise, dissipated work) is stepped. The stress divergence of
//! eq 20 then takes `P = τ F⁻ᵀ` plus the Kelvin–Voigt damping of eq 23–24, exactly as for an
//! elastic law. The elastic part of a plastic body is the Hencky law with the material's `K`
//! and `G` (the law for which the exponential-map return is exact), whatever elastic law the
//! solver was built with; in 2D (plane strain) `F` is embedded with `F_zz = 1` and the
//! out-of-plane elastic and plastic stretches evolve in the 3×3 history.
//!
//! Which variants carry it:
//! - `tl` ([`Shear::Original`]) and `tl-gm` ([`Shear::Ganzenmuller`]): the full stress `P` goes
//!   through eq 20; GM's hourglass penalty (on the difference between the pair displacement
//!   predicted by `F` and the actual one) is added unchanged: it vanishes for a linear
//!   displacement field and so does not compete with the plastic stress.
//! - `tl-hf` ([`Shear::HourglassFree`]) refuses a plastic law: it replaces the divergence of the
//!   shear stress `G g b` by a Laplacian of position (eq 26–27), i.e. it hard-wires an elastic
//!   deviator; a plastic deviator is not of that form, and the remainder `τ_r = τ − G g b`
//!   taken without the correction matrix would carry the whole plastic correction through the
//!   uncorrected divergence that HF avoids. This is UL-ENOG's reason for refusing one too.

use super::{Shear, TlSolver};
use crate::damping::damping_kirchhoff;
use glam::DMat3;
use serde::{Deserialize, Serialize};
use sph_core::distributed::OverRanks;
use sph_core::{Dim, Error};
use sph_materials::plasticity::{FinitePlasticState, HenckyPlasticity, HenckyReturn, PlasticLaw};
use sph_materials::Material;

/// The history a plastic TL particle carries: the material's state and the energy its returns
/// have dissipated (J).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PlasticParticle {
    /// `Cp⁻¹`, equivalent plastic strain and temperature rise.
    pub history: FinitePlasticState,
    /// Plastic dissipation of this particle since `t = 0`, `Σ V⁰ τ:Δεp` (J).
    pub dissipated: f64,
}

/// `F` of dimension `D` as the 3×3 tensor of the return (plane strain: `F_zz = 1`).
#[inline(always)]
fn to_3d<D: Dim>(f: D::Matrix) -> DMat3 {
    D::to_mat3(f, 1.0)
}

/// The in-plane block of a 3×3 tensor (the whole of it in 3D).
#[inline(always)]
fn from_3d<D: Dim>(m: DMat3) -> D::Matrix {
    D::matrix_from_fn(|r, c| m.col(c)[r])
}

/// The return at `f` and the first Piola stress with damping, premultiplied for eq 20:
/// `(τ F⁻ᵀ + τ_d F⁻ᵀ) Bᵀ` (the plastic counterpart of [`crate::original::corrected_piola`]).
#[inline(always)]
pub(crate) fn plastic_corrected_piola<D: Dim>(
    plasticity: &HenckyPlasticity,
    gamma: f64,
    f: D::Matrix,
    f_dot: D::Matrix,
    b: D::Matrix,
    history: &FinitePlasticState,
    dt: f64,
) -> (D::Matrix, HenckyReturn) {
    let r = plasticity.return_mapping(to_3d::<D>(f), history, dt);
    let mut tau = from_3d::<D>(r.kirchhoff);
    if gamma > 0.0 {
        tau += damping_kirchhoff::<D>(gamma, f, f_dot);
    }
    let f_inv_t = D::transpose(D::try_inverse(f).unwrap_or_else(crate::original::nan_matrix::<D>));
    (tau * f_inv_t * D::transpose(b), r)
}

impl<D: Dim, M: Material<D>> TlSolver<D, M> {
    /// Makes the body elastic–plastic with `law` (J2 or Johnson–Cook) on a Hencky elastic law
    /// with the material's `K` and `G` (see [`crate::solver::plastic`]): the history is stepped
    /// with every stress evaluation. Adds the output field `plastic_strain` (and `temperature`
    /// for Johnson–Cook with thermal softening), the figure `plastic_work`, the plastic history
    /// to checkpoints, and makes [`TlSolver::energy`]'s strain energy the Hencky energy of the
    /// elastic part.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for `tl-hf` (its Laplacian shear force hard-wires an elastic
    /// deviator: use `tl` or `tl-gm`), for a solver that has already stepped, or a law constant
    /// out of range.
    pub fn with_plasticity(mut self, law: PlasticLaw) -> Result<Self, Error> {
        if matches!(self.shear, Shear::HourglassFree { .. }) {
            return Err(Error::invalid(
                "material.law",
                law.name(),
                "an elastic law for tl-hf (its Laplacian shear force hard-wires an elastic \
                 deviator, which a yield surface cannot cap; use tl or tl-gm)",
            ));
        }
        if self.steps > 0 {
            return Err(Error::invalid(
                "plasticity",
                format!("added after {} steps", self.steps),
                "a solver that has not stepped",
            ));
        }
        self.plasticity = Some(HenckyPlasticity::new(law, self.material.constants())?);
        self.plastic = vec![PlasticParticle::default(); self.positions.len()];
        Ok(self)
    }

    /// The plastic law with its Hencky constants (`None`: elastic).
    pub fn plasticity(&self) -> Option<&HenckyPlasticity> {
        self.plasticity.as_ref()
    }

    /// The per-particle plastic history (empty for an elastic body).
    pub fn plastic_history(&self) -> &[PlasticParticle] {
        &self.plastic
    }

    /// Equivalent plastic strain per particle (empty for an elastic body).
    pub fn plastic_strain(&self) -> Vec<f64> {
        self.plastic
            .iter()
            .map(|p| p.history.state.equivalent_plastic_strain)
            .collect()
    }

    /// Whether the law has a temperature (Johnson–Cook with thermal softening): then the output
    /// field `temperature` is offered.
    pub fn thermal(&self) -> bool {
        matches!(
            self.plasticity.as_ref().map(|p| &p.plasticity.law),
            Some(PlasticLaw::JohnsonCook(jc)) if jc.thermal.is_some()
        )
    }

    /// Temperature per particle (K): the initial temperature plus the adiabatic rise of its
    /// plastic work. Empty unless [`TlSolver::thermal`].
    pub fn temperatures(&self) -> Vec<f64> {
        match self.plasticity.as_ref().map(|p| &p.plasticity.law) {
            Some(PlasticLaw::JohnsonCook(jc)) if jc.thermal.is_some() => self
                .plastic
                .iter()
                .map(|p| jc.temperature(p.history.state.temperature_rise))
                .collect(),
            _ => Vec::new(),
        }
    }

    /// Plastic dissipation since `t = 0` summed over the (owned) particles in index order (J;
    /// 0 for an elastic body).
    pub fn plastic_work(&self) -> f64 {
        let local = self
            .plastic
            .iter()
            .enumerate()
            .filter(|(i, _)| self.domain.counts(*i))
            .map(|(_, p)| p.dissipated)
            .sum::<f64>();
        self.domain.sum_over_ranks(&[local])[0]
    }

    /// The Kirchhoff stress of particle `i` at its current `F` returned with its history,
    /// without stepping it (rate-independent: for output), as a 3×3 Cauchy stress.
    pub(super) fn plastic_cauchy_3d(&self, plasticity: &HenckyPlasticity, i: usize) -> DMat3 {
        let f = to_3d::<D>(self.deformation[i]);
        let r = plasticity.return_mapping(f, &self.plastic[i].history, f64::INFINITY);
        r.kirchhoff * (1.0 / f.determinant())
    }

    /// Hencky strain energy `V⁰ ψ(Fe)` of particle `i`.
    pub(super) fn plastic_strain_energy(&self, plasticity: &HenckyPlasticity, i: usize) -> f64 {
        self.volumes[i]
            * plasticity
                .strain_energy_density(to_3d::<D>(self.deformation[i]), &self.plastic[i].history)
    }
}
