//! What a scene attaches to a built TL solver: constraints, rigid tools, the quasi-static
//! relaxation, a held centre, loads, surface pressure and probes, or a prescribed configuration.

use super::TlSolver;
use crate::original;
use crate::reference_pairs::with_pair_rows;
use sph_core::pressure::{ResolvedPressure, SurfacePressure};
use sph_core::relaxation::{PairwiseDamper, PairwiseDamping};
use sph_core::scene::ProbeSchedule;
use sph_core::tool::{ReactionMeter, RigidTool, ToolSet};
use sph_core::{Constraints, Dim, Error, Kernel, Loads, Probe, Solver};
use sph_materials::Material;

impl<D: Dim, M: Material<D>> TlSolver<D, M> {
    /// Attaches the constraints (applied to velocities and accelerations at the points of the
    /// scheme the paper prescribes); constrained particles are excluded from the time-step maxima.
    /// Named constraints (grips) record the reaction force they receive as a series
    /// `/series/<name>` with the mean position of their particles.
    pub fn with_constraints(mut self, constraints: Constraints<D>) -> Self {
        self.free = constraints.free_mask(self.len());
        self.constraints = constraints;
        self.grip_meters = vec![ReactionMeter::default(); self.constraints.named().count()];
        self.rebuild_series();
        self.refresh_rates();
        self
    }

    /// Attaches rigid tools in kinematic contact with the body, frictionless or with Coulomb
    /// friction (see [`sph_core::tool`] and [`sph_core::friction`]): contact offset the deformed
    /// half cell, applied after the velocity update, looking ahead one step from the half-step
    /// positions. Each tool records its travel, the mean reaction force it receives over each
    /// probe interval (and with friction its tangential part and the sticking fraction) as the
    /// series `/series/<name>`.
    ///
    /// # Errors
    /// As [`ToolSet::new`]: a tool name that is not a name, two tools (or a tool and a named
    /// constraint) with the same name, a tool at or above the body's sound speed.
    pub fn with_tools(mut self, tools: Vec<RigidTool<D>>) -> Result<Self, Error> {
        let names: Vec<&str> = self.constraints.named().map(|(_, n)| n).collect();
        self.tools = ToolSet::new(tools, &names, self.sound_speed)?;
        self.rebuild_series();
        self.update_stretch_extremes();
        Ok(self)
    }

    /// Attaches the quasi-static relaxation of the TL paper's punching and pulling cases (the
    /// splitting random-choice pairwise damping, [`sph_core::relaxation`]) over the reference
    /// neighbour list, applied to the velocities right after their update (before contact and
    /// constraints), as SPHinXsys applies it between the two halves of the step.
    ///
    /// # Errors
    /// Invalid damping parameters.
    pub fn with_relaxation(mut self, damping: PairwiseDamping) -> Result<Self, Error> {
        if self.deferred {
            return Err(Error::invalid(
                "ranks",
                "a solver built for ranks",
                "1 for a TL run with the pairwise relaxation (not distributed yet)",
            ));
        }
        self.relaxation = Some(PairwiseDamper::new::<D, _>(
            damping,
            &self.list,
            &self.reference,
            &self.kernel,
            &self.volumes,
        )?);
        Ok(self)
    }

    /// Holds the centre of mass of the free particles still along the selected axes: after
    /// each velocity update, the free particles' mass-weighted mean velocity along those axes
    /// is removed. For a body whose rigid motion nothing else fixes and whose symmetric state
    /// is unstable (a strip between frictionless punches slides sideways once it wraps around
    /// their corners): a symmetry condition on the rigid mode only, which leaves the
    /// deformation free. It acts like an external force, so momentum along those axes is not
    /// conserved but held at its value (zero for a body at rest).
    pub fn with_centre_held(mut self, axes: [bool; 3]) -> Self {
        self.held_axes = axes;
        self
    }

    /// Attaches body accelerations and point forces.
    pub fn with_loads(mut self, loads: Loads<D>) -> Self {
        self.loads = loads;
        self
    }

    /// Adds a follower surface pressure (see [`sph_core::pressure`]), applied with the loads at
    /// the half step, with `F` of the half step. Normals left `None` are estimated from the
    /// reference neighbourhood (`N_i ∥ −Σ_j W_ij (X_j − X_i)`); a solver built for ranks needs
    /// them given.
    ///
    /// # Errors
    /// Particle indices outside the body, normals or areas of the wrong length, zero or
    /// non-finite normals, non-positive areas, or an interior particle with estimated normals.
    pub fn with_surface_pressure(mut self, sp: SurfacePressure<D>) -> Result<Self, Error> {
        if sp.normals.is_none() {
            self.built("surface pressure with estimated normals")?;
        }
        let (list, x0, kernel) = (&self.list, &self.reference, &self.kernel);
        let resolved = ResolvedPressure::resolve(sp, self.len(), self.dp, |i| {
            list.neighbors(i).iter().fold(D::zero(), |s, &j| {
                let x = x0[j as usize] - x0[i];
                s + x * kernel.w(D::norm(x))
            })
        })?;
        self.pressures.push(resolved);
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

    /// Replaces the current state by positions `x` and velocities `v`, with `F` computed from
    /// `x` by the corrected SPH gradient (the state a prescribed deformation gives), and `Ḟ` from
    /// `v`. For tests and for starting from a pre-deformed state.
    pub fn set_configuration(&mut self, x: Vec<D::Vector>, v: Vec<D::Vector>) -> Result<(), Error> {
        self.built("set_configuration")?;
        let n = self.len();
        if x.len() != n || v.len() != n {
            return Err(Error::invalid(
                "configuration",
                format!("{} positions, {} velocities", x.len(), v.len()),
                &format!("{n} of each"),
            ));
        }
        self.deformation = with_pair_rows!(self.pair_view(), |rows| {
            original::deformation_gradient::<D>(rows, &self.correction, &self.reference, &x)
        });
        self.positions = x;
        self.velocities = v;
        self.refresh_rates();
        self.update_stretch_extremes();
        Ok(())
    }
}
