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
