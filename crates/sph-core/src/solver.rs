//! The [`Solver`] trait every method implements, and the output field type.

use crate::dim::Dim;
use crate::error::Error;
use crate::scene::{Probe, Series};

/// A named per-particle output field, computed on demand (only when written).
#[derive(Clone, Debug)]
pub enum Field<D: Dim> {
    /// One scalar per particle (von Mises stress, J, density, disorder).
    Scalar(Vec<f64>),
    /// One vector per particle.
    Vector(Vec<D::Vector>),
    /// One matrix per particle (deformation gradient, stress).
    Matrix(Vec<D::Matrix>),
}

impl<D: Dim> Field<D> {
    /// The entries at `rows`, in that order (a rank's own particles of a local field).
    pub fn pick(&self, rows: &[u32]) -> Self {
        fn take<T: Copy>(v: &[T], rows: &[u32]) -> Vec<T> {
            rows.iter().map(|&r| v[r as usize]).collect()
        }
        match self {
            Field::Scalar(v) => Field::Scalar(take(v, rows)),
            Field::Vector(v) => Field::Vector(take(v, rows)),
            Field::Matrix(v) => Field::Matrix(take(v, rows)),
        }
    }
}

/// What one step did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepInfo {
    /// The time step taken.
    pub dt: f64,
    /// Simulated time after the step.
    pub time: f64,
    /// Steps taken so far (after this one).
    pub step: u64,
}

/// An energy budget: named terms whose sum the continuous problem conserves, so that the
/// discrete scheme's error shows as one number, the residual `total − initial_total`.
///
/// `terms` holds stored energies (kinetic, elastic parts, contact) and accumulated transfers
/// with the sign that keeps the sum constant (energy dissipated counts positive, work done on
/// the body by forces outside the model negative). `notes` holds diagnostics that are not part
/// of the sum, e.g. an exactly accumulated work beside the energy estimate that stands in the
/// sum.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EnergyBudget {
    /// Terms of the conserved total.
    pub terms: Vec<(&'static str, f64)>,
    /// Diagnostics outside the total.
    pub notes: Vec<(&'static str, f64)>,
    /// The total at `t = 0`.
    pub initial_total: f64,
}

impl EnergyBudget {
    /// Sum of the terms.
    pub fn total(&self) -> f64 {
        self.terms.iter().map(|t| t.1).sum()
    }

    /// `total − initial_total`: zero for a scheme that conserves what the terms account for.
    pub fn residual(&self) -> f64 {
        self.total() - self.initial_total
    }

    /// The term or note called `name`.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.terms
            .iter()
            .chain(&self.notes)
            .find(|t| t.0 == name)
            .map(|t| t.1)
    }
}

/// A particle method advancing one body (or a set of interacting bodies) in time.
pub trait Solver<D: Dim>: Send {
    /// Method name as the command line spells it (`tl-hf`, `ul-enog`, `mps`, ...).
    fn method(&self) -> &'static str;

    /// Advances by one step of `min(stable Δt, max_dt)`, so a caller can land exactly on
    /// snapshot times. Errors stop the run cleanly (non-finite values, lost neighbours), leaving
    /// the state of the last good step readable.
    fn step(&mut self, max_dt: f64) -> Result<StepInfo, Error>;

    /// The stable time step the next step would take (before the `max_dt` cap).
    fn stable_dt(&self) -> f64;

    /// The blow-up guard [`Solver::step`] applies before it moves anything:
    /// [`Error::TimeStepCollapsed`] when the step the current state allows (its speeds and
    /// accelerations) is below the method's floor, a small fraction of the acoustic step at
    /// rest ([`crate::diagnostics::MIN_DT_RATIO`]). A run driver calls it before the run, so
    /// that a state that cannot take its first step (a body thrown far faster than its sound
    /// speed, a very soft material) is refused before anything is written. Default: no guard.
    fn check_time_step(&self) -> Result<(), Error> {
        Ok(())
    }

    /// The shortest step one call of [`Solver::step`] is made of: [`Solver::stable_dt`] unless
    /// the method sub-steps (UL's dual stepping: the acoustic step). Run drivers estimate the
    /// work of a run from it before they start.
    fn substep_dt(&self) -> f64 {
        self.stable_dt()
    }

    /// Simulated time.
    fn time(&self) -> f64;

    /// Steps taken.
    fn step_count(&self) -> u64;

    /// Number of particles.
    fn len(&self) -> usize {
        self.positions().len()
    }

    /// Whether the body has no particles (never true for a validly built solver).
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Current positions.
    fn positions(&self) -> &[D::Vector];

    /// Current velocities.
    fn velocities(&self) -> &[D::Vector];

    /// The identity of each particle in the current storage order: `particle_ids()[k]` is the
    /// index, in the body the solver was built from, of the particle now stored at `k` (so it
    /// is a permutation of `0..len()`). The identity by default; a method that reorders its
    /// particles (UL's spatial sort) returns its permutation, so output written at different
    /// times can be matched particle by particle.
    fn particle_ids(&self) -> std::borrow::Cow<'_, [u32]> {
        std::borrow::Cow::Owned((0..self.len() as u32).collect())
    }

    /// Names of the fields [`Solver::field`] can compute.
    fn field_names(&self) -> Vec<&'static str>;

    /// Computes a named output field, or `None` for an unknown name.
    fn field(&self, name: &str) -> Option<Field<D>>;

    /// The probes attached by the scene, with what they recorded.
    fn probes(&self) -> &[Probe<D>];

    /// Other recorded time series (tool and grip reactions, ...); none by default.
    fn series(&self) -> Vec<Series> {
        Vec::new()
    }

    /// Kinetic energy `Σ ½ m v²` and strain energy `Σ V⁰ ψ`, for methods with a strain energy.
    fn energies(&self) -> Option<(f64, f64)> {
        None
    }

    /// Total linear momentum `Σ m v` (3-vector; z = 0 in 2D), for methods that track masses.
    fn momentum(&self) -> Option<glam::DVec3> {
        None
    }

    /// Writes everything the next [`Solver::step`] reads that the scene does not determine:
    /// positions, velocities, the method's evolving fields, time, step count, probe and series
    /// records (see [`crate::state`]). Not the neighbour list or anything derived from the
    /// reference configuration: [`Solver::restore_state`] is called on a solver freshly built
    /// from the same scene, which has them. A run restored from this state continues
    /// bit-identically. The default: this solver cannot save its state (an error).
    fn save_state(&self, out: &mut crate::StateWriter) -> Result<(), Error> {
        let _ = out;
        Err(Error::Checkpoint(format!(
            "the method {} cannot save its state",
            self.method()
        )))
    }

    /// Reads back what [`Solver::save_state`] wrote, into a solver freshly built from the same
    /// scene (same case, parameters and method: a mismatch of names or sizes is an
    /// [`Error::Checkpoint`]), and rebuilds what depends on the state (neighbour lists).
    fn restore_state(&mut self, input: &mut crate::StateReader<'_>) -> Result<(), Error> {
        let _ = input;
        Err(Error::Checkpoint(format!(
            "the method {} cannot restore a state",
            self.method()
        )))
    }

    /// The energy budget (see [`EnergyBudget`]), for methods that keep one.
    fn energy_budget(&self) -> Option<EnergyBudget> {
        None
    }

    /// Neighbour pairs visited by the force evaluations so far (directed pairs summed over
    /// evaluations): the machine-independent work of the run, for cost comparisons between
    /// methods. `None` if the solver does not count it.
    fn pair_visits(&self) -> Option<u64> {
        None
    }

    /// Counters and checks particular to the method, by name, for the run's summary (UL:
    /// acoustic sub-steps, neighbour rebuilds, isolated particles, the momentum balance); none
    /// by default. Read by the case's summary, so the results file carries them too.
    fn figures(&self) -> Vec<(&'static str, f64)> {
        Vec::new()
    }

    /// Number of ranks the run is distributed over (1 unless the solver is a
    /// [`crate::distributed::DistributedSolver`]).
    fn ranks(&self) -> usize {
        1
    }

    /// In a distributed run, the particles this process owns, read without gathering (what
    /// its per-rank results file holds); `None` on one process, where the whole body is the
    /// process's share.
    fn owned_share(&self) -> Option<crate::distributed::OwnedShare<'_, D>> {
        None
    }

    /// Advances until `time() ≥ t_end` (the last step is shortened to land on it). Returns the
    /// number of steps taken.
    fn advance_to(&mut self, t_end: f64) -> Result<u64, Error> {
        let mut n = 0;
        while self.time() < t_end {
            let remaining = t_end - self.time();
            // Guard against a last step too small to change `time` in floating point.
            if remaining <= 1e-14 * t_end.abs().max(1e-300) {
                break;
            }
            self.step(remaining)?;
            n += 1;
        }
        Ok(n)
    }
}

/// The kinematic output fields every total-Lagrangian method (one with a deformation gradient
/// per particle) shares: `velocity`, `displacement` (x − X), `jacobian` (det F), `density`
/// (ρ0/J) and `deformation_gradient`. `None` for any other name, so a solver handles its own
/// fields (stress, disorder) and falls back to this.
pub fn deformation_field<D: Dim>(
    name: &str,
    positions: &[D::Vector],
    reference: &[D::Vector],
    velocities: &[D::Vector],
    deformation: &[D::Matrix],
    density: f64,
) -> Option<Field<D>> {
    Some(match name {
        "velocity" => Field::Vector(velocities.to_vec()),
        "displacement" => Field::Vector(
            positions
                .iter()
                .zip(reference)
                .map(|(&x, &x0)| x - x0)
                .collect(),
        ),
        "jacobian" => Field::Scalar(deformation.iter().map(|&f| D::det(f)).collect()),
        "density" => Field::Scalar(deformation.iter().map(|&f| density / D::det(f)).collect()),
        "deformation_gradient" => Field::Matrix(deformation.to_vec()),
        _ => return None,
    })
}

/// Names of the fields [`deformation_field`] computes.
pub const DEFORMATION_FIELDS: [&str; 5] = [
    "velocity",
    "displacement",
    "jacobian",
    "density",
    "deformation_gradient",
];

/// Index of the first non-finite vector, if any (run-time blow-up detection).
pub fn first_non_finite<D: Dim>(v: &[D::Vector]) -> Option<usize> {
    v.iter().position(|&x| !D::is_finite(x))
}
