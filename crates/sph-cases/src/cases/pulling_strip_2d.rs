//! Benchmark case 3: the pulling strip (TL paper §4.3, Fig. 7).
//!
//! A rubber square `size × size` (centred at the origin), neo-Hookean, whose top and bottom
//! `grip_rows` particle rows are pulled apart at `±pull_speed` (smooth start, then a hold; see
//! [`quasi_static`](crate::cases::quasi_static)) until the distance between the innermost
//! gripped rows has grown by the factor `stretch`. The grips are named constraints that record
//! the reaction force they receive (`/series/grip_top`, `/series/grip_bottom`): `clamped` grips
//! prescribe the whole velocity (the paper's rows pulled at `(0, ±v)`), `roller` grips only its
//! vertical part, so the rows contract freely (then the stretch is homogeneous and the summary's
//! plane-strain closed form applies).
//!
//! `stretch` is the ratio of final to initial length: the paper's "500 % tension", for which it
//! states that the 2 mm strip becomes 12 mm long, is `stretch = 6` (the default), its "1000 %"
//! is `stretch = 11`.

use crate::cases::quasi_static::{
    area_change, curve_json, grip_motion, homogeneous_plane_strain, loading_params, mean_after,
    reference_and_deformation, relaxation, surface_point, timeline,
};
use crate::cases::tl_common::{material, run_tl, tl_params, TL_METHODS};
use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::{finite_or_null, RunOptions, RunRecord};
use crate::{Case, CaseInfo};
use glam::DVec2;
use serde_json::{json, Map, Value as Json};
use sph_core::Body;
use sph_core::{Constraint, Constraints, Solver, TimeFunction, D2};
use sph_materials::{Material, MaterialKind};

/// The pulling strip.
pub struct PullingStrip2d;

impl Case for PullingStrip2d {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "pulling-strip-2d",
            description: "rubber square pulled apart by its top and bottom rows (TL §4.3)",
            methods: TL_METHODS,
        }
    }

    fn params(&self) -> Params {
        let mut specs = vec![
            Param::float("size", 2e-3, Range::Positive, "side L of the square (m)"),
            Param::int("resolution", 30, Range::Closed(4.0, 400.0), "L/dp"),
            Param::float(
                "stretch",
                6.0,
                Range::Open(1.0, 1000.0),
                "final/initial distance between the grips (6 = the paper's 500 %, 12 mm)",
            ),
            Param::float(
                "pull_speed",
                2.0,
                Range::Positive,
                "speed of each grip (m/s; the paper's 1e-4 is far slower for the same result)",
            ),
            Param::choice(
                "grip",
                "clamped",
                &["clamped", "roller"],
                "clamped: rows move as (0, ±v); roller: only their vertical velocity is imposed",
            ),
            Param::int(
                "grip_rows",
                1,
                Range::Closed(1.0, 10.0),
                "particle rows held by each grip",
            ),
            Param::float("density", 1100.0, Range::Positive, "ρ0 (kg/m³)"),
            Param::float("youngs_modulus", 1e9, Range::Positive, "E (Pa)"),
            Param::float("nu", 0.45, Range::Open(-1.0, 0.5), "Poisson's ratio"),
            Param::choice(
                "material",
                "neo-hookean",
                &["neo-hookean", "linear-elastic", "kirchhoff-vol-dev"],
                "constitutive law (the paper's rubber: neo-Hookean)",
            ),
        ];
        specs.extend(loading_params());
        specs.extend(tl_params());
        let mut p = Params::new("pulling-strip-2d", specs);
        p.set_text("probe_interval", "5e-6").expect("valid default");
        p.set_text("dt_stretch", "true").expect("valid default");
        p
    }

    fn run(
        &self,
        method: &str,
        p: &Params,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), CaseError> {
        let l = p.f64("size");
        let res = p.int("resolution");
        let rows = p.int("grip_rows");
        if 2 * rows + 2 > res {
            return Err(CaseError::InvalidValue {
                key: "grip_rows".into(),
                value: rows.to_string(),
                allowed: format!("1 <= grip_rows <= (resolution − 2)/2 = {}", (res - 2) / 2),
            });
        }
        let (rho, e, nu) = (p.f64("density"), p.f64("youngs_modulus"), p.f64("nu"));
        let kind: MaterialKind = p.text("material").parse()?;
        let mat = material(kind, e, nu, rho)?;
        let constants = *Material::<D2>::constants(&mat);
        let (set, dp) =
            crate::cases::punching_strip_2d::strip_particles(l, l, res).map_err(|e| match e {
                CaseError::InvalidValue { allowed, .. } => CaseError::InvalidValue {
                    key: "resolution".into(),
                    value: res.to_string(),
                    allowed,
                },
                e => e,
            })?;
        let n = set.len();
        let x0 = set.positions().to_vec();
        let volumes = set.volumes().to_vec();
        // Grip rows: reference y within `rows` spacings of the top/bottom face.
        let edge = 0.5 * l - rows as f64 * dp;
        let top: Vec<u32> = (0..n as u32).filter(|&i| x0[i as usize].y > edge).collect();
        let bottom: Vec<u32> = (0..n as u32)
            .filter(|&i| x0[i as usize].y < -edge)
            .collect();
        let gauge = l - (2 * rows - 1) as f64 * dp;
        let stretch = p.f64("stretch");
        let speed = p.f64("pull_speed");
        let travel = 0.5 * (stretch - 1.0) * gauge;
        let (ramp, hold) = timeline(p, travel, speed);
        let up = grip_motion::<D2>(DVec2::Y, speed, ramp, travel)?;
        let down = grip_motion::<D2>(-DVec2::Y, speed, ramp, travel)?;
        let roller = p.text("grip") == "roller";
        let grip = |particles: Vec<u32>, velocity: TimeFunction<D2>| {
            if roller {
                Constraint::PrescribedComponents {
                    particles,
                    velocity,
                    components: [false, true, false],
                }
            } else {
                Constraint::PrescribedVelocity {
                    particles,
                    velocity,
                }
            }
        };
        let mut constraints = Constraints::new();
        constraints.push_named("grip_top", grip(top, up.0), n)?;
        constraints.push_named("grip_bottom", grip(bottom, down.0), n)?;
        let end_time = up.1 + hold;
        let damping = relaxation(p, rho, e, l)?;
        let interval = p.f64("probe_interval");
        let body = Body::<D2> {
            positions: x0,
            volumes: volumes.clone(),
            dp,
            velocities: Vec::new(),
            densities: Vec::new(),
        };
        let (mu, lambda) = (constants.shear_modulus, constants.lame_lambda);
        let summarise = move |s: &dyn Solver<D2>, _: &RunRecord| {
            let mut m = pulling_summary(s, &volumes, dp, l, gauge, end_time - hold);
            let (lx, p_yy) = homogeneous_plane_strain(mu, lambda, stretch);
            m.insert("theory_homogeneous_force".into(), json!(p_yy * l));
            m.insert("theory_homogeneous_width_ratio".into(), json!(lx));
            m.insert("particle_spacing".into(), json!(dp));
            m.insert("gauge_length".into(), json!(gauge));
            m.insert("end_time".into(), json!(end_time));
            m
        };
        run_tl(
            "pulling-strip-2d",
            method,
            p,
            body,
            mat,
            |s| {
                let s = s
                    .with_constraints(constraints)
                    .with_probes(Vec::new(), interval)?;
                Ok(match damping {
                    Some(d) => s.with_relaxation(d)?,
                    None => s,
                })
            },
            end_time,
            options,
            summarise,
        )
    }
}

/// The pulling figures from the final state and the grips' series: reaction force (the force
/// pulling the top grip, mean over the second half of the hold), the force curve against the
/// stretch, the stretch reached, the neck width (current width at mid-height over the initial
/// width, from the side particles' surface points) and the area change.
pub fn pulling_summary(
    s: &dyn Solver<D2>,
    volumes: &[f64],
    dp: f64,
    l: f64,
    gauge: f64,
    hold_start: f64,
) -> Map<String, Json> {
    let mut m = Map::new();
    let series = s.series();
    let find = |name: &str| series.iter().find(|x| x.name == name);
    let t_end = s.time();
    let settled = hold_start + 0.5 * (t_end - hold_start);
    if let (Some(top), Some(bottom)) = (find("grip_top"), find("grip_bottom")) {
        // The body pulls the top grip down: the pulling force is minus its reaction.
        let f_top = -mean_after(top, "force_y", settled);
        let f_bottom = mean_after(bottom, "force_y", settled);
        m.insert("reaction_force".into(), finite_or_null(f_top));
        m.insert("reaction_force_bottom".into(), finite_or_null(f_bottom));
        let (yt, yb) = (
            top.column("y").unwrap_or(&[]),
            bottom.column("y").unwrap_or(&[]),
        );
        let (yt0, yb0) = (yt.first().copied(), yb.first().copied());
        let stretch: Vec<f64> = yt
            .iter()
            .zip(yb)
            .map(|(a, b)| match (yt0, yb0) {
                // Distance between the grips' innermost rows: their mean rows are
                // (rows − 1)/2 spacings further out, the same at every time (rigid grips).
                (Some(a0), Some(b0)) => 1.0 + ((a - b) - (a0 - b0)) / gauge,
                _ => f64::NAN,
            })
            .collect();
        m.insert(
            "stretch_reached".into(),
            finite_or_null(stretch.last().copied().unwrap_or(f64::NAN)),
        );
        let force: Vec<f64> = top
            .column("force_y")
            .unwrap_or(&[])
            .iter()
            .map(|f| -f)
            .collect();
        m.insert(
            "force_curve".into(),
            curve_json(&top.time, &stretch, &force, "stretch", 400),
        );
    }
    let (reference, f) = reference_and_deformation::<D2>(s);
    let x = s.positions();
    let all: Vec<u32> = (0..x.len() as u32).collect();
    m.insert(
        "area_change".into(),
        finite_or_null(area_change::<D2>(&f, volumes, &all)),
    );
    // Neck: the side particles of the two rows around mid-height.
    let side = 0.5 * l - 0.5 * dp;
    let (mut left, mut right, mut count) = (0.0, 0.0, 0);
    for (i, &x0) in reference.iter().enumerate() {
        if (x0.x.abs() - side).abs() > 1e-9 * l || x0.y.abs() > 0.5 * dp + 1e-9 * l {
            continue;
        }
        let out = DVec2::new(0.5 * dp * x0.x.signum(), 0.0);
        let p = surface_point::<D2>(x[i], f[i], out).x;
        if x0.x > 0.0 {
            right += p;
        } else {
            left += p;
        }
        count += 1;
    }
    let neck = if count >= 2 {
        (right - left) / (0.5 * count as f64) / l
    } else {
        f64::NAN
    };
    m.insert("neck_width".into(), finite_or_null(neck));
    m
}
