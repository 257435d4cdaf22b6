//! Rate-independent isotropic hardening of J2 plasticity: the flow stress `σ_y(ε̄p)` and its
//! slope `H = dσ_y/dε̄p`.

use serde::{Deserialize, Serialize};
use sph_core::error::{check_non_negative, check_positive};
use sph_core::Error;

/// Isotropic hardening: the uniaxial flow stress as a function of the equivalent plastic strain
/// `ε̄p` (Simo & Hughes 1998, *Computational Inelasticity*, Box 3.1, where the hardening function
/// `K(α)` is `σ_y(ε̄p)` with `α = ε̄p`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "hardening", rename_all = "kebab-case", deny_unknown_fields)]
pub enum IsotropicHardening {
    /// `σ_y = σ_0 + H ε̄p` (Simo & Hughes 1998, Box 3.1 with `K(α) = σ_Y + K̄ α`); the
    /// consistency equation of the radial return is then linear and solved exactly (Box 3.2).
    Linear {
        /// Initial yield stress `σ_0` (Pa), > 0.
        yield_stress: f64,
        /// Hardening modulus `H` (Pa), ≥ 0 (0: perfectly plastic).
        hardening_modulus: f64,
    },
    /// Saturation (Voce) hardening with a linear term,
    /// `σ_y = σ_0 + H ε̄p + (σ_∞ − σ_0)(1 − exp(−δ ε̄p))`: Voce (1948) plus a linear term, the
    /// law of the necking-bar benchmark of Simo (1988) and Simo & Hughes (1998, ch. 9),
    /// `K(α) = σ_0 + H̄ α + (K_∞ − σ_0)(1 − exp(−δ α))`. The consistency equation is solved by
    /// Newton (Box 3.2, step 4).
    Saturation {
        /// Initial yield stress `σ_0` (Pa), > 0.
        yield_stress: f64,
        /// Linear hardening modulus `H` (Pa), ≥ 0.
        hardening_modulus: f64,
        /// Saturation stress `σ_∞` (Pa), ≥ `σ_0`.
        saturation_stress: f64,
        /// Saturation exponent `δ`, > 0.
        saturation_exponent: f64,
    },
}

impl IsotropicHardening {
    /// `Ok` if every constant is in its range (named as the scene keys name them).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first constant out of range. Softening (`H < 0`,
    /// `σ_∞ < σ_0`) is refused: the radial return's consistency equation then has no unique
    /// root and the continuum problem loses ellipticity (localisation needs regularisation).
    pub fn validate(&self) -> Result<(), Error> {
        match *self {
            IsotropicHardening::Linear {
                yield_stress,
                hardening_modulus,
            } => {
                check_positive("yield_stress", yield_stress)?;
                check_non_negative("hardening_modulus", hardening_modulus)
            }
            IsotropicHardening::Saturation {
                yield_stress,
                hardening_modulus,
                saturation_stress,
                saturation_exponent,
            } => {
                check_positive("yield_stress", yield_stress)?;
                check_non_negative("hardening_modulus", hardening_modulus)?;
                if !(saturation_stress.is_finite() && saturation_stress >= yield_stress) {
                    return Err(Error::invalid(
                        "saturation_stress",
                        saturation_stress,
                        &format!("finite and ≥ yield_stress = {yield_stress}"),
                    ));
                }
                check_positive("saturation_exponent", saturation_exponent)
            }
        }
    }

    /// The initial yield stress `σ_y(0) = σ_0`.
    pub fn initial_yield_stress(&self) -> f64 {
        match *self {
            IsotropicHardening::Linear { yield_stress, .. }
            | IsotropicHardening::Saturation { yield_stress, .. } => yield_stress,
        }
    }

    /// The flow stress `σ_y(ε̄p)` and the hardening slope `H = dσ_y/dε̄p` (the formulas of the
    /// variants).
    #[inline]
    pub fn flow_stress_and_slope(&self, eps_p: f64) -> (f64, f64) {
        match *self {
            IsotropicHardening::Linear {
                yield_stress,
                hardening_modulus,
            } => (yield_stress + hardening_modulus * eps_p, hardening_modulus),
            IsotropicHardening::Saturation {
                yield_stress,
                hardening_modulus,
                saturation_stress,
                saturation_exponent,
            } => {
                let decay = (-saturation_exponent * eps_p).exp();
                let span = saturation_stress - yield_stress;
                (
                    yield_stress + hardening_modulus * eps_p + span * (1.0 - decay),
                    hardening_modulus + span * saturation_exponent * decay,
                )
            }
        }
    }
}
