//! Whole-body diagnostics every solver reports the same way: momenta, kinetic energy, speed
//! maxima for time-step criteria, and the run-time check for non-finite state.

use crate::dim::Dim;
use crate::error::Error;
use glam::DVec3;
use rayon::prelude::*;

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
    v.par_iter()
        .zip(mask)
        .map(|(&x, &f)| if f { D::norm_squared(x) } else { 0.0 })
        .reduce(|| 0.0, f64::max)
        .sqrt()
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
    if let Some(i) = positions.iter().position(|&x| !D::is_finite(x)) {
        return Err(fail("position", i));
    }
    if let Some(i) = velocities.iter().position(|&x| !D::is_finite(x)) {
        return Err(fail("velocity", i));
    }
    if let Some(i) = matrices.1.iter().position(|&m| !D::matrix_is_finite(m)) {
        return Err(fail(matrices.0, i));
    }
    Ok(())
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
