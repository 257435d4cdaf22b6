//! Plastic UL bodies: after every update of the shear stress `τ` (the two drifts of eq 23 and
//! 25, each an elastic trial by the Jaumann rate of eq 6–8), `τ` is returned to the yield
//! surface of the body's [`Plasticity`] (the radial return of Simo & Hughes 1998, Box 3.2) and
//! the particle's history is stepped. The pressure (eq 4) is not touched: J2 flow is
//! isochoric. Only the nested variants carry a plastic law: OG and OAS integrate `τ` and take its
//! divergence; ENOG's force is the Laplacian of velocity (eq 19–20), which has no stress tensor
//! to return, so it refuses one ([`UlSolver::with_plasticity`]).
//!
//! Energy: the plastic work `V τ:Δεp = V q Δε̄p` of each return ([`plastic_work_density`]) is
//! kept per particle; the budget has it as the term `plastic` (and [`UlSolver::plastic_work`]),
//! beside the stored shear energy `V τ:τ/(4G)` of [`crate::energy`].

use crate::solver::UlSolver;
use crate::Shear;
use serde::{Deserialize, Serialize};
use sph_core::{Dim, Error, Solver};
use sph_materials::plasticity::{PlasticLaw, PlasticState, Plasticity};

/// The history a plastic UL particle carries: the material's state and the energy its returns
/// have dissipated (J).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PlasticParticle {
    /// Equivalent plastic strain and temperature rise.
    pub state: PlasticState,
    /// Plastic dissipation of this particle since `t = 0` (J).
    pub dissipated: f64,
}

/// Plastic work per unit volume of one return, `τ:Δεp = q Δε̄p` with the returned stress `τ`
/// (`Δεp = (3/2) Δε̄p τ*/q*` along the radial direction, Simo & Hughes 1998 Box 3.2; `τ ∥ τ*`
/// gives `τ:τ* = (2/3) q q*`). This, not the drop of the stored energy at the return
/// (`(τ*:τ* − τ:τ)/(4G) = Δε̄p (q* + q)/2`, which contains the trial's overshoot), is what the
/// force work the step did on the deviator leaves after the stored energy: on the 40 m/s
/// collision of two steel blocks of `tests/plasticity.rs` (one advection step), the budget
/// residual is −608 J against 6.36e4 J of plastic work with it (the elastic run's own residual
/// is −666 J), +7.6e3 J with the drop.
#[inline(always)]
pub fn plastic_work_density<D: Dim>(trial: D::Matrix, returned: D::Matrix, delta: f64) -> f64 {
    let q_trial = sph_materials::plasticity::equivalent_stress::<D>(trial);
    1.5 * delta * D::ddot(returned, trial) / q_trial
}

/// Returns the trial shear stress `tau` (after an update over the time `h`) to the yield
/// surface, stepping the particle's history; `volume` is the particle's current `m/ρ`.
/// Elastic trials leave everything untouched, bit for bit.
#[inline(always)]
pub(crate) fn return_shear_stress<D: Dim>(
    plasticity: &Plasticity,
    tau: &mut D::Matrix,
    particle: &mut PlasticParticle,
    volume: f64,
    h: f64,
) {
    let trial = *tau;
    let delta = plasticity.return_stress::<D>(tau, &mut particle.state, h);
    if delta > 0.0 {
        particle.dissipated += volume * plastic_work_density::<D>(trial, *tau, delta);
    }
}

impl<D: Dim> UlSolver<D> {
    /// Makes the body elastic–plastic with `law` (J2 or Johnson–Cook), returning its shear
    /// stress to the yield surface after every update (see [`crate::plastic`]); the elastic
    /// trial uses the body's shear modulus. Adds the output field `plastic_strain` (and
    /// `temperature` for Johnson–Cook with thermal softening)
    /// (equivalent plastic strain), the figure `plastic_work`, the budget term `plastic`, and
    /// the history to checkpoints.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for `ul-enog` (its Laplacian shear force has no stress tensor
    /// to return: use `ul-og` or `ul-oas`), for a solver that has already stepped, or a law
    /// constant out of range.
    pub fn with_plasticity(mut self, law: PlasticLaw) -> Result<Self, Error> {
        if matches!(self.shear(), Shear::NonNested { .. }) {
            return Err(Error::invalid(
                "material.law",
                law.name(),
                "an elastic law for ul-enog (its Laplacian shear force has no stress tensor to \
                 return to a yield surface; use ul-og or ul-oas)",
            ));
        }
        if self.materials().len() > 1 {
            return Err(Error::invalid(
                "material.law",
                law.name(),
                "one material for a plastic law (a body of several materials is elastic for now)",
            ));
        }
        if self.step_count() > 0 {
            return Err(Error::invalid(
                "plasticity",
                format!("added after {} steps", self.step_count()),
                "a solver that has not stepped",
            ));
        }
        let plasticity = Plasticity::new(law, self.constants())?;
        self.set_plasticity(plasticity);
        Ok(self)
    }

    /// The plastic law (`None`: elastic).
    pub fn plasticity(&self) -> Option<&Plasticity> {
        self.plastic_law()
    }

    /// Equivalent plastic strain per particle (current order; empty for an elastic body).
    pub fn plastic_strain(&self) -> Vec<f64> {
        self.plastic_history()
            .iter()
            .map(|p| p.state.equivalent_plastic_strain)
            .collect()
    }

    /// Whether the law has a temperature (Johnson–Cook with thermal softening): then the output
    /// field `temperature` is offered.
    pub fn thermal(&self) -> bool {
        matches!(
            self.plastic_law().map(|p| &p.law),
            Some(PlasticLaw::JohnsonCook(jc)) if jc.thermal.is_some()
        )
    }

    /// Temperature per particle (K; current order): the initial temperature plus the adiabatic
    /// rise of its plastic work. Empty unless [`UlSolver::thermal`].
    pub fn temperatures(&self) -> Vec<f64> {
        match self.plastic_law().map(|p| &p.law) {
            Some(PlasticLaw::JohnsonCook(jc)) if jc.thermal.is_some() => self
                .plastic_history()
                .iter()
                .map(|p| jc.temperature(p.state.temperature_rise))
                .collect(),
            _ => Vec::new(),
        }
    }

    /// Plastic dissipation since `t = 0` summed over the particles in index order (J; 0 for
    /// an elastic body).
    pub fn plastic_work(&self) -> f64 {
        self.plastic_history().iter().map(|p| p.dissipated).sum()
    }
}
