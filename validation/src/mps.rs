//! MPS validation (MPS paper §IV): the cantilever plate against Table I with a convergence
//! series, the r_e sensitivity, TL-HF beside MPS on the same plate, the static cantilever
//! against beam theory, the ring under a small pressure against Lamé, and the disorder
//! indicator over time for the ring, the slab and the rings.

mod report;

pub use report::report;

use crate::frames::{frame_at, p99_value, rings_roughness};
use crate::plot::{line_plot, Series};
use crate::plot::{particle_frames, Frame};
use crate::store::{
    command_for, cost_estimate, fmt_opt, load, pct, rel, run_or_load, run_or_load_then, status,
};
use sph_cases::CaseError;
use sph_core::Body;
use std::fmt::Write as _;
use std::path::Path;

/// Cantilever resolutions (H/dp) of the convergence series; 10 is the default (the paper gives
/// none; dp = 2 mm as in its static cantilever).
const PLATE_RES: [u32; 3] = [5, 10, 20];
/// r_e / l0 of the sensitivity study.
const RES_RE: [f64; 3] = [2.1, 2.5, 3.0];
/// Static cantilever resolutions (10 is the paper's dp = 0.002; 40 shows the convergence).
const STATIC_RES: [u32; 4] = [5, 10, 20, 40];

fn plate_id(method: &str, res: u32, re: f64) -> String {
    format!("mps-plate-{method}-r{res}-re{re}")
}

/// The plate with the solid clamp (the case's default, which matches the MPS paper).
fn plate_set(res: u32, re: f64) -> Vec<String> {
    vec![
        format!("resolution={res}"),
        format!("re_over_l0={re}"),
        "end_time=1.0".into(),
        "clamp=solid".into(),
    ]
}

/// The same plate for TL-HF (which has no `r_e`; the id keeps the MPS runs' pattern).
fn tl_plate_set(res: u32) -> Vec<String> {
    let mut set = plate_set(res, 2.1);
    set.retain(|s| !s.starts_with("re_over_l0="));
    set
}

fn frame_id(res: u32) -> String {
    format!("mps-plate-mps-r{res}-re2.1-frame")
}

fn frame_set(res: u32) -> Vec<String> {
    vec![
        format!("resolution={res}"),
        "re_over_l0=2.1".into(),
        "end_time=1.0".into(),
        "clamp=frame".into(),
    ]
}

fn static_id(res: u32) -> String {
    format!("mps-static-r{res}")
}

fn static_set(res: u32) -> Vec<String> {
    vec![format!("resolution={res}"), "end_time=2.0".into()]
}

/// The ring under 1 kPa against Lamé (r_out = 3 m, the case's radii).
const LAME_ID: &str = "mps-ring-lame-p1000-b3";

fn lame_set() -> Vec<String> {
    vec![
        "outer_radius=3".into(),
        "pressure=1000".into(),
        "damping=30".into(),
        "end_time=1.5".into(),
    ]
}

/// The paper's model on the paper's cases where it clumps: the 62 kPa ring and the slab (the
/// stabilisation study in `mps_stab` holds them, α = 0 here).
fn ring_id() -> String {
    crate::mps_stab::ring_id(0.0)
}

const SLAB_FULL_ID: &str = "mps-slab-r62-roller-a0";

const RINGS_ID: &str = "mps-colliding-rings";

/// Which runs to do.
#[derive(Clone, Copy, Debug)]
pub struct Selection {
    /// Re-run even when stored.
    pub force: bool,
    /// Include the slab at the paper's resolution (11,532 particles, ~3.5·10⁶ steps: hours)
    /// and the H/dp = 20 plate with the frame clamp.
    pub full: bool,
}

/// Runs (or loads) every MPS validation run of the selection.
pub fn run_all(sel: Selection) -> Result<(), CaseError> {
    let f = sel.force;
    for res in PLATE_RES {
        run_or_load(
            &plate_id("mps", res, 2.1),
            "cantilever-plate-2d",
            "mps",
            &plate_set(res, 2.1),
            f,
        )?;
    }
    for re in RES_RE {
        run_or_load(
            &plate_id("mps", 10, re),
            "cantilever-plate-2d",
            "mps",
            &plate_set(10, re),
            f,
        )?;
    }
    // The bearings' clamp: the paper's model with the held segment free between the bearings
    // (H/dp = 20 with --full: 5,118 particles, 5.7·10⁵ steps).
    let frame_res: &[u32] = if sel.full { &[10, 20] } else { &[10] };
    for &res in frame_res {
        run_or_load(
            &frame_id(res),
            "cantilever-plate-2d",
            "mps",
            &frame_set(res),
            f,
        )?;
    }
    for res in [10, 20] {
        run_or_load(
            &plate_id("tl-hf", res, 2.1),
            "cantilever-plate-2d",
            "tl-hf",
            &tl_plate_set(res),
            f,
        )?;
    }
    for res in STATIC_RES {
        run_or_load(
            &static_id(res),
            "static-cantilever-2d",
            "mps",
            &static_set(res),
            f,
        )?;
    }
    run_or_load(LAME_ID, "pressurised-ring-2d", "mps", &lame_set(), f)?;
    let fig = |name: &str| {
        crate::workspace_root()
            .join("docs")
            .join("validation")
            .join(name)
    };
    if sel.full {
        let png = fig("mps_slab_r62_frames.png");
        run_or_load_then(
            SLAB_FULL_ID,
            "slab-tension-2d",
            "mps",
            &[
                "resolution=62".into(),
                "end_time=1".into(),
                "snapshot_interval=0.05".into(),
                "grip=roller".into(),
            ],
            f,
            &|c| {
                let frames: Vec<Frame> = [0.1, 0.3, 0.5, 1.0]
                    .iter()
                    .filter_map(|&t| frame_at(c, t, "MPS slab"))
                    .collect();
                let vmax = p99_value(&frames);
                particle_frames(
                    &png,
                    "Slab in tension (von Mises)",
                    &frames,
                    1,
                    vmax,
                    0.01 / 62.0,
                )?;
                Ok(Default::default())
            },
        )?;
    }
    let png = fig("mps_rings_frames.png");
    let stale = load(RINGS_ID).is_some_and(|r| !crate::frames::has_moving_windows(&r));
    run_or_load_then(
        RINGS_ID,
        "colliding-rings-2d",
        "mps",
        &[
            "end_time=0.25".into(),
            "contact=true".into(),
            "snapshot_interval=0.005".into(),
        ],
        f || stale,
        &|c| {
            let frames: Vec<Frame> = [0.02, 0.03, 0.04, 0.06]
                .iter()
                .filter_map(|&t| frame_at(c, t, "MPS"))
                .collect();
            let vmax = p99_value(&frames);
            particle_frames(
                &png,
                "MPS colliding rings (von Mises)",
                &frames,
                4,
                vmax,
                0.001,
            )?;
            Ok(rings_roughness(c, 0.001))
        },
    )?;
    Ok(())
}

/// Effective bending stiffness of the MPS discretisation (why the static cantilever is soft at
/// coarse resolution): a lattice beam 0.16 × 0.02 m (H/dp = `res`) is given the exact
/// plane-strain pure-bending field of curvature κ (`u_x = −κ x y`, `u_y = κ (x² + ν' y²)/2`,
/// `ν' = ν/(1 − ν)`: `σ_xx = −E' κ y`, `σ_yy = 0`), and the MPS strain energy `Σ V ψ(F_i)` of the
/// particles away from the ends (x ∈ [0.04, 0.12], full WLS support along x) is divided by the
/// continuum value `½ E' I κ²` per unit length over the same length. A ratio below 1 is a
/// bending stiffness deficit; `1/ratio − 1` the tip-deflection excess it alone would cause.
pub fn bending_stiffness_ratio(res: u32, re_over_l0: f64) -> Result<f64, String> {
    bending_stiffness_ratio_with(res, re_over_l0, sph_mps::Fit::Linear)
}

/// [`bending_stiffness_ratio`] with the given WLS fit (the quadratic fit removes the surface
/// rows' deficit; what remains is the midpoint quadrature of `∫ y² dy` over the rows,
/// `1 − (dp/H)²`).
pub fn bending_stiffness_ratio_with(
    res: u32,
    re_over_l0: f64,
    fit: sph_mps::Fit,
) -> Result<f64, String> {
    use glam::DVec2;
    use sph_core::D2;
    use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
    use sph_materials::{ElasticConstants, Material, MaterialKind};
    let (l, h, e, nu) = (0.16, 0.02, 1e5, 0.3);
    let dp = h / res as f64;
    let shape = Aabb::<D2>::new(DVec2::new(0.0, -0.5 * h), DVec2::new(l, 0.5 * h))
        .map_err(|e| e.to_string())?;
    let lattice = Lattice::<D2>::new(dp, DVec2::new(0.0, -0.5 * h)).map_err(|e| e.to_string())?;
    let set = ParticleSet::fill(&lattice, &shape).map_err(|e| e.to_string())?;
    let c = ElasticConstants::from_youngs(e, nu, 1000.0).map_err(|e| e.to_string())?;
    let mat = MaterialKind::SaintVenantKirchhoff
        .build(c)
        .map_err(|e| e.to_string())?;
    let reference = set.positions().to_vec();
    let body = Body::<D2> {
        positions: reference.clone(),
        volumes: set.volumes().to_vec(),
        dp,
        velocities: Vec::new(),
        densities: Vec::new(),
    };
    let params = sph_mps::MpsParams {
        re_over_l0,
        fit,
        ..Default::default()
    };
    let mut solver = sph_mps::MpsSolver::new(body, mat, params).map_err(|e| e.to_string())?;
    let kappa = 1e-4 / h;
    let nup = nu / (1.0 - nu);
    let bent: Vec<DVec2> = reference
        .iter()
        .map(|x| {
            *x + DVec2::new(
                -kappa * x.x * x.y,
                0.5 * kappa * (x.x * x.x + nup * x.y * x.y),
            )
        })
        .collect();
    let zero = vec![DVec2::ZERO; bent.len()];
    solver
        .set_configuration(bent, zero)
        .map_err(|e| e.to_string())?;
    let (xa, xb) = (0.04, 0.12);
    let energy: f64 = reference
        .iter()
        .zip(solver.deformation_gradients())
        .zip(solver.volumes())
        .filter(|((x, _), _)| x.x > xa && x.x < xb)
        .map(|((_, &f), &v)| {
            v * Material::<D2>::strain_energy_density(solver.material(), f).unwrap_or(f64::NAN)
        })
        .sum();
    let e_plane = e / (1.0 - nu * nu);
    let continuum = 0.5 * e_plane * h.powi(3) / 12.0 * kappa * kappa * (xb - xa);
    Ok(energy / continuum)
}
