//! Rigid tools (punches, platens, walls) that move with a prescribed velocity history and touch
//! a deformable body through **kinematic contact**, frictionless or with Coulomb friction
//! ([`crate::friction`]); a [`ToolSet`] is what every method attaches (TL, UL and MPS alike).
//!
//! # The contact law
//!
//! A tool is an exact rigid shape ([`ToolShape`]: box, ball, half-space) with a signed distance
//! `d(x)` (negative inside) and outward unit normal `n(x)`. Particle `i` stands for the material
//! of its cell, half a spacing around it, so the body's surface touches the tool when the
//! particle's centre is at the distance `r_c` (the *contact offset*) from the tool's surface
//! that the cell reaches toward it: `dp/2` undeformed; for a method that carries a deformation
//! gradient, `r_c = (dp/2)|F_iᵀ n|`, the half-width of the deformed cell along the tool's normal
//! (a cell compressed to `λ dp` against a platen reaches `λ dp/2`), which is what makes the
//! contact surface the continuum's surface rather than a layer of fixed thickness.
//!
//! The contact is enforced once per step on the velocities, right after the velocity update,
//! as a velocity constraint over the time `τ` during which the new velocity will act before the
//! next update (`τ = Δt` in position Verlet: the second half-drift of this step and the first of
//! the next; also `Δt` in velocity Verlet's drift): with the predicted position `x* = x + τ v`
//! and the tool where it will be then,
//!
//! `g = d(x* − u_tool(t + τ)) − r_c`; if `g < 0`: `v += (−g/τ) n`.
//!
//! A particle touching a tool (`g = 0` at rest relative to it) thus keeps a non-negative normal
//! velocity relative to the tool — the contact is perfectly inelastic in the normal direction
//! and lands the particle exactly on the offset surface (flat faces; to first order in `g` on
//! curved ones). Predicting over the whole `τ` matters: a correction over only the remaining
//! half-drift would leave a velocity that carries the particle twice as far, into the tool at
//! the next half-drift and out again — a pump of energy into the contact layer.
//!
//! The correction acts along the tool's normal only (frictionless: the tangential velocity is
//! untouched, the surface slides along the tool), only pushes (a particle moving away is left
//! alone, so the surface may leave the tool), and its momentum `Σ m Δv` is exactly what the tool
//! receives with the opposite sign: the reaction force on the tool is `−Σ m Δv / Δt`
//! ([`ContactOutcome`]). There is no stiffness to choose: this is the limit of an infinitely
//! stiff penalty, so interpenetration is zero on flat faces and second order in the step on
//! curved ones, at any loading speed the scheme is stable for. It is inelastic (a particle
//! hitting the tool does not bounce): right for rigid platens and quasi-static loading; for
//! elastic impacts between deformable bodies use a method's body–body contact.
//!
//! # Friction
//!
//! A tool with friction ([`RigidTool::with_friction`]) then changes the tangential velocity of
//! each particle it corrected, relative to the tool's surface there (the velocity of the tool's
//! material point over the look-ahead, so a moving or turning tool drags what sticks to it),
//! with the normal velocity change `−g/τ` as the normal impulse per unit mass: stick if the
//! sticking change is within `μ_s` times it, else slip with `μ_k` times it (see
//! [`crate::friction`]). A frictionless tool never enters that code.

use crate::amplitude::Amplitude;
use crate::dim::Dim;
use crate::error::{check_non_negative, check_positive, Error};
use crate::friction::{coulomb_velocity_change, Friction};
use crate::scene::Series;
use glam::DVec3;
use std::f64::consts::PI;

/// The geometry of a rigid tool in its initial position.
#[derive(Clone, Copy, Debug, PartialEq)]
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

    /// Signed distance from `x` to the surface (negative inside) and the outward unit normal
    /// of the surface at the closest point (the gradient of the distance; on a box's edges and
    /// corners the direction from the corner, which rounds them).
    pub fn distance(&self, x: D::Vector) -> (f64, D::Vector) {
        match *self {
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

/// A tool's prescribed rigid motion: a translation `u(t)` and, optionally, a rotation `R(t)`
/// about an axis through a centre that moves with the translation, so a point `X` of the tool
/// in its initial position is at `x(t) = c + u(t) + R(t)(X − c)`.
///
/// The translation is one of
/// - a **straight line** ([`ToolMotion::new`]): along a unit `direction` with speed `v(t)` that
///   rises smoothly from 0 to `speed` over `ramp_time` (`v = speed (1 − cos(π t/T))/2`; a jump
///   when `ramp_time` is 0), then stays constant until the tool has travelled `travel`, where it
///   stops and holds its position;
/// - a **path** ([`ToolMotion::path`]): piecewise linear through waypoints `(t_k, u_k)`, holding
///   the first before `t_0` and the last after the last time;
/// - a **velocity curve** ([`ToolMotion::translating`]): `v · a(t)` with an [`Amplitude`], the
///   displacement its closed-form integral `v ∫₀ᵗ a`.
///
/// The rotation ([`ToolMotion::rotating`]) turns by `θ(t) = ω ∫₀ᵗ a` (an angular velocity `ω`
/// times an amplitude curve, or constant) about `axis` (right-handed; in 2D the z axis).
#[derive(Clone, Debug, PartialEq)]
pub struct ToolMotion<D: Dim> {
    translation: Translation<D>,
    rotation: Option<ToolRotation<D>>,
}

/// How a tool translates (see [`ToolMotion`]).
#[derive(Clone, Debug, PartialEq)]
enum Translation<D: Dim> {
    Line {
        direction: D::Vector,
        speed: f64,
        ramp_time: f64,
        travel: f64,
    },
    Path(Vec<(f64, D::Vector)>),
    Velocity {
        velocity: D::Vector,
        amplitude: Option<Amplitude>,
    },
}

/// A tool's placement at one time: its translation and rotation (see [`ToolMotion::pose`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose<D: Dim> {
    /// The translation `u(t)`.
    pub shift: D::Vector,
    /// The rotation centre `c` (initial position) and matrix `R(t)`, if the tool turns.
    pub rotation: Option<(D::Vector, D::Matrix)>,
}

impl<D: Dim> Pose<D> {
    /// Where the point `x` in space lies in the tool's initial position:
    /// `X = c + Rᵀ(x − u − c)` (`x − u` without rotation).
    #[inline]
    pub fn to_initial(&self, x: D::Vector) -> D::Vector {
        let shifted = x - self.shift;
        match self.rotation {
            None => shifted,
            Some((c, r)) => c + D::transpose(r) * (shifted - c),
        }
    }

    /// Where the point `X` of the tool in its initial position is in space:
    /// `x = c + u + R(X − c)` (`X + u` without rotation; the inverse of [`Pose::to_initial`]).
    #[inline]
    pub fn to_space(&self, x: D::Vector) -> D::Vector {
        match self.rotation {
            None => x + self.shift,
            Some((c, r)) => c + self.shift + r * (x - c),
        }
    }

    /// A normal of the tool in its initial position, turned to where the tool is.
    #[inline]
    pub fn normal_to_space(&self, n: D::Vector) -> D::Vector {
        match self.rotation {
            None => n,
            Some((_, r)) => r * n,
        }
    }
}

/// A rotation of a tool about an axis through `centre` (its position at `t = 0`).
#[derive(Clone, Debug, PartialEq)]
pub struct ToolRotation<D: Dim> {
    /// A point of the axis, in the tool's initial position.
    pub centre: D::Vector,
    /// Unit axis (right-handed; `+z` or `−z` in 2D).
    pub axis: DVec3,
    /// Angular velocity (rad/s) that the amplitude scales.
    pub angular_velocity: f64,
    /// The amplitude curve of the angular velocity (`None`: constant).
    pub amplitude: Option<Amplitude>,
}

impl<D: Dim> ToolRotation<D> {
    /// The angle turned by time `t` (rad).
    pub fn angle(&self, t: f64) -> f64 {
        match &self.amplitude {
            Some(a) => self.angular_velocity * a.integral(t),
            None => self.angular_velocity * t.max(0.0),
        }
    }

    /// The rotation matrix by time `t`.
    pub fn matrix(&self, t: f64) -> D::Matrix {
        rotation_matrix::<D>(self.axis, self.angle(t))
    }
}

/// The rotation by `angle` about the unit `axis` (Rodrigues' formula
/// `R = cos θ I + sin θ [k]× + (1 − cos θ) k kᵀ`; in 2D the in-plane block about `±z`).
pub fn rotation_matrix<D: Dim>(axis: DVec3, angle: f64) -> D::Matrix {
    let (s, c) = angle.sin_cos();
    let k = axis.to_array();
    D::matrix_from_fn(|r, col| {
        let cross = match (r, col) {
            (0, 1) => -k[2],
            (1, 0) => k[2],
            (0, 2) => k[1],
            (2, 0) => -k[1],
            (1, 2) => -k[0],
            (2, 1) => k[0],
            _ => 0.0,
        };
        let diagonal = if r == col { c } else { 0.0 };
        diagonal + s * cross + (1.0 - c) * k[r] * k[col]
    })
}

impl<D: Dim> ToolMotion<D> {
    /// A motion along `direction` (normalised here) at `speed`, reached after a smooth ramp of
    /// `ramp_time`, stopping after a displacement of `travel` (`f64::INFINITY`: never).
    ///
    /// # Errors
    /// A zero or non-finite direction; negative or non-finite speed or ramp time; a travel that
    /// is not positive.
    pub fn new(
        direction: D::Vector,
        speed: f64,
        ramp_time: f64,
        travel: f64,
    ) -> Result<Self, Error> {
        let len = D::norm(direction);
        if !(len.is_finite() && len > 0.0) {
            return Err(Error::invalid(
                "tool direction",
                format!("{direction:?}"),
                "finite and non-zero",
            ));
        }
        check_non_negative("tool speed", speed)?;
        check_non_negative("tool ramp_time", ramp_time)?;
        if travel.is_nan() || travel <= 0.0 {
            return Err(Error::invalid("tool travel", travel, "> 0 (or infinite)"));
        }
        Ok(Self::translation(Translation::Line {
            direction: direction / len,
            speed,
            ramp_time,
            travel,
        }))
    }

    /// A tool at rest.
    pub fn fixed() -> Self {
        let mut e = D::zero();
        D::set_component(&mut e, 0, 1.0);
        Self::translation(Translation::Line {
            direction: e,
            speed: 0.0,
            ramp_time: 0.0,
            travel: f64::INFINITY,
        })
    }

    /// A piecewise-linear path through the displacements `u_k` at times `t_k` (strictly
    /// increasing); the first displacement before `t_0`, the last after the last time.
    ///
    /// # Errors
    /// No waypoint, non-finite times or displacements, times not strictly increasing.
    pub fn path(points: Vec<(f64, D::Vector)>) -> Result<Self, Error> {
        if points.is_empty() {
            return Err(Error::invalid(
                "tool path",
                "[]",
                "at least one waypoint [time, displacement...]",
            ));
        }
        for (k, &(t, u)) in points.iter().enumerate() {
            if !(t.is_finite() && D::is_finite(u)) {
                return Err(Error::invalid(
                    &format!("tool path waypoint {k}"),
                    format!("{t}, {u:?}"),
                    "finite time and displacement",
                ));
            }
            if k > 0 && t <= points[k - 1].0 {
                return Err(Error::invalid(
                    &format!("tool path waypoint {k} time"),
                    t,
                    &format!("> {} (times strictly increasing)", points[k - 1].0),
                ));
            }
        }
        Ok(Self::translation(Translation::Path(points)))
    }

    /// A translation at the velocity `velocity · a(t)` (`None`: constant velocity).
    ///
    /// # Errors
    /// A non-finite velocity.
    pub fn translating(velocity: D::Vector, amplitude: Option<Amplitude>) -> Result<Self, Error> {
        if !D::is_finite(velocity) {
            return Err(Error::invalid(
                "tool velocity",
                format!("{velocity:?}"),
                "finite",
            ));
        }
        Ok(Self::translation(Translation::Velocity {
            velocity,
            amplitude,
        }))
    }

    fn translation(translation: Translation<D>) -> Self {
        Self {
            translation,
            rotation: None,
        }
    }

    /// Adds a rotation about `axis` (normalised here; in 2D `±z`) through `centre`, at the
    /// angular velocity `angular_velocity · a(t)` (rad/s; `None`: constant).
    ///
    /// # Errors
    /// A non-finite centre or angular velocity; a zero or non-finite axis, or in 2D an axis
    /// other than `±z`.
    pub fn rotating(
        mut self,
        centre: D::Vector,
        axis: DVec3,
        angular_velocity: f64,
        amplitude: Option<Amplitude>,
    ) -> Result<Self, Error> {
        let len = axis.length();
        let planar = D::D == 3 || (axis.x == 0.0 && axis.y == 0.0);
        if !(len.is_finite() && len > 0.0 && planar) {
            return Err(Error::invalid(
                "tool rotation axis",
                format!("{axis:?}"),
                if D::D == 2 {
                    "the z axis, [0, 0, 1] or [0, 0, -1], in 2D"
                } else {
                    "finite and non-zero"
                },
            ));
        }
        if !(D::is_finite(centre) && angular_velocity.is_finite()) {
            return Err(Error::invalid(
                "tool rotation",
                format!("centre {centre:?}, angular velocity {angular_velocity}"),
                "a finite centre and angular velocity",
            ));
        }
        self.rotation = Some(ToolRotation {
            centre,
            axis: axis / len,
            angular_velocity,
            amplitude,
        });
        Ok(self)
    }

    /// The rotation, if the tool turns.
    pub fn rotation(&self) -> Option<&ToolRotation<D>> {
        self.rotation.as_ref()
    }

    /// Whether the tool only moves along a straight line (the motion of [`ToolMotion::new`],
    /// without rotation).
    pub fn is_straight(&self) -> bool {
        self.rotation.is_none() && matches!(self.translation, Translation::Line { .. })
    }

    /// The unit direction of travel of a straight-line motion; for a path or a velocity curve,
    /// the direction of the displacement at the end (of the velocity), or `x` when it is zero.
    pub fn direction(&self) -> D::Vector {
        let v = match &self.translation {
            Translation::Line { direction, .. } => return *direction,
            Translation::Path(points) => points[points.len() - 1].1,
            Translation::Velocity { velocity, .. } => *velocity,
        };
        let len = D::norm(v);
        if len > 0.0 {
            v / len
        } else {
            let mut e = D::zero();
            D::set_component(&mut e, 0, 1.0);
            e
        }
    }

    /// The largest translational speed of the motion (m/s): a straight line's speed after its
    /// ramp, a path's fastest segment, a velocity curve's `|v| max |a|`. A rotating tool's
    /// points move faster: see [`RigidTool::max_speed`].
    pub fn speed(&self) -> f64 {
        match &self.translation {
            Translation::Line { speed, .. } => *speed,
            Translation::Path(points) => points
                .windows(2)
                .map(|w| D::norm(w[1].1 - w[0].1) / (w[1].0 - w[0].0))
                .fold(0.0, f64::max),
            Translation::Velocity {
                velocity,
                amplitude,
            } => D::norm(*velocity) * amplitude.as_ref().map_or(1.0, Amplitude::max_abs),
        }
    }

    /// Distance travelled along a straight line by time `t` before the stop (no clamping).
    fn free_distance(speed: f64, ramp_time: f64, t: f64) -> f64 {
        let (v, tr) = (speed, ramp_time);
        if t <= 0.0 {
            0.0
        } else if t < tr {
            0.5 * v * (t - tr / PI * (PI * t / tr).sin())
        } else {
            0.5 * v * tr + v * (t - tr)
        }
    }

    /// Distance travelled by time `t`: along the line for a straight-line motion, else the
    /// length of the displacement `|u(t)|`.
    pub fn distance(&self, t: f64) -> f64 {
        match &self.translation {
            Translation::Line {
                speed,
                ramp_time,
                travel,
                ..
            } => Self::free_distance(*speed, *ramp_time, t).min(*travel),
            _ => D::norm(self.displacement(t)),
        }
    }

    /// Displacement `u(t)` (of the rotation centre, for a rotating tool).
    pub fn displacement(&self, t: f64) -> D::Vector {
        match &self.translation {
            Translation::Line { direction, .. } => *direction * self.distance(t),
            Translation::Path(points) => {
                let k = points.partition_point(|p| p.0 <= t);
                if k == 0 {
                    return points[0].1;
                }
                if k == points.len() {
                    return points[k - 1].1;
                }
                let ((t0, u0), (t1, u1)) = (points[k - 1], points[k]);
                u0 + (u1 - u0) * ((t - t0) / (t1 - t0))
            }
            Translation::Velocity {
                velocity,
                amplitude,
            } => {
                let s = match amplitude {
                    Some(a) => a.integral(t),
                    None => t.max(0.0),
                };
                *velocity * s
            }
        }
    }

    /// Translational velocity at time `t` (zero once a straight-line motion stopped; on a
    /// path, the slope of the segment after `t`).
    pub fn velocity(&self, t: f64) -> D::Vector {
        match &self.translation {
            Translation::Line {
                direction,
                speed,
                ramp_time,
                travel,
            } => {
                if t <= 0.0 || Self::free_distance(*speed, *ramp_time, t) >= *travel {
                    return D::zero();
                }
                let s = if t < *ramp_time {
                    0.5 * (1.0 - (PI * t / ramp_time).cos())
                } else {
                    1.0
                };
                *direction * (speed * s)
            }
            Translation::Path(points) => {
                let k = points.partition_point(|p| p.0 <= t);
                if k == 0 || k == points.len() {
                    return D::zero();
                }
                let ((t0, u0), (t1, u1)) = (points[k - 1], points[k]);
                (u1 - u0) / (t1 - t0)
            }
            Translation::Velocity {
                velocity,
                amplitude,
            } => *velocity * amplitude.as_ref().map_or(1.0, |a| a.at(t)),
        }
    }

    /// The angle turned by time `t` (rad; 0 without rotation).
    pub fn angle(&self, t: f64) -> f64 {
        self.rotation.as_ref().map_or(0.0, |r| r.angle(t))
    }

    /// The time at which the tool stops: a straight line's arrival after its travel, a path's
    /// last waypoint (infinite for a motion that never stops, or a rotating tool).
    pub fn arrival_time(&self) -> f64 {
        if self.rotation.is_some() {
            return f64::INFINITY;
        }
        let (speed, ramp_time, travel) = match &self.translation {
            Translation::Line {
                speed,
                ramp_time,
                travel,
                ..
            } => (*speed, *ramp_time, *travel),
            Translation::Path(points) => return points[points.len() - 1].0.max(0.0),
            Translation::Velocity { .. } => return f64::INFINITY,
        };
        if !travel.is_finite() || speed <= 0.0 {
            return f64::INFINITY;
        }
        let ramp_distance = Self::free_distance(speed, ramp_time, ramp_time);
        if travel >= ramp_distance {
            return ramp_time + (travel - ramp_distance) / speed;
        }
        // Inside the ramp: the distance is monotone, bisect.
        let (mut lo, mut hi) = (0.0, ramp_time);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if Self::free_distance(speed, ramp_time, mid) < travel {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        hi
    }

    /// The tool's placement at time `t`: what maps points in space to the tool's initial
    /// position.
    pub fn pose(&self, t: f64) -> Pose<D> {
        Pose {
            shift: self.displacement(t),
            rotation: self.rotation.as_ref().map(|r| (r.centre, r.matrix(t))),
        }
    }
}

/// A rigid tool: a shape with a prescribed motion and a name (for its reaction series).
#[derive(Clone, Debug, PartialEq)]
pub struct RigidTool<D: Dim> {
    /// Name (the HDF5 series `/series/<name>` records its travel and reaction).
    pub name: String,
    /// Geometry in the initial position.
    pub shape: ToolShape<D>,
    /// Motion.
    pub motion: ToolMotion<D>,
    /// Coulomb friction with the body ([`Friction::NONE`]: frictionless).
    pub friction: Friction,
}

/// What one contact pass did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactOutcome<D: Dim> {
    /// Momentum given to the body, `Σ m Δv` (the tool receives `−impulse`; the reaction force
    /// on the tool over a step `Δt` is `−impulse/Δt`).
    pub impulse: D::Vector,
    /// Particles in contact this step.
    pub active: usize,
    /// The tangential (friction) part of `impulse`.
    pub friction_impulse: D::Vector,
    /// Of the `active` particles, those that stuck (friction only).
    pub sticking: usize,
    /// Work of the normal velocity changes on the body, `Σ ½ m (|v⁺|² − |v⁻|²)`.
    pub normal_work: f64,
    /// Work of the friction velocity changes on the body.
    pub friction_work: f64,
    /// Energy the friction dissipated, `−Σ m Δv_t · (v_mid − v_tool)` (≥ 0; equal to
    /// `−friction_work` for a tool at rest).
    pub friction_dissipation: f64,
}

impl<D: Dim> RigidTool<D> {
    /// A tool named `name`.
    pub fn new(name: &str, shape: ToolShape<D>, motion: ToolMotion<D>) -> Self {
        Self {
            name: name.to_string(),
            shape,
            motion,
            friction: Friction::NONE,
        }
    }

    /// With Coulomb friction against the body (see [`crate::friction`]).
    pub fn with_friction(mut self, friction: Friction) -> Self {
        self.friction = friction;
        self
    }

    /// The largest speed of a point of the tool (m/s): its translation's speed, plus for a
    /// rotating tool the largest angular speed times the distance from the axis's centre to the
    /// farthest corner of the shape's bounding box (infinite for a turning half-space).
    pub fn max_speed(&self) -> f64 {
        let turning = self.motion.rotation().map_or(0.0, |r| {
            let omega =
                r.angular_velocity.abs() * r.amplitude.as_ref().map_or(1.0, Amplitude::max_abs);
            let (lo, hi) = self.shape.bounds();
            let mut reach = 0.0f64;
            for corner in 0..(1usize << D::D) {
                let mut x = D::zero();
                for k in 0..D::D {
                    let c = if corner >> k & 1 == 0 { lo } else { hi };
                    D::set_component(&mut x, k, D::component(c, k));
                }
                reach = reach.max(D::norm(x - r.centre));
            }
            if omega == 0.0 {
                0.0
            } else {
                omega * reach
            }
        });
        self.motion.speed() + turning
    }

    /// Signed distance and outward normal of the tool at time `t`.
    pub fn distance_at(&self, x: D::Vector, t: f64) -> (f64, D::Vector) {
        let pose = self.motion.pose(t);
        let (d, n) = self.shape.distance(pose.to_initial(x));
        (d, pose.normal_to_space(n))
    }

    /// Kinematic contact (see the [module documentation](self)): for every particle with
    /// `movable[i]`, whose predicted position `x + lookahead·v` lies closer than its contact
    /// offset `offset(i, n)` (`n` the tool's normal there) to the tool at time `t_end` (the time
    /// of that prediction), adds the normal velocity that puts it on the offset surface, then,
    /// with friction, the tangential velocity change of the Coulomb law. `max_offset` bounds the
    /// offsets (a cheap bounding-box rejection). Sequential, so the impulse sum is
    /// deterministic.
    #[allow(clippy::too_many_arguments)]
    pub fn enforce_contact(
        &self,
        t_end: f64,
        lookahead: f64,
        offset: impl Fn(usize, D::Vector) -> f64,
        max_offset: f64,
        positions: &[D::Vector],
        velocities: &mut [D::Vector],
        masses: &[f64],
        movable: &[bool],
    ) -> ContactOutcome<D> {
        let pose = self.motion.pose(t_end);
        // With friction: where the tool was one look-ahead earlier (its surface velocity).
        let before =
            (!self.friction.is_frictionless()).then(|| self.motion.pose(t_end - lookahead));
        let (lo, hi) = self.shape.bounds();
        let reach = max_offset * (1.0 + 1e-12);
        let mut out = ContactOutcome {
            impulse: D::zero(),
            active: 0,
            friction_impulse: D::zero(),
            sticking: 0,
            normal_work: 0.0,
            friction_work: 0.0,
            friction_dissipation: 0.0,
        };
        for i in 0..positions.len() {
            if !movable[i] {
                continue;
            }
            // The predicted position, in the tool's initial position.
            let predicted = positions[i] + velocities[i] * lookahead;
            let x = pose.to_initial(predicted);
            // Cheap rejection against the bounding box grown by the offset.
            if (0..D::D).any(|k| {
                let c = D::component(x, k);
                c < D::component(lo, k) - reach || c > D::component(hi, k) + reach
            }) {
                continue;
            }
            let (d, n) = self.shape.distance(x);
            let n = pose.normal_to_space(n);
            let gap = d - offset(i, n);
            if gap < 0.0 {
                let normal_change = -gap / lookahead;
                let dv = n * normal_change;
                let v0 = velocities[i];
                velocities[i] += dv;
                out.impulse += dv * masses[i];
                out.normal_work += masses[i] * D::dot(dv, v0 + dv * 0.5);
                out.active += 1;
                if let Some(before) = &before {
                    // The tool's material point at the predicted contact, over the look-ahead.
                    let tool_velocity = (predicted - before.to_space(x)) / lookahead;
                    let v1 = velocities[i];
                    let relative = v1 - tool_velocity;
                    let slip = relative - n * D::dot(relative, n);
                    let (dvt, stick) =
                        coulomb_velocity_change::<D>(slip, normal_change, self.friction);
                    velocities[i] += dvt;
                    let j = dvt * masses[i];
                    out.impulse += j;
                    out.friction_impulse += j;
                    let mid = v1 + dvt * 0.5;
                    out.friction_work += D::dot(j, mid);
                    out.friction_dissipation -= D::dot(j, mid - tool_velocity);
                    out.sticking += usize::from(stick);
                }
            }
        }
        out
    }
}

/// The rigid tools a body touches, as every method attaches them: their contact pass (the
/// impulses of one step summed per tool), reaction meters, contact counts, the work of the
/// contact and friction on the body, the series each tool records, and their checkpoint state.
///
/// A method calls [`ToolSet::begin_step`], then [`ToolSet::enforce`] once or more after its
/// velocity update, then [`ToolSet::end_step`] with the step's length; [`ToolSet::record`] on
/// its probe schedule.
///
/// ```
/// use sph_core::friction::Friction;
/// use sph_core::tool::{RigidTool, ToolMotion, ToolSet, ToolShape};
/// use sph_core::{glam::DVec2, D2};
/// // A floor with friction under one particle sliding at 1 m/s and pressed into it.
/// let floor = ToolShape::<D2>::half_space(DVec2::ZERO, DVec2::Y)?;
/// let tool = RigidTool::new("floor", floor, ToolMotion::fixed())
///     .with_friction(Friction::new(0.5, 0.5)?);
/// let mut tools = ToolSet::new(vec![tool], &[], 100.0)?;
/// let (x, mut v) = (vec![DVec2::new(0.0, 0.0)], vec![DVec2::new(1.0, -0.2)]);
/// tools.begin_step();
/// tools.enforce(0.1, 0.1, |_, _| 0.0, 0.0, &x, &mut v, &[1.0], &[true], true);
/// tools.end_step(0.1);
/// // The normal change 0.2 m/s stops the approach; friction takes 0.5 · 0.2 off the slide.
/// assert!((v[0] - DVec2::new(0.9, 0.0)).length() < 1e-15);
/// assert!(tools.work().friction < 0.0);
/// # Ok::<(), sph_core::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct ToolSet<D: Dim> {
    tools: Vec<RigidTool<D>>,
    meters: Vec<ReactionMeter<D>>,
    friction_meters: Vec<ReactionMeter<D>>,
    /// Particles in contact with, and sticking to, each tool in the last step.
    contacts: Vec<usize>,
    sticking: Vec<usize>,
    /// This step's impulses on the body per tool (all, friction part).
    impulses: Vec<D::Vector>,
    friction_impulses: Vec<D::Vector>,
    work: ToolWork,
    series: Vec<Series>,
}

/// Work done on the body by the tools since `t = 0` (J; J/m in 2D).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ToolWork {
    /// By the normal contact velocity changes (≤ 0 against tools at rest: the contact is
    /// perfectly inelastic).
    pub contact: f64,
    /// By the friction velocity changes.
    pub friction: f64,
    /// Energy the friction dissipated (≥ 0; `−friction` when the tools are at rest).
    pub friction_dissipated: f64,
}

impl<D: Dim> Default for ToolSet<D> {
    fn default() -> Self {
        Self {
            tools: Vec::new(),
            meters: Vec::new(),
            friction_meters: Vec::new(),
            contacts: Vec::new(),
            sticking: Vec::new(),
            impulses: Vec::new(),
            friction_impulses: Vec::new(),
            work: ToolWork::default(),
            series: Vec::new(),
        }
    }
}

impl<D: Dim> ToolSet<D> {
    /// The tools a body of sound speed `sound_speed` touches; `taken` are names the tools'
    /// series must not reuse (a method's named constraints).
    ///
    /// # Errors
    /// A tool name that is not a name ([`crate::error::check_name`]); two tools (or a tool and
    /// a taken name) with the same name; a tool at or above the body's sound speed.
    pub fn new(tools: Vec<RigidTool<D>>, taken: &[&str], sound_speed: f64) -> Result<Self, Error> {
        let mut names: Vec<&str> = taken.to_vec();
        for t in &tools {
            crate::error::check_name("tool name", &t.name)?;
            // The step follows the body's wave speed, not the tool's: a tool faster than
            // sound outruns the contact and collapses the step within a few dozen steps.
            let speed = t.max_speed();
            if speed >= sound_speed {
                return Err(Error::invalid(
                    &format!("speed of tool `{}`", t.name),
                    crate::error::Num(speed),
                    &format!(
                        "0 <= tool speed < {} m/s, the body's sound speed c0 (a faster tool \
                         outruns the contact)",
                        crate::error::Num(sound_speed)
                    ),
                ));
            }
            if names.contains(&t.name.as_str()) {
                return Err(Error::invalid(
                    "tool name",
                    format!("{:?}", t.name),
                    "non-empty and unique among the body's tools and named constraints",
                ));
            }
            names.push(&t.name);
        }
        let n = tools.len();
        let mut set = Self {
            tools,
            meters: vec![ReactionMeter::default(); n],
            friction_meters: vec![ReactionMeter::default(); n],
            contacts: vec![0; n],
            sticking: vec![0; n],
            impulses: vec![D::zero(); n],
            friction_impulses: vec![D::zero(); n],
            work: ToolWork::default(),
            series: Vec::new(),
        };
        set.reset_series(0.0);
        Ok(set)
    }

    /// The tools.
    pub fn tools(&self) -> &[RigidTool<D>] {
        &self.tools
    }

    /// Whether there is no tool.
    pub fn is_empty(&self) -> bool {
        self.tools.is_empty()
    }

    /// Number of tools.
    pub fn len(&self) -> usize {
        self.tools.len()
    }

    /// Whether some tool has friction.
    pub fn has_friction(&self) -> bool {
        self.tools.iter().any(|t| !t.friction.is_frictionless())
    }

    /// Particles in contact with each tool in the last step.
    pub fn contacts(&self) -> &[usize] {
        &self.contacts
    }

    /// Work the tools did on the body since `t = 0`.
    pub fn work(&self) -> ToolWork {
        self.work
    }

    /// The energy-budget terms of the tools (see [`crate::EnergyBudget`]: minus the work done
    /// on the body): `tool_contact` and `friction`; empty without tools.
    pub fn budget_terms(&self) -> Vec<(&'static str, f64)> {
        if self.is_empty() {
            return Vec::new();
        }
        vec![
            ("tool_contact", -self.work.contact),
            ("friction", -self.work.friction),
        ]
    }

    /// The figures of the tools for a run's summary: `tool_contact_work`, `friction_work`
    /// (work on the body) and `friction_dissipated`; empty without tools.
    pub fn figures(&self) -> Vec<(&'static str, f64)> {
        if self.is_empty() {
            return Vec::new();
        }
        vec![
            ("tool_contact_work", self.work.contact),
            ("friction_work", self.work.friction),
            ("friction_dissipated", self.work.friction_dissipated),
        ]
    }

    /// Starts a step: no impulse yet.
    pub fn begin_step(&mut self) {
        self.impulses.iter_mut().for_each(|j| *j = D::zero());
        self.friction_impulses
            .iter_mut()
            .for_each(|j| *j = D::zero());
    }

    /// One contact pass of every tool ([`RigidTool::enforce_contact`], same arguments), adding
    /// each tool's impulses and work; `count` records the particles in contact (the first pass
    /// of a step).
    #[allow(clippy::too_many_arguments)]
    pub fn enforce(
        &mut self,
        t_end: f64,
        lookahead: f64,
        offset: impl Fn(usize, D::Vector) -> f64 + Copy,
        max_offset: f64,
        positions: &[D::Vector],
        velocities: &mut [D::Vector],
        masses: &[f64],
        movable: &[bool],
        count: bool,
    ) {
        for (k, tool) in self.tools.iter().enumerate() {
            let out = tool.enforce_contact(
                t_end, lookahead, offset, max_offset, positions, velocities, masses, movable,
            );
            self.impulses[k] += out.impulse;
            self.friction_impulses[k] += out.friction_impulse;
            self.work.contact += out.normal_work;
            self.work.friction += out.friction_work;
            self.work.friction_dissipated += out.friction_dissipation;
            if count {
                self.contacts[k] = out.active;
                self.sticking[k] = out.sticking;
            }
        }
    }

    /// Ends a step of length `dt`: each tool's reaction `−impulse/dt` into its meters.
    pub fn end_step(&mut self, dt: f64) {
        for (meter, &impulse) in self.meters.iter_mut().zip(&self.impulses) {
            meter.add(-impulse / dt, dt);
        }
        for (k, meter) in self.friction_meters.iter_mut().enumerate() {
            if !self.tools[k].friction.is_frictionless() {
                meter.add(-self.friction_impulses[k] / dt, dt);
            }
        }
    }

    /// Empty series, one per tool, with a first row at time `t`.
    pub fn reset_series(&mut self, t: f64) {
        let axes = &["force_x", "force_y", "force_z"][..D::D];
        let friction_axes = &["friction_x", "friction_y", "friction_z"][..D::D];
        self.series = self
            .tools
            .iter()
            .map(|t| {
                let mut columns = vec!["displacement"];
                columns.extend_from_slice(axes);
                columns.push("contacts");
                let mut description = crate::conventions::TOOL_SERIES.to_string();
                if !t.friction.is_frictionless() {
                    columns.extend_from_slice(friction_axes);
                    columns.push("sticking");
                    description = format!(
                        "{description}; {}",
                        crate::conventions::TOOL_FRICTION_SERIES
                    );
                }
                // A tool off a straight line: its displacement vector, and the angle it turned.
                if !t.motion.is_straight() {
                    columns.extend_from_slice(
                        &["displacement_x", "displacement_y", "displacement_z"][..D::D],
                    );
                }
                if t.motion.rotation().is_some() {
                    columns.push("angle");
                }
                Series::new(&t.name, &columns).with_description(&description)
            })
            .collect();
        self.contacts.iter_mut().for_each(|c| *c = 0);
        self.sticking.iter_mut().for_each(|c| *c = 0);
        self.record(t);
    }

    /// Appends one row to every tool's series: travel, mean reactions since the last row,
    /// contacts (and friction).
    pub fn record(&mut self, t: f64) {
        let mut row = Vec::with_capacity(12);
        for (k, tool) in self.tools.iter().enumerate() {
            row.clear();
            row.push(tool.motion.distance(t));
            let f = self.meters[k].take_mean();
            row.extend((0..D::D).map(|c| D::component(f, c)));
            row.push(self.contacts[k] as f64);
            if !tool.friction.is_frictionless() {
                let f = self.friction_meters[k].take_mean();
                row.extend((0..D::D).map(|c| D::component(f, c)));
                let active = self.contacts[k];
                row.push(if active > 0 {
                    self.sticking[k] as f64 / active as f64
                } else {
                    0.0
                });
            }
            if !tool.motion.is_straight() {
                let u = tool.motion.displacement(t);
                row.extend((0..D::D).map(|c| D::component(u, c)));
            }
            if tool.motion.rotation().is_some() {
                row.push(tool.motion.angle(t));
            }
            self.series[k].push(t, &row);
        }
    }

    /// The tools' series.
    pub fn series(&self) -> &[Series] {
        &self.series
    }

    /// Writes the running state: contact counts, meters, work, series.
    pub fn save(&self, out: &mut crate::StateWriter) {
        let contacts: Vec<u64> = self.contacts.iter().map(|&c| c as u64).collect();
        out.u64s("tool_contacts", &contacts);
        let sticking: Vec<u64> = self.sticking.iter().map(|&c| c as u64).collect();
        out.u64s("tool_sticking", &sticking);
        ReactionMeter::save_all(out, "tool_meters", &self.meters);
        ReactionMeter::save_all(out, "tool_friction_meters", &self.friction_meters);
        let w = self.work;
        out.f64s("tool_work", &[w.contact, w.friction, w.friction_dissipated]);
        crate::state::save_series(out, &self.series);
    }

    /// Reads back [`ToolSet::save`] into a tool set built from the same scene.
    ///
    /// # Errors
    /// A mismatch of names or sizes ([`Error::Checkpoint`]).
    pub fn restore(&mut self, input: &mut crate::StateReader<'_>) -> Result<(), Error> {
        let n = Some(self.tools.len());
        let contacts = input.u64s("tool_contacts", n)?;
        self.contacts = contacts.into_iter().map(|c| c as usize).collect();
        let sticking = input.u64s("tool_sticking", n)?;
        self.sticking = sticking.into_iter().map(|c| c as usize).collect();
        ReactionMeter::restore_all(input, "tool_meters", &mut self.meters)?;
        ReactionMeter::restore_all(input, "tool_friction_meters", &mut self.friction_meters)?;
        let [contact, friction, friction_dissipated] = input.scalars::<3>("tool_work")?;
        self.work = ToolWork {
            contact,
            friction,
            friction_dissipated,
        };
        crate::state::restore_series(input, &mut self.series)
    }
}

/// Time average of a force from the impulses of successive steps (a tool's or a grip's
/// reaction), reset at each sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReactionMeter<D: Dim> {
    impulse: D::Vector,
    elapsed: f64,
    last: D::Vector,
}

impl<D: Dim> Default for ReactionMeter<D> {
    fn default() -> Self {
        Self {
            impulse: D::zero(),
            elapsed: 0.0,
            last: D::zero(),
        }
    }
}

impl<D: Dim> ReactionMeter<D> {
    /// Adds a force acting over `dt`.
    pub fn add(&mut self, force: D::Vector, dt: f64) {
        self.impulse += force * dt;
        self.elapsed += dt;
        self.last = force;
    }

    /// Writes the meters' running sums (checkpoints).
    pub fn save_all(out: &mut crate::StateWriter, name: &str, meters: &[Self]) {
        let mut v = Vec::with_capacity(2 * meters.len());
        let mut e = Vec::with_capacity(meters.len());
        for m in meters {
            v.push(m.impulse);
            v.push(m.last);
            e.push(m.elapsed);
        }
        out.vectors::<D>(name, &v);
        out.f64s(name, &e);
    }

    /// Reads back [`ReactionMeter::save_all`] into as many meters.
    pub fn restore_all(
        input: &mut crate::StateReader<'_>,
        name: &str,
        meters: &mut [Self],
    ) -> Result<(), crate::Error> {
        let v = input.vectors::<D>(name, Some(2 * meters.len()))?;
        let e = input.f64s(name, Some(meters.len()))?;
        for (k, m) in meters.iter_mut().enumerate() {
            (m.impulse, m.last, m.elapsed) = (v[2 * k], v[2 * k + 1], e[k]);
        }
        Ok(())
    }

    /// The mean force since the last call (the last step's force if no time elapsed).
    pub fn take_mean(&mut self) -> D::Vector {
        let mean = if self.elapsed > 0.0 {
            self.impulse / self.elapsed
        } else {
            self.last
        };
        self.impulse = D::zero();
        self.elapsed = 0.0;
        mean
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::{D2, D3};
    use glam::{DVec2, DVec3};

    #[test]
    fn box_distance_is_signed_with_outward_normals() {
        let b = ToolShape::<D2>::cuboid(DVec2::new(-1.0, 0.0), DVec2::new(1.0, 0.5)).unwrap();
        let (d, n) = b.distance(DVec2::new(0.2, -0.3));
        assert!(
            (d - 0.3).abs() < 1e-15 && n == DVec2::new(0.0, -1.0),
            "{d} {n}"
        );
        let (d, n) = b.distance(DVec2::new(0.9, 0.25));
        assert!(
            (d + 0.1).abs() < 1e-15 && n == DVec2::new(1.0, 0.0),
            "{d} {n}"
        );
        // Corner: distance to the corner, normal from it.
        let (d, n) = b.distance(DVec2::new(1.3, 0.9));
        assert!((d - 0.5).abs() < 1e-15, "{d}");
        assert!((n - DVec2::new(0.6, 0.8)).length() < 1e-15, "{n}");
        assert!(ToolShape::<D2>::cuboid(DVec2::ONE, DVec2::ZERO).is_err());
    }

    #[test]
    fn rounded_box_distance_is_the_sharp_ones_off_the_corners_and_a_circle_on_them() {
        let (min, max) = (DVec2::new(-1.0, 0.0), DVec2::new(1.0, 0.5));
        let b = ToolShape::<D2>::rounded_cuboid(min, max, 0.2).unwrap();
        let sharp = ToolShape::<D2>::cuboid(min, max).unwrap();
        // On a flat face, the sharp box's distance and normal.
        for x in [
            DVec2::new(0.2, -0.3),
            DVec2::new(0.9, 0.25),
            DVec2::new(-0.5, 0.7),
        ] {
            let ((d, n), (e, m)) = (b.distance(x), sharp.distance(x));
            assert!(
                (d - e).abs() < 1e-15 && (n - m).length() < 1e-15,
                "{x}: {d} {e}"
            );
        }
        // Beyond a corner: the distance to the circle of radius 0.2 about (0.8, 0.3).
        let x = DVec2::new(1.3, 0.9);
        let c = DVec2::new(0.8, 0.3);
        let (d, n) = b.distance(x);
        assert!((d - ((x - c).length() - 0.2)).abs() < 1e-15, "{d}");
        assert!((n - (x - c).normalize()).length() < 1e-15, "{n}");
        // The corner point of the sharp box is outside the rounded one.
        assert!(b.distance(max).0 > 0.0 && sharp.distance(max).0 == 0.0);
        assert_eq!(
            ToolShape::<D2>::rounded_cuboid(min, max, 0.0).unwrap(),
            sharp
        );
        assert!(
            ToolShape::<D2>::rounded_cuboid(min, max, 0.3).is_err(),
            "> half a side"
        );
        assert!(ToolShape::<D2>::rounded_cuboid(min, max, -0.1).is_err());
        assert_eq!(b.bounds(), (min, max));
    }

    #[test]
    fn ball_and_half_space_distances() {
        let s = ToolShape::<D3>::ball(DVec3::ZERO, 2.0).unwrap();
        let (d, n) = s.distance(DVec3::new(0.0, 3.0, 0.0));
        assert!((d - 1.0).abs() < 1e-15 && n == DVec3::Y);
        let w = ToolShape::<D3>::half_space(DVec3::ZERO, DVec3::new(0.0, 0.0, 2.0)).unwrap();
        assert_eq!(w.distance(DVec3::new(5.0, 1.0, -0.25)), (-0.25, DVec3::Z));
        assert!(ToolShape::<D3>::half_space(DVec3::ZERO, DVec3::ZERO).is_err());
        assert!(ToolShape::<D3>::ball(DVec3::ZERO, 0.0).is_err());
    }

    #[test]
    fn motion_ramps_smoothly_and_stops_at_its_travel() {
        let m = ToolMotion::<D2>::new(DVec2::new(0.0, -2.0), 3.0, 0.5, 1.0).unwrap();
        assert_eq!(m.velocity(0.0), DVec2::ZERO);
        // Mid-ramp speed is half the final speed; distance is the integral of the speed.
        assert!((m.velocity(0.25).y + 1.5).abs() < 1e-12);
        let ramp = m.distance(0.5);
        assert!((ramp - 0.75).abs() < 1e-12, "{ramp}");
        let h = 1e-6;
        let fd = (m.distance(0.3 + h) - m.distance(0.3 - h)) / (2.0 * h);
        assert!((fd - m.velocity(0.3).length()).abs() < 1e-8);
        let t_stop = m.arrival_time();
        assert!((t_stop - (0.5 + 0.25 / 3.0)).abs() < 1e-12, "{t_stop}");
        assert_eq!(m.distance(10.0), 1.0);
        assert_eq!(m.velocity(t_stop + 1e-9), DVec2::ZERO);
        assert_eq!(m.displacement(10.0), DVec2::new(0.0, -1.0));
        // A stop inside the ramp.
        let m = ToolMotion::<D2>::new(DVec2::X, 1.0, 1.0, 0.1).unwrap();
        assert!((m.distance(m.arrival_time()) - 0.1).abs() < 1e-12);
        assert!(ToolMotion::<D2>::new(DVec2::ZERO, 1.0, 0.0, 1.0).is_err());
        assert!(ToolMotion::<D2>::new(DVec2::X, 1.0, 0.0, 0.0).is_err());
    }

    #[test]
    fn paths_and_velocity_curves_give_their_displacements() {
        let p = ToolMotion::<D2>::path(vec![
            (0.0, DVec2::ZERO),
            (1.0, DVec2::new(0.0, -2.0)),
            (3.0, DVec2::new(4.0, -2.0)),
        ])
        .unwrap();
        assert_eq!(p.displacement(-1.0), DVec2::ZERO);
        assert_eq!(p.displacement(0.5), DVec2::new(0.0, -1.0));
        assert_eq!(p.displacement(2.0), DVec2::new(2.0, -2.0));
        assert_eq!(p.displacement(9.0), DVec2::new(4.0, -2.0));
        assert_eq!(p.velocity(0.5), DVec2::new(0.0, -2.0));
        assert_eq!(p.velocity(2.0), DVec2::new(2.0, 0.0));
        assert_eq!(p.velocity(3.5), DVec2::ZERO);
        assert_eq!((p.arrival_time(), p.distance(2.0)), (3.0, 8f64.sqrt()));
        assert!(!p.is_straight());
        assert!(ToolMotion::<D2>::path(vec![(1.0, DVec2::ZERO), (1.0, DVec2::X)]).is_err());
        assert!(ToolMotion::<D2>::path(Vec::new()).is_err());
        let ramp = Amplitude::ramp(0.0, 2.0).unwrap();
        let v = ToolMotion::<D2>::translating(DVec2::new(3.0, 0.0), Some(ramp)).unwrap();
        // ∫₀¹ t/2 dt = 1/4; after the ramp 1 + (t − 2).
        assert_eq!(v.displacement(1.0), DVec2::new(0.75, 0.0));
        assert_eq!(v.displacement(3.0), DVec2::new(6.0, 0.0));
        assert_eq!(v.velocity(1.0), DVec2::new(1.5, 0.0));
        assert!(ToolMotion::<D2>::translating(DVec2::new(f64::NAN, 0.0), None).is_err());
    }

    #[test]
    fn a_rotating_tool_turns_its_shape_and_normals_about_the_centre() {
        // A paddle [1, 2] × [−0.1, 0.1] turning about the origin at π/2 rad/s: after 1 s it
        // stands along +y.
        let shape = ToolShape::<D2>::cuboid(DVec2::new(1.0, -0.1), DVec2::new(2.0, 0.1)).unwrap();
        let motion = ToolMotion::fixed()
            .rotating(DVec2::ZERO, DVec3::Z, 0.5 * PI, None)
            .unwrap();
        let tool = RigidTool::new("paddle", shape, motion);
        assert!((tool.motion.angle(1.0) - 0.5 * PI).abs() < 1e-15);
        // The point (0, 1.5) is inside the turned paddle, 0.1 from its face at x = −0.1 whose
        // outward normal is −x (tolerance: round-off of cos(π/2)).
        let (d, n) = tool.distance_at(DVec2::new(0.0, 1.5), 1.0);
        assert!((d + 0.1).abs() < 1e-12, "{d}");
        let (d, n2) = tool.distance_at(DVec2::new(-0.3, 1.5), 1.0);
        assert!((d - 0.2).abs() < 1e-12 && (n - n2).length() < 1e-12, "{d}");
        assert!((n - DVec2::new(-1.0, 0.0)).length() < 1e-12, "{n}");
        // Contact pushes a particle in the paddle's way along the turned normal.
        let x = vec![DVec2::new(-0.05, 1.5)];
        let mut v = vec![DVec2::ZERO];
        let out = tool.enforce_contact(1.0, 0.01, |_, _| 0.0, 0.0, &x, &mut v, &[1.0], &[true]);
        assert_eq!(out.active, 1);
        assert!(v[0].x < 0.0 && v[0].y.abs() < 1e-9, "{:?}", v[0]);
        // 3D: a quarter turn about z through (1, 0, 0) takes (2, 0, 0) to (1, 1, 0).
        let r = rotation_matrix::<D3>(DVec3::Z, 0.5 * PI);
        let y = DVec3::X + r * (DVec3::new(2.0, 0.0, 0.0) - DVec3::X);
        assert!((y - DVec3::new(1.0, 1.0, 0.0)).length() < 1e-15, "{y}");
        // In 2D only the z axis.
        assert!(ToolMotion::<D2>::fixed()
            .rotating(DVec2::ZERO, DVec3::X, 1.0, None)
            .is_err());
    }

    #[test]
    fn a_corner_radius_of_half_the_side_is_accepted_when_the_corners_round_off() {
        // (1.5e-3 + 3e-4) − 1.5e-3 = 2.9999999999999992e-4: half of it is below 1.5e-4.
        let (h, t) = (1.5e-3, 3e-4);
        let min = DVec2::new(-4.5e-3, h);
        let max = DVec2::new(4.5e-3, h + t);
        assert!((max.y - min.y) * 0.5 < 1.5e-4);
        let s = ToolShape::<D2>::rounded_cuboid(min, max, 1.5e-4).unwrap();
        let ToolShape::RoundedBox { radius, .. } = s else {
            panic!("{s:?}")
        };
        assert_eq!(radius, 0.5 * (max.y - min.y));
        // Beyond round-off it is still refused.
        assert!(ToolShape::<D2>::rounded_cuboid(min, max, 1.51e-4).is_err());
    }

    #[test]
    fn contact_puts_particles_on_the_offset_surface_along_the_normal_only() {
        // A platen whose lower face is at y = 0 moving down at 1 m/s; three particles below.
        let shape = ToolShape::<D2>::cuboid(DVec2::new(-1.0, 0.0), DVec2::new(1.0, 1.0)).unwrap();
        let motion = ToolMotion::new(DVec2::new(0.0, -1.0), 1.0, 0.0, f64::INFINITY).unwrap();
        let tool = RigidTool::new("punch", shape, motion);
        let x = vec![
            DVec2::new(0.0, -0.7),
            DVec2::new(0.5, -0.45),
            DVec2::new(3.0, -0.45),
        ];
        let mut v = vec![DVec2::new(0.3, 0.0), DVec2::new(-0.2, 0.1), DVec2::ZERO];
        let m = vec![2.0, 1.0, 1.0];
        let (t_end, drift, offset) = (0.1, 0.05, 0.5);
        let out = tool.enforce_contact(
            t_end,
            drift,
            |_, _| offset,
            offset,
            &x,
            &mut v,
            &m,
            &[true; 3],
        );
        // Particle 0 ends at -0.7, clear of the offset surface at -0.1 - 0.5 = -0.6. Particle 1
        // would end at -0.445, above the offset surface at -0.6: pushed down to land on it.
        assert_eq!(out.active, 1);
        assert_eq!(v[0], DVec2::new(0.3, 0.0));
        let end = x[1] + v[1] * drift;
        assert!((end.y + 0.6).abs() < 1e-14, "{end}");
        // Tangential velocity untouched (frictionless), impulse along the normal only.
        assert_eq!(v[1].x, -0.2);
        assert!((out.impulse.y - m[1] * (v[1].y - 0.1)).abs() < 1e-14);
        assert_eq!(out.impulse.x, 0.0);
        // Far particle: untouched.
        assert_eq!(v[2], DVec2::ZERO);
    }

    #[test]
    fn friction_sticks_within_the_static_cone_and_slides_on_the_kinetic_one() {
        // A floor at y = 0 at rest; one particle pressed into it at 1 m/s, sliding along it.
        let floor = ToolShape::<D2>::half_space(DVec2::ZERO, DVec2::Y).unwrap();
        let tool = RigidTool::new("floor", floor, ToolMotion::fixed())
            .with_friction(Friction::new(0.5, 0.2).unwrap());
        let x = vec![DVec2::new(0.0, 0.0)];
        let (tau, m) = (0.1, [2.0]);
        // Slides at 0.4 ≤ μ_s · 1: stuck.
        let mut v = vec![DVec2::new(0.4, -1.0)];
        let out = tool.enforce_contact(tau, tau, |_, _| 0.0, 0.0, &x, &mut v, &m, &[true]);
        assert_eq!((out.active, out.sticking), (1, 1));
        assert!(v[0].length() < 1e-15, "{}", v[0]);
        // The friction impulse is what stopped the slide; the work is the kinetic energy lost.
        assert!((out.friction_impulse - DVec2::new(-0.8, 0.0)).length() < 1e-15);
        assert!((out.impulse - DVec2::new(-0.8, 2.0)).length() < 1e-15);
        let ke = 0.5 * 2.0 * (0.4f64.powi(2) + 1.0);
        assert!((out.normal_work + out.friction_work + ke).abs() < 1e-15);
        assert!((out.friction_dissipation + out.friction_work).abs() < 1e-15);
        // Slides at 0.9 > μ_s · 1: slowed by μ_k · 1.
        let mut v = vec![DVec2::new(-0.9, -1.0)];
        let out = tool.enforce_contact(tau, tau, |_, _| 0.0, 0.0, &x, &mut v, &m, &[true]);
        assert_eq!((out.active, out.sticking), (1, 0));
        assert!((v[0] - DVec2::new(-0.7, 0.0)).length() < 1e-15, "{}", v[0]);
        assert!(out.friction_dissipation > 0.0);
    }

    #[test]
    fn a_moving_tool_drags_what_sticks_to_it_and_does_work_through_friction() {
        // A belt (the floor moving at 2 m/s along x) under a particle at rest pressed into it.
        let floor = ToolShape::<D3>::half_space(DVec3::ZERO, DVec3::Z).unwrap();
        let belt = ToolMotion::translating(DVec3::new(2.0, 0.0, 0.0), None).unwrap();
        let tool =
            RigidTool::new("belt", floor, belt).with_friction(Friction::new(1.0, 1.0).unwrap());
        let x = vec![DVec3::ZERO];
        let mut v = vec![DVec3::new(0.0, 0.0, -3.0)];
        let out = tool.enforce_contact(1.0, 0.5, |_, _| 0.0, 0.0, &x, &mut v, &[1.0], &[true]);
        // Relative slip 2 m/s ≤ μ_s · 3: it sticks, moving with the belt.
        assert_eq!(out.sticking, 1);
        assert!(
            (v[0] - DVec3::new(2.0, 0.0, 0.0)).length() < 1e-12,
            "{}",
            v[0]
        );
        // The belt did positive work on it (½ m 2²); the dissipation is what the slip lost.
        assert!(
            (out.friction_work - 2.0).abs() < 1e-12,
            "{}",
            out.friction_work
        );
        assert!(
            (out.friction_dissipation - 2.0).abs() < 1e-12,
            "{}",
            out.friction_dissipation
        );
        // A turning tool: a disc of radius 1 spinning at 1 rad/s about its centre drags a
        // particle sticking to its rim at the rim's speed, tangentially.
        let disc = ToolShape::<D2>::ball(DVec2::ZERO, 1.0).unwrap();
        let spin = ToolMotion::fixed()
            .rotating(DVec2::ZERO, DVec3::Z, 1.0, None)
            .unwrap();
        let tool =
            RigidTool::new("disc", disc, spin).with_friction(Friction::new(1.0, 1.0).unwrap());
        let x = vec![DVec2::new(0.0, 1.0)];
        let mut v = vec![DVec2::new(0.0, -2.0)];
        let tau = 1e-6;
        let out = tool.enforce_contact(tau, tau, |_, _| 0.0, 0.0, &x, &mut v, &[1.0], &[true]);
        assert_eq!(out.sticking, 1);
        assert!((v[0] - DVec2::new(-1.0, 0.0)).length() < 1e-5, "{}", v[0]);
    }

    #[test]
    fn a_tool_set_meters_the_friction_and_keeps_series_columns_of_frictionless_tools() {
        let floor = ToolShape::<D2>::half_space(DVec2::ZERO, DVec2::Y).unwrap();
        let plain = RigidTool::new("plain", floor, ToolMotion::fixed());
        let rough = RigidTool::new("rough", floor, ToolMotion::fixed())
            .with_friction(Friction::new(0.3, 0.3).unwrap());
        let mut set = ToolSet::new(vec![plain.clone(), rough], &[], 10.0).unwrap();
        assert!(set.has_friction());
        assert_eq!(
            set.series()[0].columns,
            ["displacement", "force_x", "force_y", "contacts"]
        );
        assert_eq!(
            set.series()[1].columns,
            [
                "displacement",
                "force_x",
                "force_y",
                "contacts",
                "friction_x",
                "friction_y",
                "sticking"
            ]
        );
        // Two particles sliding into the floors: the first tool takes all the normal
        // velocity, the second none (already on the surface), so no friction there.
        let x = vec![DVec2::ZERO, DVec2::new(1.0, 0.0)];
        let mut v = vec![DVec2::new(1.0, -1.0), DVec2::new(0.1, -1.0)];
        set.begin_step();
        set.enforce(
            0.5,
            0.5,
            |_, _| 0.0,
            0.0,
            &x,
            &mut v,
            &[1.0, 1.0],
            &[true, true],
            true,
        );
        set.end_step(0.5);
        set.record(0.5);
        assert_eq!(set.contacts(), &[2, 0]);
        let s = &set.series()[0];
        assert_eq!(s.column("force_y").unwrap()[1], -4.0);
        assert_eq!(set.series()[1].column("friction_x").unwrap()[1], 0.0);
        // Names are checked, and a tool must be slower than sound.
        assert!(ToolSet::new(vec![plain.clone(), plain.clone()], &[], 10.0).is_err());
        assert!(ToolSet::new(vec![plain.clone()], &["plain"], 10.0).is_err());
        let fast = RigidTool::new(
            "fast",
            floor,
            ToolMotion::translating(DVec2::new(20.0, 0.0), None).unwrap(),
        );
        assert!(ToolSet::new(vec![fast], &[], 10.0).is_err());
        // Its state round-trips through a checkpoint.
        let mut out = crate::StateWriter::default();
        set.save(&mut out);
        let bytes = out.into_bytes();
        let mut back = ToolSet::new(set.tools().to_vec(), &[], 10.0).unwrap();
        back.restore(&mut crate::StateReader::new(&bytes)).unwrap();
        assert_eq!(back.work(), set.work());
        assert_eq!(back.series(), set.series());
    }

    #[test]
    fn reaction_meter_averages_over_the_interval() {
        let mut r = ReactionMeter::<D2>::default();
        r.add(DVec2::new(1.0, 0.0), 1.0);
        r.add(DVec2::new(4.0, 2.0), 3.0);
        assert_eq!(r.take_mean(), DVec2::new(3.25, 1.5));
        assert_eq!(r.take_mean(), DVec2::new(4.0, 2.0));
    }
}
