//! Benchmark case 2: the punching strip (TL paper §4.2, Fig. 5–6).
//!
//! A rubber strip `width × height` (centred at the origin), neo-Hookean, compressed between two
//! rigid punches of `punch_width × punch_thickness` (edges rounded by `punch_corner_radius`, 0:
//! sharp) that start touching its top and bottom faces
//! and travel `compression · height/2` each toward the centre at `punch_speed` (smooth start,
//! then a hold; see [`quasi_static`](crate::cases::quasi_static)). Contact is frictionless and
//! kinematic (`sph_core::tool`): the strip slides along the punches and may leave them, and each
//! punch records the reaction force it receives (`/series/punch_top`, `/series/punch_bottom`).
//! The relaxation damping is the TL paper's splitting random-choice one with `L = height`.
//!
//! Punches wider than the strip (`punch_width = 3 · width`) make the compression homogeneous:
//! the summary then compares with the plane-strain closed form
//! ([`homogeneous_plane_strain`]). The paper's punch speed, 2 mm/s, would take ~2·10⁷ steps at
//! H/dp = 30; the default speed is the largest at which halving it changes the final force by
//! less than 1 % (docs/validation.md).

use crate::cases::quasi_static::{
    area_change, curve_json, homogeneous_plane_strain, loading_params, mean_after,
    mirror_asymmetry, reference_and_deformation, relaxation, surface_point, timeline,
};
use crate::cases::tl_common::{material, run_tl, tl_params, TL_METHODS};
use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::{finite_or_null, RunOptions, RunRecord};
use crate::{Case, CaseInfo};
use glam::DVec2;
use serde_json::{json, Map, Value as Json};
use sph_core::error::Num;
use sph_core::tool::{RigidTool, ToolMotion, ToolShape};
use sph_core::Body;
use sph_core::{Solver, D2};
use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
use sph_materials::{Material, MaterialKind};

/// The punching strip.
pub struct PunchingStrip2d;

/// Widest punch allowed, as a multiple of the strip width (a wider punch is the same load).
pub const MAX_PUNCH_WIDTH_RATIO: f64 = 10.0;

impl Case for PunchingStrip2d {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "punching-strip-2d",
            description: "rubber strip compressed between two rigid frictionless punches (TL §4.2)",
            methods: TL_METHODS,
        }
    }

    fn params(&self) -> Params {
        let mut specs = vec![
            Param::float("width", 9e-3, Range::Positive, "strip width (m)"),
            Param::float("height", 3e-3, Range::Positive, "strip height H (m)"),
            Param::float(
                "punch_width",
                9e-3,
                Range::Positive,
                "punch width (m; the paper's = the strip width; at most 10 × width)",
            ),
            Param::float(
                "punch_thickness",
                3e-4,
                Range::Positive,
                "punch thickness (m)",
            ),
            Param::float(
                "punch_corner_radius",
                0.0,
                Range::NonNegative,
                "radius of the punches' edges (m; 0: sharp, the paper's; the FE reference rounds \
                 them by 5e-5; at most half the punch thickness)",
            ),
            Param::float(
                "compression",
                0.5,
                Range::Open(0.0, 1.0),
                "height reduction at the end (0.5 = 50 %)",
            ),
            Param::int("resolution", 30, Range::Closed(4.0, 400.0), "H/dp"),
            Param::bool(
                "hold_centre",
                false,
                "hold the strip's centre of mass still in x (frictionless punches leave its \
                 sideways sliding free, and it is unstable once the strip wraps their corners)",
            ),
            Param::float(
                "punch_speed",
                2.0,
                Range::Positive,
                "speed of each punch (m/s; the paper's 2e-3 is ~1000× slower for the same result)",
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
        let mut p = Params::new("punching-strip-2d", specs);
        p.set_text("probe_interval", "1e-6").expect("valid default");
        p.set_text("dt_stretch", "true").expect("valid default");
        p
    }

    fn run(
        &self,
        method: &str,
        p: &Params,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), CaseError> {
        let (w, h) = (p.f64("width"), p.f64("height"));
        let pw = p.f64("punch_width");
        if pw > MAX_PUNCH_WIDTH_RATIO * w {
            return Err(CaseError::InvalidValue {
                key: "punch_width".into(),
                value: Num(pw).to_string(),
                allowed: format!(
                    "0 < punch_width <= {MAX_PUNCH_WIDTH_RATIO} × width = {}",
                    Num(MAX_PUNCH_WIDTH_RATIO * w)
                ),
            });
        }
        let (t, corner) = (p.f64("punch_thickness"), p.f64("punch_corner_radius"));
        if corner > 0.5 * t.min(pw) {
            return Err(CaseError::InvalidValue {
                key: "punch_corner_radius".into(),
                value: Num(corner).to_string(),
                allowed: format!(
                    "0 <= punch_corner_radius <= half the punch thickness and width = {}",
                    Num(0.5 * t.min(pw))
                ),
            });
        }
        let (rho, e, nu) = (p.f64("density"), p.f64("youngs_modulus"), p.f64("nu"));
        let kind: MaterialKind = p.text("material").parse()?;
        let mat = material(kind, e, nu, rho)?;
        let constants = *Material::<D2>::constants(&mat);
        let (set, dp) = strip_particles(w, h, p.int("resolution"))?;
        let volumes = set.volumes().to_vec();
        let body = Body::<D2> {
            positions: set.positions().to_vec(),
            volumes: volumes.clone(),
            dp,
            velocities: Vec::new(),
            densities: Vec::new(),
        };
        let compression = p.f64("compression");
        let speed = p.f64("punch_speed");
        let travel = 0.5 * compression * h;
        let (ramp, hold) = timeline(p, travel, speed);
        let down = ToolMotion::<D2>::new(DVec2::new(0.0, -1.0), speed, ramp, travel)?;
        let up = ToolMotion::<D2>::new(DVec2::new(0.0, 1.0), speed, ramp, travel)?;
        let top = ToolShape::rounded_cuboid(
            DVec2::new(-0.5 * pw, 0.5 * h),
            DVec2::new(0.5 * pw, 0.5 * h + t),
            corner,
        )?;
        let bottom = ToolShape::rounded_cuboid(
            DVec2::new(-0.5 * pw, -0.5 * h - t),
            DVec2::new(0.5 * pw, -0.5 * h),
            corner,
        )?;
        let tools = vec![
            RigidTool::new("punch_top", top, down.clone()),
            RigidTool::new("punch_bottom", bottom, up),
        ];
        let end_time = down.arrival_time() + hold;
        let damping = relaxation(p, rho, e, h)?;
        let interval = p.f64("probe_interval");
        let hold_centre = p.flag("hold_centre");
        let (mu, lambda) = (constants.shear_modulus, constants.lame_lambda);
        let summary_tools = tools.clone();
        let summarise = move |s: &dyn Solver<D2>, _: &RunRecord| {
            let mut m = punching_summary(s, &summary_tools, &volumes, dp, w, h, end_time - hold);
            let (lx, p_yy) = homogeneous_plane_strain(mu, lambda, 1.0 - compression);
            m.insert("theory_homogeneous_force".into(), json!(-p_yy * w));
            m.insert("theory_homogeneous_width_ratio".into(), json!(lx));
            m.insert("particle_spacing".into(), json!(dp));
            m.insert("end_time".into(), json!(end_time));
            m
        };
        run_tl(
            "punching-strip-2d",
            method,
            p,
            body,
            mat,
            |s| {
                let s = s
                    .with_tools(tools)?
                    .with_centre_held([hold_centre, false, false])
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

/// The strip's particles: a lattice of spacing `dp = height/resolution` filling
/// `[−w/2, w/2] × [−h/2, h/2]` (symmetric about both axes).
pub fn strip_particles(
    w: f64,
    h: f64,
    resolution: i64,
) -> Result<(ParticleSet<D2>, f64), CaseError> {
    let dp = h / resolution as f64;
    let nx = (w / dp).round();
    if nx < 2.0 || (nx * dp - w).abs() > 1e-9 * w {
        return Err(CaseError::InvalidValue {
            key: "width".into(),
            value: Num(w).to_string(),
            allowed: format!(
                "a whole multiple (≥ 2) of dp = height/resolution = {}",
                Num(dp)
            ),
        });
    }
    let corner = DVec2::new(-0.5 * w, -0.5 * h);
    let shape = Aabb::<D2>::new(corner, -corner)?;
    let set = ParticleSet::fill(&Lattice::new(dp, corner)?, &shape)?;
    Ok((set, dp))
}

/// The punching figures from the final state and the punches' series (see the module docs):
/// reaction force, force curve, compression reached, area change, bulge and barrelling,
/// symmetry, and the deepest penetration of a particle's half-spacing surface into a punch.
pub fn punching_summary(
    s: &dyn Solver<D2>,
    tools: &[RigidTool<D2>],
    volumes: &[f64],
    dp: f64,
    w: f64,
    h: f64,
    hold_start: f64,
) -> Map<String, Json> {
    let mut m = Map::new();
    let series = s.series();
    let find = |name: &str| series.iter().find(|x| x.name == name);
    let t_end = s.time();
    let settled = hold_start + 0.5 * (t_end - hold_start);
    if let (Some(top), Some(bottom)) = (find("punch_top"), find("punch_bottom")) {
        let f_top = mean_after(top, "force_y", settled);
        let f_bottom = mean_after(bottom, "force_y", settled);
        m.insert("reaction_force".into(), finite_or_null(f_top));
        m.insert("reaction_force_bottom".into(), finite_or_null(-f_bottom));
        m.insert(
            "force_imbalance".into(),
            finite_or_null((f_top + f_bottom).abs() / f_top.abs()),
        );
        let d_top = top.column("displacement").unwrap_or(&[]);
        let d_bottom = bottom.column("displacement").unwrap_or(&[]);
        let compression: Vec<f64> = d_top
            .iter()
            .zip(d_bottom)
            .map(|(a, b)| (a + b) / h)
            .collect();
        m.insert(
            "compression_reached".into(),
            finite_or_null(compression.last().copied().unwrap_or(0.0)),
        );
        m.insert(
            "force_curve".into(),
            curve_json(
                &top.time,
                &compression,
                top.column("force_y").unwrap_or(&[]),
                "compression",
                400,
            ),
        );
    }
    let (reference, f) = reference_and_deformation::<D2>(s);
    let x = s.positions();
    let all: Vec<u32> = (0..x.len() as u32).collect();
    m.insert(
        "area_change".into(),
        finite_or_null(area_change::<D2>(&f, volumes, &all)),
    );
    // Side surface: particles of the outermost columns, their surface point dp/2 outward.
    let side = 0.5 * w - 0.5 * dp;
    let (mut widest, mut mid, mut end_row) = (0.0f64, 0.0f64, 0.0f64);
    let (mut mid_dist, mut end_dist) = (f64::INFINITY, f64::INFINITY);
    for (i, &x0) in reference.iter().enumerate() {
        if (x0.x.abs() - side).abs() > 1e-9 * w {
            continue;
        }
        let out = DVec2::new(0.5 * dp * x0.x.signum(), 0.0);
        let reach = surface_point::<D2>(x[i], f[i], out).x.abs();
        widest = widest.max(reach);
        // Row closest to mid-height, and the top/bottom rows.
        let dm = x0.y.abs();
        if dm < mid_dist - 1e-12 {
            (mid_dist, mid) = (dm, reach);
        } else if (dm - mid_dist).abs() <= 1e-12 {
            mid = mid.max(reach);
        }
        let de = 0.5 * h - x0.y.abs();
        if de < end_dist - 1e-12 {
            (end_dist, end_row) = (de, reach);
        } else if (de - end_dist).abs() <= 1e-12 {
            end_row = end_row.max(reach);
        }
    }
    m.insert("bulge".into(), finite_or_null(widest / (0.5 * w)));
    m.insert("width_ratio_mid".into(), finite_or_null(mid / (0.5 * w)));
    m.insert(
        "width_ratio_faces".into(),
        finite_or_null(end_row / (0.5 * w)),
    );
    let sym_x = mirror_asymmetry::<D2>(&reference, x, 0, dp);
    let sym_y = mirror_asymmetry::<D2>(&reference, x, 1, dp);
    m.insert("symmetry_error".into(), finite_or_null(sym_x.max(sym_y)));
    m.insert("symmetry_error_x".into(), finite_or_null(sym_x));
    m.insert("symmetry_error_y".into(), finite_or_null(sym_y));
    let mode = if sym_x.max(sym_y) > 0.5 {
        "asymmetric (buckled)"
    } else if mid > end_row * 1.01 {
        "barrelled"
    } else {
        "homogeneous"
    };
    m.insert("deformation_mode".into(), json!(mode));
    // Deepest penetration of the strip's surface (each particle's deformed half cell, the
    // contact offset) into a punch.
    let penetration = x
        .iter()
        .zip(&f)
        .map(|(&xi, &fi)| {
            tools
                .iter()
                .map(|t| {
                    let (d, n) = t.distance_at(xi, t_end);
                    0.5 * dp * (fi.transpose() * n).length() - d
                })
                .fold(f64::NEG_INFINITY, f64::max)
        })
        .fold(0.0f64, f64::max);
    m.insert(
        "max_penetration_over_dp".into(),
        finite_or_null(penetration / dp),
    );
    m
}
