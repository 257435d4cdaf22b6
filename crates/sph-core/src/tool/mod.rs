//! Rigid tools (punches, platens, walls) that move with a prescribed velocity history and touch
//! a deformable body through **kinematic contact**, frictionless or with Coulomb friction
//! ([`crate::friction`]); a [`ToolSet`] is what every method attaches (TL, UL and MPS alike).
//!
//! # The contact law
//!
//! A tool is a rigid shape ([`ToolShape`]: box, ball, half-space, or a triangle mesh or 2D
//! outline through [`SignedDistance`]) with a signed distance
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
use crate::friction::{coulomb_velocity_change, Friction};

mod motion;
mod set;
mod shape;

pub use motion::{rotation_matrix, Pose, ToolMotion, ToolRotation};
pub use set::{ReactionMeter, ToolSet, ToolWork};
pub use shape::{SignedDistance, ToolShape};

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

#[cfg(test)]
mod tests;
