//! What the quasi-static TL cases share (punching strip, pulling strip, pulling cylinder): the
//! loading keys and the relaxation, the homogeneous plane-strain closed form, and measures of
//! the deformed shape (boundary points, mirror symmetry, area change, force curves).
//!
//! # Loading protocol
//! A tool or grip travels its distance at the case's speed after a smooth start
//! (`sph_core::tool::ToolMotion`: speed rising as `(1 − cos)/2` over a tenth of the loading
//! time), then holds still for `hold_time` while the relaxation removes what is left of the
//! motion; the case's figures are read at the end of the hold. The relaxation is the TL paper's
//! splitting random-choice pairwise damping (`sph_core::relaxation`) with viscosity
//! `η = (β/4) √(ρ0 E) L`, `L` the body's size along the load. A run is quasi-static when halving
//! the speed changes the measured force by less than 1 % (shown in docs/validation.md).

use crate::params::{Param, Params, Range};
use serde_json::{json, Value as Json};
use sph_core::relaxation::PairwiseDamping;
use sph_core::{Dim, Field, Series, Solver, TimeFunction, ToolMotion};
use std::collections::HashMap;

/// Fraction of the loading time spent on the smooth start.
pub const RAMP_FRACTION: f64 = 0.1;

/// Default hold as a fraction of the loading time (when `hold_time` is 0).
pub const HOLD_FRACTION: f64 = 0.2;

/// The keys of the quasi-static protocol (besides the case's speed key).
pub fn loading_params() -> Vec<Param> {
    vec![
        Param::float(
            "relaxation",
            1.0,
            Range::Closed(0.0, 100.0),
            "strength β of the pairwise relaxation damping, η = (β/4)√(ρ0 E) L (0: off)",
        ),
        Param::float(
            "hold_time",
            0.0,
            Range::NonNegative,
            "time held still after the loading (s; 0: a fifth of the loading time)",
        ),
    ]
}

/// The loading timeline for a tool travelling `travel` at `speed`: `(ramp_time, hold_time)`.
pub fn timeline(p: &Params, travel: f64, speed: f64) -> (f64, f64) {
    let loading = travel / speed;
    let hold = match p.f64("hold_time") {
        h if h > 0.0 => h,
        _ => HOLD_FRACTION * loading,
    };
    (RAMP_FRACTION * loading, hold)
}

/// A grip's prescribed velocity: along `direction` at `speed` after a smooth start of
/// `ramp` (the tools' [`ToolMotion`] profile), stopping after `travel`. Returns the velocity
/// function and the arrival time.
pub fn grip_motion<D: Dim>(
    direction: D::Vector,
    speed: f64,
    ramp: f64,
    travel: f64,
) -> Result<(TimeFunction<D>, f64), sph_core::Error> {
    let motion = ToolMotion::<D>::new(direction, speed, ramp, travel)?;
    let arrival = motion.arrival_time();
    Ok((TimeFunction::new(move |t| motion.velocity(t)), arrival))
}

/// The relaxation damping for a body of size `length`, or `None` when `relaxation` is 0.
pub fn relaxation(
    p: &Params,
    density: f64,
    youngs: f64,
    length: f64,
) -> Result<Option<PairwiseDamping>, sph_core::Error> {
    let beta = p.f64("relaxation");
    if beta == 0.0 {
        return Ok(None);
    }
    PairwiseDamping::new(PairwiseDamping::viscosity_for(
        beta, density, youngs, length,
    ))
    .map(Some)
}

/// Homogeneous plane-strain stretch of the compressible neo-Hookean solid
/// (`ψ = (μ/2)(I₁ − 3) − μ ln J + (λ/2)(ln J)²`, `λ_z = 1`) between frictionless platens that
/// impose `λ_y`, with `σ_xx = 0`: solves `μ(λ_x² − 1) + λ ln(λ_x λ_y) = 0` for `λ_x` (its left
/// side increases monotonically in `λ_x`) and returns `(λ_x, P_yy)` with the nominal stress
/// `P_yy = [μ(λ_y² − 1) + λ ln(λ_x λ_y)]/λ_y` (docs/methods.md); the force per unit depth is `P_yy`
/// times the reference width.
pub fn homogeneous_plane_strain(mu: f64, lambda: f64, stretch_y: f64) -> (f64, f64) {
    let residual = |lx: f64| mu * (lx * lx - 1.0) + lambda * (lx * stretch_y).ln();
    // Bracket: the residual is −∞ at 0⁺ and grows without bound.
    let (mut lo, mut hi) = (1e-12, 1.0);
    while residual(hi) < 0.0 {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if residual(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let lx = 0.5 * (lo + hi);
    let p_yy = (mu * (stretch_y * stretch_y - 1.0) + lambda * (lx * stretch_y).ln()) / stretch_y;
    (lx, p_yy)
}

/// Mean of `column` over the samples of `series` at times `≥ t0` (NaN if none).
pub fn mean_after(series: &Series, column: &str, t0: f64) -> f64 {
    let Some(c) = series.column(column) else {
        return f64::NAN;
    };
    let v: Vec<f64> = series
        .time
        .iter()
        .zip(c)
        .filter(|(t, _)| **t >= t0)
        .map(|(_, &x)| x)
        .collect();
    if v.is_empty() {
        f64::NAN
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

/// A force curve `{time: [...], x: [...], force: [...]}` (JSON) from a series' times and two
/// of its columns, at most `max_points` samples (evenly thinned, the last kept).
pub fn curve_json(time: &[f64], x: &[f64], force: &[f64], x_name: &str, max_points: usize) -> Json {
    let n = x.len().min(force.len()).min(time.len());
    let stride = n.div_ceil(max_points.max(1)).max(1);
    let pick = |v: &[f64]| -> Vec<Json> {
        (0..n)
            .step_by(stride)
            .chain((n > 0 && !(n - 1).is_multiple_of(stride)).then_some(n - 1))
            .map(|k| crate::runner::finite_or_null(v[k]))
            .collect()
    };
    json!({ "time": pick(time), x_name: pick(x), "force": pick(force) })
}

/// The reference positions `X = x − u` and deformation gradients of a TL solver.
pub fn reference_and_deformation<D: Dim>(s: &dyn Solver<D>) -> (Vec<D::Vector>, Vec<D::Matrix>) {
    let reference = match s.field("displacement") {
        Some(Field::Vector(u)) => s.positions().iter().zip(&u).map(|(&x, &u)| x - u).collect(),
        _ => s.positions().to_vec(),
    };
    let f = match s.field("deformation_gradient") {
        Some(Field::Matrix(f)) => f,
        _ => vec![D::identity(); s.len()],
    };
    (reference, f)
}

/// Relative area (volume) change `Σ V⁰ J / Σ V⁰ − 1` over the particles `body`.
pub fn area_change<D: Dim>(f: &[D::Matrix], volumes: &[f64], body: &[u32]) -> f64 {
    let (mut v0, mut v) = (0.0, 0.0);
    for &i in body {
        let i = i as usize;
        v0 += volumes[i];
        v += volumes[i] * D::det(f[i]);
    }
    v / v0 - 1.0
}

/// The current position of the material point `X_i + offset` of particle `i`'s neighbourhood,
/// to first order: `x_i + F_i offset` (a surface point half a spacing beyond a boundary
/// particle).
pub fn surface_point<D: Dim>(x: D::Vector, f: D::Matrix, offset: D::Vector) -> D::Vector {
    x + f * offset
}

/// Largest distance, in units of `dp`, between a particle's current position and the mirror
/// image (component `axis` negated) of its mirror partner's, over the particles whose reference
/// partner (mirror of `X` about the plane `X_axis = 0`) exists within `dp/4`: zero for a
/// deformation symmetric about that plane.
pub fn mirror_asymmetry<D: Dim>(
    reference: &[D::Vector],
    current: &[D::Vector],
    axis: usize,
    dp: f64,
) -> f64 {
    let key = |x: D::Vector| -> [i64; 3] {
        let mut k = [0i64; 3];
        for (c, slot) in k.iter_mut().enumerate().take(D::D) {
            *slot = (D::component(x, c) * 4.0 / dp).round() as i64;
        }
        k
    };
    let index: HashMap<[i64; 3], usize> = reference
        .iter()
        .enumerate()
        .map(|(i, &x)| (key(x), i))
        .collect();
    let mirror = |mut x: D::Vector| {
        let c = D::component(x, axis);
        D::set_component(&mut x, axis, -c);
        x
    };
    let mut worst: f64 = 0.0;
    for (i, &x0) in reference.iter().enumerate() {
        if let Some(&j) = index.get(&key(mirror(x0))) {
            worst = worst.max(D::norm(current[i] - mirror(current[j])) / dp);
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;
    use sph_core::D2;

    #[test]
    fn homogeneous_compression_satisfies_the_free_side_condition_and_matches_a_hand_value() {
        // E = 1 GPa, ν = 0.45: μ = 0.3448 GPa, λ = 3.1034 GPa.
        let (e, nu): (f64, f64) = (1e9, 0.45);
        let mu = e / (2.0 * (1.0 + nu));
        let lambda = nu * e / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let (lx, p) = homogeneous_plane_strain(mu, lambda, 0.7);
        let residual = mu * (lx * lx - 1.0) + lambda * (lx * 0.7f64).ln();
        assert!(residual.abs() < 1e-6, "{residual}");
        // An independent solution of the same equations (Python bisection): λ_x = 1.316723,
        // P_yy = −0.612689 GPa (tolerance: the 7 digits quoted).
        assert!((lx - 1.316723).abs() < 2e-6, "{lx}");
        assert!((p / 1e9 + 0.612689).abs() < 2e-6, "{p}");
        // Small strain: plane strain with σ_xx = 0 is uniaxial stress in y in the plane, whose
        // modulus is E' = E/(1 − ν²).
        let eps = 1e-6;
        let (_, p) = homogeneous_plane_strain(mu, lambda, 1.0 - eps);
        let e_prime = e / (1.0 - nu * nu);
        assert!(
            (p / (-eps) - e_prime).abs() < 1e-4 * e_prime,
            "{}",
            p / -eps
        );
        // Identity at λ_y = 1.
        let (lx, p) = homogeneous_plane_strain(mu, lambda, 1.0);
        assert!((lx - 1.0).abs() < 1e-12 && p.abs() < 1e-3);
    }

    #[test]
    fn mirror_asymmetry_is_zero_for_symmetric_motion_and_counts_a_shift() {
        let x0: Vec<DVec2> = [(-1.5, 0.5), (1.5, 0.5), (-0.5, -0.5), (0.5, -0.5)]
            .iter()
            .map(|&(a, b)| DVec2::new(a, b))
            .collect();
        // Symmetric stretch in x: no asymmetry.
        let x: Vec<DVec2> = x0
            .iter()
            .map(|p| DVec2::new(1.3 * p.x, 0.9 * p.y))
            .collect();
        assert_eq!(mirror_asymmetry::<D2>(&x0, &x, 0, 1.0), 0.0);
        // A rigid shift by 0.2 in x breaks the x-mirror symmetry by 0.4 dp.
        let x: Vec<DVec2> = x0.iter().map(|p| *p + DVec2::new(0.2, 0.0)).collect();
        assert!((mirror_asymmetry::<D2>(&x0, &x, 0, 1.0) - 0.4).abs() < 1e-12);
        // The y-mirror partners do not exist here: nothing to compare.
        assert_eq!(mirror_asymmetry::<D2>(&x0, &x, 1, 1.0), 0.0);
    }

    #[test]
    fn curve_is_thinned_but_keeps_the_ends() {
        let x: Vec<f64> = (0..1000).map(|k| k as f64).collect();
        let c = curve_json(&x, &x, &x, "compression", 100);
        let xs = c["compression"].as_array().unwrap();
        assert!(xs.len() <= 101, "{}", xs.len());
        assert_eq!(xs[0], json!(0.0));
        assert_eq!(xs[xs.len() - 1], json!(999.0));
    }
}
