//! Properties every constitutive law must have (docs/methods.md "Materials"), in 2D (plane strain) and
//! 3D: zero stress at identity, symmetric S, S = 2∂ψ/∂C (as P = ∂ψ/∂F), objectivity, Hooke at
//! small strain; plus parameter validation, name parsing and von Mises.

use glam::{DMat2, DMat3, DVec3};
use proptest::prelude::*;
use sph_core::{Dim, D2, D3};
use sph_materials::{
    von_mises, DeviatorDimension, ElasticConstants, KirchhoffVolDev, Material, MaterialKind,
    MaterialModel, MooneyRivlinLike, NeoHookean, SaintVenantKirchhoff, MATERIAL_NAMES,
};

/// The TL paper's oscillating plate (E = 2 MPa, ν = 0.3975) and its rubber (17 MPa, ν = 0.45).
fn constant_sets() -> [ElasticConstants; 2] {
    [
        ElasticConstants::from_youngs(2.0e6, 0.3975, 1000.0).unwrap(),
        ElasticConstants::from_youngs(1.7e7, 0.45, 1100.0).unwrap(),
    ]
}

/// Every law, built through `MaterialModel` (so the dispatch is tested too), plus both
/// deviator choices of the Kirchhoff law and the MPS paper's Mooney–Rivlin constants.
fn all_laws() -> Vec<(String, MaterialModel)> {
    let mut out = Vec::new();
    for c in constant_sets() {
        for name in MATERIAL_NAMES {
            let kind: MaterialKind = name.parse().unwrap();
            out.push((
                format!("{name} E={}", c.youngs_modulus),
                kind.build(c).unwrap(),
            ));
        }
        out.push((
            format!("kirchhoff-vol-dev embedded-3d E={}", c.youngs_modulus),
            MaterialModel::KirchhoffVolDev(KirchhoffVolDev::with_deviator(
                c,
                DeviatorDimension::Embedded3d,
            )),
        ));
    }
    out.push((
        "mooney-rivlin MPS paper".into(),
        MaterialModel::MooneyRivlin(MooneyRivlinLike::mps_paper()),
    ));
    out
}

/// Deterministic pseudo-random numbers in [−1, 1) (xorshift; no dependency, reproducible).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// `I + amplitude · random`, redrawn until `det F ≥ 0.3` (moderate, invertible deformation).
fn random_f<D: Dim>(rng: &mut Rng, amplitude: f64) -> D::Matrix {
    loop {
        let a: Vec<f64> = (0..9).map(|_| rng.next()).collect();
        let f = D::identity() + D::matrix_from_fn(|r, c| amplitude * a[3 * r + c]);
        if D::det(f) >= 0.3 {
            return f;
        }
    }
}

fn mat_from_array<D: Dim>(a: &[f64; 9]) -> D::Matrix {
    D::matrix_from_fn(|r, c| a[3 * r + c])
}

fn frob3(m: DMat3) -> f64 {
    D3::frobenius(m)
}

// ---------------------------------------------------------------- zero stress at identity

fn check_zero_at_identity<D: Dim>() {
    for (name, law) in all_laws() {
        let e = law_constants::<D>(&law).youngs_modulus;
        let i = D::identity();
        // Tolerance 1e-12·E absolute: at F = I every term is an exact cancellation of O(E)
        // quantities (e.g. μI − μC⁻¹, c₁ − c₁I₃^(1/3)), so only a few ulps of E may remain.
        let tol = 1e-12 * e;
        let s = Material::<D>::second_piola_kirchhoff(&law, i);
        assert!(D::frobenius(s) <= tol, "{name}: S(I) = {s:?}");
        assert!(
            D::frobenius(Material::<D>::first_piola_kirchhoff(&law, i)) <= tol,
            "{name}: P(I)"
        );
        assert!(
            D::frobenius(Material::<D>::kirchhoff_stress(&law, i)) <= tol,
            "{name}: τ(I)"
        );
        let sigma = Material::<D>::cauchy_stress_3d(&law, i);
        assert!(frob3(sigma) <= tol, "{name}: σ(I) = {sigma:?}");
        let psi = Material::<D>::strain_energy_density(&law, i).unwrap();
        assert!(psi.abs() <= tol, "{name}: ψ(I) = {psi}");
        // TL-HF split at rest: τ_r = −ζ G I (eq. 28 at F = I), g = 1.
        let (tau_r, g) = Material::<D>::hf_split(&law, i, 1.07);
        let c = law_constants::<D>(&law);
        let want = D::identity() * (-1.07 * c.shear_modulus);
        assert!(
            D::frobenius(tau_r - want) <= tol * c.shear_modulus,
            "{name}: τ_r(I)"
        );
        assert!((g - 1.0).abs() <= 1e-15, "{name}: g(I)");
    }
}

// ---------------------------------------------------------------- the TL-HF split

/// The split represents the law: `τ_r + G g b − (1 − ζ)(G g tr b/d) I = τ(F)` for any F
/// (tolerance: round-off relative to the largest term).
fn check_hf_split_represents_the_law<D: Dim>() {
    let mut rng = Rng(0x1234_5678);
    let zeta = 1.07;
    for (name, law) in all_laws() {
        let gmod = law_constants::<D>(&law).shear_modulus;
        for _ in 0..20 {
            let f = random_f::<D>(&mut rng, 0.4);
            let (tau_r, g) = Material::<D>::hf_split(&law, f, zeta);
            let b = f * D::transpose(f);
            let back = tau_r + b * (gmod * g)
                - D::identity() * ((1.0 - zeta) * gmod * g * D::trace(b) / D::D as f64);
            let tau = Material::<D>::kirchhoff_stress(&law, f);
            let scale = D::frobenius(tau) + gmod * D::frobenius(b);
            assert!(
                D::frobenius(back - tau) <= 1e-13 * scale,
                "{name}: {:e}",
                D::frobenius(back - tau) / scale
            );
        }
    }
}

#[test]
fn hf_split_represents_every_law_2d() {
    check_hf_split_represents_the_law::<D2>();
}

#[test]
fn hf_split_represents_every_law_3d() {
    check_hf_split_represents_the_law::<D3>();
}

fn law_constants<D: Dim>(law: &MaterialModel) -> ElasticConstants {
    *Material::<D>::constants(law)
}

#[test]
fn stress_and_energy_vanish_at_identity_2d() {
    check_zero_at_identity::<D2>();
}

#[test]
fn stress_and_energy_vanish_at_identity_3d() {
    check_zero_at_identity::<D3>();
}

// ---------------------------------------------------------------- symmetry and consistency

fn check_symmetric_and_consistent<D: Dim>() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    for (name, law) in all_laws() {
        for _ in 0..50 {
            let f = random_f::<D>(&mut rng, 0.3);
            let s = Material::<D>::second_piola_kirchhoff(&law, f);
            let scale = D::frobenius(s).max(1e-3 * law_constants::<D>(&law).youngs_modulus);
            // Tolerance 1e-12 relative: S is built symmetric (C, C⁻¹, I) or as F⁻¹τF⁻ᵀ whose
            // asymmetry is round-off amplified by cond(F)² ≲ 50 for these F.
            let asym = D::frobenius(s - D::transpose(s));
            assert!(
                asym <= 1e-12 * scale,
                "{name}: |S − Sᵀ| = {asym:e}, F = {f:?}"
            );
            // P = F S and τ = F S Fᵀ = P Fᵀ, also for laws that override them (same bound).
            let p = Material::<D>::first_piola_kirchhoff(&law, f);
            let tau = Material::<D>::kirchhoff_stress(&law, f);
            let fs = D::frobenius(f);
            assert!(
                D::frobenius(p - f * s) <= 1e-12 * scale * fs * fs,
                "{name}: P ≠ FS"
            );
            assert!(
                D::frobenius(tau - p * D::transpose(f)) <= 1e-12 * scale * fs * fs * fs,
                "{name}: τ ≠ PFᵀ"
            );
            // The in-plane block of the 3×3 Cauchy stress is τ/J, and it is symmetric.
            let sigma = Material::<D>::cauchy_stress_3d(&law, f);
            let j = D::det(f);
            for r in 0..D::D {
                for c in 0..D::D {
                    let expect = D::matrix_get(tau, r, c) / j;
                    assert!(
                        (sigma.col(c)[r] - expect).abs() <= 1e-12 * scale * fs * fs / j,
                        "{name}: σ block ({r},{c}) {} vs τ/J {expect}",
                        sigma.col(c)[r]
                    );
                }
            }
            assert!(frob3(sigma - sigma.transpose()) <= 1e-11 * scale * fs * fs / j);
        }
    }
}

#[test]
fn second_piola_kirchhoff_is_symmetric_and_stress_measures_agree_2d() {
    check_symmetric_and_consistent::<D2>();
}

#[test]
fn second_piola_kirchhoff_is_symmetric_and_stress_measures_agree_3d() {
    check_symmetric_and_consistent::<D3>();
}

// ---------------------------------------------------------------- P = ∂ψ/∂F

fn check_energy_derivative<D: Dim>() {
    let mut rng = Rng(0xD1B5_4A32_D192_ED03);
    for (name, law) in all_laws() {
        for _ in 0..20 {
            let f = random_f::<D>(&mut rng, 0.3);
            let p = Material::<D>::first_piola_kirchhoff(&law, f);
            let h = 1e-6 * D::frobenius(f);
            let psi = |m: D::Matrix| Material::<D>::strain_energy_density(&law, m).unwrap();
            let fd = D::matrix_from_fn(|r, c| {
                let e = D::matrix_from_fn(|i, k| if (i, k) == (r, c) { h } else { 0.0 });
                (psi(f + e) - psi(f - e)) / (2.0 * h)
            });
            // Central differences: truncation ~h²ψ‴ ≈ 1e-12·E and round-off ~ε_mach·ψ/h
            // ≈ 1e-16·0.1E/1e-6 = 1e-11·E, both ≤ 1e-8 of |P| ~ 0.1E, so 1e-6 relative is a
            // safe bound that still catches any wrong term (those are O(1) relative).
            let err = D::frobenius(fd - p);
            assert!(
                err <= 1e-6 * D::frobenius(p),
                "{name}: |∂ψ/∂F − P| = {err:e}, |P| = {:e}, F = {f:?}",
                D::frobenius(p)
            );
        }
    }
}

#[test]
fn first_piola_kirchhoff_is_the_energy_derivative_2d() {
    check_energy_derivative::<D2>();
}

#[test]
fn first_piola_kirchhoff_is_the_energy_derivative_3d() {
    check_energy_derivative::<D3>();
}

// ---------------------------------------------------------------- objectivity (proptest)

fn check_objectivity<D: Dim>(q: D::Matrix, f: D::Matrix) -> Result<(), TestCaseError> {
    let q3 = D::to_mat3(q, 1.0);
    for (name, law) in all_laws() {
        let s = Material::<D>::second_piola_kirchhoff(&law, f);
        let s_rot = Material::<D>::second_piola_kirchhoff(&law, q * f);
        let scale = D::frobenius(s).max(law_constants::<D>(&law).youngs_modulus);
        // Tolerance 1e-10 relative to max(|S|, E): QᵀQ = I only to round-off, and C⁻¹ amplifies
        // it by cond(C) ≲ 1e2 for det F ≥ 0.3 and 40 % stretch; 1e-10 leaves a wide margin.
        let err = D::frobenius(s_rot - s);
        prop_assert!(err <= 1e-10 * scale, "{}: |S(QF) − S(F)| = {:e}", name, err);
        let sigma = Material::<D>::cauchy_stress_3d(&law, f);
        let sigma_rot = Material::<D>::cauchy_stress_3d(&law, q * f);
        let err = frob3(sigma_rot - q3 * sigma * q3.transpose());
        prop_assert!(
            err <= 1e-10 * frob3(sigma).max(law_constants::<D>(&law).youngs_modulus),
            "{}: |σ(QF) − QσQᵀ| = {:e}",
            name,
            err
        );
        let psi = Material::<D>::strain_energy_density(&law, f).unwrap();
        let psi_rot = Material::<D>::strain_energy_density(&law, q * f).unwrap();
        prop_assert!((psi_rot - psi).abs() <= 1e-10 * psi.abs().max(scale * 1e-3));
    }
    Ok(())
}

fn moderate_f() -> impl Strategy<Value = [f64; 9]> {
    prop::array::uniform9(-0.4f64..0.4).prop_map(|a| {
        let mut m = a;
        m[0] += 1.0;
        m[4] += 1.0;
        m[8] += 1.0;
        m
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn laws_are_objective_2d(angle in -std::f64::consts::PI..std::f64::consts::PI, a in moderate_f()) {
        let f = mat_from_array::<D2>(&a);
        prop_assume!(D2::det(f) > 0.3);
        check_objectivity::<D2>(DMat2::from_angle(angle), f)?;
    }

    #[test]
    fn laws_are_objective_3d(
        axis in prop::array::uniform3(-1.0f64..1.0),
        angle in -std::f64::consts::PI..std::f64::consts::PI,
        a in moderate_f(),
    ) {
        let axis = DVec3::from_array(axis);
        prop_assume!(axis.length() > 0.1);
        let f = mat_from_array::<D3>(&a);
        prop_assume!(D3::det(f) > 0.3);
        check_objectivity::<D3>(DMat3::from_axis_angle(axis.normalize(), angle), f)?;
    }
}

// ---------------------------------------------------------------- small-strain limit

/// The law's small-strain Lamé pair `(λ, μ)` as it acts in the plane of `D`, and the `σzz`
/// coefficient of `tr ε` (plane strain): Hooke with the given constants for every law except
/// the 2D Kirchhoff law with `d = 2` (see `DeviatorDimension::Spatial`).
fn small_strain_moduli<D: Dim>(law: &MaterialModel) -> (f64, f64, f64) {
    let c = law_constants::<D>(law);
    match law {
        MaterialModel::KirchhoffVolDev(k)
            if D::D == 2 && k.deviator == DeviatorDimension::Spatial =>
        {
            // τ ≈ K tr ε I + 2G(ε − ½ tr ε I); τ_zz = K tr ε.
            (
                c.bulk_modulus - c.shear_modulus,
                c.shear_modulus,
                c.bulk_modulus,
            )
        }
        _ => (c.lame_lambda, c.shear_modulus, c.lame_lambda),
    }
}

fn check_small_strain<D: Dim>() {
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    let eps = 1e-7;
    for (name, law) in all_laws() {
        let (lambda, mu, lambda_zz) = small_strain_moduli::<D>(&law);
        for _ in 0..20 {
            let a: Vec<f64> = (0..9).map(|_| rng.next()).collect();
            let grad_u = mat_from_array::<D>(&a.try_into().unwrap());
            let f = D::identity() + grad_u * eps;
            let strain = (grad_u + D::transpose(grad_u)) * (0.5 * eps);
            let tr = D::trace(strain);
            let hooke = D::to_mat3(
                D::identity() * (lambda * tr) + strain * (2.0 * mu),
                lambda_zz * tr,
            );
            let sigma = Material::<D>::cauchy_stress_3d(&law, f);
            // Tolerance 1e-5 relative: the neglected terms are O(ε) = 1e-7 relative (geometric
            // and material nonlinearity), and cancellation of O(E) terms leaves round-off
            // ~1e-16·E/(1e-7·E) = 1e-9 relative; the MPS constants (λ/c₁ ≈ 80) cost 2 digits more.
            let err = frob3(sigma - hooke);
            assert!(
                err <= 1e-5 * frob3(hooke),
                "{name}: |σ − Hooke| / |Hooke| = {:e}",
                err / frob3(hooke)
            );
        }
    }
}

#[test]
fn small_strain_limit_is_hooke_plane_strain_2d() {
    check_small_strain::<D2>();
}

#[test]
fn small_strain_limit_is_hooke_3d() {
    check_small_strain::<D3>();
}

#[test]
fn kirchhoff_deviator_choices_coincide_in_3d_and_differ_in_2d() {
    let c = constant_sets()[0];
    let spatial = KirchhoffVolDev::new(c);
    let embedded = KirchhoffVolDev::with_deviator(c, DeviatorDimension::Embedded3d);
    let mut rng = Rng(7);
    let f3 = random_f::<D3>(&mut rng, 0.3);
    // Same formula in 3D: bitwise equal.
    assert_eq!(
        Material::<D3>::kirchhoff_stress(&spatial, f3),
        Material::<D3>::kirchhoff_stress(&embedded, f3)
    );
    // In 2D, simple shear F = [[1, γ], [0, 1]] gives τ_xx − τ_yy = Gγ² with either d (J = 1),
    // but the in-plane trace differs: 0 with d = 2 (deviator in the plane), Gγ²/3 with d = 3
    // (the out-of-plane deviator entry takes −Gγ²/3).
    let gamma = 0.2;
    let f = DMat2::from_cols_array(&[1.0, 0.0, gamma, 1.0]);
    let t2 = Material::<D2>::kirchhoff_stress(&spatial, f);
    let t3 = Material::<D2>::kirchhoff_stress(&embedded, f);
    let g = c.shear_modulus;
    // Closed forms; 1e-12 relative for round-off.
    assert!((D2::trace(t2)).abs() <= 1e-12 * g);
    assert!((D2::trace(t3) - g * gamma * gamma / 3.0).abs() <= 1e-12 * g);
    assert!((t2.col(1)[0] - g * gamma).abs() <= 1e-12 * g);
    assert!((t3.col(1)[0] - g * gamma).abs() <= 1e-12 * g);
}

#[test]
fn mooney_rivlin_small_strain_moduli_are_c1_plus_c2_and_two_lambda() {
    let m = MooneyRivlinLike::mps_paper();
    let c = Material::<D3>::constants(&m);
    // Exact arithmetic on the paper's numbers (1e-12 relative for the E, ν round trip).
    let g = MooneyRivlinLike::MPS_PAPER_C1 + MooneyRivlinLike::MPS_PAPER_C2;
    assert!((c.shear_modulus - g).abs() <= 1e-12 * g);
    assert!(
        (c.bulk_modulus - 2.0 * MooneyRivlinLike::MPS_PAPER_LAMBDA).abs() <= 1e-12 * c.bulk_modulus
    );
    // Built from constants, the split honours c2_fraction and the moduli.
    let k = MooneyRivlinLike::from_constants(constant_sets()[0], 0.25).unwrap();
    assert!((k.c2() - 0.25 * constant_sets()[0].shear_modulus).abs() <= 1e-9);
    assert!((2.0 * k.lambda() - constant_sets()[0].bulk_modulus).abs() <= 1e-6);
}

#[test]
fn neo_hookean_uniaxial_stretch_matches_closed_form() {
    // F = diag(s, 1, 1): S11 = μ + (λ ln s − μ)/s², S22 = S33 = λ ln s (TL eq. 8).
    let c = constant_sets()[1];
    let law = NeoHookean::new(c);
    let s = 1.3;
    let f = DMat3::from_diagonal(DVec3::new(s, 1.0, 1.0));
    let st = Material::<D3>::second_piola_kirchhoff(&law, f);
    let (lam, mu) = (c.lame_lambda, c.shear_modulus);
    // 1e-12 relative: a handful of flops.
    assert!((st.x_axis.x - (mu + (lam * s.ln() - mu) / (s * s))).abs() <= 1e-12 * c.youngs_modulus);
    assert!((st.y_axis.y - lam * s.ln()).abs() <= 1e-12 * c.youngs_modulus);
    // The same stretch in 2D plane strain gives the same in-plane S and σzz.
    let f2 = DMat2::from_diagonal(glam::DVec2::new(s, 1.0));
    let s2 = Material::<D2>::second_piola_kirchhoff(&law, f2);
    assert!((s2.x_axis.x - st.x_axis.x).abs() <= 1e-12 * c.youngs_modulus);
    let sig2 = Material::<D2>::cauchy_stress_3d(&law, f2);
    let sig3 = Material::<D3>::cauchy_stress_3d(&law, f);
    assert!(frob3(sig2 - sig3) <= 1e-12 * c.youngs_modulus);
}

#[test]
fn saint_venant_kirchhoff_energy_matches_mps_eq_11() {
    let c = constant_sets()[0];
    let law = SaintVenantKirchhoff::new(c);
    // Uniaxial Green strain e: ψ = λ/2 e² + μ e². F = diag(√(1+2e), 1, 1).
    let e: f64 = 0.05;
    let f = DMat3::from_diagonal(DVec3::new((1.0 + 2.0 * e).sqrt(), 1.0, 1.0));
    let psi = Material::<D3>::strain_energy_density(&law, f).unwrap();
    let expect = 0.5 * c.lame_lambda * e * e + c.shear_modulus * e * e;
    // 1e-12 relative: √ and squaring round-off only.
    assert!((psi - expect).abs() <= 1e-12 * expect, "{psi} vs {expect}");
}

// ---------------------------------------------------------------- validation

fn err_text<T: std::fmt::Debug>(r: Result<T, sph_core::Error>) -> String {
    r.expect_err("expected an invalid-parameter error")
        .to_string()
}

#[test]
fn youngs_modulus_must_be_positive_and_finite() {
    for e in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let msg = err_text(ElasticConstants::from_youngs(e, 0.3, 1000.0));
        assert!(msg.contains("youngs_modulus"), "{msg}");
    }
}

#[test]
fn poisson_ratio_must_lie_in_open_interval_minus_one_to_half() {
    for nu in [-1.0, -1.5, 0.5, 0.6, f64::NAN] {
        let msg = err_text(ElasticConstants::from_youngs(1e6, nu, 1000.0));
        assert!(
            msg.contains("poisson_ratio") && msg.contains("-1 < poisson_ratio < 0.5"),
            "{msg}"
        );
    }
    // Exactly 0.5 (incompressible) is rejected: K and λ would be infinite.
    let msg = err_text(ElasticConstants::from_youngs(1e6, 0.5, 1000.0));
    assert!(msg.contains("poisson_ratio"), "{msg}");
    // The edges just inside are accepted.
    assert!(ElasticConstants::from_youngs(1e6, 0.499, 1000.0).is_ok());
    assert!(ElasticConstants::from_youngs(1e6, -0.999, 1000.0).is_ok());
}

#[test]
fn density_must_be_positive_and_finite() {
    for rho in [0.0, -1000.0, f64::NAN] {
        let msg = err_text(ElasticConstants::from_youngs(1e6, 0.3, rho));
        assert!(msg.contains("density"), "{msg}");
        let msg = err_text(ElasticConstants::from_bulk_shear(1e6, 1e5, rho));
        assert!(msg.contains("density"), "{msg}");
    }
}

#[test]
fn bulk_and_shear_moduli_must_be_positive() {
    for bad in [0.0, -1.0, f64::NAN] {
        let msg = err_text(ElasticConstants::from_bulk_shear(bad, 1e5, 1000.0));
        assert!(msg.contains("bulk_modulus"), "{msg}");
        let msg = err_text(ElasticConstants::from_bulk_shear(1e6, bad, 1000.0));
        assert!(msg.contains("shear_modulus"), "{msg}");
    }
}

#[test]
fn mooney_rivlin_parameters_are_validated() {
    let ok = |c1, c2, l| MooneyRivlinLike::new(c1, c2, l, 1000.0);
    assert!(err_text(ok(0.0, 1.0, 1.0)).contains("c1"));
    assert!(err_text(ok(f64::NAN, 1.0, 1.0)).contains("c1"));
    assert!(err_text(ok(1.0, -1.0, 1.0)).contains("c2"));
    assert!(err_text(ok(1.0, 0.0, 0.0)).contains("lambda"));
    assert!(err_text(ok(1.0, 0.0, -2.0)).contains("lambda"));
    assert!(err_text(MooneyRivlinLike::new(1.0, 1.0, 1.0, 0.0)).contains("density"));
    assert!(
        ok(1.0, 0.0, 1.0).is_ok(),
        "c2 = 0 (neo-Hookean-like) is allowed"
    );
    let c = constant_sets()[0];
    for f in [-0.1, 1.0, f64::NAN] {
        let msg = err_text(MooneyRivlinLike::from_constants(c, f));
        assert!(msg.contains("c2_fraction"), "{msg}");
        let msg = err_text(MaterialKind::MooneyRivlin { c2_fraction: f }.build(c));
        assert!(msg.contains("c2_fraction"), "{msg}");
    }
}

#[test]
fn material_names_parse_and_unknown_names_list_the_allowed_ones() {
    let c = constant_sets()[0];
    for name in MATERIAL_NAMES {
        let kind: MaterialKind = name.parse().unwrap();
        assert_eq!(kind.to_string(), name);
        let model = kind.build(c).unwrap();
        let law_name = Material::<D2>::name(&model);
        // linear-elastic is Saint Venant–Kirchhoff (TL eq. 5).
        let expect = if name == "linear-elastic" {
            "saint-venant-kirchhoff"
        } else {
            name
        };
        assert_eq!(law_name, expect);
        assert_eq!(Material::<D3>::name(&model), expect);
    }
    let msg = err_text("hookean".parse::<MaterialKind>());
    assert!(msg.contains("material"), "{msg}");
    for name in MATERIAL_NAMES {
        assert!(msg.contains(name), "{msg} lacks {name}");
    }
}

#[test]
fn laws_are_usable_as_trait_objects() {
    let c = constant_sets()[0];
    let laws: Vec<Box<dyn Material<D3>>> = vec![
        Box::new(SaintVenantKirchhoff::new(c)),
        Box::new(NeoHookean::new(c)),
        Box::new(KirchhoffVolDev::new(c)),
        Box::new(MooneyRivlinLike::from_constants(c, 0.1).unwrap()),
    ];
    for law in &laws {
        // Zero at identity to well within 1e-6 Pa (E = 2 MPa; see the identity tests).
        assert!(law
            .second_piola_kirchhoff(DMat3::IDENTITY)
            .abs_diff_eq(DMat3::ZERO, 1e-6));
        assert!(law.strain_energy_density(DMat3::IDENTITY).is_some());
    }
}

#[test]
fn singular_deformation_gives_non_finite_stress_not_a_panic() {
    let f = DMat2::from_cols_array(&[1.0, 2.0, 2.0, 4.0]); // det = 0
    for (name, law) in all_laws() {
        let s = Material::<D2>::second_piola_kirchhoff(&law, f);
        if matches!(law, MaterialModel::SaintVenantKirchhoff(_)) {
            // SVK is a polynomial in F: defined (and finite) for any F.
            assert!(s.is_finite(), "{name}: {s:?}");
        } else {
            // The others need C⁻¹, F⁻¹ or ln J: the solver's non-finite check must see it.
            assert!(
                !s.is_finite(),
                "{name}: S of a singular F should be non-finite, got {s:?}"
            );
        }
    }
}

// ---------------------------------------------------------------- von Mises

#[test]
fn von_mises_of_uniaxial_shear_and_hydrostatic_stress() {
    // Closed forms; 1e-14 relative for a dozen flops on O(1) values.
    let s = -3.5;
    let uni = DMat3::from_diagonal(DVec3::new(0.0, s, 0.0));
    assert!((von_mises(uni) - s.abs()).abs() <= 1e-14 * s.abs());
    let tau = 2.0;
    let shear = DMat3::from_cols_array(&[0.0, tau, 0.0, tau, 0.0, 0.0, 0.0, 0.0, 0.0]);
    assert!((von_mises(shear) - 3f64.sqrt() * tau).abs() <= 1e-14 * tau);
    let shear_yz = DMat3::from_cols_array(&[0.0, 0.0, 0.0, 0.0, 0.0, tau, 0.0, tau, 0.0]);
    assert!((von_mises(shear_yz) - 3f64.sqrt() * tau).abs() <= 1e-14 * tau);
    let hydro = DMat3::IDENTITY * 7.0e6;
    assert!(von_mises(hydro) <= 1e-14 * 7.0e6);
    // Adding a hydrostatic part changes nothing.
    assert!((von_mises(shear + hydro) - 3f64.sqrt() * tau).abs() <= 1e-8);
}

#[test]
fn von_mises_matches_the_component_formula_of_methods_md() {
    let m = DMat3::from_cols_array(&[1.0, 0.4, -0.2, 0.4, -2.0, 0.7, -0.2, 0.7, 0.5]);
    let (xx, yy, zz) = (m.x_axis.x, m.y_axis.y, m.z_axis.z);
    let (xy, yz, zx) = (m.y_axis.x, m.z_axis.y, m.x_axis.z);
    let expect = (xx * xx + yy * yy + zz * zz - xx * yy - yy * zz - zz * xx
        + 3.0 * (xy * xy + yz * yz + zx * zx))
        .sqrt();
    // 1e-14 relative: two algebraically equal forms, O(1) entries.
    assert!((von_mises(m) - expect).abs() <= 1e-14 * expect);
}

#[test]
fn plane_strain_von_mises_includes_sigma_zz() {
    // Uniaxial plane-strain compression at small strain: σzz = λ ε ≠ 0 changes σ̄.
    let c = constant_sets()[0];
    let law = SaintVenantKirchhoff::new(c);
    let eps = -1e-6;
    let f = DMat2::from_diagonal(glam::DVec2::new(1.0 + eps, 1.0));
    let sigma = Material::<D2>::cauchy_stress_3d(&law, f);
    let (sxx, syy, szz) = (sigma.x_axis.x, sigma.y_axis.y, sigma.z_axis.z);
    // 1e-5 relative: small-strain (O(ε) = 1e-6) geometric terms.
    assert!((szz - c.lame_lambda * eps).abs() <= 1e-5 * (c.lame_lambda * eps).abs());
    assert!((syy - szz).abs() <= 1e-5 * szz.abs());
    let vm = von_mises(sigma);
    assert!((vm - (sxx - syy).abs()).abs() <= 1e-5 * vm);
    assert!((vm - 2.0 * c.shear_modulus * eps.abs()).abs() <= 1e-5 * vm);
}

// ---------------------------------------------------------------- serde (no format crate:
// serde's own value deserializers)

/// A number as serde sees it in JSON/TOML: also accepted where an `Option` is expected (serde's
/// own `F64Deserializer` refuses that).
struct Num(f64);

impl<'de> serde::de::IntoDeserializer<'de, serde::de::value::Error> for Num {
    type Deserializer = Self;
    fn into_deserializer(self) -> Self {
        self
    }
}

impl<'de> serde::Deserializer<'de> for Num {
    type Error = serde::de::value::Error;
    fn deserialize_any<V: serde::de::Visitor<'de>>(self, v: V) -> Result<V::Value, Self::Error> {
        v.visit_f64(self.0)
    }
    fn deserialize_option<V: serde::de::Visitor<'de>>(self, v: V) -> Result<V::Value, Self::Error> {
        v.visit_some(self)
    }
    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf unit
        unit_struct newtype_struct seq tuple tuple_struct map struct enum identifier ignored_any
    }
}

#[test]
fn elastic_constants_deserialize_from_either_pair_and_reject_inconsistent_fields() {
    use serde::de::value::{Error as DeError, MapDeserializer};
    use serde::Deserialize;
    let de = |pairs: Vec<(&'static str, f64)>| {
        ElasticConstants::deserialize(MapDeserializer::<_, DeError>::new(
            pairs.into_iter().map(|(k, v)| (k, Num(v))),
        ))
    };
    let c = de(vec![
        ("youngs_modulus", 2e6),
        ("poisson_ratio", 0.3975),
        ("density", 1000.0),
    ])
    .unwrap();
    assert_eq!(c, constant_sets()[0]);
    let kg = de(vec![
        ("bulk_modulus", c.bulk_modulus),
        ("shear_modulus", c.shear_modulus),
        ("density", 1000.0),
    ])
    .unwrap();
    // Round trip through K, G: 1e-12 relative.
    assert!((kg.youngs_modulus - 2e6).abs() <= 1e-12 * 2e6);
    let msg = de(vec![
        ("youngs_modulus", 2e6),
        ("poisson_ratio", 0.5),
        ("density", 1000.0),
    ])
    .unwrap_err()
    .to_string();
    assert!(msg.contains("poisson_ratio"), "{msg}");
    let msg = de(vec![
        ("youngs_modulus", 2e6),
        ("poisson_ratio", 0.3),
        ("density", 1000.0),
        ("sound_speed", 1.0),
    ])
    .unwrap_err()
    .to_string();
    assert!(msg.contains("sound_speed"), "{msg}");
    assert!(de(vec![("youngs_modulus", 2e6), ("density", 1000.0)]).is_err());
}

#[test]
fn material_kind_deserializes_from_its_kind_tag() {
    use serde::de::value::{Error as DeError, MapDeserializer};
    use serde::Deserialize;
    for name in MATERIAL_NAMES {
        let kind = MaterialKind::deserialize(MapDeserializer::<_, DeError>::new(
            vec![("kind", name)].into_iter(),
        ))
        .unwrap();
        // Options take the same defaults as the name parser.
        assert_eq!(kind, name.parse::<MaterialKind>().unwrap());
    }
    assert!(
        MaterialKind::deserialize(MapDeserializer::<_, DeError>::new(
            vec![("kind", "rubber")].into_iter()
        ))
        .is_err()
    );
}
