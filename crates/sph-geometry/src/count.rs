//! A fill whose particle count holds the enclosed volume: every particle keeps the volume
//! `dp^d` of its lattice cell, and the count `N` is brought to `round(V / dp^d)`, with `V` the
//! volume (area) the boundary encloses, so `|N dp^d − V| ≤ dp^d / 2`.
//!
//! A lattice fill takes the cells whose centres are inside: where the surface cuts a cell, the
//! cell counts whole or not at all, and over a curved surface the two do not cancel (a sphere
//! at 20 particles across holds 0.8 % more cells than its volume, docs/validation.md,
//! "Geometry"). [`match_count`] removes the surplus from the outer layer, or adds the deficit
//! just inside the surface, at places spread evenly over it; the relaxation
//! ([`crate::fit::relax`]) then evens the layer out around them.
//!
//! # Which particles
//! - **Removal**: the candidates are the layer particles (a face neighbour of their cell is not
//!   in the fill), in order of increasing depth below the surface (the cells that lie most
//!   outside hold the least of the body). Among them a greedy pass keeps, in that order, every
//!   candidate farther than `r` from all kept before (a Poisson-disc selection, as in Bridson's
//!   and Dunbar & Humphreys' dart throwing, here over a fixed candidate order so that it is
//!   deterministic); `r` is the largest (by bisection) for which the pass keeps at least the
//!   surplus, and the first `surplus` kept are removed.
//! - **Addition**: the candidates are the empty cells next to the fill (face neighbours of a
//!   layer cell not in it) whose centre is less than `dp/2` outside (the cells the surface
//!   cuts; all empty neighbours if these are too few), in order of increasing distance
//!   outside; the same spread selection (over the places they go to)
//!   picks the deficit, and each new particle is placed at depth `dp/2` below the surface along
//!   the normal of its closest point, where the relaxation's surface bounding keeps the layer.
//!
//! Everything is sequential or an ordered parallel map: the result does not depend on the
//! thread count.

use crate::generate::Lattice;
use crate::Boundary;
use rayon::prelude::*;
use sph_core::{budget, Dim, Error};
use std::collections::HashMap;

/// Bisection steps of the selection radius (the radius is found to `2^-40` of its range).
const BISECTION: usize = 40;

/// The count of particles of volume `dp^d` whose total is nearest the enclosed volume
/// `volume`: `round(volume / dp^d)`, at least 1.
pub fn volume_count<D: Dim>(volume: f64, dp: f64) -> usize {
    (volume / dp.powi(D::D as i32)).round().max(1.0) as usize
}

/// What [`match_count`] changed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct CountChange {
    /// Particles of the lattice fill.
    pub lattice: usize,
    /// Particles removed from the outer layer.
    pub removed: usize,
    /// Particles added inside the surface.
    pub added: usize,
}

/// The integer lattice cell of a point of `lattice` (its centre is `origin + (n + ½) dp`).
fn cell<D: Dim>(lattice: &Lattice<D>, x: D::Vector) -> [i64; 3] {
    let mut c = [0i64; 3];
    for k in 0..D::D {
        c[k] = ((D::component(x, k) - D::component(lattice.origin(), k)) / lattice.dp() - 0.5)
            .round() as i64;
    }
    c
}

/// The centre of lattice cell `c`.
fn centre<D: Dim>(lattice: &Lattice<D>, c: [i64; 3]) -> D::Vector {
    let mut v = [0.0; 3];
    for k in 0..D::D {
        v[k] = D::component(lattice.origin(), k) + (c[k] as f64 + 0.5) * lattice.dp();
    }
    D::vector(v)
}

/// The `2d` face neighbours of cell `c`.
fn face_neighbours<D: Dim>(c: [i64; 3]) -> impl Iterator<Item = [i64; 3]> {
    (0..D::D).flat_map(move |k| {
        [-1, 1].into_iter().map(move |s| {
            let mut n = c;
            n[k] += s;
            n
        })
    })
}

/// Brings the count of `x`, the cell centres of a lattice fill of `boundary` (as
/// [`crate::fit::lattice_points`] gives them), to [`volume_count`] of the enclosed volume by
/// removing surface-layer particles or adding particles just inside the surface, spread evenly
/// (module documentation). Keeps the order of the particles it does not remove; added ones
/// come last.
///
/// # Errors
/// An enclosed volume not finite and `> 0` (naming the file); a point of `x` not at a cell centre of `lattice` (off by more than `dp/4`); the particle
/// budget for added particles.
pub fn match_count<D: Dim>(
    x: &mut Vec<D::Vector>,
    boundary: &dyn Boundary<D>,
    lattice: &Lattice<D>,
) -> Result<CountChange, Error> {
    let dp = lattice.dp();
    let volume = boundary.volume();
    if !(volume.is_finite() && volume > 0.0) {
        return Err(crate::file_error(
            boundary.name(),
            format!("enclosed volume {volume:?} is not finite and > 0: the particle count cannot be matched to it"),
        ));
    }
    let target = volume_count::<D>(volume, dp);
    let mut change = CountChange {
        lattice: x.len(),
        ..CountChange::default()
    };
    if x.len() == target || x.is_empty() {
        return Ok(change);
    }
    let cells: Vec<[i64; 3]> = x.par_iter().map(|&xi| cell(lattice, xi)).collect();
    if let Some(i) = (0..x.len()).find(|&i| D::norm(x[i] - centre(lattice, cells[i])) > 0.25 * dp) {
        return Err(Error::invalid(
            "lattice points",
            format!("{:?}", x[i]),
            "cell centres of the lattice the fill was made on",
        ));
    }
    let mut sorted = cells.clone();
    sorted.par_sort_unstable();
    let filled = |c: &[i64; 3]| sorted.binary_search(c).is_ok();
    let layer = |i: usize| face_neighbours::<D>(cells[i]).any(|n| !filled(&n));
    if x.len() > target {
        // Layer particles, shallowest first (index breaks ties).
        let mut cands: Vec<(f64, usize)> = (0..x.len())
            .into_par_iter()
            .filter(|&i| layer(i))
            .map(|i| (boundary.signed_distance(x[i]).0, i))
            .collect();
        cands.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        let points: Vec<D::Vector> = cands.iter().map(|&(_, i)| x[i]).collect();
        let picked = spread::<D>(&points, x.len() - target, dp);
        let mut remove = vec![false; x.len()];
        for &k in &picked {
            remove[cands[k].1] = true;
        }
        let mut i = 0;
        x.retain(|_| {
            i += 1;
            !remove[i - 1]
        });
        change.removed = picked.len();
    } else {
        // Empty cells next to the fill, least outside first.
        let mut empty: Vec<[i64; 3]> = (0..x.len())
            .into_par_iter()
            .flat_map_iter(|i| {
                face_neighbours::<D>(cells[i])
                    .filter(|n| !filled(n))
                    .collect::<Vec<_>>()
            })
            .collect();
        empty.par_sort_unstable();
        empty.dedup();
        let mut cands: Vec<(f64, D::Vector, D::Vector)> = empty
            .par_iter()
            .map(|&c| {
                let p = centre(lattice, c);
                let (phi, n) = boundary.signed_distance(p);
                (phi, p, p - n * (phi + 0.5 * dp))
            })
            .collect();
        // (The sort is stable and `empty` sorted: ties keep the cell order.)
        cands.sort_by(|a, b| a.0.total_cmp(&b.0));
        // Cells whose centre lies less than dp/2 outside (part of the cell inside); farther
        // ones only if these do not suffice. (A centre dp/2 or more outside projects onto
        // a layer particle where the layer already sits at depth dp/2.)
        let within = cands.partition_point(|c| c.0 < 0.5 * dp);
        if within >= target - x.len() {
            cands.truncate(within);
        }
        let points: Vec<D::Vector> = cands.iter().map(|c| c.2).collect();
        let picked = spread::<D>(&points, target - x.len(), dp);
        budget::reserve::<D>(
            picked.len() as f64,
            "the particles added to match the volume",
        )?;
        budget::book::<D>(picked.len() as u64);
        x.extend(picked.iter().map(|&k| cands[k].2));
        change.added = picked.len();
    }
    Ok(change)
}

/// The first `count` (all, if fewer) of `points` (in priority order) kept by a greedy
/// exclusion pass of the largest radius that keeps at least `count` (module documentation),
/// as indices into `points`, in priority order.
fn spread<D: Dim>(points: &[D::Vector], count: usize, dp: f64) -> Vec<usize> {
    if count >= points.len() {
        return (0..points.len()).collect();
    }
    // At radius 0 every point is kept; beyond the points' extent only the first.
    let (mut a, mut b) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for &p in points {
        for k in 0..D::D {
            a[k] = a[k].min(D::component(p, k));
            b[k] = b[k].max(D::component(p, k));
        }
    }
    let extent = (0..D::D).map(|k| (b[k] - a[k]).powi(2)).sum::<f64>().sqrt();
    let (mut lo, mut hi) = (0.0, extent + dp);
    if count <= 1 {
        return (0..count).collect();
    }
    for _ in 0..BISECTION {
        let r = 0.5 * (lo + hi);
        if greedy::<D>(points, r, count).len() >= count {
            lo = r;
        } else {
            hi = r;
        }
    }
    let mut kept = greedy::<D>(points, lo, count);
    kept.truncate(count);
    kept
}

/// The points kept by one greedy pass at exclusion radius `r` (each farther than `r` from all
/// kept before it), stopping once `stop` are kept.
fn greedy<D: Dim>(points: &[D::Vector], r: f64, stop: usize) -> Vec<usize> {
    let mut kept = Vec::new();
    if r <= 0.0 {
        return (0..points.len().min(stop)).collect();
    }
    let key = |p: D::Vector| -> [i64; 3] {
        let mut c = [0i64; 3];
        for k in 0..D::D {
            c[k] = (D::component(p, k) / r).floor() as i64;
        }
        c
    };
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    let r2 = r * r;
    for (k, &p) in points.iter().enumerate() {
        let c = key(p);
        let mut free = true;
        'search: for dz in if D::D == 3 { -1..=1 } else { 0..=0 } {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    if let Some(list) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) {
                        if list.iter().any(|&j| D::norm_squared(points[j] - p) <= r2) {
                            free = false;
                            break 'search;
                        }
                    }
                }
            }
        }
        if free {
            grid.entry(c).or_default().push(k);
            kept.push(k);
            if kept.len() >= stop {
                break;
            }
        }
    }
    kept
}
