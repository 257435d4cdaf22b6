//! Building a TL solver: the body, kernel and initial state ([`TlSolver::new`], or without the
//! neighbour data for a distributed run, [`TlSolver::for_ranks`]), and the reference data
//! (neighbour rows, pair data, correction matrices) of its particles.

use super::{Shear, TlParams, TlSolver, DEFAULT_CONTACT_SCALE};
use crate::damping::damping_coefficient;
use crate::hourglass_free::{normalised_zeta, HfLaplacian};
use crate::reference_pairs::{with_pair_rows, PairScalar, ReferencePairs};
use sph_core::correction::correction_matrices_counted;
use sph_core::neighbor::CellGrid;
use sph_core::scene::ProbeSchedule;
use sph_core::tool::ToolSet;
use sph_core::{Body, Constraints, Dim, Error, Kernel, Loads, NeighborList, WendlandC2};
use sph_materials::Material;

/// The pair scalar a shear treatment reads.
pub(super) fn pair_scalar(shear: Shear) -> PairScalar {
    match shear {
        Shear::Original => PairScalar::None,
        Shear::HourglassFree { .. } => PairScalar::Laplacian,
        Shear::Ganzenmuller { .. } => PairScalar::Penalty,
    }
}

/// The error for particle `i` at zero distance from a neighbour in the reference configuration.
pub(super) fn coincident_error(i: usize) -> Error {
    Error::invalid(
        "positions",
        format!("particle {i} coincides with a neighbour"),
        "distinct reference positions",
    )
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
        body: impl Into<Body<D>>,
        material: M,
        shear: Shear,
        params: TlParams,
    ) -> Result<Self, Error> {
        let mut solver = Self::assemble(body.into(), material, shear, params)?;
        let grid = CellGrid::<D>::build(&solver.reference, solver.kernel.cutoff())?;
        let list = grid.neighbor_list(&solver.reference, solver.kernel.cutoff())?;
        drop(grid);
        if let Some(i) = (0..list.len()).find(|&i| list.count(i) < D::D) {
            return Err(Error::TooFewNeighbours {
                particle: i,
                found: list.count(i),
                required: D::D,
            });
        }
        solver.build_reference_data(list, |_| true)?;
        solver.refresh_rates();
        Ok(solver)
    }

    /// A solver of the whole body **to be distributed** ([`distribute`](super::distribute)): the particles and
    /// their initial state, to which constraints, loads and probes are attached as to
    /// [`TlSolver::new`]'s, but without the neighbour list, pair data and correction matrices
    /// of the whole body. Each rank builds those for its own particles and halo only, so no
    /// rank ever holds them for the whole body (docs/distributed.md). The results are those of
    /// [`TlSolver::new`], bit for bit. Such a solver cannot step before it is distributed.
    ///
    /// # Errors
    /// As [`TlSolver::new`], except the neighbour checks, which [`distribute`](super::distribute) makes.
    pub fn for_ranks(
        body: impl Into<Body<D>>,
        material: M,
        shear: Shear,
        params: TlParams,
    ) -> Result<Self, Error> {
        Self::assemble(body.into(), material, shear, params)
    }

    /// Whether the reference data wait for [`distribute`](super::distribute) ([`TlSolver::for_ranks`]).
    pub fn is_deferred(&self) -> bool {
        self.deferred
    }

    /// Refuses `what` on a solver whose neighbour data wait for [`distribute`](super::distribute).
    pub(super) fn built(&self, what: &str) -> Result<(), Error> {
        if self.deferred {
            return Err(Error::invalid(
                what,
                "a solver built for ranks (TlSolver::for_ranks)",
                "a solver distributed with sph_tl::distribute, or built with TlSolver::new",
            ));
        }
        Ok(())
    }

    /// The checked body, kernel and initial state, without any neighbour data: the state
    /// arrays that depend on them (`F`, `Ḟ`, stresses, accelerations, correction matrices) are
    /// left empty until [`Self::build_reference_data`].
    fn assemble(body: Body<D>, material: M, shear: Shear, params: TlParams) -> Result<Self, Error> {
        body.validate("tl body")?;
        body.reject_densities("tl")?;
        params.validate()?;
        shear.validate(params.hf_laplacian)?;
        let n = body.len();
        let velocities = body.velocities_or_rest();
        let constants = *material.constants();
        let density = constants.density;
        let sound_speed = constants.sound_speed;
        let kernel = WendlandC2::<D>::from_spacing(body.dp, params.h_over_dp)?;
        let reference = body.positions;
        let volumes = body.volumes;
        let gamma = if params.damping {
            damping_coefficient(density, sound_speed, kernel.h())
        } else {
            0.0
        };
        let masses = volumes.iter().map(|v| v * density).collect();
        let pairs = ReferencePairs::new(
            &NeighborList::default(),
            &reference,
            &volumes,
            &kernel,
            pair_scalar(shear),
            params.pair_storage,
        )
        .0;
        Ok(Self {
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
            list: NeighborList::default(),
            pairs,
            correction: Vec::new(),
            guarded: 0,
            deferred: true,
            velocities,
            deformation: Vec::new(),
            deformation_rate: Vec::new(),
            accelerations: Vec::new(),
            plasticity: None,
            plastic: Vec::new(),
            stress: Vec::new(),
            isochoric: Vec::new(),
            hf_zeta: Vec::new(),
            constraints: Constraints::new(),
            free: vec![true; n],
            loads: Loads::new(),
            pressures: Vec::new(),
            probes: Vec::new(),
            schedule: ProbeSchedule::every(0.0)?,
            tools: ToolSet::default(),
            grip_meters: Vec::new(),
            series: Vec::new(),
            relaxation: None,
            held_axes: [false; 3],
            dp: body.dp,
            time: 0.0,
            steps: 0,
            max_speed: 0.0,
            max_acceleration: 0.0,
            min_stretch: 1.0,
            max_stretch: 1.0,
            domain: None,
            contact: None,
            contact_scale: DEFAULT_CONTACT_SCALE,
            contact_friction: None,
        })
    }

    /// Builds the reference data of the current particles over the neighbour list `list`:
    /// pair data, correction matrices (the guarded ones counted where `counted`) and the state
    /// arrays of their size (`F = I`, `Ḟ = 0`). Does not refresh the rates.
    ///
    /// # Errors
    /// Coincident reference positions (a neighbour at zero distance).
    pub(super) fn build_reference_data(
        &mut self,
        list: NeighborList,
        counted: impl Fn(usize) -> bool + Sync + Send,
    ) -> Result<(), Error> {
        let n = self.reference.len();
        let (pairs, coincident) = ReferencePairs::new(
            &list,
            &self.reference,
            &self.volumes,
            &self.kernel,
            pair_scalar(self.shear),
            self.params.pair_storage,
        );
        if let Some(k) = coincident {
            let i = list.offsets().partition_point(|&o| o <= k) - 1;
            return Err(coincident_error(i));
        }
        let corr = correction_matrices_counted::<D, _>(
            &list,
            &self.reference,
            &self.kernel,
            &self.volumes,
            self.params.correction_min_eigenvalue,
            counted,
        )?;
        self.list = list;
        self.pairs = pairs;
        self.correction = corr.matrices;
        self.guarded = corr.guarded;
        self.deformation = vec![D::identity(); n];
        self.deformation_rate = vec![D::zero_matrix(); n];
        self.accelerations = vec![D::zero(); n];
        self.stress = vec![D::zero_matrix(); n];
        self.isochoric = if matches!(self.shear, Shear::HourglassFree { .. }) {
            vec![1.0; n]
        } else {
            Vec::new()
        };
        self.hf_zeta = if self.params.hf_laplacian == HfLaplacian::Normalised {
            with_pair_rows!(self.pair_view(), |rows| normalised_zeta::<D>(
                rows,
                &self.reference
            ))
        } else {
            Vec::new()
        };
        self.deferred = false;
        Ok(())
    }
}
