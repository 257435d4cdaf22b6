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
    /// A geometry file (mesh, outline) that cannot be read or filled.
    #[error("{file}: {message}")]
    Geometry {
        /// The file (or the name given to an in-memory mesh).
        file: String,
        /// What is wrong, with the counts that show it.
        message: String,
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

/// A number as an error message shows it: the shortest form that reads back to the same
/// value, in scientific notation outside `[1e-4, 1e6)` (`1e300`, not 301 digits; `2.5e-7`,
/// `1e13`), so a message stays one short line whatever the input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Num(pub f64);

impl std::fmt::Display for Num {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let x = self.0;
        if x == 0.0 || !x.is_finite() || (1e-4..1e6).contains(&x.abs()) {
            write!(f, "{x}")
        } else {
            write!(f, "{x:e}")
        }
    }
}

/// `Ok(())` if `value` is finite and `> 0`, else an error naming `field`.
pub fn check_positive(field: &str, value: f64) -> Result<(), Error> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(field, Num(value), "finite and > 0"))
    }
}

/// `Ok(())` if `value` is finite and `≥ 0`, else an error naming `field`.
pub fn check_non_negative(field: &str, value: f64) -> Result<(), Error> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(field, Num(value), "finite and >= 0"))
    }
}

/// `Ok(())` if `lo < value < hi` (open interval), else an error naming `field`.
pub fn check_open_range(field: &str, value: f64, lo: f64, hi: f64) -> Result<(), Error> {
    if value.is_finite() && value > lo && value < hi {
        Ok(())
    } else {
        Err(Error::invalid(
            field,
            Num(value),
            &format!("{} < {field} < {}", Num(lo), Num(hi)),
        ))
    }
}

/// `Ok(())` if `lo ≤ value ≤ hi` (closed interval), else an error naming `field`.
pub fn check_closed_range(field: &str, value: f64, lo: f64, hi: f64) -> Result<(), Error> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(Error::invalid(
            field,
            Num(value),
            &format!("{} <= {field} <= {}", Num(lo), Num(hi)),
        ))
    }
}

/// Longest name [`check_name`] accepts, bytes: a results file `<name>-<method>.h5` with its
/// temporary suffix (`.<pid>-<k>.tmp`) and lock suffix must stay within the 255 bytes a file
/// name may have.
pub const MAX_NAME_BYTES: usize = 128;

/// `Ok(())` if `name` is a name and cannot act as a path: 1 to [`MAX_NAME_BYTES`] bytes, no
/// `/` or `\`, not `.` or `..`, no control character (newline, tab, NUL, …). Scene, body,
/// probe, constraint, tool and series names become file names (`<scene>-<method>.h5`) and
/// HDF5 group names (`/probes/<probe>`), so a name that could climb out of the output
/// directory, make directories or break a line is refused before any work; `what` names it in
/// the error (`probe name`).
pub fn check_name(what: &str, name: &str) -> Result<(), Error> {
    let why = if name.is_empty() {
        Some("empty")
    } else if name.len() > MAX_NAME_BYTES {
        Some("too long")
    } else if name.contains(['/', '\\']) {
        Some("a path separator")
    } else if name == "." || name == ".." {
        Some("a directory name")
    } else if name.chars().any(char::is_control) {
        Some("a control character")
    } else {
        None
    };
    match why {
        None => Ok(()),
        Some(why) => Err(Error::invalid(
            what,
            format!("{name:?} ({why})"),
            &format!(
                "a name of 1 to {MAX_NAME_BYTES} bytes without `/`, `\\` or control characters, \
                 not `.` or `..`"
            ),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_in_messages_stay_short() {
        assert_eq!(Num(1e300).to_string(), "1e300");
        assert_eq!(Num(-1e300).to_string(), "-1e300");
        assert_eq!(Num(1e13).to_string(), "1e13");
        assert_eq!(Num(2.5e-7).to_string(), "2.5e-7");
        assert_eq!(Num(1100.0).to_string(), "1100");
        assert_eq!(Num(0.45).to_string(), "0.45");
        assert_eq!(Num(0.0).to_string(), "0");
        assert_eq!(Num(f64::NAN).to_string(), "NaN");
        let e = check_positive("density", -1e300).unwrap_err().to_string();
        assert_eq!(
            e,
            "invalid density = -1e300: allowed range is finite and > 0"
        );
        let e = check_closed_range("modulus", 1e14, 0.0, 1e13)
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "invalid modulus = 1e14: allowed range is 0 <= modulus <= 1e13"
        );
    }

    #[test]
    fn names_that_could_be_paths_are_refused() {
        for good in ["plate", "tip-probe_1", "Grip A", "ζ", "..x", "a.b"] {
            check_name("probe name", good).unwrap();
        }
        check_name("probe name", &"x".repeat(MAX_NAME_BYTES)).unwrap();
        for (bad, why) in [
            ("", "empty"),
            ("a/b", "a path separator"),
            ("/abs", "a path separator"),
            ("../up", "a path separator"),
            ("a\\b", "a path separator"),
            (".", "a directory name"),
            ("..", "a directory name"),
            ("new\nline", "a control character"),
            ("tab\there", "a control character"),
            ("nul\0", "a control character"),
        ] {
            let e = check_name("probe name", bad).unwrap_err().to_string();
            assert!(
                e.starts_with("invalid probe name = ") && e.contains(why),
                "{bad:?}: {e}"
            );
            assert_eq!(e.lines().count(), 1, "{e}");
        }
        let long = "x".repeat(MAX_NAME_BYTES + 1);
        assert!(check_name("name", &long)
            .unwrap_err()
            .to_string()
            .contains("too long"));
    }
}
