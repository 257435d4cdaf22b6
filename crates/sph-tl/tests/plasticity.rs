//! Elastic–plastic TL bodies (`tl`, `tl-gm` with J2 or Johnson–Cook at finite strain):
//!
//! 1. a patch under a prescribed homogeneous uniaxial-strain velocity field (`F = diag(λ,1,1)`,
//!    in 2D plane strain and in 3D) follows the closed form of the exponential-map return:
//!    loading past yield, then elastic unloading;
//! 2. `tl-hf` refuses a plastic law in one line;
//! 3. the plastic history survives a checkpoint bit for bit;
//! 4. an elastic body has no plastic history or fields; Johnson–Cook heats and offers the
//!    temperature field.
//!
//! Steel-like (E = 200 GPa, ν = 0.3, ρ0 = 7850), dp = 1 mm, small blocks: seconds.

use glam::{DVec2, DVec3};
use sph_core::state::{StateReader, StateWriter};
use sph_core::tool::{RigidTool, ToolMotion, ToolShape};
use sph_core::{Body, Constraint, Constraints, Dim, Field, Solver, TimeFunction, D2, D3};
use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
use sph_materials::plasticity::{IsotropicHardening, JohnsonCook, PlasticLaw, ThermalSoftening};
use sph_materials::{ElasticConstants, LinearElastic, Material};
use sph_tl::{Shear, TlParams, TlSolver};

const DP: f64 = 1e-3;
const SIGMA0: f64 = 250e6;
const H_LIN: f64 = 2e9;

fn steel() -> LinearElastic {
    LinearElastic::new(ElasticConstants::from_youngs(200e9, 0.3, 7850.0).unwrap())
}

fn linear() -> PlasticLaw {
    PlasticLaw::J2(IsotropicHardening::Linear {
        yield_stress: SIGMA0,
        hardening_modulus: H_LIN,
    })
}

fn block<D: Dim>(size: D::Vector) -> ParticleSet<D> {
    let shape = Aabb::<D>::from_corner(D::zero(), size).unwrap();
    ParticleSet::fill(&Lattice::new(DP, D::zero()).unwrap(), &shape).unwrap()
}

fn body<D: Dim>(set: &ParticleSet<D>, velocities: Vec<D::Vector>) -> Body<D> {
    Body {
        positions: set.positions().to_vec(),
        volumes: set.volumes().to_vec(),
        dp: DP,
        velocities,
        densities: Vec::new(),
    }
}

/// Strain rate of the patch (1/s) and the turning times: loading to `T1` (log strain 1 %, five
/// times the yield strain), unloading at `−RATE` to `T2` (back to 0.7 %); ~1000 steps.
const RATE: f64 = 100.0;
const T1: f64 = 1e-4;
const T2: f64 = 1.3e-4;

fn log_strain(t: f64) -> f64 {
    if t <= T1 {
        RATE * t
    } else {
        RATE * (2.0 * T1 - t)
    }
}

fn strain_rate(t: f64) -> f64 {
    if t <= T1 {
        RATE
    } else {
        -RATE
    }
}

/// `Ḟ_xx` of the prescribed motion `x = X exp(ε(t))` along x.
fn f_rate(t: f64) -> f64 {
    strain_rate(t) * log_strain(t).exp()
}

/// A patch whose every particle moves with `v = ε̇(t) X exp(ε(t)) e_x`: the corrected
/// gradient makes `Ḟ = diag(Ḟ_xx, 0, 0)` exact for every particle, edges included.
fn patch<D: Dim>(size: D::Vector, shear: Shear) -> TlSolver<D, LinearElastic>
where
    LinearElastic: Material<D>,
{
    let set = block::<D>(size);
    let x0 = set.positions().to_vec();
    let mut constraints = Constraints::new();
    for (i, &x) in x0.iter().enumerate() {
        let x0x = D::component(x, 0);
        let velocity = TimeFunction::<D>::new(move |t| D::vector([f_rate(t) * x0x, 0.0, 0.0]));
        let c = Constraint::PrescribedVelocity {
            particles: vec![i as u32],
            velocity,
        };
        constraints.push(c, x0.len()).unwrap();
    }
    TlSolver::new(
        body(&set, vec![D::zero(); x0.len()]),
        steel(),
        shear,
        TlParams::default(),
    )
    .unwrap()
    .with_plasticity(linear())
    .unwrap()
    .with_constraints(constraints)
}

/// The closed form of uniaxial strain `F = diag(λ, 1, 1)`, `ε = ln λ`, loading: the Hencky
/// deviator is `2G (2/3 ε − ε̄p)` along x, `q = 2Gε − 3G ε̄p`, and past yield
/// `ε̄p = (2Gε − σ0)/(3G + H)` (the flow direction is fixed, so the return is exact).
fn plastic_strain_loading(eps: f64, g: f64) -> f64 {
    ((2.0 * g * eps - SIGMA0) / (3.0 * g + H_LIN)).max(0.0)
}

/// Cauchy von Mises stress of the closed form with plastic strain `ep` at `ε`: `|2Gε − 3G ε̄p|/J`
/// with `J = λ = exp ε`.
fn von_mises_of(eps: f64, ep: f64, g: f64) -> f64 {
    (2.0 * g * eps - 3.0 * g * ep).abs() / eps.exp()
}

/// Runs the patch and returns the largest deviations of `ε̄p` (over its final value) and of the
/// von Mises stress (over σ0) from the closed form, over every particle and step, and the final
/// `ε̄p`. Each step's return is taken at its half step `F^{n+1/2} = F^{n+1} − (Δt/2) Ḟ^{n+1}`;
/// the output stress is the return at `F^{n+1}` from that history. During unloading `ε̄p`
/// keeps the value of the peak half step and the stress is elastic.
fn run_patch<D: Dim>(size: D::Vector, shear: Shear) -> (f64, f64, f64)
where
    LinearElastic: Material<D>,
{
    let mut s = patch::<D>(size, shear);
    let g = Material::<D>::constants(&steel()).shear_modulus;
    let (mut eps_peak, mut err_ep, mut err_q, mut ep_final) = (0.0f64, 0.0f64, 0.0f64, 0.0);
    let mut steps = 0;
    while s.time() < T2 * (1.0 - 1e-12) {
        let stop = if s.time() < T1 * (1.0 - 1e-12) {
            T1
        } else {
            T2
        };
        let info = s.step(stop - s.time()).unwrap();
        steps += 1;
        let ep = s.plastic_strain();
        let Some(Field::Scalar(vm)) = s.field("von_mises") else {
            panic!("no von_mises field")
        };
        for (i, &f) in s.deformation_gradients().iter().enumerate() {
            let fxx = D::matrix_get(f, 0, 0);
            // The off-diagonal and lateral entries stay at their identity values.
            let lateral = (D::frobenius(f - D::identity()) - (fxx - 1.0).abs()).abs();
            assert!(lateral < 1e-12, "F = {f:?}");
            let eps = fxx.ln();
            let eps_mid = (fxx - 0.5 * info.dt * f_rate(s.time())).ln();
            eps_peak = eps_peak.max(eps_mid);
            let ep_ref = plastic_strain_loading(eps_peak, g);
            err_ep = err_ep.max((ep[i] - ep_ref).abs());
            let q_ref = if eps >= eps_peak {
                von_mises_of(eps, plastic_strain_loading(eps, g).max(ep_ref), g)
            } else {
                von_mises_of(eps, ep_ref, g)
            };
            err_q = err_q.max((vm[i] - q_ref).abs() / SIGMA0);
            ep_final = ep_ref;
        }
    }
    assert!(steps > 500, "{steps} steps");
    assert!(eps_peak > 0.0099 && ep_final > 0.0, "{eps_peak} {ep_final}");
    (err_ep / ep_final, err_q, ep_final)
}

/// Tolerance 1e-9: the return is exact for this proportional path, so what is left is the
/// round-off of `F` integrated over ~1000 half steps and of the eigen-solver and logarithm.
/// The same path in 2D (plane strain, `F_zz = 1` and the 3×3 history) and 3D, for `tl` and
/// `tl-gm` (the homogeneous field has no hourglass penalty).
#[test]
fn uniaxial_strain_patch_follows_the_closed_form_elastic_plastic_path() {
    for (name, shear) in [("tl", Shear::Original), ("tl-gm", Shear::ganzenmuller())] {
        let (ep, q, epf) = run_patch::<D2>(DVec2::new(8.0 * DP, 6.0 * DP), shear);
        println!("2D {name}: max |Δε̄p|/ε̄p {ep:.2e}, max |Δq|/σ0 {q:.2e}, ε̄p = {epf:.5e}");
        assert!(ep < 1e-9 && q < 1e-9);
        let (ep, q, epf) = run_patch::<D3>(DVec3::new(5.0 * DP, 4.0 * DP, 4.0 * DP), shear);
        println!("3D {name}: max |Δε̄p|/ε̄p {ep:.2e}, max |Δq|/σ0 {q:.2e}, ε̄p = {epf:.5e}");
        assert!(ep < 1e-9 && q < 1e-9);
    }
}

#[test]
fn hf_refuses_a_plastic_law_in_one_line() {
    let set = block::<D2>(DVec2::new(4.0 * DP, 4.0 * DP));
    let s = TlSolver::new(
        body(&set, Vec::new()),
        steel(),
        Shear::hourglass_free(),
        TlParams::default(),
    )
    .unwrap();
    let e = s
        .with_plasticity(linear())
        .err()
        .expect("HF must refuse")
        .to_string();
    assert!(
        e.contains("material.law") && e.contains("tl-hf") && !e.contains('\n'),
        "{e}"
    );
}

/// A 2D steel block hitting a rigid wall at 150 m/s (plastic at the struck face).
fn impact(law: Option<PlasticLaw>) -> TlSolver<D2, LinearElastic> {
    let set = block::<D2>(DVec2::new(6.0 * DP, 10.0 * DP));
    let n = set.len();
    // The block's bottom half cell touches y = 0.
    let b = body(&set, vec![DVec2::new(0.0, -150.0); n]);
    let wall = RigidTool::new(
        "wall",
        ToolShape::half_space(DVec2::ZERO, DVec2::Y).unwrap(),
        ToolMotion::fixed(),
    );
    let s = TlSolver::new(b, steel(), Shear::Original, TlParams::default()).unwrap();
    let s = match law {
        Some(l) => s.with_plasticity(l).unwrap(),
        None => s,
    };
    s.with_tools(vec![wall]).unwrap()
}

#[test]
fn plastic_history_survives_a_checkpoint_bit_for_bit() {
    let mut a = impact(Some(linear()));
    for _ in 0..40 {
        a.step(f64::INFINITY).unwrap();
    }
    let mut w = StateWriter::new();
    a.save_state(&mut w).unwrap();
    let bytes = w.into_bytes();
    let mut b = impact(Some(linear()));
    b.restore_state(&mut StateReader::new(&bytes)).unwrap();
    for _ in 0..40 {
        a.step(f64::INFINITY).unwrap();
        b.step(f64::INFINITY).unwrap();
    }
    assert!(a.plastic_work() > 0.0);
    assert_eq!(a.plastic_history(), b.plastic_history());
    assert_eq!(a.positions(), b.positions());
    assert_eq!(a.plastic_work().to_bits(), b.plastic_work().to_bits());
}

/// The impact dissipates: plastic strain at the struck face, plastic work a sizeable share of
/// the kinetic energy lost, `det Cp⁻¹ = 1` on every particle (plastic incompressibility through
/// the solver, 1e-12); the output field is the history.
#[test]
fn impact_flows_plastically_at_the_struck_face() {
    let mut s = impact(Some(linear()));
    let ke0 = s.energy().kinetic;
    while s.time() < 5e-6 {
        s.step(f64::INFINITY).unwrap();
    }
    let e = s.energy();
    let wp = s.plastic_work();
    let ep = s.plastic_strain();
    let (mut bottom, mut top) = (0.0f64, 0.0f64);
    for (x, &e) in s.reference_positions().iter().zip(&ep) {
        if x.y < 2.0 * DP {
            bottom = bottom.max(e);
        } else if x.y > 8.0 * DP {
            top = top.max(e);
        }
    }
    println!(
        "impact: KE0 {ke0:.4e} J, KE {:.4e}, strain {:.4e}, plastic work {wp:.4e}, \
         max ε̄p struck face {bottom:.4e}, far end {top:.4e}",
        e.kinetic, e.strain
    );
    assert!(bottom > 0.01 && bottom > 10.0 * top);
    assert!(wp > 0.05 * ke0 && wp < ke0);
    for p in s.plastic_history() {
        let det = p.history.inverse_plastic_cauchy_green.determinant();
        assert!((det - 1.0).abs() < 1e-12, "det Cp⁻¹ − 1 = {:e}", det - 1.0);
    }
    assert!(s.field_names().contains(&"plastic_strain"));
    match s.field("plastic_strain") {
        Some(Field::Scalar(v)) => assert_eq!(v, ep),
        _ => panic!("no plastic_strain field"),
    }
    assert!(!s.field_names().contains(&"temperature"));
    assert!(s
        .figures()
        .iter()
        .any(|(k, v)| *k == "plastic_work" && *v == wp));
}

#[test]
fn an_elastic_body_has_no_plastic_history() {
    let mut s = impact(None);
    for _ in 0..5 {
        s.step(f64::INFINITY).unwrap();
    }
    assert!(s.plasticity().is_none() && s.plastic_history().is_empty());
    assert!(!s.field_names().contains(&"plastic_strain"));
    assert!(s.field("plastic_strain").is_none());
    assert!(!s.figures().iter().any(|(k, _)| *k == "plastic_work"));
}

#[test]
fn johnson_cook_heats_where_it_flows_and_offers_the_temperature() {
    let jc = PlasticLaw::JohnsonCook(JohnsonCook {
        a: 806e6,
        b: 614e6,
        n: 0.168,
        c: 0.0089,
        reference_strain_rate: 1.0,
        thermal: Some(ThermalSoftening {
            m: 1.1,
            room_temperature: 293.15,
            melting_temperature: 1813.15,
            initial_temperature: 293.15,
            taylor_quinney: 0.9,
            specific_heat: 460.0,
        }),
    });
    let mut s = impact(Some(jc));
    while s.time() < 5e-6 {
        s.step(f64::INFINITY).unwrap();
    }
    assert!(s.thermal() && s.field_names().contains(&"temperature"));
    let t = s.temperatures();
    let ep = s.plastic_strain();
    let hottest = t.iter().copied().fold(0.0, f64::max);
    println!(
        "johnson-cook impact: max T {hottest:.2} K, max ε̄p {:.4e}",
        ep.iter().copied().fold(0.0, f64::max)
    );
    assert!(hottest > 293.15 + 1.0);
    for (ti, ei) in t.iter().zip(&ep) {
        // No flow, no heat.
        assert_eq!(*ei == 0.0, *ti == 293.15);
    }
}
