//! Benchmark case 7: a Palmaz–Schatz-like stent (TL paper §4.6, Fig. 19–21).
//!
//! # Geometry (procedural; the paper's CAD file is not available)
//! A slotted tube in its expanded state: a thin-walled tube of `length` L, outer `diameter` D
//! and `wall` thickness t whose wall keeps only a lattice of diamond cells. On the unrolled
//! mid-surface (arc length `s = r_mid θ`, axial `z ∈ [0, L]`) the cell corners (nodes) sit in
//! `cells_along + 1` rows `z_j = j L/cells_along`, row `j` holding `cells_around` nodes at
//! `θ = 2π (k + (j mod 2)/2)/cells_around`; every node is joined to the two nearest nodes of
//! the next row by a straight strut, so the struts zig-zag along the tube and enclose diamond
//! slots, the shape a Palmaz–Schatz slotted tube takes when expanded (a single segment, without
//! the bridge of the two-segment device). A wall particle belongs to the stent when its unrolled
//! distance to the nearest strut centre line is at most `strut_width/2`. The particles are
//! body-fitted (`sph_geometry::generate::tube_polar`: `wall/dp` layers across the wall, rings of
//! spacing ≈ dp, slices of thickness dp), `dp = wall/wall_layers` (the paper's dp = t/3).
//!
//! # Loading
//! - `point-forces`: two diametrically opposed forces `force` on the nodes at mid-length on the
//!   ±y sides (θ = 90°, 270°), pointing toward the axis, each spread evenly over the particles
//!   within `strut_width` of the node's outer-surface point (a single particle would receive an
//!   acceleration of ~10⁹ m/s²);
//! - `punches`: two rigid cuboids `punch_length × punch_size × punch_size` along z touching the
//!   outer surface at ±y and moving toward the axis at `punch_speed` (frictionless kinematic
//!   contact, `sph_core::tool`), each recording its reaction force.
//!
//! Snapshots every 0.02 ms by default (the paper shows 0.18 and 0.34 ms).

use crate::cases::tl_common::{material, run_tl, tl_params, TL_METHODS};
use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::{finite_or_null, RunOptions, RunRecord};
use crate::{Case, CaseInfo};
use glam::{DVec2, DVec3};
use serde_json::{json, Map, Value as Json};
use sph_core::error::Num;
use sph_core::tool::{RigidTool, ToolMotion, ToolShape};
use sph_core::Body;
use sph_core::{Field, Loads, Solver, TimeFunction, D3};
use sph_geometry::generate::{tube_polar, ParticleSet};
use sph_materials::MaterialKind;
use std::f64::consts::PI;

/// The stent.
pub struct Stent3d;

/// The stent pattern (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StentPattern {
    /// Outer radius.
    pub outer_radius: f64,
    /// Wall thickness.
    pub wall: f64,
    /// Length.
    pub length: f64,
    /// Diamond cells around the circumference.
    pub cells_around: usize,
    /// Diamond cells along the length.
    pub cells_along: usize,
    /// Strut width (on the unrolled mid-surface).
    pub strut_width: f64,
}

impl StentPattern {
    /// Radius of the wall's mid-surface.
    pub fn mid_radius(&self) -> f64 {
        self.outer_radius - 0.5 * self.wall
    }

    /// Node `k` of row `j`: `(θ, z)`.
    pub fn node(&self, j: usize, k: i64) -> (f64, f64) {
        let shift = if j % 2 == 1 { 0.5 } else { 0.0 };
        (
            2.0 * PI * (k as f64 + shift) / self.cells_around as f64,
            j as f64 * self.length / self.cells_along as f64,
        )
    }

    /// Unrolled distance from `(θ, z)` (z measured from the tube's start) to the nearest strut
    /// centre line.
    pub fn strut_distance(&self, theta: f64, z: f64) -> f64 {
        let rm = self.mid_radius();
        let dz = self.length / self.cells_along as f64;
        let band = (z / dz).floor().clamp(0.0, (self.cells_along - 1) as f64) as usize;
        let mut best = f64::INFINITY;
        // The struts of this band and its neighbours (a strut half-width is below a band).
        for j in band.saturating_sub(1)..=(band + 1).min(self.cells_along - 1) {
            for k in 0..self.cells_around as i64 {
                let (t0, z0) = self.node(j, k);
                for side in [-0.5, 0.5] {
                    let t1 = t0 + side * 2.0 * PI / self.cells_around as f64;
                    let z1 = z0 + dz;
                    // Unrolled coordinates relative to node (t0, z0), θ wrapped to (−π, π].
                    let wrap = |a: f64| (a + PI).rem_euclid(2.0 * PI) - PI;
                    let p = DVec2::new(rm * wrap(theta - t0), z - z0);
                    let d = DVec2::new(rm * (t1 - t0), z1 - z0);
                    let s = (p.dot(d) / d.length_squared()).clamp(0.0, 1.0);
                    best = best.min((p - d * s).length());
                }
            }
        }
        best
    }

    /// The stent's particles (tube_polar wall with `layers` layers, masked by the struts),
    /// the tube running along z from `z = 0` to `length`, and `dp`.
    pub fn particles(&self, layers: usize) -> Result<(ParticleSet<D3>, f64), CaseError> {
        let dp = self.wall / layers as f64;
        let mut set = tube_polar(
            DVec3::ZERO,
            DVec3::Z,
            self.outer_radius - self.wall,
            self.outer_radius,
            self.length,
            dp,
        )?;
        let half = 0.5 * self.strut_width;
        set.retain(|_, x| self.strut_distance(x.y.atan2(x.x), x.z) <= half);
        Ok((set, dp))
    }
}

impl Case for Stent3d {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "stent-3d",
            description:
                "Palmaz–Schatz-like diamond-cell stent under point forces or punches (TL §4.6)",
            methods: TL_METHODS,
        }
    }

    fn params(&self) -> Params {
        let mut specs = vec![
            Param::float("length", 20e-3, Range::Positive, "stent length L (m)"),
            Param::float("diameter", 10e-3, Range::Positive, "outer diameter D (m)"),
            Param::float("wall", 0.1e-3, Range::Positive, "wall thickness t (m)"),
            Param::int(
                "wall_layers",
                3,
                Range::Closed(1.0, 12.0),
                "particle layers across the wall (dp = wall/wall_layers; the paper's 3)",
            ),
            Param::int(
                "cells_around",
                12,
                Range::Closed(3.0, 200.0),
                "diamond cells around",
            ),
            Param::int(
                "cells_along",
                8,
                Range::Closed(1.0, 200.0),
                "diamond cells along",
            ),
            Param::float("strut_width", 0.2e-3, Range::Positive, "strut width (m)"),
            Param::choice(
                "loading",
                "point-forces",
                &["point-forces", "punches"],
                "two opposite point forces at mid-length, or two rigid punches along the stent",
            ),
            Param::float("force", 0.1, Range::Positive, "each point force (N)"),
            Param::float(
                "punch_speed",
                0.1,
                Range::Positive,
                "speed of each punch (m/s)",
            ),
            Param::float(
                "punch_size",
                0.15e-3,
                Range::Positive,
                "punch cross-section side (m)",
            ),
            Param::float(
                "punch_length",
                20e-3,
                Range::Positive,
                "punch length along z (m)",
            ),
            Param::float("end_time", 0.34e-3, Range::Positive, "simulated time (s)"),
            Param::float("density", 1100.0, Range::Positive, "ρ0 (kg/m³)"),
            Param::float("youngs_modulus", 17e6, Range::Positive, "E (Pa)"),
            Param::float("nu", 0.45, Range::Open(-1.0, 0.5), "Poisson's ratio"),
            Param::choice(
                "material",
                "neo-hookean",
                &["neo-hookean", "linear-elastic", "kirchhoff-vol-dev"],
                "constitutive law (the paper's: neo-Hookean)",
            ),
        ];
        specs.extend(tl_params());
        let mut p = Params::new("stent-3d", specs);
        p.set_text("snapshot_interval", "2e-5")
            .expect("valid default");
        p.set_text("probe_interval", "2e-6").expect("valid default");
        p
    }

    fn run(
        &self,
        method: &str,
        p: &Params,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), CaseError> {
        let pattern = StentPattern {
            outer_radius: 0.5 * p.f64("diameter"),
            wall: p.f64("wall"),
            length: p.f64("length"),
            cells_around: p.int("cells_around") as usize,
            cells_along: p.int("cells_along") as usize,
            strut_width: p.f64("strut_width"),
        };
        if pattern.wall >= pattern.outer_radius {
            return Err(CaseError::InvalidValue {
                key: "wall".into(),
                value: Num(pattern.wall).to_string(),
                allowed: format!("0 < wall < diameter/2 = {}", Num(pattern.outer_radius)),
            });
        }
        // The point forces and punches act at the mid-length nodes on the ±y sides: nodes sit
        // there only for an even number of cells along and a multiple of 4 around.
        if !pattern.cells_along.is_multiple_of(2) {
            return Err(CaseError::InvalidValue {
                key: "cells_along".into(),
                value: pattern.cells_along.to_string(),
                allowed: "an even number (the loads act at the nodes at mid-length)".into(),
            });
        }
        if !pattern.cells_around.is_multiple_of(4) {
            return Err(CaseError::InvalidValue {
                key: "cells_around".into(),
                value: pattern.cells_around.to_string(),
                allowed: "a multiple of 4 (the loads act at the nodes on the ±y sides)".into(),
            });
        }
        let layers = p.int("wall_layers") as usize;
        let dp = pattern.wall / layers as f64;
        if pattern.strut_width < 2.0 * dp {
            return Err(CaseError::InvalidValue {
                key: "strut_width".into(),
                value: Num(pattern.strut_width).to_string(),
                allowed: format!("at least 2 dp = 2 wall/wall_layers = {}", Num(2.0 * dp)),
            });
        }
        let (rho, e, nu) = (p.f64("density"), p.f64("youngs_modulus"), p.f64("nu"));
        let kind: MaterialKind = p.text("material").parse()?;
        let mat = material(kind, e, nu, rho)?;
        let (set, dp) = pattern.particles(layers)?;
        let n = set.len();
        let x0 = set.positions().to_vec();
        let r_out = pattern.outer_radius;
        let z_mid = 0.5 * pattern.length;
        // The loaded regions: within a strut width of the mid-length nodes' outer surface points
        // on the ±y sides.
        let near = |side: f64| -> Vec<u32> {
            let c = DVec3::new(0.0, side * r_out, z_mid);
            (0..n as u32)
                .filter(|&i| (x0[i as usize] - c).length() <= pattern.strut_width)
                .collect()
        };
        let (plus, minus) = (near(1.0), near(-1.0));
        if plus.is_empty() || minus.is_empty() {
            return Err(CaseError::Config(format!(
                "stent-3d: no particle within strut_width = {} m of the mid-length nodes' outer \
                 points at ±y (particle spacing {} m): widen the struts or add wall_layers",
                Num(pattern.strut_width),
                Num(dp)
            )));
        }
        let loading = p.text("loading").to_string();
        let mut loads = Loads::<D3>::new();
        let mut tools = Vec::new();
        if loading == "point-forces" {
            let f = p.f64("force");
            for (region, dir) in [(&plus, -1.0), (&minus, 1.0)] {
                let share = DVec3::new(0.0, dir * f / region.len() as f64, 0.0);
                for &i in region {
                    loads.add_point_force(i, TimeFunction::constant(share));
                }
            }
        } else {
            let (a, len) = (p.f64("punch_size"), p.f64("punch_length"));
            let speed = p.f64("punch_speed");
            let ramp = 0.05 * p.f64("end_time");
            for (name, side) in [("punch_top", 1.0), ("punch_bottom", -1.0)] {
                let y0 = side * r_out;
                let (ylo, yhi) = if side > 0.0 {
                    (y0, y0 + a)
                } else {
                    (y0 - a, y0)
                };
                let shape = ToolShape::cuboid(
                    DVec3::new(-0.5 * a, ylo, z_mid - 0.5 * len),
                    DVec3::new(0.5 * a, yhi, z_mid + 0.5 * len),
                )?;
                let motion =
                    ToolMotion::new(DVec3::new(0.0, -side, 0.0), speed, ramp, f64::INFINITY)?;
                tools.push(RigidTool::new(name, shape, motion));
            }
        }
        let body = Body::<D3> {
            positions: x0.clone(),
            volumes: set.volumes().to_vec(),
            dp,
            velocities: Vec::new(),
            densities: Vec::new(),
        };
        let interval = p.f64("probe_interval");
        let summarise = move |s: &dyn Solver<D3>, _: &RunRecord| {
            let mut m = stent_summary(s, &pattern, &plus, &minus);
            m.insert("particle_spacing".into(), json!(dp));
            m.insert("loading".into(), json!(loading));
            m
        };
        run_tl(
            "stent-3d",
            method,
            p,
            body,
            mat,
            |s| {
                Ok(s.with_loads(loads)
                    .with_tools(tools)?
                    .with_probes(Vec::new(), interval)?)
            },
            p.f64("end_time"),
            options,
            summarise,
        )
    }
}

/// The stent's figures: the diameter along the loading axis (distance between the mean
/// positions of the two loaded regions, relative change), and where the final disorder is
/// largest (the particle's reference angle and axial position, and its distance to the
/// nearest strut node in strut widths: below 1 means at a junction).
pub fn stent_summary(
    s: &dyn Solver<D3>,
    pattern: &StentPattern,
    plus: &[u32],
    minus: &[u32],
) -> Map<String, Json> {
    let mut m = Map::new();
    let (reference, _) = crate::cases::quasi_static::reference_and_deformation::<D3>(s);
    let mean = |x: &[DVec3], set: &[u32]| {
        set.iter().map(|&i| x[i as usize]).sum::<DVec3>() / set.len() as f64
    };
    let d0 = mean(&reference, plus).y - mean(&reference, minus).y;
    let d = mean(s.positions(), plus).y - mean(s.positions(), minus).y;
    m.insert("loaded_diameter_initial".into(), finite_or_null(d0));
    m.insert("loaded_diameter".into(), finite_or_null(d));
    m.insert("diameter_change".into(), finite_or_null(d / d0 - 1.0));
    if let Some(Field::Scalar(dis)) = s.field("disorder") {
        if let Some((i, &worst)) = dis
            .iter()
            .enumerate()
            .filter(|(_, v)| v.is_finite())
            .max_by(|a, b| a.1.total_cmp(b.1))
        {
            let x0 = reference[i];
            let theta = x0.y.atan2(x0.x);
            let mut node_dist = f64::INFINITY;
            for j in 0..=pattern.cells_along {
                for k in 0..pattern.cells_around as i64 {
                    let (t, z) = pattern.node(j, k);
                    let dt = ((theta - t + PI).rem_euclid(2.0 * PI) - PI) * pattern.mid_radius();
                    node_dist = node_dist.min(DVec2::new(dt, x0.z - z).length());
                }
            }
            m.insert("final_max_disorder".into(), finite_or_null(worst));
            m.insert(
                "final_max_disorder_at".into(),
                json!({
                    "theta_deg": theta.to_degrees(),
                    "z": x0.z,
                    "node_distance_over_strut_width": node_dist / pattern.strut_width,
                }),
            );
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pattern() -> StentPattern {
        StentPattern {
            outer_radius: 5e-3,
            wall: 0.1e-3,
            length: 20e-3,
            cells_around: 12,
            cells_along: 8,
            strut_width: 0.2e-3,
        }
    }

    #[test]
    fn nodes_and_strut_centre_lines_are_at_distance_zero_and_slots_are_empty() {
        let p = pattern();
        for j in 0..=p.cells_along {
            for k in 0..p.cells_around as i64 {
                let (t, z) = p.node(j, k);
                assert!(p.strut_distance(t, z) < 1e-12, "node {j},{k}");
            }
        }
        // Mid-point of a strut.
        let (t0, z0) = p.node(2, 3);
        let (t1, z1) = (t0 + PI / 12.0, z0 + 2.5e-3);
        assert!(p.strut_distance(0.5 * (t0 + t1), 0.5 * (z0 + z1)) < 1e-12);
        // The centre of a diamond slot (between two nodes of a row, half a band up) is far
        // from every strut: at least a quarter of the smaller cell dimension.
        let (ta, za) = p.node(2, 3);
        let centre = (ta + PI / 12.0, za);
        let d = p.strut_distance(centre.0, centre.1 + 1e-9);
        assert!(d > 0.5e-3, "{d}");
        // Periodic in θ.
        assert!(
            (p.strut_distance(0.1, 7e-3) - p.strut_distance(0.1 + 2.0 * PI, 7e-3)).abs() < 1e-15
        );
    }

    #[test]
    fn a_coarse_stent_has_the_struts_volume() {
        let p = StentPattern {
            wall: 0.2e-3,
            strut_width: 0.4e-3,
            length: 10e-3,
            cells_along: 4,
            ..pattern()
        };
        let (set, dp) = p.particles(2).unwrap();
        // Expected: total strut length × width × wall (joints overlap: a few % less).
        let dz = p.length / p.cells_along as f64;
        let ds = p.mid_radius() * PI / p.cells_around as f64;
        let strut = (dz * dz + ds * ds).sqrt();
        let expected =
            2.0 * (p.cells_around * p.cells_along) as f64 * strut * p.strut_width * p.wall;
        let got = set.total_volume();
        // Tolerance: the lattice resolves the strut width to ±dp, and nodes overlap (≤ 10 %).
        assert!(
            (got / expected - 1.0).abs() < 0.15,
            "{got} vs {expected}, dp {dp}"
        );
        assert!(set.positions().iter().all(|x| {
            let r = (x.x * x.x + x.y * x.y).sqrt();
            r > p.outer_radius - p.wall && r < p.outer_radius
        }));
    }
}
