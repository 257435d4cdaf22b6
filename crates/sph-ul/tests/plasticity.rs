//! Elastic–plastic UL bodies (`ul-og`, `ul-oas` with a J2 law): a patch under a prescribed
//! homogeneous uniaxial-strain velocity field follows the closed-form stress path of the radial
//! return (loading past yield, then elastic unloading); ENOG refuses a plastic law; the energy
//! budget closes with the plastic dissipation; the history survives a checkpoint; elastic bodies
//! are unchanged.

mod common;

use common::*;
use glam::{DVec2, DVec3};
use sph_core::state::{StateReader, StateWriter};
use sph_core::{Constraint, Constraints, Dim, Field, Solver, TimeFunction, D2, D3};
use sph_materials::plasticity::{equivalent_stress, IsotropicHardening, PlasticLaw};
use sph_materials::ElasticConstants;
use sph_ul::{Shear, Stepping, UlParams, UlSolver};

/// Steel-like: E = 200 GPa, ν = 0.3 (G ≈ 76.9 GPa), ρ0 = 7850 kg/m³.
fn steel() -> ElasticConstants {
    ElasticConstants::from_youngs(200e9, 0.3, 7850.0).unwrap()
}

const SIGMA0: f64 = 250e6;
const H_LIN: f64 = 2e9;

fn linear() -> PlasticLaw {
    PlasticLaw::J2(IsotropicHardening::Linear {
        yield_stress: SIGMA0,
        hardening_modulus: H_LIN,
    })
}

/// Strain rate of the patch (1/s): 1 % in 1 ms, ~1000 acoustic steps.
const RATE: f64 = 10.0;
/// Loading to `T1` (ε = ln stretch = 1 %), unloading at `−RATE` to `T2` (back to 0.7 %).
const T1: f64 = 1e-3;
const T2: f64 = 1.3e-3;

/// `∫ ε̇ dt` of the prescribed history: the logarithmic strain along x.
fn log_strain(t: f64) -> f64 {
    if t <= T1 {
        RATE * t
    } else {
        RATE * (2.0 * T1 - t)
    }
}

/// `ε̇(t)`: loading up to and including `T1` (the step that ends at `T1` loads throughout).
fn strain_rate(t: f64) -> f64 {
    if t <= T1 {
        RATE
    } else {
        -RATE
    }
}

/// A patch of `n` particles whose every particle moves with the homogeneous uniaxial-strain
/// field `v = ε̇(t) x e_x`, i.e. `x(t) = x0 exp(ε(t))`: one prescribed-velocity constraint per
/// particle. Single stepping (a rebuild, so a fresh correction matrix, every acoustic step) and
/// the corrected velocity gradient make `L = diag(ε̇, 0, 0)` exact for every particle, edges
/// included, up to the motion within one step.
fn patch<D: Dim>(n: [usize; 3], shear: Shear, law: Option<PlasticLaw>) -> UlSolver<D> {
    let set = block::<D>(n);
    let x0 = set.positions().to_vec();
    let b = body(&set, vec![D::zero(); x0.len()]);
    let params = UlParams {
        stepping: Stepping::Single,
        corrected_velocity_gradient: true,
        ..UlParams::default()
    };
    let mut constraints = Constraints::new();
    for (i, &x) in x0.iter().enumerate() {
        let x0x = D::component(x, 0);
        let velocity = TimeFunction::<D>::new(move |t| {
            D::vector([strain_rate(t) * x0x * log_strain(t).exp(), 0.0, 0.0])
        });
        let c = Constraint::PrescribedVelocity {
            particles: vec![i as u32],
            velocity,
        };
        constraints.push(c, x0.len()).unwrap();
    }
    let s = UlSolver::new(b, steel(), shear, params).unwrap();
    let s = match law {
        Some(l) => s.with_plasticity(l).unwrap(),
        None => s,
    };
    s.with_constraints(constraints)
}

/// The extent of the particles along x, and of their velocities.
fn extents<D: Dim>(s: &UlSolver<D>) -> (f64, f64) {
    let span = |v: &[D::Vector]| {
        let xs = v.iter().map(|&p| D::component(p, 0));
        xs.clone().fold(f64::MIN, f64::max) - xs.fold(f64::MAX, f64::min)
    };
    (span(s.positions()), span(s.velocities()))
}

/// The closed form of the path for the loading branch: uniaxial log strain `ε` has the
/// deviatoric equivalent strain `ē = κ ε` (`κ = 2/3` in 3D; `1/√3` for the 2D in-plane
/// deviator, `d = 2`); loading is proportional, so `q = 3G(ē − ε̄p)` exactly and, past yield,
/// `q = σ_0 + H ε̄p`: `ε̄p = (3Gē − σ_0)/(3G + H)`. Returns `(q, ε̄p)`.
fn loading(eps: f64, kappa: f64, g: f64) -> (f64, f64) {
    let e_eq = kappa * eps;
    if 3.0 * g * e_eq <= SIGMA0 {
        (3.0 * g * e_eq, 0.0)
    } else {
        let ep = (3.0 * g * e_eq - SIGMA0) / (3.0 * g + H_LIN);
        (SIGMA0 + H_LIN * ep, ep)
    }
}

/// Runs the patch through loading and unloading and returns the largest deviation of `q` from
/// the closed form (relative to σ_0) and of `ε̄p` (relative to its final value), over every
/// particle and step. The reference strain is the patch's measured log stretch; the peak strain
/// is that of the mid-step of the turning step (the first drift of eq 23 still loads), where the
/// stress peaked. Unloading from `(q_peak, ε̄p_peak)` is elastic: `q = |q_peak − 3Gκ(ε_peak −
/// ε)|`, `ε̄p = ε̄p_peak` (the 0.3 % of unloading take the signed stress from `q_peak` to
/// about `−0.55 q_peak` in 2D, `−0.77 q_peak` in 3D: reverse yield would need `−q_peak`).
fn run_patch<D: Dim>(n: [usize; 3], shear: Shear, kappa: f64) -> (f64, f64, f64) {
    let mut s = patch::<D>(n, shear, Some(linear()));
    let g = steel().shear_modulus;
    let l0 = extents(&s).0;
    let (mut eps_peak, mut err_q, mut err_ep, mut ep_final) = (0.0f64, 0.0f64, 0.0f64, 0.0);
    let mut steps = 0;
    while s.time() < T2 * (1.0 - 1e-12) {
        let (l, dv) = extents(&s);
        let stop = if s.time() < T1 * (1.0 - 1e-12) {
            T1
        } else {
            T2
        };
        let info = s.step(stop - s.time()).unwrap();
        steps += 1;
        // The strain after the step's first drift (with the velocities of its start).
        let eps_mid = ((l + 0.5 * info.dt * dv) / l0).ln();
        let eps = (extents(&s).0 / l0).ln();
        eps_peak = eps_peak.max(eps_mid).max(eps);
        let (q_ref, ep_ref) = if eps >= eps_peak {
            loading(eps, kappa, g)
        } else {
            let (q_peak, ep_peak) = loading(eps_peak, kappa, g);
            ((q_peak - 3.0 * g * kappa * (eps_peak - eps)).abs(), ep_peak)
        };
        let ep = s.plastic_strain();
        for (i, &tau) in s.shear_stress().iter().enumerate() {
            let q = equivalent_stress::<D>(tau);
            // Tension along x: τ_xx > 0 on loading while q grows.
            err_q = err_q.max((q - q_ref).abs() / SIGMA0);
            err_ep = err_ep.max((ep[i] - ep_ref).abs());
        }
        ep_final = ep_ref;
    }
    assert!(steps > 500, "{steps} steps");
    assert!(
        eps_peak > 0.0099 && ep_final > 0.0,
        "peak strain {eps_peak}, ε̄p {ep_final}"
    );
    (err_q, err_ep / ep_final, ep_final)
}

#[test]
fn uniaxial_strain_patch_follows_the_closed_form_elastic_plastic_path() {
    // Loading to ε = 1 % (5× the yield strain), unloading to 0.7 %, through zero stress. Tolerance 1e-4: the
    // stress integrates Σ h D of the velocity gradient, the reference the log stretch of the
    // positions; they differ by O(Σ (ε̇ h)²) ~ 1e-8 in strain (≈ 1e-5 σ_0), plus the correction
    // matrix of the step's start against the kernel data of its middle (a bias of ε̇ h/2 ~ 5e-6
    // of D). Without the return the error would be the whole plastic part (q ≈ 4 σ_0 off).
    let (q2, ep2, epf2) = run_patch::<D2>([12, 12, 1], Shear::Original, 1.0 / 3f64.sqrt());
    println!("2D OG: max |Δq|/σ0 {q2:.2e}, max |Δε̄p|/ε̄p {ep2:.2e}, ε̄p = {epf2:.4e}");
    assert!(q2 < 1e-4 && ep2 < 1e-4);
    let (q, ep, _) = run_patch::<D2>([10, 10, 1], Shear::artificial_stress(), 1.0 / 3f64.sqrt());
    println!("2D OAS: max |Δq|/σ0 {q:.2e}, max |Δε̄p|/ε̄p {ep:.2e}");
    assert!(q < 1e-4 && ep < 1e-4);
    let (q3, ep3, epf3) = run_patch::<D3>([6, 6, 6], Shear::Original, 2.0 / 3.0);
    println!("3D OG: max |Δq|/σ0 {q3:.2e}, max |Δε̄p|/ε̄p {ep3:.2e}, ε̄p = {epf3:.4e}");
    assert!(q3 < 1e-4 && ep3 < 1e-4);
    // GNOG: the homogeneous field has no penalty, the stress path is OG's.
    let (q, ep, _) = run_patch::<D2>([10, 10, 1], Shear::generalized(), 1.0 / 3f64.sqrt());
    println!("2D GNOG: max |Δq|/σ0 {q:.2e}, max |Δε̄p|/ε̄p {ep:.2e}");
    assert!(q < 1e-4 && ep < 1e-4);
}

#[test]
fn enog_refuses_a_plastic_law_in_one_line() {
    let set = block::<D2>([4, 4, 1]);
    let b = body(&set, vec![DVec2::ZERO; set.len()]);
    let s = UlSolver::new(b, steel(), Shear::non_nested(), UlParams::default()).unwrap();
    let e = s
        .with_plasticity(linear())
        .err()
        .expect("ENOG must refuse")
        .to_string();
    assert!(
        e.contains("material.law") && e.contains("ul-enog") && !e.contains('\n'),
        "{e}"
    );
}

#[test]
fn invalid_plastic_constants_are_refused() {
    let set = block::<D2>([4, 4, 1]);
    let b = body(&set, vec![DVec2::ZERO; set.len()]);
    let s = UlSolver::new(b, steel(), Shear::Original, UlParams::default()).unwrap();
    let bad = PlasticLaw::J2(IsotropicHardening::Linear {
        yield_stress: 0.0,
        hardening_modulus: 1e9,
    });
    let e = s.with_plasticity(bad).err().unwrap().to_string();
    assert!(e.contains("yield_stress"), "{e}");
}

/// A free steel block whose two halves move towards each other at `±v`: compression waves
/// that yield the middle.
fn colliding_block(v: f64, budget: bool) -> UlSolver<D2> {
    colliding_block_with(Shear::Original, v, budget)
}

fn colliding_block_with(shear: Shear, v: f64, budget: bool) -> UlSolver<D2> {
    let set = block::<D2>([24, 8, 1]);
    let xc = 12.0 * DP;
    let vel = set
        .positions()
        .iter()
        .map(|p| DVec2::new(if p.x < xc { v } else { -v }, 0.0))
        .collect();
    let params = UlParams {
        energy_budget: budget,
        ..UlParams::default()
    };
    UlSolver::new(body(&set, vel), steel(), shear, params)
        .unwrap()
        .with_plasticity(linear())
        .unwrap()
}

#[test]
fn energy_budget_closes_with_the_plastic_dissipation() {
    // 40 m/s: a uniaxial-strain pulse of ~v/c ≈ 8e-3, four times the yield strain. The budget's
    // residual is what the scheme leaves unaccounted: measured −608 J against 6.36e4 J of
    // plastic work, as the same run with an unreachable yield stress (−666 J); 2 % of the
    // plastic work leaves a factor 2 (without the term the residual would be the whole plastic
    // work; with the stored-energy drop at the return as the dissipation, +7.6e3 J).
    let mut s = colliding_block(40.0, true);
    let ke0 = s.energy().kinetic;
    while s.time() < 2e-5 {
        s.step(f64::INFINITY).unwrap();
    }
    let b = s.energy_budget().unwrap();
    let wp = b.get("plastic").unwrap();
    let res = b.residual();
    println!("KE0 {ke0:.4e} J, plastic work {wp:.4e} J, residual {res:.3e} J");
    assert!(wp > 0.05 * ke0, "plastic work {wp} of KE0 {ke0}");
    assert!(
        res.abs() < 0.02 * wp,
        "residual {res} against plastic work {wp}"
    );
    assert_eq!(
        s.figures()
            .iter()
            .find(|f| f.0 == "plastic_work")
            .unwrap()
            .1,
        s.plastic_work()
    );
    // GNOG: the same budget with its penalty's work as a term. GNOG needs the corrected
    // velocity gradient, which makes the nested shear pair not energy-consistent (UlParams::
    // corrected_velocity_gradient); its residual is that of OG with the same gradient: measured
    // +9.42e3 J (penalty term 2.17e3 J, plastic work 7.32e4 J) against +1.02e4 J for OG with B.
    let run = |shear: Shear, corrected: bool| {
        let set = block::<D2>([24, 8, 1]);
        let xc = 12.0 * DP;
        let vel = set
            .positions()
            .iter()
            .map(|p| DVec2::new(if p.x < xc { 40.0 } else { -40.0 }, 0.0))
            .collect();
        let params = UlParams {
            corrected_velocity_gradient: corrected,
            ..UlParams::default()
        };
        let mut s = UlSolver::new(body(&set, vel), steel(), shear, params)
            .unwrap()
            .with_plasticity(linear())
            .unwrap();
        while s.time() < 2e-5 {
            s.step(f64::INFINITY).unwrap();
        }
        s.energy_budget().unwrap()
    };
    let (gnog, og_b) = (run(Shear::generalized(), false), run(Shear::Original, true));
    let (wp, res, pen) = (
        gnog.get("plastic").unwrap(),
        gnog.residual(),
        gnog.get("hourglass_penalty").unwrap(),
    );
    println!(
        "GNOG: plastic work {wp:.4e} J, penalty {pen:.3e} J, residual {res:.3e} J; OG with B {:.3e} J",
        og_b.residual()
    );
    assert!(wp > 0.05 * ke0 && pen != 0.0);
    assert!(res.abs() < 1.5 * og_b.residual().abs());
    let max_ep = s.plastic_strain().into_iter().fold(0.0, f64::max);
    assert!(max_ep > 0.0);
    // The output field is the history, in the current order.
    assert!(s.field_names().contains(&"plastic_strain"));
    match s.field("plastic_strain") {
        Some(Field::Scalar(v)) => assert_eq!(v, s.plastic_strain()),
        _ => panic!("no plastic_strain field"),
    }
}

#[test]
fn plastic_history_survives_a_checkpoint_bit_for_bit() {
    let mut a = colliding_block(40.0, true);
    for _ in 0..20 {
        a.step(f64::INFINITY).unwrap();
    }
    let mut w = StateWriter::new();
    a.save_state(&mut w).unwrap();
    let bytes = w.into_bytes();
    let mut b = colliding_block(40.0, true);
    b.restore_state(&mut StateReader::new(&bytes)).unwrap();
    for _ in 0..20 {
        a.step(f64::INFINITY).unwrap();
        b.step(f64::INFINITY).unwrap();
    }
    assert!(a.plastic_work() > 0.0);
    assert_eq!(a.plastic_strain(), b.plastic_strain());
    assert_eq!(a.shear_stress(), b.shear_stress());
    assert_eq!(a.positions(), b.positions());
    assert_eq!(a.plastic_work().to_bits(), b.plastic_work().to_bits());
}

#[test]
fn an_elastic_body_has_no_plastic_history_and_a_high_yield_stress_changes_nothing() {
    // A yield stress far above every stress: the plastic body runs bit for bit as the elastic
    // one (elastic trials are returned untouched).
    let set = block::<D3>([5, 4, 3]);
    let v: Vec<DVec3> = set
        .positions()
        .iter()
        .map(|p| DVec3::new(p.y, -p.x, 0.3 * p.z) * 50.0)
        .collect();
    let mk = || {
        UlSolver::new(
            body(&set, v.clone()),
            steel(),
            Shear::Original,
            UlParams::default(),
        )
    };
    let mut elastic = mk().unwrap();
    let mut plastic = mk()
        .unwrap()
        .with_plasticity(PlasticLaw::J2(IsotropicHardening::Linear {
            yield_stress: 1e12,
            hardening_modulus: 0.0,
        }))
        .unwrap();
    assert!(elastic.plastic_strain().is_empty() && elastic.plasticity().is_none());
    assert!(!elastic.field_names().contains(&"plastic_strain"));
    assert!(elastic.field("plastic_strain").is_none());
    for _ in 0..10 {
        elastic.step(f64::INFINITY).unwrap();
        plastic.step(f64::INFINITY).unwrap();
    }
    assert_eq!(elastic.positions(), plastic.positions());
    assert_eq!(elastic.shear_stress(), plastic.shear_stress());
    assert!(plastic.plastic_strain().iter().all(|&e| e == 0.0));
}

#[test]
fn johnson_cook_heats_where_it_flows_and_offers_the_temperature() {
    use sph_materials::plasticity::{JohnsonCook, ThermalSoftening};
    // OFHC copper (Johnson & Cook 1983, Table 1) on the steel block's elastic constants:
    // 4 m/s, one advection step (≈0.65 ms: the waves cross the block many times) yields
    // 144 of the 192 particles and leaves the others elastic; the temperature rises exactly where ε̄p > 0, by
    // β σ_y Δε̄p/(ρ0 c_p) per increment, so at least β A ε̄p/(ρ0 c_p) (σ_y ≥ A·(1 − T*^m), T*
    // small here).
    let law = PlasticLaw::JohnsonCook(JohnsonCook {
        a: 90e6,
        b: 292e6,
        n: 0.31,
        c: 0.025,
        reference_strain_rate: 1.0,
        thermal: Some(ThermalSoftening {
            m: 1.09,
            room_temperature: 294.0,
            melting_temperature: 1356.0,
            initial_temperature: 300.0,
            taylor_quinney: 0.9,
            specific_heat: 383.0,
        }),
    });
    let set = block::<D2>([24, 8, 1]);
    let xc = 12.0 * DP;
    let vel = set
        .positions()
        .iter()
        .map(|p| DVec2::new(if p.x < xc { 4.0 } else { -4.0 }, 0.0))
        .collect();
    let mut s = UlSolver::new(
        body(&set, vel),
        steel(),
        Shear::Original,
        UlParams::default(),
    )
    .unwrap()
    .with_plasticity(law)
    .unwrap();
    assert!(s.thermal() && s.field_names().contains(&"temperature"));
    while s.time() < 4e-6 {
        s.step(f64::INFINITY).unwrap();
    }
    let (t, ep) = (s.temperatures(), s.plastic_strain());
    let mut heated = 0;
    for (&t, &e) in t.iter().zip(&ep) {
        if e > 0.0 {
            heated += 1;
            assert!(
                t - 300.0 >= 0.9 * 90e6 * e / (7850.0 * 383.0) * (1.0 - 1e-12),
                "{t} {e}"
            );
        } else {
            assert_eq!(t, 300.0);
        }
    }
    let rise = t.iter().fold(0.0f64, |m, &x| m.max(x - 300.0));
    println!(
        "{heated} of {} particles heated, by up to {rise:.2} K",
        t.len()
    );
    assert!(heated > 0);
    match s.field("temperature") {
        Some(Field::Scalar(v)) => assert_eq!(v, t),
        _ => panic!("no temperature field"),
    }
    // J2 has no temperature.
    assert!(!colliding_block(40.0, false).thermal());
}
