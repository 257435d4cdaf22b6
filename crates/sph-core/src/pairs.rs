//! Per-pair kernel data aligned with a [`NeighborList`]: distance, unit vector and `W′` (the
//! kernel value `W`, which few terms read, from the distance on demand: [`PairKernel::w`]).
//! A record is 32 bytes in 2D and 40 in 3D; storing `W` too made them 40 and 48, and the
//! UL sub-step, which rewrites and re-reads every record, measurably slower (docs/performance.md).
//! Total-Lagrangian methods compute it once in the reference configuration; updated-Lagrangian
//! methods after every neighbour rebuild and, by default, again in every acoustic sub-step
//! ([`PairSymmetry::fill`] computes each unordered pair once there).

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
    /// Radial derivative `W′(r_ij) ≤ 0`; `∇_i W_ij = W′ e_ij`.
    pub dw: f64,
}

impl<D: Dim> PairKernel<D> {
    /// All zero: the filler of a pair buffer before its data are computed.
    pub fn zero() -> Self {
        Self {
            e: D::zero(),
            r: 0.0,
            dw: 0.0,
        }
    }

    /// Kernel value `W(r_ij)` of `kernel` (the kernel the data were filled with) at the stored
    /// distance: the same bits as the `W` of [`Kernel::w_and_dw_dr`] there.
    #[inline(always)]
    pub fn w<K: Kernel>(&self, kernel: &K) -> f64 {
        kernel.w(self.r)
    }

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
    let mut out = vec![PairKernel::<D>::zero(); list.num_pairs()];
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
    crate::parallel::gather_slices(
        list.offsets(),
        out,
        #[inline(always)]
        |i, slots: &mut [PairKernel<D>]| {
            let xi = queries[i];
            let start = list.offsets()[i];
            let neighbours = &indices[start..start + slots.len()];
            for (slot, &j) in slots.iter_mut().zip(neighbours) {
                *slot = pair_kernel::<D, K>(xi - targets[j as usize], kernel);
            }
        },
    );
}

/// Kernel data of the pair whose separation is `d = x_i − x_j`: the one formula behind every
/// fill in this module, and behind every solver that recomputes pair data instead of storing
/// them (same bits as the stored data).
#[inline(always)]
pub fn pair_kernel<D: Dim, K: Kernel>(d: D::Vector, kernel: &K) -> PairKernel<D> {
    let r = D::norm(d);
    let e = if r > 0.0 { d / r } else { D::zero() };
    let dw = kernel.dw_dr(r);
    PairKernel { e, r, dw }
}

/// The data of the reversed pair `(j, i)` from that of `(i, j)`: the same `r`, `W′` and
/// `e_ji = −e_ij`. Bit for bit what [`pair_kernel`] gives for `−d` (IEEE subtraction, the
/// norm and the division are sign-symmetric); the zero vector of coincident particles stays
/// positive, as [`pair_kernel`] makes it.
#[inline(always)]
fn reversed<D: Dim>(p: PairKernel<D>) -> PairKernel<D> {
    PairKernel {
        e: if p.r > 0.0 { -p.e } else { D::zero() },
        ..p
    }
}

/// The two halves of a symmetric self list (`j` is a neighbour of `i` exactly when `i` is a
/// neighbour of `j`; rows in any order): the slots `(i, j ≥ i)`, whose kernel data are
/// computed, and the slots `(i, j < i)`, which receive the reversed data of their mirror
/// `(j, i)`. Built once per neighbour list in one pass over its pairs; [`Self::fill`] then
/// does the work of [`fill_pair_kernels`] with about half the square roots, divisions and
/// kernel evaluations, bit for bit the same result, in one parallel region: each task computes
/// its block of rows and copies the mirrors that lie in that block; a slot `(i, j < i)` whose
/// mirror lies in another task's block is computed too (the same bits as the copy), so no
/// serial pass follows the region (blocks hold 512–1,023 particles: a fifth of the pairs of
/// the UL 3D plate at H/dp 3 cross them, 5 % of the 2D plate's at H/dp 10).
///
/// # Example
/// ```
/// use sph_core::dim::{Dim, D2};
/// use sph_core::kernel::{Kernel, WendlandC2};
/// use sph_core::neighbor::CellGrid;
/// use sph_core::pairs::{pair_kernels, PairSymmetry};
///
/// let x: Vec<_> = (0..50).map(|k| D2::vector([(k % 7) as f64 * 0.1, (k / 7) as f64 * 0.1, 0.0])).collect();
/// let kernel = WendlandC2::<D2>::from_spacing(0.1, 1.3).unwrap();
/// let list = CellGrid::<D2>::build(&x, kernel.cutoff()).unwrap().neighbor_list(&x, kernel.cutoff()).unwrap();
/// let halves = PairSymmetry::new(&list).expect("a self list is symmetric");
/// let mut pairs = pair_kernels::<D2, _>(&x, &list, &kernel);
/// halves.fill(&x, &list, &kernel, &mut pairs);
/// assert_eq!(pairs, pair_kernels::<D2, _>(&x, &list, &kernel));
/// ```
#[derive(Clone, Debug, Default)]
pub struct PairSymmetry {
    /// `list.num_pairs()` of the list it was built from.
    pairs: usize,
    /// Row `i`'s computed slots are `upper[upper_start[i]..upper_start[i + 1]]`.
    upper_start: Vec<usize>,
    /// Slots `(i, j ≥ i)`, absolute, grouped by row.
    upper: Vec<u32>,
    /// Row `i`'s copies within its block are `local[local_start[i]..local_start[i + 1]]`.
    local_start: Vec<usize>,
    /// `(k, m)`: the slot `k` of `(i, j < i)` and the slot `m` of its mirror `(j, i)`, with `j`
    /// in the same block of [`crate::parallel::gather_blocks`] as `i`.
    local: Vec<(u32, u32)>,
    /// Row `i`'s slots `(i, j < i)` with `j` in another block are
    /// `cross[cross_start[i]..cross_start[i + 1]]` (computed, not copied).
    cross_start: Vec<usize>,
    /// Those slots, absolute, grouped by row.
    cross: Vec<u32>,
}

impl PairSymmetry {
    /// The halves of `list`, or `None` if the list is not symmetric or has more than
    /// `u32::MAX` pairs (then use [`fill_pair_kernels`]).
    pub fn new(list: &NeighborList) -> Option<Self> {
        let n = list.len();
        let pairs = list.num_pairs();
        u32::try_from(pairs).ok()?;
        let (offsets, indices) = (list.offsets(), list.indices());
        let mut upper_start = Vec::with_capacity(n + 1);
        let mut upper = Vec::with_capacity(pairs / 2 + n);
        let mut lower_start = vec![0usize; n + 1];
        upper_start.push(0);
        for i in 0..n {
            let mut below = 0;
            for k in list.range(i) {
                if indices[k] as usize >= i {
                    upper.push(k as u32);
                } else {
                    below += 1;
                }
            }
            upper_start.push(upper.len());
            lower_start[i + 1] = lower_start[i] + below;
        }
        // The transpose of the upper halves: walking the rows `j` in ascending order, each
        // upper slot `m = (j, i > j)` goes to row `i`'s bucket as `(j, m)`.
        let mut bucket = vec![(u32::MAX, u32::MAX); lower_start[n]];
        let mut fill = lower_start.clone();
        for j in 0..n {
            for &m in &upper[upper_start[j]..upper_start[j + 1]] {
                let i = indices[m as usize] as usize;
                if i > j {
                    let slot = fill[i];
                    if slot >= lower_start[i + 1] {
                        return None;
                    }
                    bucket[slot] = (j as u32, m);
                    fill[i] += 1;
                }
            }
        }
        // Match each bucket entry with row `i`'s slot of `j` (through `slot_of`, valid while
        // row `i` is scanned; a stale or consumed entry fails the range check).
        let mut slot_of = vec![u32::MAX; n];
        let mut local_start = Vec::with_capacity(n + 1);
        let mut local = Vec::with_capacity(lower_start[n]);
        let mut cross_start = Vec::with_capacity(n + 1);
        let mut cross = Vec::new();
        local_start.push(0);
        cross_start.push(0);
        let block: Vec<usize> = (0..n).map(|i| crate::parallel::block_of(n, i)).collect();
        for i in 0..n {
            if fill[i] != lower_start[i + 1] {
                return None;
            }
            for k in list.range(i) {
                let j = indices[k] as usize;
                if j < i {
                    slot_of[j] = k as u32;
                }
            }
            for &(j, m) in &bucket[lower_start[i]..lower_start[i + 1]] {
                let j = j as usize;
                let k = std::mem::replace(&mut slot_of[j], u32::MAX) as usize;
                if !(offsets[i]..offsets[i + 1]).contains(&k) || indices[k] as usize != j {
                    return None;
                }
                if block[j] == block[i] {
                    local.push((k as u32, m));
                } else {
                    cross.push(k as u32);
                }
            }
            local_start.push(local.len());
            cross_start.push(cross.len());
        }
        Some(Self {
            pairs,
            upper_start,
            upper,
            local_start,
            local,
            cross_start,
            cross,
        })
    }

    /// [`fill_pair_kernels`]`(positions, positions, list, kernel, out)` for the list these
    /// halves were built from, identical bits for any thread count.
    ///
    /// # Panics
    /// If `list` or `out` does not match the list the halves were built from in length.
    pub fn fill<D: Dim, K: Kernel>(
        &self,
        positions: &[D::Vector],
        list: &NeighborList,
        kernel: &K,
        out: &mut [PairKernel<D>],
    ) {
        assert_eq!(
            list.num_pairs(),
            self.pairs,
            "neighbour list of these halves"
        );
        assert_eq!(
            list.len() + 1,
            self.upper_start.len(),
            "particles of these halves"
        );
        assert_eq!(out.len(), self.pairs, "pair buffer length");
        let (offsets, indices) = (list.offsets(), list.indices());
        let x_j = list.values(positions);
        crate::parallel::gather_blocks(
            offsets,
            out,
            #[inline(always)]
            |rows: std::ops::Range<usize>, block: &mut [PairKernel<D>]| {
                let base = offsets[rows.start];
                for i in rows.clone() {
                    let xi = positions[i];
                    let upper = &self.upper[self.upper_start[i]..self.upper_start[i + 1]];
                    let cross = &self.cross[self.cross_start[i]..self.cross_start[i + 1]];
                    for &k in upper.iter().chain(cross) {
                        let j = indices[k as usize] as usize;
                        // SAFETY: `j` is an index of `list`, which made the view.
                        let x_j = unsafe { x_j.at(j) };
                        block[k as usize - base] = pair_kernel::<D, K>(xi - x_j, kernel);
                    }
                }
                for &(k, m) in &self.local[self.local_start[rows.start]..self.local_start[rows.end]]
                {
                    block[k as usize - base] = reversed(block[m as usize - base]);
                }
            },
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::{D2, D3};
    use crate::kernel::WendlandC2;
    use crate::neighbor::{neighbor_list_cells, CellGrid};

    /// A jittered lattice of `n` points per side (deterministic).
    fn cloud<D: Dim>(n: usize, dp: f64) -> Vec<D::Vector> {
        let layers = if D::D == 3 { n } else { 1 };
        let mut seed = 12345u64;
        let mut jitter = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.3 * dp
        };
        let mut v = Vec::new();
        for k in 0..layers {
            for j in 0..n {
                for i in 0..n {
                    let c = [i as f64 * dp, j as f64 * dp, k as f64 * dp];
                    v.push(D::vector([
                        c[0] + jitter(),
                        c[1] + jitter(),
                        c[2] + jitter(),
                    ]));
                }
            }
        }
        v
    }

    /// Exact text of every pair (Debug prints the shortest round-trip form, sign of zero
    /// included), so equal text is equal bits.
    fn bits<D: Dim>(p: &[PairKernel<D>]) -> Vec<String> {
        p.iter().map(|p| format!("{p:?}")).collect()
    }

    fn check<D: Dim>(n: usize) {
        let dp = 0.01;
        let x = cloud::<D>(n, dp);
        let kernel = WendlandC2::<D>::from_spacing(dp, 1.3).unwrap();
        let cutoff = kernel.cutoff();
        // The UL list (cell-scan row order) and the sorted TL list.
        let lists = [
            CellGrid::<D>::build(&x, cutoff)
                .unwrap()
                .neighbor_list(&x, cutoff)
                .unwrap(),
            neighbor_list_cells::<D>(&x, cutoff).unwrap(),
        ];
        for list in &lists {
            let halves = PairSymmetry::new(list).expect("symmetric");
            let expected = bits::<D>(&pair_kernels(&x, list, &kernel));
            for threads in [1, 2, 3] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let mut out = vec![
                    PairKernel::<D> {
                        e: D::zero(),
                        r: -1.0,
                        dw: 1.0
                    };
                    list.num_pairs()
                ];
                pool.install(|| halves.fill(&x, list, &kernel, &mut out));
                assert_eq!(
                    bits::<D>(&out),
                    expected,
                    "{} particles, {threads} threads",
                    x.len()
                );
            }
        }
    }

    #[test]
    fn symmetric_fill_is_bit_identical_to_the_plain_fill() {
        check::<D2>(5);
        check::<D2>(60); // 3,600 particles: both passes split over the pool
        check::<D3>(4);
        check::<D3>(13);
    }

    #[test]
    fn asymmetric_lists_have_no_halves() {
        // 0 → 1 without 1 → 0.
        let list = NeighborList::from_parts(vec![0, 1, 1], vec![1]).unwrap();
        assert!(PairSymmetry::new(&list).is_none());
        // 0 ↔ 1 and 0 → 2 only.
        let list = NeighborList::from_parts(vec![0, 2, 3, 3], vec![1, 2, 0]).unwrap();
        assert!(PairSymmetry::new(&list).is_none());
        // 2 → 0 only (the lower half without its upper).
        let list = NeighborList::from_parts(vec![0, 0, 0, 1], vec![0]).unwrap();
        assert!(PairSymmetry::new(&list).is_none());
        // A duplicated pair in both rows.
        let list = NeighborList::from_parts(vec![0, 2, 4], vec![1, 1, 0, 0]).unwrap();
        assert!(PairSymmetry::new(&list).is_none());
        // Symmetric, self pairs included.
        let list = NeighborList::from_parts(vec![0, 2, 4], vec![0, 1, 1, 0]).unwrap();
        assert!(PairSymmetry::new(&list).is_some());
    }

    #[test]
    #[should_panic(expected = "neighbour list of these halves")]
    fn halves_refuse_another_list() {
        let a = NeighborList::from_parts(vec![0, 1, 2], vec![1, 0]).unwrap();
        let b = NeighborList::from_parts(vec![0, 0, 0], vec![]).unwrap();
        let halves = PairSymmetry::new(&a).unwrap();
        let x = [D2::vector([0.0; 3]), D2::vector([0.01, 0.0, 0.0])];
        let kernel = WendlandC2::<D2>::from_spacing(0.01, 1.3).unwrap();
        halves.fill::<D2, _>(&x, &b, &kernel, &mut []);
    }
}
