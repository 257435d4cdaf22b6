//! Benchmark case 18: static equilibrium of a cantilever beam under a tip load (MPS paper §IV.E,
//! Fig. 6).
//!
//! Beam `L × H = 0.16 × 0.02` (x from 0 to L, centred on y = 0), `dp = H/resolution`
//! (paper: 0.002, resolution 10), held at x = 0 by `clamp_layers` columns of fixed particles
//! behind it (x < 0). E = 1e5, ν = 0.3, Saint Venant–Kirchhoff (the deflection is ~0.06 % of L,
//! so the law does not matter); the paper gives no density: ρ = 1000 (it only sets the time
//! scale). The tip load `P = 0.005` N (per unit depth, plane strain) is split equally over the
//! particles of the last column (x = L − dp/2) as constant point forces in −y, applied at
//! t = 0, and the velocity damping `c_d` brings the beam to rest: the first bending mode has
//! ω1 ≈ 8.3 rad/s, so `c_d = 16 /s` (≈ critical for it) damps every mode at ≥ 8 /s and
//! `end_time = 3 s` leaves a residual of ≈ e^−24.
//!
//! Reported: `tip_deflection` (downward, mean over the last column), the Euler–Bernoulli
//! plane-strain value `w(a) = P a³/(3 E' I)` with `E' = E/(1 − ν²)`, `I = H³/12` and the load
//! arm `a = L − dp/2` (the loaded particles' distance from the clamp face; `..._nominal` uses
//! `a = L`, the paper's printed value), the Timoshenko value (adds the shear deflection
//! `P a/(κ G H)`, κ = 5/6), the relative errors, and the deflection curve (mean downward
//! displacement per column vs `w(x) = P x²(3a − x)/(6 E' I)`).

use crate::cases::mps_common::{mps_params, run_mps};
use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::{finite_or_null, RunOptions, RunRecord};
use crate::{Case, CaseInfo};
use glam::DVec2;
use serde_json::{json, Map, Value as Json};
use sph_core::error::Num;
use sph_core::Body;
use sph_core::{Constraint, Constraints, Loads, Solver, TimeFunction, D2};
use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
use sph_materials::{ElasticConstants, MaterialKind};

/// The static cantilever.
pub struct StaticCantilever2d;

/// Euler–Bernoulli deflection of a plane-strain cantilever (unit width) under a tip load `P`
/// at `a`: `w(x) = P x² (3a − x) / (6 E' I)` for `0 ≤ x ≤ a`, `E' = E/(1 − ν²)`, `I = H³/12`.
pub fn beam_deflection(x: f64, p: f64, a: f64, h: f64, youngs: f64, nu: f64) -> f64 {
    let e = youngs / (1.0 - nu * nu);
    let i = h.powi(3) / 12.0;
    p * x * x * (3.0 * a - x) / (6.0 * e * i)
}

/// Tip deflection `w(L) = P L³/(3 E' I)`.
pub fn tip_deflection_theory(p: f64, l: f64, h: f64, youngs: f64, nu: f64) -> f64 {
    beam_deflection(l, p, l, h, youngs, nu)
}

/// Shear (Timoshenko) part of the tip deflection, `P a / (κ G H)`, κ = 5/6, unit width.
pub fn shear_deflection(p: f64, a: f64, h: f64, youngs: f64, nu: f64) -> f64 {
    let g = youngs / (2.0 * (1.0 + nu));
    p * a / (5.0 / 6.0 * g * h)
}

impl Case for StaticCantilever2d {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "static-cantilever-2d",
            description: "cantilever beam under a tip load, damped to equilibrium (MPS §IV.E)",
            methods: &["mps"],
        }
    }

    fn params(&self) -> Params {
        let mut specs = vec![
            Param::float("length", 0.16, Range::Positive, "beam length L (m)"),
            Param::float("thickness", 0.02, Range::Positive, "beam height H (m)"),
            Param::int("resolution", 10, Range::Closed(2.0, 400.0), "H/dp"),
            Param::int(
                "clamp_layers",
                3,
                Range::Closed(1.0, 20.0),
                "fixed columns behind x = 0",
            ),
            Param::float("youngs_modulus", 1e5, Range::Positive, "E (Pa)"),
            Param::float("nu", 0.3, Range::Open(-1.0, 0.5), "Poisson's ratio"),
            Param::float(
                "density",
                1000.0,
                Range::Positive,
                "ρ0 (kg/m³; not in the paper)",
            ),
            Param::float("load", 0.005, Range::Any, "tip load P (N per unit depth)"),
            Param::float("end_time", 3.0, Range::Positive, "simulated time (s)"),
        ];
        specs.extend(mps_params());
        let mut p = Params::new("static-cantilever-2d", specs);
        p.set_text("damping", "16").expect("valid default");
        p.set_text("probe_interval", "1e-3").expect("valid default");
        p
    }

    fn run(
        &self,
        method: &str,
        p: &Params,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), CaseError> {
        crate::resolve_method(self, Some(method))?;
        let (l, h) = (p.f64("length"), p.f64("thickness"));
        let (e, nu) = (p.f64("youngs_modulus"), p.f64("nu"));
        let dp = h / p.int("resolution") as f64;
        let nx = (l / dp).round();
        if (nx * dp - l).abs() > 1e-9 * l {
            return Err(CaseError::InvalidValue {
                key: "length".into(),
                value: Num(l).to_string(),
                allowed: format!(
                    "a whole multiple of dp = thickness/resolution = {}",
                    Num(dp)
                ),
            });
        }
        let behind = p.int("clamp_layers") as f64 * dp;
        let shape = Aabb::<D2>::new(DVec2::new(-behind, -0.5 * h), DVec2::new(l, 0.5 * h))?;
        let lattice = Lattice::<D2>::new(dp, DVec2::new(-behind, -0.5 * h))?;
        let mut set = ParticleSet::fill(&lattice, &shape)?;
        set.tag_where("clamp", |_, x| x.x < 0.0)?;
        set.tag_where("tip", |_, x| x.x > l - dp)?;
        let clamp = set.tagged("clamp")?;
        let tip = set.tagged("tip")?;
        let c = ElasticConstants::from_youngs(e, nu, p.f64("density"))?;
        let mat = MaterialKind::SaintVenantKirchhoff.build(c)?;
        let load = p.f64("load");
        let per = load / tip.len() as f64;
        let mut loads = Loads::new();
        for &i in &tip {
            loads.add_point_force(i, TimeFunction::constant(DVec2::new(0.0, -per)));
        }
        let n = set.len();
        let mut constraints = Constraints::new();
        constraints.push(Constraint::Fixed { particles: clamp }, n)?;
        let reference = set.positions().to_vec();
        let body = Body::<D2> {
            positions: reference.clone(),
            volumes: set.volumes().to_vec(),
            dp,
            velocities: Vec::new(),
            densities: Vec::new(),
        };
        let arm = l - 0.5 * dp;
        let interval = p.f64("probe_interval");
        let probe_particle = tip
            .iter()
            .copied()
            .min_by(|&a, &b| {
                let (ya, yb) = (reference[a as usize].y.abs(), reference[b as usize].y.abs());
                ya.total_cmp(&yb)
            })
            .expect("the tip column is not empty");
        run_mps(
            "static-cantilever-2d",
            p,
            body,
            mat,
            |s| {
                Ok(s.with_constraints(constraints)
                    .with_loads(loads)
                    .with_probes(
                        vec![sph_core::Probe::particle("tip", probe_particle)],
                        interval,
                    )?)
            },
            p.f64("end_time"),
            options,
            move |s, _| static_summary(s, &reference, dp, l, h, arm, load, e, nu),
        )
    }
}

#[allow(clippy::too_many_arguments)]
fn static_summary(
    s: &dyn Solver<D2>,
    reference: &[DVec2],
    dp: f64,
    l: f64,
    h: f64,
    arm: f64,
    load: f64,
    e: f64,
    nu: f64,
) -> Map<String, Json> {
    // Mean downward displacement per column of the beam (x > 0).
    let ncol = (l / dp).round() as usize;
    let mut sum = vec![0.0; ncol];
    let mut cnt = vec![0usize; ncol];
    for (x0, x) in reference.iter().zip(s.positions()) {
        if x0.x > 0.0 {
            let k = ((x0.x / dp).floor() as usize).min(ncol - 1);
            sum[k] += x0.y - x.y;
            cnt[k] += 1;
        }
    }
    let xs: Vec<f64> = (0..ncol).map(|k| (k as f64 + 0.5) * dp).collect();
    let w: Vec<f64> = sum
        .iter()
        .zip(&cnt)
        .map(|(s, &c)| s / c.max(1) as f64)
        .collect();
    let w_theory: Vec<f64> = xs
        .iter()
        .map(|&x| beam_deflection(x, load, arm, h, e, nu))
        .collect();
    let tip = w[ncol - 1];
    let theory = beam_deflection(arm, load, arm, h, e, nu);
    let nominal = tip_deflection_theory(load, l, h, e, nu);
    let timo = theory + shear_deflection(load, arm, h, e, nu);
    let speed_max = s
        .velocities()
        .iter()
        .map(|v| v.length())
        .fold(0.0, f64::max);
    let mut m = Map::new();
    m.insert("tip_deflection".into(), finite_or_null(tip));
    m.insert("tip_deflection_theory".into(), json!(theory));
    m.insert("tip_deflection_theory_nominal".into(), json!(nominal));
    m.insert("tip_deflection_theory_timoshenko".into(), json!(timo));
    m.insert(
        "tip_deflection_error".into(),
        finite_or_null(tip / theory - 1.0),
    );
    m.insert(
        "tip_deflection_error_nominal".into(),
        finite_or_null(tip / nominal - 1.0),
    );
    m.insert(
        "tip_deflection_error_timoshenko".into(),
        finite_or_null(tip / timo - 1.0),
    );
    m.insert("load_arm".into(), json!(arm));
    m.insert("final_speed_max".into(), finite_or_null(speed_max));
    m.insert("deflection_x".into(), json!(xs));
    m.insert(
        "deflection_w".into(),
        Json::Array(w.iter().map(|&v| finite_or_null(v)).collect()),
    );
    m.insert("deflection_w_theory".into(), json!(w_theory));
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tip_deflection_matches_hand_value() {
        // P L³/(3 E' I): 0.005 · 0.16³ / (3 · 1e5/0.91 · 0.02³/12) = 9.3184e-5 m.
        let w = tip_deflection_theory(0.005, 0.16, 0.02, 1e5, 0.3);
        let e = 1e5 / (1.0 - 0.09);
        let hand = 0.005 * 0.16f64.powi(3) / (3.0 * e * 0.02f64.powi(3) / 12.0);
        assert!((w / hand - 1.0).abs() < 1e-14);
        assert!((w - 9.3184e-5).abs() < 1e-8, "{w}");
        // The curve is clamped (w = w' = 0 at 0) and equals the tip value at x = L.
        assert_eq!(beam_deflection(0.0, 0.005, 0.16, 0.02, 1e5, 0.3), 0.0);
        let d = beam_deflection(1e-7, 0.005, 0.16, 0.02, 1e5, 0.3) / 1e-7;
        assert!(d.abs() < 1e-9);
        // Shear part: P a / (κ G H), G = E/2.6.
        let s = shear_deflection(0.005, 0.16, 0.02, 1e5, 0.3);
        assert!((s - 0.005 * 0.16 / (5.0 / 6.0 * 1e5 / 2.6 * 0.02)).abs() < 1e-18);
    }
}
