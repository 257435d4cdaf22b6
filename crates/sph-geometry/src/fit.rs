//! Body-fitted particles: a lattice fill of a [`Boundary`], then a relaxation that pulls the
//! surface layer onto the surface and evens out the particles' volumes, and the report of how
//! well the particles fit.
//!
//! # Relaxation
//! The particle-relaxation of Zhu, Zhang & Hu 2021 ("A CAD-compatible body-fitted particle
//! generator for arbitrarily complex geometry and its application to wave-structure
//! interaction", J. Hydrodyn. 33), as SPHinXsys runs it: every particle moves down the
//! gradient of the kernel sum,
//!
//! `a_i = −2 (Σ_j V_j ∇_i W_ij + n_i P(d_i))`,
//!
//! where the second term stands for the particles missing beyond the surface: `d_i` is the
//! particle's depth below the surface, `n_i` the outward normal there, and
//! `P(d) = ∫_plane W dS` the kernel integrated over a plane at distance `d` (by the divergence
//! theorem, `∫ ∇W` over the half-space beyond the plane; exact for a flat surface, tabulated
//! once). The step is SPHinXsys's: `Δx_i = ½ a_i Δt²` with `Δt² = h / (16 max|a|)`, so no
//! particle moves more than `h/32` per step. After each step every particle less than `dp/2`
//! below the surface (or beyond it) is put back at depth `dp/2` along the normal ("surface
//! bounding"), which is where the outermost layer of a fill of cells of size `dp` belongs.
//!
//! Where SPHinXsys samples a level set on a background mesh, the distance here is exact (the
//! closest point on the mesh or outline, [`Boundary::signed_distance`]) and evaluated only for
//! particles within reach of the surface (re-selected every [`RESELECT`] steps, within which no
//! particle can move farther than the margin; a particle is measured again only once it has
//! moved far enough since its last measurement to have come within reach). A particle whose
//! last measured depth exceeds how far it has moved since is certainly inside: its distance
//! skips the inside test (a winding number on a mesh, the costly half of the query), and its
//! push from the surface is not evaluated at all once that depth exceeds the kernel's support.
//! The kernel sum runs over neighbour lists with a skin ([`SKIN_OVER_DP`]), rebuilt only once
//! some particle has moved half the skin since the last build: a step moves a particle by at
//! most `h/32`, so the lists serve several steps where a cell grid was rebuilt every step.
//!
//! # Report
//! [`FitReport`]: the particle count; the total particle volume `N dp^d` against the enclosed
//! volume of the boundary, and the factor [`FitOptions::match_volume`] scaled every particle's
//! volume by so the two agree (see "Volume" below); how far the surface particles (the outermost layer: those less than
//! one spacing below the surface) are from depth `dp/2` (RMS and max, in units of `dp`; 0 is a
//! perfect fit; an unrelaxed lattice gives an RMS near `1/√12 ≈ 0.29`, and by this selection the
//! max is below `0.5`); and the spread (relative standard deviation) of the particle volumes the
//! kernel sees, `V_i = 1/(Σ_j W_ij + Q(d_i)/dp^d)`, with `Q(d) = ∫ W` over the half-space beyond
//! the surface standing for the missing neighbours.
//!
//! # Volume
//! A fill of cells of size `dp` holds `N dp^d`, which misses the enclosed volume by the cells the
//! surface cuts: at 20 particles across, +0.94 % for a sphere mesh of 128 segments (+0.84 % from
//! the exact ball), +0.40 % for a torus, 0 for a cube on the lattice (docs/validation.md,
//! "Geometry", the rows with the count match off). By default ([`FitOptions::match_count`]) the
//! count is brought to `round(V_mesh / dp^d)` before the relaxation ([`crate::count`]: surplus
//! particles removed from the outer layer, or a deficit added just inside the surface, spread
//! evenly), so every particle keeps the volume `dp^d` and `|N dp^d − V_mesh| ≤ dp^d / 2`; the
//! relaxation then evens the layer out. [`FitOptions::match_volume`] (off by default) also
//! scales every particle's volume by `V_mesh / (N dp^d)` after the relaxation, which leaves
//! at most that half particle (a factor within `1 ± 1/(2N)`) and, without the count match,
//! the whole lattice error (see its documentation for the bias that brings); the report keeps
//! the unscaled `N dp^d` in [`FitReport::volume`] and the factor in [`FitReport::volume_scale`].

use crate::count::match_count;
use crate::generate::{Lattice, ParticleSet};
use crate::Boundary;
use rayon::prelude::*;
use sph_core::budget;
use sph_core::error::check_positive;
use sph_core::kernel::{Kernel, WendlandC2};
use sph_core::neighbor::CellGrid;
use sph_core::{Dim, Error};

/// `h / dp` of the relaxation kernel (SPHinXsys's default; the Wendland C2 support is `2h`).
pub const RELAX_H_OVER_DP: f64 = 1.3;

/// Steps between re-selections of the particles near the surface.
pub const RESELECT: usize = 10;

/// Default number of relaxation steps (see docs/validation.md, "Geometry": the surface
/// distance and volume spread level off well before).
pub const DEFAULT_RELAX_STEPS: usize = 200;

/// How to fit particles to a boundary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitOptions {
    /// Relaxation steps after the lattice fill (0: the fill as it is, count-matched by
    /// [`Self::match_count`]).
    pub relax_steps: usize,
    /// Scale every particle's volume by `V_mesh / (N dp^d)` so the body's total volume is the
    /// boundary's enclosed volume (module documentation, "Volume"). Default `false`: the
    /// factor changes `Σ_j V_j ∇W_ij` with it, so the sums that no correction matrix
    /// normalises (TL-HF's remaining stress and Laplacian, UL's forces) get stiffer by the
    /// same factor, a bias of the dynamics of the order of the volume error it removes (≈ 1 %
    /// at 20 across without [`Self::match_count`]; with it the factor is within `1 ± 1/(2N)`,
    /// the rounding of the count). Turn it on where the total mass must be the enclosed
    /// volume's to round-off.
    pub match_volume: bool,
    /// Bring the count to the enclosed volume before the relaxation: `N = round(V / dp^d)`
    /// particles of volume `dp^d` ([`crate::count::match_count`]: surplus removed from the
    /// outer layer, or a deficit added just inside the surface, spread evenly over it).
    /// Default `true`; `false` keeps the lattice fill's count.
    pub match_count: bool,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            relax_steps: DEFAULT_RELAX_STEPS,
            match_volume: false,
            match_count: true,
        }
    }
}

/// How well a body's particles fit its boundary (see the module documentation).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct FitReport {
    /// Number of particles.
    pub particles: usize,
    /// Number of particles of the lattice fill, before [`FitOptions::match_count`] changed it.
    pub lattice_particles: usize,
    /// Total particle volume (area in 2D) of the fill, `N dp^d`, before any scaling.
    pub volume: f64,
    /// The volume (area) the boundary encloses.
    pub mesh_volume: f64,
    /// The factor every particle's volume was scaled by: `mesh_volume / volume` with
    /// [`FitOptions::match_volume`], else 1. The particles' total volume is
    /// `volume * volume_scale`.
    pub volume_scale: f64,
    /// RMS distance of the surface particles from depth `dp/2`, in units of `dp`.
    pub surface_distance_rms: f64,
    /// Largest distance of a surface particle from depth `dp/2`, in units of `dp`.
    pub surface_distance_max: f64,
    /// Relative standard deviation of the kernel-sum particle volumes.
    pub volume_spread: f64,
    /// Relaxation steps taken.
    pub relax_steps: usize,
}

/// The cell centres of `lattice` inside `shape`, as [`Lattice::points`] (same points, same
/// order) but with the inside test run on every core: the test is the costly part for a mesh.
pub fn lattice_points<D: Dim>(
    lattice: &Lattice<D>,
    shape: &dyn crate::generate::Shape<D>,
) -> Result<Vec<D::Vector>, Error> {
    let (lo, hi) = shape.bounds();
    if !D::is_finite(lo) || !D::is_finite(hi) {
        return Err(Error::invalid(
            "shape bounds",
            format!("{lo:?} .. {hi:?}"),
            "finite",
        ));
    }
    let dp = lattice.dp();
    let o = lattice.origin();
    let mut first = [0i64; 3];
    let mut last = [0i64; 3];
    let mut candidates: f64 = 1.0;
    for k in 0..D::D {
        let a = ((D::component(lo, k) - D::component(o, k)) / dp - 0.5).floor() - 1.0;
        let b = ((D::component(hi, k) - D::component(o, k)) / dp - 0.5).ceil() + 1.0;
        first[k] = a as i64;
        last[k] = b as i64;
        candidates *= b - a + 1.0;
    }
    if candidates > (1u64 << 32) as f64 {
        return Err(Error::invalid(
            "dp",
            dp,
            "large enough that the shape's bounding box holds at most 2^32 lattice cells",
        ));
    }
    let allowance = budget::remaining::<D>();
    // One slab (the last axis) per task; slabs concatenated in order.
    let axis = D::D - 1;
    let slabs: Vec<Vec<D::Vector>> = (first[axis]..=last[axis])
        .into_par_iter()
        .map(|n_last| {
            let mut out = Vec::new();
            let centre = |k: usize, n: i64| D::component(o, k) + (n as f64 + 0.5) * dp;
            let (r1, r2) = if D::D == 3 {
                (first[1]..=last[1], n_last..=n_last)
            } else {
                (n_last..=n_last, 0..=0)
            };
            for n2 in r2 {
                for n1 in r1.clone() {
                    for n0 in first[0]..=last[0] {
                        let c = [
                            centre(0, n0),
                            centre(1, n1),
                            if D::D == 3 { centre(2, n2) } else { 0.0 },
                        ];
                        let x = D::vector(c);
                        if shape.contains(x) {
                            out.push(x);
                        }
                    }
                }
            }
            out
        })
        .collect();
    let n: usize = slabs.iter().map(Vec::len).sum();
    if n as u64 > allowance {
        return Err(budget::exceeded::<D>(
            n as f64,
            &format!("the lattice fill at dp = {dp:?}"),
        ));
    }
    budget::book::<D>(n as u64);
    Ok(slabs.concat())
}

/// The kernel integrated over a plane (`P`) and over the half-space beyond it (`Q`), as
/// functions of the plane's distance `d ∈ [0, 2h]`, tabulated.
#[derive(Clone, Debug)]
pub struct HalfSpaceIntegrals {
    step: f64,
    plane: Vec<f64>,
    half: Vec<f64>,
}

impl HalfSpaceIntegrals {
    const N: usize = 256;

    /// The tables for `kernel` in `D` dimensions (midpoint quadrature, 4096 points per
    /// integral: relative error below 1e-6).
    pub fn new<D: Dim>(kernel: &WendlandC2<D>) -> Self {
        let support = kernel.cutoff();
        let step = support / Self::N as f64;
        let q = 4096;
        let plane_at = |d: f64| -> f64 {
            if d >= support {
                return 0.0;
            }
            if D::D == 3 {
                // 2π ∫_d^R W(r) r dr.
                let dr = (support - d) / q as f64;
                (0..q)
                    .map(|k| {
                        let r = d + (k as f64 + 0.5) * dr;
                        kernel.w(r) * r
                    })
                    .sum::<f64>()
                    * dr
                    * 2.0
                    * std::f64::consts::PI
            } else {
                // 2 ∫_0^√(R²−d²) W(√(d² + t²)) dt.
                let tmax = (support * support - d * d).sqrt();
                let dt = tmax / q as f64;
                (0..q)
                    .map(|k| {
                        let t = (k as f64 + 0.5) * dt;
                        kernel.w((d * d + t * t).sqrt())
                    })
                    .sum::<f64>()
                    * dt
                    * 2.0
            }
        };
        // Q(d) = ∫_d^R P(s) ds is the kernel over the half-space beyond the plane, one integral
        // over the radius: Q(d) = ∫_d^R W(r) A(r) dr with A the part of the sphere (circle) of
        // radius r beyond the plane, 2π r (r − d) in 3D and 2 r arccos(d/r) in 2D; with
        // r = d + (R − d) u², smooth at r = d, by the midpoint rule.
        let half_at = |d: f64| -> f64 {
            if d >= support {
                return 0.0;
            }
            let du = 1.0 / q as f64;
            (0..q)
                .map(|k| {
                    let u = (k as f64 + 0.5) * du;
                    let r = d + (support - d) * u * u;
                    let beyond = if D::D == 3 {
                        2.0 * std::f64::consts::PI * r * (r - d)
                    } else {
                        2.0 * r * (d / r).min(1.0).acos()
                    };
                    kernel.w(r) * beyond * 2.0 * (support - d) * u
                })
                .sum::<f64>()
                * du
        };
        let plane: Vec<f64> = (0..=Self::N).map(|k| plane_at(k as f64 * step)).collect();
        let half = (0..=Self::N).map(|k| half_at(k as f64 * step)).collect();
        Self { step, plane, half }
    }

    fn lookup(table: &[f64], step: f64, d: f64) -> f64 {
        let s = d.max(0.0) / step;
        let k = s.floor() as usize;
        if k + 1 >= table.len() {
            return 0.0;
        }
        let f = s - k as f64;
        table[k] * (1.0 - f) + table[k + 1] * f
    }

    /// `P(d) = ∫ W` over a plane at distance `d ≥ 0`.
    pub fn plane(&self, d: f64) -> f64 {
        Self::lookup(&self.plane, self.step, d)
    }

    /// `Q(d) = ∫ W` over the half-space beyond a plane at distance `d ≥ 0`.
    pub fn half_space(&self, d: f64) -> f64 {
        Self::lookup(&self.half, self.step, d)
    }
}

/// The body-fitted particles of `boundary` at spacing `dp`: the lattice fill (cell faces
/// through the boundary's lower bound), its count brought to the enclosed volume
/// ([`FitOptions::match_count`]), relaxed ([`FitOptions::relax_steps`]), each particle of
/// volume `dp^d` scaled by [`FitReport::volume_scale`] ([`FitOptions::match_volume`]), and the
/// report.
///
/// # Errors
/// `dp` not finite and `> 0`; a boundary no lattice cell centre falls in (the message names
/// the file and its size against `dp`); the particle budget.
pub fn fit<D: Dim>(
    boundary: &dyn Boundary<D>,
    dp: f64,
    options: &FitOptions,
) -> Result<(ParticleSet<D>, FitReport), Error> {
    check_positive("dp", dp)?;
    let (lo, hi) = boundary.bounds();
    let lattice = Lattice::new(dp, lo)?;
    let mut x = lattice_points(&lattice, boundary)?;
    if x.is_empty() {
        let size = (0..D::D)
            .map(|k| D::component(hi, k) - D::component(lo, k))
            .fold(0.0, f64::max);
        return Err(crate::file_error(
            boundary.name(),
            format!(
                "no particle at dp = {dp:?} falls inside (size {size:.4e}, enclosed volume {:.4e}): make dp smaller or check the file is a closed surface",
                boundary.volume()
            ),
        ));
    }
    let lattice_count = x.len();
    if options.match_count {
        match_count(&mut x, boundary, &lattice)?;
    }
    let kernel = WendlandC2::<D>::from_spacing(dp, RELAX_H_OVER_DP)?;
    let tables = HalfSpaceIntegrals::new(&kernel);
    relax(&mut x, boundary, dp, &kernel, &tables, options.relax_steps)?;
    let n = x.len();
    let raw = ParticleSet::from_parts(x, vec![dp.powi(D::D as i32); n])?.with_spacing(dp);
    let mut report = report(&raw, boundary, dp, &kernel, &tables, options.relax_steps)?;
    report.lattice_particles = lattice_count;
    if !options.match_volume {
        return Ok((raw, report));
    }
    report.volume_scale = volume_scale(report.volume, report.mesh_volume);
    let (x, volumes, _) = raw.into_parts();
    let volumes = volumes.iter().map(|v| v * report.volume_scale).collect();
    let set = ParticleSet::from_parts(x, volumes)?.with_spacing(dp);
    Ok((set, report))
}

/// The factor that makes a fill's total particle volume `particles` the enclosed volume `mesh`
/// (module documentation, "Volume"); 1 when either is not finite and `> 0` (no scaling rather
/// than a degenerate one).
pub fn volume_scale(particles: f64, mesh: f64) -> f64 {
    if particles.is_finite() && particles > 0.0 && mesh.is_finite() && mesh > 0.0 {
        mesh / particles
    } else {
        1.0
    }
}

/// The skin of the relaxation's neighbour lists, in units of `dp`: the lists hold the pairs
/// within `cutoff + skin` and are rebuilt once some particle has moved more than `skin / 2`
/// since the last build (Verlet 1967, "Computer \"experiments\" on classical fluids. I.",
/// Phys. Rev. 159; Allen & Tildesley, "Computer Simulation of Liquids", §5.3.1), which no
/// step can do before `skin / 2 / (h/32)` ≈ 5 steps.
pub const SKIN_OVER_DP: f64 = 0.4;

/// Particles per neighbour-list chunk (each chunk owns its list, rebuilt in place).
const LIST_CHUNK: usize = 512;

/// The neighbour lists of `LIST_CHUNK` consecutive particles.
#[derive(Default)]
struct NeighbourChunk {
    /// `start[k] .. start[k + 1]`: particle `k`'s neighbours in `list`.
    start: Vec<u32>,
    list: Vec<u32>,
}

impl NeighbourChunk {
    fn of(&self, k: usize) -> &[u32] {
        &self.list[self.start[k] as usize..self.start[k + 1] as usize]
    }
}

/// (Re)builds `lists` as the pairs of `x` closer than `radius` (self excluded), each
/// particle's neighbours in the grid's candidate order: the same for any thread count.
fn build_lists<D: Dim>(
    lists: &mut Vec<NeighbourChunk>,
    x: &[D::Vector],
    radius: f64,
) -> Result<(), Error> {
    let grid = CellGrid::<D>::build(x, radius)?;
    lists.resize_with(x.len().div_ceil(LIST_CHUNK), NeighbourChunk::default);
    let r2 = radius * radius;
    lists.par_iter_mut().enumerate().for_each(|(c, chunk)| {
        chunk.start.clear();
        chunk.list.clear();
        chunk.start.push(0);
        let end = ((c + 1) * LIST_CHUNK).min(x.len());
        for i in c * LIST_CHUNK..end {
            let xi = x[i];
            grid.for_each_candidate_at(xi, |j, xj| {
                if j as usize != i && D::norm_squared(xi - xj) < r2 {
                    chunk.list.push(j);
                }
            });
            chunk.start.push(chunk.list.len() as u32);
        }
    });
    Ok(())
}

/// Relaxes `x` in place (module documentation).
pub fn relax<D: Dim>(
    x: &mut [D::Vector],
    boundary: &dyn Boundary<D>,
    dp: f64,
    kernel: &WendlandC2<D>,
    tables: &HalfSpaceIntegrals,
    steps: usize,
) -> Result<(), Error> {
    if steps == 0 {
        return Ok(());
    }
    let v = dp.powi(D::D as i32);
    let cutoff = kernel.cutoff();
    let h = kernel.h();
    // Within RESELECT steps of at most h/32 each no particle moves more than this.
    let margin = RESELECT as f64 * h / 32.0 + dp;
    let reach = cutoff + margin;
    let mut near: Vec<u32> = Vec::new();
    let mut is_near = vec![false; x.len()];
    let mut accel = vec![D::zero(); x.len()];
    // Each particle's depth when last measured and how far it has moved since: its depth now
    // is at least the difference, so only particles that may have come within reach are
    // measured again (the interior of a fill barely moves and is measured once).
    let mut depth = vec![f64::NEG_INFINITY; x.len()];
    let mut drift = vec![0.0; x.len()];
    // The outward normal at the last measurement; a particle not moved since (`drift` 0) has
    // its depth and normal without a new query.
    let mut normal = vec![D::zero(); x.len()];
    // Neighbour lists to `cutoff + skin`, rebuilt once some particle has moved more than
    // `skin / 2` since the last build (then no pair within `cutoff` can be missing).
    let skin = SKIN_OVER_DP * dp;
    let cutoff2 = cutoff * cutoff;
    let mut lists: Vec<NeighbourChunk> = Vec::new();
    let mut since_build = vec![0.0; x.len()];
    for step in 0..steps {
        if step % RESELECT == 0 {
            depth
                .par_iter_mut()
                .zip(drift.par_iter_mut())
                .zip(normal.par_iter_mut())
                .zip(x.par_iter())
                .for_each(|(((d, moved), nd), &xi)| {
                    if *d - *moved < reach {
                        let (phi, n) = depth_measure(boundary, xi, *d - *moved);
                        (*d, *nd, *moved) = (-phi, n, 0.0);
                    }
                });
            near = (0..x.len() as u32)
                .filter(|&i| depth[i as usize] < reach)
                .collect();
            is_near.iter_mut().for_each(|f| *f = false);
            for &i in &near {
                is_near[i as usize] = true;
            }
        }
        if lists.is_empty() || 2.0 * since_build.iter().copied().fold(0.0, f64::max) > skin {
            build_lists::<D>(&mut lists, x, cutoff + skin)?;
            since_build.iter_mut().for_each(|m| *m = 0.0);
        }
        let xs: &[D::Vector] = x;
        accel
            .par_chunks_mut(LIST_CHUNK)
            .zip(depth.par_chunks_mut(LIST_CHUNK))
            .zip(drift.par_chunks_mut(LIST_CHUNK))
            .zip(normal.par_chunks_mut(LIST_CHUNK))
            .zip(lists.par_iter())
            .enumerate()
            .for_each(|(c, ((((acc, depth), drift), normal), list))| {
                for (k, a) in acc.iter_mut().enumerate() {
                    let i = c * LIST_CHUNK + k;
                    let xi = xs[i];
                    let mut s = D::zero();
                    for &j in list.of(k) {
                        let d = xi - xs[j as usize];
                        // (The square root only for pairs within the cutoff: a third of a
                        // list lies in the skin.)
                        let r2 = D::norm_squared(d);
                        if r2 < cutoff2 && r2 > 0.0 {
                            let r = r2.sqrt();
                            s += d * (kernel.dw_dr(r) * v / r);
                        }
                    }
                    // The surface's push vanishes beyond the kernel's reach (P(d ≥ cutoff) = 0).
                    let min_depth = depth[k] - drift[k];
                    if is_near[i] && min_depth < cutoff {
                        // Measured where it stands (not moved since): the same query's result.
                        let (phi, n) = if drift[k] == 0.0 && depth[k].is_finite() {
                            (-depth[k], normal[k])
                        } else {
                            depth_measure(boundary, xi, min_depth)
                        };
                        (depth[k], normal[k], drift[k]) = (-phi, n, 0.0);
                        s += n * tables.plane((-phi).max(0.0));
                    }
                    *a = s * -2.0;
                }
            });
        let amax = accel
            .par_iter()
            .map(|&a| D::norm(a))
            .reduce(|| 0.0, f64::max);
        if !(amax > 0.0 && amax.is_finite()) {
            break;
        }
        let dt2 = 0.0625 * h / amax;
        x.par_iter_mut()
            .zip(accel.par_iter())
            .zip(drift.par_iter_mut())
            .zip(since_build.par_iter_mut())
            .for_each(|(((xi, &a), moved), since)| {
                let dx = D::norm(a * (0.5 * dt2));
                *xi += a * (0.5 * dt2);
                *moved += dx;
                *since += dx;
            });
        // Surface bounding: nothing beyond depth dp/2.
        let bound = 0.5 * dp;
        let measured: Vec<(u32, f64, D::Vector)> = near
            .par_iter()
            .filter_map(|&i| {
                let (xi, min_depth) = (x[i as usize], depth[i as usize] - drift[i as usize]);
                // Certainly deeper than the bound: nothing to do.
                if min_depth >= bound {
                    return None;
                }
                let (phi, n) = depth_measure(boundary, xi, min_depth);
                Some((i, phi, n))
            })
            .collect();
        for (i, phi, n) in measured {
            let i = i as usize;
            if phi > -bound {
                let xi = x[i] - n * (phi + bound);
                let dx = D::norm(xi - x[i]);
                drift[i] += dx;
                since_build[i] += dx;
                x[i] = xi;
            } else {
                // Not moved: the measurement stands for the next step's push.
                (depth[i], normal[i], drift[i]) = (-phi, n, 0.0);
            }
        }
    }
    Ok(())
}

/// The signed distance of a particle whose depth is at least `min_depth` (its last measured
/// depth less how far it has moved since; `−∞` when never measured): a particle certainly
/// inside skips the inside test ([`Boundary::signed_distance_on_side`]), bit-identical to the
/// full query.
fn depth_measure<D: Dim>(
    boundary: &dyn Boundary<D>,
    x: D::Vector,
    min_depth: f64,
) -> (f64, D::Vector) {
    if min_depth > 0.0 {
        boundary.signed_distance_on_side(x, true)
    } else {
        boundary.signed_distance(x)
    }
}

/// The report of a fitted set (module documentation).
pub fn report<D: Dim>(
    set: &ParticleSet<D>,
    boundary: &dyn Boundary<D>,
    dp: f64,
    kernel: &WendlandC2<D>,
    tables: &HalfSpaceIntegrals,
    relax_steps: usize,
) -> Result<FitReport, Error> {
    let x = set.positions();
    // (The scan-cone surface detection of sph_core::surface also flags second-layer particles
    // seen through the gaps of a relaxed, no longer cubic, outer layer: the depth selects.)
    let phis: Vec<f64> = x
        .par_iter()
        .map(|&xi| boundary.signed_distance(xi).0)
        .collect();
    let deviations: Vec<f64> = phis
        .iter()
        .filter(|&&phi| phi > -dp)
        .map(|&phi| (phi + 0.5 * dp).abs() / dp)
        .collect();
    let m = deviations.len().max(1) as f64;
    let rms = (deviations.iter().map(|d| d * d).sum::<f64>() / m).sqrt();
    let max = deviations.iter().copied().fold(0.0, f64::max);
    let cutoff = kernel.cutoff();
    let v = dp.powi(D::D as i32);
    let grid = CellGrid::<D>::build(x, cutoff)?;
    let volumes: Vec<f64> = x
        .par_iter()
        .zip(phis.par_iter())
        .map(|(&xi, &phi)| {
            let mut sum = 0.0;
            grid.for_each_candidate_at(xi, |_, xj| {
                let r = D::norm(xi - xj);
                if r < cutoff {
                    sum += kernel.w(r);
                }
            });
            // The missing neighbours' share: `∫ W` beyond the surface, over one particle volume.
            if phi > -cutoff {
                sum += tables.half_space((-phi).max(0.0)) / v;
            }
            1.0 / sum
        })
        .collect();
    let n = volumes.len() as f64;
    let mean = volumes.iter().sum::<f64>() / n;
    let var = volumes.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    Ok(FitReport {
        particles: x.len(),
        lattice_particles: x.len(),
        volume: set.total_volume(),
        mesh_volume: boundary.volume(),
        volume_scale: 1.0,
        surface_distance_rms: rms,
        surface_distance_max: max,
        volume_spread: var.sqrt() / mean,
        relax_steps,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use sph_core::{D2, D3};

    /// Q(d) from its definition ∫_d^R P(s) ds, by a nested midpoint rule on the tabulated P.
    fn half_by_plane_integral(t: &HalfSpaceIntegrals, support: f64, d: f64) -> f64 {
        let n = 20_000;
        let ds = (support - d) / n as f64;
        (0..n)
            .map(|k| t.plane(d + (k as f64 + 0.5) * ds))
            .sum::<f64>()
            * ds
    }

    fn check<D: Dim>() {
        let kernel = WendlandC2::<D>::from_spacing(1.0, RELAX_H_OVER_DP).unwrap();
        let t = HalfSpaceIntegrals::new(&kernel);
        let support = kernel.cutoff();
        // Half the kernel's unit integral lies beyond a plane through its centre.
        assert!(
            (t.half_space(0.0) - 0.5).abs() < 1e-6,
            "{}",
            t.half_space(0.0)
        );
        for f in [0.0, 0.1, 0.3, 0.6, 0.9] {
            let d = f * support;
            let (q, by_p) = (t.half_space(d), half_by_plane_integral(&t, support, d));
            assert!((q - by_p).abs() < 2e-5, "d = {d}: Q {q} against ∫P {by_p}");
        }
        assert_eq!(t.half_space(support), 0.0);
    }

    /// The lists' claim: after every particle has moved less than `skin / 2` since the build,
    /// every pair closer than `cutoff` is in the lists (so the sum over the lists is the sum
    /// over all pairs within `cutoff`, the particles a per-step grid would give).
    #[test]
    fn neighbour_lists_hold_every_pair_within_cutoff_until_a_half_skin_move() {
        let (cutoff, skin) = (2.6, SKIN_OVER_DP);
        // A jittered lattice of 12³ (a deterministic hash for the jitter).
        let jitter = |i: usize, k: usize| {
            let h = (i as u64 * 3 + k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11;
            h as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut x: Vec<glam::DVec3> = (0..12 * 12 * 12)
            .map(|i| {
                glam::DVec3::new((i % 12) as f64, (i / 12 % 12) as f64, (i / 144) as f64)
                    + glam::DVec3::new(jitter(i, 0), jitter(i, 1), jitter(i, 2)) * 0.3
            })
            .collect();
        let mut lists = Vec::new();
        build_lists::<D3>(&mut lists, &x, cutoff + skin).unwrap();
        // Move every particle by just under skin/2 in a varying direction.
        for (i, xi) in x.iter_mut().enumerate() {
            let d = glam::DVec3::new(jitter(i, 5), jitter(i, 6), jitter(i, 7));
            *xi += d.normalize() * (0.499 * skin);
        }
        let mut pairs = 0;
        for i in 0..x.len() {
            let chunk = &lists[i / LIST_CHUNK];
            let listed: Vec<u32> = chunk.of(i % LIST_CHUNK).to_vec();
            for j in 0..x.len() {
                if j != i && (x[i] - x[j]).length() < cutoff {
                    assert!(listed.contains(&(j as u32)), "pair {i} {j} missing");
                    pairs += 1;
                }
            }
            assert!(!listed.contains(&(i as u32)));
        }
        assert!(pairs > 50 * x.len(), "{pairs}");
    }

    #[test]
    fn the_half_space_integral_is_the_integral_of_the_plane_integral() {
        check::<D2>();
        check::<D3>();
    }
}
