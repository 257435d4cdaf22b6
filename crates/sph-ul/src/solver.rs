//! The UL solver: body set-up, neighbour rebuilds with cell-order reordering, and the
//! position-Verlet acoustic step (UL paper eq 23–25) inside the dual-criteria time stepping of §5.
//!
//! One acoustic step of length `Δt`:
//! 1. eq 23: `x`, `ρ` (and the shear stress `τ` of OG/OAS) to the half step with the rates of the
//!    previous step;
//! 2. eq 4: pressure from the half-step density; forces: Riemann pressure (eq 12) plus the
//!    variant's shear acceleration (OG: eq 13; OAS: eq 13 plus the artificial stress; ENOG: the
//!    accumulated `A_s` of the previous step, eq 20 note), contact between bodies
//!    ([`crate::contact`]); loads; constraints;
//! 3. eq 24: `v^{n+1} = v^n + Δt a` (with the energy budget, the work of the tracked force parts
//!    is accumulated first, see [`crate::energy`]); velocity constraints at the new time;
//! 4. rates with `v^{n+1}`: continuity (eq 11), the Jaumann rate of `τ` (eq 6–8 with the velocity
//!    gradient of eq 14/26) and, for ENOG, the Laplacian sum of eq 19 (or 18);
//! 5. eq 25: `x`, `ρ`, `τ` to the full step; then the ENOG accumulation
//!    `A_s += Δt · 2ζ (G/ρ) Σ …` (never reset).
//!
//! Element-wise work rides on the pair loops it follows or precedes: step 1 and the pressures
//! of step 2 are one pass (`drift_and_pressures`), steps 4 and 5 and the next
//! `|v|max` another (`compute_rates`), so a sub-step is five parallel loops (drift, kernel
//! data, forces, kick, rates) instead of nine; each is the same arithmetic per particle as the
//! separate loops, in the same order, so the results are bit for bit those of the separate
//! loops (and the same for every thread count).
//!
//! The neighbour list and the correction matrix `B` are those of the last rebuild, frozen over
//! the acoustic sub-steps of one advection step; the kernel data (`e_ij`, `r_ij`, `W′`; `W` from `r_ij` where a term reads it) are
//! recomputed over that list from the half-step positions of every sub-step
//! ([`UlParams::refresh_kernel_data`], default; frozen too when off). Volumes `V_j = m_j/ρ_j` use
//! the current densities. Every pair term is antisymmetric in `(i, j)` at one instant, so linear
//! momentum is conserved to round-off by every variant.

use crate::artificial_stress::{self, ArtificialShear};
use crate::contact::Contact;
use crate::energy::{kick_with_works, ul_budget, AccumulatedWork, Energy};
use crate::generalized::{penalty_pair, spin_rotation, GeneralizedShear};
use crate::nested::{jaumann_rate, shear_energy, velocity_gradient_pair, NestedShear};
use crate::non_nested::{
    conservative_laplacian_pair, default_zeta, non_conservative_laplacian_pair,
    shear_acceleration_rate, AccumulatedShear, LaplacianForm,
};
use crate::plastic::{return_shear_stress, PlasticParticle};
use crate::riemann::{
    continuity_has_jump, continuity_jump, dissipative_pressure, pressure, pressure_energy,
    pressure_pair_factor, RiemannScheme,
};
use crate::shear::{Shear, ShearForce};
use crate::stepping::{acoustic_dt, advection_dt, next_substep, Stepping};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sph_core::contact::{body_force_series, record_body_forces};
use sph_core::contact_friction::{ContactFriction, FrictionTable};
use sph_core::correction::{correction_matrices, DEFAULT_MIN_EIGENVALUE};
use sph_core::diagnostics;
use sph_core::disorder::{affine_fit, disorder_indicator, ReferenceWeights};
use sph_core::error::{check_closed_range, check_open_range, check_positive};
use sph_core::neighbor::{apply_permutation, invert_permutation};
use sph_core::pairs::{fill_pair_kernels, PairSymmetry};
use sph_core::scene::ProbeSchedule;
use sph_core::solver::first_non_finite;
use sph_core::state::{
    restore_probes, restore_series, save_probes, save_series, StateReader, StateWriter,
};
use sph_core::tool::{RigidTool, ToolSet};
use sph_core::{
    Body, CellGrid, Constraints, Dim, EnergyBudget, Error, Field, Kernel, Loads, NeighborList,
    PairKernel, Probe, Series, Solver, StepInfo, WendlandC2,
};
use sph_materials::{von_mises, ElasticConstants, Plasticity};

mod build;
mod measures;
mod params;
mod state;
mod substep;
pub use params::UlParams;

/// Variant data resolved at construction.
#[derive(Clone, Copy, Debug)]
enum Variant {
    Original,
    Artificial {
        epsilon: f64,
        n: u32,
        inv_w_dp: f64,
    },
    NonNested {
        factor: f64,
        form: LaplacianForm,
    },
    /// GNOG: `ξ G` of the penalty.
    Generalized {
        xi_g: f64,
    },
}

/// Per-particle rates computed with `v^{n+1}` (step 4 of the module docs).
#[derive(Clone, Copy, Debug)]
struct Rates<D: Dim> {
    /// `dρ/dt` (eq 11).
    density: f64,
    /// The pressure-jump part of `dρ/dt` (the paper's Riemann scheme only).
    density_jump: f64,
    /// `dτ/dt` (eq 6–8).
    stress: D::Matrix,
    /// ENOG: `dA_s/dt` (eq 20).
    shear: D::Vector,
}

impl<D: Dim> Rates<D> {
    fn zero() -> Self {
        Self {
            density: 0.0,
            density_jump: 0.0,
            stress: D::zero_matrix(),
            shear: D::zero(),
        }
    }
}

/// Updated-Lagrangian SPH solver for one body. See the crate documentation.
pub struct UlSolver<D: Dim> {
    /// The materials (`K`, `G`, `ρ0`, `c0` each); one for a solver built by [`UlSolver::new`].
    materials: Vec<ElasticConstants>,
    /// Index into `materials` per particle (current order).
    material: Vec<u16>,
    shear: Shear,
    variant: Variant,
    params: UlParams,
    kernel: WendlandC2<D>,
    /// The largest sound speed of the materials: the acoustic time step's.
    c0: f64,
    /// Whether `τ` is integrated (OG, OAS; ENOG with `track_shear_stress`).
    tracks_stress: bool,
    // Per-particle state (current order).
    positions: Vec<D::Vector>,
    velocities: Vec<D::Vector>,
    densities: Vec<f64>,
    masses: Vec<f64>,
    /// Shear stress `τ` (empty if not tracked).
    stress: Vec<D::Matrix>,
    /// ENOG accumulated shear acceleration `A_s`; GNOG accumulated penalty acceleration (empty
    /// otherwise).
    accumulated: Vec<D::Vector>,
    /// GNOG: the velocity gradient `L` of the last rates (empty otherwise).
    gradients: Vec<D::Matrix>,
    /// The plastic law (`None`: elastic; see [`crate::plastic`]).
    plasticity: Option<Plasticity>,
    /// Per-particle plastic history (empty for an elastic body, which pays nothing else).
    plastic: Vec<PlasticParticle>,
    rates: Vec<Rates<D>>,
    initial_positions: Vec<D::Vector>,
    original_index: Vec<u32>,
    free: Vec<bool>,
    // Rebuild data (frozen over the acoustic sub-steps).
    list: NeighborList,
    pairs: Vec<PairKernel<D>>,
    /// The two halves of `list` (built at each rebuild), so the per-sub-step refresh of
    /// `pairs` computes each unordered pair once; `None` if the list were not symmetric.
    halves: Option<PairSymmetry>,
    correction: Vec<D::Matrix>,
    guarded: usize,
    rebuild_positions: Vec<D::Vector>,
    /// Contact between bodies (`None`: one body).
    contact: Option<Contact<D>>,
    /// Coulomb friction between the bodies (`None`: frictionless contact).
    contact_friction: Option<ContactFriction<D>>,
    /// Contact force on each body, recorded with the probes.
    series: Vec<Series>,
    /// Rigid tools in kinematic contact (with friction where a tool has it) with the bodies.
    tools: ToolSet<D>,
    // Energy budget: work accumulated since t = 0, the total at t = 0, and per particle the
    // Riemann-dissipation and artificial-stress accelerations of the last force evaluation
    // and the load accelerations.
    work: AccumulatedWork,
    initial_total: f64,
    // Momentum balance: Σ m v at t = 0 and the impulse the constraints removed since.
    initial_momentum: D::Vector,
    constraint_impulse: D::Vector,
    budget_parts: Vec<[D::Vector; 2]>,
    load_accelerations: Vec<D::Vector>,
    // Scratch: a step's kicked velocities, for the budget's booking where a tool changes them.
    kicked: Vec<D::Vector>,
    // Particles without neighbours: at the last rebuild, the most at any rebuild, first time.
    isolated: usize,
    isolated_max: usize,
    first_isolation: Option<f64>,
    // Scratch (allocated once).
    pressures: Vec<f64>,
    /// `V_j = m_j/ρ_j` of the current densities, set with the pressures (the pair loops read it
    /// instead of dividing per pair).
    current_volumes: Vec<f64>,
    accelerations: Vec<D::Vector>,
    /// The energy budget's pressure-jump work per particle over a drift (empty otherwise).
    jump_work: Vec<f64>,
    artificial: Vec<D::Matrix>,
    volumes: Vec<f64>,
    // Scene.
    constraints: Constraints<D>,
    loads: Loads<D>,
    probes: Vec<Probe<D>>,
    schedule: ProbeSchedule,
    time: f64,
    steps: u64,
    acoustic_steps: u64,
    /// Pairs visited by the force evaluations so far ([`Solver::pair_visits`]).
    pair_visits: u64,
    rebuilds: u64,
    max_speed: f64,
}

impl<D: Dim> UlSolver<D> {
    /// Attaches the constraints. Particle indices refer to the body's **original** order (the
    /// order of [`Body::positions`]); they are remapped to the current order and at every
    /// reordering. Constrained particles are excluded from the time-step maxima.
    pub fn with_constraints(mut self, mut constraints: Constraints<D>) -> Self {
        constraints.remap(&self.inverse_index());
        self.free = constraints.free_mask(self.len());
        self.constraints = constraints;
        self.refresh_rates();
        self.reset_budget();
        self
    }

    /// Attaches body accelerations and point forces (indices in the original order).
    pub fn with_loads(mut self, mut loads: Loads<D>) -> Self {
        loads.remap(&self.inverse_index());
        self.loads = loads;
        if self.params.energy_budget {
            self.load_accelerations = vec![D::zero(); self.len()];
        }
        self
    }

    /// Makes the particles separate bodies (`body_of[i]` for input particle `i`) that meet
    /// through contact (docs/methods.md, SPHinXsys; see [`crate::contact`]): each body keeps
    /// its own neighbours (pressure, shear, continuity and `B` see only the own body), and
    /// particles of different bodies closer than the kernel support push each other apart with
    /// the contact pressure `p_c = κ c0² ρ_c`, `ρ_c,i = Σ_{j ∈ other} max(W_ij − W(dp), 0) m_j`,
    /// `a_i −= (2/m_i) Σ_j ½(p_c,i + p_c,j) V_i V_j W′_ij e_ij` (`κ` =
    /// [`UlParams::contact_scale`], `c0` the sound speed of the particle's own material, as
    /// SPHinXsys's contact stiffness per body) — antisymmetric per pair, so momentum is
    /// conserved; repulsive only (bodies separate freely). The contact force on each body is
    /// recorded with the probes as the series `contact_force_<body>` with columns `x`, `y`
    /// (, `z`) ([`Solver::series`]).
    ///
    /// # Errors
    /// `body_of` not one entry per particle; a body holding particles of two materials
    /// ([`UlSolver::with_materials`]).
    pub fn with_contact(mut self, body_of: Vec<u32>) -> Result<Self, Error> {
        let n = self.len();
        if body_of.len() != n {
            return Err(Error::invalid(
                "body_of",
                body_of.len(),
                &format!("one body id per particle ({n})"),
            ));
        }
        let body: Vec<u32> = self
            .original_index
            .iter()
            .map(|&o| body_of[o as usize])
            .collect();
        let bodies = body.iter().map(|&b| b as usize + 1).max().unwrap_or(0);
        // Each body has one material: its particles' pairs read one ρ0 c0 (eq 12).
        let mut material_of_body: Vec<Option<u16>> = vec![None; bodies];
        for (&b, &m) in body.iter().zip(&self.material) {
            match material_of_body[b as usize] {
                Some(other) if other != m => {
                    return Err(Error::invalid(
                        "body_of",
                        b,
                        &format!(
                            "bodies of one material each (body {b} holds materials {other} and {m})"
                        ),
                    ))
                }
                _ => material_of_body[b as usize] = Some(m),
            }
        }
        let materials: Vec<ElasticConstants> = material_of_body
            .iter()
            .map(|m| self.materials[m.unwrap_or(0) as usize])
            .collect();
        let dp = self.kernel.h() / self.params.h_over_dp;
        let contact = Contact::new(
            body,
            self.kernel.w(dp),
            self.params.contact_scale,
            &materials,
        );
        self.series = body_force_series(contact.bodies, D::D);
        self.contact = Some(contact);
        self.rebuild()?;
        self.refresh_rates();
        self.reset_budget();
        Ok(self)
    }

    /// Coulomb friction between the bodies of [`UlSolver::with_contact`], with the coefficients
    /// of `table` per pair of bodies ([`sph_core::contact_friction`]: velocity-level
    /// stick/slide on each contact pair after the kick, with the pair's contact force as the
    /// normal force). The series gain `contact_friction_<b>` (the mean friction force on body
    /// `b` and the sticking fraction), the summary `contact_friction_work`, the energy budget
    /// the term `contact_friction` (minus the friction work); the impulse fixed partners take
    /// is part of the momentum balance's constraint impulse. A frictionless table changes
    /// nothing (the bits of frictionless contact).
    ///
    /// # Errors
    /// No [`UlSolver::with_contact`] before, or a table of another number of bodies.
    pub fn with_contact_friction(mut self, table: FrictionTable) -> Result<Self, Error> {
        let Some(contact) = &self.contact else {
            return Err(Error::invalid(
                "contact friction",
                "a solver without body-body contact",
                "with_contact first",
            ));
        };
        if table.bodies() != contact.bodies {
            return Err(Error::invalid(
                "contact friction bodies",
                table.bodies(),
                &format!("the solver's {} bodies", contact.bodies),
            ));
        }
        self.contact_friction =
            (!table.is_frictionless()).then(|| ContactFriction::new(table, self.len()));
        self.reset_budget();
        Ok(self)
    }

    /// Attaches rigid tools in kinematic contact with the bodies, frictionless or with Coulomb
    /// friction ([`sph_core::tool`], [`sph_core::friction`]): after each acoustic step's kick
    /// and velocity constraints, the new velocity looks ahead one acoustic step from the
    /// half-step positions (the step of TL's tools), with the contact offset `dp/2` (UL carries
    /// no deformation gradient). Each tool records its series `/series/<name>` with the probes;
    /// the budget gains the terms `tool_contact` and `friction` (minus the tools' work on the
    /// body), the summary `tool_contact_work`, `friction_work`, `friction_dissipated`.
    ///
    /// # Errors
    /// As [`ToolSet::new`]: a tool name that is not a name or is used twice, a tool at or above
    /// the sound speed.
    pub fn with_tools(mut self, tools: Vec<RigidTool<D>>) -> Result<Self, Error> {
        let names: Vec<&str> = self.constraints.named().map(|(_, n)| n).collect();
        // A tool must be slower than sound in the softest body it may touch.
        let c_min = self
            .materials
            .iter()
            .map(|c| c.sound_speed)
            .fold(f64::INFINITY, f64::min);
        let mut set = ToolSet::new(tools, &names, c_min)?;
        set.reset_series(self.time);
        self.tools = set;
        self.reset_budget();
        Ok(self)
    }

    /// Makes the body plastic (checked by [`UlSolver::with_plasticity`]): a virgin history
    /// per particle.
    pub(crate) fn set_plasticity(&mut self, plasticity: Plasticity) {
        self.plasticity = Some(plasticity);
        self.plastic = vec![PlasticParticle::default(); self.len()];
        self.reset_budget();
    }

    /// The plastic law, if any.
    pub(crate) fn plastic_law(&self) -> Option<&Plasticity> {
        self.plasticity.as_ref()
    }

    /// The per-particle plastic history (current order; empty if elastic).
    pub(crate) fn plastic_history(&self) -> &[PlasticParticle] {
        &self.plastic
    }

    /// Sets the budget's reference total to the current energies (while at `t = 0`).
    fn reset_budget(&mut self) {
        if self.steps == 0 {
            self.work = AccumulatedWork::default();
            self.initial_total = 0.0;
            self.initial_total = self.energy_budget_now().total();
            self.initial_momentum = self.linear_momentum();
            self.constraint_impulse = D::zero();
            if let Some(f) = &mut self.contact_friction {
                f.reset();
            }
        }
    }

    /// Attaches probes (indices in the original order), recorded at `t = 0` and then every
    /// `interval` of simulated time (0 = every acoustic step), at the first acoustic sub-step
    /// that reaches each sample time (so the samples resolve times shorter than an advection
    /// step). The contact-force series are recorded on the same schedule.
    ///
    /// # Errors
    /// Probes that [`sph_core::scene::check_probes`] refuses; a negative or non-finite
    /// `interval`.
    pub fn with_probes(mut self, mut probes: Vec<Probe<D>>, interval: f64) -> Result<Self, Error> {
        sph_core::scene::check_probes(&probes)?;
        self.schedule = ProbeSchedule::every(interval)?;
        let inv = self.inverse_index();
        for p in &mut probes {
            p.remap(&inv);
        }
        self.probes = probes;
        for s in &mut self.series {
            *s = Series::new(&s.name, &AXES[..D::D]).with_description(&s.description);
        }
        if let Some(f) = &mut self.contact_friction {
            f.reset();
        }
        if self.schedule.due(self.time) {
            self.record_probes();
        }
        Ok(self)
    }

    /// The blow-up floor of every step and acoustic sub-step: [`diagnostics::MIN_DT_RATIO`] of
    /// the acoustic step at rest.
    fn time_step_floor(&self) -> f64 {
        diagnostics::MIN_DT_RATIO
            * acoustic_dt(self.params.cfl_acoustic, self.kernel.h(), self.c0, 0.0)
    }

    /// `inv[original] = current`.
    fn inverse_index(&self) -> Vec<u32> {
        invert_permutation(&self.original_index)
    }

    fn record_if_due(&mut self) {
        let recorded = !(self.series.is_empty() && self.tools.is_empty());
        if (!self.probes.is_empty() || recorded) && self.schedule.due(self.time) {
            self.record_probes();
        }
    }

    fn record_probes(&mut self) {
        for p in &mut self.probes {
            p.record(self.time, &self.positions, &self.velocities);
        }
        if let Some(c) = &self.contact {
            record_body_forces::<D>(&mut self.series, self.time, &c.body_forces(&self.masses));
        }
        if !self.tools.is_empty() {
            self.tools.record(self.time);
        }
        if let Some(f) = &mut self.contact_friction {
            f.record(self.time);
        }
    }

    fn check_finite(&self) -> Result<(), Error> {
        let fail = |field: &str, i: usize| Error::NonFinite {
            field: field.into(),
            particle: self.original_index[i] as usize,
            step: self.steps,
            time: self.time,
        };
        if let Some(i) = first_non_finite::<D>(&self.positions) {
            return Err(fail("position", i));
        }
        if let Some(i) = first_non_finite::<D>(&self.velocities) {
            return Err(fail("velocity", i));
        }
        if let Some(i) = self.densities.iter().position(|r| !r.is_finite()) {
            return Err(fail("density", i));
        }
        // J = ρ0/ρ: a density that is not positive is an inverted particle.
        if let Some(i) = self.densities.iter().position(|&r| r <= 0.0) {
            return Err(Error::Inverted {
                particle: self.original_index[i] as usize,
                jacobian: self.material_of(i).density / self.densities[i],
                step: self.steps,
                time: self.time,
            });
        }
        Ok(())
    }

    /// The shear treatment.
    pub fn shear(&self) -> Shear {
        self.shear
    }

    /// The numerical parameters.
    pub fn params(&self) -> &UlParams {
        &self.params
    }

    /// The elastic constants (`K`, `G`, `ρ0`, `c0 = √(K/ρ0)`, eq 5) of the first material (the
    /// only one of a solver built by [`UlSolver::new`]).
    pub fn constants(&self) -> &ElasticConstants {
        &self.materials[0]
    }

    /// The materials ([`UlSolver::with_materials`]).
    pub fn materials(&self) -> &[ElasticConstants] {
        &self.materials
    }

    /// The material index of each particle (current order).
    pub fn material_ids(&self) -> &[u16] {
        &self.material
    }

    /// The constants of particle `i`'s material (current order).
    #[inline(always)]
    fn material_of(&self, i: usize) -> &ElasticConstants {
        &self.materials[self.material[i] as usize]
    }

    /// The kernel.
    pub fn kernel(&self) -> &WendlandC2<D> {
        &self.kernel
    }

    /// `original_index()[k]` is the index in the input body of the particle now stored at `k`
    /// (particles are reordered in cell order at rebuilds).
    pub fn original_index(&self) -> &[u32] {
        &self.original_index
    }

    /// Maps a per-particle array in the current order back to the input order.
    pub fn to_original_order<T: Clone>(&self, data: &[T]) -> Vec<T> {
        apply_permutation(&self.inverse_index(), data)
    }

    /// Particle masses `ρ0 V⁰` (current order).
    pub fn masses(&self) -> &[f64] {
        &self.masses
    }

    /// Densities (current order).
    pub fn densities(&self) -> &[f64] {
        &self.densities
    }

    /// Shear stress `τ` (empty for ENOG without `track_shear_stress`).
    pub fn shear_stress(&self) -> &[D::Matrix] {
        &self.stress
    }

    /// ENOG's accumulated shear acceleration `A_s` (eq 20; empty for OG/OAS).
    pub fn accumulated_shear_acceleration(&self) -> &[D::Vector] {
        &self.accumulated
    }

    /// The neighbour list of the last rebuild.
    pub fn neighbors(&self) -> &NeighborList {
        &self.list
    }

    /// How many particles needed the correction-matrix guard at the last rebuild.
    pub fn guarded_particles(&self) -> usize {
        self.guarded
    }

    /// Acoustic sub-steps taken so far.
    pub fn acoustic_step_count(&self) -> u64 {
        self.acoustic_steps
    }

    /// Particles without any neighbour at the last rebuild (only non-zero with
    /// [`UlParams::allow_isolated`]).
    pub fn isolated(&self) -> usize {
        self.isolated
    }

    /// The most particles without any neighbour at any rebuild so far.
    pub fn isolated_max(&self) -> usize {
        self.isolated_max
    }

    /// Time of the first rebuild that found a particle without neighbours.
    pub fn first_isolation_time(&self) -> Option<f64> {
        self.first_isolation
    }

    /// Neighbour rebuilds so far (including the one at construction).
    pub fn rebuild_count(&self) -> u64 {
        self.rebuilds
    }

    /// Accelerations of the last acoustic step.
    pub fn accelerations(&self) -> &[D::Vector] {
        &self.accelerations
    }
}

/// Column names of the contact-force series (the force's components).
const AXES: [&str; 3] = ["x", "y", "z"];

pub(crate) use sph_core::parallel::gather;
use sph_core::parallel::{fold_columns, gather2, gather_columns};

/// Checks a per-particle array: length `n` (or empty if `optional`), every entry finite and > 0.
fn check_per_particle(field: &str, v: &[f64], n: usize, optional: bool) -> Result<(), Error> {
    if v.len() != n && !(optional && v.is_empty()) {
        let allowed = if optional {
            format!("empty or one per particle ({n})")
        } else {
            format!("one per particle ({n})")
        };
        return Err(Error::invalid(field, v.len(), &allowed));
    }
    if let Some(i) = v.iter().position(|x| !(x.is_finite() && *x > 0.0)) {
        return Err(Error::invalid(
            &format!("{field}[{i}]"),
            v[i],
            "> 0 and finite",
        ));
    }
    Ok(())
}

impl<D: Dim> Solver<D> for UlSolver<D> {
    fn method(&self) -> &'static str {
        self.shear.method_name()
    }

    /// `acoustic_steps`, `neighbour_rebuilds`, `isolated_max`, `momentum_balance` (the norm of
    /// [`UlSolver::momentum_balance`], unscaled) and `first_isolation_time` (NaN: none).
    fn figures(&self) -> Vec<(&'static str, f64)> {
        let mut figures = vec![
            ("acoustic_steps", self.acoustic_steps as f64),
            ("neighbour_rebuilds", self.rebuilds as f64),
            ("isolated_max", self.isolated_max as f64),
            ("momentum_balance", D::norm(self.momentum_balance())),
            (
                "first_isolation_time",
                self.first_isolation.unwrap_or(f64::NAN),
            ),
        ];
        if self.plasticity.is_some() {
            figures.push(("plastic_work", self.plastic_work()));
        }
        figures.extend(self.tools.figures());
        if let Some(f) = &self.contact_friction {
            figures.push(("contact_friction_work", f.work()));
        }
        figures
    }

    /// The step and the first acoustic sub-step the current speeds allow, against
    /// [`diagnostics::MIN_DT_RATIO`] of the acoustic step at rest (the checks of `step`).
    fn check_time_step(&self) -> Result<(), Error> {
        let floor = self.time_step_floor();
        diagnostics::check_time_step(self.stable_dt(), floor, self.steps, self.time)?;
        let acoustic = acoustic_dt(
            self.params.cfl_acoustic,
            self.kernel.h(),
            self.c0,
            self.max_speed,
        );
        diagnostics::check_time_step(acoustic, floor, self.steps, self.time)
    }

    /// Dual stepping: one advection step of `min(Δt_ad, max_dt)` (eq 21): rebuild, then
    /// acoustic sub-steps (eq 22–25) until the advection step is filled exactly. Single
    /// stepping: rebuild, then one acoustic step of `min(Δt_ac, max_dt)`.
    fn step(&mut self, max_dt: f64) -> Result<StepInfo, Error> {
        // Blow-up guard (diagnostics::MIN_DT_RATIO of the acoustic step at rest), checked on
        // the advection step here and on every acoustic sub-step below.
        let floor = self.time_step_floor();
        diagnostics::check_time_step(self.stable_dt(), floor, self.steps, self.time)?;
        if max_dt.is_nan() || max_dt <= 0.0 {
            return Err(Error::invalid("max_dt", max_dt, "> 0"));
        }
        if self.materials.len() > 1
            && self.contact.is_none()
            && self.material.iter().any(|&m| m != self.material[0])
        {
            return Err(Error::invalid(
                "materials",
                self.materials.len(),
                "one material per body: particles of several materials need with_contact",
            ));
        }
        let dt = self.stable_dt().min(max_dt);
        self.rebuild()?;
        let start = self.time;
        match self.params.stepping {
            Stepping::Single => self.acoustic_step(dt),
            Stepping::Dual => {
                let mut elapsed = 0.0;
                while elapsed < dt {
                    let stable = acoustic_dt(
                        self.params.cfl_acoustic,
                        self.kernel.h(),
                        self.c0,
                        self.max_speed,
                    );
                    if stable.is_nan() || stable <= floor {
                        self.check_finite()?;
                    }
                    diagnostics::check_time_step(stable, floor, self.steps, self.time)?;
                    let sub = next_substep(stable, dt - elapsed);
                    self.acoustic_step(sub);
                    elapsed += sub;
                    if elapsed < dt {
                        // Probes and series sample at acoustic resolution.
                        self.record_if_due();
                    }
                }
            }
        }
        self.time = start + dt;
        self.steps += 1;
        self.check_finite()?;
        self.record_if_due();
        Ok(StepInfo {
            dt,
            time: self.time,
            step: self.steps,
        })
    }

    /// Dual: the advection step of eq 21; single: the acoustic step of eq 22 (both with the
    /// current `|v|max` over unconstrained particles).
    fn stable_dt(&self) -> f64 {
        let h = self.kernel.h();
        match self.params.stepping {
            Stepping::Dual => advection_dt(
                self.params.cfl_advection,
                h,
                self.max_speed,
                self.params.speed_floor * self.c0,
            ),
            Stepping::Single => acoustic_dt(self.params.cfl_acoustic, h, self.c0, self.max_speed),
        }
    }

    /// The acoustic step of eq 22 (what a dual step is made of).
    fn substep_dt(&self) -> f64 {
        acoustic_dt(
            self.params.cfl_acoustic,
            self.kernel.h(),
            self.c0,
            self.max_speed,
        )
    }

    /// The state in the current particle order with the original index of each particle: `x`,
    /// `v`, `ρ`, `τ`, the ENOG accumulator, the rates the next step's first drift reads, the
    /// last accelerations and pressures, `|v|max`, time, steps and counters, probe records.
    /// Every step starts with a rebuild, so no neighbour data is needed.
    fn save_state(&self, out: &mut StateWriter) -> Result<(), Error> {
        self.write_state(out)
    }

    /// Puts the particles of this freshly built solver in the saved order (every per-particle
    /// field, constraint, load and probe follows), then reads the state.
    fn restore_state(&mut self, input: &mut StateReader<'_>) -> Result<(), Error> {
        self.read_state(input)
    }

    fn time(&self) -> f64 {
        self.time
    }

    fn pair_visits(&self) -> Option<u64> {
        Some(self.pair_visits)
    }

    fn step_count(&self) -> u64 {
        self.steps
    }

    fn positions(&self) -> &[D::Vector] {
        &self.positions
    }

    fn velocities(&self) -> &[D::Vector] {
        &self.velocities
    }

    /// [`UlSolver::original_index`]: the input index of each particle in the current order.
    fn particle_ids(&self) -> std::borrow::Cow<'_, [u32]> {
        std::borrow::Cow::Borrowed(&self.original_index)
    }

    fn field_names(&self) -> Vec<&'static str> {
        let mut names = vec![
            "velocity",
            "displacement",
            "density",
            "pressure",
            "von_mises",
            "shear_stress",
            "disorder",
            "fragment",
            "original_index",
            "body",
            "material",
        ];
        if self.plasticity.is_some() {
            names.push("plastic_strain");
        }
        if self.thermal() {
            names.push("temperature");
        }
        names
    }

    /// Output fields in the current particle order (see [`UlSolver::original_index`]).
    /// `fragment` labels the connected pieces of the own-body neighbour graph of the last
    /// rebuild (`0..k`; a body that breaks apart — numerical fracture — has several); `body`
    /// is the body id of [`UlSolver::with_contact`] (0 for one body), `material` the index into
    /// [`UlSolver::materials`].
    fn field(&self, name: &str) -> Option<Field<D>> {
        let n = self.len();
        Some(match name {
            "velocity" => Field::Vector(self.velocities.clone()),
            "displacement" => Field::Vector(
                self.positions
                    .iter()
                    .zip(&self.initial_positions)
                    .map(|(&x, &x0)| x - x0)
                    .collect(),
            ),
            "density" => Field::Scalar(self.densities.clone()),
            "pressure" => Field::Scalar(
                (0..n)
                    .map(|i| {
                        let c = self.material_of(i);
                        pressure(self.densities[i], c.density, c.sound_speed)
                    })
                    .collect(),
            ),
            "von_mises" => Field::Scalar(
                (0..n)
                    .into_par_iter()
                    .map(|i| von_mises(self.cauchy_3d(i)))
                    .collect(),
            ),
            "shear_stress" => Field::Matrix(if self.stress.is_empty() {
                vec![D::zero_matrix(); n]
            } else {
                self.stress.clone()
            }),
            "disorder" => Field::Scalar(self.disorder()),
            "fragment" => Field::Scalar(
                self.list
                    .components()
                    .0
                    .into_iter()
                    .map(f64::from)
                    .collect(),
            ),
            "original_index" => {
                Field::Scalar(self.original_index.iter().map(|&i| i as f64).collect())
            }
            "plastic_strain" if self.plasticity.is_some() => Field::Scalar(self.plastic_strain()),
            "temperature" if self.thermal() => Field::Scalar(self.temperatures()),
            "body" => Field::Scalar(match &self.contact {
                Some(c) => c.body.iter().map(|&b| f64::from(b)).collect(),
                None => vec![0.0; n],
            }),
            "material" => Field::Scalar(self.material.iter().map(|&m| f64::from(m)).collect()),
            _ => return None,
        })
    }

    fn probes(&self) -> &[Probe<D>] {
        &self.probes
    }

    fn energies(&self) -> Option<(f64, f64)> {
        let e = self.energy();
        Some((e.kinetic, e.volumetric + e.shear))
    }

    fn momentum(&self) -> Option<glam::DVec3> {
        Some(D::to_vec3(self.linear_momentum()))
    }

    fn energy_budget(&self) -> Option<EnergyBudget> {
        self.params.energy_budget.then(|| self.energy_budget_now())
    }

    /// The contact-force series of the bodies, then the tools' series.
    fn series(&self) -> Vec<Series> {
        let mut all = self.series.clone();
        all.extend(self.tools.series().iter().cloned());
        if let Some(f) = &self.contact_friction {
            all.extend(f.series().iter().cloned());
        }
        all
    }
}
