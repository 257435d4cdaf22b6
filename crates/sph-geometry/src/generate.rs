//! Particle generators: shapes, the cell-centred lattice fill, polar ring/tube generators and the
//! [`ParticleSet`] a scene builds its bodies from.
//!
//! # Shapes
//! A [`Shape`] answers "is this point inside?" and gives a bounding box. Primitives: [`Aabb`]
//! (rectangle / box, both dimensions), [`Annulus`] (2D ring or disc), [`HollowSphere`] (3D shell or
//! ball), [`Cylinder`] (3D solid cylinder or tube along any axis) and [`FnShape`] (any predicate).
//! Combinators: [`Union`], [`Difference`], [`Intersection`], also reachable as
//! `a.union(b)`, `a.difference(b)`, `a.intersection(b)`. Every primitive treats its boundary as
//! inside (closed sets); with the cell-centred lattice this never matters (see below).
//!
//! # Cell-centred lattice
//! [`Lattice`] with spacing `dp` and origin `o` places particle candidates at cell centres
//! `o + (n + ½) dp` per axis (`n` any integer) and [`ParticleSet::fill`] keeps the candidates the
//! shape contains, each with volume `V = dp^d` (docs/methods.md: `V⁰ = dp^d`).
//!
//! Membership is decided at cell centres, which lie half a spacing away from every lattice-cell
//! face. When a body's boundaries lie on cell faces (choose `o` on a corner of the body and
//! lengths that are whole multiples of `dp`), every candidate is at least `dp/2` from every
//! boundary, so floating-point round-off of order `1e-16·L` cannot flip a decision and the count
//! is exact: a 0.2 × 0.02 plate at `dp = 0.002` gives 100 × 10 particles, a 1 × 1 × 6 column at
//! `H/dp = 6` gives 1,296. Only a boundary passing exactly through a cell centre is ambiguous
//! (e.g. a plate of odd `H/dp` centred on a lattice whose origin is the plate's centre line): avoid
//! it by anchoring the origin on a face of the body.
//!
//! # Tags
//! Each particle carries a `u32` of bit flags; bit `k` means "in the `k`-th named region" of the
//! set ([`ParticleSet::regions`]). Regions are created by name ([`ParticleSet::tag_region`] with a
//! shape, [`ParticleSet::tag_where`] with a predicate, [`ParticleSet::tag_particles`] with
//! indices) and read back as index lists for constraints and probes ([`ParticleSet::tagged`],
//! [`ParticleSet::untagged`]). A particle may be in several regions; at most 32 regions per set.
//! Tags follow their particles through [`ParticleSet::permute`], [`ParticleSet::retain`] and
//! [`ParticleSet::extend`] (which merges regions by name).
//!
//! # Particle budget
//! Every generator checks the particle budget of [`sph_core::budget`] before it allocates: the
//! polar generators compute their count in closed form first, the lattice fill stops as soon as
//! it would keep one particle too many. Parameters that would need more memory than the budget
//! (or more than 2³² − 1 particles, or a count that overflows every integer) give
//! [`Error::TooManyParticles`] with the estimate and the limit, never a panic or an abort.

use glam::{DVec2, DVec3};
use sph_core::budget;
use sph_core::dim::{Dim, D2, D3};
use sph_core::error::{check_non_negative, check_positive, Error};
use std::f64::consts::PI;

mod polar;
mod shapes;
pub use polar::*;
pub use shapes::*;
use shapes::{check_radii, component_max, component_min};

/// Largest number of lattice candidates a fill may visit (guards against a `dp` far too small
/// for the shape, which would otherwise exhaust memory or time).
const MAX_CANDIDATES: u64 = 1 << 32;

/// Largest number of named regions in one [`ParticleSet`] (one bit of the `u32` tag each).
pub const MAX_REGIONS: usize = 32;

// ---------------------------------------------------------------------------------------------
// Lattice
// ---------------------------------------------------------------------------------------------

/// A cell-centred Cartesian lattice: candidates at `origin + (n + ½) dp` per axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lattice<D: Dim> {
    dp: f64,
    origin: D::Vector,
}

impl<D: Dim> Lattice<D> {
    /// A lattice of spacing `dp` (finite, `> 0`; error names `dp`) whose cell faces pass through
    /// `origin`. Put `origin` on a corner (or face) of the body so its boundaries lie on faces.
    pub fn new(dp: f64, origin: D::Vector) -> Result<Self, Error> {
        check_positive("dp", dp)?;
        if !D::is_finite(origin) {
            return Err(Error::invalid("origin", format!("{origin:?}"), "finite"));
        }
        Ok(Self { dp, origin })
    }

    /// The spacing.
    pub fn dp(&self) -> f64 {
        self.dp
    }

    /// A point on cell faces (cell centres are at `origin + (n + ½) dp`).
    pub fn origin(&self) -> D::Vector {
        self.origin
    }

    /// The volume of one cell, `dp^d`.
    pub fn cell_volume(&self) -> f64 {
        self.dp.powi(D::D as i32)
    }

    /// The cell centres that `shape` contains, in lattice order (first axis fastest).
    pub fn points(&self, shape: &dyn Shape<D>) -> Result<Vec<D::Vector>, Error> {
        let (lo, hi) = shape.bounds();
        if !D::is_finite(lo) || !D::is_finite(hi) {
            return Err(Error::invalid(
                "shape bounds",
                format!("{lo:?} .. {hi:?}"),
                "finite",
            ));
        }
        // Index range per axis: every centre in [lo, hi], plus one cell of margin each side so
        // that round-off in the division can never drop a candidate (contains() decides).
        let mut first = [0i64; 3];
        let mut last = [0i64; 3];
        let mut candidates: u64 = 1;
        for k in 0..D::D {
            let o = D::component(self.origin, k);
            let a = ((D::component(lo, k) - o) / self.dp - 0.5).floor() - 1.0;
            let b = ((D::component(hi, k) - o) / self.dp - 0.5).ceil() + 1.0;
            if b < a {
                return Ok(Vec::new());
            }
            if (b - a) >= MAX_CANDIDATES as f64 {
                return Err(too_fine(self.dp));
            }
            first[k] = a as i64;
            last[k] = b as i64;
            candidates = candidates.saturating_mul((last[k] - first[k] + 1) as u64);
        }
        if candidates > MAX_CANDIDATES {
            return Err(too_fine(self.dp));
        }
        let centre = |k: usize, n: i64| D::component(self.origin, k) + (n as f64 + 0.5) * self.dp;
        // The particle budget (sph_core::budget) is checked as the points are kept, so memory
        // never grows past it; when it runs out, the count is estimated from the share of
        // the candidates kept so far.
        let allowance = budget::remaining::<D>();
        let mut visited: u64 = 0;
        let mut out = Vec::new();
        for n2 in first[2]..=last[2] {
            for n1 in first[1]..=last[1] {
                for n0 in first[0]..=last[0] {
                    let mut c = [0.0; 3];
                    for (k, &n) in [n0, n1, n2].iter().enumerate().take(D::D) {
                        c[k] = centre(k, n);
                    }
                    let x = D::vector(c);
                    visited += 1;
                    if shape.contains(x) {
                        if out.len() as u64 >= allowance {
                            let estimate =
                                (out.len() + 1) as f64 * candidates as f64 / visited as f64;
                            return Err(budget::exceeded::<D>(
                                estimate,
                                &format!("the lattice fill at dp = {:?}", self.dp),
                            ));
                        }
                        out.push(x);
                    }
                }
            }
        }
        budget::book::<D>(out.len() as u64);
        Ok(out)
    }
}

fn too_fine(dp: f64) -> Error {
    Error::invalid(
        "dp",
        dp,
        &format!("large enough that the shape's bounding box holds at most {MAX_CANDIDATES} lattice cells"),
    )
}

// ---------------------------------------------------------------------------------------------
// Particle sets
// ---------------------------------------------------------------------------------------------

/// Generated particles: positions, volumes and region tags (structure of arrays, all the same
/// length). A scene turns a set into a body (`m = ρ0 V`) and its regions into constraint lists.
#[derive(Clone, Debug, PartialEq)]
pub struct ParticleSet<D: Dim> {
    positions: Vec<D::Vector>,
    volumes: Vec<f64>,
    tags: Vec<u32>,
    regions: Vec<String>,
    /// The spacing the generator used (`None` for sets assembled from parts or from sets of
    /// different spacings).
    spacing: Option<f64>,
}

impl<D: Dim> Default for ParticleSet<D> {
    fn default() -> Self {
        Self::new()
    }
}

impl<D: Dim> ParticleSet<D> {
    /// An empty set (to [`extend`](Self::extend) with bodies).
    pub fn new() -> Self {
        Self {
            positions: Vec::new(),
            volumes: Vec::new(),
            tags: Vec::new(),
            regions: Vec::new(),
            spacing: None,
        }
    }

    /// Particles from given positions and volumes (no regions). Errors if the lengths differ,
    /// a position is not finite or a volume is not finite and `> 0`.
    pub fn from_parts(positions: Vec<D::Vector>, volumes: Vec<f64>) -> Result<Self, Error> {
        if positions.len() != volumes.len() {
            return Err(Error::invalid(
                "volumes",
                format!("{} entries", volumes.len()),
                &format!("one per position ({})", positions.len()),
            ));
        }
        if let Some(i) = positions.iter().position(|&x| !D::is_finite(x)) {
            return Err(Error::invalid(
                &format!("positions[{i}]"),
                format!("{:?}", positions[i]),
                "finite",
            ));
        }
        for (i, &v) in volumes.iter().enumerate() {
            check_positive(&format!("volumes[{i}]"), v)?;
        }
        let n = positions.len();
        Ok(Self {
            positions,
            volumes,
            tags: vec![0; n],
            regions: Vec::new(),
            spacing: None,
        })
    }

    /// The cell centres of `lattice` inside `shape`, each of volume `dp^d` (module docs: exact
    /// counts when boundaries lie on cell faces). Errors with [`Error::EmptyBody`] if no centre
    /// is inside.
    pub fn fill(lattice: &Lattice<D>, shape: &dyn Shape<D>) -> Result<Self, Error> {
        let positions = lattice.points(shape)?;
        if positions.is_empty() {
            return Err(Error::EmptyBody {
                body: format!("lattice fill at dp = {}", lattice.dp()),
            });
        }
        let n = positions.len();
        Ok(Self {
            positions,
            volumes: vec![lattice.cell_volume(); n],
            tags: vec![0; n],
            regions: Vec::new(),
            spacing: Some(lattice.dp()),
        })
    }

    /// The particle spacing the generator used: the lattice spacing of a fill, the `dp` of a
    /// polar generator; kept by [`extend`](Self::extend) only when both sets agree; `None` for
    /// sets made [`from_parts`](Self::from_parts).
    pub fn spacing(&self) -> Option<f64> {
        self.spacing
    }

    /// Records the spacing a set was generated with (for generators outside this module).
    pub fn with_spacing(mut self, dp: f64) -> Self {
        self.spacing = Some(dp);
        self
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Whether the set has no particle.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// Positions.
    pub fn positions(&self) -> &[D::Vector] {
        &self.positions
    }

    /// Volumes (`V⁰`; masses are `ρ0 V⁰`).
    pub fn volumes(&self) -> &[f64] {
        &self.volumes
    }

    /// Masses `ρ0 V` for a reference density `rho0`.
    pub fn masses(&self, rho0: f64) -> Vec<f64> {
        self.volumes.iter().map(|v| rho0 * v).collect()
    }

    /// Raw tag bits per particle (bit `k` = region `regions()[k]`).
    pub fn tags(&self) -> &[u32] {
        &self.tags
    }

    /// Region names in bit order.
    pub fn regions(&self) -> &[String] {
        &self.regions
    }

    /// Positions, volumes and tags, consuming the set.
    pub fn into_parts(self) -> (Vec<D::Vector>, Vec<f64>, Vec<u32>) {
        (self.positions, self.volumes, self.tags)
    }

    /// Sum of the volumes.
    pub fn total_volume(&self) -> f64 {
        self.volumes.iter().sum()
    }

    /// Componentwise `(min, max)` of the positions, `None` when empty.
    pub fn bounds(&self) -> Option<(D::Vector, D::Vector)> {
        let first = *self.positions.first()?;
        Some(self.positions.iter().fold((first, first), |(lo, hi), &x| {
            (component_min::<D>(lo, x), component_max::<D>(hi, x))
        }))
    }

    /// The tag bit of region `name`, if it exists.
    pub fn region_bit(&self, name: &str) -> Option<u32> {
        self.regions
            .iter()
            .position(|r| r == name)
            .map(|k| 1u32 << k)
    }

    /// The bit of region `name`, creating the region if new.
    fn bit_or_create(&mut self, name: &str) -> Result<u32, Error> {
        if let Some(bit) = self.region_bit(name) {
            return Ok(bit);
        }
        if self.regions.len() >= MAX_REGIONS {
            return Err(Error::invalid(
                "region",
                name,
                &format!("at most {MAX_REGIONS} regions per particle set"),
            ));
        }
        self.regions.push(name.to_string());
        Ok(1u32 << (self.regions.len() - 1))
    }

    /// Adds every particle `i` with `pred(i, x_i)` to region `name` (created if new; earlier
    /// members stay). Returns the region's tag bit.
    pub fn tag_where(
        &mut self,
        name: &str,
        mut pred: impl FnMut(usize, D::Vector) -> bool,
    ) -> Result<u32, Error> {
        let bit = self.bit_or_create(name)?;
        for (i, (tag, &x)) in self.tags.iter_mut().zip(&self.positions).enumerate() {
            if pred(i, x) {
                *tag |= bit;
            }
        }
        Ok(bit)
    }

    /// Adds the particles inside `shape` to region `name` (created if new). Returns the bit.
    pub fn tag_region(&mut self, name: &str, shape: &dyn Shape<D>) -> Result<u32, Error> {
        self.tag_where(name, |_, x| shape.contains(x))
    }

    /// Adds the listed particles to region `name` (created if new); errors on an index out of
    /// range (before changing anything). Returns the bit.
    pub fn tag_particles(&mut self, name: &str, indices: &[u32]) -> Result<u32, Error> {
        if let Some(&i) = indices.iter().find(|&&i| i as usize >= self.len()) {
            return Err(Error::invalid(
                "particle index",
                i,
                &format!("< {} (particles in the set)", self.len()),
            ));
        }
        let bit = self.bit_or_create(name)?;
        for &i in indices {
            self.tags[i as usize] |= bit;
        }
        Ok(bit)
    }

    fn bit(&self, name: &str) -> Result<u32, Error> {
        self.region_bit(name).ok_or_else(|| {
            Error::invalid(
                "region",
                name,
                &format!("one of the set's regions {:?}", self.regions),
            )
        })
    }

    /// Indices (ascending) of the particles in region `name`; errors on an unknown name, so a
    /// misspelt region never silently yields an empty constraint.
    pub fn tagged(&self, name: &str) -> Result<Vec<u32>, Error> {
        let bit = self.bit(name)?;
        Ok(self.indices_where(|t| t & bit != 0))
    }

    /// Indices (ascending) of the particles not in region `name` (e.g. the free part of a
    /// clamped plate); errors on an unknown name.
    pub fn untagged(&self, name: &str) -> Result<Vec<u32>, Error> {
        let bit = self.bit(name)?;
        Ok(self.indices_where(|t| t & bit == 0))
    }

    /// Whether particle `i` is in region `name` (false for an unknown name).
    pub fn is_tagged(&self, i: usize, name: &str) -> bool {
        self.region_bit(name)
            .is_some_and(|bit| self.tags.get(i).is_some_and(|t| t & bit != 0))
    }

    /// Indices (ascending) of the particles whose position satisfies `pred` (a region chosen
    /// by a condition rather than a [`Shape`]).
    pub fn select(&self, pred: impl Fn(D::Vector) -> bool) -> Vec<u32> {
        (0..self.len() as u32)
            .filter(|&i| pred(self.positions[i as usize]))
            .collect()
    }

    /// Indices (ascending) of the particles inside `shape`.
    pub fn inside(&self, shape: &dyn Shape<D>) -> Vec<u32> {
        self.select(|x| shape.contains(x))
    }

    fn indices_where(&self, f: impl Fn(u32) -> bool) -> Vec<u32> {
        self.tags
            .iter()
            .enumerate()
            .filter(|(_, &t)| f(t))
            .map(|(i, _)| i as u32)
            .collect()
    }

    /// Reorders every field by `perm` (`perm[new] = old`, the convention of
    /// [`sph_core::neighbor::apply_permutation`]); errors unless `perm` is a permutation of
    /// `0..len`.
    pub fn permute(&mut self, perm: &[u32]) -> Result<(), Error> {
        let n = self.len();
        if perm.len() != n {
            return Err(Error::invalid(
                "permutation length",
                perm.len(),
                &format!("= {n} (particles in the set)"),
            ));
        }
        let mut seen = vec![false; n];
        for &old in perm {
            let old = old as usize;
            if old >= n || std::mem::replace(&mut seen[old], true) {
                return Err(Error::invalid(
                    "permutation",
                    old,
                    "each index 0..len exactly once",
                ));
            }
        }
        use sph_core::neighbor::apply_permutation;
        self.positions = apply_permutation(perm, &self.positions);
        self.volumes = apply_permutation(perm, &self.volumes);
        self.tags = apply_permutation(perm, &self.tags);
        Ok(())
    }

    /// Keeps the particles `i` with `keep(i, x_i)` (in order, tags kept); returns how many were
    /// removed. Use it to cut holes a shape cannot express or to thin a set.
    pub fn retain(&mut self, mut keep: impl FnMut(usize, D::Vector) -> bool) -> usize {
        let mask: Vec<bool> = self
            .positions
            .iter()
            .enumerate()
            .map(|(i, &x)| keep(i, x))
            .collect();
        let before = self.len();
        let mut it = mask.iter();
        self.positions.retain(|_| *it.next().unwrap());
        let mut it = mask.iter();
        self.volumes.retain(|_| *it.next().unwrap());
        let mut it = mask.iter();
        self.tags.retain(|_| *it.next().unwrap());
        before - self.len()
    }

    /// Index of the particle nearest to `point` (lowest index on a tie), `None` when empty.
    pub fn nearest(&self, point: D::Vector) -> Option<usize> {
        let mut best: Option<(usize, f64)> = None;
        for (i, &x) in self.positions.iter().enumerate() {
            let d2 = D::norm_squared(x - point);
            if best.is_none_or(|(_, b)| d2 < b) {
                best = Some((i, d2));
            }
        }
        best.map(|(i, _)| i)
    }

    /// Moves every particle by `offset`.
    pub fn translate(&mut self, offset: D::Vector) {
        for x in &mut self.positions {
            *x += offset;
        }
    }

    /// Appends `other`'s particles (for multi-body scenes or composite bodies), merging regions by
    /// name so each keeps its members. Returns the index range of the appended particles.
    /// Errors (leaving `self` unchanged) if the merged set would exceed [`MAX_REGIONS`].
    pub fn extend(&mut self, other: &ParticleSet<D>) -> Result<std::ops::Range<usize>, Error> {
        let new_names = other
            .regions
            .iter()
            .filter(|r| !self.regions.contains(r))
            .count();
        if self.regions.len() + new_names > MAX_REGIONS {
            return Err(Error::invalid(
                "region",
                format!("{} after merging", self.regions.len() + new_names),
                &format!("at most {MAX_REGIONS} regions per particle set"),
            ));
        }
        let map: Vec<u32> = other
            .regions
            .iter()
            .map(|r| self.bit_or_create(r))
            .collect::<Result<_, _>>()?;
        let start = self.len();
        self.spacing = match (self.is_empty(), self.spacing, other.spacing) {
            (true, _, b) => b,
            (false, Some(a), Some(b)) if a == b => Some(a),
            _ => None,
        };
        self.positions.extend_from_slice(&other.positions);
        self.volumes.extend_from_slice(&other.volumes);
        self.tags.extend(other.tags.iter().map(|&t| {
            map.iter()
                .enumerate()
                .filter(|(k, _)| t & (1u32 << k) != 0)
                .fold(0u32, |acc, (_, &bit)| acc | bit)
        }));
        Ok(start..self.len())
    }
}

/// Distance from each point to its nearest other point (`f64::INFINITY` if none lies within
/// `radius`), with a cell list of edge `radius`: a spacing check for generated sets (a gap or a
/// near-coincident pair shows as an outlier).
pub fn nearest_distances<D: Dim>(positions: &[D::Vector], radius: f64) -> Result<Vec<f64>, Error> {
    let grid = sph_core::neighbor::CellGrid::<D>::build(positions, radius)?;
    Ok(positions
        .iter()
        .enumerate()
        .map(|(i, &x)| {
            let mut best = f64::INFINITY;
            grid.for_each_candidate_at(x, |j, xj| {
                if j as usize != i {
                    best = best.min(D::norm(x - xj));
                }
            });
            if best <= radius {
                best
            } else {
                f64::INFINITY
            }
        })
        .collect())
}
