//! Inelastic materials: J2 (von Mises) plasticity with isotropic hardening and the Johnson–Cook
//! flow stress, for solvers that integrate a hypoelastic deviatoric stress (the updated-Lagrangian
//! family, whose Jaumann rate gives the elastic trial).
//!
//! - [`PlasticState`]: the per-particle history (equivalent plastic strain, temperature rise).
//!   Elastic laws have none: a solver keeps an empty history vector for them and pays nothing.
//! - [`PlasticLaw`]: the flow stress — [`IsotropicHardening`] (linear or saturation) for `j2`,
//!   [`JohnsonCook`] for `johnson-cook`.
//! - [`Plasticity`]: a law with the elastic constants it returns with; its
//!   [`Plasticity::return_stress`] is the one call a solver makes per particle after each
//!   deviatoric stress update ([`radial_return`], Simo & Hughes 1998 Box 3.2).
//!
//! - [`HenckyPlasticity`]: the same laws at finite strain for total-Lagrangian solvers
//!   (`F = Fe Fp`, Hencky elasticity, the exponential-map return of [`finite_strain`], whose
//!   principal-frame return is [`Plasticity::return_stress`]).
//!
//! In 2D the deviator is the updated-Lagrangian paper's in-plane one (`d = 2`, `s_zz = 0`), so
//! `q = √(3/2 s:s)` sums its in-plane components; in 3D it is the full deviator.
//!
//! ```
//! use glam::DMat3;
//! use sph_core::D3;
//! use sph_materials::plasticity::{IsotropicHardening, PlasticLaw, PlasticState, Plasticity};
//! use sph_materials::ElasticConstants;
//!
//! // Steel-like: E = 200 GPa, ν = 0.3, σ_0 = 250 MPa, H = 1 GPa. A pure-shear trial stress of
//! // q* = 400 MPa returns onto the yield surface q = σ_0 + H Δε̄p.
//! let c = ElasticConstants::from_youngs(200e9, 0.3, 7850.0)?;
//! let law = PlasticLaw::J2(IsotropicHardening::Linear { yield_stress: 250e6, hardening_modulus: 1e9 });
//! let plastic = Plasticity::new(law, &c)?;
//! let tau = 400e6 / 3f64.sqrt();
//! let mut s = DMat3::from_cols_array(&[0.0, tau, 0.0, tau, 0.0, 0.0, 0.0, 0.0, 0.0]);
//! let mut state = PlasticState::default();
//! let d = plastic.return_stress::<D3>(&mut s, &mut state, 1e-6);
//! assert!((d - 150e6 / (3.0 * c.shear_modulus + 1e9)).abs() < 1e-18);
//! let q = (1.5 * (2.0 * s.x_axis.y * s.x_axis.y)).sqrt();
//! assert!((q - (250e6 + 1e9 * d)).abs() < 1e-6);
//! assert_eq!(state.equivalent_plastic_strain, d);
//! # Ok::<(), sph_core::Error>(())
//! ```

pub mod finite_strain;
pub mod hardening;
pub mod johnson_cook;
pub mod return_mapping;

pub use finite_strain::{
    first_piola_of_kirchhoff, FinitePlasticState, HenckyPlasticity, HenckyReturn,
};
pub use hardening::IsotropicHardening;
pub use johnson_cook::{JohnsonCook, ThermalSoftening};
pub use return_mapping::{
    equivalent_stress, plastic_strain_increment, radial_return, solve_consistency, RadialReturn,
    CONSISTENCY_TOLERANCE,
};

use crate::ElasticConstants;
use serde::{Deserialize, Serialize};
use sph_core::error::check_positive;
use sph_core::{Dim, Error};

/// The names of the plastic laws as scenes spell them.
pub const PLASTIC_LAW_NAMES: [&str; 2] = ["j2", "johnson-cook"];

/// The history of one particle of a plastic material: stepped with the stress, saved in
/// checkpoints, written as output. The default is the virgin state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PlasticState {
    /// Equivalent plastic strain `ε̄p = ∫ √(2/3 ε̇p:ε̇p) dt` (output field `plastic_strain`).
    pub equivalent_plastic_strain: f64,
    /// Temperature rise by adiabatic heating since the start (K; Johnson–Cook with thermal
    /// softening and a Taylor–Quinney fraction > 0, else 0).
    pub temperature_rise: f64,
}

/// A plastic flow law: the flow stress `σ_y` as a function of the history, the plastic strain
/// rate and the temperature, with J2 (von Mises) yield and associated flow.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "law", rename_all = "kebab-case")]
pub enum PlasticLaw {
    /// J2 plasticity with rate-independent isotropic hardening (scene `law = "j2"`).
    J2(IsotropicHardening),
    /// J2 plasticity with the Johnson–Cook flow stress (scene `law = "johnson-cook"`).
    JohnsonCook(JohnsonCook),
}

impl PlasticLaw {
    /// The name a scene uses (one of [`PLASTIC_LAW_NAMES`]).
    pub fn name(&self) -> &'static str {
        match self {
            PlasticLaw::J2(_) => "j2",
            PlasticLaw::JohnsonCook(_) => "johnson-cook",
        }
    }

    /// `Ok` if every constant is in its range.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first constant out of range.
    pub fn validate(&self) -> Result<(), Error> {
        match self {
            PlasticLaw::J2(h) => h.validate(),
            PlasticLaw::JohnsonCook(jc) => jc.validate(),
        }
    }

    /// The hardening modulus when the consistency equation is linear (J2 with linear hardening),
    /// so that [`solve_consistency`] solves it in closed form.
    #[inline]
    pub fn linear_hardening_modulus(&self) -> Option<f64> {
        match *self {
            PlasticLaw::J2(IsotropicHardening::Linear {
                hardening_modulus, ..
            }) => Some(hardening_modulus),
            _ => None,
        }
    }

    /// The flow stress after a plastic increment `Δε̄p` taken over `dt` from `state`, and its
    /// consistent derivative `dσ_y/dΔε̄p` (the slope Newton needs in Box 3.2 of Simo & Hughes
    /// 1998): for J2 `σ_y(ε̄p_n + Δε̄p)` and `H`; for Johnson–Cook
    /// `S(ε̄p_n + Δε̄p) R(Δε̄p/dt) Θ(T_n)` and `(S′ R + S R′/dt) Θ` (`S`, `R`, `Θ` the three
    /// factors of Johnson & Cook 1983 eq. 1, the temperature that of the step's start). `dt ≤ 0`
    /// or infinite: no rate effect.
    #[inline]
    pub fn flow_stress_after(&self, state: &PlasticState, delta: f64, dt: f64) -> (f64, f64) {
        let eps = state.equivalent_plastic_strain + delta;
        match self {
            PlasticLaw::J2(h) => h.flow_stress_and_slope(eps),
            PlasticLaw::JohnsonCook(jc) => {
                let (s, ds) = jc.strain_hardening(eps);
                let (r, dr) = if dt > 0.0 && dt.is_finite() {
                    let (r, dr) = jc.rate_factor(delta / dt);
                    (r, dr / dt)
                } else {
                    (1.0, 0.0)
                };
                let theta = jc.thermal_factor(jc.temperature(state.temperature_rise));
                // `S′ R` is +∞ for n < 1 at ε̄p = 0; a zero thermal factor (melted) has no slope.
                let slope = if theta == 0.0 {
                    0.0
                } else {
                    (ds * r + s * dr) * theta
                };
                (s * r * theta, slope)
            }
        }
    }
}

/// A plastic law with the elastic constants of its trial stress: what a solver holds.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plasticity {
    /// The flow law.
    pub law: PlasticLaw,
    /// Shear modulus `G` of the elastic trial (Pa).
    pub shear_modulus: f64,
    /// Density for the adiabatic heating (`ρ0`: the elastic volume change of a metal is below
    /// 1 %, and plastic flow is isochoric).
    pub density: f64,
}

impl Plasticity {
    /// The law with the shear modulus and density of `constants`, validated.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first constant out of range.
    pub fn new(law: PlasticLaw, constants: &ElasticConstants) -> Result<Self, Error> {
        law.validate()?;
        check_positive("shear_modulus", constants.shear_modulus)?;
        Ok(Self {
            law,
            shear_modulus: constants.shear_modulus,
            density: constants.density,
        })
    }

    /// Returns the trial deviator `s` (updated in place) onto the yield surface and steps the
    /// particle's history: `ε̄p += Δε̄p` and, for Johnson–Cook with heating, the adiabatic
    /// temperature rise of the increment (explicit: the return used the temperature of the
    /// step's start). `dt`: the time of the trial increment. Returns `Δε̄p` (0: elastic, `s`
    /// untouched bit for bit).
    #[inline]
    pub fn return_stress<D: Dim>(
        &self,
        s: &mut D::Matrix,
        state: &mut PlasticState,
        dt: f64,
    ) -> f64 {
        let r = radial_return::<D>(&self.law, self.shear_modulus, *s, state, dt);
        if r.delta_eps_p > 0.0 {
            *s = r.deviator;
            state.equivalent_plastic_strain += r.delta_eps_p;
            if let PlasticLaw::JohnsonCook(jc) = &self.law {
                state.temperature_rise +=
                    jc.adiabatic_heating(r.flow_stress, r.delta_eps_p, self.density);
            }
        }
        r.delta_eps_p
    }
}
