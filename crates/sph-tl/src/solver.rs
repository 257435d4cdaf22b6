//! The TL solver: body set-up in the reference configuration and the position-Verlet step
//! (TL paper eq 30–32) with the time step of eq 33.

use crate::damping::damping_coefficient;
use crate::{ganzenmuller, hourglass_free, original};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sph_core::correction::{correction_matrices, DEFAULT_MIN_EIGENVALUE};
use sph_core::diagnostics;
use sph_core::disorder::disorder_indicator;
use sph_core::error::{check_non_negative, check_positive};
use sph_core::neighbor::CellGrid;
use sph_core::pairs::pair_kernels;
use sph_core::scene::ProbeSchedule;
use sph_core::solver::{deformation_field, DEFORMATION_FIELDS};
use sph_core::{
    Constraints, Dim, Error, Field, Kernel, Loads, NeighborList, PairKernel, Probe, Solver,
    StepInfo, WendlandC2,
};
use sph_materials::{von_mises, Material};

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

    fn validate(&self) -> Result<(), Error> {
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
}

impl Default for TlParams {
    fn default() -> Self {
        Self {
            h_over_dp: 1.15,
            cfl: 0.6,
            damping: true,
            correction_min_eigenvalue: DEFAULT_MIN_EIGENVALUE,
            min_dt_ratio: diagnostics::MIN_DT_RATIO,
        }
    }
}

/// The particles of one body in its reference configuration.
#[derive(Clone, Debug)]
pub struct TlBody<D: Dim> {
    /// Reference positions `X` (also the initial positions).
    pub positions: Vec<D::Vector>,
    /// Reference volumes `V⁰`.
    pub volumes: Vec<f64>,
    /// Initial particle spacing `dp` (sets h).
    pub dp: f64,
    /// Initial velocities (empty = at rest).
    pub velocities: Vec<D::Vector>,
}

/// Kinetic and strain energy of the body.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Energy {
    /// `Σ ½ m v²`.
    pub kinetic: f64,
    /// `Σ V⁰ ψ(F)` (the HF variant uses the energy of its volumetric–deviatoric law; the GM
    /// penalty has no energy and is not included).
    pub strain: f64,
}

impl Energy {
    /// Kinetic plus strain energy.
    pub fn total(&self) -> f64 {
        self.kinetic + self.strain
    }
}

/// Variant-specific per-pair data, computed once.
#[derive(Clone, Debug)]
enum PairData {
    Original,
    /// `V_j W′(r⁰)/r⁰` per pair.
    HourglassFree {
        zeta: f64,
        lap: Vec<f64>,
    },
    /// `V_j W(r⁰)/|X_ij|²` per pair.
    Ganzenmuller {
        alpha: f64,
        weight: Vec<f64>,
    },
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
    pairs: Vec<PairKernel<D>>,
    /// `V_j ∇⁰_i W_ij` per pair.
    grad_v: Vec<D::Vector>,
    correction: Vec<D::Matrix>,
    guarded: usize,
    pair_data: PairData,
    // State.
    positions: Vec<D::Vector>,
    velocities: Vec<D::Vector>,
    deformation: Vec<D::Matrix>,
    deformation_rate: Vec<D::Matrix>,
    accelerations: Vec<D::Vector>,
    // Scratch (allocated once).
    stress: Vec<D::Matrix>,
    isochoric: Vec<f64>,
    // Scene.
    constraints: Constraints<D>,
    free: Vec<bool>,
    loads: Loads<D>,
    probes: Vec<Probe<D>>,
    schedule: ProbeSchedule,
    time: f64,
    steps: u64,
    max_speed: f64,
    max_acceleration: f64,
}

impl<D: Dim, M: Material<D>> TlSolver<D, M> {
    /// Builds the solver: neighbours, kernel data and correction matrices in the reference
    /// configuration.
    ///
    /// # Errors
    /// Empty body, mismatched array lengths, non-positive `dp`/volumes/parameters, non-finite
    /// positions, or a particle with fewer than `D::D` neighbours (its correction matrix and
    /// stress divergence are meaningless).
    pub fn new(
        body: TlBody<D>,
        material: M,
        shear: Shear,
        params: TlParams,
    ) -> Result<Self, Error> {
        let n = body.positions.len();
        if n == 0 {
            return Err(Error::EmptyBody {
                body: "tl body".into(),
            });
        }
        check_positive("dp", body.dp)?;
        check_positive("h_over_dp", params.h_over_dp)?;
        check_positive("cfl", params.cfl)?;
        check_positive("min_dt_ratio", params.min_dt_ratio)?;
        shear.validate()?;
        if body.volumes.len() != n {
            return Err(Error::invalid(
                "volumes",
                body.volumes.len(),
                &format!("one per particle ({n})"),
            ));
        }
        if let Some(i) = body
            .volumes
            .iter()
            .position(|v| !(v.is_finite() && *v > 0.0))
        {
            return Err(Error::invalid(
                &format!("volumes[{i}]"),
                body.volumes[i],
                "> 0 and finite",
            ));
        }
        let velocities = if body.velocities.is_empty() {
            vec![D::zero(); n]
        } else if body.velocities.len() == n {
            body.velocities
        } else {
            return Err(Error::invalid(
                "velocities",
                body.velocities.len(),
                &format!("empty or one per particle ({n})"),
            ));
        };
        let constants = *material.constants();
        let density = constants.density;
        let sound_speed = constants.sound_speed;
        let kernel = WendlandC2::<D>::from_spacing(body.dp, params.h_over_dp)?;
        let reference = body.positions;
        let list = CellGrid::<D>::build(&reference, kernel.cutoff())?
            .neighbor_list(&reference, kernel.cutoff())?;
        if let Some(i) = (0..n).find(|&i| list.count(i) < D::D) {
            return Err(Error::TooFewNeighbours {
                particle: i,
                found: list.count(i),
                required: D::D,
            });
        }
        let pairs = pair_kernels::<D, _>(&reference, &list, &kernel);
        let volumes = body.volumes;
        let grad_v: Vec<D::Vector> = list
            .indices()
            .par_iter()
            .zip(&pairs)
            .map(|(&j, p)| p.grad() * volumes[j as usize])
            .collect();
        let corr =
            correction_matrices::<D>(&list, &pairs, &volumes, params.correction_min_eigenvalue)?;
        let pair_data = match shear {
            Shear::Original => PairData::Original,
            Shear::HourglassFree { zeta } => PairData::HourglassFree {
                zeta,
                lap: list
                    .indices()
                    .par_iter()
                    .zip(&pairs)
                    .map(|(&j, p)| volumes[j as usize] * p.dw / p.r)
                    .collect(),
            },
            Shear::Ganzenmuller { alpha } => PairData::Ganzenmuller {
                alpha,
                weight: list
                    .indices()
                    .par_iter()
                    .zip(&pairs)
                    .map(|(&j, p)| volumes[j as usize] * p.w / (p.r * p.r))
                    .collect(),
            },
        };
        if let PairData::HourglassFree { lap, .. } | PairData::Ganzenmuller { weight: lap, .. } =
            &pair_data
        {
            if let Some(k) = lap.iter().position(|v| !v.is_finite()) {
                // Only coincident reference positions make r⁰ = 0.
                let i = list.offsets().partition_point(|&o| o <= k) - 1;
                return Err(Error::invalid(
                    "positions",
                    format!("particle {i} coincides with a neighbour"),
                    "distinct reference positions",
                ));
            }
        }
        let gamma = if params.damping {
            damping_coefficient(density, sound_speed, kernel.h())
        } else {
            0.0
        };
        let masses = volumes.iter().map(|v| v * density).collect();
        let mut solver = Self {
            material,
            shear,
            params,
            kernel,
            density,
            sound_speed,
            gamma,
            positions: reference.clone(),
            reference,
            volumes,
            masses,
            list,
            pairs,
            grad_v,
            correction: corr.matrices,
            guarded: corr.guarded,
            pair_data,
            velocities,
            deformation: vec![D::identity(); n],
            deformation_rate: vec![D::zero_matrix(); n],
            accelerations: vec![D::zero(); n],
            stress: vec![D::zero_matrix(); n],
            isochoric: if matches!(shear, Shear::HourglassFree { .. }) {
                vec![1.0; n]
            } else {
                Vec::new()
            },
            constraints: Constraints::new(),
            free: vec![true; n],
            loads: Loads::new(),
            probes: Vec::new(),
            schedule: ProbeSchedule::every(0.0)?,
            time: 0.0,
            steps: 0,
            max_speed: 0.0,
            max_acceleration: 0.0,
        };
        solver.refresh_rates();
        Ok(solver)
    }

    /// Attaches the constraints (applied to velocities and accelerations at the points of the
    /// scheme the paper prescribes); constrained particles are excluded from the time-step maxima.
    pub fn with_constraints(mut self, constraints: Constraints<D>) -> Self {
        self.free = constraints
            .prescribed_mask(self.len())
            .into_iter()
            .map(|c| !c)
            .collect();
        self.constraints = constraints;
        self.refresh_rates();
        self
    }

    /// Attaches body accelerations and point forces.
    pub fn with_loads(mut self, loads: Loads<D>) -> Self {
        self.loads = loads;
        self
    }

    /// Attaches probes, recorded at `t = 0` and then every `interval` of simulated time
    /// (0 = every step).
    pub fn with_probes(mut self, probes: Vec<Probe<D>>, interval: f64) -> Result<Self, Error> {
        self.schedule = ProbeSchedule::every(interval)?;
        self.probes = probes;
        if self.schedule.due(self.time) {
            self.record_probes();
        }
        Ok(self)
    }

    /// Replaces the current state by positions `x` and velocities `v`, with `F` computed from
    /// `x` by the corrected SPH gradient (the state a prescribed deformation gives), and `Ḟ` from
    /// `v`. For tests and for starting from a pre-deformed state.
    pub fn set_configuration(&mut self, x: Vec<D::Vector>, v: Vec<D::Vector>) -> Result<(), Error> {
        let n = self.len();
        if x.len() != n || v.len() != n {
            return Err(Error::invalid(
                "configuration",
                format!("{} positions, {} velocities", x.len(), v.len()),
                &format!("{n} of each"),
            ));
        }
        self.deformation = original::deformation_gradient::<D>(
            &self.list,
            &self.grad_v,
            &self.correction,
            &self.reference,
            &x,
        );
        self.positions = x;
        self.velocities = v;
        self.refresh_rates();
        Ok(())
    }

    /// Recomputes `Ḟ` from the current velocities and the speed maximum (after a state change).
    fn refresh_rates(&mut self) {
        self.constraints
            .apply_to_velocities(self.time, &mut self.velocities);
        original::deformation_rate::<D>(
            &self.list,
            &self.grad_v,
            &self.correction,
            &self.velocities,
            &mut self.deformation_rate,
        );
        self.max_speed = diagnostics::max_norm_where::<D>(&self.velocities, &self.free);
    }

    /// Accelerations of the current state (positions, `F`, `Ḟ`), without loads or constraints:
    /// the force evaluation of one step, exposed for tests and diagnostics.
    pub fn evaluate_accelerations(&mut self) -> &[D::Vector] {
        self.compute_internal_accelerations();
        &self.accelerations
    }

    /// The variant's internal accelerations into `self.accelerations`.
    fn compute_internal_accelerations(&mut self) {
        let inv_rho = 1.0 / self.density;
        let (material, gamma) = (&self.material, self.gamma);
        match &self.pair_data {
            PairData::Original | PairData::Ganzenmuller { .. } => {
                self.stress
                    .par_iter_mut()
                    .zip(&self.deformation)
                    .zip(&self.deformation_rate)
                    .zip(&self.correction)
                    .for_each(|(((s, &f), &fd), &b)| {
                        *s = original::corrected_piola::<D, M>(material, gamma, f, fd, b);
                    });
                original::stress_divergence::<D>(
                    &self.list,
                    &self.grad_v,
                    &self.stress,
                    inv_rho,
                    &mut self.accelerations,
                );
                if let PairData::Ganzenmuller { alpha, weight } = &self.pair_data {
                    let scale = alpha * material.constants().youngs_modulus * 0.5 * inv_rho;
                    ganzenmuller::add_penalty_acceleration::<D>(
                        &self.list,
                        weight,
                        &self.reference,
                        &self.positions,
                        &self.deformation,
                        scale,
                        &mut self.accelerations,
                    );
                }
            }
            PairData::HourglassFree { zeta, lap } => {
                let zeta = *zeta;
                self.stress
                    .par_iter_mut()
                    .zip(&mut self.isochoric)
                    .zip(&self.deformation)
                    .zip(&self.deformation_rate)
                    .for_each(|(((s, jf), &f), &fd)| {
                        let (p, j) =
                            hourglass_free::remaining_piola::<D, M>(material, zeta, gamma, f, fd);
                        *s = p;
                        *jf = j;
                    });
                let g = material.constants().shear_modulus;
                hourglass_free::acceleration::<D>(
                    &self.list,
                    &self.grad_v,
                    lap,
                    &self.stress,
                    &self.positions,
                    &self.isochoric,
                    inv_rho,
                    zeta * g * inv_rho,
                    &mut self.accelerations,
                );
            }
        }
    }

    fn record_probes(&mut self) {
        for p in &mut self.probes {
            p.record(self.time, &self.positions, &self.velocities);
        }
    }

    fn check_finite(&self) -> Result<(), Error> {
        diagnostics::check_finite_state::<D>(
            &self.positions,
            &self.velocities,
            ("deformation gradient", &self.deformation),
            self.steps,
            self.time,
        )?;
        diagnostics::check_jacobians::<D>(&self.deformation, self.steps, self.time)
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

    /// How many particles needed the correction-matrix guard.
    pub fn guarded_particles(&self) -> usize {
        self.guarded
    }

    /// Deformation gradients.
    pub fn deformation_gradients(&self) -> &[D::Matrix] {
        &self.deformation
    }

    /// Accelerations of the last step.
    pub fn accelerations(&self) -> &[D::Vector] {
        &self.accelerations
    }

    /// Total linear momentum `Σ m v`.
    pub fn linear_momentum(&self) -> D::Vector {
        diagnostics::linear_momentum::<D>(&self.velocities, &self.masses)
    }

    /// Total angular momentum `Σ m x × v` about the origin (3-vector; only `z` in 2D).
    pub fn angular_momentum(&self) -> glam::DVec3 {
        diagnostics::angular_momentum::<D>(&self.positions, &self.velocities, &self.masses)
    }

    /// Kinetic and strain energy.
    pub fn energy(&self) -> Energy {
        let kinetic = diagnostics::kinetic_energy::<D>(&self.velocities, &self.masses);
        let c = *self.material.constants();
        let strain = self
            .deformation
            .iter()
            .zip(&self.volumes)
            .map(|(&f, &v)| {
                let psi = match self.shear {
                    Shear::HourglassFree { .. } => {
                        hourglass_free::strain_energy::<D>(c.bulk_modulus, c.shear_modulus, f)
                    }
                    _ => self.material.strain_energy_density(f).unwrap_or(f64::NAN),
                };
                v * psi
            })
            .sum();
        Energy { kinetic, strain }
    }

    /// The disorder indicator of METHODS.md per particle.
    pub fn disorder(&self) -> Vec<f64> {
        disorder_indicator::<D>(
            &self.list,
            &self.pairs,
            &self.reference,
            &self.positions,
            &self.deformation,
        )
    }

    /// Cauchy stress (3×3, elastic part) of particle `i`'s law.
    fn cauchy_3d(&self, f: D::Matrix) -> glam::DMat3 {
        match self.shear {
            Shear::HourglassFree { .. } => {
                hourglass_free::kirchhoff_stress_3d::<D, M>(&self.material, f) / D::det(f)
            }
            _ => self.material.cauchy_stress_3d(f),
        }
    }
}

impl<D: Dim, M: Material<D>> Solver<D> for TlSolver<D, M> {
    fn method(&self) -> &'static str {
        self.shear.method_name()
    }

    /// One position-Verlet step (TL paper eq 30–32).
    fn step(&mut self, max_dt: f64) -> Result<StepInfo, Error> {
        let stable = self.stable_dt();
        let min_dt =
            self.params.min_dt_ratio * self.params.cfl * self.kernel.h() / self.sound_speed;
        if !(stable.is_finite() && stable > min_dt) {
            return Err(Error::TimeStepCollapsed {
                dt: stable,
                min: min_dt,
                step: self.steps,
                time: self.time,
            });
        }
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
        // Forces at the half step; loads; constraints.
        self.compute_internal_accelerations();
        if !self.loads.is_empty() {
            self.loads
                .add_accelerations(self.time + half, &self.masses, &mut self.accelerations);
        }
        self.constraints
            .apply_to_accelerations(&mut self.accelerations);
        // Eq 31: velocities to the full step.
        self.velocities
            .par_iter_mut()
            .zip(&self.accelerations)
            .for_each(|(v, &a)| *v += a * dt);
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
        self.max_acceleration = diagnostics::max_norm_where::<D>(&self.accelerations, &self.free);
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

    /// Eq 33: `Δt = CFL · min(h/(c + |v|max), √(h/|a|max))` over unconstrained particles.
    fn stable_dt(&self) -> f64 {
        let h = self.kernel.h();
        let acoustic = h / (self.sound_speed + self.max_speed);
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

    fn positions(&self) -> &[D::Vector] {
        &self.positions
    }

    fn velocities(&self) -> &[D::Vector] {
        &self.velocities
    }

    fn field_names(&self) -> Vec<&'static str> {
        let mut names = DEFORMATION_FIELDS.to_vec();
        names.extend(["von_mises", "disorder"]);
        names
    }

    fn field(&self, name: &str) -> Option<Field<D>> {
        match name {
            "von_mises" => Some(Field::Scalar(
                self.deformation
                    .par_iter()
                    .map(|&f| von_mises(self.cauchy_3d(f)))
                    .collect(),
            )),
            "disorder" => Some(Field::Scalar(self.disorder())),
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

    fn energies(&self) -> Option<(f64, f64)> {
        let e = self.energy();
        Some((e.kinetic, e.strain))
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
    f.par_iter_mut()
        .zip(f_dot)
        .for_each(|(f, &fd)| *f += fd * h);
    x.par_iter_mut().zip(v).for_each(|(x, &v)| *x += v * h);
}
