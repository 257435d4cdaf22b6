//! Neighbour search: a counting-sort cell-linked list (the workhorse) and a kiddo kd-tree (probes,
//! irregular sets, cross-checks), both producing the same compressed neighbour list
//! ([`NeighborList`], CSR: offsets + indices).
//!
//! Neighbours of `i` are the particles `j ≠ i` with `|x_i − x_j|² < cutoff²`, where the squared
//! distance is always computed by [`distance_squared`], so the two searches return identical
//! sets, including for points exactly at the cut-off (excluded by both). The canonical lists
//! ([`neighbor_list_cells`], [`neighbor_list_kdtree`]) sort each particle's neighbours by index:
//! equal sets give equal lists. [`CellGrid::neighbor_list`] leaves them in cell-scan order (a
//! deterministic function of the positions; the solvers' lists).
//!
//! Lists are built in parallel over fixed blocks of query particles and concatenated in block
//! order, so the result does not depend on the thread schedule.

use crate::dim::Dim;
use crate::error::{check_positive, Error};
use rayon::prelude::*;

mod list;
pub use list::{NeighborList, NeighbourValues};

/// Query particles per parallel work item. Fixed (not derived from the thread count) so the
/// output is identical for every number of threads.
const BLOCK: usize = 256;

/// Squared distance between two points: the one definition both searches use.
#[inline(always)]
pub fn distance_squared<D: Dim>(a: D::Vector, b: D::Vector) -> f64 {
    D::norm_squared(a - b)
}

/// Neighbour rows of a fixed point set, read one particle at a time: a stored
/// [`NeighborList`], or a search on demand ([`GridNeighbours`]) that holds no list at all. What
/// a domain decomposition needs of the neighbours ([`crate::decomposition`]).
pub trait Neighbours: Sync {
    /// Number of particles.
    fn len(&self) -> usize;

    /// Whether there are no particles.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Calls `f(j)` for each neighbour `j` of particle `i`, in the row's order.
    fn for_each_neighbour(&self, i: usize, f: impl FnMut(u32));

    /// The number of neighbours of particle `i`.
    fn neighbour_count(&self, i: usize) -> usize {
        let mut c = 0;
        self.for_each_neighbour(i, |_| c += 1);
        c
    }
}

impl Neighbours for NeighborList {
    fn len(&self) -> usize {
        NeighborList::len(self)
    }

    fn for_each_neighbour(&self, i: usize, f: impl FnMut(u32)) {
        self.neighbors(i).iter().copied().for_each(f);
    }

    fn neighbour_count(&self, i: usize) -> usize {
        self.count(i)
    }
}

/// The neighbour count of every particle of `list` (in parallel, fixed blocks).
pub fn neighbour_counts(list: &impl Neighbours) -> Vec<u32> {
    (0..list.len())
        .into_par_iter()
        .with_min_len(BLOCK)
        .map(|i| list.neighbour_count(i) as u32)
        .collect()
}

/// The neighbour rows of the points a [`CellGrid`] was built from, searched when asked for:
/// row `i` is exactly row `i` of [`CellGrid::neighbor_list`] (same neighbours, same order),
/// without the list's memory. A rank of a distributed run uses it to find its halo and to
/// build the rows of its own particles only.
pub struct GridNeighbours<'a, D: Dim> {
    grid: &'a CellGrid<D>,
    positions: &'a [D::Vector],
    cutoff: f64,
}

impl<'a, D: Dim> GridNeighbours<'a, D> {
    /// The rows of `positions` (the points `grid` was built from) within `cutoff`.
    ///
    /// # Errors
    /// `cutoff` not positive or larger than the grid's cell size, or `positions` of another
    /// length than the grid's.
    pub fn new(
        grid: &'a CellGrid<D>,
        positions: &'a [D::Vector],
        cutoff: f64,
    ) -> Result<Self, Error> {
        grid.check_query("positions", positions.len(), cutoff)?;
        Ok(Self {
            grid,
            positions,
            cutoff,
        })
    }

    /// The first particle that coincides with one of its neighbours, if any (a zero distance:
    /// no kernel gradient can be formed).
    pub fn first_coincident(&self) -> Option<usize> {
        (0..self.positions.len())
            .into_par_iter()
            .with_min_len(BLOCK)
            .find_first(|&i| {
                let xi = self.positions[i];
                let mut hit = false;
                self.for_each_neighbour(i, |j| {
                    hit |= distance_squared::<D>(xi, self.positions[j as usize]) == 0.0;
                });
                hit
            })
    }
}

impl<D: Dim> Neighbours for GridNeighbours<'_, D> {
    fn len(&self) -> usize {
        self.positions.len()
    }

    fn for_each_neighbour(&self, i: usize, mut f: impl FnMut(u32)) {
        let xi = self.positions[i];
        let rc2 = self.cutoff * self.cutoff;
        self.grid.for_each_candidate_at(xi, |j, xj| {
            if j as usize != i && distance_squared::<D>(xi, xj) < rc2 {
                f(j);
            }
        });
    }
}

fn check_finite<D: Dim>(positions: &[D::Vector]) -> Result<(), Error> {
    match positions.iter().position(|&x| !D::is_finite(x)) {
        None => Ok(()),
        Some(i) => Err(Error::NonFinite {
            field: "position".into(),
            particle: i,
            step: 0,
            time: 0.0,
        }),
    }
}

/// A uniform grid of cells (edge = the cut-off) with the particles sorted by cell. Cells are
/// ordered `(z, y, x)` lexicographically, so the three cells adjacent along x hold a
/// contiguous run of sorted particles.
///
/// Two layouts, the same lists: **dense** (every cell of the bounding box numbered
/// `x + nx (y + ny z)`, a counting sort) while the box needs at most `4 n + 4096` cells, and
/// **sparse** (only the occupied cells, found by binary search) when it would need more — a
/// fragment or a blown-up particle flying far away. Both scan the same cells in the same order,
/// so a neighbour list is bit for bit the same in either; the sparse one keeps the cell edge at
/// the cut-off, where enlarging the cells would make the search quadratic.
#[derive(Clone, Debug)]
pub struct CellGrid<D: Dim> {
    origin: D::Vector,
    cell_size: f64,
    inv_cell: f64,
    /// Dense layout: cells per axis (1 for unused axes). Sparse layout: unused (`[0; 3]`).
    dims: [usize; 3],
    /// `cell_start[c]..cell_start[c + 1]` indexes `sorted` for cell `c` (dense: the cell
    /// number; sparse: the position of the cell in `occupied`).
    cell_start: Vec<u32>,
    /// Which layout.
    sparse: bool,
    /// Sparse layout: the occupied cells' coordinates `[z, y, x]`, ascending. Dense: empty.
    occupied: Vec<[i64; 3]>,
    /// Particle indices in cell order (the permutation `new → old`).
    sorted: Vec<u32>,
    /// Positions in cell order (`sorted_pos[k] = positions[sorted[k]]`), so the candidate scan
    /// reads memory contiguously whatever the particles' own order.
    sorted_pos: Vec<D::Vector>,
}

/// Largest number of cells of the dense layout relative to the particle count; a bounding box
/// that would need more (a particle flying far away, a sparse scene) takes the sparse layout.
fn max_cells(n: usize) -> usize {
    4 * n + 4096
}

impl<D: Dim> CellGrid<D> {
    /// Sorts `positions` into cells of edge `cell_size` (the dense layout, or the sparse one
    /// when the bounding box would need more than `4 n + 4096` cells). Errors on a
    /// non-positive cell size or non-finite positions.
    pub fn build(positions: &[D::Vector], cell_size: f64) -> Result<Self, Error> {
        Self::build_as(positions, cell_size, false)
    }

    /// [`Self::build`] in the sparse layout whatever the bounding box (for tests and
    /// comparisons: the lists are the dense layout's, bit for bit).
    pub fn build_sparse(positions: &[D::Vector], cell_size: f64) -> Result<Self, Error> {
        Self::build_as(positions, cell_size, true)
    }

    fn build_as(positions: &[D::Vector], cell_size: f64, sparse: bool) -> Result<Self, Error> {
        check_positive("cell_size", cell_size)?;
        check_finite::<D>(positions)?;
        let n = positions.len();
        if n > u32::MAX as usize {
            return Err(Error::invalid("particles", n, "< 2^32"));
        }
        let mut lo = [0.0f64; 3];
        let mut hi = [0.0f64; 3];
        if let Some(&first) = positions.first() {
            for k in 0..D::D {
                lo[k] = D::component(first, k);
                hi[k] = lo[k];
            }
            for &x in positions {
                for k in 0..D::D {
                    let v = D::component(x, k);
                    lo[k] = lo[k].min(v);
                    hi[k] = hi[k].max(v);
                }
            }
        }
        let mut dims = [1usize; 3];
        let mut total = 1.0f64;
        for k in 0..D::D {
            let d = ((hi[k] - lo[k]) / cell_size).floor() + 1.0;
            total *= d;
            dims[k] = d as usize;
        }
        let sparse = sparse || total > max_cells(n) as f64;
        let mut origin = D::zero();
        for k in 0..D::D {
            D::set_component(&mut origin, k, lo[k]);
        }
        let mut grid = Self {
            origin,
            cell_size,
            inv_cell: 1.0 / cell_size,
            dims: if sparse { [0; 3] } else { dims },
            cell_start: Vec::new(),
            sparse,
            occupied: Vec::new(),
            sorted: Vec::new(),
            sorted_pos: Vec::new(),
        };
        if sparse {
            grid.sort_sparse(positions);
        } else {
            grid.sort_dense(positions);
        }
        grid.sorted_pos = grid.sorted.iter().map(|&i| positions[i as usize]).collect();
        Ok(grid)
    }

    /// Counting sort into the dense cells: cell of each particle, counts, prefix sum, stable
    /// scatter.
    fn sort_dense(&mut self, positions: &[D::Vector]) {
        let n = positions.len();
        let ncell = self.dims[0] * self.dims[1] * self.dims[2];
        let mut cell_of = vec![0u32; n];
        crate::parallel::gather(
            &mut cell_of,
            #[inline(always)]
            |i, c| *c = self.cell_index(positions[i]) as u32,
        );
        let mut start = vec![0u32; ncell + 1];
        for &c in &cell_of {
            start[c as usize + 1] += 1;
        }
        for c in 0..ncell {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut sorted = vec![0u32; n];
        for (i, &c) in cell_of.iter().enumerate() {
            let slot = &mut fill[c as usize];
            sorted[*slot as usize] = i as u32;
            *slot += 1;
        }
        self.cell_start = start;
        self.sorted = sorted;
    }

    /// Sort by (cell, index) into the occupied cells: the dense layout's order.
    fn sort_sparse(&mut self, positions: &[D::Vector]) {
        let mut keyed: Vec<([i64; 3], u32)> = positions
            .iter()
            .enumerate()
            .map(|(i, &x)| (self.cell_key(x), i as u32))
            .collect();
        keyed.par_sort_unstable();
        self.sorted = keyed.iter().map(|&(_, i)| i).collect();
        self.occupied.clear();
        self.cell_start.clear();
        for (k, &(key, _)) in keyed.iter().enumerate() {
            if self.occupied.last() != Some(&key) {
                self.occupied.push(key);
                self.cell_start.push(k as u32);
            }
        }
        self.cell_start.push(keyed.len() as u32);
    }

    /// Unclamped cell coordinates of a point as a sparse key `[z, y, x]` (saturated at the
    /// ends of `i64`; unused axes 0).
    #[inline(always)]
    fn cell_key(&self, x: D::Vector) -> [i64; 3] {
        let mut key = [0i64; 3];
        for k in 0..D::D {
            let f = ((D::component(x, k) - D::component(self.origin, k)) * self.inv_cell).floor();
            key[2 - k] = f as i64;
        }
        key
    }

    /// Cell coordinates of a point, clamped to the grid.
    #[inline(always)]
    fn cell_coords(&self, x: D::Vector) -> [usize; 3] {
        let mut c = [0usize; 3];
        for k in 0..D::D {
            let f = ((D::component(x, k) - D::component(self.origin, k)) * self.inv_cell).floor();
            c[k] = if f <= 0.0 {
                0
            } else {
                (f as usize).min(self.dims[k] - 1)
            };
        }
        c
    }

    #[inline(always)]
    fn cell_index(&self, x: D::Vector) -> usize {
        let c = self.cell_coords(x);
        c[0] + self.dims[0] * (c[1] + self.dims[1] * c[2])
    }

    /// The cell edge.
    pub fn cell_size(&self) -> f64 {
        self.cell_size
    }

    /// Number of cells stored: every cell of the bounding box in the dense layout, the
    /// occupied ones in the sparse layout (at most `4 n + 4096` in the dense layout).
    pub fn num_cells(&self) -> usize {
        if self.is_sparse() {
            self.occupied.len()
        } else {
            self.dims[0] * self.dims[1] * self.dims[2]
        }
    }

    /// Whether the grid stores only its occupied cells (see [`CellGrid`]).
    pub fn is_sparse(&self) -> bool {
        self.sparse
    }

    /// Particle indices in cell order: the permutation `perm[new] = old` that makes particles in
    /// the same cell contiguous in memory. Apply it to every per-particle field with
    /// [`apply_permutation`] and rebuild.
    pub fn cell_order(&self) -> &[u32] {
        &self.sorted
    }

    /// Calls `f(j)` for every particle `j` of this grid in the cells adjacent to `x` (including
    /// its own cell): the candidates of a radius query with radius ≤ the cell size.
    #[inline(always)]
    pub fn for_each_candidate(&self, x: D::Vector, mut f: impl FnMut(u32)) {
        self.for_each_candidate_at(x, |j, _| f(j));
    }

    /// As [`Self::for_each_candidate`], also passing the candidate's position (read from the
    /// grid's cell-ordered copy, contiguous in memory).
    #[inline(always)]
    pub fn for_each_candidate_at(&self, x: D::Vector, mut f: impl FnMut(u32, D::Vector)) {
        if self.sparse {
            return self.for_each_sparse_candidate(x, f);
        }
        // A point outside the grid is clamped to the border cells; candidates are then still a
        // superset of the particles within one cell edge, because the grid encloses them all.
        let c = self.cell_coords(x);
        let x_lo = c[0].saturating_sub(1);
        let x_hi = (c[0] + 1).min(self.dims[0] - 1);
        let (y_lo, y_hi) = (c[1].saturating_sub(1), (c[1] + 1).min(self.dims[1] - 1));
        let (z_lo, z_hi) = (c[2].saturating_sub(1), (c[2] + 1).min(self.dims[2] - 1));
        for z in z_lo..=z_hi {
            for y in y_lo..=y_hi {
                let row = self.dims[0] * (y + self.dims[1] * z);
                let a = self.cell_start[row + x_lo] as usize;
                let b = self.cell_start[row + x_hi + 1] as usize;
                for (&j, &xj) in self.sorted[a..b].iter().zip(&self.sorted_pos[a..b]) {
                    f(j, xj);
                }
            }
        }
    }

    /// The sparse layout's [`Self::for_each_candidate_at`]: the same cells in the same order,
    /// each row of three cells along x found by binary search among the occupied ones.
    #[inline]
    fn for_each_sparse_candidate(&self, x: D::Vector, mut f: impl FnMut(u32, D::Vector)) {
        let [cz, cy, cx] = self.cell_key(x);
        let span = |c: i64, used: bool| {
            if used {
                c.saturating_sub(1)..=c.saturating_add(1)
            } else {
                0..=0
            }
        };
        for z in span(cz, D::D > 2) {
            for y in span(cy, D::D > 1) {
                let first = [z, y, cx.saturating_sub(1)];
                let last = [z, y, cx.saturating_add(1)];
                let a = self.occupied.partition_point(|k| *k < first);
                let b = a + self.occupied[a..].partition_point(|k| *k <= last);
                let (a, b) = (self.cell_start[a] as usize, self.cell_start[b] as usize);
                for (&j, &xj) in self.sorted[a..b].iter().zip(&self.sorted_pos[a..b]) {
                    f(j, xj);
                }
            }
        }
    }

    /// A query of `cutoff` over `n` points named `what` must use the points the grid was
    /// built from, with a cut-off no larger than the cell size.
    fn check_query(&self, what: &str, n: usize, cutoff: f64) -> Result<(), Error> {
        check_positive("cutoff", cutoff)?;
        if cutoff > self.cell_size * (1.0 + 1e-12) {
            return Err(Error::invalid(
                "cutoff",
                cutoff,
                &format!("<= the cell size {}", self.cell_size),
            ));
        }
        if n != self.sorted.len() {
            return Err(Error::invalid(
                what,
                n,
                &format!("the {} points the grid was built from", self.sorted.len()),
            ));
        }
        Ok(())
    }

    /// Neighbour list of the points this grid was built from (`positions` must be the same
    /// slice): `j ≠ i` with `|x_i − x_j| < cutoff`. `cutoff` must not exceed the cell size.
    ///
    /// Each row lists its neighbours in cell-scan order (deterministic: it depends only on the
    /// positions, not on threads). Sorting the rows costs about as much again as the search, so it
    /// is left to [`NeighborList::sort_rows`] for callers that need the canonical order.
    pub fn neighbor_list(
        &self,
        positions: &[D::Vector],
        cutoff: f64,
    ) -> Result<NeighborList, Error> {
        self.query(positions, positions, cutoff, true)
    }

    /// Contact list: for each point of `queries` (another set), the points of `targets` (the set
    /// this grid was built from) closer than `cutoff`. Indices refer to `targets`; rows are in
    /// cell-scan order as in [`Self::neighbor_list`].
    pub fn contact_list(
        &self,
        queries: &[D::Vector],
        targets: &[D::Vector],
        cutoff: f64,
    ) -> Result<NeighborList, Error> {
        check_finite::<D>(queries)?;
        self.query(queries, targets, cutoff, false)
    }

    fn query(
        &self,
        queries: &[D::Vector],
        targets: &[D::Vector],
        cutoff: f64,
        exclude_self: bool,
    ) -> Result<NeighborList, Error> {
        self.check_query("targets", targets.len(), cutoff)?;
        let rc2 = cutoff * cutoff;
        let blocks: Vec<(Vec<u32>, Vec<u32>)> = crate::parallel::map_tasks(
            queries.len().div_ceil(BLOCK),
            #[inline(always)]
            |b| {
                let chunk = &queries[b * BLOCK..((b + 1) * BLOCK).min(queries.len())];
                let mut counts = Vec::with_capacity(chunk.len());
                let mut idx = Vec::with_capacity(chunk.len() * 64);
                for (k, &xi) in chunk.iter().enumerate() {
                    let i = (b * BLOCK + k) as u32;
                    let start = idx.len();
                    self.for_each_candidate_at(xi, |j, xj| {
                        if (!exclude_self || j != i) && distance_squared::<D>(xi, xj) < rc2 {
                            idx.push(j);
                        }
                    });
                    counts.push((idx.len() - start) as u32);
                }
                (counts, idx)
            },
        );
        Ok(NeighborList::from_blocks(queries.len(), blocks))
    }
}

/// Neighbour list of `positions` by the cell-linked list (cells of edge `cutoff`), rows sorted
/// ascending: the canonical list, identical to [`neighbor_list_kdtree`].
pub fn neighbor_list_cells<D: Dim>(
    positions: &[D::Vector],
    cutoff: f64,
) -> Result<NeighborList, Error> {
    let mut list = CellGrid::<D>::build(positions, cutoff)?.neighbor_list(positions, cutoff)?;
    list.sort_rows();
    Ok(list)
}

/// Neighbour list of `positions` by a kiddo kd-tree, rows sorted ascending; identical to
/// [`neighbor_list_cells`].
pub fn neighbor_list_kdtree<D: Dim>(
    positions: &[D::Vector],
    cutoff: f64,
) -> Result<NeighborList, Error> {
    kd_query::<D>(positions, positions, cutoff, true)
}

/// Contact list of `queries` against `targets` by a kd-tree (indices refer to `targets`, rows
/// sorted ascending).
pub fn contact_list_kdtree<D: Dim>(
    queries: &[D::Vector],
    targets: &[D::Vector],
    cutoff: f64,
) -> Result<NeighborList, Error> {
    kd_query::<D>(queries, targets, cutoff, false)
}

fn kd_query<D: Dim>(
    queries: &[D::Vector],
    targets: &[D::Vector],
    cutoff: f64,
    exclude_self: bool,
) -> Result<NeighborList, Error> {
    check_positive("cutoff", cutoff)?;
    check_finite::<D>(queries)?;
    check_finite::<D>(targets)?;
    match D::D {
        2 => kd_query_k::<D, 2>(queries, targets, cutoff, exclude_self),
        _ => kd_query_k::<D, 3>(queries, targets, cutoff, exclude_self),
    }
}

fn kd_query_k<D: Dim, const K: usize>(
    queries: &[D::Vector],
    targets: &[D::Vector],
    cutoff: f64,
    exclude_self: bool,
) -> Result<NeighborList, Error> {
    use kiddo::{ImmutableKdTree, SquaredEuclidean};
    let to_arr = |x: D::Vector| -> [f64; K] { std::array::from_fn(|k| D::component(x, k)) };
    if targets.is_empty() {
        let blocks = vec![(vec![0u32; queries.len()], Vec::new())];
        return Ok(NeighborList::from_blocks(queries.len(), blocks));
    }
    let pts: Vec<[f64; K]> = targets.iter().map(|&x| to_arr(x)).collect();
    let tree = ImmutableKdTree::<f64, K>::new_from_slice(&pts)
        .map_err(|e| Error::invalid("kd_tree_points", format!("{e:?}"), "a buildable point set"))?;
    let rc2 = cutoff * cutoff;
    // Ask for a slightly larger radius, then filter with `distance_squared`, so the kd-tree
    // and the cell list agree to the last bit at the cut-off.
    let query_r2 = rc2 * (1.0 + 1e-9);
    let blocks: Vec<(Vec<u32>, Vec<u32>)> = queries
        .par_chunks(BLOCK)
        .enumerate()
        .map(|(b, chunk)| {
            let mut counts = Vec::with_capacity(chunk.len());
            let mut idx = Vec::with_capacity(chunk.len() * 64);
            for (k, &xi) in chunk.iter().enumerate() {
                let i = (b * BLOCK + k) as u32;
                let start = idx.len();
                let found = tree
                    .query(&to_arr(xi))
                    .within::<SquaredEuclidean<f64>>(query_r2)
                    .unsorted()
                    .execute();
                for item in found {
                    let j = item.item;
                    if (!exclude_self || j != i)
                        && distance_squared::<D>(xi, targets[j as usize]) < rc2
                    {
                        idx.push(j);
                    }
                }
                idx[start..].sort_unstable();
                counts.push((idx.len() - start) as u32);
            }
            (counts, idx)
        })
        .collect();
    Ok(NeighborList::from_blocks(queries.len(), blocks))
}

/// Reorders `data` by a permutation `perm[new] = old` (as returned by
/// [`CellGrid::cell_order`]).
pub fn apply_permutation<T: Clone>(perm: &[u32], data: &[T]) -> Vec<T> {
    perm.iter().map(|&old| data[old as usize].clone()).collect()
}

/// The inverse permutation (`inv[old] = new`).
pub fn invert_permutation(perm: &[u32]) -> Vec<u32> {
    let mut inv = vec![0u32; perm.len()];
    for (new, &old) in perm.iter().enumerate() {
        inv[old as usize] = new as u32;
    }
    inv
}
