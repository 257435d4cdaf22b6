//! Amplitude curves: dimensionless functions of time `a(t)` that scale a prescribed quantity,
//! as in finite-element input files (a load or a velocity is a magnitude times an amplitude).
//! A grip pulled at `v a(t)` with a [`Amplitude::SmoothStep`] starts without a jolt; a
//! pressure `p a(t)` with a [`Amplitude::Table`] follows a measured history.
//!
//! ```
//! use sph_core::Amplitude;
//!
//! let a = Amplitude::smooth_step(0.0, 1e-3)?;          // 0 → 1 over the first millisecond
//! assert_eq!((a.at(0.0), a.at(5e-4), a.at(2e-3)), (0.0, 0.5, 1.0));
//! let t = Amplitude::table(vec![(0.0, 0.0), (1.0, 2.0), (2.0, 2.0)])?;
//! assert_eq!((t.at(0.5), t.integral(2.0)), (1.0, 3.0));
//! # Ok::<(), sph_core::Error>(())
//! ```

use crate::error::{check_non_negative, check_positive, Error};
use std::f64::consts::PI;

/// A dimensionless function of time. Before its start a ramp or step is 0; after its end, 1
/// (a table holds its first and last values beyond its ends).
#[derive(Clone, Debug, PartialEq)]
pub enum Amplitude {
    /// Linear from 0 at `start` to 1 at `start + duration`, then 1.
    Ramp {
        /// When the ramp begins (s).
        start: f64,
        /// How long it takes (s).
        duration: f64,
    },
    /// From 0 at `start` to 1 at `start + duration` along `ξ³(10 − 15ξ + 6ξ²)`,
    /// `ξ = (t − start)/duration` (Abaqus' smooth step): value, slope and curvature are continuous,
    /// so a velocity scaled by it starts with zero acceleration and zero jerk.
    SmoothStep {
        /// When the step begins (s).
        start: f64,
        /// How long it takes (s).
        duration: f64,
    },
    /// Piecewise linear through the points `(t_k, a_k)` (times strictly increasing); `a_0`
    /// before the first, the last value after the last.
    Table(Vec<(f64, f64)>),
    /// `offset + amplitude · sin(2π frequency · t + phase)`.
    Sine {
        /// Frequency (Hz).
        frequency: f64,
        /// Amplitude of the oscillation (dimensionless).
        amplitude: f64,
        /// Phase at `t = 0` (rad).
        phase: f64,
        /// Mean value (dimensionless).
        offset: f64,
    },
}

impl Amplitude {
    /// [`Amplitude::Ramp`], checked.
    ///
    /// # Errors
    /// A negative or non-finite start, a duration that is not positive and finite.
    pub fn ramp(start: f64, duration: f64) -> Result<Self, Error> {
        check_non_negative("ramp start", start)?;
        check_positive("ramp duration", duration)?;
        Ok(Amplitude::Ramp { start, duration })
    }

    /// [`Amplitude::SmoothStep`], checked.
    ///
    /// # Errors
    /// As [`Amplitude::ramp`].
    pub fn smooth_step(start: f64, duration: f64) -> Result<Self, Error> {
        check_non_negative("smooth-step start", start)?;
        check_positive("smooth-step duration", duration)?;
        Ok(Amplitude::SmoothStep { start, duration })
    }

    /// [`Amplitude::Table`], checked.
    ///
    /// # Errors
    /// No point, a non-finite time or value, or times not strictly increasing.
    pub fn table(points: Vec<(f64, f64)>) -> Result<Self, Error> {
        if points.is_empty() {
            return Err(Error::invalid(
                "table",
                "[]",
                "at least one point [time, value]",
            ));
        }
        for (k, &(t, a)) in points.iter().enumerate() {
            if !(t.is_finite() && a.is_finite()) {
                return Err(Error::invalid(
                    &format!("table point {k}"),
                    format!("[{t}, {a}]"),
                    "finite time and value",
                ));
            }
            if k > 0 && t <= points[k - 1].0 {
                return Err(Error::invalid(
                    &format!("table point {k} time"),
                    t,
                    &format!("> {} (times strictly increasing)", points[k - 1].0),
                ));
            }
        }
        Ok(Amplitude::Table(points))
    }

    /// [`Amplitude::Sine`], checked.
    ///
    /// # Errors
    /// A frequency that is not positive and finite; a non-finite amplitude, phase or offset.
    pub fn sine(frequency: f64, amplitude: f64, phase: f64, offset: f64) -> Result<Self, Error> {
        check_positive("sine frequency", frequency)?;
        for (name, v) in [
            ("sine amplitude", amplitude),
            ("sine phase", phase),
            ("sine offset", offset),
        ] {
            if !v.is_finite() {
                return Err(Error::invalid(name, v, "finite"));
            }
        }
        Ok(Amplitude::Sine {
            frequency,
            amplitude,
            phase,
            offset,
        })
    }

    /// The largest `|a(t)|` over all times.
    pub fn max_abs(&self) -> f64 {
        match self {
            Amplitude::Ramp { .. } | Amplitude::SmoothStep { .. } => 1.0,
            Amplitude::Table(points) => points.iter().map(|p| p.1.abs()).fold(0.0, f64::max),
            Amplitude::Sine {
                amplitude, offset, ..
            } => offset.abs() + amplitude.abs(),
        }
    }

    /// The value at time `t`.
    pub fn at(&self, t: f64) -> f64 {
        match self {
            Amplitude::Ramp { start, duration } => ((t - start) / duration).clamp(0.0, 1.0),
            Amplitude::SmoothStep { start, duration } => {
                let x = ((t - start) / duration).clamp(0.0, 1.0);
                x * x * x * (10.0 - 15.0 * x + 6.0 * x * x)
            }
            Amplitude::Table(points) => table_value(points, t),
            Amplitude::Sine {
                frequency,
                amplitude,
                phase,
                offset,
            } => offset + amplitude * (2.0 * PI * frequency * t + phase).sin(),
        }
    }

    /// `∫₀ᵗ a(s) ds` (s), in closed form: the displacement of a tool moving at `v a(t)`.
    pub fn integral(&self, t: f64) -> f64 {
        if t <= 0.0 {
            return 0.0;
        }
        match self {
            Amplitude::Ramp { start, duration } => {
                let s = (t - start).max(0.0);
                if s < *duration {
                    0.5 * s * s / duration
                } else {
                    0.5 * duration + (s - duration)
                }
            }
            Amplitude::SmoothStep { start, duration } => {
                let s = (t - start).max(0.0);
                if s < *duration {
                    let x = s / duration;
                    duration * x * x * x * x * (2.5 - 3.0 * x + x * x)
                } else {
                    0.5 * duration + (s - duration)
                }
            }
            Amplitude::Table(points) => table_integral(points, t),
            Amplitude::Sine {
                frequency,
                amplitude,
                phase,
                offset,
            } => {
                let w = 2.0 * PI * frequency;
                offset * t - amplitude / w * ((w * t + phase).cos() - phase.cos())
            }
        }
    }
}

/// Linear interpolation in a table held constant beyond its ends.
fn table_value(points: &[(f64, f64)], t: f64) -> f64 {
    let k = points.partition_point(|p| p.0 <= t);
    if k == 0 {
        return points[0].1;
    }
    if k == points.len() {
        return points[k - 1].1;
    }
    let ((t0, a0), (t1, a1)) = (points[k - 1], points[k]);
    a0 + (a1 - a0) * (t - t0) / (t1 - t0)
}

/// `∫₀ᵗ` of [`table_value`]: trapezoids over the pieces of `[0, t]`.
fn table_integral(points: &[(f64, f64)], t: f64) -> f64 {
    // Breakpoints inside (0, t), with the ends.
    let mut knots = vec![0.0];
    knots.extend(points.iter().map(|p| p.0).filter(|&s| s > 0.0 && s < t));
    knots.push(t);
    knots
        .windows(2)
        .map(|w| 0.5 * (w[1] - w[0]) * (table_value(points, w[0]) + table_value(points, w[1])))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed-form integrals against a fine midpoint rule (tolerance: the rule's error,
    /// O(h²) of the second derivative, well under 1e-9 with 2e5 intervals).
    #[test]
    fn integrals_match_quadrature() {
        let curves = [
            Amplitude::ramp(0.1, 0.3).unwrap(),
            Amplitude::smooth_step(0.0, 0.5).unwrap(),
            Amplitude::table(vec![(-1.0, 0.5), (0.2, 1.0), (0.4, -1.0), (0.9, 3.0)]).unwrap(),
            Amplitude::table(vec![(0.3, 2.0)]).unwrap(),
            Amplitude::sine(2.0, 0.5, 0.3, 1.0).unwrap(),
        ];
        for a in &curves {
            for t in [0.05, 0.25, 0.45, 1.3] {
                let n = 200_000;
                let h = t / n as f64;
                let q: f64 = (0..n).map(|k| a.at((k as f64 + 0.5) * h) * h).sum();
                assert!((q - a.integral(t)).abs() < 1e-9, "{a:?} t = {t}: {q}");
            }
        }
    }

    #[test]
    fn steps_start_at_zero_and_end_at_one_smoothly() {
        let s = Amplitude::smooth_step(1.0, 2.0).unwrap();
        assert_eq!(
            (s.at(0.5), s.at(1.0), s.at(3.0), s.at(9.0)),
            (0.0, 0.0, 1.0, 1.0)
        );
        assert_eq!(s.at(2.0), 0.5);
        // Zero slope at both ends (one-sided differences, tolerance O(h²) = 1e-12).
        let h = 1e-6;
        assert!((s.at(1.0 + h) - s.at(1.0)) / h < 1e-9);
        assert!((s.at(3.0) - s.at(3.0 - h)) / h < 1e-9);
        let r = Amplitude::ramp(0.0, 4.0).unwrap();
        assert_eq!((r.at(-1.0), r.at(1.0), r.at(5.0)), (0.0, 0.25, 1.0));
    }

    #[test]
    fn bad_curves_are_refused_naming_the_field() {
        let e = Amplitude::ramp(0.0, 0.0).unwrap_err().to_string();
        assert!(e.contains("ramp duration"), "{e}");
        let e = Amplitude::table(vec![(0.0, 1.0), (0.0, 2.0)])
            .unwrap_err()
            .to_string();
        assert!(e.contains("table point 1 time"), "{e}");
        assert!(Amplitude::table(Vec::new()).is_err());
        assert!(Amplitude::sine(0.0, 1.0, 0.0, 0.0).is_err());
        assert!(Amplitude::sine(1.0, f64::NAN, 0.0, 0.0).is_err());
    }
}
