//! Blow-up detection in the UL solver (issue 14, item 8): an infinite or huge acceleration
//! inside an advection step stops the run at the next acoustic sub-step with
//! `TimeStepCollapsed` (before the guard, Δt_ac = 0 and the sub-step loop never ended); a NaN
//! speed is not ignored by the maximum that sets the sub-step.

use glam::DVec2;
use sph_core::Body;
use sph_core::{Error, Loads, Solver, TimeFunction, D2};
use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
use sph_materials::ElasticConstants;
use sph_ul::{Shear, Stepping, UlParams, UlSolver};

const DP: f64 = 0.01;

fn solver(stepping: Stepping, g: f64) -> UlSolver<D2> {
    let c = ElasticConstants::from_youngs(2.0e6, 0.3975, 1000.0).unwrap();
    let lattice = Lattice::<D2>::new(DP, DVec2::ZERO).unwrap();
    let set = ParticleSet::fill(
        &lattice,
        &Aabb::new(DVec2::ZERO, DVec2::new(8.0 * DP, 5.0 * DP)).unwrap(),
    )
    .unwrap();
    let body = Body {
        positions: set.positions().to_vec(),
        volumes: set.volumes().to_vec(),
        dp: DP,
        velocities: Vec::new(),
        densities: Vec::new(),
    };
    let params = UlParams {
        stepping,
        ..UlParams::default()
    };
    let mut loads = Loads::new();
    // The load switches on after the first advection step has started from rest.
    loads.add_body_acceleration(
        None,
        TimeFunction::new(move |t| DVec2::new(if t > 0.0 { g } else { 0.0 }, 0.0)),
    );
    UlSolver::new(body, c, Shear::non_nested(), params)
        .unwrap()
        .with_loads(loads)
}

fn run_until_error(s: &mut UlSolver<D2>) -> Error {
    for _ in 0..1_000 {
        if let Err(e) = s.step(f64::INFINITY) {
            return e;
        }
    }
    panic!("the run went on for 1,000 steps");
}

#[test]
fn an_infinite_or_huge_acceleration_stops_the_sub_steps_as_collapsed() {
    for g in [f64::INFINITY, 1e300] {
        for stepping in [Stepping::Dual, Stepping::Single] {
            let mut s = solver(stepping, g);
            let e = run_until_error(&mut s);
            assert!(
                matches!(e, Error::TimeStepCollapsed { .. } | Error::NonFinite { .. }),
                "g = {g}, {stepping:?}: {e:?}"
            );
        }
    }
}

#[test]
fn a_nan_acceleration_stops_the_run_as_non_finite() {
    let mut s = solver(Stepping::Dual, f64::NAN);
    let e = run_until_error(&mut s);
    assert!(matches!(e, Error::NonFinite { .. }), "{e:?}");
    // Stopped within the first advection step, at its second acoustic sub-step: the NaN speed
    // was not dropped by the maximum.
    assert_eq!(s.step_count(), 0);
    assert!(s.acoustic_step_count() <= 2, "{}", s.acoustic_step_count());
}

/// The run driver's work estimate: a dual step is made of acoustic sub-steps, and
/// `substep_dt` reports the acoustic one (eq 22), not the advection step (eq 21).
#[test]
fn substep_dt_is_the_acoustic_step() {
    let dual = solver(Stepping::Dual, 0.0);
    let single = solver(Stepping::Single, 0.0);
    assert_eq!(dual.substep_dt(), single.stable_dt());
    assert!(dual.stable_dt() > 10.0 * dual.substep_dt());
}
