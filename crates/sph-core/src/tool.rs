//! Rigid tools (punches, platens, walls) that move with a prescribed velocity history and touch
//! a deformable body through **frictionless kinematic contact**.
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

use crate::dim::Dim;
use crate::error::{check_non_negative, check_positive, Error};
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

/// A prescribed rigid translation: along a unit `direction` with speed `v(t)` that rises
/// smoothly from 0 to `speed` over `ramp_time` (`v = speed (1 − cos(π t/T))/2`; a jump when
/// `ramp_time` is 0), then stays constant until the tool has travelled `travel`, where it stops
/// and holds its position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToolMotion<D: Dim> {
    direction: D::Vector,
    speed: f64,
    ramp_time: f64,
    travel: f64,
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
        Ok(Self {
            direction: direction / len,
            speed,
            ramp_time,
            travel,
        })
    }

    /// A tool at rest.
    pub fn fixed() -> Self {
        let mut e = D::zero();
        D::set_component(&mut e, 0, 1.0);
        Self {
            direction: e,
            speed: 0.0,
            ramp_time: 0.0,
            travel: f64::INFINITY,
        }
    }

    /// The unit direction of travel.
    pub fn direction(&self) -> D::Vector {
        self.direction
    }

    /// The speed after the ramp (m/s).
    pub fn speed(&self) -> f64 {
        self.speed
    }

    /// Distance travelled by time `t` before the stop (no clamping).
    fn free_distance(&self, t: f64) -> f64 {
        let (v, tr) = (self.speed, self.ramp_time);
        if t <= 0.0 {
            0.0
        } else if t < tr {
            0.5 * v * (t - tr / PI * (PI * t / tr).sin())
        } else {
            0.5 * v * tr + v * (t - tr)
        }
    }

    /// Distance travelled along the direction by time `t`.
    pub fn distance(&self, t: f64) -> f64 {
        self.free_distance(t).min(self.travel)
    }

    /// Displacement by time `t`.
    pub fn displacement(&self, t: f64) -> D::Vector {
        self.direction * self.distance(t)
    }

    /// Velocity at time `t` (zero once stopped).
    pub fn velocity(&self, t: f64) -> D::Vector {
        if t <= 0.0 || self.free_distance(t) >= self.travel {
            return D::zero();
        }
        let s = if t < self.ramp_time {
            0.5 * (1.0 - (PI * t / self.ramp_time).cos())
        } else {
            1.0
        };
        self.direction * (self.speed * s)
    }

    /// The time at which the tool stops (infinite if it never does).
    pub fn arrival_time(&self) -> f64 {
        if !self.travel.is_finite() || self.speed <= 0.0 {
            return f64::INFINITY;
        }
        let ramp_distance = self.free_distance(self.ramp_time);
        if self.travel >= ramp_distance {
            return self.ramp_time + (self.travel - ramp_distance) / self.speed;
        }
        // Inside the ramp: the distance is monotone, bisect.
        let (mut lo, mut hi) = (0.0, self.ramp_time);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if self.free_distance(mid) < self.travel {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        hi
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
}

/// What one contact pass did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactOutcome<D: Dim> {
    /// Momentum given to the body, `Σ m Δv` (the tool receives `−impulse`; the reaction force
    /// on the tool over a step `Δt` is `−impulse/Δt`).
    pub impulse: D::Vector,
    /// Particles in contact this step.
    pub active: usize,
}

impl<D: Dim> RigidTool<D> {
    /// A tool named `name`.
    pub fn new(name: &str, shape: ToolShape<D>, motion: ToolMotion<D>) -> Self {
        Self {
            name: name.to_string(),
            shape,
            motion,
        }
    }

    /// Signed distance and outward normal of the tool at time `t`.
    pub fn distance_at(&self, x: D::Vector, t: f64) -> (f64, D::Vector) {
        self.shape.distance(x - self.motion.displacement(t))
    }

    /// Frictionless kinematic contact (see the [module documentation](self)): for every
    /// particle with `movable[i]`, whose predicted position `x + lookahead·v` lies closer than
    /// its contact offset `offset(i, n)` (`n` the tool's normal there) to the tool at time
    /// `t_end` (the time of that prediction), adds the normal velocity that puts it on the
    /// offset surface. `max_offset` bounds the offsets (a cheap bounding-box rejection).
    /// Sequential, so the impulse sum is deterministic.
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
        let shift = self.motion.displacement(t_end);
        let (lo, hi) = self.shape.bounds();
        let reach = max_offset * (1.0 + 1e-12);
        let mut impulse = D::zero();
        let mut active = 0;
        for i in 0..positions.len() {
            if !movable[i] {
                continue;
            }
            let x = positions[i] + velocities[i] * lookahead - shift;
            // Cheap rejection against the bounding box grown by the offset.
            if (0..D::D).any(|k| {
                let c = D::component(x, k);
                c < D::component(lo, k) - reach || c > D::component(hi, k) + reach
            }) {
                continue;
            }
            let (d, n) = self.shape.distance(x);
            let gap = d - offset(i, n);
            if gap < 0.0 {
                let dv = n * (-gap / lookahead);
                velocities[i] += dv;
                impulse += dv * masses[i];
                active += 1;
            }
        }
        ContactOutcome { impulse, active }
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
    fn reaction_meter_averages_over_the_interval() {
        let mut r = ReactionMeter::<D2>::default();
        r.add(DVec2::new(1.0, 0.0), 1.0);
        r.add(DVec2::new(4.0, 2.0), 3.0);
        assert_eq!(r.take_mean(), DVec2::new(3.25, 1.5));
        assert_eq!(r.take_mean(), DVec2::new(4.0, 2.0));
    }
}
