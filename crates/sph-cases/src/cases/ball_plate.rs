//! CASES.md 12–13: a rubber ball hitting a rubber plate (UL paper §6.5–6.6, Fig. 17–21), in 2D
//! ([`BallPlate2d`], plate fixed at both ends) and 3D ([`BallPlate3d`], plate fixed on its four
//! edges).
//!
//! Plate `plate_length` (0.5, along x) × `plate_thickness` (0.02, along y) [× `plate_width`
//! (0.5, along z) in 3D], centred at the origin, cut from a cell-centred lattice of spacing `dp`
//! (0.0025; the lengths must be whole multiples of it). "Fixed at the ends / edges": the
//! particles within `clamp_width` (0.01 = 4 dp, the frame SPHinXsys uses for its clamps) of the
//! ends x = ±L/2 (and in 3D of the edges z = ±W/2) are held fixed; the span between the clamps is
//! free. Ball of radius `ball_radius` (0.05) with its centre `ball_distance` (0.1) above the plate
//! centre (on the plate normal, y), moving toward the plate at `v0` (2D: 0.02 c0, Fig. 18; 0.06
//! and 0.12 c0 in Fig. 19–20; 3D: 0.12 c0, Fig. 21); ρ = 1200, E = 1e7, ν = 0.49
//! (c0 = 372.7 m/s). The 2D ball is `annulus_polar` with `r_in = 0` (concentric rings); the 3D
//! ball `hollow_sphere_polar` (concentric spherical layers, Fibonacci poles on z, away from the
//! contact at the ball's bottom) or, with `layout = lattice`, a lattice cut.
//!
//! Ball and plate are two bodies of one UL solver meeting through the UL contact pressure;
//! `allow_fracture` is on. End time 0.05 s (2D) / 0.02 s (3D): the paper's figures give no
//! times; these cover the impact, the largest deflection of the plate and the ball's rebound at
//! every speed (docs/validation.md).
//!
//! Summary: the ball's centre-of-mass velocity along y at the end (`ball_velocity_final`), the
//! largest downward deflection of the plate centre's bottom particle (`plate_deflection_max`), the
//! contact force on the ball (`contact_force_max` along +y, `contact_start`, `contact_end`),
//! `v0_m_per_s`, `v0_over_c0`, and the standard UL figures.

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
use glam::{DVec2, DVec3};
use serde_json::{json, Map, Value as Json};
use sph_core::{Constraint, Constraints, Dim, Probe, Solver, D2, D3};
use sph_geometry::generate::ParticleSet;
use sph_geometry::generate::{annulus_polar, hollow_sphere, hollow_sphere_polar, Aabb, Lattice};
use sph_materials::{Material, MaterialKind};

/// The 2D ball–plate impact.
pub struct BallPlate2d;
/// The 3D ball–plate impact.
pub struct BallPlate3d;

fn params(case: &str, three_d: bool) -> Params {
    let mut specs = vec![
        Param::float("ball_radius", 0.05, Range::Positive, "R (m)"),
        Param::float(
            "ball_distance",
            0.1,
            Range::Positive,
            "distance of the ball's centre from the plate's centre, along the plate normal (m)",
        ),
        Param::float("plate_length", 0.5, Range::Positive, "L, along x (m)"),
        Param::float("plate_thickness", 0.02, Range::Positive, "H, along y (m)"),
        Param::float(
            "clamp_width",
            0.01,
            Range::Positive,
            "width of the fixed strips at the plate's ends (3D: edges) (m)",
        ),
        Param::float("dp", 0.0025, Range::Positive, "particle spacing (m)"),
        Param::float("youngs_modulus", 1e7, Range::Positive, "E (Pa)"),
        Param::float("nu", 0.49, Range::Open(-1.0, 0.5), "Poisson's ratio"),
        Param::float("density", 1200.0, Range::Positive, "ρ0 (kg/m³)"),
        Param::float(
            "end_time",
            if three_d { 0.02 } else { 0.05 },
            Range::Positive,
            "simulated time (s)",
        ),
        contact_param(),
    ];
    if three_d {
        specs.push(Param::float(
            "plate_width",
            0.5,
            Range::Positive,
            "W, along z (m)",
        ));
        specs.push(layout_param("layers"));
    }
    specs.extend(speed_params(
        if three_d { 0.12 } else { 0.02 },
        "speed of the ball toward the plate (unit: v0_unit)",
    ));
    specs.extend(crate::runner::output_params());
    specs.extend(ul_params());
    let mut p = Params::new(case, specs);
    for (k, v) in [("probe_interval", "2e-5"), ("allow_fracture", "true")] {
        p.set_text(k, v).expect("valid default");
    }
    p
}

/// The checked geometry (all bad input is reported here, before any particle is made).
struct Geometry {
    radius: f64,
    distance: f64,
    length: f64,
    thickness: f64,
    width: f64,
    clamp: f64,
    dp: f64,
}

fn geometry(p: &Params, three_d: bool) -> Result<Geometry, CaseError> {
    let g = Geometry {
        radius: p.f64("ball_radius"),
        distance: p.f64("ball_distance"),
        length: p.f64("plate_length"),
        thickness: p.f64("plate_thickness"),
        width: if three_d { p.f64("plate_width") } else { 0.0 },
        clamp: p.f64("clamp_width"),
        dp: p.f64("dp"),
    };
    if g.distance < g.radius + 0.5 * g.thickness {
        return Err(invalid(
            "ball_distance",
            g.distance,
            format!(
                "ball_distance >= ball_radius + plate_thickness/2 = {} (the ball overlaps the plate)",
                g.radius + 0.5 * g.thickness
            ),
        ));
    }
    check_dp(g.dp, g.thickness, "plate_thickness")?;
    check_dp(g.dp, g.radius, "ball_radius")?;
    let mut lengths = vec![("plate_length", g.length), ("plate_thickness", g.thickness)];
    if three_d {
        lengths.push(("plate_width", g.width));
    }
    for (key, len) in lengths {
        if ((len / g.dp).round() * g.dp - len).abs() > 1e-9 * len {
            return Err(invalid(
                key,
                len,
                format!("a whole multiple of dp = {}", g.dp),
            ));
        }
    }
    let span = if three_d {
        g.length.min(g.width)
    } else {
        g.length
    };
    if g.clamp < g.dp || g.clamp >= 0.5 * span {
        return Err(invalid(
            "clamp_width",
            g.clamp,
            format!(
                "dp = {} <= clamp_width < half the plate = {}",
                g.dp,
                0.5 * span
            ),
        ));
    }
    Ok(g)
}

/// Ball (body 0) then plate (body 1), the plate's clamped particles, and the plate particle at
/// the bottom of its centre (probe `plate_centre`).
fn scene<D: Dim>(
    ball: ParticleSet<D>,
    plate: ParticleSet<D>,
    clamped: impl Fn(D::Vector) -> bool,
    bottom_centre: D::Vector,
) -> Result<(ParticleSet<D>, usize, Vec<u32>, u32), CaseError> {
    let nb = ball.len();
    let mut set = ball;
    set.extend(&plate)?;
    let fixed: Vec<u32> = (nb..set.len())
        .filter(|&i| clamped(set.positions()[i]))
        .map(|i| i as u32)
        .collect();
    let probe = nb
        + plate
            .nearest(bottom_centre)
            .expect("the plate has particles");
    Ok((set, nb, fixed, probe as u32))
}

#[allow(clippy::too_many_arguments)]
fn run_scene<D: Dim>(
    case: &'static str,
    method: &str,
    p: &Params,
    set: ParticleSet<D>,
    nb: usize,
    fixed: Vec<u32>,
    probe: u32,
    dp: f64,
    down: D::Vector,
    options: &RunOptions,
) -> Result<(RunRecord, Map<String, Json>), CaseError>
where
    sph_materials::MaterialModel: Material<D>,
{
    let (e, nu, rho) = (p.f64("youngs_modulus"), p.f64("nu"), p.f64("density"));
    let mat = material(MaterialKind::LinearElastic, e, nu, rho)?;
    let constants = *Material::<D>::constants(&mat);
    let c0 = constants.sound_speed;
    let v0 = speed(p, c0);
    let n = set.len();
    let body_of: Vec<u32> = (0..n).map(|i| u32::from(i >= nb)).collect();
    let velocities = (0..n)
        .map(|i| if i < nb { down * v0 } else { D::zero() })
        .collect();
    let volumes = set.volumes().to_vec();
    let body = sph_core::Body::<D> {
        positions: set.positions().to_vec(),
        volumes: volumes.clone(),
        dp,
        velocities,
        densities: Vec::new(),
    };
    let interval = p.f64("probe_interval");
    let bodies = body_of.clone();
    let y0 = D::dot(set.positions()[probe as usize], down);
    run_ul(
        case,
        method,
        p,
        body,
        constants,
        |s| {
            let mut c = Constraints::new();
            c.push(Constraint::Fixed { particles: fixed }, s.len())?;
            let s = s.with_constraints(c).with_contact(body_of)?;
            Ok(s.with_probes(vec![Probe::particle("plate_centre", probe)], interval)?)
        },
        p.f64("end_time"),
        options,
        move |s: &dyn Solver<D>, _: &RunRecord| {
            let mut m = contact_summary(s, 0, down);
            let vb = body_velocities(s, &bodies, &volumes, 2);
            m.insert(
                "ball_velocity_final".into(),
                finite_or_null(-D::dot(vb[0], down)),
            );
            if let Some(pr) = s.probes().iter().find(|x| x.name == "plate_centre") {
                let d = pr
                    .positions
                    .iter()
                    .map(|&x| D::dot(x, down) - y0)
                    .fold(0.0, f64::max);
                m.insert("plate_deflection_max".into(), finite_or_null(d));
            }
            m.insert("v0_m_per_s".into(), json!(v0));
            m.insert("v0_over_c0".into(), json!(v0 / c0));
            m.insert("ball_particles".into(), json!(nb));
            m
        },
    )
}

impl Case for BallPlate2d {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "ball-plate-2d",
            description: "rubber ball hitting a plate fixed at both ends (UL §6.5)",
            methods: UL_METHODS,
        }
    }

    fn params(&self) -> Params {
        params("ball-plate-2d", false)
    }

    fn run(
        &self,
        method: &str,
        p: &Params,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), CaseError> {
        let g = geometry(p, false)?;
        let (hl, ht) = (0.5 * g.length, 0.5 * g.thickness);
        let ball = annulus_polar(DVec2::new(0.0, g.distance), 0.0, g.radius, g.dp)?;
        let corner = DVec2::new(-hl, -ht);
        let plate = ParticleSet::fill(
            &Lattice::<D2>::new(g.dp, corner)?,
            &Aabb::<D2>::new(corner, DVec2::new(hl, ht))?,
        )?;
        let clamp = hl - g.clamp;
        let (set, nb, fixed, probe) = scene(
            ball,
            plate,
            |x: DVec2| x.x.abs() > clamp,
            DVec2::new(0.0, -ht),
        )?;
        run_scene(
            "ball-plate-2d",
            method,
            p,
            set,
            nb,
            fixed,
            probe,
            g.dp,
            DVec2::NEG_Y,
            options,
        )
    }
}

impl Case for BallPlate3d {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "ball-plate-3d",
            description: "rubber ball hitting a plate fixed on its four edges (UL §6.6)",
            methods: UL_METHODS,
        }
    }

    fn params(&self) -> Params {
        params("ball-plate-3d", true)
    }

    fn run(
        &self,
        method: &str,
        p: &Params,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), CaseError> {
        let g = geometry(p, true)?;
        let (hl, ht, hw) = (0.5 * g.length, 0.5 * g.thickness, 0.5 * g.width);
        let centre = DVec3::new(0.0, g.distance, 0.0);
        let ball = match p.text("layout") {
            "lattice" => hollow_sphere(centre, 0.0, g.radius, g.dp)?,
            _ => hollow_sphere_polar(centre, 0.0, g.radius, g.dp)?,
        };
        let corner = DVec3::new(-hl, -ht, -hw);
        let plate = ParticleSet::fill(
            &Lattice::<D3>::new(g.dp, corner)?,
            &Aabb::<D3>::new(corner, DVec3::new(hl, ht, hw))?,
        )?;
        let (cx, cz) = (hl - g.clamp, hw - g.clamp);
        let (set, nb, fixed, probe) = scene(
            ball,
            plate,
            |x: DVec3| x.x.abs() > cx || x.z.abs() > cz,
            DVec3::new(0.0, -ht, 0.0),
        )?;
        run_scene(
            "ball-plate-3d",
            method,
            p,
            set,
            nb,
            fixed,
            probe,
            g.dp,
            DVec3::NEG_Y,
            options,
        )
    }
}
