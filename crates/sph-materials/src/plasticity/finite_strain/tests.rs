//! Closed-form checks of the exponential-map return.

use super::*;
use crate::plasticity::{IsotropicHardening, JohnsonCook, ThermalSoftening};

const E: f64 = 200e9;
const NU: f64 = 0.3;
const RHO: f64 = 7850.0;

fn constants() -> ElasticConstants {
    ElasticConstants::from_youngs(E, NU, RHO).unwrap()
}

fn linear(yield_stress: f64, hardening_modulus: f64) -> HenckyPlasticity {
    let law = PlasticLaw::J2(IsotropicHardening::Linear {
        yield_stress,
        hardening_modulus,
    });
    HenckyPlasticity::new(law, &constants()).unwrap()
}

fn von_mises(tau: DMat3) -> f64 {
    let dev = tau - DMat3::IDENTITY * ((tau.x_axis.x + tau.y_axis.y + tau.z_axis.z) / 3.0);
    super::super::equivalent_stress::<D3>(dev)
}

/// Uniaxial strain `F = diag(λ, 1, 1)` to λ = 1.25 in 250 steps with linear hardening: the
/// axes are fixed and the flow direction constant, so the return is exact at every step and
/// must match `ε̄p = (2Gε − σ0)/(3G + H)`, `q = 2Gε − 3Gε̄p`, `τ11 = Kε + 2q/3`,
/// `τ22 = Kε − q/3` (ε = ln λ) to round-off (1e-10 relative: a few hundred ulps of the eigen
/// solver and logarithm).
#[test]
fn uniaxial_strain_matches_the_closed_form_at_every_step() {
    let (s0, h) = (400e6, 10e9);
    let law = linear(s0, h);
    let (k, g) = (constants().bulk_modulus, constants().shear_modulus);
    let mut hist = FinitePlasticState::default();
    let (mut yielded, mut worst) = (0, 0.0f64);
    for step in 1..=250 {
        let lambda = 1.0 + 0.25 * step as f64 / 250.0;
        let f = DMat3::from_diagonal(DVec3::new(lambda, 1.0, 1.0));
        let r = law.return_mapping(f, &hist, 1e-6);
        hist = r.history;
        let eps = lambda.ln();
        let ep = ((2.0 * g * eps - s0) / (3.0 * g + h)).max(0.0);
        let q = 2.0 * g * eps - 3.0 * g * ep;
        let (t11, t22) = (k * eps + 2.0 * q / 3.0, k * eps - q / 3.0);
        let scale = t11.abs();
        worst = worst.max(
            (r.kirchhoff.x_axis.x - t11)
                .abs()
                .max((r.kirchhoff.y_axis.y - t22).abs())
                / scale,
        );
        assert!(
            (r.kirchhoff.x_axis.x - t11).abs() <= 1e-10 * scale,
            "step {step}"
        );
        assert!(
            (r.kirchhoff.y_axis.y - t22).abs() <= 1e-10 * scale,
            "step {step}"
        );
        assert!(
            (r.kirchhoff.z_axis.z - t22).abs() <= 1e-10 * scale,
            "step {step}"
        );
        assert!((hist.state.equivalent_plastic_strain - ep).abs() <= 1e-12);
        yielded += usize::from(r.delta_eps_p > 0.0);
    }
    eprintln!(
        "uniaxial strain: worst |τ − closed form|/τ11 = {worst:.2e} over {yielded} plastic steps"
    );
    assert!(yielded > 240, "{yielded} plastic steps");
}

/// Uniaxial stress: axial stretch to 1.3 in 150 steps, the lateral stretch solved each step so
/// that `τ22 = τ33 = 0` (Newton with a difference quotient, to 1e-9 of the axial stress).
/// The analytic curve of a Hencky law with linear hardening in log strain is
/// `τ = E(H ε + σ0)/(E + H)` beyond yield (`ε = τ/E + ε̄p`, `τ = σ0 + H ε̄p`); matched to
/// 1e-8 relative (the lateral solve's tolerance, amplified by `E/H`).
#[test]
fn uniaxial_stress_follows_the_analytic_hardening_curve() {
    let (s0, h) = (250e6, 2e9);
    let law = linear(s0, h);
    let mut hist = FinitePlasticState::default();
    let (mut mu, mut worst): (f64, f64) = (1.0, 0.0);
    for step in 1..=150 {
        let lambda = 1.0 + 0.3 * step as f64 / 150.0;
        let lateral = |mu: f64| {
            let f = DMat3::from_diagonal(DVec3::new(lambda, mu, mu));
            law.return_mapping(f, &hist, 1e-6)
        };
        for _ in 0..50 {
            let r = lateral(mu);
            if r.kirchhoff.y_axis.y.abs() <= 1e-11 * r.kirchhoff.x_axis.x.abs() {
                break;
            }
            let d = 1e-7 * mu;
            let slope = (lateral(mu + d).kirchhoff.y_axis.y - r.kirchhoff.y_axis.y) / d;
            mu -= r.kirchhoff.y_axis.y / slope;
        }
        let r = lateral(mu);
        hist = r.history;
        let eps = lambda.ln();
        let tau = if E * eps <= s0 {
            E * eps
        } else {
            E * (h * eps + s0) / (E + h)
        };
        worst = worst.max((r.kirchhoff.x_axis.x - tau).abs() / tau);
        assert!(r.kirchhoff.y_axis.y.abs() <= 1e-9 * tau, "step {step}");
        assert!(
            (r.kirchhoff.x_axis.x - tau).abs() <= 1e-8 * tau,
            "step {step}: {} vs {tau}",
            r.kirchhoff.x_axis.x
        );
    }
    eprintln!("uniaxial stress: worst |τ − analytic|/τ = {worst:.2e}, final lateral stretch {mu}");
    // Plastic flow is isochoric: the lateral stretch tends to λ^(−1/2) times the elastic part.
    assert!(mu < 1.0 / 1.3f64.sqrt() * 1.01);
}

/// Simple shear `F = I + γ e1⊗e2` to γ = 1 in 1000 steps, perfectly plastic. Elastic: the
/// Hencky von Mises stress is `2√3 G asinh(γ/2)` (log stretches ±asinh(γ/2)), so yielding
/// starts at `γ_y = 2 sinh(σ0/(2√3 G))`. Beyond: consistency `q = σ0` to 1e-10 relative,
/// no pressure (`J = 1`, `det Cp⁻¹ = 1`: |tr τ| below 1e-6 σ0), and plastic incompressibility
/// `det Fp = 1` to 1e-12 after 1000 returns.
#[test]
fn simple_shear_yields_at_the_hencky_onset_and_stays_on_the_surface() {
    let s0 = 300e6;
    let law = linear(s0, 0.0);
    let g = constants().shear_modulus;
    let gamma_y = 2.0 * (s0 / (2.0 * 3f64.sqrt() * g)).sinh();
    let mut hist = FinitePlasticState::default();
    let n = 1000;
    let (mut first_plastic, mut worst) = (None, 0.0f64);
    for step in 1..=n {
        let gamma = step as f64 / n as f64;
        let f = DMat3::from_cols(DVec3::X, DVec3::new(gamma, 1.0, 0.0), DVec3::Z);
        let r = law.return_mapping(f, &hist, 1e-6);
        hist = r.history;
        let q = von_mises(r.kirchhoff);
        if r.delta_eps_p == 0.0 {
            assert!(
                first_plastic.is_none(),
                "elastic after yielding at step {step}"
            );
            let elastic = 2.0 * 3f64.sqrt() * g * (gamma / 2.0).asinh();
            assert!((q - elastic).abs() <= 1e-12 * elastic, "step {step}");
        } else {
            first_plastic.get_or_insert(gamma);
            worst = worst.max((q - s0).abs() / s0);
            assert!((q - s0).abs() <= 1e-10 * s0, "step {step}: q = {q}");
            let trace = r.kirchhoff.x_axis.x + r.kirchhoff.y_axis.y + r.kirchhoff.z_axis.z;
            assert!(trace.abs() <= 1e-6 * s0, "step {step}: tr τ = {trace}");
        }
    }
    let first = first_plastic.expect("yields");
    assert!(first >= gamma_y && first - 1.0 / n as f64 <= gamma_y);
    let det = hist.inverse_plastic_cauchy_green.determinant();
    eprintln!(
        "simple shear: onset γ = {first} (Hencky γ_y = {gamma_y}), worst |q − σ0|/σ0 = {worst:.2e}, \
         det Cp⁻¹ − 1 = {:.2e}, ε̄p = {}",
        det - 1.0,
        hist.state.equivalent_plastic_strain
    );
    // det Cp⁻¹ = det Fp⁻²: both to 1e-12.
    assert!((det - 1.0).abs() <= 1e-12, "det Cp⁻¹ − 1 = {:e}", det - 1.0);
    assert!(hist.state.equivalent_plastic_strain > 0.5);
}

/// Johnson–Cook with rate and thermal softening along a non-proportional path (stretch then
/// shear, with rotation): after each plastic return the von Mises stress equals the flow
/// stress `σ_y(ε̄p_{n+1}, Δε̄p/Δt, T_n)` computed independently from eq. 1, to 1e-10 relative;
/// `det Cp⁻¹ = 1` to 1e-12 throughout; the temperature rises by `β σ_y Δε̄p/(ρ c_p)`.
#[test]
fn johnson_cook_return_is_consistent_and_isochoric() {
    let jc = JohnsonCook {
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
    };
    let law = HenckyPlasticity::new(PlasticLaw::JohnsonCook(jc), &constants()).unwrap();
    let dt = 1e-7;
    let mut hist = FinitePlasticState::default();
    let (mut plastic, mut worst, mut worst_det) = (0, 0.0f64, 0.0f64);
    for step in 1..=400 {
        let t = step as f64 / 400.0;
        let (c, s) = (t.cos(), t.sin());
        let rotation = DMat3::from_cols(DVec3::new(c, s, 0.0), DVec3::new(-s, c, 0.0), DVec3::Z);
        let stretch = DMat3::from_cols(
            DVec3::new(1.0 + 0.2 * t, 0.0, 0.0),
            DVec3::new(0.4 * t * t, 1.0 - 0.05 * t, 0.0),
            DVec3::new(0.0, 0.1 * t, 1.0),
        );
        let f = rotation * stretch;
        let before = hist.state;
        let r = law.return_mapping(f, &hist, dt);
        hist = r.history;
        if r.delta_eps_p > 0.0 {
            plastic += 1;
            let sy = jc.flow_stress(
                hist.state.equivalent_plastic_strain,
                r.delta_eps_p / dt,
                jc.temperature(before.temperature_rise),
            );
            let q = von_mises(r.kirchhoff);
            worst = worst.max((q - sy).abs() / sy);
            assert!((q - sy).abs() <= 1e-10 * sy, "step {step}: q {q}, σ_y {sy}");
            let heat = jc.adiabatic_heating(sy, r.delta_eps_p, RHO);
            let rise = hist.state.temperature_rise - before.temperature_rise;
            assert!((rise - heat).abs() <= 1e-12 * heat.max(1e-300));
            assert!((r.plastic_work - q * r.delta_eps_p).abs() <= 1e-12 * r.plastic_work);
        }
        let det = hist.inverse_plastic_cauchy_green.determinant();
        worst_det = worst_det.max((det - 1.0).abs());
        assert!((det - 1.0).abs() <= 1e-12, "step {step}: {:e}", det - 1.0);
    }
    eprintln!(
        "johnson-cook: {plastic} plastic steps, worst |q − σ_y|/σ_y = {worst:.2e}, worst |det Cp⁻¹ − 1| = {worst_det:.2e}, ε̄p = {}, ΔT = {} K",
        hist.state.equivalent_plastic_strain, hist.state.temperature_rise
    );
    assert!(plastic > 300, "{plastic} plastic steps");
}

/// Small-strain limit: along a non-proportional symmetric strain path `F = I + ε(t)` of
/// amplitude `a`, the Hencky return equals the hypoelastic radial return of the UL solvers
/// (`s* = s_n + 2G dev Δε`, `p = K tr ε`, [`Plasticity::return_stress`]) up to terms of order
/// `a` relative: measured max |τ − σ_UL| / max|σ_UL| is below 2a for a = 1e-3 and 1e-4, and
/// drops by about 10× with a (first-order agreement: the geometric terms of the logarithm).
#[test]
fn small_strain_limit_is_the_hypoelastic_radial_return() {
    let path = |a: f64, t: f64| {
        let m = DMat3::from_cols(
            DVec3::new((3.0 * t).sin(), 0.3 * (2.0 * t).sin(), 0.1 * t),
            DVec3::new(0.3 * (2.0 * t).sin(), -0.5 * (5.0 * t).sin(), 0.2 * t.cos()),
            DVec3::new(0.1 * t, 0.2 * t.cos(), 0.4 * (4.0 * t).cos() - 0.4),
        );
        m * a
    };
    let deviation = |a: f64| {
        let c = constants();
        let law = linear(0.3 * c.youngs_modulus * a, 0.05 * c.youngs_modulus);
        let (k, g) = (c.bulk_modulus, c.shear_modulus);
        let mut hist = FinitePlasticState::default();
        let mut s = DMat3::ZERO;
        let mut ul = PlasticState::default();
        let mut eps_prev = DMat3::ZERO;
        let (mut worst, mut largest, mut plastic): (f64, f64, usize) = (0.0, 0.0, 0);
        for step in 1..=600 {
            let eps = path(a, 3.0 * step as f64 / 600.0);
            let d = eps - eps_prev;
            eps_prev = eps;
            let tr = |m: DMat3| m.x_axis.x + m.y_axis.y + m.z_axis.z;
            s += (d - DMat3::IDENTITY * (tr(d) / 3.0)) * (2.0 * g);
            let delta = law.plasticity.return_stress::<D3>(&mut s, &mut ul, 1e-6);
            let sigma = s + DMat3::IDENTITY * (k * tr(eps));
            let r = law.return_mapping(DMat3::IDENTITY + eps, &hist, 1e-6);
            hist = r.history;
            plastic += usize::from(delta > 0.0);
            let diff = r.kirchhoff - sigma;
            worst = worst.max(D3::frobenius(diff));
            largest = largest.max(D3::frobenius(sigma));
        }
        assert!(plastic > 100, "{plastic} plastic steps");
        worst / largest
    };
    let (d3, d4) = (deviation(1e-3), deviation(1e-4));
    eprintln!(
        "small-strain limit: max |τ − σ_UL|/max|σ_UL| = {d3:.3e} (a 1e-3), {d4:.3e} (a 1e-4)"
    );
    assert!(d3 < 2e-3 && d4 < 2e-4, "{d3:e} {d4:e}");
    assert!((5.0..20.0).contains(&(d3 / d4)), "ratio {}", d3 / d4);
}

/// Stress and energy agree: with the plastic history frozen (an elastic state after plastic
/// flow), `P = τ F⁻ᵀ` equals `∂ψ/∂F` of [`HenckyPlasticity::strain_energy_density`] by central
/// differences (step 1e-6, agreement 1e-6 of |P|: the difference quotient's truncation and
/// cancellation).
#[test]
fn first_piola_is_the_derivative_of_the_hencky_energy() {
    let law = linear(250e6, 1e9);
    let mut hist = FinitePlasticState::default();
    let f_at = |t: f64| {
        DMat3::from_cols(
            DVec3::new(1.0 + 0.1 * t, 0.05 * t, 0.0),
            DVec3::new(0.3 * t, 1.0 - 0.02 * t, 0.01 * t),
            DVec3::new(0.0, 0.02 * t, 1.0 + 0.03 * t),
        )
    };
    for step in 1..=100 {
        hist = law
            .return_mapping(f_at(step as f64 / 100.0), &hist, 1e-6)
            .history;
    }
    // An elastic state with the frozen Cp⁻¹: `F = (I + A) Cp^½`, so `be = (I + A)(I + A)ᵀ`
    // with a small, non-symmetric `A` (rotation plus stretch) below yield.
    let (c, q) = D3::symmetric_eigen(hist.inverse_plastic_cauchy_green.inverse());
    let cp_half = D3::from_eigen(DVec3::new(c.x.sqrt(), c.y.sqrt(), c.z.sqrt()), q);
    let a = DMat3::from_cols(
        DVec3::new(4e-4, 1e-4, -2e-4),
        DVec3::new(-3e-4, -1e-4, 2e-4),
        DVec3::new(1e-4, 3e-4, 2e-4),
    );
    let f = (DMat3::IDENTITY + a) * cp_half;
    let r = law.return_mapping(f, &hist, 1e-6);
    assert_eq!(r.delta_eps_p, 0.0);
    let p = first_piola_of_kirchhoff(r.kirchhoff, f);
    let h = 1e-6;
    let mut worst = 0.0f64;
    for col in 0..3 {
        for row in 0..3 {
            let mut e = DMat3::ZERO;
            e.col_mut(col)[row] = h;
            let dpsi = (law.strain_energy_density(f + e, &hist)
                - law.strain_energy_density(f - e, &hist))
                / (2.0 * h);
            let exact = p.col(col)[row];
            worst = worst.max((dpsi - exact).abs() / D3::frobenius(p));
            assert!(
                (dpsi - exact).abs() <= 1e-6 * D3::frobenius(p),
                "P[{row}{col}] {exact} vs ∂ψ/∂F {dpsi}"
            );
        }
    }
    eprintln!(
        "P vs ∂ψ/∂F: worst |difference|/|P| = {worst:.2e} (|P| = {:.3e} Pa)",
        D3::frobenius(p)
    );
}

/// An inverted deformation gradient gives a non-finite stress and leaves the history alone.
#[test]
fn inverted_deformation_gives_nan_stress() {
    let law = linear(250e6, 1e9);
    let hist = FinitePlasticState::default();
    let r = law.return_mapping(
        DMat3::from_diagonal(DVec3::new(-1.0, 1.0, 1.0)),
        &hist,
        1e-6,
    );
    assert!(r.kirchhoff.x_axis.x.is_nan());
    assert_eq!(r.history, hist);
}
