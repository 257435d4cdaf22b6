//! Domain decomposition of the reference configuration for distributed runs: recursive
//! coordinate bisection (RCB) weighted by neighbour count, and the halo layers a rank needs.
//!
//! **RCB.** The particles of a group of `k` ranks are split across the longest edge of their
//! bounding box (the lowest axis on a tie) at the weighted position that gives the first
//! `⌊k/2⌋` ranks the fraction `⌊k/2⌋/k` of the group's weight, and each half is split again
//! until every group has one rank. A particle's weight is its neighbour count plus one (the
//! work of its force sums plus its own update). Particles are ordered by coordinate, then by
//! index, so the split is deterministic; every particle gets exactly one owner.
//!
//! **Halo.** For the total-Lagrangian methods the neighbours never change, so a rank's halo is
//! fixed for the run: layer 1 is the neighbours of its owned particles that it does not own,
//! layer 2 the neighbours of layer 1 that are in neither (see `docs/distributed.md` for why two
//! layers make one velocity message per step enough).

use crate::dim::Dim;
use crate::error::Error;
use crate::neighbor::{NeighborList, Neighbours};

/// Which rank owns each particle.
#[derive(Clone, Debug, PartialEq)]
pub struct Partition {
    owner: Vec<u32>,
    ranks: usize,
}

impl Partition {
    /// RCB of `positions` over `ranks` ranks, particle `i` weighing `weights[i]` (see the module
    /// documentation).
    ///
    /// # Errors
    /// `ranks` outside `1..=positions.len()`, `weights` of another length, or a weight that is
    /// negative or not finite.
    pub fn recursive_bisection<D: Dim>(
        positions: &[D::Vector],
        weights: &[f64],
        ranks: usize,
    ) -> Result<Self, Error> {
        let n = positions.len();
        if ranks == 0 || ranks > n {
            return Err(Error::invalid(
                "ranks",
                ranks,
                &format!("1 to the number of particles ({n})"),
            ));
        }
        if weights.len() != n {
            return Err(Error::invalid(
                "weights",
                format!("{} weights", weights.len()),
                &format!("one per particle ({n})"),
            ));
        }
        if let Some(w) = weights.iter().find(|w| !(w.is_finite() && **w >= 0.0)) {
            return Err(Error::invalid("weights", w, "finite and ≥ 0"));
        }
        let mut owner = vec![0u32; n];
        let mut ids: Vec<u32> = (0..n as u32).collect();
        bisect::<D>(positions, weights, &mut ids, 0, ranks, &mut owner);
        Ok(Self { owner, ranks })
    }

    /// RCB weighted by neighbour count plus one (`list` over `positions`).
    ///
    /// # Errors
    /// As [`Partition::recursive_bisection`].
    pub fn by_neighbour_count<D: Dim>(
        positions: &[D::Vector],
        list: &NeighborList,
        ranks: usize,
    ) -> Result<Self, Error> {
        let counts: Vec<u32> = (0..list.len()).map(|i| list.count(i) as u32).collect();
        Self::by_counts::<D>(positions, &counts, ranks)
    }

    /// RCB weighted by the given neighbour counts plus one (the same partition as
    /// [`Partition::by_neighbour_count`] with a list of those counts).
    ///
    /// # Errors
    /// As [`Partition::recursive_bisection`].
    pub fn by_counts<D: Dim>(
        positions: &[D::Vector],
        counts: &[u32],
        ranks: usize,
    ) -> Result<Self, Error> {
        let weights: Vec<f64> = counts.iter().map(|&c| c as f64 + 1.0).collect();
        Self::recursive_bisection::<D>(positions, &weights, ranks)
    }

    /// Number of ranks.
    pub fn ranks(&self) -> usize {
        self.ranks
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.owner.len()
    }

    /// Whether there are no particles (never for a built partition).
    pub fn is_empty(&self) -> bool {
        self.owner.is_empty()
    }

    /// The rank owning particle `i`.
    pub fn owner(&self, i: usize) -> usize {
        self.owner[i] as usize
    }

    /// The particles `rank` owns, ascending.
    pub fn owned(&self, rank: usize) -> Vec<u32> {
        (0..self.owner.len() as u32)
            .filter(|&i| self.owner[i as usize] as usize == rank)
            .collect()
    }

    /// Layers 1 and 2 of `rank`'s halo (ascending): the neighbours of its particles it does
    /// not own, and their neighbours that are neither owned nor in layer 1.
    pub fn halo_layers(&self, rank: usize, list: &impl Neighbours) -> (Vec<u32>, Vec<u32>) {
        let n = self.owner.len();
        // 0: not needed, 1: owned, 2: layer 1, 3: layer 2.
        let mut mark = vec![0u8; n];
        for (i, m) in mark.iter_mut().enumerate() {
            if self.owner[i] as usize == rank {
                *m = 1;
            }
        }
        for i in 0..n {
            if self.owner[i] as usize == rank {
                list.for_each_neighbour(i, |j| {
                    if mark[j as usize] == 0 {
                        mark[j as usize] = 2;
                    }
                });
            }
        }
        for i in 0..n {
            if mark[i] == 2 {
                list.for_each_neighbour(i, |j| {
                    if mark[j as usize] == 0 {
                        mark[j as usize] = 3;
                    }
                });
            }
        }
        let layer = |k: u8| (0..n as u32).filter(|&i| mark[i as usize] == k).collect();
        (layer(2), layer(3))
    }

    /// For every rank at once: the sizes of its halo layers 1 and 2 ([`Partition::halo_layers`])
    /// and the number of ranks owning particles of them (the ranks it receives from). For the
    /// communication model of docs/distributed-model.md: cost grows with the halo, not with
    /// the number of particles times the number of ranks.
    pub fn halo_counts(&self, list: &NeighborList) -> Vec<[usize; 3]> {
        let n = self.owner.len();
        let mut layer1: Vec<Vec<u32>> = vec![Vec::new(); self.ranks];
        for i in 0..n {
            let o = self.owner[i];
            for &j in list.neighbors(i) {
                if self.owner[j as usize] != o {
                    layer1[o as usize].push(j);
                }
            }
        }
        layer1.iter_mut().for_each(|h| {
            h.sort_unstable();
            h.dedup();
        });
        layer1
            .iter()
            .enumerate()
            .map(|(r, h1)| {
                let mut h2: Vec<u32> = h1
                    .iter()
                    .flat_map(|&j| list.neighbors(j as usize).iter().copied())
                    .filter(|&k| {
                        self.owner[k as usize] as usize != r && h1.binary_search(&k).is_err()
                    })
                    .collect();
                h2.sort_unstable();
                h2.dedup();
                let mut from: Vec<u32> = h1
                    .iter()
                    .chain(&h2)
                    .map(|&j| self.owner[j as usize])
                    .collect();
                from.sort_unstable();
                from.dedup();
                [h1.len(), h2.len(), from.len()]
            })
            .collect()
    }
}

/// Splits `ids` over ranks `first..first + k`.
fn bisect<D: Dim>(
    positions: &[D::Vector],
    weights: &[f64],
    ids: &mut [u32],
    first: usize,
    k: usize,
    owner: &mut [u32],
) {
    if k == 1 {
        ids.iter().for_each(|&i| owner[i as usize] = first as u32);
        return;
    }
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for &i in ids.iter() {
        for a in 0..D::D {
            let c = D::component(positions[i as usize], a);
            lo[a] = lo[a].min(c);
            hi[a] = hi[a].max(c);
        }
    }
    let axis = (0..D::D).fold(0, |best, a| {
        if hi[a] - lo[a] > hi[best] - lo[best] {
            a
        } else {
            best
        }
    });
    ids.sort_unstable_by(|&a, &b| {
        D::component(positions[a as usize], axis)
            .total_cmp(&D::component(positions[b as usize], axis))
            .then(a.cmp(&b))
    });
    let k_left = k / 2;
    let total: f64 = ids.iter().map(|&i| weights[i as usize]).sum();
    let target = total * k_left as f64 / k as f64;
    // The cut closest to the target that leaves each side at least as many particles as ranks.
    let (min_cut, max_cut) = (k_left, ids.len() - (k - k_left));
    let mut cut = min_cut;
    let mut acc: f64 = ids[..min_cut].iter().map(|&i| weights[i as usize]).sum();
    let mut best = (acc - target).abs();
    for c in min_cut + 1..=max_cut {
        acc += weights[ids[c - 1] as usize];
        let err = (acc - target).abs();
        if err < best {
            (best, cut) = (err, c);
        }
    }
    let (left, right) = ids.split_at_mut(cut);
    bisect::<D>(positions, weights, left, first, k_left, owner);
    bisect::<D>(positions, weights, right, first + k_left, k - k_left, owner);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::D3;
    use crate::neighbor::CellGrid;
    use glam::DVec3;

    fn block(nx: usize, ny: usize, nz: usize) -> Vec<DVec3> {
        let mut x = Vec::new();
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    x.push(DVec3::new(i as f64, j as f64, k as f64));
                }
            }
        }
        x
    }

    #[test]
    fn every_particle_is_owned_once_and_the_weights_balance() {
        let x = block(6, 5, 20);
        let list = CellGrid::<D3>::build(&x, 2.3)
            .unwrap()
            .neighbor_list(&x, 2.3)
            .unwrap();
        for ranks in [1, 2, 3, 5, 8] {
            let p = Partition::by_neighbour_count::<D3>(&x, &list, ranks).unwrap();
            let mut seen = vec![0; x.len()];
            let mut load = vec![0.0; ranks];
            for r in 0..ranks {
                for i in p.owned(r) {
                    seen[i as usize] += 1;
                    load[r] += list.count(i as usize) as f64 + 1.0;
                }
            }
            assert!(seen.iter().all(|&s| s == 1), "{ranks} ranks");
            let mean = load.iter().sum::<f64>() / ranks as f64;
            let worst = load
                .iter()
                .fold(0.0f64, |m, &l| m.max((l / mean - 1.0).abs()));
            // Cuts fall between planes of 30 particles of ~50 neighbours: a few % off at most.
            assert!(worst < 0.06, "{ranks} ranks: imbalance {worst}");
            // The column is long in z: two ranks cut it across z.
            if ranks == 2 {
                let z0 = p
                    .owned(0)
                    .iter()
                    .map(|&i| x[i as usize].z)
                    .fold(0.0, f64::max);
                let z1 = p
                    .owned(1)
                    .iter()
                    .map(|&i| x[i as usize].z)
                    .fold(99.0, f64::min);
                assert!(z0 < z1);
            }
        }
    }

    #[test]
    fn halo_layers_are_the_neighbours_not_owned_and_theirs() {
        let x = block(4, 4, 12);
        let list = CellGrid::<D3>::build(&x, 1.5)
            .unwrap()
            .neighbor_list(&x, 1.5)
            .unwrap();
        let p = Partition::by_neighbour_count::<D3>(&x, &list, 2).unwrap();
        let (h1, h2) = p.halo_layers(0, &list);
        // Cut across z at the middle: planes of 16 particles, cut-off 1.5 reaches one plane.
        assert_eq!(p.owned(0).len(), 96);
        assert_eq!((h1.len(), h2.len()), (16, 16));
        for &i in &h1 {
            assert_eq!(p.owner(i as usize), 1);
            assert!(list
                .neighbors(i as usize)
                .iter()
                .any(|&j| p.owner(j as usize) == 0));
        }
        for &i in &h2 {
            assert!(!h1.contains(&i) && p.owner(i as usize) == 1);
            assert!(list.neighbors(i as usize).iter().any(|j| h1.contains(j)));
        }
    }

    #[test]
    fn halo_counts_agree_with_the_layers_of_each_rank() {
        let x = block(7, 5, 9);
        let list = CellGrid::<D3>::build(&x, 2.3)
            .unwrap()
            .neighbor_list(&x, 2.3)
            .unwrap();
        let p = Partition::by_neighbour_count::<D3>(&x, &list, 5).unwrap();
        for (r, c) in p.halo_counts(&list).into_iter().enumerate() {
            let (h1, h2) = p.halo_layers(r, &list);
            let mut from: Vec<usize> = h1.iter().chain(&h2).map(|&j| p.owner(j as usize)).collect();
            from.sort_unstable();
            from.dedup();
            assert_eq!(c, [h1.len(), h2.len(), from.len()], "rank {r}");
        }
    }

    #[test]
    fn bad_rank_counts_and_weights_are_refused() {
        let x = block(2, 1, 1);
        let e = Partition::recursive_bisection::<D3>(&x, &[1.0, 1.0], 3).unwrap_err();
        assert!(e.to_string().contains("ranks"), "{e}");
        let e = Partition::recursive_bisection::<D3>(&x, &[1.0, f64::NAN], 2).unwrap_err();
        assert!(e.to_string().contains("weights"), "{e}");
    }
}
