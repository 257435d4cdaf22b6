//! Benchmark case 6: the twisting column (TL paper §4.5, Fig. 14–18).
//!
//! The bending column's geometry (axis along z here; the paper's axis is y) with the initial
//! angular velocity `ω = [0, 0, Ω0 sin(π z0 / 2L)]` about the column's axis, i.e.
//! `v = ω × (x − axis)`; neo-Hookean, ν = 0.499 for Ω0 = 105 (0.49 for 300 and 400).

use crate::analysis::extremes;
use crate::cases::bending_column_3d::{column_params, run_column};
use crate::cases::tl_common::{tl_params, TL_METHODS};
use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::{finite_or_null, RunOptions, RunRecord};
use crate::{Case, CaseInfo};
use glam::DVec3;
use serde_json::{json, Map, Value as Json};
use sph_core::{Solver, D3};

/// The twisting column.
pub struct TwistingColumn3d;

impl Case for TwistingColumn3d {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "twisting-column-3d",
            description:
                "neo-Hookean column twisted by a sinusoidal initial angular velocity (TL §4.5)",
            methods: TL_METHODS,
        }
    }

    fn params(&self) -> Params {
        let mut specs = column_params(10, 0.499, 0.3);
        specs.push(Param::float(
            "omega0",
            105.0,
            Range::NonNegative,
            "Ω0 (rad/s)",
        ));
        specs.extend(tl_params());
        let mut p = Params::new("twisting-column-3d", specs);
        p.set_text("probe_interval", "1e-4").expect("valid default");
        p
    }

    fn params_for(&self, method: &str) -> Params {
        crate::cases::tl_common::with_hf_paper_law(self.params(), method)
    }

    fn run(
        &self,
        method: &str,
        p: &Params,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), CaseError> {
        let (h, l) = (p.f64("cross_section"), p.f64("length"));
        let omega0 = p.f64("omega0");
        let centre = DVec3::new(0.5 * h, 0.5 * h, 0.0);
        let corner = DVec3::new(h, h, l);
        run_column(
            "twisting-column-3d",
            method,
            p,
            options,
            |x| {
                let w = DVec3::new(
                    0.0,
                    0.0,
                    omega0 * (std::f64::consts::PI * x.z / (2.0 * l)).sin(),
                );
                let r = x - centre;
                w.cross(DVec3::new(r.x, r.y, 0.0))
            },
            ("tip_corner", corner),
            move |s, _| twist_summary(s, corner, centre),
        )
    }
}

/// Extremes of the top corner's coordinates and of its rotation angle about the axis.
fn twist_summary(s: &dyn Solver<D3>, corner: DVec3, centre: DVec3) -> Map<String, Json> {
    let mut m = Map::new();
    if let Some(p) = s.probes().first() {
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            let c: Vec<f64> = p.positions.iter().map(|x| x[k]).collect();
            let (lo, hi) = extremes(&c);
            m.insert(format!("tip_{axis}_min"), finite_or_null(lo));
            m.insert(format!("tip_{axis}_max"), finite_or_null(hi));
        }
        let a0 = (corner.y - centre.y).atan2(corner.x - centre.x);
        // Unwrapped rotation angle of the corner about the axis.
        let mut angle = Vec::with_capacity(p.positions.len());
        let mut prev = 0.0f64;
        for x in &p.positions {
            let a = (x.y - centre.y).atan2(x.x - centre.x) - a0;
            let mut d = a - prev;
            d -= (d / std::f64::consts::TAU).round() * std::f64::consts::TAU;
            prev += d;
            angle.push(prev);
        }
        let (lo, hi) = extremes(&angle);
        m.insert("tip_angle_min".into(), finite_or_null(lo));
        m.insert("tip_angle_max".into(), finite_or_null(hi));
        m.insert("tip_reference".into(), json!(corner.to_array()));
    }
    m
}
