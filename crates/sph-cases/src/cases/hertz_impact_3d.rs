//! A verification of body–body contact (not in the papers): two identical solid elastic spheres
//! colliding head-on, or one sphere hitting a rigid wall, far below the sound speed, compared
//! with Hertz's quasi-static impact theory ([`hertz_impact`]).
//!
//! Methods: the UL family (`ul-enog`, `ul-og`, `ul-oas`, `ul-gnog`) and the TL family (`tl-hf`,
//! `tl`, `tl-gm`): the first contact problem both families run. UL: one [`sph_ul::UlSolver`]
//! whose bodies meet through its contact pressure ([`sph_ul::contact`]); TL: one
//! [`sph_tl::TlSolver`] split into bodies ([`sph_tl::TlSolver::with_bodies`]: each sphere its
//! own reference configuration) that meet through TL's contact ([`sph_tl::contact`], the same
//! contact-density law). `contact_stiffness` is the scale `κ` of either: 1 for UL, TL's
//! measured [`sph_tl::DEFAULT_CONTACT_SCALE`] = 2 for TL unless set ([`Case::params_for`]).
//! Each family's numerical keys are refused with the other family's methods.
//!
//! Spheres of radius `radius`, each moving at `velocity` toward the other along x (or the one
//! sphere toward the wall), linear elastic (`E`, `ν`, `ρ`; TL: Saint Venant–Kirchhoff, the same
//! law at these strains), `dp = radius/resolution`. The
//! initial gap between the surfaces is `dp/2` (the surface particles sit `dp/2` inside the
//! surfaces, so they start `1.5 dp` apart — the contact density counts only pairs closer than
//! `dp` — and touch after a short flight). `layout = layers` (default, chosen by measurement:
//! docs/validation.md) builds the spheres from concentric spherical layers
//! (`hollow_sphere_polar`, poles on z, away from the contact on the x axis), the right sphere the
//! mirror image of the left; `lattice` cuts them from a cubic lattice whose cell faces pass
//! through the centres; `mesh` fits them to a UV-sphere triangle mesh ([`mesh_sphere`]), the
//! right sphere again the mirror image. The wall is a fixed body (every particle `Fixed`), a lattice slab
//! `x ∈ [0, 3 dp]` (thicker than UL's kernel support 2.6 dp, TL's 2.3 dp) of `1.2 radius`
//! square, meeting the sphere through the same contact as a second sphere would (for TL too: a
//! fixed TL body, not a rigid tool, so both families meet the wall through their body contact).
//! `target = tool` is the rigid wall as a half-space tool `x ≥ 0` ([`sph_core::tool`], named
//! `wall`): its kinematic contact stops a particle's approach at `dp/2` from the plane, with no
//! contact layer of its own (the contact time and force then come from the tool's recorded
//! reaction; `contact_stiffness` has nothing to scale and must keep its default).
//!
//! Summary: `contact_time` (the first contact's duration, from the recorded contact force:
//! exactly zero while no pair interacts, sampled every `t_c/400`), `max_force` (largest contact
//! force along x), `restitution` (rebound speed / impact speed of the left sphere's centre of
//! mass at the end), `energy_change` (kinetic + elastic + contact energy at the end over the
//! initial kinetic energy, − 1: the energy the impact lost; UL: its budget's stored terms, TL:
//! kinetic + strain + contact energy of the last monitor sample), `momentum_change` (two
//! spheres: |total momentum| at the end over one sphere's `m v`; null on the wall, which takes
//! momentum), beside the theory's
//! `contact_time_theory`, `max_force_theory`, `max_compression_theory`, and `velocity_over_c0`.
//! The end time (key `end_time`, 0 = automatic) is the flight to contact plus `2 t_c`.

use crate::cases::impact_common::{
    body_velocities, contact_param, contact_summary, tool_contact_summary,
};
use crate::cases::tl_common::{material, run_tl, tl_params, TL_METHODS};
use crate::cases::ul_common::{run_ul, ul_params};
use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::{finite_or_null, RunOptions, RunRecord};
use crate::{Case, CaseInfo};
use glam::DVec3;
use serde_json::{json, Map, Value as Json};
use sph_core::tool::{RigidTool, ToolMotion, ToolShape};
use sph_core::{Constraint, Constraints, Solver, D3};
use sph_geometry::fit::{fit, FitOptions};
use sph_geometry::generate::{hollow_sphere, hollow_sphere_polar, Aabb, Lattice, ParticleSet};
use sph_geometry::mesh::{MeshSolid, TriMesh};
use sph_materials::{Material, MaterialKind};

/// The Hertz impact.
pub struct HertzImpact3d;

/// The methods of the Hertz impact: UL's and TL's (the first contact problem both families
/// run: docs/validation.md).
pub const HERTZ_METHODS: &[&str] = &[
    "ul-enog", "ul-og", "ul-oas", "ul-gnog", "tl-hf", "tl", "tl-gm",
];

/// What a sphere hits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HertzTarget {
    /// An identical sphere moving toward it at the same speed.
    Sphere,
    /// A rigid, frictionless wall.
    Wall,
}

/// Hertz's quasi-static impact: contact time, largest mutual approach and peak force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HertzImpact {
    /// Duration of the contact `t_c`.
    pub contact_time: f64,
    /// Largest mutual approach of the centres `δ_max` (sphere on wall: of centre and wall).
    pub max_compression: f64,
    /// Peak contact force `F_max`.
    pub max_force: f64,
}

/// The reduced radius, mass, modulus and the relative speed `(R*, m*, E*, v_rel)` of
/// [`hertz_impact`].
fn reduced(
    target: HertzTarget,
    radius: f64,
    mass: f64,
    youngs: f64,
    nu: f64,
    velocity: f64,
) -> (f64, f64, f64, f64) {
    let e_prime = youngs / (1.0 - nu * nu);
    match target {
        HertzTarget::Sphere => (0.5 * radius, 0.5 * mass, 0.5 * e_prime, 2.0 * velocity),
        HertzTarget::Wall => (radius, mass, e_prime, velocity),
    }
}

/// Hertz's impact of an elastic sphere (radius `R`, mass `m`, Young's modulus `E`, Poisson's
/// ratio `ν`) moving at `v` toward `target` (Johnson, *Contact Mechanics*, 1985, §11.4;
/// docs/methods.md "Contact, rigid tools and impacts"), valid for `v ≪ c0` (quasi-static contact):
///
/// `t_c = 2.87 (m*² / (R* E*² v_rel))^(1/5)`, `δ_max = (15 m* v_rel² / (16 E* √R*))^(2/5)`,
/// `F_max = (4/3) E* √R* δ_max^(3/2)`,
///
/// with, for two identical spheres each at `v` toward the other, `R* = R/2`, `m* = m/2`,
/// `E* = E/(2(1 − ν²))`, `v_rel = 2v`; for a sphere on a rigid wall (`1/E* = (1 − ν²)/E +
/// 0`) `R* = R`, `m* = m`, `E* = E/(1 − ν²)`, `v_rel = v`. The two give the same `t_c` and
/// `F_max` (the wall is the symmetry plane of the two-sphere impact) and `δ_max` halves.
pub fn hertz_impact(
    target: HertzTarget,
    radius: f64,
    mass: f64,
    youngs: f64,
    nu: f64,
    velocity: f64,
) -> HertzImpact {
    let (r, m, e, v) = reduced(target, radius, mass, youngs, nu, velocity);
    let contact_time = 2.87 * (m * m / (r * e * e * v)).powf(0.2);
    let max_compression = (15.0 * m * v * v / (16.0 * e * r.sqrt())).powf(0.4);
    let max_force = 4.0 / 3.0 * e * r.sqrt() * max_compression.powf(1.5);
    HertzImpact {
        contact_time,
        max_compression,
        max_force,
    }
}

/// The Hertz contact force over time, `F(t)` for `t ∈ [0, t_c]` in `samples` steps: the
/// solution of `m* δ̈ = −(4/3) E* √R* δ^(3/2)` from `δ = 0`, `δ̇ = v_rel` (the equation
/// [`hertz_impact`] solves in closed form for `t_c`, `δ_max`, `F_max`), by classical
/// Runge–Kutta with 100 steps per output interval `t_c / samples`; the returned points are
/// `(t, F)`, ending when `δ` returns to 0.
pub fn hertz_force_history(
    target: HertzTarget,
    radius: f64,
    mass: f64,
    youngs: f64,
    nu: f64,
    velocity: f64,
    samples: usize,
) -> Vec<(f64, f64)> {
    let (r, m, e, v) = reduced(target, radius, mass, youngs, nu, velocity);
    let stiffness = 4.0 / 3.0 * e * r.sqrt();
    let force = |d: f64| stiffness * d.max(0.0).powf(1.5);
    let t_c = hertz_impact(target, radius, mass, youngs, nu, velocity).contact_time;
    let refine = 100;
    let h = t_c / (samples.max(1) * refine) as f64;
    let (mut d, mut u, mut t) = (0.0f64, v, 0.0);
    let mut out = vec![(0.0, 0.0)];
    let mut k = 0usize;
    while d >= 0.0 && k < 2 * samples * refine {
        let acc = |d: f64| -force(d) / m;
        let (k1d, k1u) = (u, acc(d));
        let (k2d, k2u) = (u + 0.5 * h * k1u, acc(d + 0.5 * h * k1d));
        let (k3d, k3u) = (u + 0.5 * h * k2u, acc(d + 0.5 * h * k2d));
        let (k4d, k4u) = (u + h * k3u, acc(d + h * k3d));
        d += h / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
        u += h / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u);
        t += h;
        k += 1;
        if k.is_multiple_of(refine) || d < 0.0 {
            out.push((t, force(d)));
        }
    }
    out
}

/// Segments (around and, halved, pole to pole) of the UV-sphere mesh of `layout = mesh`: its
/// largest distance from the exact sphere, `R (1 − cos(√2 π/n))` (at the triangles'
/// circumcentres), is 6.0e-4 R: 0.6 % of `dp` at R/dp = 10, 1.2 % at 20.
pub const MESH_SEGMENTS: usize = 128;

/// The particles of a sphere body-fitted to a UV-sphere triangle mesh ([`TriMesh::uv_sphere`],
/// [`MESH_SEGMENTS`] segments) at spacing `dp` with the default relaxation
/// ([`sph_geometry::fit::fit`]): what a user importing the sphere as an STL file gets.
pub fn mesh_sphere(centre: DVec3, radius: f64, dp: f64) -> Result<ParticleSet<D3>, CaseError> {
    let mesh = TriMesh::uv_sphere(centre, radius, MESH_SEGMENTS);
    let solid = MeshSolid::new(mesh, "uv-sphere")?;
    let (set, _) = fit(&solid, dp, &FitOptions::default())?;
    Ok(set)
}

impl Case for HertzImpact3d {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "hertz-impact-3d",
            description:
                "two solid elastic spheres (or sphere on a rigid wall) against Hertz theory",
            methods: HERTZ_METHODS,
        }
    }

    /// TL methods get TL's measured contact scale `contact_stiffness` =
    /// [`sph_tl::DEFAULT_CONTACT_SCALE`] (UL's is 1).
    fn params_for(&self, method: &str) -> Params {
        let mut p = self.params();
        if TL_METHODS.contains(&method) {
            p.set_text(
                "contact_stiffness",
                &sph_tl::DEFAULT_CONTACT_SCALE.to_string(),
            )
            .expect("a positive contact scale");
        }
        p
    }

    fn params(&self) -> Params {
        let mut specs = vec![
            Param::float("radius", 0.05, Range::Positive, "sphere radius R (m)"),
            Param::float(
                "velocity",
                1.0,
                Range::Positive,
                "speed of each sphere toward the other (or toward the wall) (m/s)",
            ),
            Param::float("youngs_modulus", 1e7, Range::Positive, "E (Pa)"),
            Param::float("nu", 0.4, Range::Open(-1.0, 0.5), "Poisson's ratio"),
            Param::float("density", 1200.0, Range::Positive, "ρ0 (kg/m³)"),
            Param::int("resolution", 10, Range::Closed(3.0, 100.0), "R/dp"),
            Param::choice(
                "target",
                "sphere",
                &["sphere", "wall", "tool"],
                "what the sphere hits: an identical sphere, a rigid wall of fixed particles \
                 (`wall`) or a rigid half-space tool (`tool`)",
            ),
            Param::choice(
                "layout",
                "layers",
                &["layers", "lattice", "mesh"],
                "particles of the spheres: `layers` = concentric spherical layers on Fibonacci \
                 lattices (sph_geometry::generate::hollow_sphere_polar, smooth surface), \
                 `lattice` = cut from a cubic lattice (staircase surface), `mesh` = body-fitted \
                 to a UV-sphere triangle mesh of 128 segments (sph_geometry::fit, \
                 default relaxation: the surface layer dp/2 inside the mesh)",
            ),
            contact_param(),
            Param::float(
                "end_time",
                0.0,
                Range::NonNegative,
                "simulated time (s); 0: flight to contact + 2 t_c of Hertz",
            ),
        ];
        specs.extend(crate::runner::output_params());
        // Both families' numerical keys (each marked with its methods); the output keys once.
        for param in ul_params().into_iter().chain(tl_params()) {
            if !specs.iter().any(|p| p.key == param.key) {
                specs.push(param);
            }
        }
        Params::new("hertz-impact-3d", specs)
    }

    fn run(
        &self,
        method: &str,
        p: &Params,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), CaseError> {
        let (radius, v, e, nu, rho) = (
            p.f64("radius"),
            p.f64("velocity"),
            p.f64("youngs_modulus"),
            p.f64("nu"),
            p.f64("density"),
        );
        let dp = radius / p.int("resolution") as f64;
        // The rigid half-space tool: the theory's wall, met through the tools' contact.
        let tool = p.text("target") == "tool";
        let target = if p.text("target") == "sphere" {
            HertzTarget::Sphere
        } else {
            HertzTarget::Wall
        };
        let mat = material(MaterialKind::LinearElastic, e, nu, rho)?;
        let constants = *Material::<D3>::constants(&mat);
        let gap = 0.5 * dp;
        // Left sphere: its surface gap/2 left of x = 0 (sphere target) or gap left of the wall.
        let offset = if target == HertzTarget::Sphere {
            0.5 * gap
        } else {
            gap
        };
        let centre = DVec3::new(-(radius + offset), 0.0, 0.0);
        let left = match p.text("layout") {
            "lattice" => hollow_sphere(centre, 0.0, radius, dp)?,
            "mesh" => mesh_sphere(centre, radius, dp)?,
            _ => hollow_sphere_polar(centre, 0.0, radius, dp)?,
        };
        let nl = left.len();
        let mut set = left.clone();
        let mut constraints = Constraints::new();
        let second = match target {
            HertzTarget::Wall if tool => ParticleSet::from_parts(Vec::new(), Vec::new())?,
            HertzTarget::Sphere => {
                let mirrored: Vec<DVec3> = left
                    .positions()
                    .iter()
                    .map(|x| DVec3::new(-x.x, x.y, x.z))
                    .collect();
                ParticleSet::from_parts(mirrored, left.volumes().to_vec())?
            }
            HertzTarget::Wall => {
                let half = 0.6 * radius;
                let slab = Aabb::<D3>::new(
                    DVec3::new(0.0, -half, -half),
                    DVec3::new(3.0 * dp, half, half),
                )?;
                ParticleSet::fill(&Lattice::<D3>::new(dp, DVec3::ZERO)?, &slab)?
            }
        };
        set.extend(&second)?;
        let n = set.len();
        if target == HertzTarget::Wall && !tool {
            constraints.push(
                Constraint::Fixed {
                    particles: (nl as u32..n as u32).collect(),
                },
                n,
            )?;
        }
        let body_of: Vec<u32> = (0..n).map(|i| u32::from(i >= nl)).collect();
        let velocities: Vec<DVec3> = (0..n)
            .map(|i| match (i < nl, target) {
                (true, _) => DVec3::new(v, 0.0, 0.0),
                (false, HertzTarget::Sphere) => DVec3::new(-v, 0.0, 0.0),
                (false, HertzTarget::Wall) => DVec3::ZERO,
            })
            .collect();
        let mass = rho * left.total_volume();
        let theory = hertz_impact(target, radius, mass, e, nu, v);
        let closing = if target == HertzTarget::Sphere {
            2.0 * v
        } else {
            v
        };
        let end = match p.f64("end_time") {
            t if t > 0.0 => t,
            _ => gap / closing + 2.0 * theory.contact_time,
        };
        let interval = match p.f64("probe_interval") {
            t if t > 0.0 => t,
            _ => theory.contact_time / 400.0,
        };
        let volumes = set.volumes().to_vec();
        let body = sph_core::Body::<D3> {
            positions: set.positions().to_vec(),
            volumes: volumes.clone(),
            dp,
            velocities,
            densities: Vec::new(),
        };
        let c0 = constants.sound_speed;
        let ke0 = 0.5
            * mass
            * v
            * v
            * if target == HertzTarget::Sphere {
                2.0
            } else {
                1.0
            };
        let body_of_summary = body_of.clone();
        let summarise = move |s: &dyn Solver<D3>, record: &RunRecord| {
            let mut m = if tool {
                tool_contact_summary(s, "wall", DVec3::X)
            } else {
                contact_summary(s, 0, DVec3::X)
            };
            let duration = m.get("contact_duration").and_then(Json::as_f64);
            m.insert(
                "contact_time".into(),
                duration.map_or(Json::Null, |t| json!(t)),
            );
            let f = m.get("contact_force_max").and_then(Json::as_f64);
            m.insert("max_force".into(), f.map_or(Json::Null, finite_or_null));
            m.insert("contact_time_theory".into(), json!(theory.contact_time));
            m.insert("max_force_theory".into(), json!(theory.max_force));
            m.insert(
                "max_compression_theory".into(),
                json!(theory.max_compression),
            );
            let vb = body_velocities(s, &body_of_summary, &volumes, 2);
            m.insert("restitution".into(), finite_or_null(-vb[0].x / v));
            // Two equal spheres: the total momentum stays 0 (the wall takes momentum).
            let momentum = match target {
                HertzTarget::Sphere => finite_or_null((vb[0] + vb[1]).length() / v),
                HertzTarget::Wall => Json::Null,
            };
            m.insert("momentum_change".into(), momentum);
            m.insert("velocity_over_c0".into(), json!(v / c0));
            m.insert("sphere_particles".into(), json!(nl));
            // UL: the budget's stored terms; TL (no budget): kinetic + strain, whose strain
            // part carries the contact energy (`Solver::energies` of TL).
            let stored = match record.monitor.last() {
                Some(x) => match &x.budget {
                    Some(b) => Some(
                        ["kinetic", "volumetric", "shear", "contact"]
                            .iter()
                            .filter_map(|k| b.get(k))
                            .sum::<f64>(),
                    ),
                    None => Some(x.kinetic + x.strain),
                },
                None => None,
            };
            if let Some(stored) = stored {
                m.insert("energy_change".into(), finite_or_null(stored / ke0 - 1.0));
            }
            m
        };
        let kappa = p.f64("contact_stiffness");
        // The tool: the half-space x ≥ 0 whose surface faces the sphere (−x).
        let wall = if tool {
            if kappa != self.params_for(method).f64("contact_stiffness") {
                return Err(CaseError::InvalidValue {
                    key: "contact_stiffness".into(),
                    value: kappa.to_string(),
                    allowed: "its default with target = \"tool\" (the tool's contact is \
                              kinematic: no contact pressure to scale)"
                        .into(),
                });
            }
            let shape = ToolShape::half_space(DVec3::ZERO, -DVec3::X)?;
            vec![RigidTool::new("wall", shape, ToolMotion::fixed())]
        } else {
            Vec::new()
        };
        if TL_METHODS.contains(&method) {
            return run_tl(
                "hertz-impact-3d",
                method,
                p,
                body,
                mat,
                |s| {
                    let s = if tool {
                        s.with_tools(wall)?.with_constraints(constraints)
                    } else {
                        s.with_bodies(body_of)?
                            .with_contact_scale(kappa)?
                            .with_constraints(constraints)
                    };
                    Ok(s.with_probes(Vec::new(), interval)?)
                },
                end,
                options,
                summarise,
            );
        }
        run_ul(
            "hertz-impact-3d",
            method,
            p,
            body,
            constants,
            |s| {
                let s = if tool {
                    s.with_constraints(constraints).with_tools(wall)?
                } else {
                    s.with_constraints(constraints).with_contact(body_of)?
                };
                Ok(s.with_probes(Vec::new(), interval)?)
            },
            end,
            options,
            summarise,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The formula against two independent checks: energy (the work of the Hertz force up to
    /// δ_max, `(8/15) E* √R* δ_max^(5/2)`, equals the initial kinetic energy of the relative
    /// motion `½ m* v_rel²`) and the contact time from integrating `m* δ̈ = −(4/3) E* √R* δ^(3/2)`
    /// (RK4, 2·10⁵ steps: 1e-4 relative; 2.87 is a 3-digit constant, 2.868 exact, so 2e-3),
    /// and the symmetry of sphere–sphere and sphere–wall.
    #[test]
    fn hertz_formulas_match_energy_and_the_contact_ode() {
        let (r, e, nu, rho, v) = (0.05, 1e7, 0.4, 1200.0, 1.0);
        let m = rho * 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
        let s = hertz_impact(HertzTarget::Sphere, r, m, e, nu, v);
        let w = hertz_impact(HertzTarget::Wall, r, m, e, nu, v);
        // Two spheres: R* = R/2, m* = m/2, E* = E/(2(1 − ν²)), v_rel = 2v.
        let (rs, ms, es, vr) = (0.5 * r, 0.5 * m, e / (2.0 * (1.0 - nu * nu)), 2.0 * v);
        let work = 8.0 / 15.0 * es * rs.sqrt() * s.max_compression.powf(2.5);
        assert!((work / (0.5 * ms * vr * vr) - 1.0).abs() < 1e-12, "energy");
        // Contact ODE: from δ = 0, δ̇ = v_rel until δ returns to 0 (2·10⁵ RK4 steps).
        let f = hertz_force_history(HertzTarget::Sphere, r, m, e, nu, v, 2000);
        let t = f.last().unwrap().0;
        let peak = f.iter().map(|p| p.1).fold(0.0, f64::max);
        assert!(
            (t / s.contact_time - 1.0).abs() < 2e-3,
            "t_c {t} vs {}",
            s.contact_time
        );
        assert!(
            (peak / s.max_force - 1.0).abs() < 1e-5,
            "F {peak} vs {}",
            s.max_force
        );
        // The default case (CASES-style numbers): t_c ≈ 6.4 ms, F_max ≈ 360 N, δ ≈ 4.4 mm.
        assert!((s.contact_time - 6.4e-3).abs() < 0.1e-3, "{s:?}");
        assert!((s.max_force - 360.0).abs() < 10.0, "{s:?}");
        // The wall is the symmetry plane: same t_c and F_max, half the approach.
        assert!((w.contact_time / s.contact_time - 1.0).abs() < 1e-12);
        assert!((w.max_force / s.max_force - 1.0).abs() < 1e-12);
        assert!((w.max_compression / s.max_compression - 0.5).abs() < 1e-12);
    }
}
