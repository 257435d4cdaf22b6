//! The [`Material`] trait: stress measures from the deformation gradient, and the small tensor
//! helpers the laws share.

use crate::ElasticConstants;
use glam::DMat3;
use sph_core::Dim;

/// A hyperelastic (or elastic) constitutive law: stress from the deformation gradient `F`.
///
/// Stress measures (TL paper eq. 3–4, 9): second Piola–Kirchhoff `S`, first Piola–Kirchhoff
/// `P = F S`, Kirchhoff `τ = F S Fᵀ = P Fᵀ`, Cauchy `σ = τ / J`, `J = det F`.
///
/// In 2D everything is **plane strain**: the out-of-plane stretch is 1 (`F_zz = 1`), `S`, `P`
/// and `τ` are the in-plane 2×2 blocks, and [`Material::cauchy_stress_3d`] adds the
/// out-of-plane `σ_zz` the law gives. Each law's doc says whether a dimension-dependent formula
/// uses `d = D::D` or the 3×3 embedding.
///
/// All methods are allocation-free and called per particle per step. They never panic: for a
/// law that needs `F⁻¹`, `C⁻¹` or `ln J`, a singular `F` (or `det F ≤ 0` where `ln J` enters)
/// yields non-finite entries, so the solver's non-finite check reports it; Saint
/// Venant–Kirchhoff is a polynomial in `F` and stays finite.
pub trait Material<D: Dim>: Send + Sync {
    /// Short name of the law (the name [`crate::MaterialKind`] parses).
    fn name(&self) -> &'static str;

    /// The elastic constants the law was built from (for a law with its own parameters, the
    /// small-strain equivalents).
    fn constants(&self) -> &ElasticConstants;

    /// Second Piola–Kirchhoff stress `S(F)` (symmetric; TL paper eq. 4).
    fn second_piola_kirchhoff(&self, f: D::Matrix) -> D::Matrix;

    /// First Piola–Kirchhoff stress `P = F S` (TL paper eq. 4).
    #[inline]
    fn first_piola_kirchhoff(&self, f: D::Matrix) -> D::Matrix {
        f * self.second_piola_kirchhoff(f)
    }

    /// Kirchhoff stress `τ = F S Fᵀ = J σ` (TL paper eq. 9 read backwards: `P = τ F⁻ᵀ`).
    #[inline]
    fn kirchhoff_stress(&self, f: D::Matrix) -> D::Matrix {
        f * self.second_piola_kirchhoff(f) * D::transpose(f)
    }

    /// Cauchy stress `σ = τ / J` as a 3×3 tensor. In 2D (plane strain, `F_zz = 1`) the in-plane
    /// block is `τ / J` and `σ_zz` is the out-of-plane stress the law gives; `σ_xz = σ_yz = 0`.
    /// Used for output (von Mises), not in the force loop.
    fn cauchy_stress_3d(&self, f: D::Matrix) -> DMat3;

    /// Strain energy density `ψ(F)` per unit reference volume, or `None` when the law has no
    /// energy. For every law here `P = ∂ψ/∂F`, i.e. `S = 2 ∂ψ/∂C`.
    fn strain_energy_density(&self, f: D::Matrix) -> Option<f64>;

    /// Volumetric Kirchhoff stress `(K/2)(J² − 1)` (TL paper eq. 11 and 13), the pressure-like
    /// part the TL-HF formulation (eq. 25–28) takes from the material.
    #[inline]
    fn volumetric_kirchhoff(&self, j: f64) -> f64 {
        0.5 * self.constants().bulk_modulus * (j * j - 1.0)
    }
}

/// `m⁻¹`, or a matrix of NaN when `m` is singular (so a degenerate `F` surfaces as a non-finite
/// stress instead of a panic).
#[inline]
pub(crate) fn inverse_or_nan<D: Dim>(m: D::Matrix) -> D::Matrix {
    match D::try_inverse(m) {
        Some(inv) => inv,
        None => D::identity() * f64::NAN,
    }
}

/// Green–Lagrange strain `E = ½(FᵀF − I)` (TL paper eq. 5).
#[inline]
pub(crate) fn green_lagrange<D: Dim>(f: D::Matrix) -> D::Matrix {
    (D::transpose(f) * f - D::identity()) * 0.5
}

/// `J^(−2/d)` with the common cases folded at compile time for `d = D::D`.
#[inline]
pub(crate) fn j_pow_minus_two_over(j: f64, d: usize) -> f64 {
    match d {
        2 => 1.0 / j,
        3 => {
            let c = j.cbrt();
            1.0 / (c * c)
        }
        _ => j.powf(-2.0 / d as f64),
    }
}

/// Cauchy stress from the 3×3 Kirchhoff stress and `J`.
#[inline]
pub(crate) fn cauchy_from_kirchhoff(tau3: DMat3, j: f64) -> DMat3 {
    tau3 * (1.0 / j)
}
