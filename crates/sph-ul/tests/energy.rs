//! Energy of the UL solver (`ul-og`, `ul-oas`, `ul-enog`), 2D and 3D:
//!
//! 1. the pressure/continuity pair never creates energy (`dE/dt ≤ 0`, exactly, from the rates);
//! 2. a free oscillation with dissipation on never gains energy;
//! 3. the energy budget closes (free oscillation, both Riemann schemes; contact).
//!
//! Material and bodies as in `properties.rs` (`common`); `-- --nocapture` prints measurements.

mod common;

use common::*;
use glam::{DVec2, DVec3};
use proptest::prelude::*;
use sph_core::{Body, Dim, Solver, D2, D3};
use sph_geometry::generate::ParticleSet;
use sph_ul::{RiemannScheme, Shear, Stepping, UlParams, UlSolver};

// ------------------------------------------------- 1. pressure/continuity dissipate energy

/// `dE/dt = Σ m v·a + Σ m p/ρ² dρ/dt` from the pressure (eq 12) and continuity (eq 11) rates of
/// an ENOG body at its first step (`A_s = 0`, so the forces are the Riemann pressure only).
/// Analytically `dE/dt = ½ Σ_ij V_i V_j W′ [β ρ0 c0 u_ij² + (p_i − p_j)²/(ρ0 c0)] ≤ 0`; the
/// returned pair is `(dE/dt, Σ |terms|)` so the test can bound the round-off.
fn energy_rate<D: Dim>(v: Vec<D::Vector>, rho: Vec<f64>, set: &ParticleSet<D>) -> (f64, f64) {
    let mut b = body(set, v);
    b.densities = rho;
    let mut s = UlSolver::new(b, constants(), Shear::non_nested(), UlParams::default()).unwrap();
    let a = s.evaluate_accelerations().to_vec();
    let drho = s.evaluate_density_rates();
    let c = constants();
    let (mut rate, mut scale) = (0.0, 0.0);
    for i in 0..s.len() {
        let m = s.masses()[i];
        let rho = s.densities()[i];
        let p = c.sound_speed.powi(2) * (rho - c.density);
        let k = m * D::dot(s.velocities()[i], a[i]);
        let e = m * p / (rho * rho) * drho[i];
        rate += k + e;
        scale += k.abs() + e.abs();
    }
    (rate, scale)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// Tolerance: the identity is exact; the two sums reorder the same pair terms, so the
    /// residual is round-off, ~1e-16 of Σ|terms| times the neighbour count; 1e-12 leaves a
    /// factor > 100. Also strictly negative (every case has approaching pairs and pressure
    /// jumps). Measured (3D case, printed): dE/dt = −13.8 W against Σ|terms| = 18.2 W.
    #[test]
    fn pressure_and_continuity_never_create_energy(
        vs in proptest::collection::vec(-1.0f64..1.0, 2 * 48),
        rs in proptest::collection::vec(-1.0f64..1.0, 48),
    ) {
        let set = block::<D2>([8, 6, 1]);
        let u = 0.02 * c0();
        let v: Vec<DVec2> = (0..48).map(|i| DVec2::new(vs[2 * i], vs[2 * i + 1]) * u).collect();
        let rho: Vec<f64> = rs.iter().map(|r| 1000.0 * (1.0 + 1e-3 * r)).collect();
        let (rate, scale) = energy_rate::<D2>(v, rho, &set);
        prop_assert!(rate <= 1e-12 * scale, "dE/dt = {rate:e}, scale {scale:e}");
        prop_assert!(rate < 0.0);
    }
}

#[test]
fn pressure_and_continuity_never_create_energy_3d() {
    let set = block::<D3>([4, 4, 4]);
    let n = set.positions().len();
    let v: Vec<DVec3> = (0..n)
        .map(|i| {
            let t = i as f64;
            DVec3::new((1.3 * t).sin(), (2.1 * t).cos(), (0.7 * t).sin()) * 0.02 * c0()
        })
        .collect();
    let rho: Vec<f64> = (0..n)
        .map(|i| 1000.0 * (1.0 + 1e-3 * (3.7 * i as f64).sin()))
        .collect();
    let (rate, scale) = energy_rate::<D3>(v, rho, &set);
    println!("3D: dE/dt = {rate:e}, scale {scale:e}");
    assert!(rate < 0.0 && rate <= 1e-12 * scale);
}

// ----------------------------------------------------------- 2. free oscillation energy

/// A free 2D block 16 × 8 with a zero-momentum, zero-spin extensional velocity field
/// `v = A (x − c, −(y − c))/(8 dp)`, A = 0.02 c0.
fn breathing_block() -> Body<D2> {
    let set = block::<D2>([16, 8, 1]);
    let c = centroid::<D2>(set.positions());
    let amp = 0.02 * c0() / (8.0 * DP);
    let v = set
        .positions()
        .iter()
        .map(|&x| DVec2::new(x.x - c.x, -(x.y - c.y)) * amp)
        .collect();
    body(&set, v)
}

/// The total-energy and kinetic-energy histories of [`breathing_block`], sampled every 0.2 ms.
fn free_oscillation(shear: Shear, params: UlParams) -> (Vec<f64>, Vec<f64>) {
    let mut s = UlSolver::new(breathing_block(), constants(), shear, params).unwrap();
    let (mut total, mut kinetic) = (vec![s.energy().total()], vec![s.energy().kinetic]);
    // Period of the breathing mode ≈ 3.5 ms (measured from the kinetic peaks); run 40 ms.
    while s.time() < 0.04 {
        s.step(2.0e-4).unwrap();
        let e = s.energy();
        total.push(e.total());
        kinetic.push(e.kinetic);
    }
    (total, kinetic)
}

/// Local maxima of the kinetic energy, relative to the initial value.
fn kinetic_peaks(kinetic: &[f64]) -> Vec<f64> {
    (1..kinetic.len() - 1)
        .filter(|&k| kinetic[k] > kinetic[k - 1] && kinetic[k] >= kinetic[k + 1])
        .map(|k| kinetic[k] / kinetic[0])
        .collect()
}

/// OG (eq 13–14, uncorrected gradient, the default): the estimate
/// `½mv² + Σ m c0²(ln ρ/ρ0 + ρ0/ρ − 1) + Σ V τ:τ/4G` is conserved by the semi-discrete equations
/// up to the Riemann dissipation (≤ 0); position Verlet adds a bounded O(Δt²) oscillation. Allowed:
/// 1e-3 relative above E(0) at any sample (every 0.2 ms over 40 ms); measured: never above E(0),
/// dual and single stepping. (With the B-corrected gradient the pair is not energy-consistent:
/// +5% measured, printed.)
///
/// ENOG has no stored energy of its own (`A_s` is an accumulated acceleration; the output stress
/// only estimates it: +9% measured), so the test is that successive kinetic-energy peaks of the
/// free oscillation decay: measured 0.952, 0.926, 0.899, 0.858, … 0.709 of K(0) over 11 peaks.
///
/// OAS: the artificial stress has no energy in the estimate (measured +8.5%); checked bounded.
#[test]
fn free_oscillation_never_gains_energy() {
    let run = |shear: Shear, corrected: bool, stepping: Stepping| {
        let params = UlParams {
            corrected_velocity_gradient: corrected,
            stepping,
            ..UlParams::default()
        };
        let (total, kinetic) = free_oscillation(shear, params);
        let e0 = total[0];
        let max = total.iter().cloned().fold(0.0, f64::max);
        println!(
            "{} (B {corrected}, {stepping:?}): max E/E0 − 1 = {:.2e}, E_end/E0 = {:.4}, {} samples",
            shear.method_name(),
            max / e0 - 1.0,
            total.last().unwrap() / e0,
            total.len()
        );
        (max / e0 - 1.0, kinetic)
    };
    for stepping in [Stepping::Dual, Stepping::Single] {
        let (gain, _) = run(Shear::Original, false, stepping);
        assert!(gain <= 1e-3, "OG gained {gain:e}");
        let (_, kinetic) = run(Shear::non_nested(), false, stepping);
        let peaks = kinetic_peaks(&kinetic);
        println!("  ENOG kinetic peaks / K0: {peaks:.3?}");
        assert!(peaks.len() >= 8);
        assert!(peaks.windows(2).all(|w| w[1] <= w[0]), "{peaks:?}");
        assert!(peaks[0] < 1.0);
    }
    // With the correction B and with the artificial stress (OAS) alike: measured, no sample
    // above E(0); the same 1e-3 as OG (it allowed OAS 20 % before it was measured).
    let (gain, _) = run(Shear::Original, true, Stepping::Dual);
    assert!(gain <= 1e-3, "OG with B gained {gain:e}");
    let (gain, _) = run(Shear::artificial_stress(), false, Stepping::Dual);
    assert!(gain <= 1e-3, "OAS gained {gain:e}");
}

// -------------------------------------------------------------- 3. energy budget

/// The energy budget closes on the free oscillation of section 2 (40 ms, ≈ 11 periods, ≈ 440
/// acoustic steps) with the paper's Riemann scheme (the library default: dissipation with the
/// limiter, density diffusion by the pressure jump) and with the cases' scheme (β = 1, no
/// jump): the residual `total − total(0)` (kinetic + volumetric + shear + contact + dissipated +
/// diffused − artificial work), relative to the initial energy, stays below the bound stated
/// per variant at every step. What is exact and what is estimated is in `sph_ul::energy`;
/// measured values are printed.
///
/// - OG, OAS (artificial stress work accumulated): exact up to the hypoelastic `V̇ τ:τ/(4G)`
///   term and the O(Δt²) of position Verlet; measured 4.6e-3 / 2.1e-3 (paper scheme),
///   1.4e-3 / 1.5e-3 (β = 1): bound 1e-2.
/// - ENOG: the shear term is the estimate from the output stress (eq 26), not the energy of
///   `A_s`: measured 0.11 / 0.10, bound 0.2; with the exactly accumulated `shear_work` instead,
///   measured 2.8e-4 / 1.8e-4: bound 1e-3.
#[test]
fn energy_budget_closes_on_a_free_oscillation() {
    for scheme in [RiemannScheme::Paper, RiemannScheme::SphinxsysTests] {
        for shear in variants() {
            let params = UlParams {
                riemann: scheme,
                ..UlParams::default()
            };
            let mut s = UlSolver::new(breathing_block(), constants(), shear, params).unwrap();
            let (mut worst, mut worst_exact) = (0.0f64, 0.0f64);
            while s.time() < 0.04 {
                s.step(2.0e-4).unwrap();
                let b = Solver::<D2>::energy_budget(&s).unwrap();
                worst = worst.max((b.residual() / b.initial_total).abs());
                if let Some(w) = b.get("shear_work") {
                    let exact = b.residual() - b.get("shear").unwrap() + w;
                    worst_exact = worst_exact.max((exact / b.initial_total).abs());
                }
            }
            let b = Solver::<D2>::energy_budget(&s).unwrap();
            println!(
                "{scheme:?} {}: max |residual|/E0 = {worst:.2e} (exact shear work: \
                 {worst_exact:.2e}); of E0 = {:.3e}: dissipated {:.3e}, diffused {:.3e}",
                shear.method_name(),
                b.initial_total,
                b.get("dissipated").unwrap(),
                b.get("diffused").unwrap(),
            );
            assert!(b.get("dissipated").unwrap() > 0.0);
            assert!(b.get("diffused").unwrap() >= 0.0);
            match shear {
                Shear::NonNested { .. } => {
                    assert!(worst < 0.2, "ENOG residual {worst}");
                    assert!(worst_exact < 1e-3, "ENOG exact-work residual {worst_exact}");
                }
                _ => assert!(worst < 1e-2, "{} residual {worst}", shear.method_name()),
            }
        }
    }
}

/// Two 2D blocks (6 × 6 particles each, ENOG, 0.05 c0 each) collide through the contact of
/// `properties.rs` (section 9) and separate: linear momentum stays at round-off during the
/// contact (bound as in its section 2: 1e-12 of Σ m|v|), and the budget closes. With the exact work
/// of `A_s` and of the
/// contact forces in place of their estimates the residual stays below 5e-3 of E0 (measured
/// 1.7e-3: the time-stepping error of the stiff contact); the estimated contact energy is positive while the blocks touch and zero once
/// they are apart, where it equals the exact contact work only if the contact is conservative
/// (the difference, printed, is what the contact model took out).
#[test]
fn contact_conserves_momentum_and_the_budget_closes() {
    let a = block::<D2>([6, 6, 1]);
    let n = a.len();
    let mut positions = a.positions().to_vec();
    positions.extend(a.positions().iter().map(|x| *x + DVec2::new(7.0 * DP, 0.0)));
    let mut volumes = a.volumes().to_vec();
    volumes.extend(a.volumes());
    let v0 = 0.05 * c0();
    let body = Body::<D2> {
        positions,
        volumes,
        dp: DP,
        velocities: (0..2 * n)
            .map(|i| DVec2::new(if i < n { v0 } else { -v0 }, 0.0))
            .collect(),
        densities: Vec::new(),
    };
    let params = UlParams {
        riemann: RiemannScheme::SphinxsysTests,
        ..UlParams::default()
    };
    let mut s = UlSolver::new(body, constants(), Shear::non_nested(), params)
        .unwrap()
        .with_contact((0..2 * n).map(|i| u32::from(i >= n)).collect())
        .unwrap();
    let scale = 2.0 * n as f64 * 1000.0 * DP * DP * v0;
    let (mut p_max, mut worst, mut contact_max) = (0.0f64, 0.0f64, 0.0f64);
    while s.time() < 6e-3 {
        s.step(f64::INFINITY).unwrap();
        let p: DVec2 = s.linear_momentum();
        p_max = p_max.max(p.length());
        let b = Solver::<D2>::energy_budget(&s).unwrap();
        let exact = b.residual() - b.get("shear").unwrap() + b.get("shear_work").unwrap()
            - b.get("contact").unwrap()
            + b.get("contact_work").unwrap();
        worst = worst.max((exact / b.initial_total).abs());
        contact_max = contact_max.max(b.get("contact").unwrap());
    }
    let b = Solver::<D2>::energy_budget(&s).unwrap();
    let f = Solver::<D2>::series(&s);
    println!(
        "contact: |P| max {:.2e} of Σm|v|; residual with exact works {worst:.2e} of E0; contact \
         energy max {:.3e}, at the end {:.3e}, contact work at the end {:.3e} (E0 {:.3e}); \
         {} force samples",
        p_max / scale,
        contact_max,
        b.get("contact").unwrap(),
        b.get("contact_work").unwrap(),
        b.initial_total,
        f[0].len()
    );
    assert!(p_max < 1e-12 * scale, "momentum {p_max}");
    assert!(worst < 5e-3, "residual {worst}");
    assert!(contact_max > 0.0 && b.get("contact").unwrap() == 0.0);
    // The recorded contact forces on the two bodies are equal and opposite (columns x, y), and
    // the left body was pushed to −x.
    assert_eq!(f.len(), 2);
    let fx = f[0].column("x").unwrap();
    let peak = fx.iter().copied().fold(0.0, f64::min);
    assert!(peak < 0.0 && f[0].len() > 10);
    for c in ["x", "y"] {
        for (a, b) in f[0].column(c).unwrap().iter().zip(f[1].column(c).unwrap()) {
            assert!((a + b).abs() <= 1e-12 * peak.abs(), "{c}: {a} vs {b}");
        }
    }
}
