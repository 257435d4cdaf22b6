//! Benchmark case 9: the simply supported square plate (UL paper §6.2, Fig. 8, eq 31–33).
//!
//! Plate L × W × H (0.4 × 0.4 × 0.01), ρ = 1000, E = 1e8, ν = 0.3. Simple supports: the
//! particles at mid-thickness of the four lateral sides (the outermost column of particles on
//! each side, in the middle layer — the two middle layers when H/dp is even) have their z
//! velocity held at zero. Initial velocity `v_z = A sin(mπx/L) sin(nπy/W)` (eq 31) with
//! amplitude `A = velocity` (1 m/s: eq 31 has no factor). The centre probe is the material point
//! at the plate's centre (Shepard-interpolated).

use crate::analysis::{extremes, mean_period};
use crate::cases::tl_common::material;
use crate::cases::ul_common::{run_ul, ul_params, UL_METHODS};
use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::{finite_or_null, RunOptions, RunRecord};
use crate::{Case, CaseInfo};
use glam::DVec3;
use serde_json::{json, Map, Value as Json};
use sph_core::error::Num;
use sph_core::Body;
use sph_core::{Constraint, Constraints, Probe, Solver, D3};
use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
use sph_materials::{Material, MaterialKind};

/// The simply supported 3D plate.
pub struct OscillatingPlate3d;

/// Thin-plate period of mode (m, n) of a simply supported plate (UL paper eq 32–33):
/// `T = (2/π) [(m/L)² + (n/W)²]⁻¹ √(ρ H / D)`, `D = E H³ / (12 (1 − ν²))`.
pub fn simply_supported_period(
    (m, n): (f64, f64),
    (l, w, h): (f64, f64, f64),
    youngs: f64,
    nu: f64,
    density: f64,
) -> f64 {
    let d = youngs * h.powi(3) / (12.0 * (1.0 - nu * nu));
    2.0 / std::f64::consts::PI / ((m / l).powi(2) + (n / w).powi(2)) * (density * h / d).sqrt()
}

impl Case for OscillatingPlate3d {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "oscillating-plate-3d",
            description: "simply supported square plate, mode (m, n) initial velocity (UL §6.2)",
            methods: UL_METHODS,
        }
    }

    fn params(&self) -> Params {
        let mut specs = vec![
            Param::float("length", 0.4, Range::Positive, "L (m)"),
            Param::float("width", 0.4, Range::Positive, "W (m)"),
            Param::float("thickness", 0.01, Range::Positive, "H (m)"),
            Param::int("resolution", 3, Range::Closed(2.0, 40.0), "H/dp"),
            Param::int("mode_m", 1, Range::Closed(1.0, 10.0), "mode number along x"),
            Param::int("mode_n", 1, Range::Closed(1.0, 10.0), "mode number along y"),
            Param::float(
                "velocity",
                1.0,
                Range::NonNegative,
                "amplitude A of v_z (m/s)",
            ),
            Param::float("nu", 0.3, Range::Open(-1.0, 0.5), "Poisson's ratio"),
            Param::float("youngs_modulus", 1e8, Range::Positive, "E (Pa)"),
            Param::float("density", 1000.0, Range::Positive, "ρ0 (kg/m³)"),
            Param::float("end_time", 0.15, Range::Positive, "simulated time (s)"),
        ];
        specs.extend(crate::runner::output_params());
        specs.extend(ul_params());
        let mut p = Params::new("oscillating-plate-3d", specs);
        p.set_text("probe_interval", "1e-4").expect("valid default");
        p
    }

    fn run(
        &self,
        method: &str,
        p: &Params,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), CaseError> {
        let (l, w, h) = (p.f64("length"), p.f64("width"), p.f64("thickness"));
        let res = p.int("resolution");
        let dp = h / res as f64;
        for (key, len) in [("length", l), ("width", w)] {
            if ((len / dp).round() * dp - len).abs() > 1e-9 * len {
                return Err(CaseError::InvalidValue {
                    key: key.into(),
                    value: Num(len).to_string(),
                    allowed: format!(
                        "a whole multiple of dp = thickness/resolution = {}",
                        Num(dp)
                    ),
                });
            }
        }
        let (e, nu, rho) = (p.f64("youngs_modulus"), p.f64("nu"), p.f64("density"));
        let mat = material(MaterialKind::LinearElastic, e, nu, rho)?;
        let constants = *Material::<D3>::constants(&mat);
        let shape = Aabb::<D3>::new(DVec3::ZERO, DVec3::new(l, w, h))?;
        let mut set = ParticleSet::fill(&Lattice::<D3>::new(dp, DVec3::ZERO)?, &shape)?;
        let mid = 0.5 * h;
        set.tag_where("support", |_, x| {
            let side = x.x < dp || x.x > l - dp || x.y < dp || x.y > w - dp;
            side && (x.z - mid).abs() <= 0.5 * dp + 1e-9 * h
        })?;
        let support = set.tagged("support")?;
        let (m, n) = (p.int("mode_m") as f64, p.int("mode_n") as f64);
        let a = p.f64("velocity");
        let pi = std::f64::consts::PI;
        let velocities = set
            .positions()
            .iter()
            .map(|x| {
                DVec3::new(
                    0.0,
                    0.0,
                    a * (m * pi * x.x / l).sin() * (n * pi * x.y / w).sin(),
                )
            })
            .collect();
        let body = Body::<D3> {
            positions: set.positions().to_vec(),
            volumes: set.volumes().to_vec(),
            dp,
            velocities,
            densities: Vec::new(),
        };
        let reference = set.positions().to_vec();
        let volumes = set.volumes().to_vec();
        let interval = p.f64("probe_interval");
        // The observation point: the centre for odd modes; a quarter point otherwise.
        let at = DVec3::new(l / (2.0 * m), w / (2.0 * n), mid);
        let period_theory = simply_supported_period((m, n), (l, w, h), e, nu, rho);
        run_ul(
            "oscillating-plate-3d",
            method,
            p,
            body,
            constants,
            |s| {
                let mut c = Constraints::new();
                c.push(
                    Constraint::FixedComponents {
                        particles: support,
                        components: [false, false, true],
                    },
                    s.len(),
                )?;
                let probe = Probe::point("centre", at, &reference, &volumes, s.kernel())?;
                Ok(s.with_constraints(c).with_probes(vec![probe], interval)?)
            },
            p.f64("end_time"),
            options,
            move |s: &dyn Solver<D3>, _: &RunRecord| {
                let mut out = Map::new();
                if let Some(pr) = s.probes().first() {
                    let z: Vec<f64> = pr.positions.iter().map(|x| x.z - mid).collect();
                    let period = mean_period(&pr.times, &z, 0.0);
                    let (lo, hi) = extremes(&z);
                    out.insert("period".into(), period.map_or(Json::Null, finite_or_null));
                    out.insert("amplitude".into(), finite_or_null(lo.abs().max(hi.abs())));
                    if let Some(t) = period {
                        out.insert(
                            "period_error_vs_theory".into(),
                            finite_or_null(t / period_theory - 1.0),
                        );
                    }
                }
                out.insert("period_theory".into(), json!(period_theory));
                out.insert("observation_point".into(), json!(at.to_array()));
                out
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn periods_match_cases_md() {
        // the papers: 0.05322 (1,1), 0.02129 (2,1), 0.01331 (2,2); 4 digits printed → 1e-3.
        for (mode, t) in [
            ((1.0, 1.0), 0.05322),
            ((2.0, 1.0), 0.02129),
            ((2.0, 2.0), 0.01331),
        ] {
            let p = simply_supported_period(mode, (0.4, 0.4, 0.01), 1e8, 0.3, 1000.0);
            assert!((p / t - 1.0).abs() < 1e-3, "{mode:?}: {p} vs {t}");
        }
    }
}
