//! Benchmark case 15: a slab in pure tension (MPS paper §IV.B, Fig. 2).
//!
//! Slab 3 cm × 1 cm (centred on the origin), SVK with `K = 3.25e6`, `μ = 7.15e5`, `ρ = 1000`.
//! The particles in the end strips 0.2 cm wide are moved with the prescribed velocity
//! `v_x(t) = ∓ a min(t, t_a)` (`a = 0.5 m/s²` for `t_a = 1 s`; the paper: "the acceleration
//! of 0.5 m/s² to the particles within 0.2 cm strips off the ends ... within a time interval of
//! 1 second"). Key `grip`: `roller` (default) prescribes only `v_x` and leaves the strips free
//! to contract sideways with the slab — the paper prescribes an acceleration along the slab and
//! nothing else, and reports a "pure extensional stress field" outside the strips; `rigid` also
//! holds `v_y = 0`, which makes the four corners where the free surface meets a strip
//! re-entrant corners of a sideways-clamped slab. With either grip plane-strain SVK gives out
//! long before the paper's t = 0.5 s (measured at H/dp = 20, MPS, a particle inverts: roller
//! at t = 0.157 s without and 0.168 s with `stabilisation = 3`, rigid at 0.134 s and
//! 0.360 s (the latter disordered, max e 1.4); `validate mps`, docs/validation.md).
//!
//! Resolution: the paper's 11,594 particles are 187 × 62 (dp ≈ 1.6e-4); we default to
//! `resolution = H/dp = 62`, 186 × 62 = 11,532 particles, so both sides are whole numbers of
//! spacings. That is ~3.5·10⁶ steps to t = 1 s at C = 0.1 (hours); lower resolutions are
//! usable for checks.
//!
//! Summary: `final_length` (extent in x), `nominal_strain` (final/initial − 1), the middle
//! third's strain `F_xx − 1`: mean and `middle_strain_uniformity` = std/mean over its
//! particles (0 for a perfectly uniform extension), its smallest and largest `J`, and the
//! standard `max_disorder` (clumping shows there).

use crate::analysis::extremes;
use crate::cases::mps_common::{mps_params, run_mps};
use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::{finite_or_null, RunOptions, RunRecord};
use crate::{Case, CaseInfo};
use glam::DVec2;
use serde_json::{json, Map, Value as Json};
use sph_core::error::Num;
use sph_core::Body;
use sph_core::{Constraint, Constraints, Field, Solver, TimeFunction, D2};
use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
use sph_materials::{ElasticConstants, MaterialKind};

/// The slab in tension.
pub struct SlabTension2d;

impl Case for SlabTension2d {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "slab-tension-2d",
            description: "SVK slab pulled by its accelerated end strips (MPS §IV.B)",
            methods: &["mps"],
        }
    }

    fn params(&self) -> Params {
        let mut specs = vec![
            Param::float("length", 0.03, Range::Positive, "slab length (m)"),
            Param::float("thickness", 0.01, Range::Positive, "slab height H (m)"),
            Param::int("resolution", 62, Range::Closed(2.0, 1000.0), "H/dp"),
            Param::float(
                "strip_width",
                0.002,
                Range::Positive,
                "width of the pulled end strips (m)",
            ),
            Param::float(
                "acceleration",
                0.5,
                Range::Any,
                "acceleration of each strip, outward (m/s²)",
            ),
            Param::float(
                "accel_time",
                1.0,
                Range::NonNegative,
                "duration of the acceleration (s)",
            ),
            Param::float("bulk_modulus", 3.25e6, Range::Positive, "K (Pa)"),
            Param::float("shear_modulus", 7.15e5, Range::Positive, "μ (Pa)"),
            Param::float("density", 1000.0, Range::Positive, "ρ0 (kg/m³)"),
            Param::float("end_time", 1.0, Range::Positive, "simulated time (s)"),
            Param::choice(
                "grip",
                "roller",
                &["roller", "rigid"],
                "end strips: roller = only v_x prescribed (they contract sideways with the slab), \
                 rigid = v_y held at 0 as well",
            ),
        ];
        specs.extend(mps_params());
        Params::new("slab-tension-2d", specs)
    }

    fn run(
        &self,
        method: &str,
        p: &Params,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), CaseError> {
        crate::resolve_method(self, Some(method))?;
        let (l, h) = (p.f64("length"), p.f64("thickness"));
        let dp = h / p.int("resolution") as f64;
        let nx = (l / dp).round();
        if (nx * dp - l).abs() > 1e-9 * l {
            return Err(CaseError::InvalidValue {
                key: "length".into(),
                value: Num(l).to_string(),
                allowed: format!(
                    "a whole multiple of dp = thickness/resolution = {}",
                    Num(dp)
                ),
            });
        }
        let lo = DVec2::new(-0.5 * l, -0.5 * h);
        let shape = Aabb::<D2>::new(lo, -lo)?;
        let mut set = ParticleSet::fill(&Lattice::<D2>::new(dp, lo)?, &shape)?;
        let w = p.f64("strip_width");
        // Each strip must hold a column of particles and leave the slab between them free.
        if !(w > 0.5 * dp && w < 0.5 * l) {
            return Err(CaseError::InvalidValue {
                key: "strip_width".into(),
                value: Num(w).to_string(),
                allowed: format!(
                    "dp/2 = {} < strip_width < length/2 = {}",
                    Num(0.5 * dp),
                    Num(0.5 * l)
                ),
            });
        }
        set.tag_where("left", |_, x| x.x < -0.5 * l + w)?;
        set.tag_where("right", |_, x| x.x > 0.5 * l - w)?;
        set.tag_where("middle", |_, x| x.x.abs() < l / 6.0)?;
        let (left, right, middle) = (
            set.tagged("left")?,
            set.tagged("right")?,
            set.tagged("middle")?,
        );
        let c = ElasticConstants::from_bulk_shear(
            p.f64("bulk_modulus"),
            p.f64("shear_modulus"),
            p.f64("density"),
        )?;
        let mat = MaterialKind::SaintVenantKirchhoff.build(c)?;
        let (a, ta) = (p.f64("acceleration"), p.f64("accel_time"));
        let speed = move |t: f64| a * t.min(ta);
        let n = set.len();
        let rigid = p.text("grip") == "rigid";
        let grip = |particles: Vec<u32>, sign: f64| {
            let velocity = TimeFunction::new(move |t| DVec2::new(sign * speed(t), 0.0));
            if rigid {
                Constraint::PrescribedVelocity {
                    particles,
                    velocity,
                }
            } else {
                Constraint::PrescribedComponents {
                    particles,
                    velocity,
                    components: [true, false, false],
                }
            }
        };
        let mut constraints = Constraints::new();
        constraints.push(grip(left, -1.0), n)?;
        constraints.push(grip(right, 1.0), n)?;
        let body = Body::<D2> {
            positions: set.positions().to_vec(),
            volumes: set.volumes().to_vec(),
            dp,
            velocities: Vec::new(),
            densities: Vec::new(),
        };
        run_mps(
            "slab-tension-2d",
            p,
            body,
            mat,
            |s| Ok(s.with_constraints(constraints)),
            p.f64("end_time"),
            options,
            move |s, _| slab_summary(s, &middle, l, dp),
        )
    }
}

fn slab_summary(s: &dyn Solver<D2>, middle: &[u32], l: f64, dp: f64) -> Map<String, Json> {
    let mut m = Map::new();
    let xs: Vec<f64> = s.positions().iter().map(|x| x.x).collect();
    let (lo, hi) = extremes(&xs);
    // Particle centres span l − dp initially.
    let length = hi - lo + dp;
    m.insert("final_length".into(), finite_or_null(length));
    m.insert("nominal_strain".into(), finite_or_null(length / l - 1.0));
    if let Some(Field::Matrix(f)) = s.field("deformation_gradient") {
        let eps: Vec<f64> = middle
            .iter()
            .map(|&i| f[i as usize].x_axis.x - 1.0)
            .collect();
        let js: Vec<f64> = middle
            .iter()
            .map(|&i| f[i as usize].determinant())
            .collect();
        let n = eps.len().max(1) as f64;
        let mean = eps.iter().sum::<f64>() / n;
        let var = eps.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / n;
        m.insert("middle_strain_mean".into(), finite_or_null(mean));
        m.insert("middle_strain_std".into(), finite_or_null(var.sqrt()));
        m.insert(
            "middle_strain_uniformity".into(),
            finite_or_null(var.sqrt() / mean.abs()),
        );
        let (jlo, jhi) = extremes(&js);
        m.insert("middle_jacobian_min".into(), finite_or_null(jlo));
        m.insert("middle_jacobian_max".into(), finite_or_null(jhi));
    }
    m.insert("middle_particles".into(), json!(middle.len()));
    m
}
