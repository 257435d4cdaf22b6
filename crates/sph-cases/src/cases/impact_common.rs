//! What the UL impact cases share (colliding balls, ball–plate 2D and 3D, the Hertz impact): the
//! contact and layout keys, the speed unit, bad-input errors, the bodies' centre-of-mass
//! velocities, and the figures of the recorded contact force.
//!
//! Every impact scene is one [`sph_ul::UlSolver`] whose bodies (ball, plate, other ball, wall)
//! meet through the UL contact pressure ([`sph_ul::contact`]); the contact force on each body is
//! recorded as the series `contact_force_<body>` (written to `/series` of the results file).

use crate::analysis::first_contact;
use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::finite_or_null;
use serde_json::{json, Map, Value as Json};
use sph_core::error::Num;
use sph_core::{Dim, Field, Series, Solver};

/// The contact key of the impact cases: the scale `κ` of the contact pressure.
pub fn contact_param() -> Param {
    Param::float(
        "contact_stiffness",
        1.0,
        Range::Positive,
        "scale κ of the UL contact pressure between bodies, p_c = κ c0² ρ_c (1: docs/methods.md)",
    )
}

/// The speed keys: `v0` (> 0) in `v0_unit` (`c0` by default, as in the UL paper).
pub fn speed_params(default: f64, help: &'static str) -> Vec<Param> {
    vec![
        Param::float("v0", default, Range::Positive, help),
        Param::choice(
            "v0_unit",
            "c0",
            &["c0", "m/s"],
            "unit of v0: the sound speed c0 = √(K/ρ0) (the UL paper's), or m/s",
        ),
    ]
}

/// `v0` in m/s.
pub fn speed(p: &Params, c0: f64) -> f64 {
    match p.text("v0_unit") {
        "c0" => p.f64("v0") * c0,
        _ => p.f64("v0"),
    }
}

/// The layout key of the balls: body-fitted spherical layers or a lattice cut.
pub fn layout_param(default: &'static str) -> Param {
    Param::choice(
        "layout",
        default,
        &["layers", "lattice"],
        "particles of the balls: `layers` = concentric spherical layers on Fibonacci lattices \
         (sph_geometry::generate::hollow_sphere_polar, smooth surface), `lattice` = cut from a \
         cubic lattice (staircase surface)",
    )
}

/// A bad-input error naming `key`.
pub fn invalid(key: &str, value: f64, allowed: String) -> CaseError {
    CaseError::InvalidValue {
        key: key.into(),
        value: Num(value).to_string(),
        allowed,
    }
}

/// `dp ≤ thickness / 3` (at least three particle layers across the thinnest part).
pub fn check_dp(dp: f64, thickness: f64, what: &str) -> Result<(), CaseError> {
    if dp > thickness / 3.0 {
        return Err(invalid(
            "dp",
            dp,
            format!(
                "dp <= {what} / 3 = {} (three particles across)",
                thickness / 3.0
            ),
        ));
    }
    Ok(())
}

/// The input index of each particle in the solver's current order (UL reorders particles).
pub fn original_order<D: Dim>(s: &dyn Solver<D>) -> Vec<usize> {
    match s.field("original_index") {
        Some(Field::Scalar(ix)) => ix.iter().map(|&i| i as usize).collect(),
        _ => (0..s.len()).collect(),
    }
}

/// Centre-of-mass velocity of each body (`body_of` and `volumes` in the input order; equal
/// density, so volumes weigh as masses).
pub fn body_velocities<D: Dim>(
    s: &dyn Solver<D>,
    body_of: &[u32],
    volumes: &[f64],
    bodies: usize,
) -> Vec<D::Vector> {
    let mut sum = vec![D::zero(); bodies];
    let mut vol = vec![0.0; bodies];
    for (&v, o) in s.velocities().iter().zip(original_order(s)) {
        let b = body_of[o] as usize;
        sum[b] += v * volumes[o];
        vol[b] += volumes[o];
    }
    sum.iter()
        .zip(&vol)
        .map(|(&s, &v)| s * (1.0 / v.max(f64::MIN_POSITIVE)))
        .collect()
}

/// Figures of the contact force on body `body` (the series `contact_force_<body>`, columns
/// `x`, `y` (, `z`)) along the unit `axis` (the impact direction; the force on the body is
/// against it): the largest magnitude `contact_force_max`, its time, and the first contact's
/// start, end and duration.
pub fn contact_summary<D: Dim>(
    s: &dyn Solver<D>,
    body: usize,
    axis: D::Vector,
) -> Map<String, Json> {
    let name = format!("contact_force_{body}");
    let all = s.series();
    let Some(series) = all.iter().find(|x| x.name == name) else {
        return Map::new();
    };
    force_figures::<D>(series, 0, false, axis)
}

/// The figures of [`contact_summary`] from a rigid tool's series (`tool`, columns `force_x`,
/// `force_y` (, `force_z`) after `displacement`: the force the body exerts on the tool, so the
/// force on the body is its opposite).
pub fn tool_contact_summary<D: Dim>(
    s: &dyn Solver<D>,
    tool: &str,
    axis: D::Vector,
) -> Map<String, Json> {
    let all = s.series();
    let Some(series) = all.iter().find(|x| x.name == tool) else {
        return Map::new();
    };
    force_figures::<D>(series, 1, true, axis)
}

/// The force on a body from the `D` columns of `series` starting at `first` (their opposite
/// with `reaction`), along the unit `axis` it moves (the force on it is against it):
/// `contact_force_max` (the largest `−F·axis`), its time `contact_force_max_time`, and the
/// first contact's `contact_start`, `contact_end`, `contact_duration` (the force's magnitude
/// exactly zero while nothing touches).
fn force_figures<D: Dim>(
    series: &Series,
    first: usize,
    reaction: bool,
    axis: D::Vector,
) -> Map<String, Json> {
    let mut m = Map::new();
    let sign = if reaction { -1.0 } else { 1.0 };
    let force = |k: usize| {
        let mut v = D::zero();
        for (c, col) in series.values[first..].iter().enumerate().take(D::D) {
            D::set_component(&mut v, c, sign * col[k]);
        }
        v
    };
    let f: Vec<f64> = (0..series.len()).map(|k| -D::dot(force(k), axis)).collect();
    let (k, peak) =
        f.iter().copied().enumerate().fold(
            (0, 0.0),
            |(kb, b), (k, x)| if x > b { (k, x) } else { (kb, b) },
        );
    m.insert("contact_force_max".into(), finite_or_null(peak));
    if peak > 0.0 {
        m.insert("contact_force_max_time".into(), json!(series.time[k]));
    }
    let magnitude: Vec<f64> = (0..series.len()).map(|k| D::norm(force(k))).collect();
    if let Some((a, b)) = first_contact(&series.time, &magnitude) {
        m.insert("contact_start".into(), json!(a));
        m.insert("contact_end".into(), json!(b));
        m.insert("contact_duration".into(), json!(b - a));
    }
    m
}
