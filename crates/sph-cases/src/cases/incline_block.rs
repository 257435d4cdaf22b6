//! An elastic block on an incline with Coulomb friction: the check of the friction law
//! ([`sph_core::friction`]) against the rigid-block answer, for every method family.
//!
//! A block of side `size` (0.1 m; a square in 2D, a cube in 3D) cut from a cell-centred lattice
//! of spacing `size / resolution` rests on a rigid floor (a half-space tool `incline` whose
//! surface is y = 0, with `friction_static` μ_s and `friction_kinetic` μ_k). The incline is made
//! by turning gravity instead of the floor: `g = gravity · (sin θ, −cos θ)` with θ = `angle`
//! (degrees), so "down the slope" is +x. Gravity rises smoothly over `ramp_time` (0.05 s,
//! about five periods of the block's lowest vertical mode at the defaults) on a block at rest
//! whose bottom row touches the floor (the contact offset dp/2).
//!
//! A rigid block sticks for tan θ ≤ μ_s and otherwise slides with the acceleration
//! `g (sin θ − μ_k cos θ)` (`acceleration_theory`; 0 when it sticks). The ramp matters for the
//! sticking side: gravity applied at once (`ramp_time = 0`) sends a compression wave through the
//! elastic block that unloads its base when it comes back from the top face; the base slips
//! while unloaded, and once sliding a block with tan θ > μ_k keeps sliding (Coulomb's law, not a
//! numerical artefact), so a suddenly loaded block slides anywhere in μ_k < tan θ < μ_s.
//!
//! Summary: `acceleration` — the mean acceleration of the block's centre of mass along the slope
//! after the ramp, `g sin θ − F̄_x/m` from the mean tangential force on the floor over the probe
//! samples after `ramp_time` (Newton's law: gravity and the floor are the only external forces);
//! `velocity_final`, the centre of mass's velocity along the slope at the end;
//! `acceleration_theory`; `acceleration_error` (relative, when both slide; null otherwise);
//! `slid` — whether the bottom row moved down the slope by more than `dp/20` on average;
//! `slide_distance` (m, the bottom row's mean travel); `sticking_final` and `sticking_mean`,
//! the fraction of the contacting particles that stuck in the last step and its mean over the
//! probe samples; and the tools' `tool_contact_work`, `friction_work` and
//! `friction_dissipated`.
//!
//! With `floor = "body"` (TL and UL methods) the floor is a fixed slab body instead of the
//! tool, meeting the block through the body-body contact with the friction of
//! [`sph_core::contact_friction`] (`floor_refinement`: the slab's spacing is dp divided by it);
//! `acceleration` is then the parabola fit of the block's mean position after the ramp, the
//! summary adds `contact_friction_work`, `gravity_impulse` and (UL) `gravity_impulse_error`,
//! and `sticking_*` come from the series `contact_friction_0`. Measured at θ = 30°, μ_s = 0.4,
//! μ_k = 0.3 (end 0.3 s): the friction force is μ_k times the normal force within 1 %, but the
//! block slides slower than the rigid answer by the drag of the particle floor's roughness,
//! UL-ENOG −20 % / −9.8 % at resolution 10 / 20 (slab of the block's spacing; frictionless:
//! −0.04 % on a twice finer slab), TL-HF −7.4 % / −4.5 % on a twice finer slab (TL's
//! contact, pairs closer than dp only, is rougher: frictionless −39 % on a slab of the block’s
//! spacing, −0.9 % on a twice finer one). It sticks at θ = 15°, μ_s = 0.6.

use crate::cases::mps_common::{mps_params, run_mps, MPS_METHODS};
use crate::cases::tl_common::{material, run_tl, tl_params};
use crate::cases::ul_common::{run_ul, ul_params, UL_METHODS};
use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::{finite_or_null, RunOptions, RunRecord};
use crate::{Case, CaseInfo};
use serde_json::{json, Map, Value as Json};
use sph_core::contact_friction::FrictionTable;
use sph_core::friction::Friction;
use sph_core::scene::ProbeTarget;
use sph_core::tool::{RigidTool, ToolMotion, ToolShape};
use sph_core::{
    Amplitude, Body, Constraint, Constraints, Dim, Loads, Probe, Solver, TimeFunction, D2, D3,
};
use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
use sph_materials::{Material, MaterialKind, MaterialModel};

/// The block on an incline.
pub struct InclineBlock;

/// Every method family.
pub const INCLINE_METHODS: &[&str] = &["tl-hf", "tl", "tl-gm", "ul-enog", "ul-og", "ul-oas", "mps"];

/// The rigid block's answer: `g (sin θ − μ_k cos θ)` when it slides (`tan θ > μ_s`), else 0.
pub fn sliding_acceleration(gravity: f64, angle_deg: f64, mu_s: f64, mu_k: f64) -> f64 {
    let theta = angle_deg.to_radians();
    if theta.tan() <= mu_s {
        0.0
    } else {
        gravity * (theta.sin() - mu_k * theta.cos())
    }
}

/// The case's keys: its own, then every family's (see inside for the one shared name).
fn incline_params(mps: bool) -> Params {
    let mut specs = vec![
        Param::int("dimension", 2, Range::Closed(2.0, 3.0), "2 or 3"),
        Param::float(
            "angle",
            30.0,
            Range::Closed(0.0, 80.0),
            "incline angle θ (degrees)",
        ),
        Param::float(
            "friction_static",
            0.4,
            Range::NonNegative,
            "static Coulomb coefficient μ_s",
        ),
        Param::float(
            "friction_kinetic",
            0.3,
            Range::NonNegative,
            "kinetic Coulomb coefficient μ_k (<= μ_s)",
        ),
        Param::int("resolution", 10, Range::Closed(2.0, 200.0), "size/dp"),
        Param::float("end_time", 0.3, Range::Positive, "simulated time (s)"),
        Param::float(
            "ramp_time",
            0.05,
            Range::NonNegative,
            "gravity rises smoothly ((1 − cos)/2) over this time (s; 0: at once); the \
             acceleration is measured after it",
        ),
        Param::choice(
            "floor",
            "tool",
            &["tool", "body"],
            "what the block rests on: a rigid half-space tool, or a fixed slab body (TL and UL \
             methods) meeting it through the body-body contact with its friction",
        ),
        Param::int(
            "floor_refinement",
            1,
            Range::Closed(1.0, 4.0),
            "floor = \"body\": the slab's particle spacing is dp / floor_refinement (a finer \
             slab is a smoother floor for the particle contact)",
        ),
        Param::float("size", 0.1, Range::Positive, "side of the block (m)"),
        Param::float("gravity", 9.81, Range::Positive, "|g| (m/s²)"),
        Param::float("youngs_modulus", 1e6, Range::Positive, "E (Pa)"),
        Param::float("nu", 0.3, Range::Open(-1.0, 0.5), "Poisson's ratio"),
        Param::float("density", 1000.0, Range::Positive, "ρ0 (kg/m³)"),
    ];
    // Every family's keys; where two share a name (`damping`: TL's switch, MPS's rate; the
    // output keys), the method's own comes first.
    let families = if mps {
        [mps_params(), tl_params(), ul_params()]
    } else {
        [tl_params(), ul_params(), mps_params()]
    };
    for family in families {
        for param in family {
            if !specs.iter().any(|p| p.key == param.key) {
                specs.push(param);
            }
        }
    }
    let mut p = Params::new("incline-block", specs);
    p.set_text("probe_interval", "1e-3").expect("valid default");
    p
}

impl Case for InclineBlock {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "incline-block",
            description: "elastic block on an incline with Coulomb friction: sticks or slides \
                          at g(sin θ − μk cos θ) (2D and 3D)",
            methods: INCLINE_METHODS,
        }
    }

    /// The keys of every family; MPS's `damping` (a rate) shares its name with TL's (a
    /// switch), so the TL one is listed here and [`Case::params_for`] gives MPS its own.
    fn params(&self) -> Params {
        incline_params(false)
    }

    fn params_for(&self, method: &str) -> Params {
        incline_params(MPS_METHODS.contains(&method))
    }

    fn run(
        &self,
        method: &str,
        p: &Params,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), CaseError> {
        // Bad coefficients before any particle is made.
        let friction = Friction::new(p.f64("friction_static"), p.f64("friction_kinetic"))?;
        if p.text("floor") == "body" && MPS_METHODS.contains(&method) {
            return Err(CaseError::InvalidValue {
                key: "floor".into(),
                value: "body".into(),
                allowed: format!(
                    "\"tool\" for {method} (friction between bodies is built for TL and UL)"
                ),
            });
        }
        if p.text("floor") == "body" {
            return if p.int("dimension") == 3 {
                run_on_body::<D3>(method, p, friction, options)
            } else {
                run_on_body::<D2>(method, p, friction, options)
            };
        }
        if p.int("dimension") == 3 {
            run_block::<D3>(method, p, friction, options)
        } else {
            run_block::<D2>(method, p, friction, options)
        }
    }
}

/// What both floors share: the block, its material, the turned gravity and the rigid answer.
struct BlockSetup<D: Dim> {
    /// The block's particle spacing (m).
    dp: f64,
    /// The block's side (m).
    size: f64,
    end_time: f64,
    /// The gravity ramp's duration (s).
    ramp: f64,
    /// The probes' sampling interval (s).
    interval: f64,
    mat: MaterialModel,
    /// The block `[−size/2, size/2] × [0, size] (× [−size/2, size/2])` above the floor y = 0.
    block: ParticleSet<D>,
    /// The block's reference positions.
    reference: Vec<D::Vector>,
    /// The block's bottom row (indices into `reference`).
    bottom: Vec<usize>,
    /// `g (sin θ, −cos θ)`: the incline made by turning gravity.
    gravity: D::Vector,
    /// [`sliding_acceleration`] for the case's angle and coefficients.
    theory: f64,
    slope: Slope,
}

impl<D: Dim> BlockSetup<D>
where
    MaterialModel: Material<D>,
{
    /// Reads the case's keys (bad values are errors before any particle is made) and fills the
    /// block.
    fn new(p: &Params, friction: Friction) -> Result<Self, CaseError> {
        let (size, resolution) = (p.f64("size"), p.int("resolution"));
        let dp = size / resolution as f64;
        let (e, nu, rho) = (p.f64("youngs_modulus"), p.f64("nu"), p.f64("density"));
        let (g, angle) = (p.f64("gravity"), p.f64("angle"));
        let (end_time, ramp) = (p.f64("end_time"), p.f64("ramp_time"));
        if ramp >= end_time {
            return Err(CaseError::InvalidValue {
                key: "ramp_time".into(),
                value: ramp.to_string(),
                allowed: format!("0 <= ramp_time < end_time = {end_time}"),
            });
        }
        let mat = material(MaterialKind::LinearElastic, e, nu, rho)?;
        let block = lattice(
            dp,
            [-0.5 * size, 0.0, -0.5 * size],
            [0.5 * size, size, 0.5 * size],
        )?;
        let reference = block.positions().to_vec();
        let bottom = (0..reference.len())
            .filter(|&i| D::component(reference[i], 1) < dp)
            .collect();
        let theta = angle.to_radians();
        let slope = Slope {
            gravity: g * theta.sin(),
            mass: rho * block.volumes().iter().sum::<f64>(),
            ramp,
        };
        Ok(Self {
            dp,
            size,
            end_time,
            ramp,
            interval: p.f64("probe_interval"),
            mat,
            block,
            reference,
            bottom,
            gravity: D::vector([g * theta.sin(), -g * theta.cos(), 0.0]),
            theory: sliding_acceleration(
                g,
                angle,
                friction.static_coefficient,
                friction.kinetic_coefficient,
            ),
            slope,
        })
    }

    /// Gravity on `particles` (every particle with `None`), rising smoothly over the ramp.
    fn gravity_loads(&self, particles: Option<Vec<u32>>) -> Result<Loads<D>, CaseError> {
        let mut loads = Loads::<D>::new();
        loads.add_body_acceleration(
            particles,
            if self.ramp > 0.0 {
                TimeFunction::scaled(self.gravity, Amplitude::smooth_step(0.0, self.ramp)?)
            } else {
                TimeFunction::constant(self.gravity)
            },
        );
        Ok(loads)
    }
}

/// The particles of a cell-centred lattice of `spacing` in the box `lo`–`hi` (its third
/// components ignored in 2D).
fn lattice<D: Dim>(spacing: f64, lo: [f64; 3], hi: [f64; 3]) -> Result<ParticleSet<D>, CaseError> {
    let (mut lo, mut hi) = (lo, hi);
    if D::D == 2 {
        (lo[2], hi[2]) = (0.0, 0.0);
    }
    let (lo, hi) = (D::vector(lo), D::vector(hi));
    Ok(ParticleSet::fill(
        &Lattice::<D>::new(spacing, lo)?,
        &Aabb::<D>::new(lo, hi)?,
    )?)
}

/// The block on the rigid floor tool.
fn run_block<D: Dim>(
    method: &str,
    p: &Params,
    friction: Friction,
    options: &RunOptions,
) -> Result<(RunRecord, Map<String, Json>), CaseError>
where
    MaterialModel: Material<D>,
{
    let setup = BlockSetup::<D>::new(p, friction)?;
    let loads = setup.gravity_loads(None)?;
    let BlockSetup {
        dp,
        end_time,
        interval,
        mat,
        block,
        reference,
        bottom,
        theory,
        slope,
        ..
    } = setup;
    let body = Body::<D> {
        positions: reference.clone(),
        volumes: block.volumes().to_vec(),
        dp,
        velocities: vec![D::zero(); block.len()],
        densities: Vec::new(),
    };
    let floor = ToolShape::half_space(D::zero(), D::vector([0.0, 1.0, 0.0]))?;
    let tool = RigidTool::new("incline", floor, ToolMotion::fixed()).with_friction(friction);
    let summarise = move |s: &dyn Solver<D>, _: &RunRecord| {
        block_summary(s, &reference, &bottom, dp, theory, slope)
    };
    if UL_METHODS.contains(&method) {
        let constants = *Material::<D>::constants(&mat);
        return run_ul(
            "incline-block",
            method,
            p,
            body,
            constants,
            |s| {
                Ok(s.with_loads(loads)
                    .with_tools(vec![tool])?
                    .with_probes(Vec::new(), interval)?)
            },
            end_time,
            options,
            summarise,
        );
    }
    if MPS_METHODS.contains(&method) {
        return run_mps(
            "incline-block",
            p,
            body,
            mat,
            |s| {
                Ok(s.with_loads(loads)
                    .with_tools(vec![tool])?
                    .with_probes(Vec::new(), interval)?)
            },
            end_time,
            options,
            summarise,
        );
    }
    run_tl(
        "incline-block",
        method,
        p,
        body,
        mat,
        |s| {
            Ok(s.with_loads(loads)
                .with_tools(vec![tool])?
                .with_probes(Vec::new(), interval)?)
        },
        end_time,
        options,
        summarise,
    )
}

/// The block on a fixed slab body instead of the tool (`floor = "body"`): the slab
/// `[−size/2 − 4dp, size/2 + L + 4dp]` long (× the block's depth plus `4dp` each side in 3D),
/// `4dp` thick with its top row one `dp` below the block's bottom row, `L = ½ g sin θ
/// end_time²` the frictionless travel, of the block's material and a lattice of spacing
/// `dp / floor_refinement`, every particle `Fixed`; block and slab meet through the method's
/// body-body contact with the Coulomb friction of [`sph_core::contact_friction`] between them.
/// The acceleration is the least-squares slope of the block's mean velocity along the slope (a
/// probe with equal weights on every block particle) over the samples after the ramp
/// ([`probe_acceleration`]). `gravity_impulse` is `|g| m (end_time − ramp_time/2)`, the impulse
/// gravity gave the block: with UL, the solver's `momentum_balance` (`|Σ m v − (Σ m v)₀ + J_c|`,
/// `J_c` the impulse the fixed slab's constraint took, the friction reaction included) must
/// equal it: `gravity_impulse_error` is `momentum_balance / gravity_impulse − 1`.
fn run_on_body<D: Dim>(
    method: &str,
    p: &Params,
    friction: Friction,
    options: &RunOptions,
) -> Result<(RunRecord, Map<String, Json>), CaseError>
where
    MaterialModel: Material<D>,
{
    let setup = BlockSetup::<D>::new(p, friction)?;
    let nb = setup.block.len();
    let block_ids: Vec<u32> = (0..nb as u32).collect();
    let loads = setup.gravity_loads(Some(block_ids.clone()))?;
    let BlockSetup {
        dp,
        size,
        end_time,
        ramp,
        interval,
        mat,
        block,
        reference,
        bottom,
        gravity,
        theory,
        slope,
    } = setup;
    let travel = 0.5 * p.f64("gravity") * p.f64("angle").to_radians().sin() * end_time * end_time;
    let margin = 4.0 * dp;
    // The slab's top row at y = −dp/2, one dp below the block's bottom row (touching).
    let fine = dp / p.int("floor_refinement") as f64;
    let top = -0.5 * dp + 0.5 * fine;
    let slab = lattice(
        fine,
        [-0.5 * size - margin, top - margin, -0.5 * size - margin],
        [0.5 * size + travel + margin, top, 0.5 * size + margin],
    )?;
    let mut set = block;
    set.extend(&slab)?;
    let n = set.len();
    let body_of: Vec<u32> = (0..n).map(|i| u32::from(i >= nb)).collect();
    let mut constraints = Constraints::new();
    constraints.push(
        Constraint::Fixed {
            particles: (nb as u32..n as u32).collect(),
        },
        n,
    )?;
    let body = Body::<D> {
        positions: set.positions().to_vec(),
        volumes: set.volumes().to_vec(),
        dp,
        velocities: vec![D::zero(); n],
        densities: Vec::new(),
    };
    let mut table = FrictionTable::new(2);
    table.set(0, 1, friction)?;
    // The block's mean velocity (equal masses: its centre of mass's).
    let w = 1.0 / nb as f64;
    let centre = Probe::<D> {
        name: "block".into(),
        target: ProbeTarget::Point {
            reference: D::vector([0.0, 0.5 * size, 0.0]),
            weights: block_ids
                .iter()
                .map(|&i| (i, w, reference[i as usize]))
                .collect(),
        },
        fields: Vec::new(),
        times: Vec::new(),
        positions: Vec::new(),
        velocities: Vec::new(),
    };
    // The gravity impulse on the block along the slope and into it: ∫ g(t) dt · m with the
    // smooth ramp's integral T/2.
    let impulse = D::norm(gravity) * slope.mass * (end_time - 0.5 * ramp);
    let summarise = move |s: &dyn Solver<D>, _: &RunRecord| {
        let mut m = block_summary(s, &reference, &bottom, dp, theory, slope);
        let a = probe_acceleration(s, ramp).unwrap_or(f64::NAN);
        m.insert("acceleration".into(), finite_or_null(a));
        let slid = m.get("slid") == Some(&Json::Bool(true));
        m.insert(
            "acceleration_error".into(),
            if slid && theory > 0.0 {
                finite_or_null(a / theory - 1.0)
            } else {
                Json::Null
            },
        );
        m.insert("gravity_impulse".into(), finite_or_null(impulse));
        for (name, value) in s.figures() {
            match name {
                "contact_friction_work" => {
                    m.insert(name.into(), finite_or_null(value));
                }
                // UL: the balance against gravity's impulse (relative).
                "momentum_balance" => {
                    m.insert(
                        "gravity_impulse_error".into(),
                        finite_or_null(value / impulse - 1.0),
                    );
                }
                _ => {}
            }
        }
        if let Some(series) = s.series().iter().find(|x| x.name == "contact_friction_0") {
            if let Some(st) = series.column("sticking") {
                m.insert(
                    "sticking_final".into(),
                    finite_or_null(st.last().copied().unwrap_or(f64::NAN)),
                );
                let later = &st[1.min(st.len())..];
                m.insert(
                    "sticking_mean".into(),
                    finite_or_null(later.iter().sum::<f64>() / later.len() as f64),
                );
            }
        }
        m
    };
    if UL_METHODS.contains(&method) {
        let constants = *Material::<D>::constants(&mat);
        return run_ul(
            "incline-block",
            method,
            p,
            body,
            constants,
            |s| {
                Ok(s.with_constraints(constraints)
                    .with_loads(loads)
                    .with_contact(body_of)?
                    .with_contact_friction(table)?
                    .with_probes(vec![centre], interval)?)
            },
            end_time,
            options,
            summarise,
        );
    }
    run_tl(
        "incline-block",
        method,
        p,
        body,
        mat,
        |s| {
            Ok(s.with_bodies(body_of)?
                .with_contact_friction(table)?
                .with_constraints(constraints)
                .with_loads(loads)
                .with_probes(vec![centre], interval)?)
        },
        end_time,
        options,
        summarise,
    )
}

/// Twice the leading coefficient of the least-squares parabola `x(t) = c0 + c1 t + c2 t²`
/// through the block probe's position along the slope over the samples at or after `ramp`
/// (`None` with fewer than three). The position, the integral of the velocity, carries the
/// block's bouncing on the particle floor (vertical and rocking modes, ±0.1 m/s in the
/// velocity at resolution 10) damped by its frequency, so the fit is steadier than one of the
/// velocity or the velocity change over the window.
fn probe_acceleration<D: Dim>(s: &dyn Solver<D>, ramp: f64) -> Option<f64> {
    let probe = s.probes().iter().find(|p| p.name == "block")?;
    let (t, x): (Vec<f64>, Vec<f64>) = probe
        .times
        .iter()
        .zip(&probe.positions)
        .filter(|(&t, _)| t >= ramp * (1.0 - 1e-12))
        .map(|(&t, &x)| (t, D::component(x, 0)))
        .unzip();
    if t.len() < 3 {
        return None;
    }
    // Centred time for conditioning; normal equations of the 3 × 3 fit.
    let tm = t.iter().sum::<f64>() / t.len() as f64;
    let mut a = [[0.0; 3]; 3];
    let mut b = [0.0; 3];
    for (&ti, &xi) in t.iter().zip(&x) {
        let s = ti - tm;
        let row = [1.0, s, s * s];
        for r in 0..3 {
            for c in 0..3 {
                a[r][c] += row[r] * row[c];
            }
            b[r] += row[r] * xi;
        }
    }
    let m = glam::DMat3::from_cols_array_2d(&a);
    if m.determinant().abs() <= f64::MIN_POSITIVE {
        return None;
    }
    let c = m.inverse() * glam::DVec3::from_array(b);
    Some(2.0 * c.z)
}

/// What the acceleration along the slope is measured from.
#[derive(Clone, Copy, Debug)]
struct Slope {
    /// `g sin θ` after the ramp (m/s²).
    gravity: f64,
    /// The block's mass (kg; per unit depth in 2D).
    mass: f64,
    /// The gravity ramp's duration (s).
    ramp: f64,
}

/// The mean acceleration of the centre of mass along the slope over the samples after the
/// ramp, from Newton's law: `g sin θ − F̄_x/m`, with `F̄_x` the time average of the force the
/// block exerts on the floor along the slope (the series `incline`'s `force_x`, each row the
/// mean over the interval since the row before). `None` without samples after the ramp.
fn windowed_acceleration(s: &dyn Solver<impl Dim>, slope: Slope) -> Option<f64> {
    let series = s.series();
    let floor = series.iter().find(|x| x.name == "incline")?;
    let force = floor.column("force_x")?;
    let (mut impulse, mut span) = (0.0, 0.0);
    for (w, &f) in floor.time.windows(2).zip(&force[1..]) {
        let (t0, t1) = (w[0], w[1]);
        if t0 >= slope.ramp * (1.0 - 1e-12) {
            impulse += f * (t1 - t0);
            span += t1 - t0;
        }
    }
    (span > 0.0).then(|| slope.gravity - impulse / span / slope.mass)
}

/// The block's figures from the final state (see the module documentation).
fn block_summary<D: Dim>(
    s: &dyn Solver<D>,
    reference: &[D::Vector],
    bottom: &[usize],
    dp: f64,
    theory: f64,
    slope: Slope,
) -> Map<String, Json> {
    let ids = s.particle_ids();
    let (x, v) = (s.positions(), s.velocities());
    // Equal volumes and density: the centre of mass is the mean (in input order, so every
    // method sums in the same order).
    let mut at = vec![0usize; ids.len()];
    for (k, &id) in ids.iter().enumerate() {
        at[id as usize] = k;
    }
    let n = reference.len() as f64;
    let vx = at.iter().map(|&k| D::component(v[k], 0)).sum::<f64>() / n;
    let slide = bottom
        .iter()
        .map(|&i| D::component(x[at[i]], 0) - D::component(reference[i], 0))
        .sum::<f64>()
        / bottom.len().max(1) as f64;
    let acceleration = windowed_acceleration(s, slope).unwrap_or(f64::NAN);
    let slid = slide > 0.05 * dp;
    let mut m = Map::new();
    m.insert("acceleration".into(), finite_or_null(acceleration));
    m.insert("acceleration_theory".into(), json!(theory));
    m.insert(
        "acceleration_error".into(),
        if slid && theory > 0.0 {
            finite_or_null(acceleration / theory - 1.0)
        } else {
            Json::Null
        },
    );
    m.insert("slid".into(), json!(slid));
    m.insert("velocity_final".into(), finite_or_null(vx));
    m.insert("slide_distance".into(), finite_or_null(slide));
    for (name, value) in s.figures() {
        if matches!(
            name,
            "tool_contact_work" | "friction_work" | "friction_dissipated"
        ) {
            m.insert(name.into(), finite_or_null(value));
        }
    }
    if let Some(series) = s.series().iter().find(|x| x.name == "incline") {
        if let Some(st) = series.column("sticking") {
            m.insert(
                "sticking_final".into(),
                finite_or_null(st.last().copied().unwrap_or(f64::NAN)),
            );
            // The samples after t = 0 (the first row is the empty start).
            let later = &st[1.min(st.len())..];
            m.insert(
                "sticking_mean".into(),
                finite_or_null(later.iter().sum::<f64>() / later.len() as f64),
            );
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rigid_block_sticks_below_the_static_angle_and_slides_above() {
        assert_eq!(sliding_acceleration(9.81, 20.0, 0.4, 0.3), 0.0);
        let a = sliding_acceleration(9.81, 30.0, 0.4, 0.3);
        let expected = 9.81 * (0.5 - 0.3 * 3f64.sqrt() / 2.0);
        assert!((a - expected).abs() < 1e-12, "{a}");
        // Frictionless: g sin θ.
        assert!((sliding_acceleration(2.0, 30.0, 0.0, 0.0) - 1.0).abs() < 1e-12);
    }
}
