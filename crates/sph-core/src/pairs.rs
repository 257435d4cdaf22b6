//! Per-pair kernel data aligned with a [`NeighborList`]: distance, unit vector, `W` and `W′`.
//! Total-Lagrangian methods compute it once in the reference configuration; updated-Lagrangian
//! methods once per neighbour rebuild (frozen over the acoustic sub-steps).

use crate::dim::Dim;
use crate::kernel::Kernel;
use crate::neighbor::NeighborList;

/// Kernel data of one directed pair `(i, j)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairKernel<D: Dim> {
    /// Unit vector `e_ij = (x_i − x_j)/r_ij`, pointing from `j` to `i` (zero if `r_ij = 0`).
    pub e: D::Vector,
    /// Distance `r_ij`.
    pub r: f64,
    /// Kernel value `W(r_ij)`.
    pub w: f64,
    /// Radial derivative `W′(r_ij) ≤ 0`; `∇_i W_ij = W′ e_ij`.
    pub dw: f64,
}

impl<D: Dim> PairKernel<D> {
    /// Kernel gradient `∇_i W_ij = W′(r_ij) e_ij`.
    #[inline(always)]
    pub fn grad(&self) -> D::Vector {
        self.e * self.dw
    }
}

/// Kernel data of every pair of `list` (query `i`, neighbour `j`, both in `positions`), in the
/// order of [`NeighborList::indices`].
pub fn pair_kernels<D: Dim, K: Kernel>(
    positions: &[D::Vector],
    list: &NeighborList,
    kernel: &K,
) -> Vec<PairKernel<D>> {
    pair_kernels_between(positions, positions, list, kernel)
}

/// Kernel data of every pair of a contact list (`i` in `queries`, `j` in `targets`).
pub fn pair_kernels_between<D: Dim, K: Kernel>(
    queries: &[D::Vector],
    targets: &[D::Vector],
    list: &NeighborList,
    kernel: &K,
) -> Vec<PairKernel<D>> {
    let mut out = vec![
        PairKernel::<D> {
            e: D::zero(),
            r: 0.0,
            w: 0.0,
            dw: 0.0
        };
        list.num_pairs()
    ];
    fill_pair_kernels(queries, targets, list, kernel, &mut out);
    out
}

/// Recomputes pair data into an existing buffer of length `list.num_pairs()` (no allocation).
pub fn fill_pair_kernels<D: Dim, K: Kernel>(
    queries: &[D::Vector],
    targets: &[D::Vector],
    list: &NeighborList,
    kernel: &K,
    out: &mut [PairKernel<D>],
) {
    assert_eq!(out.len(), list.num_pairs(), "pair buffer length");
    let indices = list.indices();
    crate::parallel::gather_slices(list.offsets(), out, &|i, slots: &mut [PairKernel<D>]| {
        let xi = queries[i];
        let start = list.offsets()[i];
        let neighbours = &indices[start..start + slots.len()];
        for (slot, &j) in slots.iter_mut().zip(neighbours) {
            let d = xi - targets[j as usize];
            let r = D::norm(d);
            let e = if r > 0.0 { d / r } else { D::zero() };
            let (w, dw) = kernel.w_and_dw_dr(r);
            *slot = PairKernel { e, r, w, dw };
        }
    });
}
