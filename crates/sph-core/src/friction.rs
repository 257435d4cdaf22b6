//! Coulomb friction at the velocity level, for contacts enforced as velocity constraints (the
//! rigid tools of [`crate::tool`]).
//!
//! # The scheme
//!
//! A contact that removes a particle's approach velocity in one step gives it a normal velocity
//! change `Δv_n ≥ 0` (per unit mass: the normal impulse is `m Δv_n`). Friction then acts on the
//! particle's tangential velocity relative to the partner, `v_t`, within the same step, as an
//! impulse in the manner of Moreau's velocity-level (sweeping-process) treatment of unilateral
//! contact with Coulomb friction (J. J. Moreau, *Unilateral contact and dry friction in finite
//! freedom dynamics*, 1988), with the stick/slip return of the penalty contact of Hallquist,
//! Goudreau and Benson (*Sliding interfaces with contact-impact in large-scale Lagrangian
//! computations*, CMAME 51, 1985), as LS-DYNA applies it:
//!
//! 1. **trial (stick)**: the tangential velocity change that stops the relative sliding,
//!    `Δv_t* = −v_t`;
//! 2. if `|Δv_t*| ≤ μ_s Δv_n` the particle **sticks**: `Δv_t = Δv_t*`;
//! 3. otherwise it **slips**: the trial is returned to the kinetic cone,
//!    `Δv_t = −μ_k Δv_n v_t/|v_t|` (never more than stops it, since `μ_k ≤ μ_s`).
//!
//! Why this scheme: the contact itself has no stiffness (it is the limit of an infinitely stiff
//! penalty), and so has this friction: there is no tangential penalty stiffness to choose and no
//! time-step restriction from one, sticking is exact (zero relative tangential velocity, not a
//! small elastic creep), and a frictionless contact (`μ_s = 0`) never enters the code path (its
//! results are bit for bit those of the frictionless contact). A regularised law (a tangential
//! spring or a velocity ramp `μ(v_t)`) would need a regularisation parameter whose value changes
//! the result.
//!
//! # Work
//!
//! The work the friction impulse does on the particle is `½ m (|v⁺|² − |v⁻|²)` over its
//! velocity change. It is dissipation only when the partner is at rest: a moving tool does work
//! through friction too (a conveyor belt accelerates what lies on it), so the dissipated energy
//! is `−Σ m Δv_t · (v_mid − v_tool)` with `v_mid` the mean of the velocities before and after,
//! which is what [`coulomb_velocity_change`]'s caller accumulates when it keeps the two apart.

use crate::dim::Dim;
use crate::error::{Error, Num};

/// Static and kinetic Coulomb coefficients of a contact (`0 ≤ μ_k ≤ μ_s`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Friction {
    /// The static coefficient `μ_s`: a particle sticks while the sticking impulse is within
    /// `μ_s` times the normal impulse.
    pub static_coefficient: f64,
    /// The kinetic coefficient `μ_k`: a sliding particle receives `μ_k` times the normal
    /// impulse against its sliding direction.
    pub kinetic_coefficient: f64,
}

impl Friction {
    /// No friction (`μ_s = μ_k = 0`).
    pub const NONE: Self = Self {
        static_coefficient: 0.0,
        kinetic_coefficient: 0.0,
    };

    /// Coefficients `μ_s` (`friction_static`) and `μ_k` (`friction_kinetic`).
    ///
    /// # Errors
    /// A negative or non-finite coefficient, or `μ_k > μ_s`.
    ///
    /// ```
    /// use sph_core::friction::Friction;
    /// let f = Friction::new(0.4, 0.3)?;
    /// assert!(!f.is_frictionless());
    /// assert!(Friction::new(0.3, 0.4).is_err());
    /// # Ok::<(), sph_core::Error>(())
    /// ```
    pub fn new(static_coefficient: f64, kinetic_coefficient: f64) -> Result<Self, Error> {
        for (name, mu) in [
            ("friction_static", static_coefficient),
            ("friction_kinetic", kinetic_coefficient),
        ] {
            if !(mu.is_finite() && mu >= 0.0) {
                return Err(Error::invalid(name, Num(mu), "finite and >= 0"));
            }
        }
        if kinetic_coefficient > static_coefficient {
            return Err(Error::invalid(
                "friction_kinetic",
                Num(kinetic_coefficient),
                &format!(
                    "0 <= friction_kinetic <= friction_static (= {})",
                    Num(static_coefficient)
                ),
            ));
        }
        Ok(Self {
            static_coefficient,
            kinetic_coefficient,
        })
    }

    /// Whether the contact is frictionless (`μ_s = 0`, hence `μ_k = 0`).
    pub fn is_frictionless(&self) -> bool {
        self.static_coefficient == 0.0
    }
}

/// The tangential velocity change of a contacting particle (see the
/// [module documentation](self)): `slip` is the particle's velocity relative to its partner
/// with the normal component removed (`v_t`), `normal_change ≥ 0` the normal velocity change the
/// contact gave it in this step (`Δv_n`). Returns `Δv_t` and whether the particle sticks.
///
/// ```
/// use sph_core::friction::{coulomb_velocity_change, Friction};
/// use sph_core::{glam::DVec2, D2};
/// let f = Friction::new(0.5, 0.3)?;
/// // Within the static cone: stopped.
/// let (dv, stick) = coulomb_velocity_change::<D2>(DVec2::new(0.4, 0.0), 1.0, f);
/// assert!(stick && dv == DVec2::new(-0.4, 0.0));
/// // Outside: slowed by μ_k Δv_n.
/// let (dv, stick) = coulomb_velocity_change::<D2>(DVec2::new(2.0, 0.0), 1.0, f);
/// assert!(!stick && dv == DVec2::new(-0.3, 0.0));
/// # Ok::<(), sph_core::Error>(())
/// ```
#[inline]
pub fn coulomb_velocity_change<D: Dim>(
    slip: D::Vector,
    normal_change: f64,
    friction: Friction,
) -> (D::Vector, bool) {
    let speed = D::norm(slip);
    if speed <= friction.static_coefficient * normal_change {
        (-slip, true)
    } else {
        (
            slip * (-friction.kinetic_coefficient * normal_change / speed),
            false,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::{D2, D3};
    use glam::{DVec2, DVec3};

    #[test]
    fn coefficients_are_checked() {
        assert!(Friction::new(0.0, 0.0).unwrap().is_frictionless());
        assert_eq!(Friction::default(), Friction::NONE);
        let e = Friction::new(-0.1, 0.0).unwrap_err().to_string();
        assert!(e.contains("friction_static") && e.contains(">= 0"), "{e}");
        let e = Friction::new(0.2, 0.3).unwrap_err().to_string();
        assert!(e.contains("friction_kinetic") && e.contains("<="), "{e}");
        assert!(Friction::new(f64::NAN, 0.0).is_err());
        assert!(Friction::new(0.2, f64::INFINITY).is_err());
    }

    #[test]
    fn sticking_stops_the_slip_and_sliding_is_returned_to_the_kinetic_cone() {
        let f = Friction::new(0.4, 0.3).unwrap();
        // At the cone's edge: still sticking.
        let (dv, stick) = coulomb_velocity_change::<D3>(DVec3::new(0.0, 0.4, 0.0), 1.0, f);
        assert!(stick && dv == DVec3::new(0.0, -0.4, 0.0));
        // Beyond: μ_k Δv_n against the slip direction, whatever that direction is.
        let slip = DVec3::new(3.0, 0.0, -4.0);
        let (dv, stick) = coulomb_velocity_change::<D3>(slip, 2.0, f);
        assert!(!stick);
        assert!((dv + slip.normalize() * 0.6).length() < 1e-15, "{dv}");
        // No normal impulse: no friction on a sliding particle, none needed on a still one.
        let (dv, stick) = coulomb_velocity_change::<D2>(DVec2::X, 0.0, f);
        assert!(!stick && dv == DVec2::ZERO);
        let (dv, stick) = coulomb_velocity_change::<D2>(DVec2::ZERO, 0.0, f);
        assert!(stick && dv == DVec2::ZERO);
        // Never reverses the slip: |Δv_t| ≤ |v_t| in both branches.
        for s in [0.1, 0.39, 0.41, 1.0, 10.0] {
            let slip = DVec2::new(s, 0.0);
            let (dv, _) = coulomb_velocity_change::<D2>(slip, 1.0, f);
            assert!(dv.length() <= slip.length() && dv.x <= 0.0, "{s}: {dv}");
        }
    }
}
