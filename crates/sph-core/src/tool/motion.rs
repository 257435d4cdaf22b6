//! A rigid tool's prescribed motion: translation paths and curves, rotation, its pose in time.

use crate::amplitude::Amplitude;
use crate::dim::Dim;
use crate::error::{check_non_negative, Error};
use glam::DVec3;
use std::f64::consts::PI;

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
    /// points move faster: see [`RigidTool::max_speed`](super::RigidTool::max_speed).
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
