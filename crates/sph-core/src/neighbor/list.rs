//! The compressed neighbour list ([`NeighborList`]) and the unchecked reads through its
//! indices ([`NeighbourValues`]).

use crate::error::Error;
use rayon::prelude::*;

/// A compressed sparse-row neighbour list: the neighbours of query particle `i` are
/// `indices[offsets[i]..offsets[i + 1]]` (sorted ascending in the canonical lists, in cell-scan
/// order from [`super::CellGrid::neighbor_list`]). For a contact list the indices refer
/// to the other point set.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct NeighborList {
    offsets: Vec<usize>,
    indices: Vec<u32>,
    /// One more than the largest index (0 when there is none): every index is below it. Set
    /// wherever a list is made (the fields are private), read by [`NeighborList::values`].
    index_bound: usize,
}

impl NeighborList {
    /// Builds a list from CSR parts, checking that offsets start at 0, never decrease and end at
    /// `indices.len()`.
    pub fn from_parts(offsets: Vec<usize>, indices: Vec<u32>) -> Result<Self, Error> {
        let ok = offsets.first() == Some(&0)
            && offsets.windows(2).all(|w| w[0] <= w[1])
            && offsets.last() == Some(&indices.len());
        if !ok {
            return Err(Error::invalid(
                "neighbor_offsets",
                "malformed",
                "starting at 0, non-decreasing, ending at indices.len()",
            ));
        }
        Ok(Self::new(offsets, indices))
    }

    /// The list of valid CSR parts, with its index bound.
    fn new(offsets: Vec<usize>, indices: Vec<u32>) -> Self {
        let index_bound = indices.iter().max().map_or(0, |&m| m as usize + 1);
        Self {
            offsets,
            indices,
            index_bound,
        }
    }

    /// One more than the largest neighbour index (0 for a list without pairs): the smallest
    /// length of an array that every index of the list may address.
    pub fn index_bound(&self) -> usize {
        self.index_bound
    }

    /// `values` (one per particle that the list's indices address) for reads at the list's
    /// neighbour indices without a bounds check per read ([`NeighbourValues::at`]); the one
    /// check is here.
    ///
    /// # Panics
    /// If `values` is shorter than [`NeighborList::index_bound`].
    ///
    /// ```
    /// use sph_core::NeighborList;
    /// let list = NeighborList::from_parts(vec![0, 1, 2], vec![1, 0]).unwrap();
    /// let mass = [2.0, 3.0];
    /// let m = list.values(&mass);
    /// // Safety: `j` is an index of `list`.
    /// let of_0: f64 = list.neighbors(0).iter().map(|&j| unsafe { m.at(j as usize) }).sum();
    /// assert_eq!(of_0, 3.0);
    /// ```
    #[inline]
    pub fn values<'a, T: Copy>(&self, values: &'a [T]) -> NeighbourValues<'a, T> {
        assert!(
            values.len() >= self.index_bound,
            "{} values for a neighbour list with indices up to {}",
            values.len(),
            self.index_bound.saturating_sub(1)
        );
        NeighbourValues { values }
    }

    /// Number of query particles.
    #[inline]
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Whether the list has no query particles.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Neighbours of query particle `i`, in the row's order.
    #[inline(always)]
    pub fn neighbors(&self, i: usize) -> &[u32] {
        &self.indices[self.offsets[i]..self.offsets[i + 1]]
    }

    /// The range of pair slots belonging to particle `i` (for arrays of per-pair data aligned
    /// with [`NeighborList::indices`]).
    #[inline(always)]
    pub fn range(&self, i: usize) -> std::ops::Range<usize> {
        self.offsets[i]..self.offsets[i + 1]
    }

    /// CSR offsets (`len() + 1` entries).
    pub fn offsets(&self) -> &[usize] {
        &self.offsets
    }

    /// CSR neighbour indices.
    pub fn indices(&self) -> &[u32] {
        &self.indices
    }

    /// Total number of (directed) pairs.
    pub fn num_pairs(&self) -> usize {
        self.indices.len()
    }

    /// Number of neighbours of `i`.
    #[inline]
    pub fn count(&self, i: usize) -> usize {
        self.offsets[i + 1] - self.offsets[i]
    }

    /// Smallest neighbour count (0 for an empty list).
    pub fn min_count(&self) -> usize {
        (0..self.len()).map(|i| self.count(i)).min().unwrap_or(0)
    }

    /// Largest neighbour count (0 for an empty list).
    pub fn max_count(&self) -> usize {
        (0..self.len()).map(|i| self.count(i)).max().unwrap_or(0)
    }

    /// Connected components of the neighbour graph (`i` and `j` joined when `j` is a neighbour of
    /// `i`): a label per point, `0..count` in order of each component's first point, and the
    /// count. A body that breaks into pieces (numerical fracture) has more than one component.
    pub fn components(&self) -> (Vec<u32>, usize) {
        let n = self.len();
        let mut parent: Vec<u32> = (0..n as u32).collect();
        fn root(parent: &mut [u32], mut i: u32) -> u32 {
            while parent[i as usize] != i {
                let p = parent[i as usize];
                parent[i as usize] = parent[p as usize];
                i = p;
            }
            i
        }
        for i in 0..n {
            for &j in self.neighbors(i) {
                let (a, b) = (root(&mut parent, i as u32), root(&mut parent, j));
                if a != b {
                    parent[a.max(b) as usize] = a.min(b);
                }
            }
        }
        let mut label = vec![u32::MAX; n];
        let mut count = 0u32;
        let mut out = vec![0u32; n];
        for i in 0..n {
            let r = root(&mut parent, i as u32) as usize;
            if label[r] == u32::MAX {
                label[r] = count;
                count += 1;
            }
            out[i] = label[r];
        }
        (out, count as usize)
    }

    /// Concatenates per-block results (counts and indices per block, in block order).
    /// Sorts every row ascending (the canonical order, in parallel over rows).
    pub fn sort_rows(&mut self) {
        let mut rows: Vec<&mut [u32]> = Vec::with_capacity(self.len());
        let mut rest: &mut [u32] = &mut self.indices;
        for w in self.offsets.windows(2) {
            let (row, tail) = std::mem::take(&mut rest).split_at_mut(w[1] - w[0]);
            rows.push(row);
            rest = tail;
        }
        rows.par_iter_mut().for_each(|r| r.sort_unstable());
    }

    pub(super) fn from_blocks(n: usize, blocks: Vec<(Vec<u32>, Vec<u32>)>) -> Self {
        let total: usize = blocks.iter().map(|b| b.1.len()).sum();
        let mut offsets = Vec::with_capacity(n + 1);
        let mut indices = Vec::with_capacity(total);
        offsets.push(0);
        for (counts, idx) in blocks {
            for c in counts {
                offsets.push(offsets.last().unwrap() + c as usize);
            }
            indices.extend_from_slice(&idx);
        }
        debug_assert_eq!(offsets.len(), n + 1);
        Self::new(offsets, indices)
    }
}

/// Per-particle values read at the neighbour indices of the list that made them
/// ([`NeighborList::values`]), without the bounds check of `values[j]` in the inner loop of
/// a pair pass (5–9 % of the instructions of a UL, TL or MPS run; docs/performance.md).
#[derive(Debug)]
pub struct NeighbourValues<'a, T> {
    values: &'a [T],
}

impl<T> Clone for NeighbourValues<'_, T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for NeighbourValues<'_, T> {}

impl<T: Copy> NeighbourValues<'_, T> {
    /// The value of particle `j`.
    ///
    /// # Safety
    /// `j` is a neighbour index of the list these values were made for (every such index is
    /// below its [`NeighborList::index_bound`], which [`NeighborList::values`] checked), or
    /// otherwise below the length of the values.
    #[inline(always)]
    pub unsafe fn at(&self, j: usize) -> T {
        debug_assert!(j < self.values.len(), "neighbour index {j} out of range");
        // SAFETY: j < values.len() by the caller's contract.
        unsafe { *self.values.get_unchecked(j) }
    }

    /// The value of particle `j` by reference (for a vector load of it).
    ///
    /// # Safety
    /// As [`NeighbourValues::at`].
    #[inline(always)]
    pub unsafe fn get(&self, j: usize) -> &T {
        debug_assert!(j < self.values.len(), "neighbour index {j} out of range");
        // SAFETY: j < values.len() by the caller's contract.
        unsafe { self.values.get_unchecked(j) }
    }
}
