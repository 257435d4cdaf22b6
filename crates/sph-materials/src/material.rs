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

    /// The TL-HF split of this law (TL paper eq. 25–28, generalised to any law): returns
    /// `(τ_r, g)` where `τ_s = G g(J) b` is the shear Kirchhoff stress whose divergence TL-HF
    /// takes as the Laplacian of position (eq. 26–27, with `g` in the place of `J^(−2/d)`) and
    ///
    /// `τ_r = τ(F) − G g [b − (tr b/d) I] − (ζ/d) G g tr(b) I`
    ///
    /// is the remaining Kirchhoff stress (eq. 28), whose divergence is taken without the
    /// correction matrix. The law's whole stress is represented: `τ_r + G g b = τ(F) +
    /// (1 − ζ)(G g/d) tr(b) I`, the last term being the paper's ζ-consistent isotropic part
    /// that makes the two sums cancel in the undeformed state (`τ_r = −ζ G I` there).
    /// `d = D::D` (`d = 2` in plane strain, as the paper).
    ///
    /// Default: `g = J^(−2/d)` (the paper's), `τ_r` by the formula, a full tensor. The paper's own
    /// law ([`crate::KirchhoffVolDev`]) gives eq. 28 exactly (isotropic `τ_r`); neo-Hookean
    /// takes `g = 1`, which makes its `τ_r` isotropic too.
    #[inline]
    fn hf_split(&self, f: D::Matrix, zeta: f64) -> (D::Matrix, f64) {
        hf_split_generic::<D, Self>(self, f, zeta)
    }
}

/// The generic TL-HF split of [`Material::hf_split`] with `g = J^(−2/d)`:
/// `τ_r = τ(F) − G g b + (1 − ζ)(G g tr b/d) I`.
#[inline]
pub fn hf_split_generic<D: Dim, M: Material<D> + ?Sized>(
    law: &M,
    f: D::Matrix,
    zeta: f64,
) -> (D::Matrix, f64) {
    let g = j_pow_minus_two_over(D::det(f), D::D);
    let gs = law.constants().shear_modulus * g;
    let b = f * D::transpose(f);
    let tr_b = D::trace(b);
    let tau =
        law.kirchhoff_stress(f) - b * gs + D::identity() * ((1.0 - zeta) * gs * tr_b / D::D as f64);
    (tau, g)
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
