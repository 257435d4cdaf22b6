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
use crate::parallel::Columns;

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
/// `(j, i)`. Built once per neighbour list, block by block in parallel (built serially for
/// the whole list it was 3 % of the UL plate's time on one thread, and the other thread
/// parked meanwhile); [`Self::fill`] then does the work of [`fill_pair_kernels`] with about
/// half the square roots, divisions and kernel evaluations, bit for bit the same result, in
/// one parallel region: each task computes its block of rows and copies the mirrors that lie
/// in that block; a slot `(i, j < i)` whose mirror lies in another block is computed too (the
/// same bits as the copy), so no serial pass follows the region. The blocks are those of
/// [`crate::parallel::blocks`] (512–1,023 particles): a fifth of the pairs of the UL 3D plate
/// at H/dp 3 cross them, 5 % of the 2D plate's at H/dp 10.
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
    /// `list.len()` of that list.
    particles: usize,
    /// One entry per block of [`crate::parallel::blocks`], in order.
    blocks: Vec<BlockHalves>,
}

/// The halves of one block of rows; slots are counted from the block's first slot.
#[derive(Clone, Debug, Default)]
struct BlockHalves {
    /// The block's rows.
    rows: std::ops::Range<usize>,
    /// Row `rows.start + r`'s computed slots are `computed[starts[r]..starts[r + 1]]`.
    starts: Vec<u32>,
    /// The computed slots, grouped by row: `(i, j ≥ i)`, and `(i, j < i)` with `j` in
    /// another block.
    computed: Vec<u32>,
    /// `(k, m)`: the slot `k` of `(i, j < i)` with `j` in this block and the slot `m` of its
    /// mirror `(j, i)`, a computed slot of row `j`.
    copies: Vec<(u32, u32)>,
}

impl BlockHalves {
    /// The halves of `rows` of `list`, or `None` if a pair of two particles of `rows` lacks
    /// its mirror or has it twice. Three passes: the block's slots split into computed ones
    /// and copies, row by row; the transpose of the computed slots `m = (j, i > j)` with `i`
    /// in the block (each goes to row `i`'s bucket as `(j, m)`); the match of each bucket
    /// entry with row `i`'s copy slot of `j`.
    #[inline(always)]
    fn new(list: &NeighborList, rows: std::ops::Range<usize>) -> Option<Self> {
        let (indices, base) = (list.indices(), list.offsets()[rows.start]);
        let (lo, hi) = (rows.start, rows.end);
        let slots = list.offsets()[hi] - base;
        let mut starts = Vec::with_capacity(rows.len() + 1);
        let mut lower_start = Vec::with_capacity(rows.len() + 1);
        let (mut computed, mut lower) = (vec![0u32; slots], vec![0u32; slots]);
        starts.push(0);
        lower_start.push(0);
        // Without branches: whether `j < i` lies in the block (a copy) is a coin toss per pair.
        let (mut c, mut l) = (0, 0);
        for i in rows.clone() {
            for k in list.range(i) {
                let j = indices[k] as usize;
                let copy = (lo..i).contains(&j);
                computed[c] = (k - base) as u32;
                lower[l] = (k - base) as u32;
                c += usize::from(!copy);
                l += usize::from(copy);
            }
            starts.push(c as u32);
            lower_start.push(l);
        }
        computed.truncate(c);
        lower.truncate(l);
        let slot = &indices[base..];
        let mut bucket = vec![(0u32, 0u32); l];
        let mut fill = lower_start.clone();
        for (r, j) in rows.clone().enumerate() {
            for &m in &computed[starts[r] as usize..starts[r + 1] as usize] {
                let i = slot[m as usize] as usize;
                if i > j && i < hi {
                    let at = fill[i - lo];
                    if at >= lower_start[i - lo + 1] {
                        return None;
                    }
                    bucket[at] = (j as u32, m);
                    fill[i - lo] += 1;
                }
            }
        }
        // Row `i`'s copy slot of each `j < i` of the block while row `i` is matched. Each
        // bucket entry consumes one; as many entries as copy slots, so a row with a doubled or
        // a missing mirror meets a consumed entry, and a row that matches leaves none behind.
        let mut slot_of = vec![u32::MAX; rows.len()];
        let mut copies = Vec::with_capacity(l);
        for r in 0..rows.len() {
            if fill[r] != lower_start[r + 1] {
                return None;
            }
            let own = &lower[lower_start[r]..lower_start[r + 1]];
            for &k in own {
                slot_of[slot[k as usize] as usize - lo] = k;
            }
            for &(j, m) in &bucket[lower_start[r]..lower_start[r + 1]] {
                let k = std::mem::replace(&mut slot_of[j as usize - lo], u32::MAX);
                if k == u32::MAX {
                    return None;
                }
                copies.push((k, m));
            }
        }
        Some(Self {
            rows,
            starts,
            computed,
            copies,
        })
    }
}

impl PairSymmetry {
    /// The halves of `list`, or `None` if the list is not symmetric within a block (a pair of
    /// two particles of one block whose mirror is missing or doubled; a pair between blocks is
    /// computed on both sides and needs no mirror) or has more than `u32::MAX` pairs (then use
    /// [`fill_pair_kernels`]).
    pub fn new(list: &NeighborList) -> Option<Self> {
        let pairs = list.num_pairs();
        u32::try_from(pairs).ok()?;
        let halves = crate::parallel::map_blocks(
            list.len(),
            #[inline(always)]
            |rows| BlockHalves::new(list, rows),
        );
        Some(Self {
            pairs,
            particles: list.len(),
            blocks: halves.into_iter().collect::<Option<_>>()?,
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
        self.fill_blocks(
            positions,
            list,
            kernel,
            out,
            #[inline(always)]
            |_, _| {},
        );
    }

    /// [`Self::fill`], and in the same task, as soon as a block of rows is filled,
    /// `then(rows, pairs, part)`: `pairs` the block's pair data (row `i`'s slots start at
    /// `list.offsets()[i] − list.offsets()[rows.start]`), `part` the block's rows of `columns`
    /// ([`Columns`]). A block's pair data are complete once its own task has filled them (a
    /// mirror is copied only within its block), so a gather that reads its rows' pair data right
    /// after the refresh (the UL force gather) runs in the refresh's parallel region: one
    /// hand-off fewer, and each block's pairs are read while they are still in the cache. The
    /// blocks are those of [`crate::parallel::blocks`]; `then` should be an `#[inline(always)]`
    /// closure (see [`crate::wide::dispatch`]).
    ///
    /// # Panics
    /// As [`Self::fill`]; if a column is neither `list.len()` long nor empty.
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
    /// let halves = PairSymmetry::new(&list).unwrap();
    /// let mut pairs = pair_kernels::<D2, _>(&x, &list, &kernel);
    /// // The kernel-gradient sum of each particle, in the refresh's parallel region.
    /// let mut grad_sum = vec![D2::zero(); x.len()];
    /// let offsets = list.offsets();
    /// halves.fill_then(&x, &list, &kernel, &mut pairs, (&mut grad_sum[..],), |rows, block, (g,)| {
    ///     let base = offsets[rows.start];
    ///     for (k, i) in rows.enumerate() {
    ///         g[k] = block[offsets[i] - base..offsets[i + 1] - base].iter().map(|p| p.grad()).sum();
    ///     }
    /// });
    /// assert_eq!(grad_sum[3], pairs[list.range(3)].iter().map(|p| p.grad()).sum());
    /// ```
    pub fn fill_then<'a, D: Dim, K: Kernel, C: Columns<'a>>(
        &self,
        positions: &[D::Vector],
        list: &NeighborList,
        kernel: &K,
        out: &mut [PairKernel<D>],
        columns: C,
        then: impl Fn(std::ops::Range<usize>, &[PairKernel<D>], C::Part) + Sync,
    ) {
        let shared = columns.share(list.len());
        self.fill_blocks(
            positions,
            list,
            kernel,
            out,
            #[inline(always)]
            |rows, block| {
                // SAFETY: the blocks are disjoint row ranges within `0..list.len()`, each
                // handed to one task.
                let part = unsafe { C::part(&shared, rows.clone()) };
                then(rows, block, part)
            },
        );
    }

    /// The fill of [`Self::fill`], calling `after(rows, block)` in each block's task once the
    /// block is filled.
    #[inline(always)]
    fn fill_blocks<D: Dim, K: Kernel>(
        &self,
        positions: &[D::Vector],
        list: &NeighborList,
        kernel: &K,
        out: &mut [PairKernel<D>],
        after: impl Fn(std::ops::Range<usize>, &[PairKernel<D>]) + Sync,
    ) {
        assert_eq!(
            list.num_pairs(),
            self.pairs,
            "neighbour list of these halves"
        );
        assert_eq!(list.len(), self.particles, "particles of these halves");
        assert_eq!(out.len(), self.pairs, "pair buffer length");
        let indices = list.indices();
        let x_j = list.values(positions);
        crate::parallel::gather_blocks(
            list.offsets(),
            out,
            #[inline(always)]
            |rows: std::ops::Range<usize>, block: &mut [PairKernel<D>]| {
                let at = self.blocks.partition_point(|b| b.rows.end <= rows.start);
                let halves = &self.blocks[at];
                assert_eq!(halves.rows, rows, "blocks of these halves");
                let slot = &indices[list.offsets()[rows.start]..];
                // Local copies: the compiler then keeps the kernel's constants and the view's
                // base in registers instead of reloading them for every pair.
                let (kernel, x_j) = (*kernel, x_j);
                for (r, i) in rows.clone().enumerate() {
                    let xi = positions[i];
                    let (from, to) = (halves.starts[r] as usize, halves.starts[r + 1] as usize);
                    for &k in &halves.computed[from..to] {
                        let j = slot[k as usize] as usize;
                        // SAFETY: `j` is an index of `list`, which made the view.
                        let x_j = unsafe { x_j.at(j) };
                        block[k as usize] = pair_kernel::<D, K>(xi - x_j, &kernel);
                    }
                }
                for &(k, m) in &halves.copies {
                    block[k as usize] = reversed(block[m as usize]);
                }
                after(rows, block);
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
            let expected_pairs = pair_kernels(&x, list, &kernel);
            let expected = bits::<D>(&expected_pairs);
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
                // The same fill with a gather of each block's rows in its task: every row
                // seen once, with its complete pair data.
                out.iter_mut().for_each(|p| p.r = -1.0);
                let offsets = list.offsets();
                let mut seen = vec![0usize; x.len()];
                let mut radii = vec![0.0; x.len()];
                pool.install(|| {
                    halves.fill_then(
                        &x,
                        list,
                        &kernel,
                        &mut out,
                        (&mut seen[..], &mut radii[..]),
                        |rows, block, (seen, radii)| {
                            let base = offsets[rows.start];
                            for (k, i) in rows.enumerate() {
                                seen[k] += 1;
                                let row = &block[offsets[i] - base..offsets[i + 1] - base];
                                radii[k] = row.iter().map(|p| p.r).sum();
                            }
                        },
                    )
                });
                assert_eq!(bits::<D>(&out), expected, "fill_then, {threads} threads");
                assert!(seen.iter().all(|&s| s == 1), "{threads} threads");
                for (i, &sum) in radii.iter().enumerate() {
                    let want: f64 = expected_pairs[list.range(i)].iter().map(|p| p.r).sum();
                    assert_eq!(sum.to_bits(), want.to_bits(), "row {i}, {threads} threads");
                }
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
    fn asymmetric_lists_have_no_halves_and_symmetric_ones_fill_as_the_plain_fill() {
        let x = [
            D2::vector([0.0; 3]),
            D2::vector([0.011, 0.002, 0.0]),
            D2::vector([-0.004, 0.013, 0.0]),
        ];
        let kernel = WendlandC2::<D2>::from_spacing(0.01, 1.3).unwrap();
        let build = |offsets: Vec<usize>, indices: Vec<u32>| {
            let list = NeighborList::from_parts(offsets, indices).unwrap();
            PairSymmetry::new(&list).map(|halves| {
                let mut out = vec![
                    PairKernel::<D2> {
                        e: D2::zero(),
                        r: -1.0,
                        dw: 1.0
                    };
                    list.num_pairs()
                ];
                halves.fill(&x, &list, &kernel, &mut out);
                assert_eq!(
                    bits::<D2>(&out),
                    bits::<D2>(&pair_kernels(&x, &list, &kernel))
                );
            })
        };
        // 0 → 1 without 1 → 0.
        assert!(build(vec![0, 1, 1, 1], vec![1]).is_none());
        // 0 ↔ 1 and 0 → 2 only.
        assert!(build(vec![0, 2, 3, 3], vec![1, 2, 0]).is_none());
        // 2 → 0 only (the lower half without its upper).
        assert!(build(vec![0, 0, 0, 1], vec![0]).is_none());
        // A duplicated pair in both rows.
        assert!(build(vec![0, 2, 4, 4], vec![1, 1, 0, 0]).is_none());
        // Symmetric, self pairs included, rows in any order.
        assert!(build(vec![0, 3, 5, 7], vec![2, 0, 1, 1, 0, 0, 2]).is_some());
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
