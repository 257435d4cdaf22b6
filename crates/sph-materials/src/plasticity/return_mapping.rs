//! The radial return of J2 plasticity for a hypoelastic deviatoric stress (Simo & Hughes 1998,
//! Box 3.2; Wilkins 1964): the elastic trial deviator `s*` of the step, the yield check, the
//! consistency equation for the plastic increment `Δε̄p`, and the scaling back onto the yield
//! surface. The pressure is not touched: plastic flow is isochoric.

use super::{PlasticLaw, PlasticState};
use sph_core::Dim;

/// Relative residual `|q − σ_y| / q*` at which the Newton iteration of
/// [`solve_consistency`] stops: a few ulps of the trial stress, the accuracy to which the
/// residual itself can be evaluated.
pub const CONSISTENCY_TOLERANCE: f64 = 1e-14;

/// Most iterations of [`solve_consistency`]: bisection alone would need ~60 to exhaust the
/// bracket in double precision; Newton takes 2–6.
const MAX_ITERATIONS: u32 = 200;

/// Von Mises equivalent stress of a deviator, `q = √(3/2 s:s)`, so that the yield condition
/// `‖s‖ ≤ √(2/3) σ_y` of Simo & Hughes 1998 (Box 3.1) reads `q ≤ σ_y`. In 2D `s` is the
/// in-plane deviator the solver integrates, with `s_zz = 0`.
#[inline]
pub fn equivalent_stress<D: Dim>(s: D::Matrix) -> f64 {
    (1.5 * D::ddot(s, s)).sqrt()
}

/// The outcome of one radial return.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadialReturn<D: Dim> {
    /// The returned deviator `s = (1 − 3G Δε̄p / q*) s*` (the trial itself if elastic).
    pub deviator: D::Matrix,
    /// The equivalent plastic strain increment `Δε̄p ≥ 0` (0 if elastic).
    pub delta_eps_p: f64,
    /// The flow stress at the end of the step, `σ_y(ε̄p_n + Δε̄p, Δε̄p/Δt, T_n)`.
    pub flow_stress: f64,
    /// The trial equivalent stress `q*`.
    pub trial_equivalent_stress: f64,
    /// Newton iterations taken (0 when elastic or solved in closed form).
    pub iterations: u32,
}

/// The plastic increment `Δε̄p` that makes the returned stress consistent,
/// `g(Δε̄p) = q* − 3G Δε̄p − σ_y(ε̄p_n + Δε̄p, Δε̄p/Δt, T_n) = 0`, given that the trial
/// stress is plastic (`g(0) > 0`); returns `(Δε̄p, σ_y, iterations)`.
///
/// Linear hardening: `Δε̄p = (q* − σ_y,n)/(3G + H)` exactly (Simo & Hughes 1998, Box 3.2 with
/// a linear `K`). Otherwise Newton's method on `g` (Box 3.2, step 4) with the consistent slope
/// `dσ_y/dΔε̄p` of [`PlasticLaw::flow_stress_after`], safeguarded by bisection on the bracket
/// `[0, (q* − σ_y,n)/3G]`: `g` decreases monotonically there (every law here is
/// non-softening in `ε̄p` and `ε̇̄p`, the temperature is that of the step's start), so the root
/// is unique and the iteration converges even where the slope is infinite (`ε̄p^n`, `n < 1`,
/// at `ε̄p = 0`) or jumps (the rate clamp at `ε̇̄p = ε̇0`).
pub fn solve_consistency(
    law: &PlasticLaw,
    shear_modulus: f64,
    q_trial: f64,
    state: &PlasticState,
    dt: f64,
) -> (f64, f64, u32) {
    let three_g = 3.0 * shear_modulus;
    let (sigma0, slope0) = law.flow_stress_after(state, 0.0, dt);
    let excess = q_trial - sigma0;
    if let Some(h) = law.linear_hardening_modulus() {
        let delta = excess / (three_g + h);
        return (delta, sigma0 + h * delta, 0);
    }
    let (mut lo, mut hi) = (0.0, excess / three_g);
    let mut delta = if slope0.is_finite() {
        excess / (three_g + slope0)
    } else {
        0.5 * hi
    };
    let mut sigma = sigma0;
    for it in 1..=MAX_ITERATIONS {
        let (s, slope) = law.flow_stress_after(state, delta, dt);
        sigma = s;
        let g = q_trial - three_g * delta - s;
        if g.abs() <= CONSISTENCY_TOLERANCE * q_trial {
            return (delta, sigma, it);
        }
        if g > 0.0 {
            lo = delta;
        } else {
            hi = delta;
        }
        if hi - lo <= 4.0 * f64::EPSILON * hi {
            return (delta, sigma, it);
        }
        let newton = delta + g / (three_g + slope);
        delta = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
    }
    (delta, sigma, MAX_ITERATIONS)
}

/// The radial return of Simo & Hughes 1998, Box 3.2, for the hypoelastic deviator of an
/// updated-Lagrangian step: with `q* = √(3/2 s*:s*)` and `f = q* − σ_y(ε̄p_n)`, the trial is
/// kept if `f ≤ 0`; else `Δε̄p` solves the consistency equation ([`solve_consistency`]) and
/// `s = (1 − 3G Δε̄p / q*) s*`. `dt` is the time over which the trial increment was taken (the
/// plastic strain rate is `Δε̄p/dt`; `dt ≤ 0` or infinite: the rate-independent limit).
/// `state` is not changed: [`super::Plasticity::return_stress`] applies the result.
pub fn radial_return<D: Dim>(
    law: &PlasticLaw,
    shear_modulus: f64,
    trial: D::Matrix,
    state: &PlasticState,
    dt: f64,
) -> RadialReturn<D> {
    let q_trial = equivalent_stress::<D>(trial);
    let (sigma0, _) = law.flow_stress_after(state, 0.0, dt);
    if q_trial <= sigma0 {
        return RadialReturn {
            deviator: trial,
            delta_eps_p: 0.0,
            flow_stress: sigma0,
            trial_equivalent_stress: q_trial,
            iterations: 0,
        };
    }
    let (delta, sigma, iterations) = solve_consistency(law, shear_modulus, q_trial, state, dt);
    RadialReturn {
        deviator: trial * (1.0 - 3.0 * shear_modulus * delta / q_trial),
        delta_eps_p: delta,
        flow_stress: sigma,
        trial_equivalent_stress: q_trial,
        iterations,
    }
}

/// The plastic strain increment of a radial return, `Δεp = Δε̄p (3/2) s*/q*` along the flow
/// direction `n = s*/‖s*‖` (Simo & Hughes 1998, Box 3.2: `Δεp = Δγ n`, `Δε̄p = √(2/3) Δγ`).
/// Traceless (isochoric flow), and `s* − s = 2G Δεp`.
#[inline]
pub fn plastic_strain_increment<D: Dim>(trial: D::Matrix, delta_eps_p: f64) -> D::Matrix {
    let q = equivalent_stress::<D>(trial);
    if q > 0.0 {
        trial * (1.5 * delta_eps_p / q)
    } else {
        D::zero_matrix()
    }
}
