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
//! the acoustic sub-steps of one advection step; the kernel data (`e_ij`, `r_ij`, `W`, `W′`) are
//! recomputed over that list from the half-step positions of every sub-step
//! ([`UlParams::refresh_kernel_data`], default; frozen too when off). Volumes `V_j = m_j/ρ_j` use
//! the current densities. Every pair term is antisymmetric in `(i, j)` at one instant, so linear
//! momentum is conserved to round-off by every variant.

use crate::artificial_stress::{self, ArtificialShear};
use crate::contact::Contact;
use crate::energy::{step_works, ul_budget, AccumulatedWork, Energy};
use crate::nested::{jaumann_rate, shear_energy, velocity_gradient_pair, NestedShear};
use crate::non_nested::{
    conservative_laplacian_pair, default_zeta, non_conservative_laplacian_pair,
    shear_acceleration_rate, AccumulatedShear, LaplacianForm,
};
use crate::riemann::{
    continuity_has_jump, continuity_jump, dissipative_pressure, pressure, pressure_energy,
    pressure_pair_factor, RiemannScheme,
};
use crate::shear::{Shear, ShearForce};
use crate::stepping::{acoustic_dt, advection_dt, next_substep, Stepping};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sph_core::correction::{correction_matrices, DEFAULT_MIN_EIGENVALUE};
use sph_core::diagnostics;
use sph_core::disorder::{affine_fit, disorder_indicator, ReferenceWeights};
use sph_core::error::check_positive;
use sph_core::neighbor::{apply_permutation, invert_permutation};
use sph_core::pairs::{fill_pair_kernels, PairSymmetry};
use sph_core::scene::ProbeSchedule;
use sph_core::solver::first_non_finite;
use sph_core::state::{
    restore_probes, restore_series, save_probes, save_series, StateReader, StateWriter,
};
use sph_core::{
    Body, CellGrid, Constraints, Dim, EnergyBudget, Error, Field, Kernel, Loads, NeighborList,
    PairKernel, Probe, Series, Solver, StepInfo, WendlandC2,
};
use sph_materials::{von_mises, ElasticConstants};

/// Numerical parameters (defaults: UL paper §5–6).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct UlParams {
    /// Smoothing length over particle spacing (1.3; cut-off 2h = 2.6 dp).
    pub h_over_dp: f64,
    /// Dual (default) or single-criterion time stepping.
    pub stepping: Stepping,
    /// `CFL_ad` of eq 21 (0.2).
    pub cfl_advection: f64,
    /// `CFL_ac` of eq 22 (0.4).
    pub cfl_acoustic: f64,
    /// Floor of `|v|max` in eq 21, as a fraction of `c0` (0.01: at most `20 h/c0`, i.e. 50
    /// acoustic sub-steps, per advection step for a body nearly at rest).
    pub speed_floor: f64,
    /// Riemann solver form (default: SPHinXsys's solid tests, β = 1 and no pressure jump; see
    /// [`RiemannScheme`]).
    pub riemann: RiemannScheme,
    /// Correct the velocity gradient with `B` (eq 26) in OG/OAS too. Default false: the paper's
    /// eq 14 has none, and only the uncorrected gradient makes the OG pair (eq 13–14)
    /// energy-consistent (`Σ V τ:L` cancels the shear power exactly; measured: with `B` a free
    /// block gains 5% energy in 10 ms, without it never gains). ENOG's output stress always
    /// uses `B` (eq 26).
    pub corrected_velocity_gradient: bool,
    /// ENOG: integrate the shear stress for output (eq 6–8 with eq 26; it never feeds back into
    /// the motion). Off saves one matrix per pair per sub-step (a quarter of the 2D plate's
    /// time); `von_mises` then shows the pressure part only and the energy budget uses the
    /// exact shear work instead of the estimate from `τ`. The `sph` cases and scene files turn
    /// it on exactly when snapshots are written.
    pub track_shear_stress: bool,
    /// Reorder particles in cell order at rebuilds (cache locality; default true).
    pub reorder: bool,
    /// Recompute the pair kernel data (`e_ij`, `r_ij`, `W`, `W′`) from the half-step positions
    /// in every acoustic sub-step, over the neighbour list of the last rebuild (the list, the
    /// cell list and `B` stay those of the rebuild). Default **on**. Off is docs/methods.md's scheme
    /// (the data of the rebuild serve the whole advection step), which makes the 2D plate
    /// (ENOG, H/dp = 10, v_f = 0.05) soften secularly: its period grows 0.278 → 0.298 s within
    /// 3 s and 0.277 → 0.366 s within 10 s, the amplitude growing with it; with the refresh the
    /// period stays 0.2749–0.2756 s over 3 s (0.2754 → 0.2741 s over 10 s). Cost, measured by
    /// `ul-stepping` (docs/performance.md): 1.4–1.6× the time per sub-step of the frozen data;
    /// dual stepping stays 2.2–2.7× faster than single.
    pub refresh_kernel_data: bool,
    /// Guard threshold of the correction matrix (see `sph_core::correction`).
    pub correction_min_eigenvalue: f64,
    /// Let particles that lose every neighbour (numerical fracture) fly on ballistically,
    /// counting them ([`UlSolver::isolated_max`]), instead of stopping with
    /// `Error::LostNeighbours` (default false).
    pub allow_isolated: bool,
    /// Scale `κ` of the contact pressure between bodies, `p_c = κ c0² ρ_c` (1: docs/methods.md; see
    /// [`crate::contact`]). Only used with [`UlSolver::with_contact`].
    pub contact_scale: f64,
    /// Keep the energy budget ([`UlSolver::energy_budget`]): the force gather also sums the
    /// dissipative part of the Riemann pressure (and OAS's artificial stress) per particle,
    /// and every acoustic step accumulates the work of those parts, of contact, of ENOG's
    /// `A_s` and of loads (default true). Measured cost (CPU time, one thread, median of 3,
    /// taken on a loaded machine): +7 % on the 2D rings with ENOG (`sph run colliding-rings-2d
    /// --method ul-enog --threads 1 --set end_time=0.01 --set energy_budget=true|false`),
    /// +2 % on the 3D balls with OG (`colliding-balls-3d --method ul-og --set dp=0.0025
    /// --set end_time=0.002`).
    pub energy_budget: bool,
}

impl Default for UlParams {
    fn default() -> Self {
        Self {
            h_over_dp: 1.3,
            stepping: Stepping::Dual,
            cfl_advection: 0.2,
            cfl_acoustic: 0.4,
            speed_floor: 0.01,
            riemann: RiemannScheme::SphinxsysTests,
            corrected_velocity_gradient: false,
            track_shear_stress: true,
            reorder: true,
            correction_min_eigenvalue: DEFAULT_MIN_EIGENVALUE,
            allow_isolated: false,
            refresh_kernel_data: true,
            contact_scale: 1.0,
            energy_budget: true,
        }
    }
}

/// Variant data resolved at construction.
#[derive(Clone, Copy, Debug)]
enum Variant {
    Original,
    Artificial { epsilon: f64, n: u32, inv_w_dp: f64 },
    NonNested { factor: f64, form: LaplacianForm },
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
    constants: ElasticConstants,
    shear: Shear,
    variant: Variant,
    params: UlParams,
    kernel: WendlandC2<D>,
    rho0: f64,
    c0: f64,
    g: f64,
    /// Whether `τ` is integrated (OG, OAS; ENOG with `track_shear_stress`).
    tracks_stress: bool,
    // Per-particle state (current order).
    positions: Vec<D::Vector>,
    velocities: Vec<D::Vector>,
    densities: Vec<f64>,
    masses: Vec<f64>,
    /// Shear stress `τ` (empty if not tracked).
    stress: Vec<D::Matrix>,
    /// ENOG accumulated shear acceleration `A_s` (empty otherwise).
    accumulated: Vec<D::Vector>,
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
    /// Contact force on each body, recorded with the probes.
    series: Vec<Series>,
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
    /// Builds the solver: validates the input, sorts the particles in cell order, builds the
    /// neighbour list, kernel data and correction matrices, and the initial rates.
    ///
    /// # Errors
    /// Empty body, mismatched array lengths, non-positive `dp`/volumes/densities/parameters,
    /// non-finite positions or velocities, or a particle without neighbours
    /// ([`Error::TooFewNeighbours`]).
    pub fn new(
        body: impl Into<Body<D>>,
        constants: ElasticConstants,
        shear: Shear,
        params: UlParams,
    ) -> Result<Self, Error> {
        let body: Body<D> = body.into();
        body.validate("ul body")?;
        check_positive("h_over_dp", params.h_over_dp)?;
        check_positive("cfl_advection", params.cfl_advection)?;
        check_positive("cfl_acoustic", params.cfl_acoustic)?;
        check_positive("speed_floor", params.speed_floor)?;
        check_positive(
            "correction_min_eigenvalue",
            params.correction_min_eigenvalue,
        )?;
        check_positive("contact_scale", params.contact_scale)?;
        shear.validate()?;
        let n = body.len();
        check_per_particle("densities", &body.densities, n, true)?;
        let velocities = body.velocities_or_rest();
        let rho0 = constants.density;
        let kernel = WendlandC2::<D>::from_spacing(body.dp, params.h_over_dp)?;
        let variant = match shear {
            Shear::Original => Variant::Original,
            Shear::ArtificialStress { epsilon, n } => Variant::Artificial {
                epsilon,
                n,
                inv_w_dp: 1.0 / kernel.w(body.dp),
            },
            Shear::NonNested { zeta, form } => Variant::NonNested {
                factor: match form {
                    LaplacianForm::Conservative => zeta.unwrap_or(default_zeta(D::D)),
                    LaplacianForm::NonConservative => 1.0,
                },
                form,
            },
        };
        let tracks_stress =
            !matches!(variant, Variant::NonNested { .. }) || params.track_shear_stress;
        let densities = if body.densities.is_empty() {
            vec![rho0; n]
        } else {
            body.densities
        };
        let masses: Vec<f64> = body.volumes.iter().map(|v| v * rho0).collect();
        let mut solver = Self {
            constants,
            shear,
            variant,
            params,
            kernel,
            rho0,
            c0: constants.sound_speed,
            g: constants.shear_modulus,
            tracks_stress,
            initial_positions: body.positions.clone(),
            positions: body.positions,
            velocities,
            densities,
            masses,
            stress: if tracks_stress {
                vec![D::zero_matrix(); n]
            } else {
                Vec::new()
            },
            accumulated: if matches!(variant, Variant::NonNested { .. }) {
                vec![D::zero(); n]
            } else {
                Vec::new()
            },
            rates: vec![Rates::zero(); n],
            original_index: (0..n as u32).collect(),
            free: vec![true; n],
            list: NeighborList::default(),
            pairs: Vec::new(),
            halves: None,
            correction: vec![D::identity(); n],
            guarded: 0,
            rebuild_positions: Vec::new(),
            contact: None,
            series: Vec::new(),
            work: AccumulatedWork::default(),
            initial_total: 0.0,
            initial_momentum: D::zero(),
            constraint_impulse: D::zero(),
            budget_parts: if params.energy_budget {
                vec![[D::zero(); 2]; n]
            } else {
                Vec::new()
            },
            load_accelerations: Vec::new(),
            isolated: 0,
            isolated_max: 0,
            first_isolation: None,
            pressures: vec![0.0; n],
            current_volumes: vec![0.0; n],
            accelerations: vec![D::zero(); n],
            jump_work: Vec::new(),
            artificial: if matches!(variant, Variant::Artificial { .. }) {
                vec![D::zero_matrix(); n]
            } else {
                Vec::new()
            },
            volumes: vec![0.0; n],
            constraints: Constraints::new(),
            loads: Loads::new(),
            probes: Vec::new(),
            schedule: ProbeSchedule::every(0.0)?,
            time: 0.0,
            steps: 0,
            acoustic_steps: 0,
            pair_visits: 0,
            rebuilds: 0,
            max_speed: 0.0,
        };
        if let Err(e) = solver.rebuild() {
            return Err(match e {
                Error::LostNeighbours { particle, .. } => Error::TooFewNeighbours {
                    particle,
                    found: 0,
                    required: 1,
                },
                e => e,
            });
        }
        solver.refresh_rates();
        solver.reset_budget();
        Ok(solver)
    }

    /// Attaches the constraints. Particle indices refer to the body's **original** order (the
    /// order of [`Body::positions`]); they are remapped to the current order and at every
    /// reordering. Constrained particles are excluded from the time-step maxima.
    pub fn with_constraints(mut self, mut constraints: Constraints<D>) -> Self {
        constraints.remap(&self.inverse_index());
        self.free = constraints
            .prescribed_mask(self.len())
            .into_iter()
            .map(|c| !c)
            .collect();
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
    /// [`UlParams::contact_scale`]) — antisymmetric per pair, so momentum is conserved;
    /// repulsive only (bodies separate freely). The contact force on each body is recorded
    /// with the probes as the series `contact_force_<body>` with columns `x`, `y` (, `z`)
    /// ([`Solver::series`]).
    ///
    /// # Errors
    /// `body_of` not one entry per particle.
    pub fn with_contact(mut self, body_of: Vec<u32>) -> Result<Self, Error> {
        let n = self.len();
        if body_of.len() != n {
            return Err(Error::invalid(
                "body_of",
                body_of.len(),
                &format!("one body id per particle ({n})"),
            ));
        }
        let body = self
            .original_index
            .iter()
            .map(|&o| body_of[o as usize])
            .collect();
        let dp = self.kernel.h() / self.params.h_over_dp;
        let contact = Contact::new(body, self.kernel.w(dp), self.params.contact_scale, self.c0);
        self.series = (0..contact.bodies)
            .map(|b| Series::new(&format!("contact_force_{b}"), &AXES[..D::D]))
            .collect();
        self.contact = Some(contact);
        self.rebuild()?;
        self.refresh_rates();
        self.reset_budget();
        Ok(self)
    }

    /// Sets the budget's reference total to the current energies (while at `t = 0`).
    fn reset_budget(&mut self) {
        if self.steps == 0 {
            self.work = AccumulatedWork::default();
            self.initial_total = 0.0;
            self.initial_total = self.energy_budget_now().total();
            self.initial_momentum = self.linear_momentum();
            self.constraint_impulse = D::zero();
        }
    }

    /// Attaches probes (indices in the original order), recorded at `t = 0` and then every
    /// `interval` of simulated time (0 = every acoustic step), at the first acoustic sub-step
    /// that reaches each sample time (so the samples resolve times shorter than an advection
    /// step). The contact-force series are recorded on the same schedule.
    pub fn with_probes(mut self, mut probes: Vec<Probe<D>>, interval: f64) -> Result<Self, Error> {
        self.schedule = ProbeSchedule::every(interval)?;
        let inv = self.inverse_index();
        for p in &mut probes {
            p.remap(&inv);
        }
        self.probes = probes;
        for s in &mut self.series {
            *s = Series::new(&s.name, &AXES[..D::D]);
        }
        if self.schedule.due(self.time) {
            self.record_probes();
        }
        Ok(self)
    }

    /// `inv[original] = current`.
    fn inverse_index(&self) -> Vec<u32> {
        invert_permutation(&self.original_index)
    }

    /// Rebuild at the start of an advection step: cell list, reordering in cell order (applied
    /// to every per-particle field, constraints, loads and probes), neighbour list, frozen
    /// kernel data and the correction matrix `B` (eq 27).
    fn rebuild(&mut self) -> Result<(), Error> {
        let cutoff = self.kernel.cutoff();
        let mut grid = CellGrid::<D>::build(&self.positions, cutoff)?;
        if self.params.reorder {
            let perm = grid.cell_order();
            if perm.iter().enumerate().any(|(k, &o)| k as u32 != o) {
                let perm = perm.to_vec();
                self.permute(&perm);
                grid = CellGrid::<D>::build(&self.positions, cutoff)?;
            }
        }
        self.list = grid.neighbor_list(&self.positions, cutoff)?;
        if let Some(contact) = &mut self.contact {
            self.list = contact.split(&self.list)?;
        }
        let n = self.len();
        if let Some(i) = (0..n).find(|&i| self.list.count(i) == 0) {
            if !self.params.allow_isolated {
                return Err(Error::LostNeighbours {
                    particle: self.original_index[i] as usize,
                    step: self.steps,
                    time: self.time,
                });
            }
            self.first_isolation.get_or_insert(self.time);
        }
        self.isolated = 0;
        for i in 0..n {
            if self.list.count(i) == 0 {
                self.isolated += 1;
                // A particle without neighbours has no shear force: ENOG's never-reset
                // accumulator (eq 20) would otherwise keep pushing a fragment for ever.
                if let Some(a) = self.accumulated.get_mut(i) {
                    *a = D::zero();
                }
            }
        }
        self.isolated_max = self.isolated_max.max(self.isolated);
        let zero = PairKernel::<D> {
            e: D::zero(),
            r: 0.0,
            w: 0.0,
            dw: 0.0,
        };
        self.pairs.resize(self.list.num_pairs(), zero);
        self.halves = PairSymmetry::new(&self.list);
        self.refresh_pair_kernels();
        if let Some(k) = self.pairs.iter().position(|p| p.r <= 0.0) {
            let i = self.list.offsets().partition_point(|&o| o <= k) - 1;
            return Err(Error::invalid(
                "positions",
                format!(
                    "particle {} coincides with a neighbour",
                    self.original_index[i]
                ),
                "distinct positions",
            ));
        }
        self.volumes
            .iter_mut()
            .zip(&self.masses)
            .zip(&self.densities)
            .for_each(|((v, &m), &rho)| *v = m / rho);
        let corr = correction_matrices::<D>(
            &self.list,
            &self.pairs,
            &self.volumes,
            self.params.correction_min_eigenvalue,
        )?;
        self.correction = corr.matrices;
        self.guarded = corr.guarded;
        self.rebuild_positions.clear();
        self.rebuild_positions.extend_from_slice(&self.positions);
        self.rebuilds += 1;
        Ok(())
    }

    /// `pairs` from the current positions: each unordered pair computed once when the list
    /// has its two halves (always, for a self list), bit for bit the plain fill otherwise.
    fn refresh_pair_kernels(&mut self) {
        match &self.halves {
            Some(halves) => halves.fill(&self.positions, &self.list, &self.kernel, &mut self.pairs),
            None => fill_pair_kernels(
                &self.positions,
                &self.positions,
                &self.list,
                &self.kernel,
                &mut self.pairs,
            ),
        }
    }

    /// Applies `perm[new] = old` to every per-particle field and relabels the scene.
    fn permute(&mut self, perm: &[u32]) {
        fn p<T: Clone>(perm: &[u32], v: &mut Vec<T>) {
            if !v.is_empty() {
                *v = apply_permutation(perm, v);
            }
        }
        p(perm, &mut self.positions);
        p(perm, &mut self.velocities);
        p(perm, &mut self.densities);
        p(perm, &mut self.masses);
        p(perm, &mut self.stress);
        p(perm, &mut self.accumulated);
        p(perm, &mut self.rates);
        p(perm, &mut self.initial_positions);
        p(perm, &mut self.original_index);
        if let Some(c) = &mut self.contact {
            c.permute(perm);
        }
        p(perm, &mut self.free);
        p(perm, &mut self.accelerations);
        let inv = invert_permutation(perm);
        self.constraints.remap(&inv);
        self.loads.remap(&inv);
        for probe in &mut self.probes {
            probe.remap(&inv);
        }
    }

    /// Applies the velocity constraints and recomputes the rates and `|v|max` (after a state
    /// change).
    fn refresh_rates(&mut self) {
        self.constraints
            .apply_to_velocities(self.time, &mut self.velocities);
        self.update_pressures();
        self.max_speed = self.compute_rates(None);
    }

    /// Eq. (4) for every particle.
    fn update_pressures(&mut self) {
        let (rho0, c0) = (self.rho0, self.c0);
        let (rho, m) = (&self.densities, &self.masses);
        gather2(&mut self.pressures, &mut self.current_volumes, |i, p, v| {
            *p = pressure(rho[i], rho0, c0);
            *v = m[i] / rho[i];
        });
    }

    /// Step 4 of the module docs: continuity (eq 11), the Jaumann rate of `τ` (eq 6–8, 14/26)
    /// and the ENOG rate (eq 19–20), in one gather over the neighbours; returns `|v|max` over
    /// the free particles. With `drift = Some((h, dt))` the same pass then applies eq 25 to
    /// each particle with its new rates (`x += h v`, `ρ += h dρ/dt`, `τ += h dτ/dt`) and eq 20
    /// (`A_s += dt dA_s/dt`): no particle's rates read another's `x`, `ρ`, `τ` or `A_s`, so
    /// this is the same as a gather followed by those updates.
    fn compute_rates(&mut self, drift: Option<(f64, f64)>) -> f64 {
        let grad = self.tracks_stress;
        let corrected = self.params.corrected_velocity_gradient
            || matches!(self.variant, Variant::NonNested { .. });
        match self.variant {
            Variant::NonNested { factor, form } => match (grad, form) {
                (true, LaplacianForm::Conservative) => {
                    self.rates_with_jump::<true, 1>(corrected, factor, drift)
                }
                (true, LaplacianForm::NonConservative) => {
                    self.rates_with_jump::<true, 2>(corrected, factor, drift)
                }
                (false, LaplacianForm::Conservative) => {
                    self.rates_with_jump::<false, 1>(corrected, factor, drift)
                }
                (false, LaplacianForm::NonConservative) => {
                    self.rates_with_jump::<false, 2>(corrected, factor, drift)
                }
            },
            _ => self.rates_with_jump::<true, 0>(corrected, 0.0, drift),
        }
    }

    /// [`Self::rates_loop`] with or without the continuity equation's pressure jump: the
    /// solid schemes have none, and then the loop neither reads `p_j` nor multiplies zeros
    /// (the same bits: the skipped terms are all `±0` added to `+0`).
    fn rates_with_jump<const GRAD: bool, const LAP: u8>(
        &mut self,
        corrected: bool,
        factor: f64,
        drift: Option<(f64, f64)>,
    ) -> f64 {
        if continuity_has_jump(self.params.riemann) {
            self.rates_loop::<GRAD, LAP, true>(corrected, factor, drift)
        } else {
            self.rates_loop::<GRAD, LAP, false>(corrected, factor, drift)
        }
    }

    /// The gather of [`Self::compute_rates`]; `GRAD`: velocity gradient and Jaumann rate;
    /// `LAP`: 0 none, 1 eq 19, 2 eq 18; `JUMP`: the scheme's pressure jump in eq 11.
    fn rates_loop<const GRAD: bool, const LAP: u8, const JUMP: bool>(
        &mut self,
        corrected: bool,
        factor: f64,
        drift: Option<(f64, f64)>,
    ) -> f64 {
        let n = self.len();
        // The energy budget's volumetric work of the pressure jump over the drift, per
        // particle at its start (summed in index order below).
        let jump_work = drift.is_some()
            && self.params.energy_budget
            && self.params.riemann == RiemannScheme::Paper;
        self.jump_work.resize(if jump_work { n } else { 0 }, 0.0);
        let list = &self.list;
        let pairs = &self.pairs;
        let (x_v, vol, p, b, m, free) = (
            &self.velocities,
            &self.current_volumes,
            &self.pressures,
            &self.correction,
            &self.masses,
            &self.free,
        );
        let (g, rho0, c0, scheme) = (self.g, self.rho0, self.c0, self.params.riemann);
        let rho0_c0 = rho0 * c0;
        let columns = (
            &mut self.rates[..],
            &mut self.positions[..],
            &mut self.densities[..],
            // Empty when ENOG's output-only stress is not integrated.
            &mut self.stress[..],
            // ENOG only.
            &mut self.accumulated[..],
            &mut self.jump_work[..],
        );
        let max_norm2 = fold_columns(n, columns, |rows, (r, x, rho, tau, a_s, jw)| {
            let mut max_norm2 = 0.0;
            for (k, i) in rows.enumerate() {
                let out = &mut r[k];
                let (v_i, p_i, rho_i) = (x_v[i], p[i], rho[k]);
                let (mut drho, mut jump) = (0.0, 0.0);
                let mut l = D::zero_matrix();
                let mut lap = D::zero();
                for (pk, &j) in pairs[list.range(i)].iter().zip(list.neighbors(i)) {
                    let j = j as usize;
                    let v_j = vol[j];
                    let v_ij = v_i - x_v[j];
                    let u = D::dot(v_ij, pk.e);
                    drho += u * pk.dw * v_j;
                    if JUMP {
                        jump += continuity_jump(p_i, p[j], rho0_c0, scheme) * pk.dw * v_j;
                    }
                    if GRAD {
                        l += velocity_gradient_pair::<D>(v_ij, pk.e, pk.dw, v_j);
                    }
                    match LAP {
                        1 => lap += conservative_laplacian_pair::<D>(v_ij, pk.e, pk.r, pk.dw, v_j),
                        2 => lap += non_conservative_laplacian_pair::<D>(v_ij, pk.r, pk.dw, v_j),
                        _ => {}
                    }
                }
                // Eq 11: ρ_i Σ [u_ij + (p_i − p_j)/(ρ0 c0)] W′ V_j, the jump part kept apart.
                out.density = rho_i * (drho + jump);
                out.density_jump = rho_i * jump;
                if GRAD {
                    if corrected {
                        l = l * b[i];
                    }
                    out.stress = jaumann_rate::<D>(l, tau[k], g);
                }
                if LAP != 0 {
                    out.shear = shear_acceleration_rate::<D>(lap, factor, g, rho_i);
                }
                if let Some((h, dt)) = drift {
                    if !jw.is_empty() {
                        jw[k] =
                            m[i] * pressure(rho_i, rho0, c0) / (rho_i * rho_i) * out.density_jump;
                    }
                    x[k] += v_i * h;
                    rho[k] += out.density * h;
                    if !tau.is_empty() {
                        tau[k] += out.stress * h;
                    }
                    if !a_s.is_empty() {
                        a_s[k] += out.shear * dt;
                    }
                }
                let v2 = if free[i] { D::norm_squared(v_i) } else { 0.0 };
                max_norm2 = diagnostics::max_or_nan(max_norm2, v2);
            }
            max_norm2
        });
        if let Some((h, _)) = drift.filter(|_| jump_work) {
            self.work.density_jump += h * self.jump_work.iter().sum::<f64>();
        }
        max_norm2
            .into_iter()
            .fold(0.0, diagnostics::max_or_nan)
            .sqrt()
    }

    /// Internal accelerations of the current state (pressure from `ρ`; the variant's shear
    /// term) into `self.accelerations`: step 2 of the module docs without loads or
    /// constraints.
    fn compute_forces(&mut self) {
        let mut out = std::mem::take(&mut self.accelerations);
        let mut parts = std::mem::take(&mut self.budget_parts);
        match self.variant {
            Variant::Original => {
                self.forces_loop(NestedShear { tau: &self.stress }, &mut out, &mut parts)
            }
            Variant::Artificial {
                epsilon,
                n,
                inv_w_dp,
            } => {
                let (tau, p, rho) = (&self.stress, &self.pressures, &self.densities);
                gather(&mut self.artificial, |i, r| {
                    let sigma = tau[i] - D::identity() * p[i];
                    *r = artificial_stress::artificial_stress::<D>(sigma, rho[i], epsilon);
                });
                self.forces_loop(
                    ArtificialShear {
                        tau: &self.stress,
                        r: &self.artificial,
                        masses: &self.masses,
                        // With refreshed kernel data `W` is already the current one.
                        positions: (!self.params.refresh_kernel_data)
                            .then_some(&self.positions[..]),
                        kernel: &self.kernel,
                        inv_w_dp,
                        n,
                    },
                    &mut out,
                    &mut parts,
                );
            }
            Variant::NonNested { .. } => self.forces_loop(
                AccumulatedShear {
                    a_s: &self.accumulated,
                },
                &mut out,
                &mut parts,
            ),
        }
        self.budget_parts = parts;
        if let Some(contact) = &mut self.contact {
            contact.add_accelerations(
                &self.positions,
                &self.masses,
                &self.densities,
                &self.kernel,
                &mut out,
            );
        }
        self.accelerations = out;
    }

    /// The force gather: Riemann pressure (eq 12) plus the shear term `S`; with the energy
    /// budget also the dissipative part of the pressure and the artificial stress per particle.
    /// `parts` is empty when the budget is off.
    fn forces_loop<S: ShearForce<D>>(
        &self,
        shear: S,
        out: &mut [D::Vector],
        parts: &mut [[D::Vector; 2]],
    ) {
        if parts.is_empty() {
            gather(out, |i, a| *a = self.force_sum::<S, false>(&shear, i).0);
        } else {
            gather2(out, parts, |i, a, b| {
                (*a, *b) = self.force_sum::<S, true>(&shear, i);
            });
        }
    }

    /// `a_i` of [`Self::forces_loop`] and, with `BUDGET`, the Riemann-dissipation and
    /// artificial-stress parts of it.
    #[inline(always)]
    fn force_sum<S: ShearForce<D>, const BUDGET: bool>(
        &self,
        shear: &S,
        i: usize,
    ) -> (D::Vector, [D::Vector; 2]) {
        let (vel, rho, vol, p) = (
            &self.velocities,
            &self.densities,
            &self.current_volumes,
            &self.pressures,
        );
        let (rho0, c0, scheme) = (self.rho0, self.c0, self.params.riemann);
        let (v_i, p_i, inv_rho_i) = (vel[i], p[i], 1.0 / rho[i]);
        let mut acc = D::zero();
        let mut parts = [D::zero(); 2];
        for (pk, &j) in self.pairs[self.list.range(i)]
            .iter()
            .zip(self.list.neighbors(i))
        {
            let j = j as usize;
            let vj_rho_i = vol[j] * inv_rho_i;
            let u = D::dot(v_i - vel[j], pk.e);
            let p_diss = dissipative_pressure(u, rho0, c0, scheme);
            let p_star = 0.5 * (p_i + p[j]) + p_diss;
            acc += pk.e * pressure_pair_factor(p_star, pk.dw, vj_rho_i);
            let (elastic, artificial) = shear.pair(i, j, pk, vj_rho_i);
            acc += elastic + artificial;
            if BUDGET {
                parts[0] += pk.e * pressure_pair_factor(p_diss, pk.dw, vj_rho_i);
                parts[1] += artificial;
            }
        }
        (acc + shear.particle(i), parts)
    }

    /// Accelerations of the current state, without loads or constraints: the force evaluation
    /// of one acoustic step, exposed for tests and diagnostics.
    pub fn evaluate_accelerations(&mut self) -> &[D::Vector] {
        self.update_pressures();
        self.compute_forces();
        &self.accelerations
    }

    /// Density rates `dρ/dt` (eq 11) of the current state (allocates; for tests and
    /// diagnostics).
    pub fn evaluate_density_rates(&mut self) -> Vec<f64> {
        self.update_pressures();
        self.compute_rates(None);
        self.rates.iter().map(|r| r.density).collect()
    }

    /// One acoustic step of length `dt` (eq 23–25), see the module documentation.
    fn acoustic_step(&mut self, dt: f64) {
        let half = 0.5 * dt;
        // Eq 23 and 4: x, ρ (and τ) to the half step with the previous rates, p and V of the
        // new ρ.
        self.drift_and_pressures(half);
        if self.params.refresh_kernel_data {
            self.refresh_pair_kernels();
        }
        // Forces, loads, constraints.
        self.compute_forces();
        if !self.loads.is_empty() {
            if self.load_accelerations.is_empty() {
                self.loads.add_accelerations(
                    self.time + half,
                    &self.masses,
                    &mut self.accelerations,
                );
            } else {
                self.load_accelerations
                    .iter_mut()
                    .for_each(|a| *a = D::zero());
                self.loads.add_accelerations(
                    self.time + half,
                    &self.masses,
                    &mut self.load_accelerations,
                );
                self.accelerations
                    .iter_mut()
                    .zip(&self.load_accelerations)
                    .for_each(|(a, &l)| *a += l);
            }
        }
        if !self.constraints.is_empty() {
            let removed = self
                .constraints
                .apply_to_accelerations_removed_force(&mut self.accelerations, &self.masses);
            self.constraint_impulse += removed * dt;
        }
        if self.params.energy_budget {
            self.accumulate_work(dt);
        }
        // Eq 24.
        let acc = &self.accelerations;
        gather(&mut self.velocities, |i, v| *v += acc[i] * dt);
        self.time += dt;
        self.constraints
            .apply_to_velocities(self.time, &mut self.velocities);
        // Rates with v^{n+1}, then eq 25 and eq 20 (A_s accumulated, never reset; used by the
        // next step), in the same pass.
        self.max_speed = self.compute_rates(Some((half, dt)));
        self.acoustic_steps += 1;
        self.pair_visits +=
            (self.list.num_pairs() + self.contact.as_ref().map_or(0, |c| c.num_pairs())) as u64;
    }

    /// Adds the work of this step's force parts to the budget (before the kick; see
    /// [`crate::energy`]).
    fn accumulate_work(&mut self, dt: f64) {
        let (a, v, m) = (&self.accelerations, &self.velocities, &self.masses[..]);
        let (parts, a_s, loads) = (
            &self.budget_parts,
            &self.accumulated,
            &self.load_accelerations,
        );
        let contact = self.contact.as_ref().map(|c| &c.accelerations[..]);
        let or_zero = |x: &[D::Vector], i: usize| x.get(i).copied().unwrap_or(D::zero());
        let [riemann, artificial, contact, shear, loads] = step_works::<D, 5>(
            |i| {
                [
                    parts[i][0],
                    parts[i][1],
                    contact.map_or(D::zero(), |c| c[i]),
                    or_zero(a_s, i),
                    or_zero(loads, i),
                ]
            },
            a,
            v,
            m,
            dt,
        );
        self.work.riemann += riemann;
        self.work.artificial += artificial;
        self.work.contact += contact;
        self.work.shear += shear;
        self.work.loads += loads;
    }

    /// Eq 23: `x += h v`, `ρ += h dρ/dt`, `τ += h dτ/dt` with the rates of the last step, then
    /// eq 4 (`p` and `V = m/ρ` of the new `ρ`), element-wise in one pass on the team (the
    /// drift of the step's second half is part of [`Self::compute_rates`]).
    fn drift_and_pressures(&mut self, h: f64) {
        let (rho0, c0) = (self.rho0, self.c0);
        if self.params.energy_budget && self.params.riemann == RiemannScheme::Paper {
            // The volumetric-energy change the pressure jump makes over this drift
            // (Σ m p/ρ² ρ̇_jump h at the start of the drift).
            self.work.density_jump += h * self
                .densities
                .iter()
                .zip(&self.masses)
                .zip(&self.rates)
                .map(|((&rho, &m), r)| m * pressure(rho, rho0, c0) / (rho * rho) * r.density_jump)
                .sum::<f64>();
        }
        let (n, v, rates, m) = (self.len(), &self.velocities, &self.rates, &self.masses);
        let columns = (
            &mut self.positions[..],
            &mut self.densities[..],
            // Empty when ENOG's output-only stress is not integrated.
            &mut self.stress[..],
            &mut self.pressures[..],
            &mut self.current_volumes[..],
        );
        gather_columns(n, columns, |rows, (x, rho, tau, p, vol)| {
            for (k, i) in rows.enumerate() {
                x[k] += v[i] * h;
                rho[k] += rates[i].density * h;
                if !tau.is_empty() {
                    tau[k] += rates[i].stress * h;
                }
                p[k] = pressure(rho[k], rho0, c0);
                vol[k] = m[i] / rho[k];
            }
        });
    }

    fn record_if_due(&mut self) {
        if (!self.probes.is_empty() || !self.series.is_empty()) && self.schedule.due(self.time) {
            self.record_probes();
        }
    }

    fn record_probes(&mut self) {
        for p in &mut self.probes {
            p.record(self.time, &self.positions, &self.velocities);
        }
        if let Some(c) = &self.contact {
            for (s, f) in self.series.iter_mut().zip(c.body_forces(&self.masses)) {
                let row: Vec<f64> = (0..D::D).map(|k| D::component(f, k)).collect();
                s.push(self.time, &row);
            }
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
                jacobian: self.constants.density / self.densities[i],
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

    /// The elastic constants (`K`, `G`, `ρ0`, `c0 = √(K/ρ0)`, eq 5).
    pub fn constants(&self) -> &ElasticConstants {
        &self.constants
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

    /// Total linear momentum `Σ m v`.
    pub fn linear_momentum(&self) -> D::Vector {
        self.velocities
            .iter()
            .zip(&self.masses)
            .fold(D::zero(), |s, (&v, &m)| s + v * m)
    }

    /// The momentum balance `Σ m v − (Σ m v)(t = 0) + J_c`, with `J_c` the impulse the
    /// constraints removed (the supports' reaction): zero up to round-off for any scene without
    /// loads, since every internal and contact pair term is antisymmetric. (ENOG drops the
    /// accumulated `A_s` of a particle that loses all its neighbours, which breaks the balance
    /// by that particle's share.)
    pub fn momentum_balance(&self) -> D::Vector {
        self.linear_momentum() - self.initial_momentum + self.constraint_impulse
    }

    /// Total angular momentum `Σ m x × v` about the origin (3-vector; only `z` in 2D).
    pub fn angular_momentum(&self) -> glam::DVec3 {
        self.positions
            .iter()
            .zip(&self.velocities)
            .zip(&self.masses)
            .fold(glam::DVec3::ZERO, |s, ((&x, &v), &m)| {
                s + D::to_vec3(x).cross(D::to_vec3(v)) * m
            })
    }

    /// Kinetic, volumetric and shear energy.
    pub fn energy(&self) -> Energy {
        let kinetic = 0.5
            * self
                .velocities
                .iter()
                .zip(&self.masses)
                .map(|(&v, &m)| m * D::norm_squared(v))
                .sum::<f64>();
        let volumetric = self
            .densities
            .iter()
            .zip(&self.masses)
            .map(|(&rho, &m)| pressure_energy(m, rho, self.rho0, self.c0))
            .sum();
        let shear = if self.tracks_stress {
            self.stress
                .iter()
                .zip(&self.masses)
                .zip(&self.densities)
                .map(|((&t, &m), &rho)| shear_energy::<D>(t, m / rho, self.g))
                .sum()
        } else if self.params.energy_budget {
            // ENOG without its output-only τ: the energy stored by the shear acceleration is
            // the work done against it, which the budget accumulates exactly.
            -self.work.shear
        } else {
            // Neither τ nor the shear work is kept: not known (the summary shows null).
            f64::NAN
        };
        Energy {
            kinetic,
            volumetric,
            shear,
        }
    }

    /// Work accumulated since `t = 0` by the force parts the budget tracks (zero without
    /// [`UlParams::energy_budget`]).
    pub fn accumulated_work(&self) -> AccumulatedWork {
        self.work
    }

    /// The energy budget now (see [`crate::energy`]): meaningful with
    /// [`UlParams::energy_budget`] (otherwise the accumulated work stays zero).
    fn energy_budget_now(&self) -> EnergyBudget {
        let contact = self.contact.as_ref().map_or(0.0, |c| {
            c.energy(&self.positions, &self.masses, &self.kernel, self.rho0)
        });
        ul_budget(
            &self.energy(),
            contact,
            &self.work,
            matches!(self.variant, Variant::NonNested { .. }),
            self.tracks_stress,
            self.initial_total,
        )
    }

    /// The disorder indicator of docs/methods.md per particle (current order), accumulated since
    /// the start: Ganzenmüller's error of the weighted least-squares affine fit from the initial
    /// configuration to the current one, over the current neighbours with weights `W⁰` of the
    /// initial distances (neighbours that were not neighbours initially get `W⁰ = 0`).
    ///
    /// docs/methods.md suggests the fit over the last advection step for UL; that measures the
    /// non-affine *increment* of one step (≤ 3·10⁻⁴ on the plate whether or not it is ordered)
    /// and misses a zigzag pattern once it has formed, so the accumulated form is reported;
    /// [`UlSolver::disorder_increment`] gives the per-step form.
    pub fn disorder(&self) -> Vec<f64> {
        // Evaluated pair by pair: the initial configuration's kernel data of today's list
        // would be a whole pair list per monitor sample (127 MB for the 3D ball-plate).
        let reference = ReferenceWeights::Kernel(&self.kernel);
        let f = affine_fit::<D>(
            &self.list,
            reference,
            &self.initial_positions,
            &self.positions,
        );
        disorder_indicator::<D>(
            &self.list,
            reference,
            &self.initial_positions,
            &self.positions,
            &f,
        )
    }

    /// The per-step disorder indicator: the affine fit of the motion since the last rebuild
    /// (the last advection step for dual stepping, the last acoustic step for single stepping)
    /// over the neighbours of that rebuild (docs/methods.md's UL form).
    pub fn disorder_increment(&self) -> Vec<f64> {
        let f = affine_fit::<D>(
            &self.list,
            ReferenceWeights::Pairs(&self.pairs),
            &self.rebuild_positions,
            &self.positions,
        );
        disorder_indicator::<D>(
            &self.list,
            ReferenceWeights::Pairs(&self.pairs),
            &self.rebuild_positions,
            &self.positions,
            &f,
        )
    }

    /// Cauchy stress `σ = τ − p I` (3×3; the out-of-plane entry is `−p` in 2D).
    fn cauchy_3d(&self, i: usize) -> glam::DMat3 {
        let p = pressure(self.densities[i], self.rho0, self.c0);
        let tau = self.stress.get(i).copied().unwrap_or(D::zero_matrix());
        D::to_mat3(tau - D::identity() * p, -p)
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
        vec![
            ("acoustic_steps", self.acoustic_steps as f64),
            ("neighbour_rebuilds", self.rebuilds as f64),
            ("isolated_max", self.isolated_max as f64),
            ("momentum_balance", D::norm(self.momentum_balance())),
            (
                "first_isolation_time",
                self.first_isolation.unwrap_or(f64::NAN),
            ),
        ]
    }

    /// Dual stepping: one advection step of `min(Δt_ad, max_dt)` (eq 21): rebuild, then
    /// acoustic sub-steps (eq 22–25) until the advection step is filled exactly. Single
    /// stepping: rebuild, then one acoustic step of `min(Δt_ac, max_dt)`.
    fn step(&mut self, max_dt: f64) -> Result<StepInfo, Error> {
        // Blow-up guard (diagnostics::MIN_DT_RATIO of the acoustic step at rest), checked on
        // the advection step here and on every acoustic sub-step below.
        let floor = diagnostics::MIN_DT_RATIO
            * acoustic_dt(self.params.cfl_acoustic, self.kernel.h(), self.c0, 0.0);
        diagnostics::check_time_step(self.stable_dt(), floor, self.steps, self.time)?;
        if max_dt.is_nan() || max_dt <= 0.0 {
            return Err(Error::invalid("max_dt", max_dt, "> 0"));
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
        let index: Vec<u64> = self.original_index.iter().map(|&o| u64::from(o)).collect();
        out.u64s("original_index", &index);
        out.vectors::<D>("positions", &self.positions);
        out.vectors::<D>("velocities", &self.velocities);
        out.f64s("densities", &self.densities);
        out.matrices::<D>("stress", &self.stress);
        out.vectors::<D>("accumulated", &self.accumulated);
        let rate_density: Vec<f64> = self.rates.iter().map(|r| r.density).collect();
        let rate_stress: Vec<D::Matrix> = self.rates.iter().map(|r| r.stress).collect();
        let rate_shear: Vec<D::Vector> = self.rates.iter().map(|r| r.shear).collect();
        out.f64s("rate_density", &rate_density);
        out.matrices::<D>("rate_stress", &rate_stress);
        out.vectors::<D>("rate_shear", &rate_shear);
        out.vectors::<D>("accelerations", &self.accelerations);
        out.f64s("pressures", &self.pressures);
        out.f64s(
            "scalars",
            &[
                self.time,
                self.max_speed,
                self.schedule.next(),
                self.first_isolation.unwrap_or(f64::NAN),
            ],
        );
        out.u64s(
            "counters",
            &[
                self.steps,
                self.acoustic_steps,
                self.rebuilds,
                self.isolated as u64,
                self.isolated_max as u64,
                u64::from(self.first_isolation.is_some()),
                self.pair_visits,
            ],
        );
        save_probes(out, &self.probes);
        // The energy budget's accumulated works, the momentum balance and the contact series.
        let w = &self.work;
        out.f64s(
            "budget",
            &[
                w.riemann,
                w.artificial,
                w.contact,
                w.shear,
                w.loads,
                w.density_jump,
                self.initial_total,
            ],
        );
        out.vectors::<D>(
            "momentum_balance",
            &[self.initial_momentum, self.constraint_impulse],
        );
        save_series(out, &self.series);
        Ok(())
    }

    /// Puts the particles of this freshly built solver in the saved order (every per-particle
    /// field, constraint, load and probe follows), then reads the state.
    fn restore_state(&mut self, input: &mut StateReader<'_>) -> Result<(), Error> {
        let n = self.len();
        let saved = input.u64s("original_index", Some(n))?;
        let mut seen = vec![false; n];
        for &o in &saved {
            match seen.get_mut(o as usize) {
                Some(s) if !*s => *s = true,
                _ => {
                    return Err(Error::Checkpoint(format!(
                        "original_index is not a permutation of 0..{n} (entry {o})"
                    )))
                }
            }
        }
        let inv = self.inverse_index();
        let perm: Vec<u32> = saved.iter().map(|&o| inv[o as usize]).collect();
        self.permute(&perm);
        let n = Some(n);
        self.positions = input.vectors::<D>("positions", n)?;
        self.velocities = input.vectors::<D>("velocities", n)?;
        self.densities = input.f64s("densities", n)?;
        self.stress = input.matrices::<D>("stress", Some(self.stress.len()))?;
        self.accumulated = input.vectors::<D>("accumulated", Some(self.accumulated.len()))?;
        let rate_density = input.f64s("rate_density", n)?;
        let rate_stress = input.matrices::<D>("rate_stress", n)?;
        let rate_shear = input.vectors::<D>("rate_shear", n)?;
        for (k, r) in self.rates.iter_mut().enumerate() {
            (r.density, r.stress, r.shear) = (rate_density[k], rate_stress[k], rate_shear[k]);
        }
        self.accelerations = input.vectors::<D>("accelerations", n)?;
        self.pressures = input.f64s("pressures", n)?;
        let [time, max_speed, next_probe, first_isolation] = input.scalars::<4>("scalars")?;
        (self.time, self.max_speed) = (time, max_speed);
        self.schedule.set_next(next_probe);
        let c = input.u64s("counters", Some(7))?;
        self.pair_visits = c[6];
        (self.steps, self.acoustic_steps, self.rebuilds) = (c[0], c[1], c[2]);
        (self.isolated, self.isolated_max) = (c[3] as usize, c[4] as usize);
        self.first_isolation = (c[5] != 0).then_some(first_isolation);
        restore_probes(input, &mut self.probes)?;
        let [riemann, artificial, contact, shear, loads, density_jump, initial_total] =
            input.scalars::<7>("budget")?;
        self.work = AccumulatedWork {
            riemann,
            artificial,
            contact,
            shear,
            loads,
            density_jump,
        };
        self.initial_total = initial_total;
        let m = input.vectors::<D>("momentum_balance", Some(2))?;
        (self.initial_momentum, self.constraint_impulse) = (m[0], m[1]);
        restore_series(input, &mut self.series)?;
        self.check_finite()
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
        vec![
            "velocity",
            "displacement",
            "density",
            "pressure",
            "von_mises",
            "shear_stress",
            "disorder",
            "fragment",
            "original_index",
        ]
    }

    /// Output fields in the current particle order (see [`UlSolver::original_index`]).
    /// `fragment` labels the connected pieces of the own-body neighbour graph of the last
    /// rebuild (`0..k`; a body that breaks apart — numerical fracture — has several).
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
                self.densities
                    .iter()
                    .map(|&r| pressure(r, self.rho0, self.c0))
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

    fn series(&self) -> Vec<Series> {
        self.series.clone()
    }
}
