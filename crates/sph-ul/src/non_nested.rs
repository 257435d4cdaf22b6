//! The essentially non-hourglass shear treatment, SPH-ENOG (UL paper §4, eq 15–20): the shear
//! acceleration is the time integral of `(G/ρ) ∇²v`, with the Laplacian in the angular-momentum
//! conservative form of eq 19 (or the non-conservative eq 18, to reproduce Fig. 7).

use crate::shear::ShearForce;
use serde::{Deserialize, Serialize};
use sph_core::Dim;
use sph_core::PairKernel;

/// Which discrete Laplacian of the velocity feeds the shear acceleration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum LaplacianForm {
    /// Eq. (19): `2ζ Σ_j (e_ij·v_ij)/r_ij ∇_i W_ij V_j`, central pair forces (conserves linear
    /// and angular momentum; zero for a rigid rotation).
    #[default]
    Conservative,
    /// Eq. (18): `2 Σ_j v_ij/r_ij W′_ij V_j` (no ζ, as printed). Not angular-momentum
    /// conservative: a rigid rotation produces shear forces that resist it (paper Fig. 7).
    NonConservative,
}

/// The calibrated `ζ = 0.7 d + 2.1` of §6 (3.5 in 2D, 4.2 in 3D) for the Wendland kernel with
/// `h = 1.3 dp`.
#[inline]
pub fn default_zeta(d: usize) -> f64 {
    0.7 * d as f64 + 2.1
}

/// Pair term of eq. (19) of the UL paper without the factor `2ζ`:
/// `(e_ij·v_ij)/r_ij W′ e_ij V_j`.
#[inline(always)]
pub fn conservative_laplacian_pair<D: Dim>(
    v_ij: D::Vector,
    e: D::Vector,
    r: f64,
    dw: f64,
    v_j: f64,
) -> D::Vector {
    e * (D::dot(e, v_ij) * dw * v_j / r)
}

/// Pair term of eq. (18) of the UL paper without the factor 2: `v_ij/r_ij W′ V_j`.
#[inline(always)]
pub fn non_conservative_laplacian_pair<D: Dim>(
    v_ij: D::Vector,
    r: f64,
    dw: f64,
    v_j: f64,
) -> D::Vector {
    v_ij * (dw * v_j / r)
}

/// Eq. (20) of the UL paper: the rate of the accumulated shear acceleration,
/// `d A_s,i/dt = 2 ζ (G/ρ_i) Σ_j (…)`, from the pair sum of [`conservative_laplacian_pair`]
/// (`factor = ζ`) or [`non_conservative_laplacian_pair`] (`factor = 1`).
#[inline(always)]
pub fn shear_acceleration_rate<D: Dim>(
    pair_sum: D::Vector,
    factor: f64,
    shear_modulus: f64,
    rho_i: f64,
) -> D::Vector {
    pair_sum * (2.0 * factor * shear_modulus / rho_i)
}

/// ENOG's shear term of the force gather: the accumulated `A_s` of the previous step (eq 20).
pub(crate) struct AccumulatedShear<'a, D: Dim> {
    pub a_s: &'a [D::Vector],
}

impl<D: Dim> ShearForce<D> for AccumulatedShear<'_, D> {
    #[inline(always)]
    fn pair(
        &self,
        _i: usize,
        _j: usize,
        _pk: &PairKernel<D>,
        _vj_rho_i: f64,
    ) -> (D::Vector, D::Vector) {
        (D::zero(), D::zero())
    }
    #[inline(always)]
    fn particle(&self, i: usize) -> D::Vector {
        self.a_s[i]
    }
}
