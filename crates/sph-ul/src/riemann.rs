//! Equation of state and the low-dissipation Riemann solver for pressure and continuity
//! (UL paper eq 4, 11–12; docs/methods.md "Updated Lagrangian").
//!
//! Convention: `e_ij = (x_i − x_j)/r_ij` points from `j` to `i`; `u_ij = (v_i − v_j)·e_ij` is
//! negative when `i` and `j` approach. `W′ ≤ 0`, so `−P* W′ e_ij` pushes `i` away from `j` for
//! `P* > 0`.

use serde::{Deserialize, Serialize};

/// Which form of the Riemann solver to use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RiemannScheme {
    /// The paper: limiter `β = min(3 max(−u_ij, 0)/c0, 1)` (dissipation only in compression)
    /// and the pressure jump in the continuity equation.
    ///
    /// Caution for solids: the jump `(p_i − p_j)/(ρ0 c0)` changes the density of particles
    /// that do not move (a density diffusion of strength ~`c0 h`, first order at free
    /// surfaces). In a solid the density is the volumetric strain, so this is a volumetric
    /// creep: the oscillating plate (ENOG, H/dp = 10) runs 24 % slow (T = 0.346 against 0.279
    /// without the jump; 0.330 against 0.273 at H/dp = 20). Hence the default is
    /// [`RiemannScheme::SphinxsysTests`], in the library as in the cases.
    Paper,
    /// What SPHinXsys's elastic-solid tests actually ran: `β = 1` in the momentum equation
    /// (dissipation in compression and expansion) and no pressure jump in continuity. The
    /// default (library and command line).
    #[default]
    SphinxsysTests,
    /// The paper's limiter `β` in the momentum equation, no pressure jump in continuity (the
    /// density then changes only through motion).
    LimitedNoJump,
}

/// Eq. (4) of the UL paper: weakly-compressible equation of state `p = c0² (ρ − ρ0)`.
#[inline(always)]
pub fn pressure(rho: f64, rho0: f64, c0: f64) -> f64 {
    c0 * c0 * (rho - rho0)
}

/// Low-dissipation limiter of the Riemann solver (UL paper ref. 28):
/// `β = min(3 max(−u_ij, 0)/c0, 1)`; zero for separating pairs (`u_ij ≥ 0`).
#[inline(always)]
pub fn limiter(u_ij: f64, c0: f64) -> f64 {
    (3.0 * (-u_ij).max(0.0) / c0).min(1.0)
}

/// Interface pressure `P*` of eq. (12) of the UL paper:
/// `P* = ½(p_i + p_j) − ½ β ρ0 c0 u_ij`, with the dissipative part from
/// [`dissipative_pressure`]. Approaching pairs (`u_ij < 0`) get `P* ≥ p̄`.
#[inline(always)]
pub fn interface_pressure(
    p_i: f64,
    p_j: f64,
    u_ij: f64,
    rho0: f64,
    c0: f64,
    scheme: RiemannScheme,
) -> f64 {
    0.5 * (p_i + p_j) + dissipative_pressure(u_ij, rho0, c0, scheme)
}

/// The dissipative part of the interface pressure of eq. (12) of the UL paper,
/// `−½ β ρ0 c0 u_ij`, with `β` from [`limiter`] (or `β = 1` for
/// [`RiemannScheme::SphinxsysTests`]). Its pair power `∝ β u_ij² W′ ≤ 0`: it only removes
/// energy (the energy budget accumulates its work as "dissipated").
#[inline(always)]
pub fn dissipative_pressure(u_ij: f64, rho0: f64, c0: f64, scheme: RiemannScheme) -> f64 {
    let beta = match scheme {
        RiemannScheme::Paper | RiemannScheme::LimitedNoJump => limiter(u_ij, c0),
        RiemannScheme::SphinxsysTests => 1.0,
    };
    -0.5 * beta * rho0 * c0 * u_ij
}

/// Pressure acceleration of one pair, eq. (12) of the UL paper:
/// `−2 m_j P*/(ρ_i ρ_j) ∇_i W_ij = −2 P* (V_j/ρ_i) W′ e_ij` with `V_j = m_j/ρ_j`.
/// Returns the scalar factor multiplying `e_ij`.
#[inline(always)]
pub fn pressure_pair_factor(p_star: f64, dw: f64, v_j_over_rho_i: f64) -> f64 {
    -2.0 * p_star * dw * v_j_over_rho_i
}

/// Pair term of the continuity equation, eq. (11) of the UL paper in the form of docs/methods.md:
/// `dρ_i/dt = ρ_i Σ_j [u_ij + (p_i − p_j)/(ρ0 c0)] W′_ij V_j`. Returns the bracket; the
/// pressure jump ([`continuity_jump`]: a pressure excess at `i` slows its density growth) is
/// dropped for [`RiemannScheme::SphinxsysTests`] and [`RiemannScheme::LimitedNoJump`].
#[inline(always)]
pub fn continuity_pair(u_ij: f64, p_i: f64, p_j: f64, rho0_c0: f64, scheme: RiemannScheme) -> f64 {
    u_ij + continuity_jump(p_i, p_j, rho0_c0, scheme)
}

/// The pressure-jump part of [`continuity_pair`], `(p_i − p_j)/(ρ0 c0)` for
/// [`RiemannScheme::Paper`], else 0. It changes the density without motion (a diffusion of
/// density); its effect on the volumetric energy, `Σ_pairs V_i V_j W′ (p_i − p_j)²/(ρ0 c0) ≤ 0`,
/// is a loss the energy budget accumulates as "diffused".
#[inline(always)]
pub fn continuity_jump(p_i: f64, p_j: f64, rho0_c0: f64, scheme: RiemannScheme) -> f64 {
    match scheme {
        RiemannScheme::Paper => (p_i - p_j) / rho0_c0,
        RiemannScheme::SphinxsysTests | RiemannScheme::LimitedNoJump => 0.0,
    }
}

/// Whether `scheme` has a pressure jump in the continuity equation at all
/// ([`continuity_jump`] is identically zero otherwise), so the gather can skip it.
#[inline]
pub fn continuity_has_jump(scheme: RiemannScheme) -> bool {
    matches!(scheme, RiemannScheme::Paper)
}

/// Potential energy of the equation of state for a particle of mass `m`: with
/// `de/dρ = p/ρ²` and eq. (4), `m c0² (ln(ρ/ρ0) + ρ0/ρ − 1)` (zero at `ρ0`, ≥ 0).
#[inline]
pub fn pressure_energy(m: f64, rho: f64, rho0: f64, c0: f64) -> f64 {
    m * c0 * c0 * ((rho / rho0).ln() + rho0 / rho - 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limiter_is_zero_in_expansion_and_saturates_in_compression() {
        assert_eq!(limiter(0.5, 10.0), 0.0);
        assert_eq!(limiter(0.0, 10.0), 0.0);
        assert!((limiter(-1.0, 10.0) - 0.3).abs() < 1e-15);
        assert_eq!(limiter(-10.0, 10.0), 1.0);
    }

    #[test]
    fn interface_pressure_exceeds_mean_only_for_approaching_pairs() {
        let (rho0, c0) = (1000.0, 50.0);
        let p = interface_pressure(100.0, 300.0, -2.0, rho0, c0, RiemannScheme::Paper);
        assert!(p > 200.0);
        let p = interface_pressure(100.0, 300.0, 2.0, rho0, c0, RiemannScheme::Paper);
        assert_eq!(p, 200.0);
        let p = interface_pressure(100.0, 300.0, 2.0, rho0, c0, RiemannScheme::SphinxsysTests);
        assert!(p < 200.0);
    }
}
