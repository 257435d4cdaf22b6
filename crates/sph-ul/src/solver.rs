//! The UL solver: body set-up, neighbour rebuilds with cell-order reordering, and the
//! position-Verlet acoustic step (UL paper eq 23–25) inside the dual-criteria time stepping of §5.
//!
//! One acoustic step of length `Δt`:
//! 1. eq 23: `x`, `ρ` (and the shear stress `τ` of OG/OAS) to the half step with the rates of the
//!    previous step;
//! 2. eq 4: pressure from the half-step density; forces: Riemann pressure (eq 12) plus the
//!    variant's shear acceleration (OG: eq 13; OAS: eq 13 plus the artificial stress; ENOG: the
//!    accumulated `A_s` of the previous step, eq 20 note); loads; constraints;
//! 3. eq 24: `v^{n+1} = v^n + Δt a`; velocity constraints at the new time;
//! 4. rates with `v^{n+1}`: continuity (eq 11), the Jaumann rate of `τ` (eq 6–8 with the velocity
//!    gradient of eq 14/26) and, for ENOG, the Laplacian sum of eq 19 (or 18);
//! 5. eq 25: `x`, `ρ`, `τ` to the full step; then the ENOG accumulation
//!    `A_s += Δt · 2ζ (G/ρ) Σ …` (never reset).
//!
//! The neighbour list and the correction matrix `B` are those of the last rebuild, frozen over
//! the acoustic sub-steps of one advection step; the kernel data (`e_ij`, `r_ij`, `W`, `W′`) are
//! recomputed over that list from the half-step positions of every sub-step
//! ([`UlParams::refresh_kernel_data`], default; frozen too when off). Volumes `V_j = m_j/ρ_j` use
//! the current densities. Every pair term is antisymmetric in `(i, j)` at one instant, so linear
//! momentum is conserved to round-off by every variant.

use crate::artificial_stress::{self, artificial_pair_acceleration};
use crate::nested::{jaumann_rate, shear_energy, shear_pair_acceleration, velocity_gradient_pair};
use crate::non_nested::{
    conservative_laplacian_pair, default_zeta, non_conservative_laplacian_pair,
    shear_acceleration_rate, LaplacianForm,
};
use crate::riemann::{
    continuity_pair, interface_pressure, pressure, pressure_energy, pressure_pair_factor,
    RiemannScheme,
};
use crate::stepping::{acoustic_dt, advection_dt, next_substep, Stepping};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sph_core::correction::{correction_matrices, DEFAULT_MIN_EIGENVALUE};
use sph_core::diagnostics;
use sph_core::disorder::{affine_fit, disorder_indicator};
use sph_core::error::{check_non_negative, check_positive};
use sph_core::neighbor::{apply_permutation, invert_permutation};
use sph_core::pairs::{fill_pair_kernels, pair_kernels};
use sph_core::scene::ProbeSchedule;
use sph_core::solver::first_non_finite;
use sph_core::{
    Body, CellGrid, Constraints, Dim, Error, Field, Kernel, Loads, NeighborList, PairKernel, Probe,
    Solver, StepInfo, WendlandC2,
};
use sph_materials::{von_mises, ElasticConstants};

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

    /// The method name as the command line spells it.
    pub fn method_name(&self) -> &'static str {
        match self {
            Shear::Original => "ul-og",
            Shear::ArtificialStress { .. } => "ul-oas",
            Shear::NonNested { .. } => "ul-enog",
        }
    }

    fn validate(&self) -> Result<(), Error> {
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
        }
    }
}

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
    /// the motion). Off saves one matrix per pair per sub-step; `von_mises` then shows the
    /// pressure part only.
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
        }
    }
}

/// Kinetic and elastic energy of the body.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Energy {
    /// `Σ ½ m v²`.
    pub kinetic: f64,
    /// Energy of the equation of state, `Σ m c0² (ln(ρ/ρ0) + ρ0/ρ − 1)`.
    pub volumetric: f64,
    /// Shear energy `Σ V τ:τ/(4G)` (for ENOG from the output shear stress: an estimate).
    pub shear: f64,
}

impl Energy {
    /// Kinetic plus elastic energy.
    pub fn total(&self) -> f64 {
        self.kinetic + self.volumetric + self.shear
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
    /// `dτ/dt` (eq 6–8).
    stress: D::Matrix,
    /// ENOG: `dA_s/dt` (eq 20).
    shear: D::Vector,
}

impl<D: Dim> Rates<D> {
    fn zero() -> Self {
        Self {
            density: 0.0,
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
    correction: Vec<D::Matrix>,
    guarded: usize,
    rebuild_positions: Vec<D::Vector>,
    // Contact between bodies (empty `body` = one body): body id per particle, the inter-body
    // pairs of the last rebuild with their kernel data (current positions), W(dp), and the
    // contact densities.
    body: Vec<u32>,
    contact_list: NeighborList,
    contact_pairs: Vec<PairKernel<D>>,
    contact_w_dp: f64,
    contact_density: Vec<f64>,
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
            correction: vec![D::identity(); n],
            guarded: 0,
            rebuild_positions: Vec::new(),
            body: Vec::new(),
            contact_list: NeighborList::default(),
            contact_pairs: Vec::new(),
            contact_w_dp: 0.0,
            contact_density: Vec::new(),
            isolated: 0,
            isolated_max: 0,
            first_isolation: None,
            pressures: vec![0.0; n],
            current_volumes: vec![0.0; n],
            accelerations: vec![D::zero(); n],
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
        self
    }

    /// Attaches body accelerations and point forces (indices in the original order).
    pub fn with_loads(mut self, mut loads: Loads<D>) -> Self {
        loads.remap(&self.inverse_index());
        self.loads = loads;
        self
    }

    /// Makes the particles separate bodies (`body_of[i]` for input particle `i`) that meet
    /// through contact (docs/methods.md, SPHinXsys): each body keeps its own neighbours (pressure,
    /// shear, continuity and `B` see only the own body), and particles of different bodies
    /// closer than the kernel support push each other apart with the contact pressure
    /// `p_c = c0² ρ_c`, `ρ_c,i = Σ_{j ∈ other} max(W_ij − W(dp), 0) m_j`,
    /// `a_i −= (2/m_i) Σ_j ½(p_c,i + p_c,j) V_i V_j W′_ij e_ij` — antisymmetric per pair, so
    /// momentum is conserved; repulsive only (bodies separate freely). The contact energy is
    /// not part of [`UlSolver::energy`].
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
        self.body = self
            .original_index
            .iter()
            .map(|&o| body_of[o as usize])
            .collect();
        let dp = self.kernel.h() / self.params.h_over_dp;
        self.contact_w_dp = self.kernel.w(dp);
        self.contact_density = vec![0.0; n];
        self.rebuild()?;
        self.refresh_rates();
        Ok(self)
    }

    /// Attaches probes (indices in the original order), recorded at `t = 0` and then every
    /// `interval` of simulated time (0 = every step).
    pub fn with_probes(mut self, mut probes: Vec<Probe<D>>, interval: f64) -> Result<Self, Error> {
        self.schedule = ProbeSchedule::every(interval)?;
        let inv = self.inverse_index();
        for p in &mut probes {
            p.remap(&inv);
        }
        self.probes = probes;
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
        if !self.body.is_empty() {
            self.split_contact_pairs()?;
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
        fill_pair_kernels(
            &self.positions,
            &self.positions,
            &self.list,
            &self.kernel,
            &mut self.pairs,
        );
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

    /// Splits the neighbour list into the own-body list (`self.list`) and the inter-body
    /// contact list.
    fn split_contact_pairs(&mut self) -> Result<(), Error> {
        let n = self.len();
        let (mut own_off, mut own_ix) = (Vec::with_capacity(n + 1), Vec::new());
        let (mut con_off, mut con_ix) = (Vec::with_capacity(n + 1), Vec::new());
        own_off.push(0);
        con_off.push(0);
        for i in 0..n {
            for &j in self.list.neighbors(i) {
                if self.body[j as usize] == self.body[i] {
                    own_ix.push(j);
                } else {
                    con_ix.push(j);
                }
            }
            own_off.push(own_ix.len());
            con_off.push(con_ix.len());
        }
        self.list = NeighborList::from_parts(own_off, own_ix)?;
        self.contact_list = NeighborList::from_parts(con_off, con_ix)?;
        Ok(())
    }

    /// Adds the contact accelerations (see [`UlSolver::with_contact`]) to `out`, with the
    /// kernel data of the inter-body pairs at the current positions.
    fn add_contact_forces(&mut self, out: &mut [D::Vector]) {
        if self.contact_list.num_pairs() == 0 {
            return;
        }
        let zero = PairKernel::<D> {
            e: D::zero(),
            r: 0.0,
            w: 0.0,
            dw: 0.0,
        };
        self.contact_pairs
            .resize(self.contact_list.num_pairs(), zero);
        fill_pair_kernels(
            &self.positions,
            &self.positions,
            &self.contact_list,
            &self.kernel,
            &mut self.contact_pairs,
        );
        let (list, pairs, m, w_dp) = (
            &self.contact_list,
            &self.contact_pairs,
            &self.masses,
            self.contact_w_dp,
        );
        gather(&mut self.contact_density, |i, rho_c| {
            *rho_c = pairs[list.range(i)]
                .iter()
                .zip(list.neighbors(i))
                .map(|(pk, &j)| (pk.w - w_dp).max(0.0) * m[j as usize])
                .sum();
        });
        let c2 = self.c0 * self.c0;
        let (rho, rho_c) = (&self.densities, &self.contact_density);
        let mut add = vec![D::zero(); self.len()];
        gather(&mut add, |i, a| {
            let v_i = m[i] / rho[i];
            let mut acc = D::zero();
            for (pk, &j) in pairs[list.range(i)].iter().zip(list.neighbors(i)) {
                let j = j as usize;
                let p_star = 0.5 * c2 * (rho_c[i] + rho_c[j]);
                acc += pk.e * (-2.0 * p_star * v_i * (m[j] / rho[j]) * pk.dw / m[i]);
            }
            *a = acc;
        });
        out.iter_mut().zip(&add).for_each(|(o, &a)| *o += a);
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
        p(perm, &mut self.body);
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
        self.compute_rates();
        self.max_speed = max_norm::<D>(&self.velocities, &self.free);
    }

    /// Eq. (4) for every particle.
    fn update_pressures(&mut self) {
        let (rho0, c0) = (self.rho0, self.c0);
        // Element-wise loops are memory-bound and tiny: on this thread (no pool hand-off).
        self.pressures
            .iter_mut()
            .zip(&self.densities)
            .for_each(|(p, &rho)| *p = pressure(rho, rho0, c0));
        self.current_volumes
            .iter_mut()
            .zip(&self.masses)
            .zip(&self.densities)
            .for_each(|((v, &m), &rho)| *v = m / rho);
    }

    /// Step 4 of the module docs: continuity (eq 11), the Jaumann rate of `τ` (eq 6–8, 14/26)
    /// and the ENOG rate (eq 19–20), in one gather over the neighbours.
    fn compute_rates(&mut self) {
        let grad = self.tracks_stress;
        let corrected = self.params.corrected_velocity_gradient
            || matches!(self.variant, Variant::NonNested { .. });
        match self.variant {
            Variant::NonNested { factor, form } => match (grad, form) {
                (true, LaplacianForm::Conservative) => {
                    self.rates_loop::<true, 1>(corrected, factor)
                }
                (true, LaplacianForm::NonConservative) => {
                    self.rates_loop::<true, 2>(corrected, factor)
                }
                (false, LaplacianForm::Conservative) => {
                    self.rates_loop::<false, 1>(corrected, factor)
                }
                (false, LaplacianForm::NonConservative) => {
                    self.rates_loop::<false, 2>(corrected, factor)
                }
            },
            _ => self.rates_loop::<true, 0>(corrected, 0.0),
        }
    }

    /// The gather of [`Self::compute_rates`]; `GRAD`: velocity gradient and Jaumann rate;
    /// `LAP`: 0 none, 1 eq 19, 2 eq 18.
    fn rates_loop<const GRAD: bool, const LAP: u8>(&mut self, corrected: bool, factor: f64) {
        let list = &self.list;
        let pairs = &self.pairs;
        let (x_v, rho, vol, p, tau, b) = (
            &self.velocities,
            &self.densities,
            &self.current_volumes,
            &self.pressures,
            &self.stress,
            &self.correction,
        );
        let (g, rho0_c0, scheme) = (self.g, self.rho0 * self.c0, self.params.riemann);
        gather(&mut self.rates, |i, out| {
            let (v_i, p_i, rho_i) = (x_v[i], p[i], rho[i]);
            let mut drho = 0.0;
            let mut l = D::zero_matrix();
            let mut lap = D::zero();
            for (pk, &j) in pairs[list.range(i)].iter().zip(list.neighbors(i)) {
                let j = j as usize;
                let v_j = vol[j];
                let v_ij = v_i - x_v[j];
                let u = D::dot(v_ij, pk.e);
                drho += continuity_pair(u, p_i, p[j], rho0_c0, scheme) * pk.dw * v_j;
                if GRAD {
                    l += velocity_gradient_pair::<D>(v_ij, pk.e, pk.dw, v_j);
                }
                match LAP {
                    1 => lap += conservative_laplacian_pair::<D>(v_ij, pk.e, pk.r, pk.dw, v_j),
                    2 => lap += non_conservative_laplacian_pair::<D>(v_ij, pk.r, pk.dw, v_j),
                    _ => {}
                }
            }
            out.density = rho_i * drho;
            if GRAD {
                if corrected {
                    l = l * b[i];
                }
                out.stress = jaumann_rate::<D>(l, tau[i], g);
            }
            if LAP != 0 {
                out.shear = shear_acceleration_rate::<D>(lap, factor, g, rho_i);
            }
        });
    }

    /// Internal accelerations of the current state (pressure from `ρ`; the variant's shear
    /// term) into `self.accelerations`: step 2 of the module docs without loads or
    /// constraints.
    fn compute_forces(&mut self) {
        let mut out = std::mem::take(&mut self.accelerations);
        match self.variant {
            Variant::Original => self.forces_loop(NestedShear { tau: &self.stress }, &mut out),
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
                );
            }
            Variant::NonNested { .. } => self.forces_loop(
                AccumulatedShear {
                    a_s: &self.accumulated,
                },
                &mut out,
            ),
        }
        if !self.body.is_empty() {
            self.add_contact_forces(&mut out);
        }
        self.accelerations = out;
    }

    /// The force gather: Riemann pressure (eq 12) plus the shear term `S`.
    fn forces_loop<S: ShearForce<D>>(&self, shear: S, out: &mut [D::Vector]) {
        let list = &self.list;
        let pairs = &self.pairs;
        let (vel, rho, vol, p) = (
            &self.velocities,
            &self.densities,
            &self.current_volumes,
            &self.pressures,
        );
        let (rho0, c0, scheme) = (self.rho0, self.c0, self.params.riemann);
        gather(out, |i, a| {
            let (v_i, p_i, inv_rho_i) = (vel[i], p[i], 1.0 / rho[i]);
            let mut acc = D::zero();
            for (pk, &j) in pairs[list.range(i)].iter().zip(list.neighbors(i)) {
                let j = j as usize;
                let vj_rho_i = vol[j] * inv_rho_i;
                let u = D::dot(v_i - vel[j], pk.e);
                let p_star = interface_pressure(p_i, p[j], u, rho0, c0, scheme);
                acc += pk.e * pressure_pair_factor(p_star, pk.dw, vj_rho_i);
                acc += shear.pair(i, j, pk, vj_rho_i);
            }
            *a = acc + shear.particle(i);
        });
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
        self.compute_rates();
        self.rates.iter().map(|r| r.density).collect()
    }

    /// One acoustic step of length `dt` (eq 23–25), see the module documentation.
    fn acoustic_step(&mut self, dt: f64) {
        let half = 0.5 * dt;
        // Eq 23: x, ρ (and τ) to the half step with the previous rates.
        self.drift(half);
        if self.params.refresh_kernel_data {
            fill_pair_kernels(
                &self.positions,
                &self.positions,
                &self.list,
                &self.kernel,
                &mut self.pairs,
            );
        }
        // Eq 4, forces, loads, constraints.
        self.update_pressures();
        self.compute_forces();
        if !self.loads.is_empty() {
            self.loads
                .add_accelerations(self.time + half, &self.masses, &mut self.accelerations);
        }
        self.constraints
            .apply_to_accelerations(&mut self.accelerations);
        // Eq 24.
        self.velocities
            .iter_mut()
            .zip(&self.accelerations)
            .for_each(|(v, &a)| *v += a * dt);
        self.time += dt;
        self.constraints
            .apply_to_velocities(self.time, &mut self.velocities);
        // Rates with v^{n+1}, then eq 25.
        self.compute_rates();
        self.drift(half);
        // Eq 20: accumulate A_s (never reset); used by the next step.
        if !self.accumulated.is_empty() {
            self.accumulated
                .iter_mut()
                .zip(&self.rates)
                .for_each(|(a, r)| *a += r.shear * dt);
        }
        self.max_speed = max_norm::<D>(&self.velocities, &self.free);
        self.acoustic_steps += 1;
        self.pair_visits += (self.list.num_pairs() + self.contact_list.num_pairs()) as u64;
    }

    /// `x += h v`, `ρ += h dρ/dt`, `τ += h dτ/dt` (eq 23 and 25).
    /// Element-wise, on this thread: the pool hand-off costs more than these loops.
    fn drift(&mut self, h: f64) {
        self.positions
            .iter_mut()
            .zip(&self.velocities)
            .for_each(|(x, &v)| *x += v * h);
        self.densities
            .iter_mut()
            .zip(&self.rates)
            .for_each(|(rho, r)| *rho += r.density * h);
        self.stress
            .iter_mut()
            .zip(&self.rates)
            .for_each(|(t, r)| *t += r.stress * h);
    }

    fn record_probes(&mut self) {
        for p in &mut self.probes {
            p.record(self.time, &self.positions, &self.velocities);
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
        let shear = self
            .stress
            .iter()
            .zip(&self.masses)
            .zip(&self.densities)
            .map(|((&t, &m), &rho)| shear_energy::<D>(t, m / rho, self.g))
            .sum();
        Energy {
            kinetic,
            volumetric,
            shear,
        }
    }

    /// The disorder indicator of docs/methods.md per particle (current order), accumulated since the
    /// start: Ganzenmüller's error of the weighted least-squares affine fit from the initial
    /// configuration to the current one, over the current neighbours with weights `W⁰` of the
    /// initial distances (neighbours that were not neighbours initially get `W⁰ = 0`).
    ///
    /// docs/methods.md suggests the fit over the last advection step for UL; that measures the
    /// non-affine *increment* of one step (≤ 3·10⁻⁴ on the plate whether or not it is ordered)
    /// and misses a zigzag pattern once it has formed, so the accumulated form is reported;
    /// [`UlSolver::disorder_increment`] gives the per-step form.
    pub fn disorder(&self) -> Vec<f64> {
        let reference = pair_kernels::<D, _>(&self.initial_positions, &self.list, &self.kernel);
        let f = affine_fit::<D>(
            &self.list,
            &reference,
            &self.initial_positions,
            &self.positions,
        );
        disorder_indicator::<D>(
            &self.list,
            &reference,
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
            &self.pairs,
            &self.rebuild_positions,
            &self.positions,
        );
        disorder_indicator::<D>(
            &self.list,
            &self.pairs,
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

/// The per-variant shear term of the force gather (monomorphised: no branch in the loop).
trait ShearForce<D: Dim>: Sync {
    /// Pair contribution to `a_i`.
    fn pair(&self, i: usize, j: usize, pk: &PairKernel<D>, vj_rho_i: f64) -> D::Vector;
    /// Per-particle contribution to `a_i`.
    fn particle(&self, i: usize) -> D::Vector;
}

struct NestedShear<'a, D: Dim> {
    tau: &'a [D::Matrix],
}

impl<D: Dim> ShearForce<D> for NestedShear<'_, D> {
    #[inline(always)]
    fn pair(&self, i: usize, j: usize, pk: &PairKernel<D>, vj_rho_i: f64) -> D::Vector {
        shear_pair_acceleration::<D>(self.tau[i], self.tau[j], pk.e, pk.dw, vj_rho_i)
    }
    #[inline(always)]
    fn particle(&self, _i: usize) -> D::Vector {
        D::zero()
    }
}

/// OAS's shear term. The artificial stress's pair factor `f_ij = W(r_ij)/W(dp)` is evaluated
/// at the *current* distance in every acoustic sub-step, not from the kernel data frozen at the
/// rebuild: `f_ij^n` (n = 4) is a stiff short-range repulsion, and with the distance frozen
/// over an advection step it lags the motion and pumps energy in — measured: the plate
/// (H/dp = 10, v_f = 0.05) blew up at t = 0.077 s and the rings at 0.07 c0 at t = 0.006 s with
/// frozen `f`, both run through with single stepping or with the current `f`. With
/// [`UlParams::refresh_kernel_data`] the pair data are current already.
struct ArtificialShear<'a, D: Dim> {
    tau: &'a [D::Matrix],
    r: &'a [D::Matrix],
    masses: &'a [f64],
    /// Current positions when the kernel data are frozen (`W` recomputed here), else `None`.
    positions: Option<&'a [D::Vector]>,
    kernel: &'a WendlandC2<D>,
    inv_w_dp: f64,
    n: u32,
}

impl<D: Dim> ShearForce<D> for ArtificialShear<'_, D> {
    #[inline(always)]
    fn pair(&self, i: usize, j: usize, pk: &PairKernel<D>, vj_rho_i: f64) -> D::Vector {
        let current = match self.positions {
            Some(x) => PairKernel::<D> {
                w: self.kernel.w(D::norm(x[i] - x[j])),
                ..*pk
            },
            None => *pk,
        };
        shear_pair_acceleration::<D>(self.tau[i], self.tau[j], pk.e, pk.dw, vj_rho_i)
            + artificial_pair_acceleration::<D>(
                self.r[i],
                self.r[j],
                &current,
                self.inv_w_dp,
                self.n,
                self.masses[j],
            )
    }
    #[inline(always)]
    fn particle(&self, _i: usize) -> D::Vector {
        D::zero()
    }
}

struct AccumulatedShear<'a, D: Dim> {
    a_s: &'a [D::Vector],
}

impl<D: Dim> ShearForce<D> for AccumulatedShear<'_, D> {
    #[inline(always)]
    fn pair(&self, _i: usize, _j: usize, _pk: &PairKernel<D>, _vj_rho_i: f64) -> D::Vector {
        D::zero()
    }
    #[inline(always)]
    fn particle(&self, i: usize) -> D::Vector {
        self.a_s[i]
    }
}

/// Loops over fewer particles than twice this run on the calling thread (one threshold for
/// every method: [`sph_core::parallel`]).
pub const PARALLEL_THRESHOLD: usize = sph_core::parallel::MIN_PARTICLES_PER_TASK;

use sph_core::parallel::gather;

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

/// Largest `|v|` over the particles marked free.
/// Largest `|v|` over the free particles; NaN if any is NaN (so the time-step guard sees it).
fn max_norm<D: Dim>(v: &[D::Vector], free: &[bool]) -> f64 {
    v.iter()
        .zip(free)
        .map(|(&x, &f)| if f { D::norm_squared(x) } else { 0.0 })
        .fold(0.0, diagnostics::max_or_nan)
        .sqrt()
}

impl<D: Dim> Solver<D> for UlSolver<D> {
    fn method(&self) -> &'static str {
        self.shear.method_name()
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
                }
            }
        }
        self.time = start + dt;
        self.steps += 1;
        self.check_finite()?;
        if !self.probes.is_empty() && self.schedule.due(self.time) {
            self.record_probes();
        }
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
            "original_index",
        ]
    }

    /// Output fields in the current particle order (see [`UlSolver::original_index`]).
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
}
