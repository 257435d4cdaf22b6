//! Benchmark case 5: the bending column (TL paper §4.4, Fig. 9–12).
//!
//! A neo-Hookean column of cross-section H × H and length L along z, clamped at its bottom:
//! `clamp_layers` extra layers of particles below z = 0 are held fixed (they are not counted in
//! the paper's 1,296 / 10,368 / 82,944 particles, which are the column's own). Initial uniform
//! velocity `v0 = velocity (√3/2, 1/2, 0)` on the column. Point S is the top corner (H, H, L),
//! interpolated (Shepard) from the particles around it.

use crate::analysis::{extremes, mean_period};
use crate::cases::tl_common::{material, run_tl, tl_params, TL_METHODS};
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
use sph_materials::MaterialKind;

/// The bending column.
pub struct BendingColumn3d;

/// The column's particles (cross-section `h`, length `l`, `resolution = h/dp`) plus
/// `clamp_layers` layers below z = 0 tagged `clamp`.
pub fn column_particles(
    h: f64,
    l: f64,
    resolution: i64,
    clamp_layers: i64,
) -> Result<(ParticleSet<D3>, f64), CaseError> {
    let dp = h / resolution as f64;
    let nz = (l / dp).round();
    if (nz * dp - l).abs() > 1e-9 * l {
        return Err(CaseError::InvalidValue {
            key: "length".into(),
            value: Num(l).to_string(),
            allowed: format!("a whole multiple of dp = H/resolution = {}", Num(dp)),
        });
    }
    let below = clamp_layers as f64 * dp;
    let shape = Aabb::<D3>::new(DVec3::new(0.0, 0.0, -below), DVec3::new(h, h, l))?;
    let lattice = Lattice::<D3>::new(dp, DVec3::new(0.0, 0.0, -below))?;
    let mut set = ParticleSet::fill(&lattice, &shape)?;
    set.tag_where("clamp", |_, x| x.z < 0.0)?;
    Ok((set, dp))
}

/// Column keys shared by the bending and twisting cases.
pub fn column_params(resolution: i64, nu: f64, end_time: f64) -> Vec<Param> {
    vec![
        Param::float("cross_section", 1.0, Range::Positive, "H (m)"),
        Param::float("length", 6.0, Range::Positive, "L (m)"),
        Param::int("resolution", resolution, Range::Closed(2.0, 200.0), "H/dp"),
        Param::int(
            "clamp_layers",
            3,
            Range::Closed(1.0, 10.0),
            "fixed layers below z = 0",
        ),
        Param::float("nu", nu, Range::Open(-1.0, 0.5), "Poisson's ratio"),
        Param::float("youngs_modulus", 17e6, Range::Positive, "E (Pa)"),
        Param::float("density", 1100.0, Range::Positive, "ρ0 (kg/m³)"),
        Param::float("end_time", end_time, Range::Positive, "simulated time (s)"),
        Param::choice(
            "material",
            "neo-hookean",
            &["neo-hookean", "linear-elastic", "kirchhoff-vol-dev"],
            "constitutive law (TL paper: neo-Hookean; tl-hf: the HF law of TL eq. 10–14)",
        ),
    ]
}

impl Case for BendingColumn3d {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "bending-column-3d",
            description: "neo-Hookean column, clamped bottom, uniform initial velocity (TL §4.4)",
            methods: TL_METHODS,
        }
    }

    fn params(&self) -> Params {
        let mut specs = column_params(6, 0.45, 3.0);
        specs.push(Param::float(
            "velocity",
            10.0,
            Range::NonNegative,
            "|v0| (m/s)",
        ));
        specs.extend(tl_params());
        let mut p = Params::new("bending-column-3d", specs);
        p.set_text("probe_interval", "1e-3").expect("valid default");
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
        let dir = DVec3::new(3f64.sqrt() / 2.0, 0.5, 0.0);
        let v0 = dir * p.f64("velocity");
        let s_point = DVec3::new(h, h, l);
        run_column(
            "bending-column-3d",
            method,
            p,
            options,
            |_| v0,
            ("S", s_point),
            move |s, _| column_summary(s, s_point, dir),
        )
    }
}

/// Builds the clamped column of the column cases (material, particles, clamp, one point probe)
/// with the initial velocity `velocity(x)` on the column (zero in the clamp) and runs it with a
/// TL method.
pub fn run_column(
    case: &str,
    method: &str,
    p: &Params,
    options: &RunOptions,
    velocity: impl Fn(DVec3) -> DVec3,
    (probe_name, probe_at): (&str, DVec3),
    summarise: impl FnOnce(&dyn Solver<D3>, &RunRecord) -> Map<String, Json>,
) -> Result<(RunRecord, Map<String, Json>), CaseError> {
    let (h, l) = (p.f64("cross_section"), p.f64("length"));
    let kind: MaterialKind = p.text("material").parse()?;
    let mat = material(kind, p.f64("youngs_modulus"), p.f64("nu"), p.f64("density"))?;
    let (set, dp) = column_particles(h, l, p.int("resolution"), p.int("clamp_layers"))?;
    let velocities = set
        .positions()
        .iter()
        .map(|&x| if x.z > 0.0 { velocity(x) } else { DVec3::ZERO })
        .collect();
    let clamp = set.tagged("clamp")?;
    let body = Body::<D3> {
        positions: set.positions().to_vec(),
        volumes: set.volumes().to_vec(),
        dp,
        velocities,
        densities: Vec::new(),
    };
    let interval = p.f64("probe_interval");
    run_tl(
        case,
        method,
        p,
        body,
        mat,
        |s| {
            let n = s.len();
            let mut c = Constraints::new();
            c.push(Constraint::Fixed { particles: clamp }, n)?;
            let probe = Probe::point(
                probe_name,
                probe_at,
                s.reference_positions(),
                s.volumes(),
                s.kernel(),
            )?;
            Ok(s.with_constraints(c).with_probes(vec![probe], interval)?)
        },
        p.f64("end_time"),
        options,
        summarise,
    )
}

/// Extremes of point S's coordinates, and the bending period from its displacement along the
/// initial velocity direction (mean over full periods).
pub fn column_summary(s: &dyn Solver<D3>, s_point: DVec3, dir: DVec3) -> Map<String, Json> {
    let mut m = Map::new();
    if let Some(p) = s.probes().first() {
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            let c: Vec<f64> = p.positions.iter().map(|x| x[k]).collect();
            let (lo, hi) = extremes(&c);
            m.insert(format!("s_{axis}_min"), finite_or_null(lo));
            m.insert(format!("s_{axis}_max"), finite_or_null(hi));
        }
        let along: Vec<f64> = p
            .positions
            .iter()
            .map(|&x| (x - s_point).dot(dir))
            .collect();
        m.insert(
            "period".into(),
            mean_period(&p.times, &along, 0.0).map_or(Json::Null, finite_or_null),
        );
        m.insert("s_reference".into(), json!(s_point.to_array()));
    }
    m
}
