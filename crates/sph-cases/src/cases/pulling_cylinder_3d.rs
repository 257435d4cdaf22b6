//! Benchmark case 4: the pulling cylinder (TL paper §4.3, Fig. 8).
//!
//! A rubber cylinder of `radius` and `height` along z (centred at the origin), neo-Hookean with
//! ν = 0.49, whose top and bottom slices of particles are clamped and pulled apart at
//! `±pull_speed` (smooth start, then a hold; see
//! [`quasi_static`](crate::cases::quasi_static)) until the distance between them has grown by
//! the factor `stretch`. Particles: the body-fitted layout of `sph_geometry::generate::tube_polar`
//! (concentric rings of spacing ≈ dp in slices of thickness dp; the paper uses a body-fitted
//! generator too), so the curved surface has no lattice steps.
//!
//! `stretch` is the ratio of final to initial length, as in the pulling strip: the paper's
//! "240 %" and "480 %" tension are `stretch = 3.4` (the default) and `5.8`.

use crate::cases::quasi_static::{
    area_change, curve_json, grip_motion, loading_params, mean_after, reference_and_deformation,
    relaxation, surface_point, timeline,
};
use crate::cases::tl_common::{material, run_tl, tl_params, TL_METHODS};
use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::{finite_or_null, RunOptions, RunRecord};
use crate::{Case, CaseInfo};
use glam::DVec3;
use serde_json::{json, Map, Value as Json};
use sph_core::error::Num;
use sph_core::Body;
use sph_core::{Constraint, Constraints, Solver, D3};
use sph_geometry::generate::tube_polar;
use sph_materials::MaterialKind;

/// The pulling cylinder.
pub struct PullingCylinder3d;

impl Case for PullingCylinder3d {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "pulling-cylinder-3d",
            description: "rubber cylinder pulled apart by its end slices (TL §4.3, Fig. 8)",
            methods: TL_METHODS,
        }
    }

    fn params(&self) -> Params {
        let mut specs = vec![
            Param::float("radius", 1e-3, Range::Positive, "cylinder radius R (m)"),
            Param::float("height", 2e-3, Range::Positive, "cylinder height (m)"),
            Param::int(
                "resolution",
                20,
                Range::Closed(4.0, 200.0),
                "height/dp (the paper's dp = 0.1 mm: 20)",
            ),
            Param::float(
                "stretch",
                3.4,
                Range::Open(1.0, 1000.0),
                "final/initial distance between the grips (3.4 = the paper's 240 %)",
            ),
            Param::float(
                "pull_speed",
                2.0,
                Range::Positive,
                "speed of each grip (m/s)",
            ),
            Param::float("density", 1100.0, Range::Positive, "ρ0 (kg/m³)"),
            Param::float("youngs_modulus", 1e9, Range::Positive, "E (Pa)"),
            Param::float("nu", 0.49, Range::Open(-1.0, 0.5), "Poisson's ratio"),
            Param::choice(
                "material",
                "neo-hookean",
                &["neo-hookean", "linear-elastic", "kirchhoff-vol-dev"],
                "constitutive law (the paper's rubber: neo-Hookean)",
            ),
        ];
        specs.extend(loading_params());
        specs.extend(tl_params());
        let mut p = Params::new("pulling-cylinder-3d", specs);
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
        let (r, h) = (p.f64("radius"), p.f64("height"));
        let dp = h / p.int("resolution") as f64;
        if r < 1.5 * dp {
            return Err(CaseError::InvalidValue {
                key: "radius".into(),
                value: Num(r).to_string(),
                allowed: format!(
                    "at least 1.5 dp = 1.5 height/resolution = {}",
                    Num(1.5 * dp)
                ),
            });
        }
        let (rho, e, nu) = (p.f64("density"), p.f64("youngs_modulus"), p.f64("nu"));
        let kind: MaterialKind = p.text("material").parse()?;
        let mat = material(kind, e, nu, rho)?;
        let set = tube_polar(DVec3::new(0.0, 0.0, -0.5 * h), DVec3::Z, 0.0, r, h, dp)?;
        let n = set.len();
        let dz = h / (h / dp).round().max(1.0);
        let x0 = set.positions().to_vec();
        let volumes = set.volumes().to_vec();
        let top: Vec<u32> = (0..n as u32)
            .filter(|&i| x0[i as usize].z > 0.5 * h - dz)
            .collect();
        let bottom: Vec<u32> = (0..n as u32)
            .filter(|&i| x0[i as usize].z < -0.5 * h + dz)
            .collect();
        let gauge = h - dz;
        let stretch = p.f64("stretch");
        let speed = p.f64("pull_speed");
        let travel = 0.5 * (stretch - 1.0) * gauge;
        let (ramp, hold) = timeline(p, travel, speed);
        let up = grip_motion::<D3>(DVec3::Z, speed, ramp, travel)?;
        let down = grip_motion::<D3>(-DVec3::Z, speed, ramp, travel)?;
        let mut constraints = Constraints::new();
        constraints.push_named(
            "grip_top",
            Constraint::PrescribedVelocity {
                particles: top,
                velocity: up.0,
            },
            n,
        )?;
        constraints.push_named(
            "grip_bottom",
            Constraint::PrescribedVelocity {
                particles: bottom,
                velocity: down.0,
            },
            n,
        )?;
        let end_time = up.1 + hold;
        let damping = relaxation(p, rho, e, h)?;
        let interval = p.f64("probe_interval");
        let outer = set.tagged("outer")?;
        let body = Body::<D3> {
            positions: x0,
            volumes: volumes.clone(),
            dp,
            velocities: Vec::new(),
            densities: Vec::new(),
        };
        let summarise = move |s: &dyn Solver<D3>, _: &RunRecord| {
            let mut m = cylinder_summary(s, &volumes, &outer, r, gauge, dz, end_time - hold);
            m.insert("particle_spacing".into(), json!(dp));
            m.insert("gauge_length".into(), json!(gauge));
            m.insert("end_time".into(), json!(end_time));
            m
        };
        run_tl(
            "pulling-cylinder-3d",
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

/// The cylinder's figures: pulling force on the top grip (N, mean over the second half of the
/// hold), force curve against the stretch, stretch reached, neck width (mean diameter of the
/// outer layer's surface points in the slices next to mid-height, over `2R`), volume change.
pub fn cylinder_summary(
    s: &dyn Solver<D3>,
    volumes: &[f64],
    outer: &[u32],
    radius: f64,
    gauge: f64,
    dz: f64,
    hold_start: f64,
) -> Map<String, Json> {
    let mut m = Map::new();
    let series = s.series();
    let find = |name: &str| series.iter().find(|x| x.name == name);
    let t_end = s.time();
    let settled = hold_start + 0.5 * (t_end - hold_start);
    if let (Some(top), Some(bottom)) = (find("grip_top"), find("grip_bottom")) {
        m.insert(
            "reaction_force".into(),
            finite_or_null(-mean_after(top, "force_z", settled)),
        );
        m.insert(
            "reaction_force_bottom".into(),
            finite_or_null(mean_after(bottom, "force_z", settled)),
        );
        let (zt, zb) = (
            top.column("z").unwrap_or(&[]),
            bottom.column("z").unwrap_or(&[]),
        );
        let d0 = zt.first().zip(zb.first()).map(|(a, b)| a - b);
        let stretch: Vec<f64> = zt
            .iter()
            .zip(zb)
            .map(|(a, b)| d0.map_or(f64::NAN, |d0| 1.0 + ((a - b) - d0) / gauge))
            .collect();
        m.insert(
            "stretch_reached".into(),
            finite_or_null(stretch.last().copied().unwrap_or(f64::NAN)),
        );
        let force: Vec<f64> = top
            .column("force_z")
            .unwrap_or(&[])
            .iter()
            .map(|f| -f)
            .collect();
        m.insert(
            "force_curve".into(),
            curve_json(&top.time, &stretch, &force, "stretch", 400),
        );
    }
    let (reference, f) = reference_and_deformation::<D3>(s);
    let x = s.positions();
    let all: Vec<u32> = (0..x.len() as u32).collect();
    m.insert(
        "volume_change".into(),
        finite_or_null(area_change::<D3>(&f, volumes, &all)),
    );
    // Outer layer particles within half a slice of mid-height: their surface points, half a
    // layer outward; the layer thickness is radius − (the layer's reference radius) times 2.
    let (mut sum, mut count) = (0.0, 0);
    for &i in outer {
        let i = i as usize;
        let x0 = reference[i];
        if x0.z.abs() > 0.5 * dz + 1e-9 * radius {
            continue;
        }
        let radial = DVec3::new(x0.x, x0.y, 0.0);
        let r0 = radial.length();
        let out = radial / r0 * (radius - r0);
        let p = surface_point::<D3>(x[i], f[i], out);
        sum += DVec3::new(p.x, p.y, 0.0).length();
        count += 1;
    }
    let neck = if count > 0 {
        sum / count as f64 / radius
    } else {
        f64::NAN
    };
    m.insert("neck_width".into(), finite_or_null(neck));
    m
}
