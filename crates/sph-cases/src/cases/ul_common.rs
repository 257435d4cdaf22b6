//! What the UL-method cases share: the UL paper's numerical parameters as case keys, the method
//! name → shear treatment mapping, and the run tail.

use crate::cases::tl_common::{meta, schedule};
use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::{drive, RunOptions, RunRecord};
use serde_json::{json, Map, Value as Json};
use sph_core::Body;
use sph_core::{Dim, Solver};
use sph_materials::ElasticConstants;
use sph_ul::{LaplacianForm, RiemannScheme, Shear, Stepping, UlParams, UlSolver};

/// The UL methods.
pub const UL_METHODS: &[&str] = &["ul-enog", "ul-og", "ul-oas", "ul-gnog"];

/// Keys every UL case accepts (defaults: UL paper §5–6).
pub fn ul_params() -> Vec<Param> {
    vec![
        Param::float(
            "ul_h_over_dp",
            1.3,
            Range::Closed(UlParams::H_OVER_DP_RANGE.0, UlParams::H_OVER_DP_RANGE.1),
            "UL smoothing length / dp",
        ),
        Param::choice(
            "stepping",
            "dual",
            &["dual", "single"],
            "dual-criteria (advection + acoustic) or single-criterion time stepping",
        ),
        Param::float(
            "ul_zeta",
            0.0,
            Range::NonNegative,
            "ENOG ζ (0: 0.7 d + 2.1, the paper's value for h = 1.3 dp)",
        )
        .only(&["ul-enog"]),
        Param::choice(
            "enog_form",
            "conservative",
            &["conservative", "non-conservative"],
            "ENOG Laplacian: eq 19 (conservative) or eq 18",
        )
        .only(&["ul-enog"]),
        Param::float(
            "as_epsilon",
            0.3,
            Range::NonNegative,
            "OAS artificial-stress ε",
        )
        .only(&["ul-oas"]),
        Param::int("as_n", 4, Range::Closed(1.0, 16.0), "OAS exponent n").only(&["ul-oas"]),
        Param::float(
            "gnog_xi",
            sph_ul::generalized::DEFAULT_XI,
            Range::Closed(1e-3, 1e3),
            "GNOG penalty factor ξ (arXiv 2409.11474; the authors' SPHinXsys default 2)",
        )
        .only(&["ul-gnog"]),
        Param::float(
            "ul_cfl_acoustic",
            0.4,
            Range::Open(UlParams::CFL_RANGE.0, UlParams::CFL_RANGE.1),
            "CFL_ac of eq 22: Δt_ac = CFL_ac h/(c0 + |v|max)",
        ),
        Param::float(
            "ul_cfl_advection",
            0.2,
            Range::Open(UlParams::CFL_RANGE.0, UlParams::CFL_RANGE.1),
            "CFL_ad of eq 21: Δt_ad = CFL_ad h/|v|max",
        ),
        Param::bool(
            "ul_corrected_gradient",
            false,
            "OG/OAS: velocity gradient with the correction matrix B (eq 26); false: eq 14 as \
             printed (energy-consistent)",
        )
        .only(&["ul-og", "ul-oas"]),
        Param::bool(
            "refresh_kernel_data",
            true,
            "recompute e_ij, r_ij, W′ from the current positions in every acoustic sub-step \
             (the list and B stay those of the rebuild); false = docs/methods.md's frozen data: \
             1.34–1.39× faster per sub-step but the plate softens secularly (period +7 % in 3 s)",
        ),
        Param::bool(
            "allow_fracture",
            false,
            "let particles that lose every neighbour fly on (counted in the summary as \
             `isolated_max`) instead of stopping the run",
        ),
        Param::bool(
            "energy_budget",
            true,
            "keep the energy budget (kinetic + volumetric + shear + contact + dissipated + \
             diffused − artificial-stress and load work; summary `energy_residual`)",
        ),
        Param::choice(
            "riemann",
            "sphinxsys-tests",
            &["paper", "sphinxsys-tests", "limited-no-jump"],
            "Riemann solver. Default: what SPHinXsys's solid tests ran (β = 1 in momentum, no \
             pressure jump in continuity). `paper`: limiter + pressure jump in continuity; the \
             jump diffuses density (a volumetric creep) and makes the plate 24 % slow \
             (T = 0.346 vs 0.279 at H/dp = 10). `limited-no-jump`: limiter, no jump",
        ),
    ]
    .into_iter()
    .map(|p| match p.methods {
        Some(_) => p,
        None => p.only(UL_METHODS),
    })
    .collect()
}

/// The UL shear treatment of a method name.
pub fn ul_shear_of(method: &str, p: &Params) -> Result<Shear, CaseError> {
    Ok(match method {
        "ul-og" => Shear::Original,
        "ul-oas" => Shear::ArtificialStress {
            epsilon: p.f64("as_epsilon"),
            n: p.int("as_n") as u32,
        },
        "ul-enog" => Shear::NonNested {
            zeta: (p.f64("ul_zeta") > 0.0).then(|| p.f64("ul_zeta")),
            form: if p.text("enog_form") == "conservative" {
                LaplacianForm::Conservative
            } else {
                LaplacianForm::NonConservative
            },
        },
        "ul-gnog" => Shear::Generalized {
            xi: Some(p.f64("gnog_xi")),
        },
        other => {
            return Err(CaseError::UnknownMethod {
                case: "ul".into(),
                method: other.into(),
                allowed: UL_METHODS.join(", "),
            })
        }
    })
}

/// The numerical parameters from the case keys.
pub fn ul_numerics(p: &Params) -> UlParams {
    UlParams {
        h_over_dp: p.f64("ul_h_over_dp"),
        stepping: if p.text("stepping") == "dual" {
            Stepping::Dual
        } else {
            Stepping::Single
        },
        riemann: match p.text("riemann") {
            "paper" => RiemannScheme::Paper,
            "limited-no-jump" => RiemannScheme::LimitedNoJump,
            _ => RiemannScheme::SphinxsysTests,
        },
        allow_isolated: p.flag("allow_fracture"),
        cfl_acoustic: p.f64("ul_cfl_acoustic"),
        refresh_kernel_data: p.flag("refresh_kernel_data"),
        corrected_velocity_gradient: p.flag("ul_corrected_gradient"),
        cfl_advection: p.f64("ul_cfl_advection"),
        energy_budget: p.flag("energy_budget"),
        // The cases with contact between bodies have the key (MPS rings: their penalty's κ).
        contact_scale: p
            .value("contact_stiffness")
            .map_or(1.0, |_| p.f64("contact_stiffness")),
        ..UlParams::default()
    }
}

/// Output fields written with every UL snapshot (besides `position` and `id`, which the
/// driver writes for every method; `id` is UL's original index).
pub const UL_FIELDS: &[&str] = &[
    "velocity",
    "displacement",
    "density",
    "pressure",
    "von_mises",
    "disorder",
    "fragment",
];

/// Builds a UL solver and runs it: the tail every UL case shares. `attach` receives the solver
/// with particle indices still in the input order (the solver remaps them).
#[allow(clippy::too_many_arguments)]
pub fn run_ul<D: Dim>(
    case: &str,
    method: &str,
    p: &Params,
    body: Body<D>,
    constants: ElasticConstants,
    attach: impl FnOnce(UlSolver<D>) -> Result<UlSolver<D>, CaseError>,
    end_time: f64,
    options: &RunOptions,
    summarise: impl FnOnce(&dyn Solver<D>, &RunRecord) -> Map<String, Json>,
) -> Result<(RunRecord, Map<String, Json>), CaseError> {
    let shear = ul_shear_of(method, p)?;
    // Scale of the momentum balance: Σ m |v| at t = 0 (or Σ m c0 for a body at rest).
    let p_scale = body
        .velocities
        .iter()
        .zip(&body.volumes)
        .map(|(&v, &vol)| D::norm(v) * vol)
        .sum::<f64>()
        .max(body.volumes.iter().sum::<f64>() * constants.sound_speed * 1e-12)
        * constants.density;
    let mut numerics = ul_numerics(p);
    // ENOG's shear stress never feeds back into the motion: integrate it only for the
    // snapshots (the energy budget then uses the exact shear work instead of the estimate).
    numerics.track_shear_stress = options.output.is_some();
    let solver = UlSolver::new(body, constants, shear, numerics)?;
    let mut solver = attach(solver)?;
    let mut meta = meta(case, method, p, solver.len());
    meta.insert(
        "guarded_particles".into(),
        json!(solver.guarded_particles()),
    );
    // Everything in the summary goes through `drive`, so the results file carries it too.
    let summarise = move |s: &dyn Solver<D>, r: &RunRecord| {
        let mut summary = summarise(s, r);
        ul_figures(s, r, p_scale, &mut summary);
        summary
    };
    let fields = crate::runner::case_fields(UL_FIELDS, &solver.field_names());
    let (record, summary) = drive::<D>(
        &mut solver,
        meta,
        schedule(p, end_time),
        &fields,
        options,
        summarise,
    )?;
    Ok((record, summary))
}

/// The UL figures of a run's summary: sub-steps and the throughput they give, neighbour
/// rebuilds, isolated particles, the momentum balance over `p_scale` (Σ m |v| at t = 0), and
/// the energy budget with exactly accumulated works.
fn ul_figures<D: Dim>(
    solver: &dyn Solver<D>,
    record: &RunRecord,
    p_scale: f64,
    summary: &mut Map<String, Json>,
) {
    let figures: std::collections::HashMap<&str, f64> = solver.figures().into_iter().collect();
    let figure = |name: &str| figures.get(name).copied().unwrap_or(f64::NAN);
    // Throughput counts force evaluations: with dual stepping one `step` is an advection step
    // made of several acoustic sub-steps, so `steps` alone would flatter single stepping.
    let acoustic = figure("acoustic_steps");
    summary.insert("advection_steps".into(), json!(record.steps));
    summary.insert("acoustic_steps".into(), json!(acoustic as u64));
    let rate = if record.solver_seconds > 0.0 {
        record.particles as f64 * acoustic / record.solver_seconds
    } else {
        0.0
    };
    summary.insert("particle_steps_per_second".into(), json!(rate));
    let rebuilds = figure("neighbour_rebuilds") as u64;
    summary.insert("neighbour_rebuilds".into(), json!(rebuilds));
    let isolated = figure("isolated_max") as u64;
    summary.insert("isolated_max".into(), json!(isolated));
    // Σ m v − (Σ m v)(0) + the supports' impulse, over Σ m |v(0)|: round-off for any scene
    // without loads (every pair term is antisymmetric).
    summary.insert(
        "momentum_balance".into(),
        json!(figure("momentum_balance") / p_scale),
    );
    // The budget with the exactly accumulated work of ENOG's A_s and of the contact forces in
    // place of their estimates (shear energy from the output stress, contact potential).
    if let Some(b) = solver.energy_budget() {
        let e0 = b.initial_total;
        let swap = |term: &str, note: &str| match (b.get(term), b.get(note)) {
            (Some(t), Some(n)) => n - t,
            _ => 0.0,
        };
        let exact = b.residual() + swap("shear", "shear_work") + swap("contact", "contact_work");
        if e0 > 0.0 {
            summary.insert("energy_residual_exact_work".into(), json!(exact / e0));
            for (key, note) in [
                ("shear_work_final", "shear_work"),
                ("contact_work_final", "contact_work"),
            ] {
                if let Some(w) = b.get(note) {
                    summary.insert(key.into(), json!(w / e0));
                }
            }
        }
    }
    summary.insert("fracture".into(), json!(isolated > 0));
    let first = figure("first_isolation_time");
    summary.insert(
        "first_isolation_time".into(),
        if first.is_nan() {
            Json::Null
        } else {
            json!(first)
        },
    );
}
