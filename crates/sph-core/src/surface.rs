//! The surface particles of a body and their outward normals, for loads that act on a surface
//! (a pressure, [`crate::pressure`]).
//!
//! A particle's **normal** is estimated from its neighbourhood in the reference configuration:
//! the kernel-weighted mean offset of its neighbours, `s_i = Σ_j W(|X_j − X_i|)(X_j − X_i)`,
//! points into the body near a surface, so `N_i = −s_i/|s_i|` (a particle with `|s_i|` below
//! `10⁻⁶ dp` has a symmetric neighbourhood and is interior). A particle is **on the surface**
//! when nothing of the body lies in front of it: no other particle within `1.5 dp` inside the
//! cone of half-angle 45° about `N_i` (the scan-region test of Marrone et al. 2010, "Fast
//! free-surface detection and level-set function definition in SPH solvers", J. Comput. Phys.
//! 229, simplified to one cone). On a lattice that is the outermost layer, corners included;
//! on the concentric layers of a ring, the innermost or outermost ring.
//!
//! The kernel is the Wendland C2 with `h = 1.3 dp` (support `2h`), as for point probes.
//!
//! ```
//! use sph_core::surface::surface_of;
//! use sph_core::{glam::DVec2, D2};
//!
//! // A 0.01 × 0.005 block: 10 × 5 particles at the cell centres of a 1 mm lattice.
//! let dp = 1e-3;
//! let x: Vec<DVec2> = (0..5)
//!     .flat_map(|j| (0..10).map(move |i| DVec2::new(i as f64 + 0.5, j as f64 + 0.5) * dp))
//!     .collect();
//! let top_rows: Vec<u32> = (0..50).filter(|&i| x[i as usize].y > 0.003).collect(); // two rows
//! let top = surface_of::<D2>(&x, dp, &top_rows)?;
//! assert_eq!(top.len(), 10 + 2);             // the top row, and the sides of the row below
//! assert!(top.iter().all(|s| s.normal.y > -1e-12));   // up, diagonal or sideways
//! # Ok::<(), sph_core::Error>(())
//! ```

use crate::dim::Dim;
use crate::error::{check_positive, Error};
use crate::kernel::{Kernel, WendlandC2};
use crate::neighbor::CellGrid;

/// `h / dp` of the kernel that estimates the normals.
pub const NORMAL_H_OVER_DP: f64 = 1.3;

/// Radius of the scan cone, in units of `dp`.
const SCAN_RADIUS: f64 = 1.5;

/// One surface particle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceParticle<D: Dim> {
    /// Its index.
    pub index: u32,
    /// Outward unit normal of the body there.
    pub normal: D::Vector,
}

/// The particles of `candidates` that lie on the surface of the body whose particles are at
/// `positions` (spacing `dp`), with their outward unit normals, in the order of `candidates`.
/// See the [module documentation](self).
///
/// # Errors
/// A spacing that is not positive, non-finite positions, or an index outside `positions`.
pub fn surface_of<D: Dim>(
    positions: &[D::Vector],
    dp: f64,
    candidates: &[u32],
) -> Result<Vec<SurfaceParticle<D>>, Error> {
    check_positive("dp", dp)?;
    if let Some(&bad) = candidates.iter().find(|&&i| i as usize >= positions.len()) {
        return Err(Error::invalid(
            "surface candidate",
            bad,
            &format!("0..{} (the body's particles)", positions.len()),
        ));
    }
    let kernel = WendlandC2::<D>::from_spacing(dp, NORMAL_H_OVER_DP)?;
    let radius = kernel.cutoff();
    let grid = CellGrid::<D>::build(positions, radius)?;
    let (r2, scan2, cos2) = (radius * radius, (SCAN_RADIUS * dp).powi(2), 0.5);
    let mut out = Vec::new();
    for &i in candidates {
        let xi = positions[i as usize];
        let mut s = D::zero();
        grid.for_each_candidate_at(xi, |j, xj| {
            let d = xj - xi;
            let q = D::norm_squared(d);
            if j != i && q < r2 {
                s += d * kernel.w(q.sqrt());
            }
        });
        let len = D::norm(s);
        if len.is_nan() || len <= 1e-6 * dp {
            continue;
        }
        let n = s * (-1.0 / len);
        // Anything in front of it: within the scan radius and 45° of the normal
        // ((d·n)² ≥ cos²45° |d|² with d·n > 0).
        let mut covered = false;
        grid.for_each_candidate_at(xi, |j, xj| {
            let d = xj - xi;
            let (q, along) = (D::norm_squared(d), D::dot(d, n));
            covered |= j != i && q < scan2 && along > 0.0 && along * along >= cos2 * q;
        });
        if !covered {
            out.push(SurfaceParticle {
                index: i,
                normal: n,
            });
        }
    }
    Ok(out)
}

/// The thickness of a body from its particles (spacing `dp`): the diameter of the largest ball
/// (disc in 2D) inside it, the "particles across" that sets a resolution (a plate's height, a
/// ring's wall, a ball's diameter).
///
/// The depth of a point below the surface is its distance to the nearest surface particle (one
/// with fewer neighbours than the interior) plus `dp/2` (the surface lies half a spacing outside the
/// surface layer); the thickness is twice the largest depth over the particles and the
/// midpoints of nearest-neighbour pairs (so that a body of an even number of layers has its
/// middle sampled), and at most the smallest extent of the particles' bounding box plus `dp`
/// (a single layer, whose particles have no one-sided neighbourhood). Exact for a lattice slab
/// of any number of layers, within `dp` for curved bodies.
///
/// ```
/// use sph_core::surface::thickness;
/// use sph_core::{glam::DVec2, D2};
///
/// // A plate 20 particles long and 4 high, at cell centres of spacing dp.
/// let dp = 1e-3;
/// let plate: Vec<DVec2> = (0..80)
///     .map(|k| DVec2::new((k % 20) as f64 + 0.5, (k / 20) as f64 + 0.5) * dp)
///     .collect();
/// assert!((thickness::<D2>(&plate, dp)? - 0.004).abs() < 1e-12);
/// # Ok::<(), sph_core::Error>(())
/// ```
///
/// # Errors
/// No particles, a spacing that is not positive, or non-finite positions.
pub fn thickness<D: Dim>(positions: &[D::Vector], dp: f64) -> Result<f64, Error> {
    check_positive("dp", dp)?;
    if positions.is_empty() {
        return Err(Error::invalid("particles", 0, "at least one"));
    }
    // Surface sites: particles with fewer neighbours within 1.5 dp than three quarters of the
    // body's interior count (its 95th percentile: 8 on a 2D lattice, 18 in 3D; an edge particle
    // has 5 or 13). Unlike `surface_of`'s cone, this does not take the second layer of a
    // staircase (a lattice-filled curve) for surface.
    let near = CellGrid::<D>::build(positions, SCAN_RADIUS * dp)?;
    let scan2 = (SCAN_RADIUS * dp).powi(2);
    let counts: Vec<u32> = positions
        .iter()
        .enumerate()
        .map(|(i, &xi)| {
            let mut n = 0;
            near.for_each_candidate_at(xi, |j, xj| {
                n += u32::from(j as usize != i && D::norm_squared(xj - xi) < scan2);
            });
            n
        })
        .collect();
    let mut sorted = counts.clone();
    sorted.sort_unstable();
    let interior = f64::from(sorted[(0.95 * (sorted.len() - 1) as f64) as usize]);
    let sites: Vec<D::Vector> = positions
        .iter()
        .zip(&counts)
        .filter(|&(_, &n)| f64::from(n) < 0.75 * interior)
        .map(|(&x, _)| x)
        .collect();
    if sites.is_empty() {
        // Too few particles for any to have fewer neighbours than the rest: one spacing.
        return Ok(dp);
    }
    // A kd-tree of the sites (2D points padded with z = 0).
    let padded = |x: D::Vector| -> [f64; 3] {
        std::array::from_fn(|k| if k < D::D { D::component(x, k) } else { 0.0 })
    };
    let points: Vec<[f64; 3]> = sites.iter().map(|&x| padded(x)).collect();
    let tree = kiddo::ImmutableKdTree::<f64, 3>::new_from_slice(&points)
        .map_err(|e| Error::invalid("surface particles", format!("{e:?}"), "a kd-tree"))?;
    let bounds = CellGrid::<D>::build(positions, 1.1 * dp)?;
    // The depth of `x`: its distance to the nearest surface site plus half a spacing.
    let depth = |x: D::Vector| -> f64 {
        let nearest = tree
            .query(&padded(x))
            .nearest_one::<kiddo::SquaredEuclidean<f64>>()
            .execute();
        nearest.distance.sqrt() + 0.5 * dp
    };
    let mut deepest = 0.0f64;
    let near2 = (1.1 * dp) * (1.1 * dp);
    for (i, &xi) in positions.iter().enumerate() {
        deepest = deepest.max(depth(xi));
        bounds.for_each_candidate_at(xi, |j, xj| {
            if (j as usize) > i && D::norm_squared(xj - xi) < near2 {
                deepest = deepest.max(depth((xi + xj) * 0.5));
            }
        });
    }
    // A single layer has no one-sided neighbourhood (no surface particle but its ends): no
    // body is thicker than its bounding box's smallest extent and a spacing.
    let extent = (0..D::D)
        .map(|k| {
            let c = positions.iter().map(|&x| D::component(x, k));
            c.clone().fold(f64::NEG_INFINITY, f64::max) - c.fold(f64::INFINITY, f64::min)
        })
        .fold(f64::INFINITY, f64::min);
    Ok((2.0 * deepest).min(extent + dp))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::{D2, D3};
    use crate::testing::cell_centres;
    use glam::DVec2;

    #[test]
    fn the_outer_layer_of_a_box_is_the_surface_with_normals_along_the_faces() {
        let dp = 1.0;
        let x = cell_centres::<D2>([8, 5, 1], dp);
        let all: Vec<u32> = (0..x.len() as u32).collect();
        let s = surface_of::<D2>(&x, dp, &all).unwrap();
        // The perimeter of an 8 × 5 lattice: 2 (8 + 5) − 4 particles.
        assert_eq!(s.len(), 22);
        for p in &s {
            let x = x[p.index as usize];
            let edge = x.x < 1.0 || x.x > 7.0 || x.y < 1.0 || x.y > 4.0;
            assert!(edge, "{x}");
            if x.y > 4.0 && x.x > 2.6 && x.x < 5.4 {
                // Mid-face, the kernel support (2.6 dp) clear of the corners: exactly up by
                // symmetry (tolerance: round-off of the weighted sum).
                assert!((p.normal - DVec2::Y).length() < 1e-12, "{x}: {}", p.normal);
            }
        }
    }

    #[test]
    fn a_3d_face_is_one_layer() {
        let dp = 1.0;
        let x = cell_centres::<D3>([4, 4, 4], dp);
        let top: Vec<u32> = (0..x.len() as u32)
            .filter(|&i| x[i as usize].z > 2.0)
            .collect();
        let s = surface_of::<D3>(&x, dp, &top).unwrap();
        // The top face (16) and the upper rings of the four sides (12 of the second row).
        assert_eq!(s.len(), 16 + 12);
        assert!(s.iter().all(|p| p.normal.z >= 0.0));
        assert!(surface_of::<D3>(&x, 0.0, &top).is_err());
        assert!(surface_of::<D3>(&x, dp, &[9999]).is_err());
    }
}
