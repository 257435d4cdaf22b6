//! Properties of the UL solver (`ul-og`, `ul-oas`, `ul-enog`), 2D and 3D (its energy is in
//! `energy.rs`):
//!
//! 1. signs of the Riemann terms on two particles (approaching pairs repel and compress;
//!    separating ones get no extra attraction; a pressure excess slows density growth);
//! 2. linear momentum of a free body is conserved to round-off by every variant (proptest);
//! 3. ENOG's conservative Laplacian (eq 19) gives no shear acceleration under a rigid rotation,
//!    the non-conservative eq 18 does (and brakes the rotation: paper Fig. 7);
//! 4. a body at rest stays at rest;
//! 5. dual and single stepping give nearly the same short trajectory;
//! 6. invalid input is rejected naming the field; lost neighbours stop the run;
//! 7. reordering keeps constraints, probes and the map back to the input order;
//! 8. isolated particles are counted; the accumulated disorder indicator sees a zigzag;
//! 9. contact between bodies conserves momentum and rebounds;
//! 10. ENOG moves identically with and without integrating its (output-only) shear stress.
//!
//! Material (`common`): the UL paper's 2D plate (E = 2 MPa, ν = 0.3975, ρ0 = 1000; c0 = 57.0
//! m/s), dp = 1 cm, h = 1.3 dp. Bodies are small so the file runs in seconds; `-- --nocapture`
//! prints measurements.

mod common;

use common::*;
use glam::{DVec2, DVec3};
use proptest::prelude::*;
use sph_core::Body;
use sph_core::{Constraint, Constraints, Dim, Error, Probe, Solver, D2, D3};
use sph_ul::{LaplacianForm, RiemannScheme, Shear, Stepping, UlParams, UlSolver};

// ------------------------------------------------------------------ 1. Riemann signs

#[test]
fn riemann_terms_have_the_right_signs_on_two_particles() {
    let (rho0, u) = (1000.0, 0.01 * c0());
    // Particle 0 at x = 0, particle 1 at x = dp; e_01 = −x.
    // Approaching at zero pressure: P* = −½ β ρ0 c0 u_01 > 0, so they repel, and compress.
    let mut s = pair_solver(
        DVec2::new(u, 0.0),
        DVec2::new(-u, 0.0),
        [rho0; 2],
        RiemannScheme::Paper,
    );
    let a = s.evaluate_accelerations().to_vec();
    println!("approaching: a = {a:?}");
    assert!(a[0].x < 0.0 && a[1].x > 0.0, "{a:?}");
    // Equal and opposite (equal masses): round-off only.
    assert!((a[0] + a[1]).length() <= 1e-15 * a[0].length());
    let drho = s.evaluate_density_rates();
    assert!(drho[0] > 0.0 && drho[1] > 0.0, "{drho:?}");

    // Separating at zero pressure: β = 0, so no force at all (no artificial attraction), and
    // the density falls.
    let mut s = pair_solver(
        DVec2::new(-u, 0.0),
        DVec2::new(u, 0.0),
        [rho0; 2],
        RiemannScheme::Paper,
    );
    assert_eq!(s.evaluate_accelerations(), &[DVec2::ZERO, DVec2::ZERO]);
    let drho = s.evaluate_density_rates();
    assert!(drho[0] < 0.0 && drho[1] < 0.0);
    // SPHinXsys's test form (β = 1 always): separating particles attract.
    let mut s = pair_solver(
        DVec2::new(-u, 0.0),
        DVec2::new(u, 0.0),
        [rho0; 2],
        RiemannScheme::SphinxsysTests,
    );
    let a = s.evaluate_accelerations().to_vec();
    assert!(a[0].x > 0.0 && a[1].x < 0.0, "{a:?}");

    // A compressed pair at rest repels (P* = p̄ > 0).
    let mut s = pair_solver(
        DVec2::ZERO,
        DVec2::ZERO,
        [1.001 * rho0; 2],
        RiemannScheme::Paper,
    );
    let a = s.evaluate_accelerations().to_vec();
    assert!(a[0].x < 0.0 && a[1].x > 0.0);
    // Approaching adds to p̄: the same pair pushed harder when approaching.
    let mut s2 = pair_solver(
        DVec2::new(u, 0.0),
        DVec2::new(-u, 0.0),
        [1.001 * rho0; 2],
        RiemannScheme::Paper,
    );
    let a2 = s2.evaluate_accelerations().to_vec();
    assert!(a2[0].x < a[0].x, "{a2:?} vs {a:?}");

    // At rest with p_0 > p_1: the pressure jump slows 0's density growth and speeds 1's.
    let mut s = pair_solver(
        DVec2::ZERO,
        DVec2::ZERO,
        [1.002 * rho0, 1.001 * rho0],
        RiemannScheme::Paper,
    );
    let drho = s.evaluate_density_rates();
    println!("pressure jump: drho = {drho:?}");
    assert!(drho[0] < 0.0 && drho[1] > 0.0);
    // Without the jump (SPHinXsys's test form) nothing changes at rest.
    let mut s = pair_solver(
        DVec2::ZERO,
        DVec2::ZERO,
        [1.002 * rho0, 1.001 * rho0],
        RiemannScheme::SphinxsysTests,
    );
    assert_eq!(s.evaluate_density_rates(), vec![0.0, 0.0]);
}

// ----------------------------------------------------------------- 2. linear momentum

/// Runs 3 advection steps of a free block with velocities `v` and returns
/// `|ΔP| / max_t Σ m|v|`.
///
/// Why round-off: every pair term of the force gather (eq 12, eq 13, the artificial stress, and
/// each ENOG increment of eq 20) is antisymmetric in (i, j) at one instant — the same frozen
/// `e_ij = −e_ji`, the same `P*`, and `m_i V_j/ρ_i = V_i V_j` — so `Σ m a = 0` up to the round-off
/// of summing the same terms in two gathers (~1e-16 × neighbour count of Σ|terms|) per
/// sub-step, over ~30 sub-steps. 1e-12 leaves a factor ≥ 10 over that.
fn momentum_drift<D: Dim>(shear: Shear, n: [usize; 3], v: Vec<D::Vector>) -> f64 {
    let set = block::<D>(n);
    let mut s = UlSolver::new(body(&set, v), constants(), shear, UlParams::default()).unwrap();
    let scale = |s: &UlSolver<D>| -> f64 {
        s.velocities()
            .iter()
            .zip(s.masses())
            .map(|(&v, &m)| m * D::norm(v))
            .sum()
    };
    let p0 = s.linear_momentum();
    let mut sc = scale(&s);
    for _ in 0..3 {
        s.step(f64::INFINITY).unwrap();
        sc = sc.max(scale(&s));
    }
    let d = D::norm(s.linear_momentum() - p0) / sc;
    println!("{}D {}: |ΔP|/Σm|v| = {d:.1e}", D::D, shear.method_name());
    d
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 8, ..ProptestConfig::default() })]

    #[test]
    fn linear_momentum_is_conserved_for_every_variant_2d(
        vs in proptest::collection::vec(-1.0f64..1.0, 2 * 48),
        amp in 0.001f64..0.05,
    ) {
        let v: Vec<DVec2> = (0..48)
            .map(|i| DVec2::new(vs[2 * i], vs[2 * i + 1]) * amp * c0())
            .collect();
        for shear in variants() {
            let d = momentum_drift::<D2>(shear, [8, 6, 1], v.clone());
            prop_assert!(d < 1e-12, "{}: {d:e}", shear.method_name());
        }
    }

    #[test]
    fn linear_momentum_is_conserved_for_every_variant_3d(
        vs in proptest::collection::vec(-1.0f64..1.0, 3 * 48),
        amp in 0.001f64..0.05,
    ) {
        let v: Vec<DVec3> = (0..48)
            .map(|i| DVec3::new(vs[3 * i], vs[3 * i + 1], vs[3 * i + 2]) * amp * c0())
            .collect();
        for shear in variants() {
            let d = momentum_drift::<D3>(shear, [4, 4, 3], v.clone());
            prop_assert!(d < 1e-12, "{}: {d:e}", shear.method_name());
        }
    }
}

// ------------------------------------------------------- 3. ENOG under rigid rotation

fn rotating<D: Dim>(n: [usize; 3], omega: DVec3, form: LaplacianForm) -> UlSolver<D> {
    let set = block::<D>(n);
    let c = centroid::<D>(set.positions());
    let v = set
        .positions()
        .iter()
        .map(|&x| D::vector(omega.cross(D::to_vec3(x - c)).to_array()))
        .collect();
    // Kernel data of x^n: the property is one of the Laplacian form on a fixed geometry (the
    // half-step positions of a ballistic rotation, x + ω×x Δt/2, are no longer a rotation of the
    // velocity field, which would add an O(ω² Δt) projection).
    let params = UlParams {
        stepping: Stepping::Single,
        refresh_kernel_data: false,
        ..UlParams::default()
    };
    let shear = Shear::NonNested { zeta: None, form };
    UlSolver::new(body(&set, v), constants(), shear, params).unwrap()
}

/// After one acoustic step from the initial state (`a = 0` there, so `v^{n+1} = v^n` exactly
/// and the kernel data are those of `x^n`), `A_s = Δt · 2ζ(G/ρ) Σ …` evaluated for the rigid
/// rotation itself. Eq 19 projects `v_ij = ω × x_ij` on `e_ij`: zero per pair up to round-off.
/// Eq 18 does not: at the free surface the tangential pair terms do not cancel.
/// Tolerance: 1e-12 of the eq-18 value (round-off of `e·(ω×e)`, ~1e-16).
fn check_rigid_rotation<D: Dim>(n: [usize; 3], omega: DVec3) {
    let mut cons = rotating::<D>(n, omega, LaplacianForm::Conservative);
    let mut non = rotating::<D>(n, omega, LaplacianForm::NonConservative);
    let dt = 0.1 * cons.stable_dt();
    cons.step(dt).unwrap();
    non.step(dt).unwrap();
    let a_c = max_norm::<D>(cons.accumulated_shear_acceleration()) / dt;
    let a_n = max_norm::<D>(non.accumulated_shear_acceleration()) / dt;
    // Scale: G/ρ · |ω| · Σ|W′|V ~ G|ω|/(ρ h).
    let scale = constants().shear_modulus * omega.length() / (1000.0 * 1.3 * DP);
    println!(
        "{}D rigid rotation: eq 19 max|dA_s/dt| = {a_c:.3e}, eq 18 = {a_n:.3e}, scale {scale:.3e}",
        D::D
    );
    assert!(a_n > 0.1 * scale, "eq 18 should react to rotation");
    assert!(a_c < 1e-12 * a_n, "eq 19 must not: {a_c:e} vs {a_n:e}");
}

#[test]
fn enog_conservative_form_has_no_shear_under_rigid_rotation() {
    check_rigid_rotation::<D2>([10, 6, 1], DVec3::new(0.0, 0.0, 20.0));
    check_rigid_rotation::<D3>([5, 4, 4], DVec3::new(3.0, -5.0, 20.0));
}

/// Paper Fig. 7: the non-conservative form resists rigid rotation. A free 2D block spinning at
/// ω = 20 rad/s (rim speed 0.03 c0) for 30 ms (0.6 rad): eq 18 loses 83.2% (dual) / 83.0%
/// (single) of the spin angular momentum; eq 19 gains 5.28% with either stepping (measured
/// 2026-12-05; the 1.8% / −5.7% once written here predate the current stepping). Eq 19 is not
/// exact here because the body is not in rigid rotation for long: it starts unstressed, so it
/// stretches, and the accumulated `A_s` of eq 20 is a lab-frame vector that does not rotate with
/// the body (the paper's eq 17 moves ∇ inside the time integral), and kernel directions are
/// frozen over each step. Allowed: |Δ| < 6% for eq 19 (the measured 5.28% and a margin of a
/// tenth of it; it allowed 10% before), and eq 18 losing at least 75%, ≥ 5× as much.
#[test]
fn non_conservative_laplacian_brakes_a_rigid_rotation() {
    let run = |form, stepping| {
        let set = block::<D2>([12, 12, 1]);
        let c = centroid::<D2>(set.positions());
        let v = set
            .positions()
            .iter()
            .map(|&x| DVec2::new(-(x.y - c.y), x.x - c.x) * 20.0)
            .collect();
        let shear = Shear::NonNested { zeta: None, form };
        let params = UlParams {
            stepping,
            ..UlParams::default()
        };
        let mut s = UlSolver::new(body(&set, v), constants(), shear, params).unwrap();
        let l0 = s.angular_momentum().z;
        s.advance_to(0.03).unwrap();
        1.0 - s.angular_momentum().z / l0
    };
    let loss_c = run(LaplacianForm::Conservative, Stepping::Dual);
    let loss_n = run(LaplacianForm::NonConservative, Stepping::Dual);
    let loss_cs = run(LaplacianForm::Conservative, Stepping::Single);
    let loss_ns = run(LaplacianForm::NonConservative, Stepping::Single);
    println!("spin loss: eq 19 {loss_c:.3e} (single {loss_cs:.3e}), eq 18 {loss_n:.3e} (single {loss_ns:.3e})");
    assert!(loss_c.abs() < 0.06 && loss_cs.abs() < 0.06);
    assert!(loss_n > 0.75 && loss_ns > 0.75);
    assert!(loss_n > 5.0 * loss_c.abs() && loss_ns > 5.0 * loss_cs.abs());
}

// ------------------------------------------------------------------- 4. at rest

/// At rest with ρ = ρ0: p = 0, τ = 0, A_s = 0 and every Riemann term vanishes, so every
/// acceleration is exactly zero (not just small), free surfaces and corners included.
#[test]
fn body_at_rest_stays_at_rest() {
    fn check<D: Dim>(n: [usize; 3]) {
        for shear in variants() {
            let set = block::<D>(n);
            let mut s = UlSolver::new(
                body(&set, Vec::new()),
                constants(),
                shear,
                UlParams::default(),
            )
            .unwrap();
            for _ in 0..3 {
                s.step(f64::INFINITY).unwrap();
            }
            assert_eq!(
                max_norm::<D>(s.velocities()),
                0.0,
                "{}",
                shear.method_name()
            );
            let x0 = s.to_original_order(s.positions());
            assert_eq!(x0, set.positions().to_vec());
        }
    }
    check::<D2>([8, 5, 1]);
    check::<D3>([4, 4, 3]);
}

/// Regression (oscillating plate 24 % too slow with `ul-enog`): the pressure jump of the paper's
/// Riemann continuity, `(p_i − p_j)/(ρ0 c0)`, changes the density of a body that does not move.
/// In a solid the density is the volumetric strain, so this is a volumetric creep; for a bent
/// plate it relaxes the through-thickness pressure gradient (first order at the free surfaces,
/// time scale H²/(c0 h) ≪ the period) and softens the plate (measured, H/dp = 10, v_f = 0.05:
/// T = 0.346 with the jump, 0.279 without; the paper's 0.279 is at H/dp = 30). Without the jump
/// the density changes only through motion: a body at rest with a bending-like linear density
/// profile keeps it exactly.
#[test]
fn continuity_without_pressure_jump_ties_density_to_motion() {
    let set = block::<D2>([12, 6, 1]);
    let rho: Vec<f64> = set
        .positions()
        .iter()
        .map(|x| 1000.0 * (1.0 + 1e-3 * (x.y / (6.0 * DP) - 0.5)))
        .collect();
    let rates = |scheme: RiemannScheme| {
        let mut b = body(&set, Vec::new());
        b.densities = rho.clone();
        let params = UlParams {
            riemann: scheme,
            ..UlParams::default()
        };
        let mut s = UlSolver::new(b, constants(), Shear::non_nested(), params).unwrap();
        s.evaluate_density_rates()
            .iter()
            .fold(0.0f64, |m, r| m.max(r.abs()))
    };
    assert_eq!(rates(RiemannScheme::SphinxsysTests), 0.0);
    assert_eq!(rates(RiemannScheme::LimitedNoJump), 0.0);
    // The paper's form: the 1 kg/m³ profile relaxes in a few ms (≪ the plate's period).
    let paper = rates(RiemannScheme::Paper);
    println!("max |dρ/dt| at rest, paper scheme: {paper:.3e} kg/m³/s");
    assert!(paper > 1.0e2, "{paper}");
}

// ------------------------------------------------------------- 5. dual vs single

/// A 2D block 16 × 8 with a smooth velocity field (|v|max = 0.02 c0), run 2 ms with dual and
/// with single stepping (ENOG and OG). Dual freezes the kernel data over ~6 sub-steps (0.2 h of
/// motion at most), so the trajectories differ by a small fraction of the displacement.
/// Tolerance: 2% of the largest displacement (measured, printed: ~0.1–0.5%).
#[test]
fn dual_and_single_stepping_agree_on_a_short_trajectory() {
    for shear in [Shear::non_nested(), Shear::Original] {
        let run = |stepping| {
            let set = block::<D2>([16, 8, 1]);
            let v = set
                .positions()
                .iter()
                .map(|&x| DVec2::new((x.y * 20.0).sin(), (x.x * 10.0).cos()) * (0.02 * c0()))
                .collect();
            let params = UlParams {
                stepping,
                ..UlParams::default()
            };
            let mut s = UlSolver::new(body(&set, v), constants(), shear, params).unwrap();
            s.advance_to(0.002).unwrap();
            let x = s.to_original_order(s.positions());
            let u: Vec<DVec2> = x
                .iter()
                .zip(set.positions())
                .map(|(&a, &b)| a - b)
                .collect();
            (x, u, s.step_count(), s.acoustic_step_count())
        };
        let (xd, ud, nd, ad) = run(Stepping::Dual);
        let (xs, _, ns, _) = run(Stepping::Single);
        let diff = xd
            .iter()
            .zip(&xs)
            .map(|(a, b)| (*a - *b).length())
            .fold(0.0, f64::max);
        let umax = max_norm::<D2>(&ud);
        println!(
            "{}: dual {nd} advection / {ad} acoustic steps, single {ns} steps; max|Δx| / max|u| = {:.3e}",
            shear.method_name(),
            diff / umax
        );
        assert!(diff < 0.02 * umax);
        assert!(nd < ns);
    }
}

// ---------------------------------------------------------------- 6. bad input

#[test]
fn invalid_input_is_rejected_naming_the_field() {
    let set = block::<D2>([4, 4, 1]);
    let err = |b: Body<D2>, shear: Shear, p: UlParams| -> String {
        UlSolver::new(b, constants(), shear, p)
            .err()
            .expect("should fail")
            .to_string()
    };
    let ok = || body(&set, Vec::new());
    let p = UlParams::default();
    let mut b = ok();
    b.dp = 0.0;
    assert!(err(b, Shear::Original, p).contains("dp"));
    let mut b = ok();
    b.volumes.pop();
    assert!(err(b, Shear::Original, p).contains("volumes"));
    let mut b = ok();
    b.volumes[3] = -1.0;
    assert!(err(b, Shear::Original, p).contains("volumes[3]"));
    let mut b = ok();
    b.densities = vec![1000.0; 3];
    assert!(err(b, Shear::Original, p).contains("densities"));
    let mut b = ok();
    b.velocities = vec![DVec2::ZERO; 2];
    assert!(err(b, Shear::Original, p).contains("velocities"));
    let mut b = ok();
    b.positions[1] = DVec2::new(f64::NAN, 0.0);
    assert!(err(b, Shear::Original, p).contains("positions[1]"));
    let zeta = Shear::NonNested {
        zeta: Some(-1.0),
        form: LaplacianForm::Conservative,
    };
    assert!(err(ok(), zeta, p).contains("zeta"));
    let eps = Shear::ArtificialStress {
        epsilon: -0.3,
        n: 4,
    };
    assert!(err(ok(), eps, p).contains("epsilon"));
    let bad = UlParams {
        cfl_acoustic: 0.0,
        ..p
    };
    assert!(err(ok(), Shear::Original, bad).contains("cfl_acoustic"));
    let bad = UlParams {
        h_over_dp: f64::NAN,
        ..p
    };
    assert!(err(ok(), Shear::Original, bad).contains("h_over_dp"));
    let mut b = ok();
    b.positions = vec![];
    b.volumes = vec![];
    assert!(matches!(
        UlSolver::new(b, constants(), Shear::Original, p),
        Err(Error::EmptyBody { .. })
    ));
    // An isolated particle has no neighbours.
    let mut b = ok();
    b.positions[0] = DVec2::new(1.0, 1.0);
    assert!(matches!(
        UlSolver::new(b, constants(), Shear::Original, p),
        Err(Error::TooFewNeighbours { found: 0, .. })
    ));
}

/// Two particles flying apart at 0.5 c0 leave each other's support within a few steps: the run
/// stops with `LostNeighbours` naming the particle's input index.
#[test]
fn particles_that_lose_all_neighbours_stop_the_run() {
    let v = 0.5 * c0();
    let b = pair_body(DVec2::new(-v, 0.0), DVec2::new(v, 0.0), [1000.0; 2]);
    // The paper's Riemann limiter dissipates only in compression, so the pair separates freely.
    let params = UlParams {
        riemann: sph_ul::RiemannScheme::Paper,
        ..UlParams::default()
    };
    let mut s = UlSolver::new(b, constants(), Shear::non_nested(), params).unwrap();
    let mut result = Ok(());
    for _ in 0..100 {
        if let Err(e) = s.step(f64::INFINITY) {
            result = Err(e);
            break;
        }
    }
    match result {
        Err(Error::LostNeighbours { particle, .. }) => assert!(particle < 2),
        other => panic!("expected LostNeighbours, got {other:?}"),
    }
}

// ------------------------------------------------------------ 7. reordering

/// The body is given in reversed order, so the first rebuild permutes every particle. A fixed
/// constraint on the input's left column and a probe on one input particle must follow their
/// particles through every reordering; `original_index` must be a permutation.
#[test]
fn reordering_keeps_constraints_probes_and_the_input_order() {
    let set = block::<D2>([12, 6, 1]);
    let mut x: Vec<DVec2> = set.positions().to_vec();
    x.reverse();
    let n = x.len();
    let v: Vec<DVec2> = x
        .iter()
        .map(|p| DVec2::new(0.0, (p.x * 15.0).sin()) * 0.02 * c0())
        .collect();
    let b = Body::<D2> {
        positions: x.clone(),
        volumes: vec![DP * DP; n],
        dp: DP,
        velocities: v,
        densities: Vec::new(),
    };
    let left: Vec<u32> = (0..n as u32).filter(|&i| x[i as usize].x < DP).collect();
    let mut c = Constraints::new();
    c.push(
        Constraint::Fixed {
            particles: left.clone(),
        },
        n,
    )
    .unwrap();
    let tip = (0..n).max_by(|&a, &b| x[a].x.total_cmp(&x[b].x)).unwrap() as u32;
    let mut s = UlSolver::new(b, constants(), Shear::non_nested(), UlParams::default())
        .unwrap()
        .with_constraints(c)
        .with_probes(vec![Probe::particle("tip", tip)], 0.0)
        .unwrap();
    assert_ne!(s.original_index()[0], 0, "reversed input must be reordered");
    for _ in 0..10 {
        s.step(f64::INFINITY).unwrap();
    }
    let mut idx = s.original_index().to_vec();
    idx.sort_unstable();
    assert_eq!(idx, (0..n as u32).collect::<Vec<_>>());
    let xo: Vec<DVec2> = s.to_original_order(s.positions());
    for &i in &left {
        assert_eq!(xo[i as usize], x[i as usize], "fixed particle {i} moved");
    }
    let probe = &s.probes()[0];
    assert_eq!(*probe.positions.last().unwrap(), xo[tip as usize]);
    assert!((xo[tip as usize] - x[tip as usize]).length() > 0.0);
    // Every output field is available and has one entry per particle.
    for name in s.field_names() {
        let f = s.field(name).unwrap();
        let len = match f {
            sph_core::Field::Scalar(v) => v.len(),
            sph_core::Field::Vector(v) => v.len(),
            sph_core::Field::Matrix(v) => v.len(),
        };
        assert_eq!(len, n, "{name}");
    }
}

// ------------------------------------------------------------- 8. fracture and disorder

/// With `allow_isolated` the same separating pair flies on and is counted as fractured.
#[test]
fn isolated_particles_are_counted_when_fracture_is_allowed() {
    let v = 0.5 * c0();
    let b = pair_body(DVec2::new(-v, 0.0), DVec2::new(v, 0.0), [1000.0; 2]);
    let params = UlParams {
        allow_isolated: true,
        riemann: sph_ul::RiemannScheme::Paper,
        ..UlParams::default()
    };
    let mut s = UlSolver::new(b, constants(), Shear::non_nested(), params).unwrap();
    assert_eq!(s.isolated_max(), 0);
    for _ in 0..100 {
        s.step(f64::INFINITY).unwrap();
    }
    assert_eq!(s.isolated(), 2);
    assert_eq!(s.isolated_max(), 2);
    let t = s.first_isolation_time().expect("isolation recorded");
    assert!(t > 0.0 && t < s.time());
    // Ballistic: no neighbour, no force.
    let before = s.velocities().to_vec();
    for _ in 0..20 {
        s.step(f64::INFINITY).unwrap();
    }
    assert_eq!(s.velocities(), &before[..]);
}

/// The accumulated disorder indicator is zero for an affine motion (a free rigid rotation is
/// affine to first order in ω t: x = (I + t Ω) X + O(ω² t²)) and large for a checkerboard
/// velocity field (the zigzag mode).
#[test]
fn accumulated_disorder_is_zero_for_affine_motion_and_sees_a_zigzag() {
    let mut s = rotating::<D2>(
        [10, 6, 1],
        DVec3::new(0.0, 0.0, 2.0),
        LaplacianForm::Conservative,
    );
    assert!(s.disorder().iter().all(|&e| e < 1e-12));
    let dt = s.stable_dt();
    for _ in 0..20 {
        s.step(dt).unwrap();
    }
    let affine = s.disorder().iter().copied().fold(0.0, f64::max);
    let set = block::<D2>([10, 6, 1]);
    let v: Vec<DVec2> = set
        .positions()
        .iter()
        .map(|x| {
            let (i, j) = ((x.x / DP) as i64, (x.y / DP) as i64);
            DVec2::new(0.0, if (i + j) % 2 == 0 { 0.2 } else { -0.2 })
        })
        .collect();
    let params = UlParams {
        stepping: Stepping::Single,
        ..UlParams::default()
    };
    let mut z = UlSolver::new(body(&set, v), constants(), Shear::non_nested(), params).unwrap();
    for _ in 0..20 {
        z.step(dt).unwrap();
    }
    let zigzag = z.disorder().iter().copied().fold(0.0, f64::max);
    println!("accumulated disorder: affine {affine:.3e}, zigzag {zigzag:.3e}");
    assert!(affine < 1e-4, "{affine}");
    assert!(
        zigzag > 100.0 * affine && zigzag > 1e-3,
        "{zigzag} vs {affine}"
    );
}

// ------------------------------------------------------------- 9. contact between bodies

/// Two blocks of one solver, made separate bodies, collide head-on: the contact pressure
/// conserves linear momentum to round-off, keeps them apart (measured: closest surface gap
/// 0.81 dp), and they rebound (left block −2.39 m/s after +2.85 m/s); the same blocks as one
/// body hold each other in tension and rebound less (−1.25 m/s).
#[test]
fn contact_between_bodies_conserves_momentum_and_rebounds() {
    let run = |contact: bool| {
        let a = block::<D2>([6, 6, 1]);
        let shifted: Vec<DVec2> = a
            .positions()
            .iter()
            .map(|x| *x + DVec2::new(7.0 * DP, 0.0))
            .collect();
        let n = a.len();
        let mut positions = a.positions().to_vec();
        positions.extend(shifted);
        let mut volumes = a.volumes().to_vec();
        volumes.extend(a.volumes());
        let v0 = 0.05 * c0();
        let velocities = (0..2 * n)
            .map(|i| DVec2::new(if i < n { v0 } else { -v0 }, 0.0))
            .collect();
        let body = Body {
            positions,
            volumes,
            dp: DP,
            velocities,
            densities: Vec::new(),
        };
        let mut s =
            UlSolver::new(body, constants(), Shear::non_nested(), UlParams::default()).unwrap();
        if contact {
            s = s
                .with_contact((0..2 * n).map(|i| u32::from(i >= n)).collect())
                .unwrap();
        }
        let mut min_gap = f64::INFINITY;
        let mut p_max: f64 = 0.0;
        while s.time() < 6e-3 {
            s.step(f64::INFINITY).unwrap();
            let x = Solver::<D2>::positions(&s);
            let ring = s.original_index();
            let (mut right_left, mut left_right) = (f64::INFINITY, f64::NEG_INFINITY);
            for (k, &o) in ring.iter().enumerate() {
                if (o as usize) < n {
                    left_right = left_right.max(x[k].x);
                } else {
                    right_left = right_left.min(x[k].x);
                }
            }
            min_gap = min_gap.min(right_left - left_right);
            let p = s.linear_momentum();
            p_max = p_max.max(p.length());
        }
        let v = Solver::<D2>::velocities(&s);
        let left: f64 = s
            .original_index()
            .iter()
            .zip(v)
            .filter(|(&o, _)| (o as usize) < n)
            .map(|(_, v)| v.x)
            .sum::<f64>()
            / n as f64;
        (min_gap, p_max, left, v0)
    };
    let (gap, p, left, v0) = run(true);
    println!(
        "contact: min gap {:.3} dp, |p| max {p:.3e}, left block v {left:.3} (v0 {v0:.3})",
        gap / DP
    );
    assert!(gap > 0.3 * DP, "bodies interpenetrate: gap {gap}");
    assert!(p < 1e-12 * v0 * 72.0 * 1000.0 * DP * DP, "momentum {p}");
    assert!(left < -0.3 * v0, "no rebound: {left}");
    let (_, _, left_one, _) = run(false);
    println!("one body: left block v {left_one:.3}");
    assert!(
        left_one > left,
        "one body should not rebound as well: {left_one} vs {left}"
    );
}

/// ENOG's shear stress is output only: without it (`track_shear_stress = false`, what the
/// cases do when no snapshot is written) the motion is the same to the last bit, and no `τ`
/// is kept.
#[test]
fn enog_motion_does_not_depend_on_tracking_the_shear_stress() {
    let set = block::<D2>([16, 8, 1]);
    let c = centroid::<D2>(set.positions());
    let amp = 0.02 * c0() / (8.0 * DP);
    let v: Vec<DVec2> = set
        .positions()
        .iter()
        .map(|&x| DVec2::new(-(x.y - c.y), x.x - c.x) * amp + DVec2::new(x.x - c.x, 0.0) * amp)
        .collect();
    let run = |track: bool| {
        let params = UlParams {
            track_shear_stress: track,
            ..UlParams::default()
        };
        let mut s = UlSolver::new(
            body(&set, v.clone()),
            constants(),
            Shear::non_nested(),
            params,
        )
        .unwrap();
        while s.time() < 0.005 {
            s.step(2.0e-4).unwrap();
        }
        s
    };
    let (on, off) = (run(true), run(false));
    assert_eq!(on.acoustic_step_count(), off.acoustic_step_count());
    let bits = |x: &[DVec2]| {
        x.iter()
            .map(|p| (p.x.to_bits(), p.y.to_bits()))
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(on.positions()), bits(off.positions()));
    assert_eq!(bits(on.velocities()), bits(off.velocities()));
    assert_eq!(on.densities(), off.densities());
    assert!(on.shear_stress().iter().any(|t| *t != glam::DMat2::ZERO));
    assert!(off.shear_stress().is_empty());
}

#[test]
fn coincident_particles_are_refused_on_any_thread_count() {
    // 2,400 particles: the scan of the pairs for a zero distance splits over the team.
    let set = block::<D2>([60, 40, 1]);
    let mut b = body(&set, Vec::new());
    b.positions[1500] = b.positions[1501];
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let e = pool
            .install(|| {
                UlSolver::new(
                    b.clone(),
                    constants(),
                    Shear::non_nested(),
                    UlParams::default(),
                )
            })
            .err()
            .expect("coincident particles accepted")
            .to_string();
        assert!(
            e.contains("positions") && e.contains("coincides with a neighbour"),
            "{threads} threads: {e}"
        );
    }
}
