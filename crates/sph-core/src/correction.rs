//! The kernel-gradient correction matrix `B_i = M_i⁻¹`,
//! `M_i = Σ_j V_j (x_j − x_i) ⊗ ∇_i W_ij` (TL paper eq 21, UL paper eq 27), with a guard for
//! particles whose `M_i` is near-singular.
//!
//! `M_i = −Σ_j V_j r_ij W′_ij e_ij ⊗ e_ij` is symmetric positive semi-definite (`W′ ≤ 0`), ≈ I in
//! the bulk and smaller at free surfaces and corners. The guard looks at its smallest
//! eigenvalue `λ_min`: if `λ_min ≥ λ_lim` the exact inverse is used; otherwise
//! `B = w M⁻¹ + (1 − w) I` with `w = max(λ_min, 0)/λ_lim`. Every eigenvalue of `w M⁻¹` is
//! `w/λ_k ≤ 1/λ_lim`, so `B` stays bounded, is continuous in `M`, and is never NaN (a particle
//! with 0 or 1 neighbours gets `B = I`).

use crate::dim::Dim;
use crate::error::{check_positive, Error};
use crate::kernel::Kernel;
use crate::neighbor::NeighborList;
use crate::pairs::{pair_kernel, PairKernel};

/// Default smallest-eigenvalue threshold of the guard. On a lattice with `h = 1.15 dp`, `M` is
/// 0.968 I (2D) or 0.994 I (3D) in the bulk and its smallest eigenvalue is 0.30 (2D) or 0.26
/// (3D) at a corner (measured in the tests), so the guard is idle for every particle of a
/// regular body and acts only for particles with very few or nearly collinear neighbours.
pub const DEFAULT_MIN_EIGENVALUE: f64 = 0.1;

/// Correction matrices of a particle set and how many needed the guard.
#[derive(Clone, Debug)]
pub struct Correction<D: Dim> {
    /// `B_i`, one per particle.
    pub matrices: Vec<D::Matrix>,
    /// Number of particles whose `M_i` had `λ_min < λ_lim` (blended toward the identity).
    pub guarded: usize,
}

/// The moment matrix `M_i = Σ_j V_j (x_j − x_i) ⊗ ∇_i W_ij` of one particle (eq 21 before the
/// inverse), from its pairs and its neighbours' volumes.
#[inline]
pub fn moment_matrix<D: Dim>(
    pairs: &[PairKernel<D>],
    neighbors: &[u32],
    volumes: &[f64],
) -> D::Matrix {
    moment_of_pairs::<D>(
        pairs.iter().copied().zip(neighbors.iter().copied()),
        volumes,
    )
}

/// `M_i` from its pairs' kernel data and neighbour indices, in list order (the one sum behind
/// [`moment_matrix`] and [`correction_matrices_at`]).
#[inline(always)]
fn moment_of_pairs<D: Dim>(
    pairs: impl Iterator<Item = (PairKernel<D>, u32)>,
    volumes: &[f64],
) -> D::Matrix {
    let mut m = D::zero_matrix();
    for (p, j) in pairs {
        // x_j − x_i = −r e_ij, ∇_i W = W′ e_ij.
        let a = p.e * (-p.r * volumes[j as usize]);
        m += D::outer(a, p.grad());
    }
    m
}

/// Guarded inverse of a symmetric positive semi-definite moment matrix: returns `B` and whether
/// the guard acted. See the module documentation.
#[inline]
pub fn guarded_inverse<D: Dim>(m: D::Matrix, min_eigenvalue: f64) -> (D::Matrix, bool) {
    let (vals, q) = D::symmetric_eigen(m);
    let lmin = D::component(vals, 0);
    if lmin >= min_eigenvalue {
        // Exact inverse through the eigen-decomposition (M is symmetric).
        let mut inv = vals;
        for k in 0..D::D {
            D::set_component(&mut inv, k, 1.0 / D::component(vals, k));
        }
        return (D::from_eigen(inv, q), false);
    }
    let w = lmin.max(0.0) / min_eigenvalue;
    let mut blended = vals;
    for k in 0..D::D {
        let l = D::component(vals, k);
        // w/λ_k + (1 − w), with w/λ_k := 0 when w = 0 (λ_k may be 0).
        let inv = if w > 0.0 { w / l } else { 0.0 };
        D::set_component(&mut blended, k, inv + (1.0 - w));
    }
    (D::from_eigen(blended, q), true)
}

/// Correction matrices `B_i` for every particle of `list`, with the guard threshold
/// `min_eigenvalue` (use [`DEFAULT_MIN_EIGENVALUE`]).
pub fn correction_matrices<D: Dim>(
    list: &NeighborList,
    pairs: &[PairKernel<D>],
    volumes: &[f64],
    min_eigenvalue: f64,
) -> Result<Correction<D>, Error> {
    guarded_corrections::<D>(
        list.len(),
        min_eigenvalue,
        |_| true,
        #[inline(always)]
        |i| moment_matrix::<D>(&pairs[list.range(i)], list.neighbors(i), volumes),
    )
}

/// [`correction_matrices`] of the configuration `positions` with its pair data computed row by
/// row ([`pair_kernel`]) instead of read from a stored list: the same matrices, bit for bit,
/// without holding the pair data of the whole list (what a solver that recomputes its pair
/// data needs to stay within its memory).
///
/// # Errors
/// `min_eigenvalue` not positive.
pub fn correction_matrices_at<D: Dim, K: Kernel>(
    list: &NeighborList,
    positions: &[D::Vector],
    kernel: &K,
    volumes: &[f64],
    min_eigenvalue: f64,
) -> Result<Correction<D>, Error> {
    correction_matrices_counted::<D, K>(list, positions, kernel, volumes, min_eigenvalue, |_| true)
}

/// As [`correction_matrices_at`], counting in [`Correction::guarded`] only the particles for
/// which `counted(i)` holds (a rank of a distributed run counts the particles it owns).
///
/// # Errors
/// `min_eigenvalue` not positive.
pub fn correction_matrices_counted<D: Dim, K: Kernel>(
    list: &NeighborList,
    positions: &[D::Vector],
    kernel: &K,
    volumes: &[f64],
    min_eigenvalue: f64,
    counted: impl Fn(usize) -> bool + Sync + Send,
) -> Result<Correction<D>, Error> {
    guarded_corrections::<D>(
        list.len(),
        min_eigenvalue,
        counted,
        #[inline(always)]
        |i| {
            let xi = positions[i];
            let row = list
                .neighbors(i)
                .iter()
                .map(|&j| (pair_kernel::<D, K>(xi - positions[j as usize], kernel), j));
            moment_of_pairs::<D>(row, volumes)
        },
    )
}

/// The guarded inverses of the moment matrices `moment(i)` of `n` particles.
fn guarded_corrections<D: Dim>(
    n: usize,
    min_eigenvalue: f64,
    counted: impl Fn(usize) -> bool + Sync + Send,
    moment: impl Fn(usize) -> D::Matrix + Sync + Send,
) -> Result<Correction<D>, Error> {
    check_positive("correction_min_eigenvalue", min_eigenvalue)?;
    let mut matrices = vec![D::zero_matrix(); n];
    let mut was_guarded = vec![false; n];
    crate::parallel::gather2(
        &mut matrices,
        &mut was_guarded,
        #[inline(always)]
        |i, b, g| {
            (*b, *g) = guarded_inverse::<D>(moment(i), min_eigenvalue);
        },
    );
    let guarded = (0..n).filter(|&i| was_guarded[i] && counted(i)).count();
    Ok(Correction { matrices, guarded })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::{D2, D3};
    use crate::kernel::{Kernel, WendlandC2};
    use crate::neighbor::neighbor_list_cells;
    use crate::pairs::pair_kernels;

    fn lattice<D: Dim>(n: [usize; 3], dp: f64) -> Vec<D::Vector> {
        let mut pts = Vec::new();
        for k in 0..(if D::D == 3 { n[2] } else { 1 }) {
            for j in 0..n[1] {
                for i in 0..n[0] {
                    pts.push(D::vector([i as f64 * dp, j as f64 * dp, k as f64 * dp]));
                }
            }
        }
        pts
    }

    struct Setup<D: Dim> {
        x: Vec<D::Vector>,
        v: Vec<f64>,
        list: NeighborList,
        pairs: Vec<PairKernel<D>>,
    }

    fn setup<D: Dim>(n: [usize; 3], h_over_dp: f64) -> Setup<D> {
        let dp = 0.1;
        let x = lattice::<D>(n, dp);
        let kernel = WendlandC2::<D>::from_spacing(dp, h_over_dp).unwrap();
        let list = neighbor_list_cells::<D>(&x, kernel.cutoff()).unwrap();
        let pairs = pair_kernels(&x, &list, &kernel);
        let v = vec![dp.powi(D::D as i32); x.len()];
        Setup { x, v, list, pairs }
    }

    fn check_b_times_m_is_identity_and_linear_gradients_exact<D: Dim>(
        n: [usize; 3],
        bulk_eigenvalue: f64,
    ) {
        let s = setup::<D>(n, 1.15);
        let corr = correction_matrices(&s.list, &s.pairs, &s.v, DEFAULT_MIN_EIGENVALUE).unwrap();
        // Every particle of a lattice block, corners included, has λ_min(M) above the guard.
        assert_eq!(corr.guarded, 0);
        // A linear field f(x) = G x + c: its corrected gradient Σ V (f_j − f_i) ⊗ ∇W B = G.
        let g = D::matrix_from_fn(|r, c| 0.3 + r as f64 - 0.7 * c as f64 + 0.1 * (r * c) as f64);
        let mut worst_bulk: f64 = 0.0;
        let mut min_eigenvalue = f64::INFINITY;
        for i in 0..s.x.len() {
            let r = s.list.range(i);
            let m = moment_matrix::<D>(&s.pairs[r.clone()], s.list.neighbors(i), &s.v);
            let b = corr.matrices[i];
            // Tolerance 1e-12: B is M⁻¹ to round-off; entries are O(1).
            assert!(
                D::frobenius(b * m - D::identity()) < 1e-12,
                "B M ≠ I at {i}"
            );
            let mut grad = D::zero_matrix();
            for (p, &j) in s.pairs[r].iter().zip(s.list.neighbors(i)) {
                let df = g * (s.x[j as usize] - s.x[i]);
                grad += D::outer(df * s.v[j as usize], p.grad());
            }
            grad = grad * b;
            // Exact for linear fields everywhere (corners included): round-off only.
            assert!(
                D::frobenius(grad - g) < 1e-11 * D::frobenius(g),
                "particle {i}"
            );
            let (vals, _) = D::symmetric_eigen(m);
            min_eigenvalue = min_eigenvalue.min(D::component(vals, 0));
            if s.list.count(i) == s.list.max_count() {
                // Bulk M is isotropic: every eigenvalue equals the lattice sum.
                for k in 0..D::D {
                    worst_bulk = worst_bulk.max((D::component(vals, k) - bulk_eigenvalue).abs());
                }
            }
        }
        // Bulk M = λ I with λ the lattice sum Σ −V r W′ e_x² for h = 1.15 dp (0.9679 in 2D, as
        // docs/methods.md says; 0.9941 in 3D); 1e-5 covers the 6-digit constants, not a wrong sum.
        assert!(
            worst_bulk < 1e-5,
            "bulk eigenvalue off by {worst_bulk}, min {min_eigenvalue}"
        );
        // Corners have the smallest eigenvalue; the guard threshold sits well below it.
        assert!(
            min_eigenvalue > 2.0 * DEFAULT_MIN_EIGENVALUE,
            "{min_eigenvalue}"
        );
    }

    #[test]
    fn correction_inverts_moment_matrix_and_makes_linear_gradients_exact_2d() {
        check_b_times_m_is_identity_and_linear_gradients_exact::<D2>([12, 9, 1], 0.967_911);
    }

    #[test]
    fn correction_inverts_moment_matrix_and_makes_linear_gradients_exact_3d() {
        check_b_times_m_is_identity_and_linear_gradients_exact::<D3>([7, 6, 6], 0.994_093);
    }

    /// The row-by-row form gives the stored-pair form's matrices bit for bit, on a jittered
    /// 3D block (surface and guarded particles included) and a 2D one.
    fn check_correction_at_matches_stored<D: Dim>(n: [usize; 3]) {
        let dp = 0.1;
        let mut x = lattice::<D>(n, dp);
        for (k, xi) in x.iter_mut().enumerate() {
            let jitter = |s: u64| ((k as u64 * 2654435761 + s) % 1000) as f64 / 1000.0 - 0.5;
            *xi += D::vector([
                0.2 * dp * jitter(1),
                0.2 * dp * jitter(7),
                0.2 * dp * jitter(13),
            ]);
        }
        let kernel = WendlandC2::<D>::from_spacing(dp, 1.15).unwrap();
        let list = neighbor_list_cells::<D>(&x, kernel.cutoff()).unwrap();
        let pairs = pair_kernels(&x, &list, &kernel);
        let v: Vec<f64> = (0..x.len())
            .map(|k| dp.powi(D::D as i32) * (1.0 + 0.01 * (k % 5) as f64))
            .collect();
        // A threshold that guards the corners too, so both branches are compared.
        let stored = correction_matrices::<D>(&list, &pairs, &v, 0.5).unwrap();
        let at = correction_matrices_at::<D, _>(&list, &x, &kernel, &v, 0.5).unwrap();
        assert!(stored.guarded > 0 && stored.guarded < x.len());
        assert_eq!(stored.guarded, at.guarded);
        assert_eq!(stored.matrices, at.matrices);
    }

    #[test]
    fn correction_from_positions_equals_correction_from_stored_pairs() {
        check_correction_at_matches_stored::<D2>([11, 8, 1]);
        check_correction_at_matches_stored::<D3>([6, 5, 7]);
    }

    #[test]
    fn guard_never_returns_nan_for_isolated_or_single_neighbour_particles() {
        // Two particles (one neighbour each), a collinear triple, and an isolated particle.
        let dp = 0.1;
        let x2 = vec![
            glam::DVec2::new(0.0, 0.0),
            glam::DVec2::new(dp, 0.0),
            glam::DVec2::new(5.0, 5.0),
            glam::DVec2::new(5.0, 5.0 + dp),
            glam::DVec2::new(5.0, 5.0 + 2.0 * dp),
        ];
        let kernel = WendlandC2::<D2>::from_spacing(dp, 1.15).unwrap();
        let list = neighbor_list_cells::<D2>(&x2, kernel.cutoff()).unwrap();
        let pairs = pair_kernels::<D2, _>(&x2, &list, &kernel);
        let v = vec![dp * dp; x2.len()];
        let corr = correction_matrices(&list, &pairs, &v, DEFAULT_MIN_EIGENVALUE).unwrap();
        assert_eq!(corr.guarded, 5);
        for b in &corr.matrices {
            assert!(D2::matrix_is_finite(*b));
            // Bounded: every eigenvalue ≤ 1/λ_lim + 1.
            assert!(D2::frobenius(*b) <= 2.0 * (1.0 / DEFAULT_MIN_EIGENVALUE + 1.0));
        }
        let lone = vec![glam::DVec3::ZERO];
        let list = neighbor_list_cells::<D3>(&lone, 0.2).unwrap();
        let k3 = WendlandC2::<D3>::new(0.1).unwrap();
        let corr = correction_matrices::<D3>(&list, &pair_kernels(&lone, &list, &k3), &[1.0], 0.1)
            .unwrap();
        assert_eq!(corr.matrices[0], glam::DMat3::IDENTITY);
    }

    #[test]
    fn guard_is_continuous_at_the_threshold() {
        // B just above and just below λ_lim differ by O(δ).
        let lim = 0.1;
        let (above, below) = (lim * (1.0 + 1e-9), lim * (1.0 - 1e-9));
        let m1 = glam::DMat2::from_diagonal(glam::DVec2::new(1.0, above));
        let m2 = glam::DMat2::from_diagonal(glam::DVec2::new(1.0, below));
        let (b1, g1) = guarded_inverse::<D2>(m1, lim);
        let (b2, g2) = guarded_inverse::<D2>(m2, lim);
        assert!(!g1 && g2);
        assert!(D2::frobenius(b1 - b2) < 1e-6);
    }
}
