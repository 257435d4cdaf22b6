//! Errors shared by every crate: invalid input that names the field and the allowed range, and
//! run-time failures (non-finite values, particles that lost their neighbours).

use thiserror::Error as ThisError;

/// An error from building or running a simulation.
#[derive(Debug, Clone, PartialEq, ThisError)]
pub enum Error {
    /// A parameter is outside its allowed range.
    #[error("invalid {field} = {value}: allowed range is {allowed}")]
    InvalidParameter {
        /// The parameter's name as the user writes it (case key or field name).
        field: String,
        /// The rejected value, formatted.
        value: String,
        /// The allowed range, in words.
        allowed: String,
    },
    /// A body or particle set has no particles.
    #[error("body `{body}` has no particles")]
    EmptyBody {
        /// Name of the body.
        body: String,
    },
    /// A particle has too few neighbours for the method (e.g. the correction matrix).
    #[error("particle {particle} has {found} neighbours; the method needs at least {required}")]
    TooFewNeighbours {
        /// Index of the particle.
        particle: usize,
        /// Number of neighbours found.
        found: usize,
        /// Number required.
        required: usize,
    },
    /// A field became NaN or infinite during a run.
    #[error("non-finite {field} at particle {particle}, step {step}, time {time:e}")]
    NonFinite {
        /// Which field (position, velocity, deformation gradient, ...).
        field: String,
        /// First offending particle.
        particle: usize,
        /// Step number at which it was detected.
        step: u64,
        /// Simulated time at which it was detected.
        time: f64,
    },
    /// The time step collapsed (blow-up or a particle with huge acceleration).
    #[error("time step {dt:e} fell below the minimum {min:e} at step {step}, time {time:e}")]
    TimeStepCollapsed {
        /// The computed time step.
        dt: f64,
        /// The smallest allowed.
        min: f64,
        /// Step number.
        step: u64,
        /// Simulated time.
        time: f64,
    },
    /// The run took as many steps as it was allowed (the `max_steps` key) before its end time:
    /// its time step has become far smaller than planned.
    #[error(
        "the step limit max_steps = {limit} was reached at time {time:e}, before the end time \
         {end:e} (mean step so far {mean_dt:e})"
    )]
    StepLimitReached {
        /// The limit.
        limit: u64,
        /// Simulated time reached.
        time: f64,
        /// The end time the run was going to.
        end: f64,
        /// Simulated time over steps so far.
        mean_dt: f64,
    },
    /// A generator would make more particles than the memory budget allows (see
    /// [`crate::budget`]); nothing was allocated.
    #[error("{what} would generate ≈ {particles} particles needing ≈ {memory} of memory, more than the limit of {limit}")]
    TooManyParticles {
        /// The generator call (e.g. `annulus_polar at dp = 1e-6`).
        what: String,
        /// The estimated particle count, formatted.
        particles: String,
        /// The estimated peak memory of the run, formatted.
        memory: String,
        /// The limit and where it comes from.
        limit: String,
    },
    /// A particle became inverted: its volume ratio `J = det F` (or `ρ0/ρ`) is not positive.
    #[error("particle {particle} inverted (J = {jacobian:e} <= 0) at step {step}, time {time:e}")]
    Inverted {
        /// The particle.
        particle: usize,
        /// Its `J`.
        jacobian: f64,
        /// Step number.
        step: u64,
        /// Simulated time.
        time: f64,
    },
    /// A particle lost all its neighbours (fracture or blow-up in an updated-Lagrangian run).
    #[error("particle {particle} lost all its neighbours at step {step}, time {time:e}")]
    LostNeighbours {
        /// The particle.
        particle: usize,
        /// Step number.
        step: u64,
        /// Simulated time.
        time: f64,
    },
    /// A checkpoint's solver state does not fit this solver (another case, parameters or
    /// method), is damaged, or the solver cannot save its state.
    #[error("checkpoint: {0}")]
    Checkpoint(String),
}

impl Error {
    /// An [`Error::InvalidParameter`] for `field` with `value` outside `allowed`.
    pub fn invalid(field: &str, value: impl std::fmt::Display, allowed: &str) -> Self {
        Error::InvalidParameter {
            field: field.to_string(),
            value: value.to_string(),
            allowed: allowed.to_string(),
        }
    }
}

/// `Ok(())` if `value` is finite and `> 0`, else an error naming `field`.
pub fn check_positive(field: &str, value: f64) -> Result<(), Error> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(field, value, "finite and > 0"))
    }
}

/// `Ok(())` if `value` is finite and `≥ 0`, else an error naming `field`.
pub fn check_non_negative(field: &str, value: f64) -> Result<(), Error> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(field, value, "finite and >= 0"))
    }
}

/// `Ok(())` if `lo < value < hi` (open interval), else an error naming `field`.
pub fn check_open_range(field: &str, value: f64, lo: f64, hi: f64) -> Result<(), Error> {
    if value.is_finite() && value > lo && value < hi {
        Ok(())
    } else {
        Err(Error::invalid(
            field,
            value,
            &format!("{lo} < {field} < {hi}"),
        ))
    }
}
