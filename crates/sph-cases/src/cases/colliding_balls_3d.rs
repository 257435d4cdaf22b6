//! CASES.md 11: two colliding hollow rubber balls (UL paper §6.4, Fig. 15–16), the 3D colliding
//! rings.
//!
//! Shells of inner/outer radius 0.03/0.04 m, centres 0.09 m apart on the x axis, each moving
//! toward the other at `v0` (0.08 c0), linear elastic (UL) E = 1e7, ν = 0.4, ρ = 1200
//! (c0 = 117.9 m/s), `dp` = 0.001 (≈ 310,000 particles; coarser `dp` allowed), snapshots at the
//! paper's t = 0.001, 0.003, 0.005, 0.007 (`snapshot_interval` 0.001), end 0.008 s.
//!
//! Particles (`layout`): `layers` (default) = concentric spherical layers, each a Fibonacci
//! lattice (`sph_geometry::generate::hollow_sphere_polar`): the surfaces are exact spheres and the
//! spacing is near-uniform (nearest distance 0.87–1.00 dp); the right ball is the mirror image of
//! the left, so the collision is symmetric. The paper relaxes its particles (Yu et al.'s level
//! set); `lattice` cuts both balls from one cubic lattice (staircase surfaces), for comparison.
//! The Fibonacci poles are on the z axis, away from the contact on the x axis.
//!
//! The balls are two bodies of one UL solver meeting through the UL contact pressure
//! (`contact_stiffness` = κ); `allow_fracture` is on (particles that lose every neighbour fly on
//! and are counted). Summary: the mean x-velocity of each ball at the end, the contact force on
//! the left ball (`contact_force_max`, `contact_start`, `contact_end`), and `v0_m_per_s`,
//! `v0_over_c0`, plus the standard UL figures (disorder, isolated particles, momentum balance,
//! energy residual).

use crate::cases::impact_common::{
    body_velocities, check_dp, contact_param, contact_summary, invalid, layout_param, speed,
    speed_params,
};
use crate::cases::tl_common::material;
use crate::cases::ul_common::{run_ul, ul_params, UL_METHODS};
use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::{finite_or_null, RunOptions, RunRecord};
use crate::{Case, CaseInfo};
use glam::DVec3;
use serde_json::{json, Map, Value as Json};
use sph_core::{Solver, D3};
use sph_geometry::generate::{hollow_sphere, hollow_sphere_polar, ParticleSet};
use sph_materials::{Material, MaterialKind};

/// Two colliding hollow balls.
pub struct CollidingBalls3d;

impl Case for CollidingBalls3d {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "colliding-balls-3d",
            description: "two hollow rubber balls colliding (UL §6.4)",
            methods: UL_METHODS,
        }
    }

    fn params(&self) -> Params {
        let mut specs = vec![
            Param::float("inner_radius", 0.03, Range::NonNegative, "r_in (m)"),
            Param::float("outer_radius", 0.04, Range::Positive, "r_out (m)"),
            Param::float(
                "centre_distance",
                0.09,
                Range::Positive,
                "distance between the balls' centres (m; ≥ 2 r_out)",
            ),
            Param::float("dp", 0.001, Range::Positive, "particle spacing (m)"),
            Param::float("youngs_modulus", 1e7, Range::Positive, "E (Pa)"),
            Param::float("nu", 0.4, Range::Open(-1.0, 0.5), "Poisson's ratio"),
            Param::float("density", 1200.0, Range::Positive, "ρ0 (kg/m³)"),
            Param::float("end_time", 0.008, Range::Positive, "simulated time (s)"),
            layout_param("layers"),
            contact_param(),
        ];
        specs.extend(speed_params(
            0.08,
            "speed of each ball toward the other (unit: v0_unit)",
        ));
        specs.extend(crate::runner::output_params());
        specs.extend(ul_params());
        let mut p = Params::new("colliding-balls-3d", specs);
        for (k, v) in [
            ("snapshot_interval", "0.001"),
            ("probe_interval", "2e-5"),
            ("allow_fracture", "true"),
        ] {
            p.set_text(k, v).expect("valid default");
        }
        p
    }

    fn run(
        &self,
        method: &str,
        p: &Params,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), CaseError> {
        let (r_in, r_out, dist, dp) = (
            p.f64("inner_radius"),
            p.f64("outer_radius"),
            p.f64("centre_distance"),
            p.f64("dp"),
        );
        if r_in >= r_out {
            return Err(invalid(
                "inner_radius",
                r_in,
                format!("inner_radius < outer_radius = {r_out}"),
            ));
        }
        if dist < 2.0 * r_out {
            return Err(invalid(
                "centre_distance",
                dist,
                format!(
                    "centre_distance >= 2 outer_radius = {} (the balls overlap)",
                    2.0 * r_out
                ),
            ));
        }
        check_dp(
            dp,
            r_out - r_in,
            "the shell thickness outer_radius − inner_radius",
        )?;
        let (e, nu, rho) = (p.f64("youngs_modulus"), p.f64("nu"), p.f64("density"));
        let mat = material(MaterialKind::LinearElastic, e, nu, rho)?;
        let constants = *Material::<D3>::constants(&mat);
        let c0 = constants.sound_speed;
        let v0 = speed(p, c0);
        let centre = DVec3::new(-0.5 * dist, 0.0, 0.0);
        let left = match p.text("layout") {
            "lattice" => hollow_sphere(centre, r_in, r_out, dp)?,
            _ => hollow_sphere_polar(centre, r_in, r_out, dp)?,
        };
        let nl = left.len();
        let mirrored: Vec<DVec3> = left
            .positions()
            .iter()
            .map(|x| DVec3::new(-x.x, x.y, x.z))
            .collect();
        let mut set = left.clone();
        set.extend(&ParticleSet::from_parts(mirrored, left.volumes().to_vec())?)?;
        let n = set.len();
        let body_of: Vec<u32> = (0..n).map(|i| u32::from(i >= nl)).collect();
        let velocities = (0..n)
            .map(|i| DVec3::new(if i < nl { v0 } else { -v0 }, 0.0, 0.0))
            .collect();
        let volumes = set.volumes().to_vec();
        let body = sph_core::Body::<D3> {
            positions: set.positions().to_vec(),
            volumes: volumes.clone(),
            dp,
            velocities,
            densities: Vec::new(),
        };
        let interval = p.f64("probe_interval");
        let bodies = body_of.clone();
        run_ul(
            "colliding-balls-3d",
            method,
            p,
            body,
            constants,
            |s| Ok(s.with_contact(body_of)?.with_probes(Vec::new(), interval)?),
            p.f64("end_time"),
            options,
            move |s: &dyn Solver<D3>, _: &RunRecord| {
                let mut m = contact_summary(s, 0, DVec3::X);
                let vb = body_velocities(s, &bodies, &volumes, 2);
                m.insert("left_velocity_final".into(), finite_or_null(vb[0].x));
                m.insert("right_velocity_final".into(), finite_or_null(vb[1].x));
                m.insert("v0_m_per_s".into(), json!(v0));
                m.insert("v0_over_c0".into(), json!(v0 / c0));
                m.insert("ball_particles".into(), json!(nl));
                m
            },
        )
    }
}
