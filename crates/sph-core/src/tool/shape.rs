//! The shapes of rigid tools and their signed distances: exact primitives, and any surface
//! that knows its signed distance ([`SignedDistance`]: a triangle mesh or a 2D outline read by
//! `sph-geometry`).

use crate::dim::Dim;
use crate::error::{check_positive, Error};
use std::fmt::Debug;
use std::sync::Arc;

/// A closed surface known by its signed distance: what a rigid tool's contact asks of its shape
/// ([`ToolShape::Surface`]). `sph-geometry` implements it on triangle meshes (3D: the closest
/// point by a bounding-volume hierarchy, the side by the generalized winding number) and on 2D
/// outlines; sph-core depends on neither.
///
/// The contact ([`super::RigidTool::enforce_contact`]) needs, for a point `x` in the tool's
/// initial position, the signed distance `d(x)` (negative inside) and the outward unit normal
/// `n(x)`, the gradient of `d` (`(x − p)/|x − p|` from the closest surface point `p`, turned
/// inward inside), and a box that holds the surface (a cheap rejection, and a rotating tool's
/// reach in [`super::RigidTool::max_speed`]).
pub trait SignedDistance<D: Dim>: Send + Sync + Debug {
    /// The signed distance from `x` to the surface (negative inside) and the outward unit
    /// normal of the surface at the closest point.
    fn signed_distance(&self, x: D::Vector) -> (f64, D::Vector);

    /// An axis-aligned box `(lower, upper)` containing the surface.
    fn bounds(&self) -> (D::Vector, D::Vector);
}

/// The geometry of a rigid tool in its initial position.
///
/// The primitives are exact; [`ToolShape::Surface`] holds any [`SignedDistance`] (a mesh or
/// outline), shared (`Arc`) so that cloning a tool does not copy its surface.
#[derive(Clone, Debug)]
pub enum ToolShape<D: Dim> {
    /// An axis-aligned box (rectangle in 2D), `min ≤ x ≤ max`.
    Box {
        /// Lower corner.
        min: D::Vector,
        /// Upper corner.
        max: D::Vector,
    },
    /// A box whose edges and corners are rounded with `radius`: the points within `radius`
    /// of the box `min + radius ≤ x ≤ max − radius`.
    RoundedBox {
        /// Lower corner (of the rounded box).
        min: D::Vector,
        /// Upper corner (of the rounded box).
        max: D::Vector,
        /// Radius of the edges and corners.
        radius: f64,
    },
    /// A ball (disc in 2D).
    Ball {
        /// Centre.
        centre: D::Vector,
        /// Radius.
        radius: f64,
    },
    /// A half-space: the solid lies on the side of the plane through `point` opposite to the
    /// unit `normal` (a wall whose surface faces along `normal`).
    HalfSpace {
        /// A point of the plane.
        point: D::Vector,
        /// Outward unit normal.
        normal: D::Vector,
    },
    /// A closed surface given by its signed distance: a triangle mesh (3D) or an outline (2D),
    /// e.g. `sph_geometry::FileSolid` read from an STL, OBJ or outline file.
    Surface(Arc<dyn SignedDistance<D>>),
}

/// Primitives compare by value, surfaces by identity (the same shared surface).
impl<D: Dim> PartialEq for ToolShape<D> {
    fn eq(&self, other: &Self) -> bool {
        use ToolShape::*;
        match (self, other) {
            (Box { min: a, max: b }, Box { min: c, max: d }) => a == c && b == d,
            (
                RoundedBox {
                    min: a,
                    max: b,
                    radius: r,
                },
                RoundedBox {
                    min: c,
                    max: d,
                    radius: s,
                },
            ) => a == c && b == d && r == s,
            (
                Ball {
                    centre: a,
                    radius: r,
                },
                Ball {
                    centre: c,
                    radius: s,
                },
            ) => a == c && r == s,
            (
                HalfSpace {
                    point: a,
                    normal: b,
                },
                HalfSpace {
                    point: c,
                    normal: d,
                },
            ) => a == c && b == d,
            (Surface(a), Surface(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

impl<D: Dim> ToolShape<D> {
    /// A box from its corners.
    ///
    /// # Errors
    /// Non-finite corners or `min_k ≥ max_k` in some direction.
    pub fn cuboid(min: D::Vector, max: D::Vector) -> Result<Self, Error> {
        for k in 0..D::D {
            let (a, b) = (D::component(min, k), D::component(max, k));
            if !(a.is_finite() && b.is_finite() && a < b) {
                return Err(Error::invalid(
                    "tool box corners",
                    format!("{min:?} .. {max:?}"),
                    "finite, with min < max in every direction",
                ));
            }
        }
        Ok(ToolShape::Box { min, max })
    }

    /// A box from its corners with edges and corners rounded by `radius` (0: [`Self::cuboid`]).
    ///
    /// # Errors
    /// As [`Self::cuboid`], and a negative radius or one larger than half the box's smallest
    /// side.
    pub fn rounded_cuboid(min: D::Vector, max: D::Vector, radius: f64) -> Result<Self, Error> {
        let sharp = Self::cuboid(min, max)?;
        let half_side = (0..D::D)
            .map(|k| 0.5 * (D::component(max, k) - D::component(min, k)))
            .fold(f64::INFINITY, f64::min);
        // Corners given as offsets from a centre lose the last bits of their difference: a
        // radius of exactly half the intended side must not be refused for that.
        let radius = if radius > half_side && radius <= half_side * (1.0 + 1e-9) {
            half_side
        } else {
            radius
        };
        if !(radius.is_finite() && (0.0..=half_side).contains(&radius)) {
            return Err(Error::invalid(
                "tool corner radius",
                radius,
                &format!("0 <= radius <= {half_side} (half the box's smallest side)"),
            ));
        }
        if radius == 0.0 {
            return Ok(sharp);
        }
        Ok(ToolShape::RoundedBox { min, max, radius })
    }

    /// A ball (disc in 2D).
    ///
    /// # Errors
    /// Non-finite centre or non-positive radius.
    pub fn ball(centre: D::Vector, radius: f64) -> Result<Self, Error> {
        check_positive("tool radius", radius)?;
        if !D::is_finite(centre) {
            return Err(Error::invalid(
                "tool centre",
                format!("{centre:?}"),
                "finite",
            ));
        }
        Ok(ToolShape::Ball { centre, radius })
    }

    /// A half-space wall whose surface passes through `point` and faces along `normal`
    /// (normalised here).
    ///
    /// # Errors
    /// Non-finite point, or a zero or non-finite normal.
    pub fn half_space(point: D::Vector, normal: D::Vector) -> Result<Self, Error> {
        let len = D::norm(normal);
        if !(D::is_finite(point) && len.is_finite() && len > 0.0) {
            return Err(Error::invalid(
                "tool half-space",
                format!("point {point:?}, normal {normal:?}"),
                "a finite point and a finite non-zero normal",
            ));
        }
        Ok(ToolShape::HalfSpace {
            point,
            normal: normal / len,
        })
    }

    /// A tool whose shape is the closed surface `surface` (a mesh or outline).
    ///
    /// # Errors
    /// A surface whose bounds are not finite with `lower ≤ upper` (an empty or broken surface).
    pub fn surface(surface: Arc<dyn SignedDistance<D>>) -> Result<Self, Error> {
        let (lo, hi) = surface.bounds();
        let ok = D::is_finite(lo)
            && D::is_finite(hi)
            && (0..D::D).all(|k| D::component(lo, k) <= D::component(hi, k));
        if !ok {
            return Err(Error::invalid(
                "tool surface bounds",
                format!("{lo:?} .. {hi:?}"),
                "finite, with lower <= upper in every direction",
            ));
        }
        Ok(ToolShape::Surface(surface))
    }

    /// Signed distance from `x` to the surface (negative inside) and the outward unit normal
    /// of the surface at the closest point (the gradient of the distance; on a box's edges and
    /// corners the direction from the corner, which rounds them).
    pub fn distance(&self, x: D::Vector) -> (f64, D::Vector) {
        match *self {
            ToolShape::Surface(ref s) => s.signed_distance(x),
            ToolShape::Box { min, max } => {
                let mut outside = D::zero();
                let (mut best, mut best_k, mut best_sign) = (f64::NEG_INFINITY, 0, 1.0);
                let mut any_outside = false;
                for k in 0..D::D {
                    let (lo, hi) = (D::component(min, k), D::component(max, k));
                    let p = D::component(x, k) - 0.5 * (lo + hi);
                    let sign = if p < 0.0 { -1.0 } else { 1.0 };
                    let q = p.abs() - 0.5 * (hi - lo);
                    if q > 0.0 {
                        any_outside = true;
                        D::set_component(&mut outside, k, sign * q);
                    }
                    if q > best {
                        (best, best_k, best_sign) = (q, k, sign);
                    }
                }
                if any_outside {
                    let d = D::norm(outside);
                    (d, outside / d)
                } else {
                    let mut n = D::zero();
                    D::set_component(&mut n, best_k, best_sign);
                    (best, n)
                }
            }
            ToolShape::RoundedBox { min, max, radius } => {
                // The box shrunk by the radius, then every distance less the radius.
                let mut r = D::zero();
                for k in 0..D::D {
                    D::set_component(&mut r, k, radius);
                }
                let core = ToolShape::<D>::Box {
                    min: min + r,
                    max: max - r,
                };
                let (d, n) = core.distance(x);
                (d - radius, n)
            }
            ToolShape::Ball { centre, radius } => {
                let r = x - centre;
                let len = D::norm(r);
                if len > 0.0 {
                    (len - radius, r / len)
                } else {
                    let mut n = D::zero();
                    D::set_component(&mut n, 0, 1.0);
                    (-radius, n)
                }
            }
            ToolShape::HalfSpace { point, normal } => (D::dot(x - point, normal), normal),
        }
    }

    /// An axis-aligned box containing the shape (infinite extent for a half-space).
    pub fn bounds(&self) -> (D::Vector, D::Vector) {
        match *self {
            ToolShape::Surface(ref s) => s.bounds(),
            ToolShape::Box { min, max } | ToolShape::RoundedBox { min, max, .. } => (min, max),
            ToolShape::Ball { centre, radius } => {
                let mut r = D::zero();
                for k in 0..D::D {
                    D::set_component(&mut r, k, radius);
                }
                (centre - r, centre + r)
            }
            ToolShape::HalfSpace { .. } => {
                let mut lo = D::zero();
                let mut hi = D::zero();
                for k in 0..D::D {
                    D::set_component(&mut lo, k, f64::NEG_INFINITY);
                    D::set_component(&mut hi, k, f64::INFINITY);
                }
                (lo, hi)
            }
        }
    }
}
