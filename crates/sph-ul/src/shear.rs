//! The shear treatment of a UL body ([`Shear`], chosen when the body is built) and the trait
//! through which each variant adds its shear term to the force gather (`ShearForce`,
//! implemented next to each variant's pair terms: [`crate::nested`],
//! [`crate::artificial_stress`], [`crate::non_nested`]).

use crate::artificial_stress;
use crate::non_nested::LaplacianForm;
use serde::{Deserialize, Serialize};
use sph_core::error::{check_non_negative, check_positive};
use sph_core::{Dim, Error, PairKernel};

/// The shear treatment, fixed when the body is built (hoisted out of the inner loops).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Shear {
    /// SPH-OG: nested shear stress (eq 6–8, 13–14).
    Original,
    /// SPH-OAS: OG plus the Gray–Monaghan–Swift artificial stress.
    ArtificialStress {
        /// Strength `ε` (0.3).
        epsilon: f64,
        /// Exponent `n` of `f_ij^n` (4).
        n: u32,
    },
    /// SPH-ENOG: shear acceleration from the Laplacian of velocity (eq 19–20).
    NonNested {
        /// `ζ` of eq 19–20; `None` = the paper's `0.7 d + 2.1`.
        zeta: Option<f64>,
        /// Eq 19 (default) or the non-conservative eq 18.
        form: LaplacianForm,
    },
    /// SPH-GNOG: OG's nested shear stress plus the accumulated penalty on the pair velocity the
    /// velocity gradients do not predict (arXiv 2409.11474; [`crate::generalized`]).
    Generalized {
        /// Penalty factor ξ; `None` = the authors' 2 ([`crate::generalized::DEFAULT_XI`]).
        xi: Option<f64>,
    },
}

impl Shear {
    /// OAS with `ε = 0.3`, `n = 4`.
    pub fn artificial_stress() -> Self {
        Shear::ArtificialStress {
            epsilon: artificial_stress::DEFAULT_EPSILON,
            n: artificial_stress::DEFAULT_EXPONENT,
        }
    }

    /// ENOG with the paper's `ζ = 0.7 d + 2.1` and the conservative eq 19.
    pub fn non_nested() -> Self {
        Shear::NonNested {
            zeta: None,
            form: LaplacianForm::Conservative,
        }
    }

    /// GNOG with the authors' `ξ = 2`.
    pub fn generalized() -> Self {
        Shear::Generalized { xi: None }
    }

    /// The method name as the command line spells it.
    pub fn method_name(&self) -> &'static str {
        match self {
            Shear::Original => "ul-og",
            Shear::ArtificialStress { .. } => "ul-oas",
            Shear::NonNested { .. } => "ul-enog",
            Shear::Generalized { .. } => "ul-gnog",
        }
    }

    pub(crate) fn validate(&self) -> Result<(), Error> {
        match *self {
            Shear::Original => Ok(()),
            Shear::ArtificialStress { epsilon, n } => {
                check_non_negative("epsilon", epsilon)?;
                if n == 0 || n > 16 {
                    return Err(Error::invalid("n", n, "1..=16"));
                }
                Ok(())
            }
            Shear::NonNested { zeta, .. } => match zeta {
                Some(z) => check_positive("zeta", z),
                None => Ok(()),
            },
            Shear::Generalized { xi } => match xi {
                Some(x) => check_positive("xi", x),
                None => Ok(()),
            },
        }
    }
}

/// The per-variant shear term of the force gather (monomorphised: no branch in the loop).
pub(crate) trait ShearForce<D: Dim>: Sync {
    /// Pair contribution to `a_i`: the shear-stress part and the artificial-stress part (zero
    /// but for OAS), kept apart for the energy budget.
    fn pair(&self, i: usize, j: usize, pk: &PairKernel<D>, vj_rho_i: f64)
        -> (D::Vector, D::Vector);
    /// Per-particle contribution to `a_i`.
    fn particle(&self, i: usize) -> D::Vector;
}
