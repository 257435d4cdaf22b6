//! Saint Venant–Kirchhoff, the TL paper's "linear elastic" law (TL eq. 5, MPS eq. 11).

use crate::material::{cauchy_from_kirchhoff, green_lagrange};
use crate::{ElasticConstants, Material};
use glam::DMat3;
use serde::{Deserialize, Serialize};
use sph_core::{Dim, D3};

/// Saint Venant–Kirchhoff: `S = λ tr(E) I + 2μ E`, `E = ½(FᵀF − I)` (TL paper eq. 5, which writes
/// it as `K tr(E) I + 2G(E − ⅓ tr(E) I)`), with energy `ψ = (λ/2)(tr E)² + μ E:E` (MPS paper
/// eq. 11).
///
/// This is also the TL paper's "linear elastic" model: eq. 5 is the only linear-elastic law it
/// gives, so `linear-elastic` and `saint-venant-kirchhoff` name the same law ([`LinearElastic`]).
///
/// 2D plane strain: `E_zz = 0`, so the 2×2 formula is exactly the in-plane block of the 3×3 one
/// (no `d` enters), and `S_zz = λ tr(E)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SaintVenantKirchhoff {
    /// Elastic constants (`λ` = `lame_lambda`, `μ` = `shear_modulus`).
    pub constants: ElasticConstants,
}

/// The TL paper's linear elastic law (eq. 5) is Saint Venant–Kirchhoff.
pub type LinearElastic = SaintVenantKirchhoff;

impl SaintVenantKirchhoff {
    /// The law with the given (already validated) constants. Infallible: any
    /// [`ElasticConstants`] is admissible.
    pub fn new(constants: ElasticConstants) -> Self {
        Self { constants }
    }

    /// `S = λ tr(E) I + 2μ E` (TL eq. 5) in any dimension.
    #[inline]
    fn pk2<E: Dim>(&self, f: E::Matrix) -> E::Matrix {
        let e = green_lagrange::<E>(f);
        E::identity() * (self.constants.lame_lambda * E::trace(e))
            + e * (2.0 * self.constants.shear_modulus)
    }
}

impl<D: Dim> Material<D> for SaintVenantKirchhoff {
    #[inline]
    fn name(&self) -> &'static str {
        "saint-venant-kirchhoff"
    }

    #[inline]
    fn constants(&self) -> &ElasticConstants {
        &self.constants
    }

    /// `S = λ tr(E) I + 2μ E` (TL eq. 5).
    #[inline]
    fn second_piola_kirchhoff(&self, f: D::Matrix) -> D::Matrix {
        self.pk2::<D>(f)
    }

    /// `σ = F S Fᵀ / J` of the 3×3 embedding (`F_zz = 1` in 2D, giving `S_zz = λ tr E`).
    fn cauchy_stress_3d(&self, f: D::Matrix) -> DMat3 {
        let f3 = D::to_mat3(f, 1.0);
        let tau = f3 * self.pk2::<D3>(f3) * f3.transpose();
        cauchy_from_kirchhoff(tau, f3.determinant())
    }

    /// `ψ = (λ/2)(tr E)² + μ E:E` (MPS eq. 11).
    #[inline]
    fn strain_energy_density(&self, f: D::Matrix) -> Option<f64> {
        let e = green_lagrange::<D>(f);
        let tr = D::trace(e);
        Some(
            0.5 * self.constants.lame_lambda * tr * tr
                + self.constants.shear_modulus * D::ddot(e, e),
        )
    }
}
