//! What the MPS-method cases share: the Hamiltonian model's numerical parameters as case keys,
//! the probe helper, and the run tail ([`run_mps`], the MPS counterpart of
//! [`crate::cases::tl_common::run_tl`]).

use crate::cases::tl_common::{meta, schedule};
use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::{drive, RunOptions, RunRecord};
use serde_json::{json, Map, Value as Json};
use sph_core::Body;
use sph_core::{Dim, Probe, Solver, WendlandC2};
use sph_materials::MaterialModel;
use sph_mps::{Fit, Integrator, MpsParams, MpsSolver};

/// The MPS method names.
pub const MPS_METHODS: &[&str] = &["mps"];

/// Keys every MPS case accepts. Defaults: `sph_mps::MpsParams::default()` (the MPS paper gives
/// neither `r_e` nor the Courant number; see that type's documentation); `damping` is 0 (the
/// Hamiltonian scheme) unless a case says otherwise.
pub fn mps_params() -> Vec<Param> {
    let d = MpsParams::default();
    let mut v = vec![
        Param::float(
            "re_over_l0",
            d.re_over_l0,
            Range::Open(MpsParams::RE_OVER_L0_RANGE.0, MpsParams::RE_OVER_L0_RANGE.1),
            "weight radius r_e / l0 of MPS eq 6",
        ),
        Param::float(
            "courant",
            d.courant,
            Range::Open(MpsParams::COURANT_RANGE.0, MpsParams::COURANT_RANGE.1),
            "C of Δt = C l0 / c0",
        ),
        Param::choice(
            "integrator",
            "velocity-verlet",
            &["velocity-verlet", "symplectic-euler"],
            "symplectic integrator (symplectic-euler = MPS eq 8)",
        ),
        Param::float(
            "damping",
            d.damping,
            Range::NonNegative,
            "velocity damping c_d (1/s) for static problems; 0 = Hamiltonian",
        ),
        Param::choice(
            "fit",
            "linear",
            &["linear", "quadratic"],
            "the WLS fit that gives F: linear (MPS eq 4–5) or with quadratic terms (exact for \
             quadratic fields at free surfaces too; beyond the paper)",
        ),
        Param::float(
            "stabilisation",
            d.stabilisation,
            Range::Closed(
                MpsParams::STABILISATION_RANGE.0,
                MpsParams::STABILISATION_RANGE.1,
            ),
            "strength α of the Hamiltonian stabilisation (penalty potential on the residual of \
             the WLS fit, stiffness α μ; beyond the paper); 0 = the paper's model, 3 = the \
             strength docs/validation.md recommends",
        ),
    ]
    .into_iter()
    .map(|p| p.only(MPS_METHODS))
    .collect::<Vec<_>>();
    v.extend(crate::runner::output_params());
    v
}

/// The numerical parameters from the case keys.
pub fn mps_numerics(p: &Params) -> MpsParams {
    MpsParams {
        re_over_l0: p.f64("re_over_l0"),
        courant: p.f64("courant"),
        integrator: match p.text("integrator") {
            "symplectic-euler" => Integrator::SymplecticEuler,
            _ => Integrator::VelocityVerlet,
        },
        damping: p.f64("damping"),
        fit: match p.text("fit") {
            "quadratic" => Fit::Quadratic,
            _ => Fit::Linear,
        },
        stabilisation: p.f64("stabilisation"),
        ..MpsParams::default()
    }
}

/// A probe on the material point `x_star`, Shepard-interpolated with a Wendland C2 kernel of
/// `h = 1.15 dp` (the TL cases' kernel, so MPS and TL probes of a case observe the same point).
pub fn point_probe<D: Dim>(
    name: &str,
    x_star: D::Vector,
    reference: &[D::Vector],
    volumes: &[f64],
    dp: f64,
) -> Result<Probe<D>, CaseError> {
    let kernel = WendlandC2::<D>::from_spacing(dp, 1.15)?;
    Ok(Probe::point(name, x_star, reference, volumes, &kernel)?)
}

/// Output fields written with every snapshot.
pub const MPS_FIELDS: &[&str] = &[
    "velocity",
    "displacement",
    "von_mises",
    "jacobian",
    "disorder",
];

/// Builds an MPS solver and runs it: the tail every MPS case shares.
#[allow(clippy::too_many_arguments)]
pub fn run_mps<D: Dim>(
    case: &str,
    p: &Params,
    body: Body<D>,
    material: MaterialModel,
    attach: impl FnOnce(MpsSolver<D, MaterialModel>) -> Result<MpsSolver<D, MaterialModel>, CaseError>,
    end_time: f64,
    options: &RunOptions,
    summarise: impl FnOnce(&dyn Solver<D>, &RunRecord) -> Map<String, Json>,
) -> Result<(RunRecord, Map<String, Json>), CaseError>
where
    MaterialModel: sph_materials::Material<D>,
{
    let solver = MpsSolver::new(body, material, mps_numerics(p))?;
    let mut solver = attach(solver)?;
    let mut meta = meta(case, "mps", p, solver.len());
    meta.insert(
        "guarded_particles".into(),
        json!(solver.guarded_particles()),
    );
    meta.insert("re".into(), json!(solver.re()));
    let schedule = schedule(p, end_time);
    if let Some(comm) = options.ranks.as_ref().filter(|c| c.size() > 1) {
        let mut solver = sph_mps::distribute(solver, comm.clone())?;
        return Ok(drive::<D>(
            &mut solver,
            meta,
            schedule,
            MPS_FIELDS,
            options,
            summarise,
        )?);
    }
    Ok(drive::<D>(
        &mut solver,
        meta,
        schedule,
        MPS_FIELDS,
        options,
        summarise,
    )?)
}
