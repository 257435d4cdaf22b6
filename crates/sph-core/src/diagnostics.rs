//! Whole-body diagnostics every solver reports the same way: momenta, kinetic energy, speed
//! maxima for time-step criteria, and the run-time check for non-finite state.

use crate::dim::Dim;
use crate::error::Error;
use glam::DVec3;

/// Total linear momentum `Σ m v`.
pub fn linear_momentum<D: Dim>(velocities: &[D::Vector], masses: &[f64]) -> D::Vector {
    velocities
        .iter()
        .zip(masses)
        .fold(D::zero(), |s, (&v, &m)| s + v * m)
}

/// Total angular momentum `Σ m x × v` about the origin (3-vector; only `z` is non-zero in 2D).
pub fn angular_momentum<D: Dim>(
    positions: &[D::Vector],
    velocities: &[D::Vector],
    masses: &[f64],
) -> DVec3 {
    positions
        .iter()
        .zip(velocities)
        .zip(masses)
        .fold(DVec3::ZERO, |s, ((&x, &v), &m)| {
            s + D::to_vec3(x).cross(D::to_vec3(v)) * m
        })
}

/// Kinetic energy `Σ ½ m v²`.
pub fn kinetic_energy<D: Dim>(velocities: &[D::Vector], masses: &[f64]) -> f64 {
    0.5 * velocities
        .iter()
        .zip(masses)
        .map(|(&v, &m)| m * D::norm_squared(v))
        .sum::<f64>()
}

/// Largest `|v|` over the particles whose `mask` entry is true (e.g. the unconstrained ones, for
/// the time-step criteria). The maximum is exact, so the parallel reduction is deterministic.
pub fn max_norm_where<D: Dim>(v: &[D::Vector], mask: &[bool]) -> f64 {
    crate::parallel::max_over(v.len(), 0.0, |i| {
        if mask[i] {
            D::norm_squared(v[i])
        } else {
            0.0
        }
    })
    .sqrt()
}

/// The collapse threshold every method states (and TL's default `min_dt_ratio`): a run stops
/// with [`Error::TimeStepCollapsed`] when its stable time step falls below this fraction of its
/// acoustic step at rest (`CFL h/c0`). The step criteria then signal `|v| > 999 c0` or
/// `|a| > 10⁶ c0²/h`: a collapsed pair of particles or an inverted element, and going on would
/// take a thousand steps to get as far as one normal step.
pub const MIN_DT_RATIO: f64 = 1e-3;

/// `Ok` if the stable step `stable` is finite and above `floor`; otherwise
/// [`Error::TimeStepCollapsed`] (a NaN step, from a NaN speed, is a collapse too).
pub fn check_time_step(stable: f64, floor: f64, step: u64, time: f64) -> Result<(), Error> {
    if stable.is_finite() && stable > floor {
        Ok(())
    } else {
        Err(Error::TimeStepCollapsed {
            dt: stable,
            min: floor,
            step,
            time,
        })
    }
}

/// The larger of `a` and `b`, NaN if either is (unlike `f64::max`, which drops a NaN): for
/// maxima that feed time-step criteria, so a NaN speed stops the run instead of being ignored.
pub fn max_or_nan(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// [`Error::Inverted`] naming the first particle whose deformation gradient has `det F ≤ 0`
/// (or a non-finite determinant): an inverted particle, which laws such as Saint
/// Venant–Kirchhoff or the Mooney–Rivlin-like law of the MPS paper would go on integrating.
pub fn check_jacobians<D: Dim>(
    deformation: &[D::Matrix],
    step: u64,
    time: f64,
) -> Result<(), Error> {
    match crate::parallel::first_index(
        deformation.len(),
        #[inline(always)]
        |i| {
            let j = D::det(deformation[i]);
            j.is_nan() || j <= 0.0
        },
    ) {
        Some(i) => Err(Error::Inverted {
            particle: i,
            jacobian: D::det(deformation[i]),
            step,
            time,
        }),
        None => Ok(()),
    }
}

/// [`Error::NonFinite`] naming the first non-finite position, velocity or matrix (e.g. the
/// deformation gradient), with the step and time at which it was found.
pub fn check_finite_state<D: Dim>(
    positions: &[D::Vector],
    velocities: &[D::Vector],
    matrices: (&str, &[D::Matrix]),
    step: u64,
    time: f64,
) -> Result<(), Error> {
    let fail = |field: &str, particle: usize| Error::NonFinite {
        field: field.into(),
        particle,
        step,
        time,
    };
    let (x, v, m) = (positions, velocities, matrices.1);
    // A healthy step returns here: one pass over the three arrays, on the team.
    let same_length = x.len() == v.len() && (m.is_empty() || m.len() == x.len());
    if same_length
        && crate::parallel::first_index(
            x.len(),
            #[inline(always)]
            |i| {
                !D::is_finite(x[i])
                    || !D::is_finite(v[i])
                    || m.get(i).is_some_and(|&m| !D::matrix_is_finite(m))
            },
        )
        .is_none()
    {
        return Ok(());
    }
    // Something is not finite: name the first entry of the first array that has one.
    if let Some(i) = x.iter().position(|&x| !D::is_finite(x)) {
        return Err(fail("position", i));
    }
    if let Some(i) = v.iter().position(|&x| !D::is_finite(x)) {
        return Err(fail("velocity", i));
    }
    match m.iter().position(|&m| !D::matrix_is_finite(m)) {
        Some(i) => Err(fail(matrices.0, i)),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::{D2, D3};
    use glam::{DMat2, DVec2};

    #[test]
    fn momenta_and_energy_of_two_particles() {
        let x = [DVec2::new(1.0, 0.0), DVec2::new(-1.0, 0.0)];
        let v = [DVec2::new(0.0, 1.0), DVec2::new(0.0, -1.0)];
        let m = [2.0, 2.0];
        assert_eq!(linear_momentum::<D2>(&v, &m), DVec2::ZERO);
        assert_eq!(
            angular_momentum::<D2>(&x, &v, &m),
            DVec3::new(0.0, 0.0, 4.0)
        );
        assert_eq!(kinetic_energy::<D2>(&v, &m), 2.0);
        assert_eq!(max_norm_where::<D2>(&v, &[false, true]), 1.0);
        assert_eq!(max_norm_where::<D3>(&[], &[]), 0.0);
    }

    #[test]
    fn inverted_particles_and_collapsed_steps_are_named() {
        let f = [
            DMat2::IDENTITY,
            DMat2::from_cols(DVec2::new(-1.0, 0.0), DVec2::new(0.0, 1.0)),
            DMat2::ZERO,
        ];
        let e = check_jacobians::<D2>(&f, 3, 0.25).unwrap_err();
        assert_eq!(
            e,
            Error::Inverted {
                particle: 1,
                jacobian: -1.0,
                step: 3,
                time: 0.25
            }
        );
        assert!(check_jacobians::<D2>(&f[..1], 0, 0.0).is_ok());
        // det = 0 (a flattened particle) counts as inverted too.
        assert!(check_jacobians::<D2>(&f[2..], 0, 0.0).is_err());
        assert!(check_time_step(1e-3, 1e-6, 0, 0.0).is_ok());
        for bad in [1e-7, 0.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                check_time_step(bad, 1e-6, 0, 0.0),
                Err(Error::TimeStepCollapsed { .. })
            ));
        }
        assert!(max_or_nan(1.0, f64::NAN).is_nan() && max_or_nan(f64::NAN, 1.0).is_nan());
        assert_eq!(max_or_nan(1.0, 2.0), 2.0);
    }

    #[test]
    fn non_finite_state_names_field_and_particle() {
        let x = [DVec2::ZERO, DVec2::new(f64::NAN, 0.0)];
        let e = check_finite_state::<D2>(&x, &[DVec2::ZERO; 2], ("F", &[]), 7, 0.5).unwrap_err();
        assert_eq!(
            e,
            Error::NonFinite {
                field: "position".into(),
                particle: 1,
                step: 7,
                time: 0.5
            }
        );
        let f = [
            DMat2::IDENTITY,
            DMat2::from_diagonal(DVec2::new(f64::INFINITY, 1.0)),
        ];
        let e = check_finite_state::<D2>(&[DVec2::ZERO; 2], &[DVec2::ZERO; 2], ("F", &f), 1, 0.0)
            .unwrap_err();
        assert!(matches!(e, Error::NonFinite { particle: 1, .. }));
    }
}
