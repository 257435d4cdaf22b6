//! Compressible Mooney–Rivlin-like law of the MPS paper (eq. 12).

use crate::constants::{check_density, check_modulus};
use crate::material::{cauchy_from_kirchhoff, inverse_or_nan};
use crate::{ElasticConstants, Material};
use glam::DMat3;
use serde::{Deserialize, Serialize};
use sph_core::{Dim, Error, D3};

/// Compressible Mooney–Rivlin-like law, MPS paper eq. 12:
/// `ψ = ½c₁ I₁ + ½c₂ I₂ − (3/2)c₁ I₃^(1/3) − (3/2)c₂ I₃^(2/3) + (λ/4)(ln I₃)²`,
/// with `I₁, I₂, I₃` the invariants of `C = FᵀF`, and
/// `S = 2 ∂ψ/∂C = c₁ I + c₂ (I₁ I − C) − [c₁ I₃^(1/3) + 2c₂ I₃^(2/3) − λ ln I₃] C⁻¹`.
///
/// `ψ` and `S` vanish at `C = I`. Small-strain limit: shear modulus `c₁ + c₂`, bulk modulus `2λ`
/// (this `λ` is not Lamé's). The MPS paper's rubber-ring constants are
/// [`Self::MPS_PAPER_C1`], [`Self::MPS_PAPER_C2`], [`Self::MPS_PAPER_LAMBDA`].
///
/// 2D plane strain: the invariants are those of the 3×3 embedding with `C_zz = 1`
/// (`I₁ = tr C + 1`, `I₂ = ½(I₁² − C:C − 1)`, `I₃ = det C`); the 2×2 `S` is the in-plane block of
/// the 3×3 one, so `S = 2 ∂ψ/∂C` holds for the 2×2 `C`, and
/// `S_zz = c₁ + c₂ (I₁ − 1) − c₁ I₃^(1/3) − 2c₂ I₃^(2/3) + λ ln I₃`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "MooneyRivlinRepr", into = "MooneyRivlinRepr")]
pub struct MooneyRivlinLike {
    c1: f64,
    c2: f64,
    lambda: f64,
    /// Small-strain equivalents: `G = c₁ + c₂`, `K = 2λ`.
    constants: ElasticConstants,
}

/// Serialised form: the law's own parameters and the density.
#[derive(Clone, Copy, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct MooneyRivlinRepr {
    c1: f64,
    c2: f64,
    lambda: f64,
    density: f64,
}

impl TryFrom<MooneyRivlinRepr> for MooneyRivlinLike {
    type Error = Error;
    fn try_from(r: MooneyRivlinRepr) -> Result<Self, Error> {
        Self::new(r.c1, r.c2, r.lambda, r.density)
    }
}

impl From<MooneyRivlinLike> for MooneyRivlinRepr {
    fn from(m: MooneyRivlinLike) -> Self {
        Self {
            c1: m.c1,
            c2: m.c2,
            lambda: m.lambda,
            density: m.constants.density,
        }
    }
}

impl MooneyRivlinLike {
    /// MPS paper (§ material instability of rings, after its ref. \[7\]): `c₁ = 1.265e5 Pa`.
    pub const MPS_PAPER_C1: f64 = 1.265e5;
    /// MPS paper: `c₂ = 1.012e4 Pa`.
    pub const MPS_PAPER_C2: f64 = 1.012e4;
    /// MPS paper: `λ = 1.012e7 Pa`.
    pub const MPS_PAPER_LAMBDA: f64 = 1.012e7;
    /// MPS paper: `ρs = 125.4 kg/m³`.
    pub const MPS_PAPER_DENSITY: f64 = 125.4;
    /// `c₂ / (c₁ + c₂)` of the MPS paper's constants (≈ 0.0741), the default split used when the
    /// law is built from [`ElasticConstants`].
    pub const MPS_PAPER_C2_FRACTION: f64 =
        Self::MPS_PAPER_C2 / (Self::MPS_PAPER_C1 + Self::MPS_PAPER_C2);

    /// The law from its own parameters (MPS eq. 12): `c₁`, `λ` and `c₂` (or `c₂ = 0`) within
    /// [`crate::constants::MODULUS_RANGE`], density within [`crate::constants::DENSITY_RANGE`]. Its [`ElasticConstants`] are the small-strain equivalents
    /// `G = c₁ + c₂`, `K = 2λ`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `c1`, `c2`, `lambda` or `density`.
    pub fn new(c1: f64, c2: f64, lambda: f64, density: f64) -> Result<Self, Error> {
        check_modulus("c1", c1)?;
        if c2 != 0.0 {
            check_modulus("c2", c2)?;
        }
        check_modulus("lambda", lambda)?;
        check_density(density)?;
        let constants = ElasticConstants::from_bulk_shear(2.0 * lambda, c1 + c2, density)?;
        Ok(Self {
            c1,
            c2,
            lambda,
            constants,
        })
    }

    /// The MPS paper's rubber (`c₁`, `c₂`, `λ`, `ρs` above).
    pub fn mps_paper() -> Self {
        Self::new(
            Self::MPS_PAPER_C1,
            Self::MPS_PAPER_C2,
            Self::MPS_PAPER_LAMBDA,
            Self::MPS_PAPER_DENSITY,
        )
        .expect("the paper's constants are valid")
    }

    /// The law matching `constants` at small strain: `c₁ + c₂ = G`, `c₂ = c2_fraction · G`,
    /// `λ = K/2`. `c2_fraction` in `[0, 1)`; [`Self::MPS_PAPER_C2_FRACTION`] reproduces the
    /// paper's ratio.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `c2_fraction`.
    pub fn from_constants(constants: ElasticConstants, c2_fraction: f64) -> Result<Self, Error> {
        if !(c2_fraction.is_finite() && (0.0..1.0).contains(&c2_fraction)) {
            return Err(Error::invalid(
                "c2_fraction",
                c2_fraction,
                "0 <= c2_fraction < 1",
            ));
        }
        let g = constants.shear_modulus;
        Ok(Self {
            c1: (1.0 - c2_fraction) * g,
            c2: c2_fraction * g,
            lambda: 0.5 * constants.bulk_modulus,
            constants,
        })
    }

    /// `c₁` (Pa).
    pub fn c1(&self) -> f64 {
        self.c1
    }
    /// `c₂` (Pa).
    pub fn c2(&self) -> f64 {
        self.c2
    }
    /// The law's `λ` (Pa; bulk modulus `2λ`, not Lamé's).
    pub fn lambda(&self) -> f64 {
        self.lambda
    }

    /// `(I₁, I₂, I₃)` of the 3×3 embedding of `C` (`C_zz = 1` in 2D), with `I₃ = J²`.
    #[inline]
    fn invariants<E: Dim>(c: E::Matrix, j: f64) -> (f64, f64, f64) {
        let extra = (3 - E::D) as f64;
        let i1 = E::trace(c) + extra;
        let i2 = 0.5 * (i1 * i1 - (E::ddot(c, c) + extra));
        (i1, i2, j * j)
    }

    /// `S` of MPS eq. 12 in any dimension.
    #[inline]
    fn pk2<E: Dim>(&self, f: E::Matrix) -> E::Matrix {
        let c = E::transpose(f) * f;
        let (i1, _, i3) = Self::invariants::<E>(c, E::det(f));
        let i3_13 = i3.cbrt();
        let coeff = self.c1 * i3_13 + 2.0 * self.c2 * i3_13 * i3_13 - self.lambda * i3.ln();
        E::identity() * (self.c1 + self.c2 * i1) - c * self.c2 - inverse_or_nan::<E>(c) * coeff
    }
}

impl<D: Dim> Material<D> for MooneyRivlinLike {
    #[inline]
    fn name(&self) -> &'static str {
        "mooney-rivlin"
    }

    #[inline]
    fn constants(&self) -> &ElasticConstants {
        &self.constants
    }

    /// `S = c₁ I + c₂ (I₁ I − C) − [c₁ I₃^(1/3) + 2c₂ I₃^(2/3) − λ ln I₃] C⁻¹` (from MPS eq. 12).
    #[inline]
    fn second_piola_kirchhoff(&self, f: D::Matrix) -> D::Matrix {
        self.pk2::<D>(f)
    }

    /// `σ = F S Fᵀ / J` of the 3×3 embedding (`F_zz = 1` in 2D).
    fn cauchy_stress_3d(&self, f: D::Matrix) -> DMat3 {
        let f3 = D::to_mat3(f, 1.0);
        let tau = f3 * self.pk2::<D3>(f3) * f3.transpose();
        cauchy_from_kirchhoff(tau, f3.determinant())
    }

    /// `ψ` of MPS eq. 12.
    #[inline]
    fn strain_energy_density(&self, f: D::Matrix) -> Option<f64> {
        let c = D::transpose(f) * f;
        let (i1, i2, i3) = Self::invariants::<D>(c, D::det(f));
        let i3_13 = i3.cbrt();
        let ln_i3 = i3.ln();
        Some(
            0.5 * self.c1 * i1 + 0.5 * self.c2 * i2
                - 1.5 * self.c1 * i3_13
                - 1.5 * self.c2 * i3_13 * i3_13
                + 0.25 * self.lambda * ln_i3 * ln_i3,
        )
    }
}
