//! Dual-criteria time stepping (UL paper §5, eq 21–22).

use serde::{Deserialize, Serialize};

/// How [`crate::UlSolver`] advances in time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Stepping {
    /// Dual criteria (§5): one `Solver::step` is one advection step (eq 21) with the neighbour
    /// list, kernel data and correction matrix rebuilt at its start and frozen over its acoustic
    /// sub-steps (eq 22).
    #[default]
    Dual,
    /// Single criterion (the baseline of Tables 2 and 4): one `Solver::step` is one acoustic step
    /// (eq 22) with a rebuild before it.
    Single,
}

/// Eq. (21) of the UL paper: `Δt_ad = CFL_ad h / |v|max`, with `|v|max` floored by a reference
/// speed so a body at rest gets a finite step.
#[inline]
pub fn advection_dt(cfl: f64, h: f64, max_speed: f64, speed_floor: f64) -> f64 {
    cfl * h / max_speed.max(speed_floor)
}

/// Eq. (22) of the UL paper: `Δt_ac = CFL_ac h / (c0 + |v|max)`.
#[inline]
pub fn acoustic_dt(cfl: f64, h: f64, c0: f64, max_speed: f64) -> f64 {
    cfl * h / (c0 + max_speed)
}

/// Length of the next acoustic sub-step given the stable `dt` and what `remaining` of the
/// advection step is left: the stable step, the whole remainder if it fits, and half the
/// remainder if it fits in two (so the last sub-step is never a sliver).
#[inline]
pub fn next_substep(dt: f64, remaining: f64) -> f64 {
    if remaining <= dt {
        remaining
    } else if remaining <= 2.0 * dt {
        0.5 * remaining
    } else {
        dt
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn substeps_fill_the_advection_step_exactly_without_slivers() {
        let (dt, total) = (0.3, 1.0);
        let mut t = 0.0;
        let mut steps = Vec::new();
        while total - t > 0.0 {
            let s = next_substep(dt, total - t);
            steps.push(s);
            t += s;
        }
        assert!((t - total).abs() < 1e-15);
        assert!(steps.iter().all(|&s| s <= dt && s >= 0.5 * 0.1));
        assert_eq!(steps.len(), 4);
    }
}
