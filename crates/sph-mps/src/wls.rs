//! The weighted-least-squares kinematics and the Hamiltonian force of the MPS paper, eq 4–7.
//!
//! Notation (docs/methods.md): `X_ij = X_j − X_i` (reference), `x_ij = x_j − x_i` (current),
//! `w_ij = w(|X_ij|)` the weight of eq 6, fixed in the reference configuration (total
//! Lagrangian). Per pair the solver stores `w_ij X_ij` once.
//!
//! Derivation of the force (eq 7). With `F_k = (Σ_j x_kj ⊗ w_kj X_kj) A_k⁻¹` linear in the current
//! positions and `A_k` fixed, a displacement `δx_i` changes
//! - `F_i` by `−Σ_j δx_i ⊗ (A_i⁻ᵀ w_ij X_ij)` (through `x_ij = x_j − x_i`), and
//! - `F_j`, for each neighbour `j` of `i`, by `δx_i ⊗ (A_j⁻ᵀ w_ji X_ji)`.
//!
//! So with `P = ∂ψ/∂F` (eq 2–3), `P : (a ⊗ b) = a · P b`, `w_ji = w_ij` and `X_ji = −X_ij`
//! (the reference neighbour list is symmetric):
//!
//! `−∂U/∂x_i = Σ_j w_ij (V_i P_i A_i⁻ᵀ + V_j P_j A_j⁻ᵀ) X_ij`,
//!
//! which is eq 7 times `ρ_i V_i` (`A` is symmetric, `P = F S`). Each pair term is antisymmetric in
//! `(i, j)`, so linear momentum is conserved to round-off; angular momentum follows from the
//! objectivity of `ψ`. Under tension (`P` positive definite) the force on `i` points toward `j`.
//! The guarded inverse of `A` (see [`moment_inverse`]) is still a fixed symmetric matrix, so the
//! force stays the exact gradient of `U` for every particle, guarded or not.

use rayon::prelude::*;
use sph_core::correction::guarded_inverse;
use sph_core::{Dim, NeighborList};
use sph_materials::Material;

/// Eq 6: `w(r) = 1 − r²/r_e²` for `r < r_e`, else 0.
#[inline(always)]
pub fn weight(r: f64, re: f64) -> f64 {
    if r < re {
        1.0 - (r * r) / (re * re)
    } else {
        0.0
    }
}

/// Eq 5 inverted with a guard: `A_i = Σ_j w_ij X_ij ⊗ X_ij` is scaled by `D / Σ_j w_ij |X_ij|²`
/// (so that it is `≈ I` for an isotropic neighbourhood and the guard threshold is
/// scale-free), inverted with [`sph_core::correction::guarded_inverse`] (blend toward the
/// identity when its smallest eigenvalue is below `min_eigenvalue`), and scaled back. `pairs`
/// yields `(w_ij, X_ij)` of one particle. Returns `A_i⁻¹` (symmetric) and whether the guard
/// acted. A particle without neighbours gets `A⁻¹ = 0` (so `F = 0`); the solver rejects such
/// bodies.
pub fn moment_inverse<D: Dim>(
    pairs: impl Iterator<Item = (f64, D::Vector)>,
    min_eigenvalue: f64,
) -> (D::Matrix, bool) {
    let mut a = D::zero_matrix();
    let mut r2 = 0.0;
    for (w, x) in pairs {
        a += D::outer(x * w, x);
        r2 += w * D::norm_squared(x);
    }
    if r2 <= 0.0 {
        return (D::zero_matrix(), true);
    }
    let scale = D::D as f64 / r2;
    let (inv, guarded) = guarded_inverse::<D>(a * scale, min_eigenvalue);
    (inv * scale, guarded)
}

/// Eq 4 for particle `i`: `F_i = (Σ_j x_ij ⊗ w_ij X_ij) A_i⁻¹` with `x_ij = x_j − x_i`.
#[inline(always)]
pub fn deformation_gradient<D: Dim>(
    xi: D::Vector,
    neighbors: &[u32],
    wx: &[D::Vector],
    x: &[D::Vector],
    a_inv: D::Matrix,
) -> D::Matrix {
    let mut b = D::zero_matrix();
    for (&j, &v) in neighbors.iter().zip(wx) {
        b += D::outer(x[j as usize] - xi, v);
    }
    b * a_inv
}

/// Pass 1 of a force evaluation, parallel over particles: `F_i` (eq 4) and the stress term
/// `G_i = V_i P(F_i) A_i⁻ᵀ` of eq 7 (`P = F S`, eq 2–3).
#[allow(clippy::too_many_arguments)]
pub fn deformation_and_stress<D: Dim, M: Material<D>>(
    material: &M,
    list: &NeighborList,
    wx: &[D::Vector],
    a_inv: &[D::Matrix],
    volumes: &[f64],
    x: &[D::Vector],
    deformation: &mut [D::Matrix],
    stress_term: &mut [D::Matrix],
) {
    let kernel = |(i, (f, g)): (usize, (&mut D::Matrix, &mut D::Matrix))| {
        let r = list.range(i);
        *f = deformation_gradient::<D>(x[i], list.neighbors(i), &wx[r], x, a_inv[i]);
        *g = material.first_piola_kirchhoff(*f) * D::transpose(a_inv[i]) * volumes[i];
    };
    if parallel(x.len()) {
        deformation
            .par_iter_mut()
            .zip(stress_term.par_iter_mut())
            .enumerate()
            .for_each(kernel);
    } else {
        deformation
            .iter_mut()
            .zip(stress_term.iter_mut())
            .enumerate()
            .for_each(kernel);
    }
}

/// Loops over fewer particles than twice this run on the calling thread (one threshold for
/// every method: [`sph_core::parallel`]).
pub const PARALLEL_THRESHOLD: usize = sph_core::parallel::MIN_PARTICLES_PER_TASK;

/// Whether loops over `n` particles go to the rayon pool ([`sph_core::parallel::worth_splitting`]).
#[inline]
pub fn parallel(n: usize) -> bool {
    sph_core::parallel::worth_splitting(n)
}

/// Pass 2, parallel over particles (gather): the internal force of eq 7,
/// `f_i = Σ_j (G_i + G_j) w_ij X_ij = −∂U/∂x_i` (see the module documentation).
pub fn internal_forces<D: Dim>(
    list: &NeighborList,
    wx: &[D::Vector],
    stress_term: &[D::Matrix],
    forces: &mut [D::Vector],
) {
    let kernel = |(i, out): (usize, &mut D::Vector)| {
        let gi = stress_term[i];
        let mut f = D::zero();
        for (&j, &v) in list.neighbors(i).iter().zip(&wx[list.range(i)]) {
            f += (gi + stress_term[j as usize]) * v;
        }
        *out = f;
    };
    if parallel(forces.len()) {
        forces.par_iter_mut().enumerate().for_each(kernel);
    } else {
        forces.iter_mut().enumerate().for_each(kernel);
    }
}

/// The cofactor matrix `cof F = det(F) F⁻ᵀ` (entry `(r, c)` is the signed minor), finite for
/// every `F`. Nanson's formula `n da = cof(F) N dA` maps a reference area vector to the current
/// one; in 2D (plane strain, `F_zz = 1`) it is the in-plane block of the 3×3 cofactor.
#[inline]
pub fn cofactor<D: Dim>(f: D::Matrix) -> D::Matrix {
    let g = |r: usize, c: usize| D::matrix_get(f, r, c);
    match D::D {
        2 => D::matrix_from_fn(|r, c| {
            let v = g(1 - r, 1 - c);
            if r == c {
                v
            } else {
                -v
            }
        }),
        _ => D::matrix_from_fn(|r, c| {
            let (r1, r2, c1, c2) = ((r + 1) % 3, (r + 2) % 3, (c + 1) % 3, (c + 2) % 3);
            g(r1, c1) * g(r2, c2) - g(r1, c2) * g(r2, c1)
        }),
    }
}
