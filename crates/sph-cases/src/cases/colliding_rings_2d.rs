//! Benchmark case 16: two colliding rubber rings — the MPS variant (MPS paper §IV.C, Fig. 3; after
//! Gray, Monaghan & Swift 2001) and the UL variant (UL paper §6.3, Fig. 11–14).
//!
//! Rings of inner/outer radius 0.03/0.04 m (the MPS paper prints "diameters of 0.03 cm and
//! 0.04 cm"; its source, Gray et al., and the UL paper use radii 3 and 4 cm), `annulus_polar`
//! with `dp = 0.001` (2,199 particles per ring; the UL paper relaxes its particles with a level
//! set, we keep the polar rings). Each family keeps its paper's set-up as its defaults
//! (`Case::params_for`; the keys are the same):
//!
//! | | `mps` | `ul-enog`, `ul-og`, `ul-oas` |
//! |---|---|---|
//! | material | SVK, K = 3.25e6, μ = 7.15e5, ρ = 1000 | linear (UL), E = 1e7, ν = 0.4, ρ = 1200 |
//! | speed `v0` of each ring | 0.2 m/s (`v0_unit = m/s`) | 0.06 c0 (`v0_unit = c0`; 0.07, 0.08 in Fig. 13–14) |
//! | gap between the rings | 0.005 | 0.01 (centres 0.09 apart) |
//! | interaction | penalty contact (below) | two UL bodies with docs/methods.md's contact pressure |
//! | end time | 0.1 s | 0.02 s |
//!
//! **MPS contact.** Both rings are one MPS body, and the Hamiltonian MPS model's neighbours and
//! weights are fixed in the reference configuration, so without a contact model particles of
//! different rings never interact and the rings pass through each other. The paper's rings do
//! collide (it shows the stress at the moment of collision) but the paper does not describe its
//! contact treatment; with `contact = true` (default) the rings interact through
//! `sph_mps::contact`, a central penalty potential between particles of different rings closer
//! than `dp` (stiffness `contact_stiffness · E`), which keeps the model Hamiltonian (momentum and
//! energy conserved). `contact = false` reproduces the pass-through. `gap` must be at least
//! `r_e`, or the reference neighbour search would glue the rings together.
//!
//! **UL.** With `contact = true` (default) the rings are two bodies of one UL solver
//! (`UlSolver::with_contact`): each keeps its own neighbours and they push each other apart
//! with docs/methods.md's contact pressure, so they rebound as in the paper's Fig. 12–14.
//! `contact = false` makes them one body, as Gray et al.: once closer than the kernel support
//! they interact like any two particles of the body and stick in tension. `allow_fracture` is
//! on: particles that lose every neighbour of their own body (numerical fracture, expected for
//! SPH-OG) fly on and are counted (`isolated_max`, `fracture`).
//!
//! Summary: the separation of the rings' facing outer particles over time (negative = the rings
//! overlap), its minimum, the mean x-velocity of each ring at the end, the total x-momentum, and
//! `v0_m_per_s`, `v0_over_c0`.

use crate::cases::mps_common::{mps_params, run_mps};
use crate::cases::ul_common::{run_ul, ul_params, UL_METHODS};
use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::{finite_or_null, RunOptions, RunRecord};
use crate::{Case, CaseInfo};
use glam::DVec2;
use serde_json::{json, Map, Value as Json};
use sph_core::error::Num;
use sph_core::Body;
use sph_core::{Probe, Solver, D2};
use sph_geometry::generate::{annulus_polar, ParticleSet};
use sph_materials::{ElasticConstants, MaterialKind};
use sph_mps::Contact;

/// Two colliding rings, MPS.
pub struct CollidingRings2d;

impl Case for CollidingRings2d {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "colliding-rings-2d",
            description: "two rubber rings colliding (MPS §IV.C; UL §6.3)",
            methods: &["mps", "ul-enog", "ul-og", "ul-oas"],
        }
    }

    fn params(&self) -> Params {
        let mut specs = vec![
            Param::float("inner_radius", 0.03, Range::Positive, "r_in (m)"),
            Param::float("outer_radius", 0.04, Range::Positive, "r_out (m)"),
            Param::float("dp", 0.001, Range::Positive, "particle spacing (m)"),
            Param::float(
                "v0",
                0.2,
                Range::Any,
                "speed of each ring toward the other (unit: v0_unit)",
            ),
            Param::choice(
                "v0_unit",
                "m/s",
                &["m/s", "c0"],
                "unit of v0: m/s, or the sound speed c0 = √(K/ρ0) (the UL paper's)",
            ),
            Param::float(
                "gap",
                0.005,
                Range::Positive,
                "initial gap between the rings (m; ≥ r_e)",
            ),
            Param::float("bulk_modulus", 3.25e6, Range::Positive, "K (Pa)"),
            Param::float("shear_modulus", 7.15e5, Range::Positive, "μ (Pa)"),
            Param::float("density", 1000.0, Range::Positive, "ρ0 (kg/m³)"),
            Param::float("end_time", 0.1, Range::Positive, "simulated time (s)"),
            Param::bool(
                "contact",
                true,
                "contact between the rings (MPS: sph_mps::contact penalty; UL: two bodies with \
                 the contact pressure of UlSolver::with_contact); false: MPS rings pass through \
                 each other, UL rings are one body",
            ),
            Param::float(
                "contact_stiffness",
                1.0,
                Range::Positive,
                "contact stiffness factor κ (MPS: penalty k = κ E dp^(d−2); UL: contact \
                 pressure p_c = κ c0² ρ_c)",
            ),
        ];
        specs.extend(mps_params());
        specs.extend(ul_params());
        let mut p = Params::new("colliding-rings-2d", specs);
        p.set_text("probe_interval", "1e-4").expect("valid default");
        p
    }

    fn params_for(&self, method: &str) -> Params {
        let mut p = self.params();
        if UL_METHODS.contains(&method) {
            // UL paper §6.3: E = 1e7, ν = 0.4, ρ0 = 1200, centres 0.09 apart, v0 = 0.06 c0.
            let (e, nu) = (1e7, 0.4);
            let k = e / (3.0 * (1.0 - 2.0 * nu));
            let g = e / (2.0 * (1.0 + nu));
            for (key, value) in [
                ("bulk_modulus", k.to_string()),
                ("shear_modulus", g.to_string()),
                ("density", "1200".into()),
                ("v0", "0.06".into()),
                ("v0_unit", "c0".into()),
                ("gap", "0.01".into()),
                ("end_time", "0.02".into()),
                ("allow_fracture", "true".into()),
            ] {
                p.set_text(key, &value).expect("valid UL default");
            }
        }
        p
    }

    fn run(
        &self,
        method: &str,
        p: &Params,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), CaseError> {
        let method = crate::resolve_method(self, Some(method))?;
        let ul = UL_METHODS.contains(&method);
        let (a, b, dp, gap) = (
            p.f64("inner_radius"),
            p.f64("outer_radius"),
            p.f64("dp"),
            p.f64("gap"),
        );
        let re = p.f64("re_over_l0") * dp;
        if !ul && gap < re {
            return Err(CaseError::InvalidValue {
                key: "gap".into(),
                value: Num(gap).to_string(),
                allowed: format!(
                    "gap >= r_e = re_over_l0·dp = {} (closer rings would share reference neighbours)",
                    Num(re)
                ),
            });
        }
        let xc = b + 0.5 * gap;
        let mut set: ParticleSet<D2> = annulus_polar(DVec2::new(-xc, 0.0), a, b, dp)?;
        let right = annulus_polar(DVec2::new(xc, 0.0), a, b, dp)?;
        let nl = set.len();
        set.extend(&right)?;
        let right_ids: Vec<u32> = (nl as u32..set.len() as u32).collect();
        set.tag_particles("right", &right_ids)?;
        let pos = set.positions().to_vec();
        let outer = set.tagged("outer")?;
        let pick = |right: bool| {
            outer
                .iter()
                .copied()
                .filter(|&i| (i as usize >= nl) == right)
                .max_by(|&i, &j| {
                    let s = if right { -1.0 } else { 1.0 };
                    (s * pos[i as usize].x).total_cmp(&(s * pos[j as usize].x))
                })
                .expect("each ring has an outer layer")
        };
        let (lf, rf) = (pick(false), pick(true));
        let (k, mu, rho) = (
            p.f64("bulk_modulus"),
            p.f64("shear_modulus"),
            p.f64("density"),
        );
        let c0 = (k / rho).sqrt();
        let v0 = match p.text("v0_unit") {
            "c0" => p.f64("v0") * c0,
            _ => p.f64("v0"),
        };
        let velocities: Vec<DVec2> = (0..set.len())
            .map(|i| DVec2::new(if i < nl { v0 } else { -v0 }, 0.0))
            .collect();
        let interval = p.f64("probe_interval");
        let probes = move || {
            vec![
                Probe::particle("left_front", lf),
                Probe::particle("right_front", rf),
            ]
        };
        let speed = move |mut m: Map<String, Json>| {
            m.insert("v0_m_per_s".into(), json!(v0));
            m.insert("v0_over_c0".into(), json!(v0 / c0));
            m
        };
        let contact = p.flag("contact");
        let body_of: Vec<u32> = (0..set.len()).map(|i| u32::from(i >= nl)).collect();
        if ul {
            let constants = ElasticConstants::from_bulk_shear(k, mu, rho)?;
            let body = Body::<D2> {
                positions: pos,
                volumes: set.volumes().to_vec(),
                dp,
                velocities,
                densities: Vec::new(),
            };
            // The UL solver reorders particles: ring membership goes by the original index.
            return run_ul(
                "colliding-rings-2d",
                method,
                p,
                body,
                constants,
                |s| {
                    let s = if contact { s.with_contact(body_of)? } else { s };
                    Ok(s.with_probes(probes(), interval)?)
                },
                p.f64("end_time"),
                options,
                move |s, _| speed(rings_summary(s, nl, dp, contact)),
            );
        }
        let c = ElasticConstants::from_bulk_shear(k, mu, rho)?;
        let mat = MaterialKind::SaintVenantKirchhoff.build(c)?;
        let body = Body::<D2> {
            positions: pos,
            volumes: set.volumes().to_vec(),
            dp,
            velocities,
            densities: Vec::new(),
        };
        let contact = contact.then(|| Contact {
            body_of,
            distance_over_dp: 1.0,
            stiffness_factor: p.f64("contact_stiffness"),
        });
        let has_contact = contact.is_some();
        run_mps(
            "colliding-rings-2d",
            p,
            body,
            mat,
            |s| {
                let s = match contact {
                    Some(c) => s.with_contact(c)?,
                    None => s,
                };
                Ok(s.with_probes(probes(), interval)?)
            },
            p.f64("end_time"),
            options,
            move |s, _| speed(rings_summary(s, nl, dp, has_contact)),
        )
    }
}

fn rings_summary(s: &dyn Solver<D2>, nl: usize, dp: f64, contact: bool) -> Map<String, Json> {
    let mut m = Map::new();
    m.insert("contact".into(), json!(contact));
    let probe = |name: &str| s.probes().iter().find(|p| p.name == name);
    if let (Some(l), Some(r)) = (probe("left_front"), probe("right_front")) {
        // Separation of the facing surfaces: particle centres sit dp/2 inside the surface.
        let sep: Vec<f64> = l
            .positions
            .iter()
            .zip(&r.positions)
            .map(|(a, b)| b.x - a.x - dp)
            .collect();
        let min = sep.iter().copied().fold(f64::INFINITY, f64::min);
        m.insert("front_separation_initial".into(), finite_or_null(sep[0]));
        m.insert("front_separation_min".into(), finite_or_null(min));
        m.insert(
            "interpenetration_max".into(),
            finite_or_null((-min).max(0.0)),
        );
    }
    // Ring membership by input index (UL reorders its particles and says where they went).
    let v = s.velocities();
    let original = s.particle_ids();
    let (mut sum, mut cnt) = ([0.0; 2], [0usize; 2]);
    for (vk, &o) in v.iter().zip(original.iter()) {
        let r = usize::from(o as usize >= nl);
        sum[r] += vk.x;
        cnt[r] += 1;
    }
    let mean = |r: usize| sum[r] / cnt[r].max(1) as f64;
    m.insert("left_velocity_final".into(), finite_or_null(mean(0)));
    m.insert("right_velocity_final".into(), finite_or_null(mean(1)));
    if let Some(p) = s.momentum() {
        m.insert("momentum_x_final".into(), finite_or_null(p.x));
    }
    m
}
