//! The particle-disorder (hourglass) indicator of docs/methods.md (Ganzenmüller's error):
//!
//! `e_i = Σ_j W⁰_ij |F_i X_ij − x_ij| / Σ_j W⁰_ij |X_ij|`, `X_ij = X_i − X_j`, `x_ij = x_i − x_j`.
//!
//! Zero for any affine motion, large for zigzag modes; it turns "the picture looks smooth" into a
//! number. `F_i` is the method's own deformation gradient (TL, MPS) or, for methods without one
//! (UL), the weighted least-squares affine fit [`affine_fit`] between a reference configuration
//! (e.g. the last neighbour rebuild) and now.

use crate::correction::{guarded_inverse, DEFAULT_MIN_EIGENVALUE};
use crate::dim::Dim;
use crate::kernel::{Kernel, WendlandC2};
use crate::neighbor::NeighborList;

/// The reference weights `W⁰_ij` of the indicator and of [`affine_fit`] (the distances
/// `|X_ij|` are those of the reference positions): the kernel evaluated at each pair's
/// reference distance as it is visited (nothing stored per pair: a method whose reference
/// data is not kept, like UL's initial configuration, would otherwise allocate the whole pair
/// list for every monitor sample), or a method's own stored weights (MPS's eq 6).
#[derive(Clone, Copy, Debug)]
pub enum ReferenceWeights<'a, D: Dim> {
    /// Evaluate this kernel at the reference distance.
    Kernel(&'a WendlandC2<D>),
    /// One stored weight per slot of the list, in list order.
    Stored(&'a [f64]),
}

impl<D: Dim> ReferenceWeights<'_, D> {
    /// `(W⁰, r)` of the pair in slot `k` of the list whose reference separation is `xij0`:
    /// the kernel at `r = |xij0|`, or the stored weight.
    #[inline(always)]
    fn at(&self, k: usize, xij0: D::Vector) -> (f64, f64) {
        let r = D::norm(xij0);
        match self {
            ReferenceWeights::Kernel(kernel) => (kernel.w(r), r),
            ReferenceWeights::Stored(w) => (w[k], r),
        }
    }
}

/// Per-particle disorder `e_i` from the method's deformation gradients, with the weights
/// `W⁰` and distances of `list`'s pairs in the reference configuration `reference`.
pub fn disorder_indicator<D: Dim>(
    list: &NeighborList,
    weights: ReferenceWeights<'_, D>,
    reference: &[D::Vector],
    current: &[D::Vector],
    deformation: &[D::Matrix],
) -> Vec<f64> {
    let (x0_j, x_j) = (list.values(reference), list.values(current));
    let mut out = vec![0.0; list.len()];
    crate::parallel::gather(
        &mut out,
        #[inline(always)]
        |i, e| {
            let (f, x0_i, x_i) = (deformation[i], reference[i], current[i]);
            let mut num = 0.0;
            let mut den = 0.0;
            for (k, &j) in list.range(i).zip(list.neighbors(i)) {
                // SAFETY: `j` is an index of `list`, which made the views.
                let (x0_j, x_j) = unsafe { (x0_j.at(j as usize), x_j.at(j as usize)) };
                let xij0 = x0_i - x0_j;
                let xij = x_i - x_j;
                let (w, r) = weights.at(k, xij0);
                num += w * D::norm(f * xij0 - xij);
                den += w * r;
            }
            *e = if den > 0.0 { num / den } else { 0.0 };
        },
    );
    out
}

/// Weighted least-squares deformation gradient mapping the reference neighbourhood onto the
/// current one: `F_i = (Σ_j W⁰ x_ij ⊗ X_ij)(Σ_j W⁰ X_ij ⊗ X_ij)⁻¹` (the moment matrix inverted
/// with the guard of [`crate::correction`], scaled to be dimensionless).
pub fn affine_fit<D: Dim>(
    list: &NeighborList,
    weights: ReferenceWeights<'_, D>,
    reference: &[D::Vector],
    current: &[D::Vector],
) -> Vec<D::Matrix> {
    let (x0_j, x_j) = (list.values(reference), list.values(current));
    let mut out = vec![D::identity(); list.len()];
    crate::parallel::gather(
        &mut out,
        #[inline(always)]
        |i, fit| {
            let (x0_i, x_i) = (reference[i], current[i]);
            let mut a = D::zero_matrix();
            let mut b = D::zero_matrix();
            let mut wsum = 0.0;
            let mut r2sum = 0.0;
            for (k, &j) in list.range(i).zip(list.neighbors(i)) {
                // SAFETY: `j` is an index of `list`, which made the views.
                let (x0_j, x_j) = unsafe { (x0_j.at(j as usize), x_j.at(j as usize)) };
                let xij0 = x0_i - x0_j;
                let xij = x_i - x_j;
                let (w, r) = weights.at(k, xij0);
                a += D::outer(xij0 * w, xij0);
                b += D::outer(xij * w, xij0);
                wsum += w;
                r2sum += w * r * r;
            }
            if wsum <= 0.0 || r2sum <= 0.0 {
                *fit = D::identity();
                return;
            }
            // Normalise A by its mean squared distance so the guard threshold is scale free.
            let scale = D::D as f64 / r2sum;
            let (inv, _) = guarded_inverse::<D>(a * scale, DEFAULT_MIN_EIGENVALUE);
            *fit = b * inv * scale;
        },
    );
    out
}

/// Summary statistics of a per-particle indicator.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DisorderStats {
    /// Maximum over particles.
    pub max: f64,
    /// 99th percentile (nearest-rank).
    pub p99: f64,
    /// Mean.
    pub mean: f64,
}

impl DisorderStats {
    /// Statistics of `values` (all zero for an empty slice). NaN values count as +∞, so a blown-up
    /// particle shows in the maximum.
    pub fn of(values: &[f64]) -> Self {
        if values.is_empty() {
            return Self::default();
        }
        let mut v: Vec<f64> = values
            .iter()
            .map(|&x| if x.is_nan() { f64::INFINITY } else { x })
            .collect();
        v.sort_unstable_by(f64::total_cmp);
        let n = v.len();
        let rank = ((0.99 * n as f64).ceil() as usize).clamp(1, n) - 1;
        Self {
            max: v[n - 1],
            p99: v[rank],
            mean: v.iter().sum::<f64>() / n as f64,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::{D2, D3};
    use crate::kernel::{Kernel, WendlandC2};
    use crate::neighbor::neighbor_list_cells;
    use crate::pairs::pair_kernels;

    fn block<D: Dim>(n: usize, dp: f64) -> Vec<D::Vector> {
        let mut v = Vec::new();
        for k in 0..(if D::D == 3 { n } else { 1 }) {
            for j in 0..n {
                for i in 0..n {
                    v.push(D::vector([i as f64 * dp, j as f64 * dp, k as f64 * dp]));
                }
            }
        }
        v
    }

    fn check<D: Dim>() {
        let dp = 0.1;
        let x0 = block::<D>(8, dp);
        let k = WendlandC2::<D>::from_spacing(dp, 1.15).unwrap();
        let list = neighbor_list_cells::<D>(&x0, k.cutoff()).unwrap();
        let stored: Vec<f64> = pair_kernels::<D, _>(&x0, &list, &k)
            .iter()
            .map(|p| p.w(&k))
            .collect();
        let pairs = ReferenceWeights::<D>::Stored(&stored);
        let g = D::matrix_from_fn(|r, c| if r == c { 1.2 - 0.1 * r as f64 } else { 0.15 });
        let x: Vec<D::Vector> = x0
            .iter()
            .map(|&x| g * x + D::vector([0.3, 0.1, -0.2]))
            .collect();
        // Affine motion: the fit recovers G, and the indicator is zero (round-off only).
        let fit = affine_fit(&list, pairs, &x0, &x);
        for f in &fit {
            assert!(D::frobenius(*f - g) < 1e-10);
        }
        let e = disorder_indicator(&list, pairs, &x0, &x, &fit);
        assert!(DisorderStats::of(&e).max < 1e-12);
        // The same with the exact F supplied by a method.
        let e = disorder_indicator(&list, pairs, &x0, &x, &vec![g; x.len()]);
        assert!(DisorderStats::of(&e).max < 1e-12);
        // Zigzag: alternate particles displaced by ±0.2 dp along x; with F = I (a zero-energy
        // mode the method does not see) the indicator is O(0.1), far from round-off.
        let zig: Vec<D::Vector> = x0
            .iter()
            .enumerate()
            .map(|(i, &x)| x + D::vector([if i % 2 == 0 { 0.02 } else { -0.02 }, 0.0, 0.0]))
            .collect();
        let e = disorder_indicator(&list, pairs, &x0, &zig, &vec![D::identity(); x0.len()]);
        let s = DisorderStats::of(&e);
        assert!(s.max > 0.05 && s.mean > 0.02, "{s:?}");
        // The least-squares fit cannot absorb the zigzag either.
        let fit = affine_fit(&list, pairs, &x0, &zig);
        let e = disorder_indicator(&list, pairs, &x0, &zig, &fit);
        assert!(DisorderStats::of(&e).mean > 0.02);
        // The kernel evaluated pair by pair gives the stored weights' bits.
        let kernel = ReferenceWeights::Kernel(&k);
        let fit_k = affine_fit(&list, kernel, &x0, &zig);
        assert_eq!(fit_k, fit);
        assert_eq!(disorder_indicator(&list, kernel, &x0, &zig, &fit_k), e);
    }

    #[test]
    fn indicator_is_zero_for_affine_motion_and_large_for_zigzag() {
        check::<D2>();
        check::<D3>();
    }

    #[test]
    fn stats_use_nearest_rank_and_flag_nan() {
        let v: Vec<f64> = (1..=200).map(|i| i as f64).collect();
        let s = DisorderStats::of(&v);
        assert_eq!((s.max, s.p99, s.mean), (200.0, 198.0, 100.5));
        assert_eq!(DisorderStats::of(&[1.0, f64::NAN]).max, f64::INFINITY);
    }
}
