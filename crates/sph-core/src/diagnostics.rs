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

/// The largest `|v|²` over `v` (0 for none), NaN if one is NaN: [`max_or_nan`] folded from 0
/// over the squared norms, as a maximum and a NaN flag, which the compiler computes several
/// vectors at a time (the fold of `max_or_nan` itself it cannot reorder).
#[inline(always)]
pub fn max_norm_squared_or_nan<D: Dim>(v: &[D::Vector]) -> f64 {
    let (mut max, mut nan) = (0.0f64, false);
    for &x in v {
        let s = D::norm_squared(x);
        max = max.max(s);
        nan |= s.is_nan();
    }
    if nan {
        f64::NAN
    } else {
        max
    }
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

/// The per-step check of a solver that carries a deformation gradient, in one pass on the
/// team: [`check_finite_state`] of `positions`, `velocities` and `matrices`, then
/// [`check_jacobians`] of `matrices`, then the vectors of `more` (e.g. the accelerations)
/// for non-finite entries; the first failure in that order is the error, as the separate calls
/// would give. A healthy state costs one pass on the team, array by array without branches;
/// only a failing state is searched again to name the entry. The separate checks, two passes
/// on the team and MPS's serial one over the accelerations, executed 11 % of the instructions
/// of the MPS cantilever plate; this one 3 % (docs/performance.md).
pub fn check_state<D: Dim>(
    positions: &[D::Vector],
    velocities: &[D::Vector],
    matrices: (&str, &[D::Matrix]),
    more: &[(&str, &[D::Vector])],
    step: u64,
    time: f64,
) -> Result<(), Error> {
    let (x, v, m) = (positions, velocities, matrices.1);
    let n = x.len();
    let same_length =
        v.len() == n && (m.is_empty() || m.len() == n) && more.iter().all(|(_, a)| a.len() == n);
    if same_length
        && !crate::parallel::fold_chunks(
            n,
            #[inline(always)]
            |rows| {
                // Array by array, each a loop without branches over its rows.
                let mut bad =
                    any_non_finite::<D>(&x[rows.clone()]) | any_non_finite::<D>(&v[rows.clone()]);
                if !m.is_empty() {
                    bad |= any_non_finite_or_inverted::<D>(&m[rows.clone()]);
                }
                for (_, a) in more {
                    bad |= any_non_finite::<D>(&a[rows.clone()]);
                }
                bad
            },
        )
        .contains(&true)
    {
        return Ok(());
    }
    check_finite_state::<D>(x, v, matrices, step, time)?;
    check_jacobians::<D>(m, step, time)?;
    for (field, a) in more {
        if let Some(i) = crate::solver::first_non_finite::<D>(a) {
            return Err(Error::NonFinite {
                field: (*field).into(),
                particle: i,
                step,
                time,
            });
        }
    }
    Ok(())
}

/// Whether `x` is NaN or ±∞, from its exponent bits (no branch, so a loop of these tests
/// vectorises).
#[inline(always)]
fn non_finite(x: f64) -> bool {
    const EXPONENT: u64 = 0x7ff0_0000_0000_0000;
    x.to_bits() & EXPONENT == EXPONENT
}

/// Whether a component of `v` is NaN or ±∞ ([`non_finite`] of each, combined without branches).
#[inline(always)]
fn vector_non_finite<D: Dim>(v: D::Vector) -> bool {
    let mut bad = false;
    for c in 0..D::D {
        bad |= non_finite(D::component(v, c));
    }
    bad
}

/// Whether an entry of `m` is NaN or ±∞.
#[inline(always)]
fn matrix_non_finite<D: Dim>(m: D::Matrix) -> bool {
    let mut bad = false;
    for c in 0..D::D {
        for r in 0..D::D {
            bad |= non_finite(D::matrix_get(m, r, c));
        }
    }
    bad
}

/// Whether a vector of `v` has a NaN or infinite component.
#[inline(always)]
fn any_non_finite<D: Dim>(v: &[D::Vector]) -> bool {
    v.iter()
        .fold(false, |bad, &v| bad | vector_non_finite::<D>(v))
}

/// Whether a matrix of `m` has a NaN or infinite entry, or a determinant that is NaN, zero or
/// negative ([`check_jacobians`]).
#[inline(always)]
fn any_non_finite_or_inverted<D: Dim>(m: &[D::Matrix]) -> bool {
    m.iter().fold(false, |bad, &m| {
        let j = D::det(m);
        bad | matrix_non_finite::<D>(m) | j.is_nan() | (j <= 0.0)
    })
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
        let v = [
            DVec2::new(3.0, 4.0),
            DVec2::ZERO,
            DVec2::new(-1.0, f64::INFINITY),
            DVec2::new(f64::NAN, 0.0),
        ];
        for k in 0..=v.len() {
            for w in [&v[..k], &v[k..]] {
                let expected = w.iter().map(|&x| D2::norm_squared(x)).fold(0.0, max_or_nan);
                let got = max_norm_squared_or_nan::<D2>(w);
                assert_eq!(got.to_bits(), expected.to_bits(), "{w:?}");
            }
        }
        assert_eq!(max_or_nan(1.0, 2.0), 2.0);
    }

    #[test]
    fn one_pass_check_fails_where_the_separate_checks_fail_first() {
        let ok_x = [DVec2::ZERO, DVec2::new(1.0, 0.0)];
        let ok_v = [DVec2::ZERO; 2];
        let ok_f = [DMat2::IDENTITY; 2];
        let ok_a = [DVec2::ONE; 2];
        let run = |x: &[DVec2], v: &[DVec2], f: &[DMat2], a: &[DVec2]| {
            check_state::<D2>(x, v, ("F", f), &[("acceleration", a)], 4, 0.5)
        };
        assert_eq!(run(&ok_x, &ok_v, &ok_f, &ok_a), Ok(()));
        assert_eq!(run(&ok_x, &ok_v, &[], &ok_a), Ok(()));
        let bad_values = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY];
        for bad in bad_values {
            let mut a = ok_a;
            a[1].y = bad;
            assert_eq!(
                run(&ok_x, &ok_v, &ok_f, &a),
                Err(Error::NonFinite {
                    field: "acceleration".into(),
                    particle: 1,
                    step: 4,
                    time: 0.5
                })
            );
            // A bad position comes before a bad acceleration of an earlier particle.
            let (mut x, mut a) = (ok_x, ok_a);
            x[1].x = bad;
            a[0].x = bad;
            let e = run(&x, &ok_v, &ok_f, &a).unwrap_err();
            assert!(
                matches!(e, Error::NonFinite { ref field, particle: 1, .. } if field == "position")
            );
            let mut f = ok_f;
            f[0].x_axis.y = bad;
            let e = run(&ok_x, &ok_v, &f, &ok_a).unwrap_err();
            assert!(matches!(e, Error::NonFinite { ref field, particle: 0, .. } if field == "F"));
        }
        // Inverted and flattened particles, large but finite values.
        let mut f = ok_f;
        f[1] = DMat2::from_diagonal(DVec2::new(-1.0, 1.0));
        assert!(matches!(
            run(&ok_x, &ok_v, &f, &ok_a),
            Err(Error::Inverted { particle: 1, .. })
        ));
        f[1] = DMat2::ZERO;
        assert!(matches!(
            run(&ok_x, &ok_v, &f, &ok_a),
            Err(Error::Inverted { particle: 1, .. })
        ));
        let big = [DVec2::splat(f64::MAX), DVec2::splat(-f64::MAX)];
        assert_eq!(run(&big, &big, &ok_f, &big), Ok(()));
        // A state long enough to be split over the team.
        let n = 5000;
        let mut x = vec![DVec2::ZERO; n];
        let f = vec![DMat2::IDENTITY; n];
        assert_eq!(check_state::<D2>(&x, &x, ("F", &f), &[], 0, 0.0), Ok(()));
        x[n - 7].y = f64::NAN;
        let e = check_state::<D2>(&x.clone(), &x, ("F", &f), &[], 0, 0.0).unwrap_err();
        assert!(matches!(e, Error::NonFinite { particle, .. } if particle == n - 7));
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
