//! Compressible neo-Hookean law of the TL paper (eq. 7–8).

use crate::material::{cauchy_from_kirchhoff, inverse_or_nan};
use crate::{ElasticConstants, Material};
use glam::DMat3;
use serde::{Deserialize, Serialize};
use sph_core::{Dim, D3};

/// Neo-Hookean, exactly as TL paper eq. 7–8:
/// `ψ = μ tr(E) − μ ln J + (λ/2)(ln J)²`, `S = ∂ψ/∂E = μ I + (λ ln J − μ) C⁻¹`, `C = FᵀF`,
/// `J = det F`. (`μ tr E = (μ/2)(I₁ − 3)`: the usual compressible neo-Hookean.)
///
/// 2D plane strain: with `F_zz = 1`, `tr E` and `J` of the 3×3 embedding equal those of the 2×2
/// block, so the 2×2 formula is the in-plane block of the 3×3 one (no `d` enters), and
/// `S_zz = λ ln J`. Undefined (NaN) for `J ≤ 0`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct NeoHookean {
    /// Elastic constants (`λ` = `lame_lambda`, `μ` = `shear_modulus`).
    pub constants: ElasticConstants,
}

impl NeoHookean {
    /// The law with the given (already validated) constants. Infallible: any
    /// [`ElasticConstants`] is admissible.
    pub fn new(constants: ElasticConstants) -> Self {
        Self { constants }
    }

    /// `S = μ I + (λ ln J − μ) C⁻¹` (TL eq. 8) in any dimension.
    #[inline]
    fn pk2<E: Dim>(&self, f: E::Matrix) -> E::Matrix {
        let mu = self.constants.shear_modulus;
        let c_inv = inverse_or_nan::<E>(E::transpose(f) * f);
        let ln_j = E::det(f).ln();
        E::identity() * mu + c_inv * (self.constants.lame_lambda * ln_j - mu)
    }
}

impl<D: Dim> Material<D> for NeoHookean {
    #[inline]
    fn name(&self) -> &'static str {
        "neo-hookean"
    }

    #[inline]
    fn constants(&self) -> &ElasticConstants {
        &self.constants
    }

    /// `S = μ I + (λ ln J − μ) C⁻¹` (TL eq. 8).
    #[inline]
    fn second_piola_kirchhoff(&self, f: D::Matrix) -> D::Matrix {
        self.pk2::<D>(f)
    }

    /// `σ = F S Fᵀ / J` of the 3×3 embedding (`F_zz = 1` in 2D, giving `S_zz = λ ln J`).
    fn cauchy_stress_3d(&self, f: D::Matrix) -> DMat3 {
        let f3 = D::to_mat3(f, 1.0);
        let tau = f3 * self.pk2::<D3>(f3) * f3.transpose();
        cauchy_from_kirchhoff(tau, f3.determinant())
    }

    /// TL-HF split with `g = 1`: the law's deviatoric Kirchhoff stress is `μ dev(b)` exactly
    /// (`τ = μ(b − I) + λ ln J I`), so the Laplacian carries `τ_s = μ b` and the remainder is
    /// isotropic: `τ_r = [λ ln J − μ + (1 − ζ)(μ/d) tr b] I` (`= −ζ μ I` at rest, as eq. 28).
    #[inline]
    fn hf_split(&self, f: D::Matrix, zeta: f64) -> (D::Matrix, f64) {
        let mu = self.constants.shear_modulus;
        let tr_b = D::ddot(f, f);
        let iso = self.constants.lame_lambda * D::det(f).ln() - mu
            + (1.0 - zeta) * mu * tr_b / D::D as f64;
        (D::identity() * iso, 1.0)
    }

    /// `ψ = μ tr(E) − μ ln J + (λ/2)(ln J)²` (TL eq. 7).
    #[inline]
    fn strain_energy_density(&self, f: D::Matrix) -> Option<f64> {
        let mu = self.constants.shear_modulus;
        let tr_e = 0.5 * (D::ddot(f, f) - D::D as f64);
        let ln_j = D::det(f).ln();
        Some(mu * tr_e - mu * ln_j + 0.5 * self.constants.lame_lambda * ln_j * ln_j)
    }
}
