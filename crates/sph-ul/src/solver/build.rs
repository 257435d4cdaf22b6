//! Building a UL solver ([`UlSolver::new`]): the input checked, the particles sorted in cell
//! order, the neighbour list, kernel data and correction matrices, and the initial rates.

use super::*;

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
        params.validate()?;
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
            Shear::Generalized { xi } => Variant::Generalized {
                xi_g: xi.unwrap_or(crate::generalized::DEFAULT_XI) * constants.shear_modulus,
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
            accumulated: if matches!(
                variant,
                Variant::NonNested { .. } | Variant::Generalized { .. }
            ) {
                vec![D::zero(); n]
            } else {
                Vec::new()
            },
            gradients: if matches!(variant, Variant::Generalized { .. }) {
                vec![D::zero_matrix(); n]
            } else {
                Vec::new()
            },
            plasticity: None,
            plastic: Vec::new(),
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
            tools: ToolSet::default(),
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
}
