//! The Hamiltonian stabilisation (`MpsParams::stabilisation`, module `sph_mps::stabilisation`):
//!
//! 1. the force is `−∂(U + U_s)/∂x` by central finite differences (2D/3D, SVK and the
//!    Mooney–Rivlin-like law), and the stabilisation's part of it is not negligible there;
//! 2. linear and angular momentum of a free body are conserved to round-off;
//! 3. the energy `Σ ½mv² + U + U_s` stays bounded without drift;
//! 4. an affine deformation costs no stabilisation energy, the alternating-column mode of the
//!    WLS gradient (no strain energy in the bulk) does, with the stiffness the construction
//!    gives it; a body at rest stays at rest;
//! 5. a negative strength is rejected.
//!
//! Measured numbers are printed with `-- --nocapture` and quoted in the comments.

mod common;

use common::*;
use glam::DVec3;
use sph_core::{Dim, Error, Solver, D2, D3};
use sph_materials::Material;
use sph_mps::{MpsParams, MpsSolver};

const ALPHA: f64 = 0.3;

fn stabilised<D: Dim, M: Material<D>>(n: [usize; 3], material: M, alpha: f64) -> MpsSolver<D, M> {
    solver_with::<D, M>(
        n,
        material,
        MpsParams {
            stabilisation: alpha,
            ..MpsParams::default()
        },
    )
}

/// Max over particles and components of `|f_fd − f|` relative to `max |f|`, and the size of the
/// stabilisation's part of the force, `max |f(α) − f(0)| / max |f(α)|`.
///
/// Tolerance 1e-6, as for the strain energy alone (properties.rs): central differences with
/// `h = 1e-6 dp`, truncation ~ (h/ℓ)² and cancellation ~1e-9. A missing `Q` (the `F`-dependence
/// of the residual), a wrong sign or a missing `j`-term gives an error of the size of the
/// stabilisation's part, which must exceed 1e-4 (100× the tolerance) for the test to mean
/// something. Measured: ≤ 3.5e-10; part 7.7e-2 (SVK), 1.1e-3–2.8e-3 (the Mooney–Rivlin-like
/// rubber, whose bulk stiffness dominates its force) (printed).
fn fd_error<D: Dim, M: Material<D> + Clone>(n: [usize; 3], material: M, seed: u64) -> (f64, f64) {
    let mut s = stabilised::<D, M>(n, material.clone(), ALPHA);
    let mut plain = solver::<D, M>(n, material);
    let mut rng = Lcg(seed);
    let x0 = deformed::<D>(s.reference_positions(), &mut rng, 0.1, 0.1);
    let v0 = vec![D::zero(); x0.len()];
    s.set_configuration(x0.clone(), v0.clone()).unwrap();
    plain.set_configuration(x0.clone(), v0.clone()).unwrap();
    let f = s.evaluate_forces().to_vec();
    let f0 = plain.evaluate_forces().to_vec();
    let diff: Vec<D::Vector> = f.iter().zip(&f0).map(|(&a, &b)| a - b).collect();
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
                u[m] = s.energy().potential();
            }
            let fd = -(u[0] - u[1]) / (2.0 * h);
            err = err.max((fd - D::component(f[i], k)).abs());
        }
    }
    let scale = max_norm::<D>(&f);
    (err / scale, max_norm::<D>(&diff) / scale)
}

#[test]
fn stabilised_force_is_minus_energy_gradient_by_finite_differences() {
    let cases = [
        ("2D SVK", fd_error::<D2, _>([6, 5, 1], svk(), 1)),
        (
            "2D Mooney-Rivlin",
            fd_error::<D2, _>([6, 5, 1], mooney(), 2),
        ),
        ("3D SVK", fd_error::<D3, _>([3, 3, 3], svk(), 3)),
        (
            "3D Mooney-Rivlin",
            fd_error::<D3, _>([3, 3, 3], mooney(), 4),
        ),
    ];
    for (name, (e, part)) in cases {
        println!("stabilised force vs -dU/dx, {name}: relative error {e:.2e}, stabilisation's part {part:.2e}");
        assert!(e < 1e-6, "{name}: {e:e}");
        assert!(
            part > 1e-4,
            "{name}: the stabilisation barely acts ({part:e})"
        );
    }
}

/// `|ΔP| / Σ m|v|` and `|ΔL| / |L|` after 2000 steps of a free, deformed body moving and
/// spinning. Same reasoning and bounds as properties.rs: every pair term is antisymmetric
/// (momentum), and `U_s` is invariant under rigid rotation, `r_ij → Q r_ij` (angular momentum);
/// only round-off remains. Bounds 1e-12 and 1e-11. Measured ≤ 1.5e-14 and ≤ 5.6e-14 (printed).
fn momenta_drift<D: Dim, M: Material<D>>(n: [usize; 3], material: M, omega: DVec3) -> (f64, f64) {
    let mut s = stabilised::<D, M>(n, material, ALPHA);
    let mut rng = Lcg(31);
    let x = deformed::<D>(s.reference_positions(), &mut rng, 0.05, 0.05);
    let c = centroid::<D>(&x);
    let u = random_velocities::<D>(
        x.len(),
        &mut rng,
        0.002 * s.material().constants().sound_speed,
    );
    let v: Vec<D::Vector> = x
        .iter()
        .zip(&u)
        .map(|(&p, &u)| u + D::vector(omega.cross(D::to_vec3(p - c)).to_array()))
        .collect();
    s.set_configuration(x, v).unwrap();
    let (p0, l0) = (s.linear_momentum(), s.angular_momentum());
    let scale: f64 = s
        .velocities()
        .iter()
        .zip(s.masses())
        .map(|(&v, &m)| m * D::norm(v))
        .sum();
    for _ in 0..2000 {
        s.step(f64::INFINITY).unwrap();
    }
    (
        D::norm(s.linear_momentum() - p0) / scale,
        (s.angular_momentum() - l0).length() / l0.length(),
    )
}

#[test]
fn stabilised_body_conserves_linear_and_angular_momentum() {
    let c = Material::<D2>::constants(&svk()).sound_speed;
    let w = 0.01 * c / (4.0 * DP);
    let e = [
        momenta_drift::<D2, _>([8, 5, 1], svk(), DVec3::Z * w),
        momenta_drift::<D2, _>([8, 5, 1], mooney(), DVec3::Z * w),
        momenta_drift::<D3, _>([4, 4, 3], svk(), DVec3::new(0.3, -0.5, 0.8) * w),
    ];
    println!("stabilised: (|dP|/sum m|v|, |dL|/|L|) after 2000 steps: {e:?}");
    assert!(e.iter().all(|&(p, l)| p < 1e-12 && l < 1e-11), "{e:?}");
}

/// 2×10⁴ velocity-Verlet steps of a free 2D block from a random 3 % deformation at rest, with
/// and without the stabilisation: `E = Σ ½mv² + U + U_s` oscillates about a constant offset
/// (a shadow Hamiltonian, O(Δt²)), no drift. Bounds as energy.rs: max deviation < 2e-2, |drift|
/// (mean over the last tenth minus the first, relative) < 0.1 × max deviation. Measured (printed):
/// α = 0.3: max deviation 4.1e-3, drift 2.5e-5; α = 0: 4.0e-3, 2.4e-4.
#[test]
fn stabilised_energy_is_bounded_without_drift() {
    for alpha in [0.0, ALPHA] {
        let mut s = stabilised::<D2, _>([5, 5, 1], svk(), alpha);
        let mut rng = Lcg(7);
        let x = deformed::<D2>(s.reference_positions(), &mut rng, 0.03, 0.03);
        let v = vec![D2::zero(); x.len()];
        s.set_configuration(x, v).unwrap();
        let e0 = s.energy().total();
        let steps = 20_000;
        let window = steps / 10;
        let (mut max_dev, mut first, mut last) = (0.0f64, 0.0, 0.0);
        for k in 0..steps {
            s.step(f64::INFINITY).unwrap();
            let e = s.energy().total();
            max_dev = max_dev.max((e - e0).abs() / e0);
            if k < window {
                first += e;
            }
            if k >= steps - window {
                last += e;
            }
        }
        let drift = (last - first) / (window as f64 * e0);
        println!("α = {alpha}: energy max deviation {max_dev:.2e}, drift {drift:.2e}");
        assert!(max_dev < 2e-2, "{max_dev}");
        assert!(drift.abs() < 0.1 * max_dev, "{drift} vs {max_dev}");
    }
}

/// The alternating-column displacement `u_x = δ (−1)^column` has no strain energy in the bulk
/// (`wls_gradient_has_the_alternating_column_zero_energy_mode`); with the stabilisation an
/// interior particle, whose F stays I, has `r_ij = u_j − u_i = ∓2δ x̂` for the neighbours in the
/// odd columns and 0 for the even ones, so its energy is
/// `½ α μ V Σ_{j odd} w_ij (2δ)²/|X_ij|² / Σ_j w_ij` — checked per interior particle to 1e-9
/// relative (round-off of sums over 12 neighbours; a wrong weight, scale or a missing factor is
/// O(1)). An affine deformation of the same size has `r_ij = 0`: its stabilisation energy is
/// ≤ 1e-20 of the zigzag's (round-off of `F X` against `x`). At rest the force is zero (bound
/// 1e-10 of the force of a 1 % strain, as properties.rs). Measured (printed): 1.2e-14, 1.1e-28,
/// 5.8e-14.
#[test]
fn stabilisation_resists_the_zero_energy_mode_and_leaves_affine_motion_alone() {
    let n = [16, 10, 1];
    let mut s = stabilised::<D2, _>(n, svk(), ALPHA);
    let mu = Material::<D2>::constants(&svk()).shear_modulus;
    let x0 = s.reference_positions().to_vec();
    let zero = vec![glam::DVec2::ZERO; x0.len()];
    let scale = 0.01 * Material::<D2>::constants(&svk()).youngs_modulus * DP;
    let rest = max_norm::<D2>(s.evaluate_forces()) / scale;
    let delta = 0.05 * DP;
    let column = |x: &glam::DVec2| (x.x / DP).floor() as i64;
    let row = |x: &glam::DVec2| (x.y / DP).floor() as i64;
    let zig: Vec<glam::DVec2> = x0
        .iter()
        .map(|x| *x + glam::DVec2::X * (delta * if column(x) % 2 == 0 { 1.0 } else { -1.0 }))
        .collect();
    s.set_configuration(zig, zero.clone()).unwrap();
    let e_zig = s.energy().stabilisation;
    let per_particle = s.stabilisation_energies().expect("on");
    let re = s.re();
    let interior = |x: &glam::DVec2| {
        column(x) >= 3 && column(x) < n[0] as i64 - 3 && row(x) >= 3 && row(x) < n[1] as i64 - 3
    };
    let mut worst: f64 = 0.0;
    for (i, x) in x0.iter().enumerate().filter(|(_, x)| interior(x)) {
        let (mut odd, mut all) = (0.0, 0.0);
        for &j in s.neighbors().neighbors(i) {
            let d = x0[j as usize] - *x;
            let w = 1.0 - d.length_squared() / (re * re);
            all += w;
            if (column(&x0[j as usize]) - column(x)) % 2 != 0 {
                odd += w * (2.0 * delta).powi(2) / d.length_squared();
            }
        }
        let expected = 0.5 * ALPHA * mu * s.volumes()[i] * odd / all;
        worst = worst.max((per_particle[i] / expected - 1.0).abs());
    }
    let total: f64 = per_particle.iter().sum();
    let affine: Vec<glam::DVec2> = x0
        .iter()
        .map(|x| glam::DVec2::new(1.05 * x.x + 0.03 * x.y, -0.02 * x.x + 0.97 * x.y))
        .collect();
    s.set_configuration(affine, zero).unwrap();
    let e_affine = s.energy().stabilisation;
    println!(
        "stabilisation: interior zigzag energy vs closed form {worst:.2e}, affine/zigzag {:.2e}, rest force {rest:.2e}",
        e_affine / e_zig
    );
    assert!(worst < 1e-9, "{worst}");
    assert!((total / e_zig - 1.0).abs() < 1e-12, "{total} vs {e_zig}");
    assert!(e_affine <= 1e-20 * e_zig, "{e_affine} vs {e_zig}");
    assert!(rest < 1e-10, "{rest}");
}

#[test]
fn negative_stabilisation_is_rejected() {
    let params = MpsParams {
        stabilisation: -0.1,
        ..MpsParams::default()
    };
    let e = MpsSolver::new(body(&block::<D2>([4, 4, 1])), svk(), params)
        .err()
        .expect("rejected");
    match e {
        Error::InvalidParameter { field, .. } => assert_eq!(field, "stabilisation"),
        other => panic!("{other:?}"),
    }
}
