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
        Self::with_materials(body, vec![constants], Vec::new(), shear, params)
    }

    /// [`UlSolver::new`] with a material per particle: `material_of[i]` indexes `materials`
    /// for input particle `i` (empty: every particle the first material). Each particle's mass
    /// is its volume times its material's `ρ0`; pressure (eq 4), the Riemann dissipation
    /// (eq 12), the shear modulus of the Jaumann rate and of ENOG's shear acceleration are each
    /// particle's own; the acoustic step (eq 22) takes the largest sound speed. A pair term
    /// reads particle `i`'s material, so particles of different materials must be different
    /// bodies ([`UlSolver::with_contact`], which checks it): the first step refuses a solver
    /// whose particles use several materials without it.
    ///
    /// # Errors
    /// As [`UlSolver::new`]; no material, more than 65 536, `material_of` neither empty nor one
    /// index below `materials.len()` per particle.
    ///
    /// # Examples
    /// ```
    /// use glam::DVec2;
    /// use sph_core::{Body, D2};
    /// use sph_materials::ElasticConstants;
    /// use sph_ul::{Shear, UlParams, UlSolver};
    /// // Two 10 × 5 blocks 2 dp apart: a soft one and a stiff one.
    /// let dp = 0.01;
    /// let mut positions = Vec::new();
    /// for (b, x0) in [0.0, 0.12].into_iter().enumerate() {
    ///     for i in 0..10 {
    ///         for j in 0..5 {
    ///             positions.push(DVec2::new(x0 + (i as f64 + 0.5) * dp, (j as f64 + 0.5) * dp));
    ///         }
    ///     }
    /// }
    /// let body_of: Vec<u32> = (0..100).map(|i| u32::from(i >= 50)).collect();
    /// let body = Body::<D2>::new(positions, vec![dp * dp; 100], dp);
    /// let soft = ElasticConstants::from_youngs(1e6, 0.3, 1000.0)?;
    /// let stiff = ElasticConstants::from_youngs(1e9, 0.3, 7800.0)?;
    /// let s = UlSolver::with_materials(
    ///     body,
    ///     vec![soft, stiff],
    ///     body_of.clone(),
    ///     Shear::non_nested(),
    ///     UlParams::default(),
    /// )?
    /// .with_contact(body_of)?;
    /// assert_eq!(s.materials().len(), 2);
    /// # Ok::<(), sph_core::Error>(())
    /// ```
    pub fn with_materials(
        body: impl Into<Body<D>>,
        materials: Vec<ElasticConstants>,
        material_of: Vec<u32>,
        shear: Shear,
        params: UlParams,
    ) -> Result<Self, Error> {
        let body: Body<D> = body.into();
        body.validate("ul body")?;
        params.validate()?;
        shear.validate()?;
        let n = body.len();
        check_per_particle("densities", &body.densities, n, true)?;
        let material = sph_core::body::material_indices(materials.len(), &material_of, n)?;
        let velocities = body.velocities_or_rest();
        let rho0 = |i: usize| materials[material[i] as usize].density;
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
            // The penalty's stiffness ξ G is one number: one material for now.
            Shear::Generalized { .. } if materials.len() > 1 => {
                return Err(Error::invalid(
                    "materials",
                    materials.len(),
                    "one material with ul-gnog (its penalty stiffness ξ G is one number)",
                ))
            }
            Shear::Generalized { xi } => Variant::Generalized {
                xi_g: xi.unwrap_or(crate::generalized::DEFAULT_XI) * materials[0].shear_modulus,
            },
        };
        let tracks_stress =
            !matches!(variant, Variant::NonNested { .. }) || params.track_shear_stress;
        let densities = if body.densities.is_empty() {
            (0..n).map(rho0).collect()
        } else {
            body.densities
        };
        let masses: Vec<f64> = body
            .volumes
            .iter()
            .enumerate()
            .map(|(i, v)| v * rho0(i))
            .collect();
        let c0 = materials.iter().map(|c| c.sound_speed).fold(0.0, f64::max);
        let mut solver = Self {
            materials,
            material,
            shear,
            variant,
            params,
            kernel,
            c0,
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
            contact_friction: None,
            series: Vec::new(),
            tools: ToolSet::default(),
            work: AccumulatedWork::default(),
            initial_total: 0.0,
            initial_momentum: D::zero(),
            constraint_impulse: D::zero(),
            kicked: Vec::new(),
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
