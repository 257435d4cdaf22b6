//! The MPS solver: body set-up in the reference configuration (eq 4–6, total Lagrangian) and the
//! symplectic time step (velocity Verlet, or the paper's symplectic Euler of eq 8) with
//! `Δt = C l0 / c`.

use crate::contact::{Contact, ResolvedContact};
use crate::stabilisation::Stabilisation;
use crate::wls::{self, Fit};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sph_core::correction::DEFAULT_MIN_EIGENVALUE;
use sph_core::diagnostics;
use sph_core::disorder::{disorder_indicator, ReferenceWeights};
use sph_core::distributed::OverRanks;
use sph_core::error::{check_closed_range, check_non_negative, check_open_range, check_positive};
use sph_core::pressure::{ResolvedPressure, SurfacePressure};
use sph_core::scene::ProbeSchedule;
use sph_core::solver::first_non_finite;
use sph_core::solver::{deformation_field, DEFORMATION_FIELDS};
use sph_core::state::{restore_probes, save_probes, StateReader, StateWriter};
use sph_core::tool::{RigidTool, ToolSet};
use sph_core::{Constraints, Dim, Error, Field, Loads, NeighborList, Probe, Solver, StepInfo};
use sph_materials::{von_mises, Material};
use std::sync::Arc;

mod build;
mod local;
mod measures;
pub use local::distribute;

/// The symplectic time integrator.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Integrator {
    /// Velocity Verlet (kick–drift–kick; Störmer/Verlet as in Suzuki & Koshizuka 2008):
    /// symplectic, time-reversible, second order, one force evaluation per step (the forces of
    /// the end of a step are reused at the start of the next). Positions and velocities are
    /// synchronous, so the energy `Σ ½mv² + Σ Vψ` oscillates at `O(Δt²)` with no drift. Default.
    #[default]
    VelocityVerlet,
    /// The paper's eq 8 (symplectic Euler): `x^{n+1} = x^n + Δt v^n`,
    /// `v^{n+1} = v^n + Δt a(x^{n+1})`. Symplectic and first order; its velocities lag the
    /// positions by half a step, so the measured energy oscillates at `O(Δt)`. The positions
    /// are those of leapfrog.
    SymplecticEuler,
}

/// Numerical parameters. The paper states neither `r_e` nor `C`; the defaults are explained on
/// each field.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MpsParams {
    /// Radius of the weight of eq 6 over the initial spacing, `r_e / l0` (> 1). Default 2.1, the
    /// usual MPS gradient radius (docs/methods.md range 2.1–3.1): 12 neighbours in 2D and 32 in 3D on
    /// a lattice.
    pub re_over_l0: f64,
    /// Courant number `C` of `Δt = C l0 / c`, `c = √(K/ρ0)` (> 0). Default 0.1 (see the crate's
    /// tests for the measured stability limit).
    pub courant: f64,
    /// The time integrator (default velocity Verlet).
    pub integrator: Integrator,
    /// Velocity damping `c_d` (1/s, ≥ 0) for static problems: `dv/dt = a − c_d v`, applied as the
    /// exact factor `exp(−c_d Δt/2)` before the first and after the last kick of each step
    /// (operator splitting, unconditionally stable; rigid motion is damped too). 0 = off
    /// (default); then the scheme is Hamiltonian.
    pub damping: f64,
    /// Guard threshold of the moment matrix `A_i` (scaled to `≈ I`), see
    /// [`crate::wls::moment_inverse`].
    pub moment_min_eigenvalue: f64,
    /// The fit that gives `F` (default: the paper's linear fit of eq 4–5).
    #[serde(default)]
    pub fit: Fit,
    /// Strength `α` (≥ 0, dimensionless) of the Hamiltonian stabilisation of
    /// [`crate::stabilisation`]: a penalty potential on the residual of the WLS fit,
    /// `U_s = Σ_i (α μ V_i/2) Σ_j ŵ_ij |x_ij − F_i X_ij|²/|X_ij|²`, which gives the zero-energy
    /// modes of eq 4–5 a stiffness `α μ`. 0 = off, the paper's model (default).
    #[serde(default)]
    pub stabilisation: f64,
}

impl MpsParams {
    /// The allowed `r_e/l0`, `lo < r_e/l0 < hi`: beyond the nearest neighbours, within a
    /// support that still resolves a body a dozen spacings thick.
    pub const RE_OVER_L0_RANGE: (f64, f64) = (1.0, 6.0);
    /// The allowed Courant number, `lo < C < hi`.
    pub const COURANT_RANGE: (f64, f64) = (0.0, 1.0);
    /// The allowed stabilisation strength α, `lo ≤ α ≤ hi`.
    pub const STABILISATION_RANGE: (f64, f64) = (0.0, 100.0);

    /// Checks every parameter against its range (the ranges the `sph` command's keys and scene
    /// files share).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first field out of range.
    pub fn validate(&self) -> Result<(), Error> {
        let (lo, hi) = Self::RE_OVER_L0_RANGE;
        check_open_range("re_over_l0", self.re_over_l0, lo, hi)?;
        let (lo, hi) = Self::COURANT_RANGE;
        check_open_range("courant", self.courant, lo, hi)?;
        check_non_negative("damping", self.damping)?;
        let (lo, hi) = Self::STABILISATION_RANGE;
        check_closed_range("stabilisation", self.stabilisation, lo, hi)?;
        check_positive("moment_min_eigenvalue", self.moment_min_eigenvalue)
    }
}

impl Default for MpsParams {
    fn default() -> Self {
        Self {
            re_over_l0: 2.1,
            courant: 0.1,
            integrator: Integrator::VelocityVerlet,
            damping: 0.0,
            moment_min_eigenvalue: DEFAULT_MIN_EIGENVALUE,
            fit: Fit::Linear,
            stabilisation: 0.0,
        }
    }
}

/// Kinetic and potential energies of the body.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Energy {
    /// `Σ ½ m v²`.
    pub kinetic: f64,
    /// `U = Σ V ψ(F)`, the potential of eq 1 (plus the contact potential when contact is on).
    pub strain: f64,
    /// The stabilisation potential `U_s` ([`crate::stabilisation`]; 0 when off).
    #[serde(default)]
    pub stabilisation: f64,
}

impl Energy {
    /// The potential energy: strain (and contact) plus stabilisation.
    pub fn potential(&self) -> f64 {
        self.strain + self.stabilisation
    }

    /// Kinetic plus potential energy (the Hamiltonian of a free body).
    pub fn total(&self) -> f64 {
        self.kinetic + self.potential()
    }
}

/// Hamiltonian MPS solver for one body. See the crate documentation.
pub struct MpsSolver<D: Dim, M: Material<D>> {
    /// The materials (one for a solver built by [`MpsSolver::new`]).
    materials: Vec<M>,
    /// Index into `materials` per particle.
    material: Vec<u16>,
    params: MpsParams,
    dp: f64,
    re: f64,
    /// The largest sound speed of the materials: the time step's.
    sound_speed: f64,
    // Reference configuration (never changes).
    reference: Vec<D::Vector>,
    volumes: Vec<f64>,
    masses: Vec<f64>,
    inv_masses: Vec<f64>,
    list: NeighborList,
    /// The gradient vectors `g_ij` of `F_i = Σ_j x_ij ⊗ g_ij` per pair (see [`crate::wls`]).
    g: Vec<D::Vector>,
    /// `g_ji` of pair `(i, j)`, in `i`'s list order.
    g_rev: Vec<D::Vector>,
    /// `A_i⁻¹` (eq 5, guarded).
    a_inv: Vec<D::Matrix>,
    guarded: usize,
    /// The eq 6 weight `w_ij` of every pair, in list order (the disorder indicator's and the
    /// surface normals' weights).
    ref_weights: Vec<f64>,
    // State.
    positions: Vec<D::Vector>,
    velocities: Vec<D::Vector>,
    deformation: Vec<D::Matrix>,
    /// `T_i = V_i P_i` (eq 7; minus the stabilisation's `Q_i` when it is on).
    stress_term: Vec<D::Matrix>,
    forces: Vec<D::Vector>,
    accelerations: Vec<D::Vector>,
    scratch: Vec<D::Vector>,
    // Scene.
    constraints: Constraints<D>,
    loads: Loads<D>,
    pressures: Vec<ResolvedPressure<D>>,
    contact: Option<ResolvedContact>,
    contact_energy: f64,
    stabilisation: Option<Stabilisation<D>>,
    stabilisation_energy: f64,
    /// Rigid tools in kinematic contact (with friction where a tool has it), and the particles
    /// they may move (those no constraint holds).
    tools: ToolSet<D>,
    free: Vec<bool>,
    probes: Vec<Probe<D>>,
    schedule: ProbeSchedule,
    time: f64,
    steps: u64,
    /// This rank's share of a distributed run (`None` on one process; see [`distribute`]).
    domain: Option<Arc<sph_core::distributed::Domain>>,
}

impl<D: Dim, M: Material<D>> MpsSolver<D, M> {
    /// Attaches the constraints (velocities at the kicks, accelerations after each force
    /// evaluation).
    pub fn with_constraints(mut self, constraints: Constraints<D>) -> Self {
        self.free = constraints.free_mask(self.len());
        self.constraints = constraints;
        self.refresh();
        self
    }

    /// Attaches body accelerations and point forces.
    pub fn with_loads(mut self, loads: Loads<D>) -> Self {
        self.loads = loads;
        self.refresh();
        self
    }

    /// Adds a follower surface pressure (see [`sph_core::pressure`]); normals left `None` are
    /// estimated from the reference neighbourhood.
    ///
    /// # Errors
    /// Particle indices outside the body, normals or areas of the wrong length, zero or
    /// non-finite normals, non-positive areas, or an interior particle with estimated normals.
    pub fn with_surface_pressure(mut self, sp: SurfacePressure<D>) -> Result<Self, Error> {
        let (list, weights, x0) = (&self.list, &self.ref_weights, &self.reference);
        let resolved = ResolvedPressure::resolve(sp, self.len(), self.dp, |i| {
            // Σ_j w_ij (X_j − X_i), summed as `e (−r w)` with `e = −(X_j − X_i)/r`.
            list.range(i)
                .zip(list.neighbors(i))
                .fold(D::zero(), |s, (k, &j)| {
                    let x = x0[j as usize] - x0[i];
                    let r = D::norm(x);
                    s + x * (-1.0 / r) * (-r * weights[k])
                })
        })?;
        self.pressures.push(resolved);
        self.refresh();
        Ok(self)
    }

    /// Attaches probes, recorded at `t = 0` and then every `interval` of simulated time
    /// (0 = every step).
    ///
    /// # Errors
    /// Probes that [`sph_core::scene::check_probes`] refuses; a negative or non-finite
    /// `interval`.
    pub fn with_probes(mut self, probes: Vec<Probe<D>>, interval: f64) -> Result<Self, Error> {
        sph_core::scene::check_probes(&probes)?;
        self.schedule = ProbeSchedule::every(interval)?;
        self.probes = probes;
        if self.schedule.due(self.time) {
            self.record_probes();
        }
        Ok(self)
    }

    /// Replaces the current positions `x` and velocities `v` (`F`, forces and accelerations are
    /// recomputed from them). For tests and for starting from a pre-deformed state.
    ///
    /// # Errors
    /// Wrong lengths or non-finite values.
    pub fn set_configuration(&mut self, x: Vec<D::Vector>, v: Vec<D::Vector>) -> Result<(), Error> {
        let n = self.len();
        if x.len() != n || v.len() != n {
            return Err(Error::invalid(
                "configuration",
                format!("{} positions, {} velocities", x.len(), v.len()),
                &format!("{n} of each"),
            ));
        }
        if let Some(i) = first_non_finite::<D>(&x).or(first_non_finite::<D>(&v)) {
            return Err(Error::invalid(
                "configuration",
                format!("non-finite value at particle {i}"),
                "finite",
            ));
        }
        self.positions = x;
        self.velocities = v;
        self.refresh();
        Ok(())
    }

    /// After a state or scene change: velocity constraints, then `F`, forces and accelerations.
    fn refresh(&mut self) {
        self.constraints
            .apply_to_velocities(self.time, &mut self.velocities);
        self.compute_accelerations();
    }

    /// `F` (eq 4) and the internal forces (eq 7, with the stabilisation's when on) of the
    /// current positions.
    fn compute_forces(&mut self) {
        wls::deformation_and_stress::<D, M>(
            (&self.materials, &self.material),
            &self.list,
            &self.g,
            &self.volumes,
            &self.positions,
            &mut self.deformation,
            &mut self.stress_term,
        );
        if let Some(d) = &self.domain {
            // Halo layer 2 has no neighbour rows here: `F` and `T` of the identity, which no
            // owned particle reads (its forces are its owner's).
            for ((f, t), &complete) in self
                .deformation
                .iter_mut()
                .zip(&mut self.stress_term)
                .zip(d.complete())
            {
                if !complete {
                    (*f, *t) = (D::identity(), D::zero_matrix());
                }
            }
        }
        if let Some(st) = &self.stabilisation {
            self.stabilisation_energy = st.add_stress_terms(
                &self.list,
                &self.positions,
                &self.deformation,
                &mut self.stress_term,
            );
        }
        wls::internal_forces::<D>(
            &self.list,
            &self.g,
            &self.g_rev,
            &self.stress_term,
            &mut self.forces,
        );
        if let Some(st) = &self.stabilisation {
            st.pair_forces(
                &self.list,
                &self.positions,
                &self.deformation,
                &mut self.forces,
            );
        }
        if let Some(c) = &self.contact {
            // Positions are finite here (checked after every step), so the search cannot fail;
            // a failure would surface as NaN energy.
            self.contact_energy = c
                .add_forces::<D>(&self.positions, &mut self.forces)
                .unwrap_or(f64::NAN);
        }
    }

    /// Accelerations at the current positions and time: internal forces, surface pressure and
    /// loads, then the constraints.
    fn compute_accelerations(&mut self) {
        self.compute_forces();
        for ((a, &f), &im) in self
            .accelerations
            .iter_mut()
            .zip(&self.forces)
            .zip(&self.inv_masses)
        {
            *a = f * im;
        }
        let inv_masses = &self.inv_masses;
        for sp in &self.pressures {
            sp.add_accelerations(
                self.time,
                &self.deformation,
                |i| inv_masses[i],
                &mut self.accelerations,
            );
        }
        if !self.loads.is_empty() {
            self.loads
                .add_accelerations(self.time, &self.masses, &mut self.accelerations);
        }
        self.constraints
            .apply_to_accelerations(&mut self.accelerations);
    }

    /// The internal forces `f_i = −∂U/∂x_i` (eq 7 times `m_i`; `U` includes the stabilisation
    /// potential when it is on) of the current positions,
    /// without pressure, loads or constraints. For tests and diagnostics; does not change the
    /// state.
    pub fn evaluate_forces(&mut self) -> &[D::Vector] {
        self.compute_forces();
        &self.forces
    }

    /// The internal accelerations `f_i / m_i` (eq 7) of the current positions, without
    /// pressure, loads or constraints. For tests and diagnostics; does not change the state.
    pub fn evaluate_accelerations(&mut self) -> &[D::Vector] {
        self.compute_forces();
        for ((a, &f), &im) in self
            .scratch
            .iter_mut()
            .zip(&self.forces)
            .zip(&self.inv_masses)
        {
            *a = f * im;
        }
        &self.scratch
    }

    // The per-particle updates below are memory-bound streams; they run on the calling thread
    // (a rayon hand-off costs more than they do below ~10⁵ particles).
    fn kick(&mut self, h: f64) {
        for (v, &a) in self.velocities.iter_mut().zip(&self.accelerations) {
            *v += a * h;
        }
    }

    fn drift(&mut self, h: f64) {
        for (x, &v) in self.positions.iter_mut().zip(&self.velocities) {
            *x += v * h;
        }
    }

    fn damp(&mut self, h: f64) {
        if self.params.damping > 0.0 {
            let factor = (-self.params.damping * h).exp();
            self.velocities.iter_mut().for_each(|v| *v *= factor);
        }
    }

    fn record_probes(&mut self) {
        for p in &mut self.probes {
            p.record(self.time, &self.positions, &self.velocities);
        }
        if !self.tools.is_empty() {
            self.tools.record(self.time);
        }
    }

    /// Contact with the rigid tools (see [`MpsSolver::with_tools`]) after a kick: the velocity
    /// now drifts the particles for `lookahead` before the next kick, with the tools where they
    /// will be at `t_end`. Contact offset: the deformed half cell `(l0/2)|Fᵀn|`.
    fn enforce_tool_contact(&mut self, t_end: f64, lookahead: f64, dt: f64) {
        let (half_dp, deformation) = (0.5 * self.dp, &self.deformation);
        let offset = |i: usize, n: D::Vector| half_dp * D::norm(D::transpose(deformation[i]) * n);
        // |Fᵀ n| ≤ ‖F‖_F bounds every particle's offset factor.
        let stretch =
            sph_core::parallel::max_over(deformation.len(), 1.0, |i| D::frobenius(deformation[i]));
        self.tools.begin_step();
        self.tools.enforce(
            t_end,
            lookahead,
            offset,
            half_dp * stretch,
            &self.positions,
            &mut self.velocities,
            &self.masses,
            &self.free,
            true,
        );
        self.tools.end_step(dt);
    }

    /// `C · min(l0/(c + |v|max), √(l0/|a|max))`: what a CFL criterion on the current state
    /// would allow (the blow-up guard of `step`; NaN if a speed or acceleration is NaN).
    fn state_dt(&self) -> f64 {
        let max = |v: &[D::Vector]| {
            let local = sph_core::parallel::fold_chunks(
                v.len(),
                #[inline(always)]
                |rows| diagnostics::max_norm_squared_or_nan::<D>(&v[rows]),
            )
            .into_iter()
            .fold(0.0, diagnostics::max_or_nan)
            .sqrt();
            self.domain.max_or_nan_over_ranks(local)
        };
        let (speed, accel) = (max(&self.velocities), max(&self.accelerations));
        let acoustic = self.dp / (self.sound_speed + speed);
        let force = if accel > 0.0 || accel.is_nan() {
            (self.dp / accel).sqrt()
        } else {
            f64::INFINITY
        };
        self.params.courant * acoustic.min(force)
    }

    fn check_finite(&self) -> Result<(), Error> {
        diagnostics::check_state::<D>(
            &self.positions,
            &self.velocities,
            ("deformation gradient", &self.deformation),
            &[("acceleration", &self.accelerations)],
            self.steps,
            self.time,
        )
    }

    /// The numerical parameters.
    pub fn params(&self) -> &MpsParams {
        &self.params
    }

    /// The first material (the only one of a solver built by [`MpsSolver::new`]).
    pub fn material(&self) -> &M {
        &self.materials[0]
    }

    /// The materials ([`MpsSolver::with_materials`]).
    pub fn materials(&self) -> &[M] {
        &self.materials
    }

    /// The material index of each particle.
    pub fn material_ids(&self) -> &[u16] {
        &self.material
    }

    /// Particle `i`'s material.
    #[inline(always)]
    fn material_of(&self, i: usize) -> &M {
        &self.materials[self.material[i] as usize]
    }

    /// The initial spacing `l0`.
    pub fn spacing(&self) -> f64 {
        self.dp
    }

    /// The weight radius `r_e` of eq 6.
    pub fn re(&self) -> f64 {
        self.re
    }

    /// The reference configuration `X`.
    pub fn reference_positions(&self) -> &[D::Vector] {
        &self.reference
    }

    /// Reference volumes.
    pub fn volumes(&self) -> &[f64] {
        &self.volumes
    }

    /// Particle masses `ρ0 V`.
    pub fn masses(&self) -> &[f64] {
        &self.masses
    }

    /// The neighbour list (reference configuration, `|X_ij| < r_e`).
    pub fn neighbors(&self) -> &NeighborList {
        &self.list
    }

    /// `A_i⁻¹` of eq 5 (guarded).
    pub fn moment_inverses(&self) -> &[D::Matrix] {
        &self.a_inv
    }

    /// How many particles needed the guard of `A_i` (or, with the quadratic fit, fell back to
    /// the linear one).
    pub fn guarded_particles(&self) -> usize {
        self.guarded
    }

    /// Deformation gradients (eq 4) of the current positions.
    pub fn deformation_gradients(&self) -> &[D::Matrix] {
        &self.deformation
    }

    /// Internal forces of the current positions (eq 7 times `m`).
    pub fn forces(&self) -> &[D::Vector] {
        &self.forces
    }

    /// Accelerations of the current state (internal, pressure, loads; constrained).
    pub fn accelerations(&self) -> &[D::Vector] {
        &self.accelerations
    }

    /// Adds penalty contact between the bodies of this solver (see [`crate::contact`]); each
    /// body's stiffness is that of the softest material among its particles.
    ///
    /// # Errors
    /// A `body_of` of the wrong length, a non-positive distance or stiffness factor, or two
    /// bodies closer than `r_e` at `t = 0` (their particles would share reference neighbours:
    /// bonded, not in contact).
    pub fn with_contact(mut self, contact: Contact) -> Result<Self, Error> {
        let n = self.len();
        let bodies = contact
            .body_of
            .iter()
            .map(|&b| b as usize + 1)
            .max()
            .unwrap_or(0);
        let mut youngs = vec![f64::INFINITY; bodies];
        if contact.body_of.len() == n {
            for (i, &b) in contact.body_of.iter().enumerate() {
                let e = Material::<D>::constants(self.material_of(i)).youngs_modulus;
                youngs[b as usize] = youngs[b as usize].min(e);
            }
        }
        let resolved = ResolvedContact::new::<D>(contact, n, self.dp, &youngs)?;
        // The WLS kinematics join the particles of the reference neighbour list for good:
        // bodies that close would be bonded, not in contact.
        let body = &resolved.body_of;
        if let Some((i, j)) = (0..n).find_map(|i| {
            self.list
                .neighbors(i)
                .iter()
                .find(|&&j| body[j as usize] != body[i])
                .map(|&j| (i, j))
        }) {
            return Err(Error::invalid(
                "contact.body_of",
                format!(
                    "particles {i} (body {}) and {j} (body {}) are reference neighbours",
                    body[i], body[j as usize]
                ),
                &format!(
                    "bodies at least r_e = {} dp apart at t = 0 (closer particles of two \
                     bodies would be bonded by the reference neighbour list, not in contact)",
                    self.params.re_over_l0
                ),
            ));
        }
        self.contact = Some(resolved);
        self.refresh();
        Ok(self)
    }

    /// Attaches rigid tools in kinematic contact with the body, frictionless or with Coulomb
    /// friction ([`sph_core::tool`], [`sph_core::friction`]): applied once per step to the
    /// velocity that drifts the particles over the step (velocity Verlet: after the first
    /// half-kick, from `x^n` to the tools at `t^{n+1}`; symplectic Euler: after the kick, from
    /// `x^{n+1}` to `t^{n+2}`), with the contact offset of the deformed half cell. Each tool
    /// records its series `/series/<name>` with the probes, and the summary the tools' work
    /// (`tool_contact_work`, `friction_work`, `friction_dissipated`).
    ///
    /// # Errors
    /// As [`ToolSet::new`]: a tool name that is not a name or is used twice, a tool at or above
    /// the sound speed.
    pub fn with_tools(mut self, tools: Vec<RigidTool<D>>) -> Result<Self, Error> {
        // A tool must be slower than sound in the softest material it may touch.
        let c_min = self
            .materials
            .iter()
            .map(|m| m.constants().sound_speed)
            .fold(f64::INFINITY, f64::min);
        let mut set = ToolSet::new(tools, &[], c_min)?;
        set.reset_series(self.time);
        self.tools = set;
        Ok(self)
    }
}

impl<D: Dim, M: Material<D>> Solver<D> for MpsSolver<D, M> {
    fn method(&self) -> &'static str {
        "mps"
    }

    /// Blow-up guard: the step stays C l0/c (the paper's), but the one a CFL criterion on the
    /// current |v| and |a| would allow must stay above MIN_DT_RATIO of it (as TL's eq 33).
    fn check_time_step(&self) -> Result<(), Error> {
        let floor = diagnostics::MIN_DT_RATIO * self.stable_dt();
        diagnostics::check_time_step(self.state_dt(), floor, self.steps, self.time)
    }

    /// One symplectic step of `Δt = min(C l0 / c, max_dt)` (see [`Integrator`]).
    fn step(&mut self, max_dt: f64) -> Result<StepInfo, Error> {
        self.check_time_step()?;
        if max_dt.is_nan() || max_dt <= 0.0 {
            return Err(Error::invalid("max_dt", max_dt, "> 0"));
        }
        let dt = self.stable_dt().min(max_dt);
        let half = 0.5 * dt;
        match self.params.integrator {
            Integrator::VelocityVerlet => {
                // Kick with a(x^n, t^n) (kept from the previous step), drift, forces at
                // x^{n+1}, kick.
                self.damp(half);
                self.kick(half);
                self.constraints
                    .apply_to_velocities(self.time + half, &mut self.velocities);
                if !self.tools.is_empty() {
                    self.enforce_tool_contact(self.time + dt, dt, dt);
                }
                self.drift(dt);
                self.time += dt;
                self.compute_accelerations();
                self.kick(half);
                self.constraints
                    .apply_to_velocities(self.time, &mut self.velocities);
                self.damp(half);
            }
            Integrator::SymplecticEuler => {
                // Eq 8: x^{n+1} = x^n + Δt v^n; v^{n+1} = v^n + Δt a(x^{n+1}).
                self.damp(half);
                self.drift(dt);
                self.time += dt;
                self.compute_accelerations();
                self.kick(dt);
                self.constraints
                    .apply_to_velocities(self.time, &mut self.velocities);
                if !self.tools.is_empty() {
                    self.enforce_tool_contact(self.time + dt, dt, dt);
                }
                self.damp(half);
            }
        }
        self.steps += 1;
        self.exchange_halo();
        self.domain.agree(self.check_finite())?;
        if !(self.probes.is_empty() && self.tools.is_empty()) && self.schedule.due(self.time) {
            self.record_probes();
        }
        Ok(StepInfo {
            dt,
            time: self.time,
            step: self.steps,
        })
    }

    /// `Δt = C l0 / c`, `c = √(K/ρ0)` (constant).
    fn stable_dt(&self) -> f64 {
        self.params.courant * self.dp / self.sound_speed
    }

    /// The state: `x`, `v`, and what the force evaluation left for the next step (`F`,
    /// `G_i`, forces, accelerations, the contact energy), time, steps and probe records.
    fn save_state(&self, out: &mut StateWriter) -> Result<(), Error> {
        out.vectors::<D>("positions", &self.positions);
        out.vectors::<D>("velocities", &self.velocities);
        out.matrices::<D>("deformation", &self.deformation);
        out.matrices::<D>("stress_term", &self.stress_term);
        out.vectors::<D>("forces", &self.forces);
        out.vectors::<D>("accelerations", &self.accelerations);
        out.f64s(
            "scalars",
            &[self.time, self.contact_energy, self.schedule.next()],
        );
        out.u64s("steps", &[self.steps]);
        save_probes(out, &self.probes);
        self.tools.save(out);
        Ok(())
    }

    fn restore_state(&mut self, input: &mut StateReader<'_>) -> Result<(), Error> {
        let n = Some(self.positions.len());
        self.positions = input.vectors::<D>("positions", n)?;
        self.velocities = input.vectors::<D>("velocities", n)?;
        self.deformation = input.matrices::<D>("deformation", n)?;
        self.stress_term = input.matrices::<D>("stress_term", n)?;
        self.forces = input.vectors::<D>("forces", n)?;
        self.accelerations = input.vectors::<D>("accelerations", n)?;
        let [time, contact_energy, next_probe] = input.scalars::<3>("scalars")?;
        (self.time, self.contact_energy) = (time, contact_energy);
        self.schedule.set_next(next_probe);
        self.steps = input.u64s("steps", Some(1))?[0];
        restore_probes(input, &mut self.probes)?;
        self.tools.restore(input)?;
        self.check_finite()
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
        names
    }

    /// The deformation fields, `von_mises`, `disorder`; `body` (the body id of
    /// [`MpsSolver::with_contact`], 0 without) and `material` (the index into
    /// [`MpsSolver::materials`]).
    fn field(&self, name: &str) -> Option<Field<D>> {
        match name {
            "von_mises" => Some(Field::Scalar(
                self.deformation
                    .par_iter()
                    .enumerate()
                    .map(|(i, &f)| von_mises(self.material_of(i).cauchy_stress_3d(f)))
                    .collect(),
            )),
            "disorder" => Some(Field::Scalar(self.disorder())),
            "body" => Some(Field::Scalar(match &self.contact {
                Some(c) => c.body_of.iter().map(|&b| f64::from(b)).collect(),
                None => vec![0.0; self.len()],
            })),
            "material" => Some(Field::Scalar(
                self.material.iter().map(|&m| f64::from(m)).collect(),
            )),
            "density" if self.materials.len() > 1 => Some(Field::Scalar(
                self.deformation
                    .iter()
                    .enumerate()
                    .map(|(i, &f)| {
                        Material::<D>::constants(self.material_of(i)).density / D::det(f)
                    })
                    .collect(),
            )),
            _ => deformation_field::<D>(
                name,
                &self.positions,
                &self.reference,
                &self.velocities,
                &self.deformation,
                Material::<D>::constants(&self.materials[0]).density,
            ),
        }
    }

    fn probes(&self) -> &[Probe<D>] {
        &self.probes
    }

    fn energies(&self) -> Option<(f64, f64)> {
        let e = self.energy();
        Some((e.kinetic, e.potential()))
    }

    fn momentum(&self) -> Option<glam::DVec3> {
        Some(D::to_vec3(self.linear_momentum()))
    }

    /// The tools' series.
    fn series(&self) -> Vec<sph_core::Series> {
        self.tools.series().to_vec()
    }

    /// The tools' work on the body (none without tools).
    fn figures(&self) -> Vec<(&'static str, f64)> {
        self.tools.figures()
    }
}
