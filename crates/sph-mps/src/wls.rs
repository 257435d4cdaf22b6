//! The weighted-least-squares kinematics and the Hamiltonian force of the MPS paper, eq 4–7.
//!
//! Notation (docs/methods.md): `X_ij = X_j − X_i` (reference), `x_ij = x_j − x_i` (current),
//! `w_ij = w(|X_ij|)` the weight of eq 6, fixed in the reference configuration (total
//! Lagrangian).
//!
//! Every fit here is linear in the current positions with coefficients fixed in the reference
//! configuration: `F_i = Σ_j x_ij ⊗ g_ij`, one *gradient vector* `g_ij` per pair. The paper's
//! linear fit (eq 4–5) has `g_ij = A_i⁻¹ w_ij X_ij` ([`linear_gradient_vectors`]); the quadratic
//! fit (beyond the paper, [`quadratic_gradient_vectors`]) adds second-order terms to the fit so
//! that `F_i` is exact for quadratic displacement fields also where the support is one-sided
//! (free surfaces), which the linear fit is not.
//!
//! Derivation of the force (eq 7). A displacement `δx_i` changes
//! - `F_i` by `−Σ_j δx_i ⊗ g_ij` (through `x_ij = x_j − x_i`), and
//! - `F_j`, for each neighbour `j` of `i`, by `δx_i ⊗ g_ji`.
//!
//! So with `P = ∂ψ/∂F` (eq 2–3) and `P : (a ⊗ b) = a · P b` (the reference neighbour list is
//! symmetric):
//!
//! `−∂U/∂x_i = Σ_j (V_i P_i g_ij − V_j P_j g_ji)`,
//!
//! which for the linear fit (`g_ji = −A_j⁻¹ w_ij X_ij`, `A` symmetric) is eq 7 times `ρ_i V_i`:
//! `Σ_j w_ij (V_i P_i A_i⁻ᵀ + V_j P_j A_j⁻ᵀ) X_ij`. Each pair term is antisymmetric in `(i, j)`,
//! so linear momentum is conserved to round-off; angular momentum follows from the objectivity
//! of `ψ` (`F(Qx) = Q F(x)`). Under tension (`P` positive definite) the force on `i` points
//! toward `j`. A guarded fit (see [`moment_inverse`]) still has fixed `g_ij`, so the force stays
//! the exact gradient of `U` for every particle, guarded or not.

use serde::{Deserialize, Serialize};
use sph_core::correction::guarded_inverse;
use sph_core::parallel::{gather, gather2};
use sph_core::{Dim, NeighborList};
use sph_materials::Material;

/// Which weighted-least-squares fit gives `F`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Fit {
    /// The paper's linear fit (eq 4–5): exact for affine fields; first-order error where the
    /// support is one-sided.
    #[default]
    Linear,
    /// Linear plus quadratic terms ([`quadratic_gradient_vectors`], beyond the paper): exact
    /// for quadratic fields everywhere, free surfaces included.
    Quadratic,
}

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

/// The gradient vectors of the paper's linear fit (eq 4–5) for one particle:
/// `g_ij = A_i⁻¹ w_ij X_ij` with `A_i⁻¹` from [`moment_inverse`]. `pairs` yields `(w_ij, X_ij)`;
/// returns the vectors in the same order and whether the guard acted.
pub fn linear_gradient_vectors<D: Dim>(
    pairs: &[(f64, D::Vector)],
    min_eigenvalue: f64,
) -> (Vec<D::Vector>, bool) {
    let (a_inv, guarded) = moment_inverse::<D>(pairs.iter().copied(), min_eigenvalue);
    (
        pairs.iter().map(|&(w, x)| a_inv * (x * w)).collect(),
        guarded,
    )
}

/// Number of monomials of the quadratic fit: `D` linear and `D(D + 1)/2` quadratic.
const fn quadratic_terms(d: usize) -> usize {
    d + d * (d + 1) / 2
}

/// The monomials of the quadratic fit at `X` (scaled by `r`: `X/r` and the products `X_a X_b/r²`,
/// `a ≤ b`), written into `p`.
fn monomials<D: Dim>(x: D::Vector, r: f64, p: &mut [f64]) {
    let d = D::D;
    for (a, pa) in p.iter_mut().enumerate().take(d) {
        *pa = D::component(x, a) / r;
    }
    let mut k = d;
    for a in 0..d {
        for b in a..d {
            p[k] = p[a] * p[b];
            k += 1;
        }
    }
}

/// The gradient vectors of the quadratic fit for one particle (beyond the paper): the weighted
/// least-squares fit `x_ij ≈ F X_ij + ½ H : (X_ij ⊗ X_ij)` over the same neighbours and weights
/// (eq 6), whose `F` part is `F_i = Σ_j x_ij ⊗ g_ij` with `g_ij` the first `D` entries of
/// `M_i⁻¹ w_ij p_ij / r` (`p_ij` the monomials of `X_ij / r`, `M_i = Σ_j w_ij p_ij p_ijᵀ`,
/// `r = r_e` for conditioning). It reproduces linear and quadratic displacement fields exactly,
/// so `F_i` has no first-order error where the support is one-sided (the surface rows of a bent
/// beam, where the linear fit under-estimates the fibre strain: `bending_stiffness_ratio` in
/// the validation crate). Falls back to [`linear_gradient_vectors`] (and reports the guard) when
/// `M_i` is singular or nearly so (a Cholesky pivot below `1e-8` of the largest diagonal entry:
/// too few or collinear neighbours, e.g. a corner particle in 3D with fewer than 9).
pub fn quadratic_gradient_vectors<D: Dim>(
    pairs: &[(f64, D::Vector)],
    r: f64,
    min_eigenvalue: f64,
) -> (Vec<D::Vector>, bool) {
    let m = quadratic_terms(D::D);
    let mut mat = vec![0.0; m * m];
    let mut p = [0.0; 9];
    for &(w, x) in pairs {
        monomials::<D>(x, r, &mut p);
        for a in 0..m {
            for b in 0..m {
                mat[a * m + b] += w * p[a] * p[b];
            }
        }
    }
    let Some(chol) = cholesky(&mut mat, m, 1e-8) else {
        let (g, _) = linear_gradient_vectors::<D>(pairs, min_eigenvalue);
        return (g, true);
    };
    let g = pairs
        .iter()
        .map(|&(w, x)| {
            monomials::<D>(x, r, &mut p);
            let mut c: Vec<f64> = p[..m].iter().map(|v| v * w).collect();
            chol.solve(&mut c);
            D::vector([c[0] / r, c[1] / r, if D::D > 2 { c[2] / r } else { 0.0 }])
        })
        .collect();
    (g, false)
}

/// A Cholesky factor `L` (lower, row-major, `L Lᵀ = M`) of a small dense symmetric matrix.
struct Cholesky<'a> {
    l: &'a [f64],
    n: usize,
}

/// Factors the `n × n` symmetric matrix `a` in place; `None` if a pivot falls below `tol` times
/// the largest diagonal entry (singular or nearly so).
fn cholesky(a: &mut [f64], n: usize, tol: f64) -> Option<Cholesky<'_>> {
    let scale = (0..n).map(|k| a[k * n + k]).fold(0.0, f64::max);
    if scale.is_nan() || scale <= 0.0 {
        return None;
    }
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[j * n + k] * a[j * n + k];
        }
        if d.is_nan() || d <= tol * scale {
            return None;
        }
        let d = d.sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = s / d;
        }
    }
    Some(Cholesky { l: a, n })
}

impl Cholesky<'_> {
    /// Solves `L Lᵀ y = b` in place.
    fn solve(&self, b: &mut [f64]) {
        let (l, n) = (self.l, self.n);
        for i in 0..n {
            let mut s = b[i];
            for k in 0..i {
                s -= l[i * n + k] * b[k];
            }
            b[i] = s / l[i * n + i];
        }
        for i in (0..n).rev() {
            let mut s = b[i];
            for k in i + 1..n {
                s -= l[k * n + i] * b[k];
            }
            b[i] = s / l[i * n + i];
        }
    }
}

/// Eq 4 for particle `i` in gradient-vector form: `F_i = Σ_j x_ij ⊗ g_ij`, `x_ij = x_j − x_i`,
/// with `g` the gradient vectors of every slot of `list`.
#[inline(always)]
pub fn deformation_gradient<D: Dim>(
    list: &NeighborList,
    i: usize,
    g: &[D::Vector],
    x: &[D::Vector],
) -> D::Matrix {
    let (xi, x_j) = (x[i], list.values(x));
    let mut f = D::zero_matrix();
    for (&j, &v) in list.neighbors(i).iter().zip(&g[list.range(i)]) {
        // SAFETY: `j` is an index of `list`, which made the view.
        f += D::outer(unsafe { x_j.at(j as usize) } - xi, v);
    }
    f
}

/// Pass 1 of a force evaluation, parallel over particles: `F_i` (eq 4) and the stress term
/// `T_i = V_i P(F_i)` of eq 7 (`P = F S`, eq 2–3), `P` of particle `i`'s material
/// (`(laws, material)`: the law of particle `i` is `laws[material[i]]`).
pub fn deformation_and_stress<D: Dim, M: Material<D>>(
    (laws, material): (&[M], &[u16]),
    list: &NeighborList,
    g: &[D::Vector],
    volumes: &[f64],
    x: &[D::Vector],
    deformation: &mut [D::Matrix],
    stress_term: &mut [D::Matrix],
) {
    gather2(
        deformation,
        stress_term,
        #[inline(always)]
        |i, f, t| {
            *f = deformation_gradient::<D>(list, i, g, x);
            *t = laws[material[i] as usize].first_piola_kirchhoff(*f) * volumes[i];
        },
    );
}

/// Pass 2, parallel over particles (gather): the internal force of eq 7,
/// `f_i = Σ_j (T_i g_ij − T_j g_ji) = −∂U/∂x_i` (see the module documentation); `g_rev[k]` is
/// `g_ji` of pair `k = (i, j)`.
pub fn internal_forces<D: Dim>(
    list: &NeighborList,
    g: &[D::Vector],
    g_rev: &[D::Vector],
    stress_term: &[D::Matrix],
    forces: &mut [D::Vector],
) {
    let t_j = list.values(stress_term);
    gather(
        forces,
        #[inline(always)]
        |i, out| {
            let ti = stress_term[i];
            let mut f = D::zero();
            let r = list.range(i);
            for ((&j, &gij), &gji) in list.neighbors(i).iter().zip(&g[r.clone()]).zip(&g_rev[r]) {
                // SAFETY: `j` is an index of `list`, which made the view.
                f += ti * gij - unsafe { t_j.at(j as usize) } * gji;
            }
            *out = f;
        },
    );
}

/// For every pair `k = (i, j)` of the (symmetric) list, the index of the reverse pair `(j, i)`.
///
/// # Panics
/// If the list is not symmetric (a reference list built within one radius always is).
pub fn reverse_pairs(list: &NeighborList) -> Vec<usize> {
    let mut rev = vec![0; list.num_pairs()];
    for i in 0..list.len() {
        for (k, &j) in list.range(i).zip(list.neighbors(i)) {
            let j = j as usize;
            let back = list
                .range(j)
                .zip(list.neighbors(j))
                .find(|(_, &m)| m as usize == i)
                .map(|(kk, _)| kk)
                .expect("the reference neighbour list is symmetric");
            rev[k] = back;
        }
    }
    rev
}

/// The cofactor matrix `cof F = det(F) F⁻ᵀ` (moved to `sph_core::dim`, where the surface
/// pressure of every method uses it).
pub use sph_core::dim::cofactor;
