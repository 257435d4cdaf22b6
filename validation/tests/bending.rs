//! The MPS bending-stiffness diagnostic (validation::mps::bending_stiffness_ratio): the WLS
//! deformation gradient of surface particles sees a one-sided neighbourhood, which lowers the
//! bending stiffness of a beam a few particles thick; the deficit must vanish under refinement.

use sph_validation::mps::bending_stiffness_ratio;

#[test]
fn bending_stiffness_deficit_shrinks_under_refinement() {
    let r: Vec<f64> = [5, 10, 20]
        .iter()
        .map(|&res| bending_stiffness_ratio(res, 2.1).unwrap())
        .collect();
    eprintln!("E_h/E (H/dp 5, 10, 20): {r:?}");
    // Soft at every resolution, monotonically stiffer, and the deficit at least halves per
    // doubling (first order in dp/H or better).
    for w in r.windows(2) {
        assert!(w[0] < w[1] && w[1] < 1.0, "{r:?}");
    }
    assert!((1.0 - r[2]) < 0.5 * (1.0 - r[1]) + 1e-3, "{r:?}");
    assert!((1.0 - r[1]) < 0.5 * (1.0 - r[0]) + 1e-3, "{r:?}");
}

#[test]
fn larger_support_radius_is_softer_in_bending() {
    let a = bending_stiffness_ratio(10, 2.1).unwrap();
    let b = bending_stiffness_ratio(10, 3.0).unwrap();
    assert!(b < a, "r_e 2.1: {a}, r_e 3.0: {b}");
}

/// With the quadratic fit the surface rows see the exact fibre strain, so the only deficit left
/// is the midpoint rule for `∫ y² dy` over the rows: `Σ_k y_k² dp = H³/12 − H dp²/12`, i.e.
/// `E_h/E = 1 − (dp/H)²` whatever `r_e` (a closed form). Tolerance 1e-4: the imposed field is
/// the small-strain pure-bending field while the energy is SVK's, whose geometric terms (the
/// section rotates by up to κ x = 6e-4) add the same +4.1e-5 at every resolution; a surface
/// deficit like the linear fit's is 1e-2 or more. Measured: 0.96004 / 0.99004 / 0.99754 at
/// H/dp 5 / 10 / 20 (and 0.99004 with r_e = 3 l0).
#[test]
fn quadratic_fit_leaves_only_the_quadrature_deficit() {
    use sph_mps::Fit;
    use sph_validation::mps::bending_stiffness_ratio_with;
    for (res, re) in [(5u32, 2.1), (10, 2.1), (20, 2.1), (10, 3.0)] {
        let r = bending_stiffness_ratio_with(res, re, Fit::Quadratic).unwrap();
        let expected = 1.0 - (1.0 / res as f64).powi(2);
        eprintln!("quadratic fit, H/dp {res}, r_e {re}: E_h/E = {r:.7} (1 − (dp/H)² = {expected})");
        assert!((r - expected).abs() < 1e-4, "{res} {re}: {r} vs {expected}");
    }
}
