//! Shapes: the membership test of a region with its bounding box, the primitives and the
//! combinators (see the [`super`] module docs).

use super::*;

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

pub(super) fn component_min<D: Dim>(a: D::Vector, b: D::Vector) -> D::Vector {
    let mut out = a;
    for k in 0..D::D {
        D::set_component(&mut out, k, D::component(a, k).min(D::component(b, k)));
    }
    out
}

pub(super) fn component_max<D: Dim>(a: D::Vector, b: D::Vector) -> D::Vector {
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

pub(super) fn check_radii(r_in: f64, r_out: f64) -> Result<(), Error> {
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
