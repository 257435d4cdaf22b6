//! Properties of the Hamiltonian MPS solver in 2D (plane strain) and 3D:
//!
//! 1. the force of eq 7 is `−∂U/∂x_i`, `U = Σ V ψ(F)`, by central finite differences (SVK and
//!    the Mooney–Rivlin-like law of eq 12);
//! 2. linear momentum of a free body is conserved to round-off;
//! 3. angular momentum of a free spinning body is conserved to round-off;
//! 4. an undeformed body at rest has zero force and stays at rest; forces are objective;
//! 5. invalid input is rejected with the error that names it;
//! 6. surface pressure: total force `p A N`, turning with the body; constraints and damping.
//!
//! The energy test (10⁵ steps) is in `energy.rs`. Measured numbers are printed with
//! `-- --nocapture` and quoted in the comments.

mod common;

use common::*;
use glam::{DMat2, DMat3, DVec3};
use proptest::prelude::*;
use sph_core::Body;
use sph_core::{Constraint, Constraints, Dim, Error, Solver, TimeFunction, D2, D3};
use sph_materials::Material;
use sph_mps::{Integrator, MpsParams, MpsSolver, SurfacePressure};

// ----------------------------------------------------------------- 1. force = −∂U/∂x

/// Max over particles and components of `|f_fd − f|`, relative to `max |f|`.
///
/// Tolerance 1e-6 (the brief's): the central difference with step `h = 1e-6 dp` has truncation
/// error `~ (h/ℓ)²` relative, `ℓ` the length over which the force changes (≥ 0.1 dp here), i.e.
/// ≤ 1e-10, and cancellation error `ε_mach U / (h |f|) ~ 1e-16 · N ε dp / h ≈ 1e-9` (U summed
/// over N ≤ 27 particles at strain ε ~ 0.1). A wrong sign, factor or missing `j`-term gives O(1).
/// Measured: ≤ 3.1e-10 (2D/3D, SVK/Mooney–Rivlin; printed).
fn fd_error<D: Dim, M: Material<D> + Clone>(n: [usize; 3], material: M, seed: u64) -> f64 {
    let mut s = solver::<D, M>(n, material);
    let mut rng = Lcg(seed);
    let x0 = deformed::<D>(s.reference_positions(), &mut rng, 0.1, 0.1);
    let v0 = vec![D::zero(); x0.len()];
    s.set_configuration(x0.clone(), v0.clone()).unwrap();
    let f = s.evaluate_forces().to_vec();
    let h = 1e-6 * DP;
    let mut err: f64 = 0.0;
    for i in 0..x0.len() {
        for k in 0..D::D {
            let mut u = [0.0; 2];
            for (m, sign) in [1.0, -1.0].into_iter().enumerate() {
                let mut x = x0.clone();
                let c = D::component(x[i], k);
                D::set_component(&mut x[i], k, c + sign * h);
                s.set_configuration(x, v0.clone()).unwrap();
                u[m] = s.energy().strain;
            }
            let fd = -(u[0] - u[1]) / (2.0 * h);
            err = err.max((fd - D::component(f[i], k)).abs());
        }
    }
    err / max_norm::<D>(&f)
}

#[test]
fn force_is_minus_energy_gradient_by_finite_differences() {
    let cases = [
        ("2D SVK", fd_error::<D2, _>([5, 4, 1], svk(), 1)),
        (
            "2D Mooney-Rivlin",
            fd_error::<D2, _>([5, 4, 1], mooney(), 2),
        ),
        ("3D SVK", fd_error::<D3, _>([3, 3, 3], svk(), 3)),
        (
            "3D Mooney-Rivlin",
            fd_error::<D3, _>([3, 3, 3], mooney(), 4),
        ),
    ];
    for (name, e) in cases {
        println!("force vs -dU/dx, {name}: relative error {e:.2e}");
        assert!(e < 1e-6, "{name}: {e:e}");
    }
}

// ----------------------------------------------------------------- 2. linear momentum

/// `|ΔP| / Σ m|v|` after `steps` steps of a free, deformed, moving body.
///
/// Why round-off: every pair term of eq 7 is antisymmetric in (i, j) (symmetric reference
/// neighbour list, `X_ji = −X_ij`), so `Σ f = 0` up to summing the same terms in two gathers:
/// ~1e-16 × (neighbour count ~12–32) × Σ|pair terms| per step. Bound 1e-12 over 200 steps.
/// Measured ≤ 3.6e-15 (printed).
fn momentum_drift<D: Dim, M: Material<D>>(n: [usize; 3], material: M, seed: u64) -> f64 {
    let mut s = solver::<D, M>(n, material);
    let mut rng = Lcg(seed);
    let x = deformed::<D>(s.reference_positions(), &mut rng, 0.05, 0.05);
    let c = s.material().constants().sound_speed;
    let v = random_velocities::<D>(x.len(), &mut rng, 0.01 * c);
    s.set_configuration(x, v).unwrap();
    let p0 = s.linear_momentum();
    let scale: f64 = s
        .velocities()
        .iter()
        .zip(s.masses())
        .map(|(&v, &m)| m * D::norm(v))
        .sum();
    for _ in 0..200 {
        s.step(f64::INFINITY).unwrap();
    }
    D::norm(s.linear_momentum() - p0) / scale
}

#[test]
fn linear_momentum_is_conserved_for_a_free_body() {
    let e = [
        momentum_drift::<D2, _>([8, 5, 1], svk(), 11),
        momentum_drift::<D2, _>([8, 5, 1], mooney(), 12),
        momentum_drift::<D3, _>([4, 4, 3], svk(), 13),
        momentum_drift::<D3, _>([4, 4, 3], mooney(), 14),
    ];
    println!("linear momentum drift / sum m|v|: {e:?}");
    assert!(e.iter().all(|&x| x < 1e-12), "{e:?}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]
    /// Same property over random states (2D, SVK, 200 steps), same tolerance and reasoning.
    #[test]
    fn linear_momentum_is_conserved_for_random_states(seed in any::<u64>()) {
        let e = momentum_drift::<D2, _>([6, 5, 1], svk(), seed);
        prop_assert!(e < 1e-12, "{e:e}");
    }
}

// ----------------------------------------------------------------- 3. angular momentum

/// `|ΔL| / |L|` after 2000 steps of a free, deformed, spinning body (about 4 rotation periods
/// of the elastic modes), velocity Verlet.
///
/// Why round-off: `U` depends on `x` only through `F_k` and `ψ(QF) = ψ(F)`, so
/// `Σ_i x_i × ∂U/∂x_i = 0` identically; a velocity-Verlet kick then changes `L` by
/// `Σ x × f Δt/2 = 0` and a drift by `Σ m Δt v × v = 0`. Only round-off remains (~1e-16 per
/// step, accumulated over 2000 steps, relative to a |L| that can be small against Σ m|x||v|):
/// bound 1e-11. Measured ≤ 2.1e-13 (2D Mooney–Rivlin), ≤ 1.6e-14 otherwise.
fn angular_momentum_drift<D: Dim, M: Material<D>>(
    n: [usize; 3],
    material: M,
    omega: DVec3,
    integrator: Integrator,
) -> f64 {
    let params = MpsParams {
        integrator,
        ..MpsParams::default()
    };
    let mut s = solver_with::<D, M>(n, material, params);
    let mut rng = Lcg(21);
    let x = deformed::<D>(s.reference_positions(), &mut rng, 0.05, 0.05);
    let c = centroid::<D>(&x);
    let v: Vec<D::Vector> = x
        .iter()
        .map(|&p| D::vector(omega.cross(D::to_vec3(p - c)).to_array()))
        .collect();
    s.set_configuration(x, v).unwrap();
    let l0 = s.angular_momentum();
    for _ in 0..2000 {
        s.step(f64::INFINITY).unwrap();
    }
    (s.angular_momentum() - l0).length() / l0.length()
}

#[test]
fn angular_momentum_is_conserved_for_a_free_spinning_body() {
    // ω such that the rim speed is ~1 % of c (a fast spin for these bodies).
    let c = Material::<D2>::constants(&svk()).sound_speed;
    let w = 0.01 * c / (4.0 * DP);
    let e = [
        angular_momentum_drift::<D2, _>([8, 5, 1], svk(), DVec3::Z * w, Integrator::VelocityVerlet),
        angular_momentum_drift::<D2, _>(
            [8, 5, 1],
            mooney(),
            DVec3::Z * w,
            Integrator::VelocityVerlet,
        ),
        angular_momentum_drift::<D3, _>(
            [4, 4, 3],
            svk(),
            DVec3::new(0.3, -0.5, 0.8) * w,
            Integrator::VelocityVerlet,
        ),
        // Symplectic Euler: a kick changes L by Σ x^{n+1} × f Δt = 0 and a drift by
        // Σ m Δt v × v = 0, so it conserves L as well.
        angular_momentum_drift::<D2, _>(
            [8, 5, 1],
            svk(),
            DVec3::Z * w,
            Integrator::SymplecticEuler,
        ),
    ];
    println!("angular momentum |dL|/|L| after 2000 steps: {e:?}");
    assert!(e.iter().all(|&x| x < 1e-11), "{e:?}");
}

// ----------------------------------------------------------------- 4. rest and objectivity

/// At rest, `F_i = (Σ X_ij ⊗ wX_ij) A_i⁻¹ = A_i A_i⁻¹ = I` for every particle (no guard), so
/// `P = 0` and the force is zero up to the round-off of `A A⁻¹` (~1e-15 relative). Scale: the
/// force of a 1 % strain, `0.01 E dp^(d−1)`; bound 1e-10 of it. After 1000 steps nothing has
/// moved beyond 1e-12 dp. Measured: max |f| / scale ≤ 5.6e-14, max |x − X| ≤ 6e-15 dp.
fn rest<D: Dim>(n: [usize; 3]) -> (f64, f64) {
    let mut s = solver::<D, _>(n, svk());
    let scale = 0.01 * Material::<D>::constants(&svk()).youngs_modulus * DP.powi(D::D as i32 - 1);
    let f = max_norm::<D>(s.evaluate_forces()) / scale;
    for _ in 0..1000 {
        s.step(f64::INFINITY).unwrap();
    }
    let moved = s
        .positions()
        .iter()
        .zip(s.reference_positions())
        .map(|(&x, &x0)| D::norm(x - x0))
        .fold(0.0, f64::max);
    (f, moved / DP)
}

#[test]
fn undeformed_body_at_rest_has_no_force_and_stays_at_rest() {
    for (name, (f, moved)) in [("2D", rest::<D2>([7, 5, 1])), ("3D", rest::<D3>([4, 4, 3]))] {
        println!("{name}: max |f| / (0.01 E dp^(d-1)) = {f:.2e}, max |x - X| / dp = {moved:.2e}");
        assert!(f < 1e-10 && moved < 1e-12, "{name}: {f:e} {moved:e}");
    }
}

/// `f(Q x + c) = Q f(x)`: `F → Q F`, `P → Q P`, so every `G_i` and hence every force rotates.
/// Tolerance 1e-12 of max |f|: round-off of the sums (Q applied in different places).
/// Measured ≤ 2.1e-13.
fn objectivity<D: Dim, M: Material<D>>(n: [usize; 3], material: M, q: D::Matrix) -> f64 {
    let mut s = solver::<D, M>(n, material);
    let mut rng = Lcg(31);
    let x = deformed::<D>(s.reference_positions(), &mut rng, 0.1, 0.1);
    let zero = vec![D::zero(); x.len()];
    s.set_configuration(x.clone(), zero.clone()).unwrap();
    let f = s.evaluate_forces().to_vec();
    let shift = D::vector([0.3, -0.7, 0.2]);
    let xr: Vec<D::Vector> = x.iter().map(|&p| q * p + shift).collect();
    s.set_configuration(xr, zero).unwrap();
    let fr = s.evaluate_forces();
    let err = f
        .iter()
        .zip(fr)
        .map(|(&a, &b)| D::norm(q * a - b))
        .fold(0.0, f64::max);
    err / max_norm::<D>(&f)
}

#[test]
fn forces_are_objective_under_rigid_rotation() {
    let q2 = DMat2::from_angle(0.7);
    let q3 = DMat3::from_axis_angle(DVec3::new(1.0, 2.0, -0.5).normalize(), 1.1);
    let e = [
        objectivity::<D2, _>([6, 5, 1], svk(), q2),
        objectivity::<D2, _>([6, 5, 1], mooney(), q2),
        objectivity::<D3, _>([4, 3, 3], svk(), q3),
        objectivity::<D3, _>([4, 3, 3], mooney(), q3),
    ];
    println!("objectivity |Q f - f(Qx)| / max|f|: {e:?}");
    assert!(e.iter().all(|&x| x < 1e-12), "{e:?}");
}

// ----------------------------------------------------------------- 5. bad input

fn field_of(e: Error) -> String {
    match e {
        Error::InvalidParameter { field, .. } => field,
        other => panic!("expected InvalidParameter, got {other:?}"),
    }
}

#[test]
fn invalid_input_is_rejected_naming_the_field() {
    let set = block::<D2>([5, 4, 1]);
    let ok = || body::<D2>(&set);
    let p = MpsParams::default();
    let build = |b: Body<D2>, p: MpsParams| MpsSolver::new(b, svk(), p).map(|_| ());

    let empty = Body::<D2> {
        positions: vec![],
        volumes: vec![],
        dp: DP,
        velocities: vec![],
        densities: Vec::new(),
    };
    assert!(matches!(build(empty, p), Err(Error::EmptyBody { .. })));
    for dp in [0.0, -1.0, f64::NAN] {
        let b = Body { dp, ..ok() };
        assert_eq!(field_of(build(b, p).unwrap_err()), "dp");
    }
    for re in [1.0, 0.5, f64::INFINITY] {
        let q = MpsParams {
            re_over_l0: re,
            ..p
        };
        assert_eq!(field_of(build(ok(), q).unwrap_err()), "re_over_l0");
    }
    for c in [0.0, -0.1, f64::NAN] {
        let q = MpsParams { courant: c, ..p };
        assert_eq!(field_of(build(ok(), q).unwrap_err()), "courant");
    }
    let q = MpsParams { damping: -1.0, ..p };
    assert_eq!(field_of(build(ok(), q).unwrap_err()), "damping");
    let b = Body {
        volumes: vec![DP * DP; 3],
        ..ok()
    };
    assert_eq!(field_of(build(b, p).unwrap_err()), "volumes");
    let mut b = ok();
    b.volumes[4] = 0.0;
    assert_eq!(field_of(build(b, p).unwrap_err()), "volumes[4]");
    let b = Body {
        velocities: vec![D2::zero(); 2],
        ..ok()
    };
    assert_eq!(field_of(build(b, p).unwrap_err()), "velocities");
    let mut b = ok();
    b.positions[3] = b.positions[2];
    assert_eq!(field_of(build(b, p).unwrap_err()), "positions");
    // r_e just above l0: corner particles have 2 neighbours, fewer than D + 1 = 3.
    let q = MpsParams {
        re_over_l0: 1.2,
        ..p
    };
    match build(ok(), q) {
        Err(Error::TooFewNeighbours {
            found, required, ..
        }) => assert_eq!((found, required), (2, 3)),
        other => panic!("{other:?}"),
    }
    // A line of particles: A_i is rank one; two isolated particles: too few neighbours.
    let far = Body::<D2> {
        positions: vec![D2::vector([0.0, 0.0, 0.0]), D2::vector([1.0, 0.0, 0.0])],
        volumes: vec![DP * DP; 2],
        dp: DP,
        velocities: vec![],
        densities: Vec::new(),
    };
    assert!(matches!(
        build(far, p),
        Err(Error::TooFewNeighbours { found: 0, .. })
    ));
    // Surface pressure: bad index, wrong normal count, interior particle with estimated normal.
    let s = || MpsSolver::new(ok(), svk(), p).unwrap();
    let e = s()
        .with_surface_pressure(SurfacePressure::constant(vec![99], 1.0))
        .err()
        .unwrap();
    assert_eq!(field_of(e), "surface_pressure.particles");
    let mut sp = SurfacePressure::<D2>::constant(vec![0, 1], 1.0);
    sp.normals = Some(vec![D2::vector([1.0, 0.0, 0.0])]);
    let e = s().with_surface_pressure(sp).err().unwrap();
    assert_eq!(field_of(e), "surface_pressure.normals");
    // Probe interval and configuration lengths.
    assert!(s().with_probes(vec![], -1.0).is_err());
    let e = s().set_configuration(vec![], vec![]).unwrap_err();
    assert_eq!(field_of(e), "configuration");
}

#[test]
fn blow_up_stops_the_run_with_a_diagnostic() {
    // A Courant number twice the stability limit (0.45 in tests/energy.rs, from the same 2 %
    // random perturbation; 0.95 is about the largest the parameter range admits) makes the
    // explicit scheme diverge; the run must stop with a
    // blow-up diagnostic (not panic, not loop forever). The first sign is an inverted particle
    // (det F < 0), seen before any value turns non-finite; without the J check the Saint
    // Venant–Kirchhoff law would go on integrating it.
    let params = MpsParams {
        courant: 0.95,
        ..MpsParams::default()
    };
    let mut s = solver_with::<D2, _>([6, 5, 1], svk(), params);
    let mut rng = Lcg(5);
    let x = deformed::<D2>(s.reference_positions(), &mut rng, 0.0, 0.02);
    let v = vec![D2::zero(); x.len()];
    s.set_configuration(x, v).unwrap();
    let mut err = None;
    for _ in 0..100_000 {
        if let Err(e) = s.step(f64::INFINITY) {
            err = Some(e);
            break;
        }
    }
    assert!(
        matches!(err, Some(Error::Inverted { jacobian, .. }) if jacobian <= 0.0),
        "expected Inverted, got {err:?}"
    );
}

/// A particle thrown at 1000 c0 trips the blow-up guard on the first step: the step a CFL
/// criterion on |v| would allow is below `MIN_DT_RATIO` of the constant `C l0/c0`.
#[test]
fn a_particle_far_faster_than_sound_stops_the_run_as_collapsed() {
    let mut s = solver_with::<D2, _>([6, 5, 1], svk(), MpsParams::default());
    let x = s.reference_positions().to_vec();
    let c0 = sph_materials::Material::<D2>::constants(s.material()).sound_speed;
    let mut v = vec![D2::zero(); x.len()];
    v[7] = D2::vector([1000.0 * c0, 0.0, 0.0]);
    s.set_configuration(x, v).unwrap();
    let e = s.step(f64::INFINITY).unwrap_err();
    assert!(matches!(e, Error::TimeStepCollapsed { .. }), "{e:?}");
    assert_eq!(s.step_count(), 0, "nothing was integrated");
}

// ----------------------------------------------------------------- 6. pressure, constraints

/// A pressure `p` on the left face (x = min) of a free 2D block, normals estimated (−x),
/// areas `dp`: the total external force is `p · (face length) · (+x)`, so
/// `dP/dt = p · n_face · dp` exactly in the first step (internal forces cancel). Then the same
/// body rotated by 90°: the load turns with it (`cof Q = Q`). Tolerances: 1e-12 relative
/// (round-off; the estimated normals of a face particle of a symmetric block are exact except
/// at the two corners, which are given explicitly).
#[test]
fn surface_pressure_pushes_along_the_inward_normal_and_turns_with_the_body() {
    let p = 1.0e3;
    let set = block::<D2>([6, 4, 1]);
    let xmin = set.positions().iter().map(|x| x.x).fold(f64::MAX, f64::min);
    let face: Vec<u32> = (0..set.len() as u32)
        .filter(|&i| set.positions()[i as usize].x < xmin + 0.5 * DP)
        .collect();
    assert_eq!(face.len(), 4);
    let sp = SurfacePressure::<D2> {
        particles: face.clone(),
        normals: Some(vec![D2::vector([-1.0, 0.0, 0.0]); face.len()]),
        areas: None,
        pressure: sph_mps::PressureFunction::constant(p),
    };
    let mut s = MpsSolver::new(body(&set), svk(), MpsParams::default())
        .unwrap()
        .with_surface_pressure(sp)
        .unwrap();
    let expected = p * face.len() as f64 * DP;
    let total = s
        .accelerations()
        .iter()
        .zip(s.masses())
        .fold(D2::zero(), |a, (&x, &m)| a + x * m);
    println!("pressure: total force {total:?}, expected ({expected}, 0)");
    assert!((total - glam::DVec2::new(expected, 0.0)).length() < 1e-12 * expected);
    // Rotate the body rigidly by 90°: the total force becomes (0, expected).
    let q = DMat2::from_angle(std::f64::consts::FRAC_PI_2);
    let xr: Vec<_> = s.reference_positions().iter().map(|&x| q * x).collect();
    let zero = vec![D2::zero(); xr.len()];
    s.set_configuration(xr, zero).unwrap();
    let total = s
        .accelerations()
        .iter()
        .zip(s.masses())
        .fold(D2::zero(), |a, (&x, &m)| a + x * m);
    assert!((total - glam::DVec2::new(0.0, expected)).length() < 1e-12 * expected);
    // Estimated normals on the left face of the same block point along −x (up to the corner
    // asymmetry): the load on face particles points along +x within 45° (exactly 45° at the
    // corners, where the neighbourhood is symmetric about the diagonal).
    let s = MpsSolver::new(body(&set), svk(), MpsParams::default())
        .unwrap()
        .with_surface_pressure(SurfacePressure::constant(face.clone(), p))
        .unwrap();
    for &i in &face {
        let a = s.accelerations()[i as usize];
        assert!(
            a.x > 0.0 && a.x >= a.y.abs() * (1.0 - 1e-9),
            "particle {i}: {a:?}"
        );
    }
}

/// A cantilever (left two columns fixed) under gravity with velocity damping comes to rest:
/// fixed particles never move, kinetic energy falls by orders of magnitude, and the tip
/// deflects downward. Damping `c_d = ω/2` (ω the beam-theory first bending frequency);
/// tolerance: fixed particles exactly (velocity and acceleration zeroed), kinetic energy below
/// 1e-6 of its peak after 20 periods (`e^(−c_d t)` gives ~1e-27 for the velocity squared;
/// measured 3e-25).
#[test]
fn damped_cantilever_under_gravity_settles_with_fixed_particles_in_place() {
    let n = [12, 3, 1];
    let set = block::<D2>(n);
    let fixed: Vec<u32> = (0..set.len() as u32)
        .filter(|&i| set.positions()[i as usize].x < 2.0 * DP)
        .collect();
    let mut c = Constraints::new();
    c.push(
        Constraint::Fixed {
            particles: fixed.clone(),
        },
        set.len(),
    )
    .unwrap();
    let mut loads = sph_core::Loads::new();
    loads.add_body_acceleration(None, TimeFunction::constant(D2::vector([0.0, -9.81, 0.0])));
    // Beam theory: first bending frequency of a cantilever L = 24 mm, H = 6 mm, E = 1e5 Pa.
    let (l, h) = (24.0 * 1e-3, 6.0 * 1e-3);
    let e: f64 = 1.0e5 / (1.0 - 0.09);
    let omega = 1.875f64.powi(2) * (e * h * h / (12.0 * 1000.0)).sqrt() / (l * l);
    let params = MpsParams {
        damping: 0.5 * omega,
        ..MpsParams::default()
    };
    let mut s = MpsSolver::new(body(&set), svk(), params)
        .unwrap()
        .with_constraints(c)
        .with_loads(loads);
    let period = 2.0 * std::f64::consts::PI / omega;
    let mut peak: f64 = 0.0;
    while s.time() < 20.0 * period {
        s.step(f64::INFINITY).unwrap();
        peak = peak.max(s.energy().kinetic);
    }
    let ke = s.energy().kinetic;
    let tip = s.positions()[set.len() - 1] - s.reference_positions()[set.len() - 1];
    println!(
        "damped cantilever: {} steps, KE end/peak = {:.2e}, tip displacement {tip:?}",
        s.step_count(),
        ke / peak
    );
    for &i in &fixed {
        assert_eq!(
            s.positions()[i as usize],
            s.reference_positions()[i as usize]
        );
    }
    assert!(ke < 1e-6 * peak, "{ke:e} vs {peak:e}");
    assert!(tip.y < 0.0);
}

// ------------------------------------------------------------ 7. zero-energy mode

/// The WLS deformation gradient (eq 4–5) has the alternating-column mode in its null space:
/// `u_x = δ (−1)^column` leaves `F_i` of every particle whose support is symmetric in x
/// unchanged (its neighbours in odd columns move by the same −2δ on both sides, those in even
/// columns not at all, and `Σ_j w X_ij` over the odd columns of a symmetric support vanishes).
/// The mode costs no energy in the bulk — only the surface rows resist it — which is how a
/// stretched body (the slab, the pressurised ring in docs/validation.md) can clump
/// column-wise; a smooth displacement of the same size does change F.
#[test]
fn wls_gradient_has_the_alternating_column_zero_energy_mode() {
    let n = [16, 10, 1];
    let mut s = solver::<D2, _>(n, svk());
    let x0 = s.reference_positions().to_vec();
    let delta = 0.05 * DP;
    let column = |x: &glam::DVec2| (x.x / DP).floor() as i64;
    let row = |x: &glam::DVec2| (x.y / DP).floor() as i64;
    // Full support: at least r_e = 2.1 dp (3 columns or rows) from every side. Near the top
    // and bottom the support is one-sided in y and the mode shears F (that is where it is
    // resisted).
    let interior = |x: &glam::DVec2| {
        column(x) >= 3 && column(x) < n[0] as i64 - 3 && row(x) >= 3 && row(x) < n[1] as i64 - 3
    };
    // Largest interior |F − I| after displacing every particle by u_x(x).
    let mut interior_dev = |u: &dyn Fn(&glam::DVec2) -> f64| {
        let x: Vec<glam::DVec2> = x0
            .iter()
            .map(|x| *x + glam::DVec2::new(u(x), 0.0))
            .collect();
        s.set_configuration(x, vec![glam::DVec2::ZERO; x0.len()])
            .unwrap();
        x0.iter()
            .zip(s.deformation_gradients())
            .filter(|(x, _)| interior(x))
            .map(|(_, f)| D2::frobenius(*f - glam::DMat2::IDENTITY))
            .fold(0.0, f64::max)
    };
    let zig_dev = interior_dev(&|x| delta * if column(x) % 2 == 0 { 1.0 } else { -1.0 });
    // A smooth field of the same amplitude: u_x = δ sin(π x / (4 dp)).
    let smooth_dev = interior_dev(&|x| delta * (std::f64::consts::PI * x.x / (4.0 * DP)).sin());
    println!("interior |F − I|: alternating columns {zig_dev:.3e}, smooth {smooth_dev:.3e}");
    assert!(zig_dev < 1e-12, "{zig_dev}");
    assert!(smooth_dev > 1e-3, "{smooth_dev}");
}
