//! Spatial dimension as a type: [`D2`] and [`D3`] over glam's `f64` vectors and matrices.
//!
//! Every solver is generic over `D: Dim` and monomorphised, so the same source serves 2D and 3D
//! with no run-time dimension branch in hot loops (`D::D` is a constant the compiler folds).
//!
//! glam's `f64` types are column-major: [`Dim::matrix_get`]`(m, r, c)` is row `r`, column `c`.
//! glam has no outer product, trace or guarded inverse; they live here.

use glam::{DMat2, DMat3, DVec2, DVec3};
use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

/// The operations a spatial vector type must offer.
pub trait VectorOps:
    Copy
    + Debug
    + Default
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Neg<Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign<f64>
{
}
impl VectorOps for DVec2 {}
impl VectorOps for DVec3 {}

/// The operations a square matrix type must offer.
pub trait MatrixOps<V>:
    Copy
    + Debug
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Neg<Output = Self>
    + Mul<Self, Output = Self>
    + Mul<V, Output = V>
    + Mul<f64, Output = Self>
    + AddAssign
    + SubAssign
{
}
impl MatrixOps<DVec2> for DMat2 {}
impl MatrixOps<DVec3> for DMat3 {}

/// A spatial dimension: its vector and matrix types and the handful of tensor operations the
/// methods need. Implemented by [`D2`] (plane strain) and [`D3`].
pub trait Dim: Copy + Debug + Default + Send + Sync + 'static {
    /// Number of spatial dimensions (2 or 3).
    const D: usize;
    /// Column vector (`DVec2` or `DVec3`).
    type Vector: VectorOps;
    /// Square matrix (`DMat2` or `DMat3`), column-major.
    type Matrix: MatrixOps<Self::Vector>;

    /// The zero vector.
    fn zero() -> Self::Vector;
    /// A vector from its components (`c[k]` for `k < D`; the rest ignored).
    fn vector(c: [f64; 3]) -> Self::Vector;
    /// Component `k` (`k < D`).
    fn component(v: Self::Vector, k: usize) -> f64;
    /// Sets component `k` (`k < D`).
    fn set_component(v: &mut Self::Vector, k: usize, value: f64);
    /// Scalar product.
    fn dot(a: Self::Vector, b: Self::Vector) -> f64;
    /// `v` as 3D vectors when `Self` is [`D3`] (for loops written for 3D only), else `None`.
    #[inline(always)]
    fn as_vec3(_v: &[Self::Vector]) -> Option<&[DVec3]> {
        None
    }
    /// `v` as 3D vectors when `Self` is [`D3`], else `None`.
    #[inline(always)]
    fn as_vec3_mut(_v: &mut [Self::Vector]) -> Option<&mut [DVec3]> {
        None
    }
    /// `m` as 3×3 matrices when `Self` is [`D3`], else `None`.
    #[inline(always)]
    fn as_mat3(_m: &[Self::Matrix]) -> Option<&[DMat3]> {
        None
    }
    /// `m` as 3×3 matrices when `Self` is [`D3`], else `None`.
    #[inline(always)]
    fn as_mat3_mut(_m: &mut [Self::Matrix]) -> Option<&mut [DMat3]> {
        None
    }
    /// Euclidean norm.
    fn norm(v: Self::Vector) -> f64 {
        Self::dot(v, v).sqrt()
    }
    /// Squared Euclidean norm.
    fn norm_squared(v: Self::Vector) -> f64 {
        Self::dot(v, v)
    }
    /// The vector embedded in 3D (z = 0 in 2D).
    fn to_vec3(v: Self::Vector) -> DVec3;
    /// Whether every component is finite.
    fn is_finite(v: Self::Vector) -> bool;

    /// The identity matrix.
    fn identity() -> Self::Matrix;
    /// The zero matrix.
    fn zero_matrix() -> Self::Matrix;
    /// Outer product `a ⊗ b` (entry `(r, c)` is `a_r b_c`).
    fn outer(a: Self::Vector, b: Self::Vector) -> Self::Matrix;
    /// Entry in row `r`, column `c`.
    fn matrix_get(m: Self::Matrix, r: usize, c: usize) -> f64;
    /// A matrix from `f(r, c)`.
    fn matrix_from_fn(f: impl Fn(usize, usize) -> f64) -> Self::Matrix;
    /// Determinant.
    fn det(m: Self::Matrix) -> f64;
    /// Transpose.
    fn transpose(m: Self::Matrix) -> Self::Matrix;
    /// Trace.
    fn trace(m: Self::Matrix) -> f64;
    /// Inverse, or `None` when the determinant is zero or the result is not finite.
    /// (glam's `inverse()` silently returns non-finite values for a singular matrix.)
    fn try_inverse(m: Self::Matrix) -> Option<Self::Matrix>;
    /// Double contraction `a : b = Σ a_rc b_rc`.
    fn ddot(a: Self::Matrix, b: Self::Matrix) -> f64;
    /// Frobenius norm.
    fn frobenius(m: Self::Matrix) -> f64 {
        Self::ddot(m, m).sqrt()
    }
    /// Whether every entry is finite.
    fn matrix_is_finite(m: Self::Matrix) -> bool;
    /// Embeds the matrix in 3×3 with `zz` as the out-of-plane diagonal entry (2D); the
    /// matrix itself in 3D. Plane strain: `zz = 1` for F, C, b; the out-of-plane stress for σ.
    fn to_mat3(m: Self::Matrix, zz: f64) -> DMat3;
    /// Eigen-decomposition of a symmetric matrix: eigenvalues in ascending order and the matrix
    /// whose columns are the matching orthonormal eigenvectors (`m = Q diag(λ) Qᵀ`).
    fn symmetric_eigen(m: Self::Matrix) -> (Self::Vector, Self::Matrix);
    /// Smallest singular value of `m` (`√` of the smallest eigenvalue of `mᵀm`), in closed form:
    /// the factor by which `m` shortens the direction it shortens most (for a deformation
    /// gradient, the smallest principal stretch).
    fn min_singular_value(m: Self::Matrix) -> f64;
    /// `Q diag(λ) Qᵀ`: rebuilds a symmetric matrix from an eigen-decomposition.
    fn from_eigen(eigenvalues: Self::Vector, q: Self::Matrix) -> Self::Matrix {
        Self::matrix_from_fn(|r, c| {
            (0..Self::D)
                .map(|k| {
                    Self::matrix_get(q, r, k)
                        * Self::component(eigenvalues, k)
                        * Self::matrix_get(q, c, k)
                })
                .sum()
        })
    }
}

/// Two dimensions (plane strain for the constitutive laws).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct D2;

/// Three dimensions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct D3;

impl Dim for D2 {
    const D: usize = 2;
    type Vector = DVec2;
    type Matrix = DMat2;

    #[inline(always)]
    fn zero() -> DVec2 {
        DVec2::ZERO
    }
    #[inline(always)]
    fn vector(c: [f64; 3]) -> DVec2 {
        DVec2::new(c[0], c[1])
    }
    #[inline(always)]
    fn component(v: DVec2, k: usize) -> f64 {
        v[k]
    }
    #[inline(always)]
    fn set_component(v: &mut DVec2, k: usize, value: f64) {
        v[k] = value;
    }
    #[inline(always)]
    fn dot(a: DVec2, b: DVec2) -> f64 {
        a.dot(b)
    }
    #[inline(always)]
    fn to_vec3(v: DVec2) -> DVec3 {
        v.extend(0.0)
    }
    #[inline(always)]
    fn is_finite(v: DVec2) -> bool {
        v.is_finite()
    }
    #[inline(always)]
    fn identity() -> DMat2 {
        DMat2::IDENTITY
    }
    #[inline(always)]
    fn zero_matrix() -> DMat2 {
        DMat2::ZERO
    }
    #[inline(always)]
    fn outer(a: DVec2, b: DVec2) -> DMat2 {
        DMat2::from_cols(a * b.x, a * b.y)
    }
    #[inline(always)]
    fn matrix_get(m: DMat2, r: usize, c: usize) -> f64 {
        m.col(c)[r]
    }
    #[inline(always)]
    fn matrix_from_fn(f: impl Fn(usize, usize) -> f64) -> DMat2 {
        DMat2::from_cols(DVec2::new(f(0, 0), f(1, 0)), DVec2::new(f(0, 1), f(1, 1)))
    }
    #[inline(always)]
    fn det(m: DMat2) -> f64 {
        m.determinant()
    }
    #[inline(always)]
    fn transpose(m: DMat2) -> DMat2 {
        m.transpose()
    }
    #[inline(always)]
    fn trace(m: DMat2) -> f64 {
        m.x_axis.x + m.y_axis.y
    }
    #[inline(always)]
    fn try_inverse(m: DMat2) -> Option<DMat2> {
        let det = m.determinant();
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let inv = m.inverse();
        inv.is_finite().then_some(inv)
    }
    #[inline(always)]
    fn ddot(a: DMat2, b: DMat2) -> f64 {
        a.x_axis.dot(b.x_axis) + a.y_axis.dot(b.y_axis)
    }
    #[inline(always)]
    fn matrix_is_finite(m: DMat2) -> bool {
        m.is_finite()
    }
    #[inline(always)]
    fn to_mat3(m: DMat2, zz: f64) -> DMat3 {
        DMat3::from_cols(
            m.x_axis.extend(0.0),
            m.y_axis.extend(0.0),
            DVec3::new(0.0, 0.0, zz),
        )
    }
    fn min_singular_value(m: DMat2) -> f64 {
        // Eigenvalues of mᵀm: (t ± √(t² − 4 det²))/2 with t = |m|².
        let t = m.x_axis.length_squared() + m.y_axis.length_squared();
        let det = m.determinant();
        let disc = (t * t - 4.0 * det * det).max(0.0).sqrt();
        // The smaller root without cancellation: det² / larger root.
        let big = 0.5 * (t + disc);
        if big > 0.0 {
            (det * det / big).sqrt()
        } else {
            0.0
        }
    }
    fn symmetric_eigen(m: DMat2) -> (DVec2, DMat2) {
        // Closed form: rotation angle θ with tan 2θ = 2 m_xy / (m_xx − m_yy).
        let (a, b, d) = (m.x_axis.x, 0.5 * (m.y_axis.x + m.x_axis.y), m.y_axis.y);
        let mean = 0.5 * (a + d);
        let half_diff = 0.5 * (a - d);
        let radius = half_diff.hypot(b);
        let theta = 0.5 * b.atan2(half_diff);
        let (s, c) = theta.sin_cos();
        // Column 0 is the eigenvector of the larger eigenvalue (mean + radius).
        let big = DVec2::new(c, s);
        let small = DVec2::new(-s, c);
        (
            DVec2::new(mean - radius, mean + radius),
            DMat2::from_cols(small, big),
        )
    }
}

impl Dim for D3 {
    const D: usize = 3;
    type Vector = DVec3;
    type Matrix = DMat3;

    #[inline(always)]
    fn zero() -> DVec3 {
        DVec3::ZERO
    }
    #[inline(always)]
    fn vector(c: [f64; 3]) -> DVec3 {
        DVec3::from_array(c)
    }
    #[inline(always)]
    fn component(v: DVec3, k: usize) -> f64 {
        v[k]
    }
    #[inline(always)]
    fn set_component(v: &mut DVec3, k: usize, value: f64) {
        v[k] = value;
    }
    #[inline(always)]
    fn dot(a: DVec3, b: DVec3) -> f64 {
        a.dot(b)
    }
    #[inline(always)]
    fn to_vec3(v: DVec3) -> DVec3 {
        v
    }
    #[inline(always)]
    fn is_finite(v: DVec3) -> bool {
        v.is_finite()
    }
    #[inline(always)]
    fn identity() -> DMat3 {
        DMat3::IDENTITY
    }
    #[inline(always)]
    fn zero_matrix() -> DMat3 {
        DMat3::ZERO
    }
    #[inline(always)]
    fn as_vec3(v: &[DVec3]) -> Option<&[DVec3]> {
        Some(v)
    }
    #[inline(always)]
    fn as_vec3_mut(v: &mut [DVec3]) -> Option<&mut [DVec3]> {
        Some(v)
    }
    #[inline(always)]
    fn as_mat3(m: &[DMat3]) -> Option<&[DMat3]> {
        Some(m)
    }
    #[inline(always)]
    fn as_mat3_mut(m: &mut [DMat3]) -> Option<&mut [DMat3]> {
        Some(m)
    }
    #[inline(always)]
    fn outer(a: DVec3, b: DVec3) -> DMat3 {
        DMat3::from_cols(a * b.x, a * b.y, a * b.z)
    }
    #[inline(always)]
    fn matrix_get(m: DMat3, r: usize, c: usize) -> f64 {
        m.col(c)[r]
    }
    #[inline(always)]
    fn matrix_from_fn(f: impl Fn(usize, usize) -> f64) -> DMat3 {
        DMat3::from_cols(
            DVec3::new(f(0, 0), f(1, 0), f(2, 0)),
            DVec3::new(f(0, 1), f(1, 1), f(2, 1)),
            DVec3::new(f(0, 2), f(1, 2), f(2, 2)),
        )
    }
    #[inline(always)]
    fn det(m: DMat3) -> f64 {
        m.determinant()
    }
    #[inline(always)]
    fn transpose(m: DMat3) -> DMat3 {
        m.transpose()
    }
    #[inline(always)]
    fn trace(m: DMat3) -> f64 {
        m.x_axis.x + m.y_axis.y + m.z_axis.z
    }
    #[inline(always)]
    fn try_inverse(m: DMat3) -> Option<DMat3> {
        let det = m.determinant();
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let inv = m.inverse();
        inv.is_finite().then_some(inv)
    }
    #[inline(always)]
    fn ddot(a: DMat3, b: DMat3) -> f64 {
        a.x_axis.dot(b.x_axis) + a.y_axis.dot(b.y_axis) + a.z_axis.dot(b.z_axis)
    }
    #[inline(always)]
    fn matrix_is_finite(m: DMat3) -> bool {
        m.is_finite()
    }
    #[inline(always)]
    fn to_mat3(m: DMat3, _zz: f64) -> DMat3 {
        m
    }
    fn min_singular_value(m: DMat3) -> f64 {
        // Smallest eigenvalue of C = mᵀm by the trigonometric solution of its characteristic
        // cubic (Smith 1961), clamped at 0 against round-off.
        let c = m.transpose() * m;
        let (c00, c11, c22) = (c.x_axis.x, c.y_axis.y, c.z_axis.z);
        let (c01, c02, c12) = (c.y_axis.x, c.z_axis.x, c.z_axis.y);
        let p1 = c01 * c01 + c02 * c02 + c12 * c12;
        let q = (c00 + c11 + c22) / 3.0;
        let p2 = (c00 - q).powi(2) + (c11 - q).powi(2) + (c22 - q).powi(2) + 2.0 * p1;
        let p = (p2 / 6.0).sqrt();
        if p <= 1e-15 * q.abs() {
            return q.max(0.0).sqrt();
        }
        let b = (c - DMat3::from_diagonal(DVec3::splat(q))) * (1.0 / p);
        let r = (0.5 * b.determinant()).clamp(-1.0, 1.0);
        let phi = r.acos() / 3.0;
        let smallest = q + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos();
        smallest.max(0.0).sqrt()
    }
    fn symmetric_eigen(m: DMat3) -> (DVec3, DMat3) {
        jacobi_eigen3(m)
    }
}

/// Cyclic Jacobi eigen-solver for a symmetric 3×3 matrix (robust for repeated eigenvalues;
/// converges to round-off in a handful of sweeps). Eigenvalues ascending.
fn jacobi_eigen3(m: DMat3) -> (DVec3, DMat3) {
    let mut a = [[0.0f64; 3]; 3];
    for (r, row) in a.iter_mut().enumerate() {
        for (c, v) in row.iter_mut().enumerate() {
            // Symmetrise so a slightly asymmetric input is handled consistently.
            *v = 0.5 * (m.col(c)[r] + m.col(r)[c]);
        }
    }
    let mut q = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let scale = a.iter().flatten().map(|v| v.abs()).fold(0.0, f64::max);
    if scale > 0.0 {
        for _sweep in 0..50 {
            let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
            if off <= 1e-15 * scale {
                break;
            }
            for (p, r) in [(0usize, 1usize), (0, 2), (1, 2)] {
                if a[p][r].abs() <= 1e-300 {
                    continue;
                }
                let theta = (a[r][r] - a[p][p]) / (2.0 * a[p][r]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                // A ← Jᵀ A J with the rotation in the (p, r) plane.
                for k in 0..3 {
                    let akp = a[k][p];
                    let akr = a[k][r];
                    a[k][p] = c * akp - s * akr;
                    a[k][r] = s * akp + c * akr;
                }
                for k in 0..3 {
                    let apk = a[p][k];
                    let ark = a[r][k];
                    a[p][k] = c * apk - s * ark;
                    a[r][k] = s * apk + c * ark;
                }
                for row in q.iter_mut() {
                    let qp = row[p];
                    let qr = row[r];
                    row[p] = c * qp - s * qr;
                    row[r] = s * qp + c * qr;
                }
            }
        }
    }
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| a[i][i].total_cmp(&a[j][j]));
    let vals = DVec3::new(
        a[order[0]][order[0]],
        a[order[1]][order[1]],
        a[order[2]][order[2]],
    );
    let col = |k: usize| DVec3::new(q[0][k], q[1][k], q[2][k]);
    (
        vals,
        DMat3::from_cols(col(order[0]), col(order[1]), col(order[2])),
    )
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

#[cfg(test)]
mod tests {
    use super::*;

    fn check_eigen<D: Dim>(m: D::Matrix) {
        let (vals, q) = D::symmetric_eigen(m);
        let rebuilt = D::from_eigen(vals, q);
        let scale = D::frobenius(m).max(1e-300);
        // Tolerance: rebuilding from a converged decomposition is exact to a few ulps of the
        // largest entry.
        assert!(
            D::frobenius(rebuilt - m) <= 1e-12 * scale,
            "{m:?} vs {rebuilt:?}"
        );
        let qtq = D::transpose(q) * q;
        assert!(D::frobenius(qtq - D::identity()) <= 1e-12);
        for k in 1..D::D {
            assert!(D::component(vals, k - 1) <= D::component(vals, k));
        }
    }

    #[test]
    fn min_singular_value_matches_the_eigen_solver_2d_and_3d() {
        fn check<D: Dim>(m: D::Matrix) {
            let c = D::transpose(m) * m;
            let (vals, _) = D::symmetric_eigen(c);
            let want = D::component(vals, 0).max(0.0).sqrt();
            let got = D::min_singular_value(m);
            // Tolerance: round-off of the closed forms relative to the largest stretch.
            let scale = D::frobenius(m);
            assert!(
                (got - want).abs() <= 1e-12 * scale,
                "{got} vs {want} for {m:?}"
            );
        }
        check::<D2>(DMat2::from_cols_array(&[1.3, 0.2, -0.4, 0.7]));
        check::<D2>(DMat2::from_diagonal(DVec2::new(2.0, 0.5)));
        check::<D2>(DMat2::IDENTITY);
        check::<D3>(DMat3::from_cols_array(&[
            1.1, 0.3, -0.2, 0.05, 0.6, 0.4, -0.3, 0.1, 1.7,
        ]));
        check::<D3>(DMat3::from_diagonal(DVec3::new(0.5, 2.0, 1.0)));
        check::<D3>(DMat3::IDENTITY);
        // A rotation times a stretch: the stretch's smallest entry.
        let rot = DMat3::from_rotation_z(0.7) * DMat3::from_rotation_x(-0.3);
        let m = rot * DMat3::from_diagonal(DVec3::new(1.4, 0.35, 0.9));
        assert!((D3::min_singular_value(m) - 0.35).abs() < 1e-12);
    }

    #[test]
    fn symmetric_eigen_reconstructs_the_matrix_2d_and_3d() {
        check_eigen::<D2>(DMat2::from_cols_array(&[2.0, 0.7, 0.7, -1.0]));
        check_eigen::<D2>(DMat2::from_cols_array(&[1.0, 0.0, 0.0, 1.0]));
        check_eigen::<D2>(DMat2::from_cols_array(&[-3.0, 0.0, 0.0, 5.0]));
        check_eigen::<D3>(DMat3::from_cols_array(&[
            2.0, 0.3, -0.4, 0.3, 1.0, 0.5, -0.4, 0.5, -2.0,
        ]));
        check_eigen::<D3>(DMat3::IDENTITY * 4.0);
        check_eigen::<D3>(DMat3::from_cols_array(&[
            1.0, 1.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0,
        ]));
    }

    #[test]
    fn outer_product_and_accessors_agree_with_row_column_convention() {
        let a = DVec3::new(1.0, 2.0, 3.0);
        let b = DVec3::new(4.0, 5.0, 6.0);
        let m = D3::outer(a, b);
        assert_eq!(D3::matrix_get(m, 1, 2), 2.0 * 6.0);
        assert_eq!(m * DVec3::X, a * 4.0);
        assert_eq!(D3::trace(m), a.dot(b));
        let m2 = D2::outer(DVec2::new(1.0, 2.0), DVec2::new(3.0, 4.0));
        assert_eq!(D2::matrix_get(m2, 0, 1), 4.0);
        assert_eq!(D2::matrix_get(m2, 1, 0), 6.0);
    }

    #[test]
    fn try_inverse_rejects_singular_matrices() {
        assert!(D2::try_inverse(D2::outer(DVec2::X, DVec2::Y)).is_none());
        assert!(D3::try_inverse(DMat3::ZERO).is_none());
        let m = DMat3::from_cols_array(&[2.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.0, 4.0]);
        let inv = D3::try_inverse(m).unwrap();
        assert!(D3::frobenius(inv * m - DMat3::IDENTITY) < 1e-15);
    }
}
