//! The radial return of J2 / Johnson–Cook plasticity against closed forms: monotonic
//! uniaxial-strain and simple-shear paths (exact for proportional loading), consistency,
//! plastic incompressibility, the Johnson–Cook clamps, and a finite-difference check of the
//! consistent hardening derivative Newton uses.

use glam::{DMat2, DMat3};
use sph_core::{Dim, D2, D3};
use sph_materials::plasticity::{
    equivalent_stress, plastic_strain_increment, radial_return, IsotropicHardening, JohnsonCook,
    PlasticLaw, PlasticState, Plasticity, ThermalSoftening, CONSISTENCY_TOLERANCE,
};
use sph_materials::ElasticConstants;

/// Steel-like constants: E = 200 GPa, ν = 0.3 (G ≈ 76.9 GPa), ρ = 7850.
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

/// Simo's necking-bar law (σ_0 = 450 MPa, σ_∞ = 715 MPa, δ = 16.93, H = 129.24 MPa).
fn saturation() -> PlasticLaw {
    PlasticLaw::J2(IsotropicHardening::Saturation {
        yield_stress: 450e6,
        hardening_modulus: 129.24e6,
        saturation_stress: 715e6,
        saturation_exponent: 16.93,
    })
}

/// Johnson & Cook 1983 Table 1, OFHC copper: A = 90 MPa, B = 292 MPa, n = 0.31, C = 0.025,
/// m = 1.09, T_melt = 1356 K; room 294 K.
fn johnson_cook(thermal: bool) -> PlasticLaw {
    PlasticLaw::JohnsonCook(JohnsonCook {
        a: 90e6,
        b: 292e6,
        n: 0.31,
        c: 0.025,
        reference_strain_rate: 1.0,
        thermal: thermal.then_some(ThermalSoftening {
            m: 1.09,
            room_temperature: 294.0,
            melting_temperature: 1356.0,
            initial_temperature: 294.0,
            taylor_quinney: 0.9,
            specific_heat: 383.0,
        }),
    })
}

/// The deviator of `e` for the dimension's convention (`d = D::D`, as the UL solver's Jaumann
/// rate: in 2D the in-plane deviator).
fn deviator<D: Dim>(e: D::Matrix) -> D::Matrix {
    e - D::identity() * (D::trace(e) / D::D as f64)
}

/// Equivalent strain of a deviatoric strain, `√(2/3 e:e)`, so that an elastic `s = 2G e` has
/// `q = 3G ē`.
fn equivalent_strain<D: Dim>(e: D::Matrix) -> f64 {
    (2.0 / 3.0 * D::ddot(e, e)).sqrt()
}

/// The rate-independent closed form of monotonic proportional loading: with the direction of
/// `s` fixed, `s = 2G(e − εp)` exactly, so `ε̄p` solves `3G(ē − ε̄p) = σ_y(ε̄p)` (if `3Gē > σ_0`)
/// whatever the step size; solved here by plain bisection, independent of the return's Newton.
fn proportional_plastic_strain(law: &PlasticLaw, g: f64, e_eq: f64) -> f64 {
    let state = |x: f64| PlasticState {
        equivalent_plastic_strain: x,
        temperature_rise: 0.0,
    };
    let f = |x: f64| 3.0 * g * (e_eq - x) - law.flow_stress_after(&state(x), 0.0, 0.0).0;
    if f(0.0) <= 0.0 {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, e_eq);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    0.5 * (lo + hi)
}

/// Drives `n` equal increments of the total strain `e_total` (hypoelastic, no spin: the trial is
/// `s + 2G dev Δε`), returning after each; checks every step's stress against the closed form of
/// [`proportional_plastic_strain`] and the consistency of plastic steps. Returns the largest
/// relative error of `q` and of `ε̄p`.
fn proportional_path<D: Dim>(law: PlasticLaw, e_total: D::Matrix, n: usize) -> (f64, f64) {
    let c = steel();
    let g = c.shear_modulus;
    let p = Plasticity::new(law, &c).unwrap();
    let de = deviator::<D>(e_total) * (1.0 / n as f64);
    let mut s = D::zero_matrix();
    let mut state = PlasticState::default();
    let (mut err_q, mut err_eps) = (0.0f64, 0.0f64);
    for k in 1..=n {
        s += de * (2.0 * g);
        p.return_stress::<D>(&mut s, &mut state, 0.0);
        let e_eq = equivalent_strain::<D>(de) * k as f64;
        let eps = proportional_plastic_strain(&law, g, e_eq);
        let q_exact = 3.0 * g * (e_eq - eps);
        let q = equivalent_stress::<D>(s);
        err_q = err_q.max((q - q_exact).abs() / q_exact);
        if eps > 0.0 {
            err_eps = err_eps.max((state.equivalent_plastic_strain - eps).abs() / eps);
            // On the yield surface.
            let sy = law.flow_stress_after(&state, 0.0, 0.0).0;
            assert!(
                (q - sy).abs() <= 1e-12 * sy,
                "step {k}: q = {q}, σ_y = {sy}"
            );
        } else {
            assert_eq!(state.equivalent_plastic_strain, 0.0);
        }
    }
    (err_q, err_eps)
}

#[test]
fn linear_hardening_uniaxial_strain_matches_the_closed_form_2d_and_3d() {
    // 3D uniaxial strain ε_xx = 1 %: ē = 2ε/3, yield at ε = σ_0/(2G) ≈ 0.16 %; closed form
    // ε̄p = (3Gē − σ_0)/(3G + H). Proportional loading makes the radial return exact for any
    // step, so the tolerance is round-off over 50 steps (1e-12).
    let e = DMat3::from_diagonal(glam::DVec3::new(0.01, 0.0, 0.0));
    let (eq, ee) = proportional_path::<D3>(linear(), e, 50);
    assert!(eq < 1e-12 && ee < 1e-12, "q {eq:e}, ε̄p {ee:e}");
    // The linear closed form by hand at the end.
    let g = steel().shear_modulus;
    let e_eq = 2.0 * 0.01 / 3.0;
    let eps = (3.0 * g * e_eq - SIGMA0) / (3.0 * g + H_LIN);
    let p = Plasticity::new(linear(), &steel()).unwrap();
    let mut s = deviator::<D3>(e) * (2.0 * g);
    let mut st = PlasticState::default();
    let d = p.return_stress::<D3>(&mut s, &mut st, 0.0);
    assert!((d - eps).abs() <= 1e-15 * eps, "{d} vs {eps}");
    // 2D: the in-plane deviator (ē = ε/√3).
    let e2 = DMat2::from_diagonal(glam::DVec2::new(0.01, 0.0));
    let (eq, ee) = proportional_path::<D2>(linear(), e2, 50);
    assert!(eq < 1e-12 && ee < 1e-12, "2D: q {eq:e}, ε̄p {ee:e}");
}

#[test]
fn simple_shear_return_matches_the_closed_form_for_every_law() {
    // Small-strain simple shear γ = 2 % (ε_xy = γ/2): ē = γ/√3. Saturation and rate-independent
    // Johnson–Cook (dt = 0) are solved by Newton; the closed form by bisection.
    let g3 = DMat3::from_cols_array(&[0.0, 0.01, 0.0, 0.01, 0.0, 0.0, 0.0, 0.0, 0.0]);
    let g2 = DMat2::from_cols_array(&[0.0, 0.01, 0.01, 0.0]);
    for law in [linear(), saturation(), johnson_cook(false)] {
        let (eq, ee) = proportional_path::<D3>(law, g3, 40);
        assert!(
            eq < 1e-12 && ee < 1e-11,
            "{}: q {eq:e}, ε̄p {ee:e}",
            law.name()
        );
        let (eq, ee) = proportional_path::<D2>(law, g2, 40);
        assert!(
            eq < 1e-12 && ee < 1e-11,
            "{} 2D: q {eq:e}, ε̄p {ee:e}",
            law.name()
        );
    }
}

#[test]
fn nonlinear_laws_on_uniaxial_strain_match_the_closed_form() {
    let e = DMat3::from_diagonal(glam::DVec3::new(0.05, 0.0, 0.0));
    for law in [saturation(), johnson_cook(false)] {
        let (eq, ee) = proportional_path::<D3>(law, e, 100);
        assert!(
            eq < 1e-12 && ee < 1e-11,
            "{}: q {eq:e}, ε̄p {ee:e}",
            law.name()
        );
    }
}

/// Trial deviators of several directions and magnitudes (up to 6 σ_0: impact-like steps).
fn trials() -> Vec<DMat3> {
    let dirs = [
        DMat3::from_diagonal(glam::DVec3::new(2.0, -1.0, -1.0)),
        DMat3::from_cols_array(&[0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
        DMat3::from_cols_array(&[0.3, 0.7, -0.2, 0.7, -1.1, 0.4, -0.2, 0.4, 0.8]),
    ];
    let mut out = Vec::new();
    for d in dirs {
        let d = deviator::<D3>(d);
        let q = equivalent_stress::<D3>(d);
        for scale in [1.01, 1.5, 3.0, 6.0] {
            out.push(d * (scale * 450e6 / q));
        }
    }
    out
}

#[test]
fn return_lands_on_the_yield_surface_with_round_off_residual() {
    // Consistency: q(s) = σ_y(ε̄p_n + Δε̄p, Δε̄p/dt, T_n) to 1e-12 relative (the Newton stop is
    // 1e-14 of q*; q* ≤ 6 σ_y), for hardened and virgin states and rate-dependent steps.
    let c = steel();
    let g = c.shear_modulus;
    for law in [
        linear(),
        saturation(),
        johnson_cook(false),
        johnson_cook(true),
    ] {
        for eps_n in [0.0, 0.05, 0.4] {
            for dt in [0.0, 1e-7, 1e-3] {
                for t in trials() {
                    let state = PlasticState {
                        equivalent_plastic_strain: eps_n,
                        temperature_rise: 120.0,
                    };
                    let r = radial_return::<D3>(&law, g, t, &state, dt);
                    if r.delta_eps_p == 0.0 {
                        assert!(r.trial_equivalent_stress <= r.flow_stress);
                        continue;
                    }
                    let q = equivalent_stress::<D3>(r.deviator);
                    let (sy, _) = law.flow_stress_after(&state, r.delta_eps_p, dt);
                    let res = (q - sy).abs() / sy;
                    assert!(
                        res < 1e-12,
                        "{} ε̄p_n {eps_n} dt {dt}: residual {res:e} after {} iterations",
                        law.name(),
                        r.iterations
                    );
                    assert!(r.iterations < 60, "{} iterations", r.iterations);
                    assert!(
                        (r.trial_equivalent_stress - 3.0 * g * r.delta_eps_p - sy).abs()
                            <= 10.0 * CONSISTENCY_TOLERANCE * r.trial_equivalent_stress
                    );
                    // Radial: s ∥ s*, same orientation.
                    let k = D3::ddot(r.deviator, t) / D3::ddot(t, t);
                    assert!(k > 0.0 && D3::frobenius(r.deviator - t * k) < 1e-12 * q);
                }
            }
        }
    }
}

#[test]
fn newton_on_a_saturation_law_without_saturation_equals_the_linear_closed_form() {
    // σ_∞ = σ_0 makes the saturation law linear: its Newton path must give the closed form.
    let c = steel();
    let sat = PlasticLaw::J2(IsotropicHardening::Saturation {
        yield_stress: SIGMA0,
        hardening_modulus: H_LIN,
        saturation_stress: SIGMA0,
        saturation_exponent: 10.0,
    });
    for t in trials() {
        let a = radial_return::<D3>(&linear(), c.shear_modulus, t, &PlasticState::default(), 0.0);
        let b = radial_return::<D3>(&sat, c.shear_modulus, t, &PlasticState::default(), 0.0);
        assert!((a.delta_eps_p - b.delta_eps_p).abs() <= 1e-13 * a.delta_eps_p);
        assert!(
            b.iterations <= 3,
            "{} Newton iterations on a linear equation",
            b.iterations
        );
    }
}

#[test]
fn plastic_flow_is_isochoric_and_changes_only_the_deviator() {
    // σ = s − p I: the return scales s only, so tr σ (the pressure) is unchanged; the plastic
    // strain increment is traceless and s* − s = 2G Δεp (the elastic–plastic split).
    let c = steel();
    let g = c.shear_modulus;
    let p = Plasticity::new(saturation(), &c).unwrap();
    for t in trials() {
        let pressure = 1.3e8;
        let sigma_trial = t - DMat3::IDENTITY * pressure;
        let mut s = t;
        let mut state = PlasticState::default();
        let d = p.return_stress::<D3>(&mut s, &mut state, 1e-6);
        assert!(d > 0.0);
        let sigma = s - DMat3::IDENTITY * pressure;
        assert!((D3::trace(sigma) - D3::trace(sigma_trial)).abs() <= 1e-15 * 3.0 * 6.0 * 450e6);
        assert!(D3::trace(s).abs() <= 1e-6, "tr s = {}", D3::trace(s));
        let dep = plastic_strain_increment::<D3>(t, d);
        assert!(D3::trace(dep).abs() <= 1e-15 * D3::frobenius(dep) * 10.0);
        assert!(D3::frobenius(t - s - dep * (2.0 * g)) <= 1e-12 * D3::frobenius(t));
        // Δε̄p = √(2/3 Δεp:Δεp).
        assert!((equivalent_strain::<D3>(dep) - d).abs() <= 1e-13 * d);
    }
}

#[test]
fn an_elastic_trial_is_returned_untouched() {
    let c = steel();
    let p = Plasticity::new(johnson_cook(true), &c).unwrap();
    let t = deviator::<D3>(DMat3::from_diagonal(glam::DVec3::new(1.0, 0.2, -0.5))) * 1e7;
    let mut s = t;
    let mut state = PlasticState::default();
    assert_eq!(p.return_stress::<D3>(&mut s, &mut state, 1e-6), 0.0);
    assert_eq!(s, t);
    assert_eq!(state, PlasticState::default());
}

#[test]
fn johnson_cook_rate_and_temperature_are_clamped() {
    let PlasticLaw::JohnsonCook(jc) = johnson_cook(true) else {
        unreachable!()
    };
    let th = jc.thermal.unwrap();
    // Rates at or below ε̇0 (0 included) give 1, not 1 + C ln(small) → −∞.
    assert_eq!(jc.rate_factor(0.0), (1.0, 0.0));
    assert_eq!(jc.rate_factor(0.5), (1.0, 0.0));
    let (r, dr) = jc.rate_factor(std::f64::consts::E * 1e3);
    assert!((r - (1.0 + 0.025 * (1.0 + 3.0 * 10f64.ln()))).abs() < 1e-14);
    assert!((dr - 0.025 / (std::f64::consts::E * 1e3)).abs() < 1e-18);
    // Below room temperature: T* = 0 (m = 1.09 fractional: T*^m would be NaN); above melting: 1.
    assert_eq!(JohnsonCook::homologous_temperature(&th, 200.0), 0.0);
    assert_eq!(jc.thermal_factor(200.0), 1.0);
    assert_eq!(jc.thermal_factor(2000.0), 0.0);
    let mid = 294.0 + 0.5 * (1356.0 - 294.0);
    assert!((jc.thermal_factor(mid) - (1.0 - 0.5f64.powf(1.09))).abs() < 1e-15);
    // Flow stress: all three factors.
    let sy = jc.flow_stress(0.2, 100.0, mid);
    let expect = (90e6 + 292e6 * 0.2f64.powf(0.31))
        * (1.0 + 0.025 * 100f64.ln())
        * (1.0 - 0.5f64.powf(1.09));
    assert!((sy - expect).abs() <= 1e-14 * expect);
    // A melted particle has no strength: the return takes the whole deviator away.
    let c = steel();
    let melted = PlasticState {
        equivalent_plastic_strain: 0.3,
        temperature_rise: 5000.0,
    };
    let r = radial_return::<D3>(
        &johnson_cook(true),
        c.shear_modulus,
        trials()[0],
        &melted,
        1e-6,
    );
    assert!(equivalent_stress::<D3>(r.deviator) <= 1e-6 * r.trial_equivalent_stress);
}

#[test]
fn adiabatic_heating_is_the_plastic_work_fraction() {
    // ΔT = β σ_y Δε̄p / (ρ c_p), with σ_y the end-of-step flow stress.
    let c = steel();
    let law = johnson_cook(true);
    let p = Plasticity::new(law, &c).unwrap();
    let t = trials()[2];
    let mut s = t;
    let mut state = PlasticState::default();
    let d = p.return_stress::<D3>(&mut s, &mut state, 1e-6);
    let sy = equivalent_stress::<D3>(s);
    let expect = 0.9 * sy * d / (7850.0 * 383.0);
    assert!((state.temperature_rise - expect).abs() <= 1e-12 * expect);
}

#[test]
fn consistent_hardening_derivative_matches_finite_differences() {
    // dσ_y/dΔε̄p of flow_stress_after against a central difference with step h = 1e-5 of the
    // smaller of Δ and ε̄p (relative truncation ~h²/Δ² ≈ 1e-10, round-off ~1e-16 σ/(h σ′) ≤ 3e-7):
    // 1e-6 relative, on both sides of the rate clamp and away from the ε̄p = 0 singularity of
    // ε̄p^n.
    let state = |eps: f64| PlasticState {
        equivalent_plastic_strain: eps,
        temperature_rise: 80.0,
    };
    for law in [saturation(), johnson_cook(false), johnson_cook(true)] {
        for eps_n in [0.0, 0.02, 0.5] {
            for (delta, dt) in [(1e-3, 1e-6), (1e-3, 1e-2), (0.05, 1e-3), (2e-4, 0.0)] {
                if eps_n + delta <= 1e-4 {
                    continue;
                }
                let st = state(eps_n);
                let h = 1e-5 * delta.min(eps_n + delta);
                // Stay on one side of the clamp Δ = ε̇0 dt.
                if dt > 0.0 && ((delta - dt).abs() < 2.0 * h) {
                    continue;
                }
                let (_, slope) = law.flow_stress_after(&st, delta, dt);
                let fd = (law.flow_stress_after(&st, delta + h, dt).0
                    - law.flow_stress_after(&st, delta - h, dt).0)
                    / (2.0 * h);
                let err = (slope - fd).abs() / slope.abs().max(1e3);
                assert!(
                    err < 1e-6,
                    "{} ε̄p {eps_n} Δ {delta} dt {dt}: {slope} vs {fd} ({err:e})",
                    law.name()
                );
            }
        }
    }
}

#[test]
fn invalid_constants_are_refused_naming_the_key() {
    let c = steel();
    let bad = [
        (
            PlasticLaw::J2(IsotropicHardening::Linear {
                yield_stress: -1.0,
                hardening_modulus: 0.0,
            }),
            "yield_stress",
        ),
        (
            PlasticLaw::J2(IsotropicHardening::Linear {
                yield_stress: 1e6,
                hardening_modulus: -5.0,
            }),
            "hardening_modulus",
        ),
        (
            PlasticLaw::J2(IsotropicHardening::Saturation {
                yield_stress: 1e6,
                hardening_modulus: 0.0,
                saturation_stress: 5e5,
                saturation_exponent: 1.0,
            }),
            "saturation_stress",
        ),
    ];
    for (law, key) in bad {
        let e = Plasticity::new(law, &c).unwrap_err().to_string();
        assert!(e.contains(key) && !e.contains('\n'), "{e}");
    }
    let PlasticLaw::JohnsonCook(mut jc) = johnson_cook(true) else {
        unreachable!()
    };
    jc.reference_strain_rate = 0.0;
    let e = PlasticLaw::JohnsonCook(jc)
        .validate()
        .unwrap_err()
        .to_string();
    assert!(e.contains("reference_strain_rate"), "{e}");
    let PlasticLaw::JohnsonCook(mut jc) = johnson_cook(true) else {
        unreachable!()
    };
    jc.thermal.as_mut().unwrap().melting_temperature = 200.0;
    let e = PlasticLaw::JohnsonCook(jc)
        .validate()
        .unwrap_err()
        .to_string();
    assert!(e.contains("melting_temperature"), "{e}");
}
