//! Volumetric–deviatoric Kirchhoff-stress law of the TL-HF paper (eq. 10–14).

use crate::material::{
    cauchy_from_kirchhoff, hf_split_generic, inverse_or_nan, j_pow_minus_two_over,
};
use crate::{ElasticConstants, Material};
use glam::DMat3;
use serde::{Deserialize, Serialize};
use sph_core::Dim;

/// Which dimension `d` the isochoric split `b̄ = J^(−2/d) b`, `dev(·) = · − (1/d) tr(·) I` uses.
/// Matters only in 2D; in 3D both are `d = 3`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DeviatorDimension {
    /// `d = D::D` (`d = 2` in 2D), as the TL paper writes eq. 12–14 and SPHinXsys implements
    /// them; docs/methods.md's default. In 2D this is a genuinely two-dimensional material: its
    /// small-strain limit is `σ = (K − G) tr(ε) I + 2G ε` in-plane, not plane-strain Hooke
    /// (`λ = K − 2G/3`), i.e. the in-plane response of a plane-strain solid whose Poisson's
    /// ratio is slightly different from the one given.
    #[default]
    Spatial,
    /// `d = 3` on the 3×3 embedding with `F_zz = 1` (`tr b → tr b + 1`, `J^(−2/3)`): true plane
    /// strain, whose small-strain limit is plane-strain Hooke with the given `E` and `ν`.
    #[serde(rename = "embedded-3d")]
    Embedded3d,
}

/// Volumetric–deviatoric law of TL paper eq. 10–14, given directly as a Kirchhoff stress:
/// `τ = (K/2)(J² − 1) I + G dev(b̄)`, `b̄ = J^(−2/d) b`, `b = F Fᵀ`,
/// `dev(b̄) = J^(−2/d) [b − (1/d) tr(b) I]` (eq. 13–14), from the energy
/// `ψ = (K/2)[½(J² − 1) − ln J] + (G/2)(tr b̄ − d)` (eq. 10–12), so that `τ = (∂ψ/∂F) Fᵀ`.
/// Then `P = τ F⁻ᵀ` (eq. 9) and `S = F⁻¹ τ F⁻ᵀ`.
///
/// `d` is chosen by [`DeviatorDimension`] (default `d = D::D`, as the paper). The energy uses the
/// same `d` as the stress, so `S = 2 ∂ψ/∂C` holds in both modes. Out-of-plane stress in 2D
/// ([`Material::cauchy_stress_3d`]): with `d = 2` the deviator lies in the plane, so
/// `τ_zz = (K/2)(J² − 1)` (the volumetric part only); with the 3×3 embedding,
/// `τ_zz = (K/2)(J² − 1) + G J^(−2/3)(1 − (tr b + 1)/3)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct KirchhoffVolDev {
    /// Elastic constants (`K` = `bulk_modulus`, `G` = `shear_modulus`).
    pub constants: ElasticConstants,
    /// The dimension `d` of the isochoric split (default: `d = D::D`, the paper's).
    #[serde(default)]
    pub deviator: DeviatorDimension,
}

impl KirchhoffVolDev {
    /// The law with the paper's `d = D::D` split. Infallible: any [`ElasticConstants`] is
    /// admissible.
    pub fn new(constants: ElasticConstants) -> Self {
        Self::with_deviator(constants, DeviatorDimension::Spatial)
    }

    /// The law with the given choice of `d` for the isochoric split.
    pub fn with_deviator(constants: ElasticConstants, deviator: DeviatorDimension) -> Self {
        Self {
            constants,
            deviator,
        }
    }

    /// `(d, number of unit out-of-plane stretches)` for dimension `D`.
    #[inline]
    fn split_dim<D: Dim>(&self) -> (usize, f64) {
        match self.deviator {
            DeviatorDimension::Spatial => (D::D, 0.0),
            DeviatorDimension::Embedded3d => (3, (3 - D::D) as f64),
        }
    }

    /// In-plane `τ` (TL eq. 13–14) and `τ_zz` (see the type's doc), with `J`.
    #[inline]
    fn tau_parts<D: Dim>(&self, f: D::Matrix) -> (D::Matrix, f64, f64) {
        let (d, extra) = self.split_dim::<D>();
        let j = D::det(f);
        let b = f * D::transpose(f);
        let tr_b = D::trace(b) + extra;
        let jd = j_pow_minus_two_over(j, d);
        let vol = self.volumetric(j);
        let g = self.constants.shear_modulus;
        let mean = tr_b / d as f64;
        let tau = D::identity() * (vol - g * jd * mean) + b * (g * jd);
        let tau_zz = if extra > 0.0 {
            vol + g * jd * (1.0 - mean)
        } else {
            vol
        };
        (tau, tau_zz, j)
    }

    /// `(K/2)(J² − 1)` (TL eq. 13, from eq. 11).
    #[inline]
    fn volumetric(&self, j: f64) -> f64 {
        0.5 * self.constants.bulk_modulus * (j * j - 1.0)
    }
}

impl<D: Dim> Material<D> for KirchhoffVolDev {
    #[inline]
    fn name(&self) -> &'static str {
        "kirchhoff-vol-dev"
    }

    #[inline]
    fn constants(&self) -> &ElasticConstants {
        &self.constants
    }

    /// `S = F⁻¹ τ F⁻ᵀ` with `τ` of TL eq. 13.
    #[inline]
    fn second_piola_kirchhoff(&self, f: D::Matrix) -> D::Matrix {
        let f_inv = inverse_or_nan::<D>(f);
        f_inv * <Self as Material<D>>::kirchhoff_stress(self, f) * D::transpose(f_inv)
    }

    /// `P = τ F⁻ᵀ` (TL eq. 9) with `τ` of eq. 13.
    #[inline]
    fn first_piola_kirchhoff(&self, f: D::Matrix) -> D::Matrix {
        let f_inv = inverse_or_nan::<D>(f);
        <Self as Material<D>>::kirchhoff_stress(self, f) * D::transpose(f_inv)
    }

    /// `τ = (K/2)(J² − 1) I + G dev(b̄)` (TL eq. 13–14).
    #[inline]
    fn kirchhoff_stress(&self, f: D::Matrix) -> D::Matrix {
        self.tau_parts::<D>(f).0
    }

    /// `σ = τ / J` with `τ_zz` as in the type's doc in 2D.
    fn cauchy_stress_3d(&self, f: D::Matrix) -> DMat3 {
        let (tau, tau_zz, j) = self.tau_parts::<D>(f);
        cauchy_from_kirchhoff(D::to_mat3(tau, tau_zz), j)
    }

    /// `ψ = (K/2)[½(J² − 1) − ln J] + (G/2)(tr b̄ − d)` (TL eq. 10–12).
    #[inline]
    fn strain_energy_density(&self, f: D::Matrix) -> Option<f64> {
        let (d, extra) = self.split_dim::<D>();
        let j = D::det(f);
        let tr_b = D::ddot(f, f) + extra;
        let w_v = 0.5 * self.constants.bulk_modulus * (0.5 * (j * j - 1.0) - j.ln());
        let w_s =
            0.5 * self.constants.shear_modulus * (j_pow_minus_two_over(j, d) * tr_b - d as f64);
        Some(w_v + w_s)
    }

    /// TL eq. 28 exactly: `τ_r = [(K/2)(J² − 1) − (ζ/d) G J^(−2/d) tr(b)] I`, `g = J^(−2/d)`,
    /// with the law's `d` (the generic split of [`Material::hf_split`] for `d = 3` embedded).
    #[inline]
    fn hf_split(&self, f: D::Matrix, zeta: f64) -> (D::Matrix, f64) {
        let (d, extra) = self.split_dim::<D>();
        if extra > 0.0 {
            // d = 3 on the embedding: not the in-plane deviator the Laplacian carries.
            return hf_split_generic::<D, Self>(self, f, zeta);
        }
        let j = D::det(f);
        let g = j_pow_minus_two_over(j, d);
        let tr_b = D::ddot(f, f);
        let iso = self.volumetric(j) - zeta / d as f64 * self.constants.shear_modulus * g * tr_b;
        (D::identity() * iso, g)
    }
}
