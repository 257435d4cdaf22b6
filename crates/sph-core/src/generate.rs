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
//! Every generator checks the particle budget of [`crate::budget`] before it allocates: the
//! polar generators compute their count in closed form first, the lattice fill stops as soon as
//! it would keep one particle too many. Parameters that would need more memory than the budget
//! (or more than 2³² − 1 particles, or a count that overflows every integer) give
//! [`Error::TooManyParticles`] with the estimate and the limit, never a panic or an abort.

use crate::budget;
use crate::dim::{Dim, D2, D3};
use crate::error::{check_non_negative, check_positive, Error};
use glam::{DVec2, DVec3};
use std::f64::consts::PI;

/// Largest number of lattice candidates a fill may visit (guards against a `dp` far too small
/// for the shape, which would otherwise exhaust memory or time).
const MAX_CANDIDATES: u64 = 1 << 32;

/// Largest number of named regions in one [`ParticleSet`] (one bit of the `u32` tag each).
pub const MAX_REGIONS: usize = 32;

// ---------------------------------------------------------------------------------------------
// Shapes
// ---------------------------------------------------------------------------------------------

/// A region of space: a membership test and a bounding box.
pub trait Shape<D: Dim>: Send + Sync {
    /// Whether `x` lies in the shape (primitives include their boundary).
    fn contains(&self, x: D::Vector) -> bool;

    /// An axis-aligned box `(min, max)` that contains the whole shape (need not be tight).
    fn bounds(&self) -> (D::Vector, D::Vector);

    /// The union of `self` and `other`.
    fn union<S: Shape<D> + 'static>(self, other: S) -> Union<D>
    where
        Self: Sized + 'static,
    {
        Union::new(vec![Box::new(self), Box::new(other)])
    }

    /// The points of `self` not in `other`.
    fn difference<S: Shape<D> + 'static>(self, other: S) -> Difference<D>
    where
        Self: Sized + 'static,
    {
        Difference::new(self, other)
    }

    /// The points in both `self` and `other`.
    fn intersection<S: Shape<D> + 'static>(self, other: S) -> Intersection<D>
    where
        Self: Sized + 'static,
    {
        Intersection::new(vec![Box::new(self), Box::new(other)])
    }

    /// The shape as a trait object (for collections of shapes).
    fn boxed(self) -> Box<dyn Shape<D>>
    where
        Self: Sized + 'static,
    {
        Box::new(self)
    }
}

impl<D: Dim, S: Shape<D> + ?Sized> Shape<D> for Box<S> {
    fn contains(&self, x: D::Vector) -> bool {
        (**self).contains(x)
    }
    fn bounds(&self) -> (D::Vector, D::Vector) {
        (**self).bounds()
    }
}

impl<D: Dim, S: Shape<D> + ?Sized> Shape<D> for &S {
    fn contains(&self, x: D::Vector) -> bool {
        (**self).contains(x)
    }
    fn bounds(&self) -> (D::Vector, D::Vector) {
        (**self).bounds()
    }
}

fn component_min<D: Dim>(a: D::Vector, b: D::Vector) -> D::Vector {
    let mut out = a;
    for k in 0..D::D {
        D::set_component(&mut out, k, D::component(a, k).min(D::component(b, k)));
    }
    out
}

fn component_max<D: Dim>(a: D::Vector, b: D::Vector) -> D::Vector {
    let mut out = a;
    for k in 0..D::D {
        D::set_component(&mut out, k, D::component(a, k).max(D::component(b, k)));
    }
    out
}

/// An axis-aligned rectangle (2D) or box (3D), boundary included.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb<D: Dim> {
    min: D::Vector,
    max: D::Vector,
}

impl<D: Dim> Aabb<D> {
    /// The box between corners `min` and `max`; every component must be finite with
    /// `min < max` (error names `min`/`max`).
    pub fn new(min: D::Vector, max: D::Vector) -> Result<Self, Error> {
        if !D::is_finite(min) {
            return Err(Error::invalid("min", format!("{min:?}"), "finite"));
        }
        for k in 0..D::D {
            let (a, b) = (D::component(min, k), D::component(max, k));
            if !(b.is_finite() && b > a) {
                return Err(Error::invalid(
                    "max",
                    format!("{max:?}"),
                    &format!("finite and > min = {min:?} in every component"),
                ));
            }
        }
        Ok(Self { min, max })
    }

    /// The box with corner `min` and edge lengths `size` (all `> 0`).
    pub fn from_corner(min: D::Vector, size: D::Vector) -> Result<Self, Error> {
        Self::new(min, min + size)
    }

    /// The lower corner.
    pub fn min(&self) -> D::Vector {
        self.min
    }

    /// The upper corner.
    pub fn max(&self) -> D::Vector {
        self.max
    }

    /// Length, area or volume: the product of the edge lengths.
    pub fn measure(&self) -> f64 {
        (0..D::D)
            .map(|k| D::component(self.max, k) - D::component(self.min, k))
            .product()
    }
}

impl<D: Dim> Shape<D> for Aabb<D> {
    fn contains(&self, x: D::Vector) -> bool {
        (0..D::D).all(|k| {
            let c = D::component(x, k);
            c >= D::component(self.min, k) && c <= D::component(self.max, k)
        })
    }
    fn bounds(&self) -> (D::Vector, D::Vector) {
        (self.min, self.max)
    }
}

/// A 2D ring `r_in ≤ |x − centre| ≤ r_out`; `r_in = 0` gives a disc.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Annulus {
    centre: DVec2,
    r_in: f64,
    r_out: f64,
}

impl Annulus {
    /// The ring with the given centre and radii (`0 ≤ r_in < r_out`, finite).
    pub fn new(centre: DVec2, r_in: f64, r_out: f64) -> Result<Self, Error> {
        check_radii(r_in, r_out)?;
        if !centre.is_finite() {
            return Err(Error::invalid("centre", centre, "finite"));
        }
        Ok(Self {
            centre,
            r_in,
            r_out,
        })
    }

    /// The disc of radius `r` (`> 0`).
    pub fn disc(centre: DVec2, r: f64) -> Result<Self, Error> {
        Self::new(centre, 0.0, r)
    }

    /// The area `π (r_out² − r_in²)`.
    pub fn area(&self) -> f64 {
        PI * (self.r_out * self.r_out - self.r_in * self.r_in)
    }
}

impl Shape<D2> for Annulus {
    fn contains(&self, x: DVec2) -> bool {
        let r2 = (x - self.centre).length_squared();
        r2 >= self.r_in * self.r_in && r2 <= self.r_out * self.r_out
    }
    fn bounds(&self) -> (DVec2, DVec2) {
        (self.centre - self.r_out, self.centre + self.r_out)
    }
}

/// A 3D spherical shell `r_in ≤ |x − centre| ≤ r_out`; `r_in = 0` gives a ball.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HollowSphere {
    centre: DVec3,
    r_in: f64,
    r_out: f64,
}

impl HollowSphere {
    /// The shell with the given centre and radii (`0 ≤ r_in < r_out`, finite).
    pub fn new(centre: DVec3, r_in: f64, r_out: f64) -> Result<Self, Error> {
        check_radii(r_in, r_out)?;
        if !centre.is_finite() {
            return Err(Error::invalid("centre", centre, "finite"));
        }
        Ok(Self {
            centre,
            r_in,
            r_out,
        })
    }

    /// The solid ball of radius `r` (`> 0`).
    pub fn ball(centre: DVec3, r: f64) -> Result<Self, Error> {
        Self::new(centre, 0.0, r)
    }

    /// The volume `4π/3 (r_out³ − r_in³)`.
    pub fn volume(&self) -> f64 {
        4.0 / 3.0 * PI * (self.r_out.powi(3) - self.r_in.powi(3))
    }
}

impl Shape<D3> for HollowSphere {
    fn contains(&self, x: DVec3) -> bool {
        let r2 = (x - self.centre).length_squared();
        r2 >= self.r_in * self.r_in && r2 <= self.r_out * self.r_out
    }
    fn bounds(&self) -> (DVec3, DVec3) {
        (self.centre - self.r_out, self.centre + self.r_out)
    }
}

/// A 3D cylinder (or tube) along an arbitrary axis: points `x` with
/// `0 ≤ (x − base)·axis ≤ length` and `r_in ≤` distance from the axis `≤ r_out`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cylinder {
    base: DVec3,
    axis: DVec3,
    r_in: f64,
    r_out: f64,
    length: f64,
}

impl Cylinder {
    /// A solid cylinder: centre of the base disc, axis direction (normalised here; must be
    /// non-zero), radius and length along the axis.
    pub fn new(base: DVec3, axis: DVec3, radius: f64, length: f64) -> Result<Self, Error> {
        Self::tube(base, axis, 0.0, radius, length)
    }

    /// A tube (hollow cylinder) with inner radius `r_in` (`0` = solid) and outer radius `r_out`.
    pub fn tube(
        base: DVec3,
        axis: DVec3,
        r_in: f64,
        r_out: f64,
        length: f64,
    ) -> Result<Self, Error> {
        check_radii(r_in, r_out)?;
        check_positive("length", length)?;
        if !base.is_finite() {
            return Err(Error::invalid("base", base, "finite"));
        }
        let axis = axis
            .try_normalize()
            .ok_or_else(|| Error::invalid("axis", axis, "finite and non-zero"))?;
        Ok(Self {
            base,
            axis,
            r_in,
            r_out,
            length,
        })
    }

    /// The volume `π (r_out² − r_in²) length`.
    pub fn volume(&self) -> f64 {
        PI * (self.r_out * self.r_out - self.r_in * self.r_in) * self.length
    }
}

impl Shape<D3> for Cylinder {
    fn contains(&self, x: DVec3) -> bool {
        let d = x - self.base;
        let s = d.dot(self.axis);
        if s < 0.0 || s > self.length {
            return false;
        }
        let r2 = (d - self.axis * s).length_squared();
        r2 >= self.r_in * self.r_in && r2 <= self.r_out * self.r_out
    }
    fn bounds(&self) -> (DVec3, DVec3) {
        let top = self.base + self.axis * self.length;
        // A disc of radius r normal to unit a extends r √(1 − a_k²) along axis k.
        let a2 = self.axis * self.axis;
        let e = (DVec3::ONE - a2).max(DVec3::ZERO).sqrt() * self.r_out;
        (self.base.min(top) - e, self.base.max(top) + e)
    }
}

fn check_radii(r_in: f64, r_out: f64) -> Result<(), Error> {
    check_non_negative("r_in", r_in)?;
    if !(r_out.is_finite() && r_out > r_in) {
        return Err(Error::invalid(
            "r_out",
            r_out,
            &format!("finite and > r_in = {r_in}"),
        ));
    }
    Ok(())
}

/// A shape given by a predicate and a bounding box (e.g. the slots of a stent).
pub struct FnShape<D: Dim, F> {
    bounds: (D::Vector, D::Vector),
    f: F,
}

impl<D: Dim, F: Fn(D::Vector) -> bool + Send + Sync> FnShape<D, F> {
    /// The points inside `bounds = (min, max)` for which `f` is true (`f` is only ever called
    /// inside the bounds by a lattice fill, but [`Shape::contains`] checks the bounds too).
    pub fn new(bounds: (D::Vector, D::Vector), f: F) -> Self {
        Self { bounds, f }
    }
}

impl<D: Dim, F: Fn(D::Vector) -> bool + Send + Sync> Shape<D> for FnShape<D, F> {
    fn contains(&self, x: D::Vector) -> bool {
        let (lo, hi) = self.bounds;
        (0..D::D).all(|k| {
            let c = D::component(x, k);
            c >= D::component(lo, k) && c <= D::component(hi, k)
        }) && (self.f)(x)
    }
    fn bounds(&self) -> (D::Vector, D::Vector) {
        self.bounds
    }
}

/// The union of shapes (a point is inside if any part contains it).
pub struct Union<D: Dim> {
    parts: Vec<Box<dyn Shape<D>>>,
}

impl<D: Dim> Union<D> {
    /// The union of `parts` (an empty union contains nothing).
    pub fn new(parts: Vec<Box<dyn Shape<D>>>) -> Self {
        Self { parts }
    }

    /// Adds one more part.
    pub fn with<S: Shape<D> + 'static>(mut self, part: S) -> Self {
        self.parts.push(Box::new(part));
        self
    }
}

impl<D: Dim> Shape<D> for Union<D> {
    fn contains(&self, x: D::Vector) -> bool {
        self.parts.iter().any(|p| p.contains(x))
    }
    fn bounds(&self) -> (D::Vector, D::Vector) {
        let mut it = self.parts.iter().map(|p| p.bounds());
        match it.next() {
            None => (D::zero(), D::zero()),
            Some(first) => it.fold(first, |(lo, hi), (l, h)| {
                (component_min::<D>(lo, l), component_max::<D>(hi, h))
            }),
        }
    }
}

/// The points of `base` that are not in `cut` (boundary of `cut` excluded from the result).
pub struct Difference<D: Dim> {
    base: Box<dyn Shape<D>>,
    cut: Box<dyn Shape<D>>,
}

impl<D: Dim> Difference<D> {
    /// `base` minus `cut`.
    pub fn new<A: Shape<D> + 'static, B: Shape<D> + 'static>(base: A, cut: B) -> Self {
        Self {
            base: Box::new(base),
            cut: Box::new(cut),
        }
    }
}

impl<D: Dim> Shape<D> for Difference<D> {
    fn contains(&self, x: D::Vector) -> bool {
        self.base.contains(x) && !self.cut.contains(x)
    }
    fn bounds(&self) -> (D::Vector, D::Vector) {
        self.base.bounds()
    }
}

/// The points every part contains.
pub struct Intersection<D: Dim> {
    parts: Vec<Box<dyn Shape<D>>>,
}

impl<D: Dim> Intersection<D> {
    /// The intersection of `parts` (must be non-empty to contain anything).
    pub fn new(parts: Vec<Box<dyn Shape<D>>>) -> Self {
        Self { parts }
    }
}

impl<D: Dim> Shape<D> for Intersection<D> {
    fn contains(&self, x: D::Vector) -> bool {
        !self.parts.is_empty() && self.parts.iter().all(|p| p.contains(x))
    }
    fn bounds(&self) -> (D::Vector, D::Vector) {
        let mut it = self.parts.iter().map(|p| p.bounds());
        match it.next() {
            None => (D::zero(), D::zero()),
            Some(first) => it.fold(first, |(lo, hi), (l, h)| {
                (component_max::<D>(lo, l), component_min::<D>(hi, h))
            }),
        }
    }
}

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
        // The particle budget (crate::budget) is checked as the points are kept, so memory
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
    /// [`crate::neighbor::apply_permutation`]); errors unless `perm` is a permutation of
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
        use crate::neighbor::apply_permutation;
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

// ---------------------------------------------------------------------------------------------
// Polar generators and convenience fills
// ---------------------------------------------------------------------------------------------

/// Layer radii of a ring `[r_in, r_out]` split into `n = max(1, round((r_out − r_in)/dp))`
/// layers of equal thickness `dr`; returns `(dr, radii at layer mid-lines)`.
fn ring_layers(r_in: f64, r_out: f64, dp: f64) -> (f64, Vec<f64>) {
    let n = ((r_out - r_in) / dp).round().max(1.0) as usize;
    let dr = (r_out - r_in) / n as f64;
    (dr, (0..n).map(|k| r_in + (k as f64 + 0.5) * dr).collect())
}

/// The particle count of [`annulus_polar`] without generating it: `n_r` layers of
/// `max(1, 2π r_k/dp)` particles, summed in closed form (within `n_r/2` of the exact count of
/// the rounded layers; any input, also one whose count overflows every integer, is safe).
fn ring_particle_estimate(r_in: f64, r_out: f64, dp: f64) -> f64 {
    let layers = ((r_out - r_in) / dp).round().max(1.0);
    let mid = 0.5 * (r_in + r_out);
    layers * (2.0 * PI * mid / dp).max(1.0) + 0.5 * layers
}

/// A 2D ring `r_in ≤ r ≤ r_out` in concentric layers, for bodies whose curved surfaces should be
/// smooth (rings, pressurised ring).
///
/// The ring is split into `n_r = max(1, round((r_out − r_in)/dp))` layers of thickness
/// `dr = (r_out − r_in)/n_r` (`= dp` when the wall is a whole number of spacings). Layer `k` has
/// `n_k = max(1, round(2π r_k / dp))` particles evenly spaced on the circle of radius
/// `r_k = r_in + (k + ½) dr`, starting at angle 0 on even layers and half a spacing later on odd
/// layers. Each particle of layer `k` has the volume of its share of the layer,
/// `V = 2π r_k dr / n_k`, so the volumes sum to `π (r_out² − r_in²)` up to round-off.
/// Regions: `"outer"` (layer `n_r − 1`) and, if `r_in > 0`, `"inner"` (layer 0).
pub fn annulus_polar(
    centre: DVec2,
    r_in: f64,
    r_out: f64,
    dp: f64,
) -> Result<ParticleSet<D2>, Error> {
    check_positive("dp", dp)?;
    check_radii(r_in, r_out)?;
    if !centre.is_finite() {
        return Err(Error::invalid("centre", centre, "finite"));
    }
    budget::reserve::<D2>(
        ring_particle_estimate(r_in, r_out, dp),
        &format!("annulus_polar at dp = {dp:?}"),
    )?;
    let (dr, radii) = ring_layers(r_in, r_out, dp);
    let mut positions = Vec::new();
    let mut volumes = Vec::new();
    let mut layer = Vec::new();
    for (k, &r) in radii.iter().enumerate() {
        let n = (2.0 * PI * r / dp).round().max(1.0) as usize;
        let v = 2.0 * PI * r * dr / n as f64;
        let phase = if k % 2 == 1 { 0.5 } else { 0.0 };
        for j in 0..n {
            let theta = 2.0 * PI * (j as f64 + phase) / n as f64;
            let (s, c) = theta.sin_cos();
            positions.push(centre + DVec2::new(c, s) * r);
            volumes.push(v);
            layer.push(k);
        }
    }
    let mut set = ParticleSet::from_parts(positions, volumes)?.with_spacing(dp);
    let last = radii.len() - 1;
    if r_in > 0.0 {
        set.tag_where("inner", |i, _| layer[i] == 0)?;
    }
    set.tag_where("outer", |i, _| layer[i] == last)?;
    Ok(set)
}

/// A 3D tube (or solid cylinder if `r_in = 0`) as [`annulus_polar`] rings stacked along `axis`:
/// `n_z = max(1, round(length/dp))` slices of thickness `dz = length/n_z` centred at
/// `base + (m + ½) dz axis`; `V = 2π r_k dr dz / n_k`, summing to `π (r_out² − r_in²) length`.
/// Regions `"outer"` and (if `r_in > 0`) `"inner"` as in [`annulus_polar`].
pub fn tube_polar(
    base: DVec3,
    axis: DVec3,
    r_in: f64,
    r_out: f64,
    length: f64,
    dp: f64,
) -> Result<ParticleSet<D3>, Error> {
    check_positive("length", length)?;
    if !base.is_finite() {
        return Err(Error::invalid("base", base, "finite"));
    }
    let axis = axis
        .try_normalize()
        .ok_or_else(|| Error::invalid("axis", axis, "finite and non-zero"))?;
    check_positive("dp", dp)?;
    check_radii(r_in, r_out)?;
    let slices = (length / dp).round().max(1.0);
    budget::reserve::<D3>(
        slices * ring_particle_estimate(r_in, r_out, dp),
        &format!("tube_polar at dp = {dp:?}"),
    )?;
    // The ring itself is a 2D set of one slice's size: booked only through the tube above.
    let ring = budget::scoped(budget::Budget::unlimited(), || {
        annulus_polar(DVec2::ZERO, r_in, r_out, dp)
    })?;
    let (u, w) = axis.any_orthonormal_pair();
    let nz = slices as usize;
    let dz = length / nz as f64;
    let mut out = ParticleSet::<D3>::new();
    for m in 0..nz {
        let c = base + axis * ((m as f64 + 0.5) * dz);
        let positions = ring.positions().iter().map(|p| c + u * p.x + w * p.y);
        let mut slice = ParticleSet::<D3>::from_parts(
            positions.collect(),
            ring.volumes().iter().map(|v| v * dz).collect(),
        )?
        .with_spacing(dp);
        for name in ring.regions() {
            let members = ring.tagged(name)?;
            slice.tag_particles(name, &members)?;
        }
        out.extend(&slice)?;
    }
    Ok(out)
}

/// A 3D hollow sphere (ball if `r_in = 0`) filled on a lattice whose cell faces pass through the
/// centre, so the particles are symmetric under reflection in each coordinate plane through it.
/// `V = dp³`; the total volume approaches `4π/3 (r_out³ − r_in³)` to first order in `dp`.
pub fn hollow_sphere(
    centre: DVec3,
    r_in: f64,
    r_out: f64,
    dp: f64,
) -> Result<ParticleSet<D3>, Error> {
    let lattice = Lattice::<D3>::new(dp, centre)?;
    ParticleSet::fill(&lattice, &HollowSphere::new(centre, r_in, r_out)?)
}

/// A 2D ring (disc if `r_in = 0`) filled on a lattice whose cell faces pass through the centre
/// (symmetric particles); `V = dp²`. See [`annulus_polar`] for smooth circular surfaces.
pub fn annulus_lattice(
    centre: DVec2,
    r_in: f64,
    r_out: f64,
    dp: f64,
) -> Result<ParticleSet<D2>, Error> {
    let lattice = Lattice::<D2>::new(dp, centre)?;
    ParticleSet::fill(&lattice, &Annulus::new(centre, r_in, r_out)?)
}
