//! The TL solver: body set-up in the reference configuration and the position-Verlet step
//! (TL paper eq 30–32) with the time step of eq 33.

use crate::hourglass_free::HfLaplacian;
use crate::reference_pairs::{with_pair_rows, PairStorage, PairView, ReferencePairs};
use crate::{ganzenmuller, hourglass_free, original};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sph_core::correction::DEFAULT_MIN_EIGENVALUE;
use sph_core::diagnostics;
use sph_core::disorder::{disorder_indicator, ReferenceWeights};
use sph_core::distributed::OverRanks;
use sph_core::error::{check_closed_range, check_non_negative, check_open_range, check_positive};
use sph_core::parallel::{gather, gather2, max_over};
use sph_core::pressure::ResolvedPressure;
use sph_core::relaxation::PairwiseDamper;
use sph_core::scene::{ProbeSchedule, Series};
use sph_core::solver::{deformation_field, DEFORMATION_FIELDS};
use sph_core::state::{
    restore_probes, restore_series, save_probes, save_series, StateReader, StateWriter,
};
use sph_core::tool::{ReactionMeter, ToolSet};
use sph_core::{
    Constraints, Dim, Error, Field, Kernel, Loads, NeighborList, Probe, Solver, StepInfo,
    WendlandC2,
};
use sph_materials::plasticity::HenckyPlasticity;
use sph_materials::{von_mises, Material};
use std::sync::Arc;

mod bodies;
mod build;
mod local;
mod measures;
pub mod plastic;
mod scene;
pub use bodies::DEFAULT_CONTACT_SCALE;
use build::coincident_error;
pub use local::distribute;
pub use plastic::PlasticParticle;

/// The shear treatment, fixed when the body is built (hoisted out of the inner loops).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Shear {
    /// TL-SPH: eq 20–22 with the material's `P` and the correction matrix.
    Original,
    /// TL-SPH-HF: eq 25–29, shear from the Laplacian of position; ζ = 1.07 by default.
    HourglassFree {
        /// The kernel-dependent correction ζ of eq 27–28.
        zeta: f64,
    },
    /// TL-SPH with Ganzenmüller's hourglass penalty; α = 0.1 by default.
    Ganzenmuller {
        /// Penalty strength α.
        alpha: f64,
    },
}

impl Shear {
    /// HF with the paper's ζ.
    pub fn hourglass_free() -> Self {
        Shear::HourglassFree {
            zeta: hourglass_free::DEFAULT_ZETA,
        }
    }

    /// GM with the default α.
    pub fn ganzenmuller() -> Self {
        Shear::Ganzenmuller {
            alpha: ganzenmuller::DEFAULT_ALPHA,
        }
    }

    /// The method name as the command line spells it.
    pub fn method_name(&self) -> &'static str {
        match self {
            Shear::Original => "tl",
            Shear::HourglassFree { .. } => "tl-hf",
            Shear::Ganzenmuller { .. } => "tl-gm",
        }
    }

    /// Checks the shear's constant and that `laplacian` is one this shear can honour.
    fn validate(&self, laplacian: HfLaplacian) -> Result<(), Error> {
        match (*self, laplacian) {
            (_, HfLaplacian::Paper) => {}
            (Shear::HourglassFree { zeta }, HfLaplacian::Normalised) => {
                if zeta != hourglass_free::DEFAULT_ZETA {
                    return Err(Error::invalid(
                        "zeta",
                        zeta,
                        &format!(
                            "{} (its default) with laplacian = normalised, which gives every \
                             particle its own ζ",
                            hourglass_free::DEFAULT_ZETA
                        ),
                    ));
                }
            }
            (other, HfLaplacian::Normalised) => {
                return Err(Error::invalid(
                    "laplacian",
                    "normalised",
                    &format!(
                        "paper for {} (the normalised Laplacian is TL-HF's)",
                        other.method_name()
                    ),
                ));
            }
        }
        match *self {
            Shear::Original => Ok(()),
            Shear::HourglassFree { zeta } => check_positive("zeta", zeta),
            Shear::Ganzenmuller { alpha } => check_non_negative("alpha", alpha),
        }
    }
}

/// Numerical parameters (defaults: TL paper §4).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TlParams {
    /// Smoothing length over particle spacing (1.15; cut-off 2h = 2.3 dp).
    pub h_over_dp: f64,
    /// CFL number of eq 33 (0.6).
    pub cfl: f64,
    /// Kelvin–Voigt damping of eq 23–24 (on).
    pub damping: bool,
    /// Guard threshold of the correction matrix (see `sph_core::correction`).
    pub correction_min_eigenvalue: f64,
    /// The run stops with [`Error::TimeStepCollapsed`] when eq 33 gives a step below this
    /// fraction of the acoustic step at rest, `CFL·h/c` (1e-3): the acceleration criterion then
    /// signals |a| > 10⁶ c²/h, a collapsed pair of particles or an inverted element, and going on
    /// would only take a million steps to get nowhere.
    pub min_dt_ratio: f64,
    /// Scale the acoustic time step of eq 33 by the smallest principal stretch over the
    /// particles, `Δt = CFL · min(σ_min h/(c + |v|max), √(h/|a|max))`. Eq 33 measures the
    /// particle spacing in the reference configuration; under strong compression the current
    /// spacing (and with it the stable step) shrinks by `σ_min(F)` while the wave speed stays
    /// at least `c`: measured on the punching strip (H/dp 20, neo-Hookean, ν 0.45), eq 33 as
    /// printed blows up before 30 % compression, with this it runs to 50 %. Default off (the
    /// paper's eq 33); the quasi-static extreme cases turn it on (key `dt_stretch`).
    pub stretch_limited_dt: bool,
    /// Whether the reference pair data are stored or recomputed at every force pass
    /// ([`PairStorage`]; the results are the same bits either way). Default
    /// [`PairStorage::Stored`]; key `pair_data`.
    #[serde(default)]
    pub pair_storage: PairStorage,
    /// TL-HF: the paper's constant ζ or each particle's own ([`HfLaplacian`]); default the
    /// paper's. Key `laplacian`. Another method with [`HfLaplacian::Normalised`] is an error.
    #[serde(default)]
    pub hf_laplacian: HfLaplacian,
}

impl TlParams {
    /// The allowed `h_over_dp`, `lo ≤ h/dp ≤ hi`: from a kernel that still reaches the first
    /// neighbours to one six spacings wide.
    pub const H_OVER_DP_RANGE: (f64, f64) = (0.5, 3.0);
    /// The allowed CFL number of eq 33, `lo < CFL < hi`.
    pub const CFL_RANGE: (f64, f64) = (0.0, 1.0);

    /// Checks every parameter against its range (the ranges the `sph` command's keys and scene
    /// files share).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first field out of range.
    pub fn validate(&self) -> Result<(), Error> {
        let (lo, hi) = Self::H_OVER_DP_RANGE;
        check_closed_range("h_over_dp", self.h_over_dp, lo, hi)?;
        check_open_range("cfl", self.cfl, Self::CFL_RANGE.0, Self::CFL_RANGE.1)?;
        check_positive("min_dt_ratio", self.min_dt_ratio)?;
        check_positive("correction_min_eigenvalue", self.correction_min_eigenvalue)
    }
}

impl Default for TlParams {
    fn default() -> Self {
        Self {
            h_over_dp: 1.15,
            cfl: 0.6,
            damping: true,
            correction_min_eigenvalue: DEFAULT_MIN_EIGENVALUE,
            min_dt_ratio: diagnostics::MIN_DT_RATIO,
            stretch_limited_dt: false,
            pair_storage: PairStorage::Stored,
            hf_laplacian: HfLaplacian::Paper,
        }
    }
}

/// Kinetic and strain energy of the body.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Energy {
    /// `Σ ½ m v²`.
    pub kinetic: f64,
    /// `Σ V⁰ ψ(F)` of the material's law (the GM penalty has no energy and is not included).
    pub strain: f64,
}

impl Energy {
    /// Kinetic plus strain energy.
    pub fn total(&self) -> f64 {
        self.kinetic + self.strain
    }
}

/// Total-Lagrangian SPH solver for one body. See the crate documentation.
pub struct TlSolver<D: Dim, M: Material<D>> {
    material: M,
    shear: Shear,
    params: TlParams,
    kernel: WendlandC2<D>,
    density: f64,
    sound_speed: f64,
    gamma: f64,
    // Reference configuration (never changes).
    reference: Vec<D::Vector>,
    volumes: Vec<f64>,
    masses: Vec<f64>,
    list: NeighborList,
    /// `V_j ∇⁰_i W_ij` and the variant's pair scalar, stored or recomputed.
    pairs: ReferencePairs<D>,
    correction: Vec<D::Matrix>,
    guarded: usize,
    /// The neighbour data wait for [`distribute`] ([`TlSolver::for_ranks`]).
    deferred: bool,
    // State.
    positions: Vec<D::Vector>,
    velocities: Vec<D::Vector>,
    deformation: Vec<D::Matrix>,
    deformation_rate: Vec<D::Matrix>,
    accelerations: Vec<D::Vector>,
    /// The plastic law (`None`: elastic; see [`plastic`]).
    plasticity: Option<HenckyPlasticity>,
    /// Per-particle plastic history (empty for an elastic body, which pays nothing else).
    plastic: Vec<PlasticParticle>,
    // Scratch (allocated once).
    stress: Vec<D::Matrix>,
    /// HF: the factor of each particle's shear stress in eq 27, `g_i` (`J^(−2/d)` for the
    /// paper's law), times `ζ_i` with the normalised Laplacian.
    isochoric: Vec<f64>,
    /// HF with [`HfLaplacian::Normalised`]: each particle's `ζ_i`
    /// ([`hourglass_free::normalised_zeta`]); empty with the paper's constant ζ.
    hf_zeta: Vec<f64>,
    // Scene.
    constraints: Constraints<D>,
    free: Vec<bool>,
    loads: Loads<D>,
    /// Follower surface pressures (Nanson's formula with this method's `F`).
    pressures: Vec<ResolvedPressure<D>>,
    probes: Vec<Probe<D>>,
    schedule: ProbeSchedule,
    /// Rigid tools in contact with the body (with their meters, series and work).
    tools: ToolSet<D>,
    /// Reaction meters of the named constraints (grips), in `Constraints::named` order.
    grip_meters: Vec<ReactionMeter<D>>,
    /// Grip series (the tools keep theirs).
    series: Vec<Series>,
    /// Quasi-static relaxation (pairwise damping), if attached.
    relaxation: Option<PairwiseDamper>,
    /// Axes along which the centre of mass of the free particles is held still.
    held_axes: [bool; 3],
    dp: f64,
    time: f64,
    steps: u64,
    max_speed: f64,
    max_acceleration: f64,
    /// Smallest and largest principal stretch over the free particles (only tracked when the
    /// time step or the tools need them; 1 otherwise).
    min_stretch: f64,
    max_stretch: f64,
    /// This rank's share of a distributed run (`None` on one process; see [`distribute`]).
    domain: Option<Arc<sph_core::distributed::Domain>>,
    /// Contact between bodies and self-contact (`None`: one body, no self-contact).
    contact: Option<crate::contact::TlContact<D>>,
    /// The contact stiffness scale `κ` ([`TlSolver::with_contact_scale`]).
    contact_scale: f64,
    /// Coulomb friction on the contact pairs (`None`: frictionless).
    contact_friction: Option<sph_core::contact_friction::ContactFriction<D>>,
}

impl<D: Dim, M: Material<D>> TlSolver<D, M> {
    /// Removes the free particles' mean velocity along the held axes (sequential sums: the
    /// same result whatever the thread count).
    fn hold_centre(&mut self) {
        if !self.held_axes.iter().take(D::D).any(|&a| a) {
            return;
        }
        let (mut p, mut m) = (D::zero(), 0.0);
        for ((&v, &mi), &free) in self.velocities.iter().zip(&self.masses).zip(&self.free) {
            if free {
                p += v * mi;
                m += mi;
            }
        }
        let mut mean = p / m;
        for (k, &held) in self.held_axes.iter().enumerate().take(D::D) {
            if !held {
                D::set_component(&mut mean, k, 0.0);
            }
        }
        for (v, &free) in self.velocities.iter_mut().zip(&self.free) {
            if free {
                *v -= mean;
            }
        }
    }

    /// Kinematic contact (with friction where a tool has it) with every tool after a velocity
    /// update of step `dt`: the new velocity drifts the particles for Δt (this step's second
    /// half-drift and the next step's first) before it changes again, so the contact looks
    /// ahead by Δt from `x^{n+1/2}`, with the tool where it will be then. Contact offset: the
    /// deformed half cell `(dp/2)|Fᵀn|`. `count` records the particles in contact.
    fn enforce_tool_contact(&mut self, dt: f64, count: bool) {
        let t_end = self.time + 1.5 * dt;
        let (half_dp, deformation) = (0.5 * self.dp, &self.deformation);
        let offset = |i: usize, n: D::Vector| half_dp * D::norm(D::transpose(deformation[i]) * n);
        self.tools.enforce(
            t_end,
            dt,
            offset,
            half_dp * self.max_stretch,
            &self.positions,
            &mut self.velocities,
            &self.masses,
            &self.free,
            count,
        );
    }

    /// The smallest principal stretch (for [`TlParams::stretch_limited_dt`]) and the largest
    /// cell half-width factor (for the tools' contact reach) over the free particles, when
    /// either is in use. Max and min are exact, so the parallel reduction is deterministic.
    fn update_stretch_extremes(&mut self) {
        if self.params.stretch_limited_dt {
            let (def, free) = (&self.deformation, &self.free);
            // min(1, s) = −max(−1, −s).
            let local = -max_over(def.len(), -1.0, |i| {
                if free[i] {
                    -D::min_singular_value(def[i])
                } else {
                    -1.0
                }
            });
            self.min_stretch = self.domain.min_over_ranks(local);
        }
        if !self.tools.is_empty() {
            // |Fᵀ n| ≤ ‖F‖_F: a bound on every particle's contact offset factor.
            let def = &self.deformation;
            self.max_stretch = max_over(def.len(), 1.0, |i| D::frobenius(def[i]));
        }
    }

    /// Recomputes `Ḟ` from the current velocities and the speed maximum (after a state change).
    fn refresh_rates(&mut self) {
        self.constraints
            .apply_to_velocities(self.time, &mut self.velocities);
        if self.deferred {
            // No neighbour data yet: the rates follow when the rank builds its share.
            return;
        }
        let view = self
            .pairs
            .view(&self.list, &self.reference, &self.volumes, &self.kernel);
        with_pair_rows!(view, |rows| original::deformation_rate::<D>(
            rows,
            &self.correction,
            &self.velocities,
            &mut self.deformation_rate,
        ));
        self.max_speed = self.domain.max_over_ranks(diagnostics::max_norm_where::<D>(
            &self.velocities,
            &self.free,
        ));
    }

    /// Accelerations of the current state (positions, `F`, `Ḟ`), without loads or constraints:
    /// the force evaluation of one step, exposed for tests and diagnostics.
    /// A plastic body's history is not stepped (the return runs over the stable step).
    pub fn evaluate_accelerations(&mut self) -> &[D::Vector] {
        self.compute_internal_accelerations(None);
        &self.accelerations
    }

    /// The variant's internal accelerations into `self.accelerations`. A plastic body returns
    /// its stress over the step `dt` and, with `Some(dt)`, steps its history; with `None` it
    /// returns over the stable step and leaves the history alone.
    fn compute_internal_accelerations(&mut self, step: Option<f64>) {
        let inv_rho = 1.0 / self.density;
        let (material, gamma) = (&self.material, self.gamma);
        let view = self
            .pairs
            .view(&self.list, &self.reference, &self.volumes, &self.kernel);
        match self.shear {
            Shear::Original | Shear::Ganzenmuller { .. } => {
                let (f, fd, b) = (&self.deformation, &self.deformation_rate, &self.correction);
                match (&self.plasticity, step) {
                    (None, _) => gather(
                        &mut self.stress,
                        #[inline(always)]
                        |i, s| {
                            *s = original::corrected_piola::<D, M>(
                                material, gamma, f[i], fd[i], b[i],
                            );
                        },
                    ),
                    (Some(plasticity), Some(dt)) => {
                        let volumes = &self.volumes;
                        gather2(
                            &mut self.stress,
                            &mut self.plastic,
                            #[inline(always)]
                            |i, s, particle| {
                                let (p, r) = plastic::plastic_corrected_piola::<D>(
                                    plasticity,
                                    gamma,
                                    f[i],
                                    fd[i],
                                    b[i],
                                    &particle.history,
                                    dt,
                                );
                                *s = p;
                                particle.history = r.history;
                                particle.dissipated += volumes[i] * r.plastic_work;
                            },
                        );
                    }
                    (Some(plasticity), None) => {
                        let (history, dt) = (&self.plastic, self.stable_dt());
                        gather(
                            &mut self.stress,
                            #[inline(always)]
                            |i, s| {
                                *s = plastic::plastic_corrected_piola::<D>(
                                    plasticity,
                                    gamma,
                                    f[i],
                                    fd[i],
                                    b[i],
                                    &history[i].history,
                                    dt,
                                )
                                .0;
                            },
                        );
                    }
                }
                let (stress, acc) = (&self.stress, &mut self.accelerations);
                with_pair_rows!(view, |rows| {
                    original::stress_divergence::<D>(rows, stress, inv_rho, acc);
                    if let Shear::Ganzenmuller { alpha } = self.shear {
                        let scale = alpha * material.constants().youngs_modulus * 0.5 * inv_rho;
                        ganzenmuller::add_penalty_acceleration::<D>(
                            rows,
                            &self.reference,
                            &self.positions,
                            &self.deformation,
                            scale,
                            acc,
                        );
                    }
                });
            }
            Shear::HourglassFree { zeta } => {
                let (f, fd, own) = (&self.deformation, &self.deformation_rate, &self.hf_zeta);
                gather2(
                    &mut self.stress,
                    &mut self.isochoric,
                    #[inline(always)]
                    |i, s, jf| {
                        // Each particle's ζ_i (normalised Laplacian) goes into its factor
                        // ζ_i g_i of eq 27; the paper's one ζ scales the whole sum below.
                        let z = if own.is_empty() { zeta } else { own[i] };
                        let (p, j) = hourglass_free::remaining_piola::<D, M>(
                            material, z, gamma, f[i], fd[i],
                        );
                        *s = p;
                        *jf = if own.is_empty() { j } else { z * j };
                    },
                );
                let g = material.constants().shear_modulus;
                let scale = if own.is_empty() { zeta } else { 1.0 };
                let (stress, acc) = (&self.stress, &mut self.accelerations);
                with_pair_rows!(view, |rows| hourglass_free::acceleration::<D>(
                    rows,
                    stress,
                    &self.positions,
                    &self.isochoric,
                    inv_rho,
                    scale * g * inv_rho,
                    acc,
                ));
            }
        }
    }

    /// The body's reference pair data with what recomputing them reads.
    fn pair_view(&self) -> PairView<'_, D> {
        self.pairs
            .view(&self.list, &self.reference, &self.volumes, &self.kernel)
    }

    fn record_probes(&mut self) {
        for p in &mut self.probes {
            p.record(self.time, &self.positions, &self.velocities);
        }
    }

    fn check_finite(&self) -> Result<(), Error> {
        diagnostics::check_state::<D>(
            &self.positions,
            &self.velocities,
            ("deformation gradient", &self.deformation),
            &[],
            self.steps,
            self.time,
        )
    }

    /// The shear treatment.
    pub fn shear(&self) -> Shear {
        self.shear
    }

    /// The numerical parameters.
    pub fn params(&self) -> &TlParams {
        &self.params
    }

    /// The material.
    pub fn material(&self) -> &M {
        &self.material
    }

    /// The kernel.
    pub fn kernel(&self) -> &WendlandC2<D> {
        &self.kernel
    }

    /// The reference configuration `X`.
    pub fn reference_positions(&self) -> &[D::Vector] {
        &self.reference
    }

    /// Reference volumes.
    pub fn volumes(&self) -> &[f64] {
        &self.volumes
    }

    /// Particle masses `ρ0 V⁰`.
    pub fn masses(&self) -> &[f64] {
        &self.masses
    }

    /// The neighbour list (reference configuration).
    pub fn neighbors(&self) -> &NeighborList {
        &self.list
    }

    /// How this solver holds its reference pair data.
    pub fn pair_storage(&self) -> PairStorage {
        if self.pairs.is_stored() {
            PairStorage::Stored
        } else {
            PairStorage::Recomputed
        }
    }

    /// How many particles needed the correction-matrix guard.
    pub fn guarded_particles(&self) -> usize {
        self.guarded
    }

    /// Each particle's ζ of TL-HF's normalised Laplacian ([`HfLaplacian::Normalised`],
    /// [`hourglass_free::normalised_zeta`]); `None` with the paper's constant ζ, another
    /// method, or before the reference data are built.
    pub fn laplacian_zeta(&self) -> Option<&[f64]> {
        (!self.hf_zeta.is_empty()).then_some(&self.hf_zeta[..])
    }

    /// Deformation gradients.
    pub fn deformation_gradients(&self) -> &[D::Matrix] {
        &self.deformation
    }

    /// Accelerations of the last step.
    pub fn accelerations(&self) -> &[D::Vector] {
        &self.accelerations
    }
}

impl<D: Dim, M: Material<D>> Solver<D> for TlSolver<D, M> {
    fn method(&self) -> &'static str {
        self.shear.method_name()
    }

    /// Eq 33's step against `min_dt_ratio` of the acoustic step at rest, `CFL h/c`.
    fn check_time_step(&self) -> Result<(), Error> {
        let floor = self.params.min_dt_ratio * self.params.cfl * self.kernel.h() / self.sound_speed;
        diagnostics::check_time_step(self.stable_dt(), floor, self.steps, self.time)
    }

    /// One position-Verlet step (TL paper eq 30–32).
    fn step(&mut self, max_dt: f64) -> Result<StepInfo, Error> {
        self.built("step")?;
        self.check_time_step()?;
        let stable = self.stable_dt();
        if max_dt.is_nan() || max_dt <= 0.0 {
            return Err(Error::invalid("max_dt", max_dt, "> 0"));
        }
        let dt = stable.min(max_dt);
        let half = 0.5 * dt;
        // Eq 30: F and x to the half step with the old Ḟ and v.
        half_step::<D>(
            &mut self.deformation,
            &self.deformation_rate,
            &mut self.positions,
            &self.velocities,
            half,
        );
        // Forces at the half step (a plastic body's return over Δt); contact; loads; constraints.
        self.compute_internal_accelerations(Some(dt));
        if let Some(c) = &mut self.contact {
            c.add_accelerations(
                &self.positions,
                &self.reference,
                &self.masses,
                &self.volumes,
                &self.kernel,
                &mut self.accelerations,
            )?;
        }
        if !self.loads.is_empty() {
            self.loads
                .add_accelerations(self.time + half, &self.masses, &mut self.accelerations);
        }
        let masses = &self.masses;
        for sp in &self.pressures {
            sp.add_accelerations(
                self.time + half,
                &self.deformation,
                |i| 1.0 / masses[i],
                &mut self.accelerations,
            );
        }
        if !self.grip_meters.is_empty() {
            let reactions = self
                .constraints
                .reactions(&self.accelerations, &self.masses);
            for (m, r) in self.grip_meters.iter_mut().zip(reactions) {
                m.add(r, dt);
            }
        }
        self.constraints
            .apply_to_accelerations(&mut self.accelerations);
        // Eq 31: velocities to the full step.
        let acc = &self.accelerations;
        gather(
            &mut self.velocities,
            #[inline(always)]
            |i, v| *v += acc[i] * dt,
        );
        // Coulomb friction on the contact pairs (a constrained component is then restored).
        if let (Some(friction), Some(contact)) = (&mut self.contact_friction, &self.contact) {
            contact.apply_friction(
                friction,
                &self.positions,
                &mut self.velocities,
                &self.masses,
                &self.volumes,
                &self.free,
                &self.kernel,
                dt,
            );
            self.constraints
                .apply_to_velocities(self.time + dt, &mut self.velocities);
        }
        // Contact with the tools, then the quasi-static relaxation of the
        // admissible velocities, then contact again if the relaxation ran (it may have pulled a
        // touching particle toward a tool). Relaxing before the contact would spread the
        // surface rows' transient velocity, which the contact is about to remove, into the
        // interior: a pump of spurious momentum (measured: kinetic energy growing 40× on the
        // punching strip).
        self.tools.begin_step();
        self.enforce_tool_contact(dt, true);
        let relaxed = match &self.relaxation {
            Some(damper) => damper.apply::<D>(
                self.steps,
                dt,
                &mut self.velocities,
                &self.masses,
                &self.free,
            ),
            None => false,
        };
        if relaxed {
            self.enforce_tool_contact(dt, false);
        }
        self.tools.end_step(dt);
        self.hold_centre();
        self.exchange_velocities();
        self.time += dt;
        self.steps += 1;
        // Eq 22 with v^{n+1}, then eq 32.
        self.refresh_rates();
        half_step::<D>(
            &mut self.deformation,
            &self.deformation_rate,
            &mut self.positions,
            &self.velocities,
            half,
        );
        self.max_acceleration = self.domain.max_over_ranks(diagnostics::max_norm_where::<D>(
            &self.accelerations,
            &self.free,
        ));
        self.update_stretch_extremes();
        self.domain.agree(self.check_finite())?;
        let nothing = self.series.is_empty()
            && self.tools.is_empty()
            && self.contact.is_none()
            && self.contact_friction.is_none();
        if !(self.probes.is_empty() && nothing) && self.schedule.due(self.time) {
            self.record_probes();
            self.record_series();
        }
        Ok(StepInfo {
            dt,
            time: self.time,
            step: self.steps,
        })
    }

    /// Eq 33: `Δt = CFL · min(h/(c + |v|max), √(h/|a|max))` over unconstrained particles (the
    /// acoustic part scaled by the smallest principal stretch with
    /// [`TlParams::stretch_limited_dt`]).
    fn stable_dt(&self) -> f64 {
        let h = self.kernel.h();
        // With contact, its wave speed `√κ c0` when the contact is stiffer than the body.
        let c = match self.contact {
            Some(_) => self.sound_speed * self.contact_scale.sqrt().max(1.0),
            None => self.sound_speed,
        };
        let acoustic = self.min_stretch * h / (c + self.max_speed);
        let force = if self.max_acceleration > 0.0 {
            (h / self.max_acceleration).sqrt()
        } else {
            f64::INFINITY
        };
        self.params.cfl * acoustic.min(force)
    }

    fn time(&self) -> f64 {
        self.time
    }

    fn step_count(&self) -> u64 {
        self.steps
    }

    fn pair_visits(&self) -> Option<u64> {
        // One force evaluation per step over a list fixed in the reference configuration.
        Some(self.steps * self.list.num_pairs() as u64)
    }

    fn positions(&self) -> &[D::Vector] {
        &self.positions
    }

    fn velocities(&self) -> &[D::Vector] {
        &self.velocities
    }

    fn field_names(&self) -> Vec<&'static str> {
        let mut names = DEFORMATION_FIELDS.to_vec();
        names.extend(["von_mises", "disorder", "body", "material"]);
        if self.plasticity.is_some() {
            names.push("plastic_strain");
            if self.thermal() {
                names.push("temperature");
            }
        }
        names
    }

    /// The deformation fields, `von_mises`, `disorder`; `body` (each particle's body,
    /// [`TlSolver::with_bodies`]) and `material` (0: a TL solver runs one material), as the UL
    /// and MPS fields of those names; for a plastic body `plastic_strain` (and `temperature`
    /// with thermal softening), and `von_mises` of the returned stress.
    fn field(&self, name: &str) -> Option<Field<D>> {
        match name {
            "von_mises" => Some(Field::Scalar(match &self.plasticity {
                None => self
                    .deformation
                    .par_iter()
                    .map(|&f| von_mises(self.cauchy_3d(f)))
                    .collect(),
                Some(p) => (0..self.deformation.len())
                    .into_par_iter()
                    .map(|i| von_mises(self.plastic_cauchy_3d(p, i)))
                    .collect(),
            })),
            "plastic_strain" if self.plasticity.is_some() => {
                Some(Field::Scalar(self.plastic_strain()))
            }
            "temperature" if self.thermal() => Some(Field::Scalar(self.temperatures())),
            "disorder" => Some(Field::Scalar(self.disorder())),
            "body" => Some(Field::Scalar(
                self.bodies().iter().map(|&b| f64::from(b)).collect(),
            )),
            "material" => Some(Field::Scalar(vec![0.0; self.positions.len()])),
            _ => deformation_field::<D>(
                name,
                &self.positions,
                &self.reference,
                &self.velocities,
                &self.deformation,
                self.density,
            ),
        }
    }

    fn probes(&self) -> &[Probe<D>] {
        &self.probes
    }

    /// The tools' series, then the grips', then with several bodies the contact force on each
    /// body, `contact_force_<body>` ([`TlSolver::with_bodies`]).
    fn series(&self) -> Vec<Series> {
        let mut all = self.tools.series().to_vec();
        all.extend(self.series.iter().cloned());
        if let Some(c) = &self.contact {
            all.extend(c.series.iter().cloned());
        }
        if let Some(f) = &self.contact_friction {
            all.extend(f.series().iter().cloned());
        }
        all
    }

    /// The tools' work on the body (`tool_contact_work`, `friction_work`,
    /// `friction_dissipated`; none without tools), with friction between bodies
    /// `contact_friction_work` (the work of the friction impulses, ≤ 0) and, for a plastic body,
    /// `plastic_work`.
    fn figures(&self) -> Vec<(&'static str, f64)> {
        let mut figures = self.tools.figures();
        if let Some(f) = &self.contact_friction {
            figures.push(("contact_friction_work", f.work()));
        }
        if self.plasticity.is_some() {
            figures.push(("plastic_work", self.plastic_work()));
        }
        figures
    }

    /// The state: `x`, `v`, `F`, `Ḟ`, the last accelerations and the extremes the time step
    /// reads, time and steps, probe and series records and the reaction meters; for a plastic
    /// body its history (`Cp⁻¹`, `ε̄p`, temperature rise, dissipation).
    fn save_state(&self, out: &mut StateWriter) -> Result<(), Error> {
        out.vectors::<D>("positions", &self.positions);
        out.vectors::<D>("velocities", &self.velocities);
        out.matrices::<D>("deformation", &self.deformation);
        out.matrices::<D>("deformation_rate", &self.deformation_rate);
        out.vectors::<D>("accelerations", &self.accelerations);
        out.f64s(
            "scalars",
            &[
                self.time,
                self.max_speed,
                self.max_acceleration,
                self.min_stretch,
                self.max_stretch,
                self.schedule.next(),
            ],
        );
        out.u64s("steps", &[self.steps]);
        save_probes(out, &self.probes);
        save_series(out, &self.series);
        if let Some(c) = &self.contact {
            save_series(out, &c.series);
        }
        self.tools.save(out);
        ReactionMeter::save_all(out, "grip_meters", &self.grip_meters);
        if let Some(f) = &self.contact_friction {
            f.save(out);
        }
        // The plastic history, only for a plastic body (an elastic checkpoint is unchanged).
        if !self.plastic.is_empty() {
            let column = |f: fn(&PlasticParticle) -> f64| -> Vec<f64> {
                self.plastic.iter().map(f).collect()
            };
            let cp_inv: Vec<glam::DMat3> = self
                .plastic
                .iter()
                .map(|p| p.history.inverse_plastic_cauchy_green)
                .collect();
            out.matrices::<sph_core::D3>("inverse_plastic_cauchy_green", &cp_inv);
            out.f64s(
                "plastic_strain",
                &column(|p| p.history.state.equivalent_plastic_strain),
            );
            out.f64s(
                "temperature_rise",
                &column(|p| p.history.state.temperature_rise),
            );
            out.f64s("plastic_dissipation", &column(|p| p.dissipated));
        }
        Ok(())
    }

    fn restore_state(&mut self, input: &mut StateReader<'_>) -> Result<(), Error> {
        let n = Some(self.positions.len());
        self.positions = input.vectors::<D>("positions", n)?;
        self.velocities = input.vectors::<D>("velocities", n)?;
        self.deformation = input.matrices::<D>("deformation", n)?;
        self.deformation_rate = input.matrices::<D>("deformation_rate", n)?;
        self.accelerations = input.vectors::<D>("accelerations", n)?;
        let [time, max_speed, max_acceleration, min_stretch, max_stretch, next_probe] =
            input.scalars::<6>("scalars")?;
        (self.time, self.max_speed, self.max_acceleration) = (time, max_speed, max_acceleration);
        (self.min_stretch, self.max_stretch) = (min_stretch, max_stretch);
        self.schedule.set_next(next_probe);
        self.steps = input.u64s("steps", Some(1))?[0];
        restore_probes(input, &mut self.probes)?;
        restore_series(input, &mut self.series)?;
        if let Some(c) = &mut self.contact {
            restore_series(input, &mut c.series)?;
        }
        self.tools.restore(input)?;
        ReactionMeter::restore_all(input, "grip_meters", &mut self.grip_meters)?;
        if let Some(f) = &mut self.contact_friction {
            f.restore(input)?;
        }
        if !self.plastic.is_empty() {
            let cp_inv = input.matrices::<sph_core::D3>("inverse_plastic_cauchy_green", n)?;
            let eps = input.f64s("plastic_strain", n)?;
            let rise = input.f64s("temperature_rise", n)?;
            let dissipated = input.f64s("plastic_dissipation", n)?;
            for (k, p) in self.plastic.iter_mut().enumerate() {
                p.history.inverse_plastic_cauchy_green = cp_inv[k];
                p.history.state.equivalent_plastic_strain = eps[k];
                p.history.state.temperature_rise = rise[k];
                p.dissipated = dissipated[k];
            }
        }
        self.check_finite()
    }

    fn energies(&self) -> Option<(f64, f64)> {
        let e = self.energy();
        Some((e.kinetic, e.strain + self.contact_energy()))
    }

    fn momentum(&self) -> Option<glam::DVec3> {
        Some(D::to_vec3(self.linear_momentum()))
    }
}

/// `F += h Ḟ`, `x += h v` (eq 30 and 32).
fn half_step<D: Dim>(
    f: &mut [D::Matrix],
    f_dot: &[D::Matrix],
    x: &mut [D::Vector],
    v: &[D::Vector],
    h: f64,
) {
    // One loop for both: a hand-off less per half step.
    gather2(
        f,
        x,
        #[inline(always)]
        |i, f, x| {
            *f += f_dot[i] * h;
            *x += v[i] * h;
        },
    );
}
