//! What the TL-method cases share: the numerical parameters of the TL paper as case keys, the
//! method name → shear treatment mapping, and the run metadata.

use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::{drive, RunOptions, RunRecord, Schedule};
use serde_json::{json, Map, Value as Json};
use sph_core::Body;
use sph_core::{Dim, Solver};
use sph_materials::{ElasticConstants, MaterialKind, MaterialModel};
use sph_tl::{HfLaplacian, PairStorage, Shear, TlParams, TlSolver};

/// The TL methods.
pub const TL_METHODS: &[&str] = &["tl-hf", "tl", "tl-gm"];

/// Keys every TL case accepts (defaults: TL paper §4).
pub fn tl_params() -> Vec<Param> {
    let mut v = vec![
        Param::float(
            "h_over_dp",
            1.15,
            Range::Closed(TlParams::H_OVER_DP_RANGE.0, TlParams::H_OVER_DP_RANGE.1),
            "smoothing length / dp",
        ),
        Param::float(
            "cfl",
            0.6,
            Range::Open(TlParams::CFL_RANGE.0, TlParams::CFL_RANGE.1),
            "CFL number of TL eq 33",
        ),
        Param::float("zeta", 1.07, Range::Positive, "ζ of TL-HF (eq 27–28)").only(&["tl-hf"]),
        Param::choice(
            "laplacian",
            "paper",
            &["paper", "normalised"],
            "ζ of TL-HF's Laplacian: the paper's one value, or normalised per particle from its \
             reference neighbourhood (then zeta stays at its default)",
        )
        .only(&["tl-hf"]),
        Param::float(
            "alpha",
            0.1,
            Range::NonNegative,
            "α of the Ganzenmüller penalty (tl-gm)",
        )
        .only(&["tl-gm"]),
        Param::bool("damping", true, "Kelvin–Voigt damping (TL eq 23–24)"),
        Param::bool(
            "dt_stretch",
            false,
            "scale eq 33's acoustic step by the smallest principal stretch (strong compression)",
        ),
        Param::choice(
            "pair_data",
            "stored",
            &["stored", "recomputed"],
            "reference pair data of the force passes: stored, or recomputed every pass (same \
             results; 3D: under 1 KiB per particle, about 2.5x the run time)",
        ),
    ]
    .into_iter()
    .map(|p| match p.methods {
        Some(_) => p,
        None => p.only(TL_METHODS),
    })
    .collect::<Vec<_>>();
    v.extend(crate::runner::output_params());
    v
}

/// The shear treatment of a TL method name.
pub fn shear_of(method: &str, p: &Params) -> Result<Shear, CaseError> {
    Ok(match method {
        "tl" => Shear::Original,
        "tl-hf" => Shear::HourglassFree {
            zeta: p.f64("zeta"),
        },
        "tl-gm" => Shear::Ganzenmuller {
            alpha: p.f64("alpha"),
        },
        other => {
            return Err(CaseError::UnknownMethod {
                case: "tl".into(),
                method: other.into(),
                allowed: TL_METHODS.join(", "),
            })
        }
    })
}

/// `params` with the `material` default the TL paper's HF formulation is written for
/// (`kirchhoff-vol-dev`, TL eq. 10–14) when `method` is `tl-hf`: a case whose paper runs TL-HF
/// with its own law (the oscillation cases) lists this per-method default, and `tl-hf` with any
/// other `material` represents that law through the generalised split
/// (`sph_materials::Material::hf_split`).
pub fn with_hf_paper_law(mut params: Params, method: &str) -> Params {
    if method == "tl-hf" {
        params
            .set_text("material", "kirchhoff-vol-dev")
            .expect("every TL case offers the paper's HF law");
    }
    params
}

/// The numerical parameters from the case keys.
pub fn tl_numerics(p: &Params) -> TlParams {
    TlParams {
        h_over_dp: p.f64("h_over_dp"),
        cfl: p.f64("cfl"),
        damping: p.flag("damping"),
        stretch_limited_dt: p.flag("dt_stretch"),
        pair_storage: PairStorage::from_name(p.text("pair_data"))
            .expect("the key's allowed values are the storage names"),
        hf_laplacian: HfLaplacian::from_name(p.text("laplacian")).unwrap_or_default(),
        ..TlParams::default()
    }
}

/// Builds the material.
pub fn material(
    kind: MaterialKind,
    youngs: f64,
    nu: f64,
    density: f64,
) -> Result<MaterialModel, CaseError> {
    let c = ElasticConstants::from_youngs(youngs, nu, density).map_err(rename_material_error)?;
    Ok(kind.build(c)?)
}

/// Material errors name `youngs_modulus`/`poisson_ratio`/`density`; the cases' keys are the
/// same except `nu`.
fn rename_material_error(e: sph_core::Error) -> CaseError {
    match e {
        sph_core::Error::InvalidParameter {
            field,
            value,
            allowed,
        } if field == "poisson_ratio" => CaseError::InvalidValue {
            key: "nu".into(),
            value,
            allowed: allowed.replace("poisson_ratio", "nu"),
        },
        other => other.into(),
    }
}

/// Standard metadata of a run.
pub fn meta(case: &str, method: &str, p: &Params, particles: usize) -> Map<String, Json> {
    let mut m = Map::new();
    m.insert("case".into(), json!(case));
    m.insert("method".into(), json!(method));
    m.insert("particles".into(), json!(particles));
    m.insert("crate_version".into(), json!(env!("CARGO_PKG_VERSION")));
    m.insert("params".into(), Json::Object(p.to_json()));
    m
}

/// The schedule from the common keys ([`crate::runner::output_params`]).
pub fn schedule(p: &Params, end_time: f64) -> Schedule {
    let monitor = p.f64("monitor_interval");
    let snapshots = p.f64("snapshot_interval");
    Schedule {
        end_time,
        snapshot_interval: if snapshots > 0.0 {
            snapshots
        } else {
            // `snapshots = 1` gives `end_time`: the first and last only.
            end_time / p.int("snapshots").max(1) as f64
        },
        monitor_interval: if monitor > 0.0 {
            monitor
        } else {
            end_time / 200.0
        },
        probe_interval: match p.value("probe_interval") {
            Some(crate::params::Value::Float(x)) => *x,
            _ => 0.0,
        },
        max_steps: match p.value("max_steps") {
            Some(crate::params::Value::Int(n)) => *n as u64,
            _ => 0,
        },
    }
}

/// Output fields written with every snapshot.
pub const TL_FIELDS: &[&str] = &[
    "velocity",
    "displacement",
    "von_mises",
    "jacobian",
    "disorder",
];

/// Builds a TL solver and runs it: the tail every TL case shares.
#[allow(clippy::too_many_arguments)]
pub fn run_tl<D: Dim>(
    case: &str,
    method: &str,
    p: &Params,
    body: Body<D>,
    material: MaterialModel,
    attach: impl FnOnce(TlSolver<D, MaterialModel>) -> Result<TlSolver<D, MaterialModel>, CaseError>,
    end_time: f64,
    options: &RunOptions,
    summarise: impl FnOnce(&dyn Solver<D>, &RunRecord) -> Map<String, Json>,
) -> Result<(RunRecord, Map<String, Json>), CaseError>
where
    MaterialModel: sph_materials::Material<D>,
{
    let shear = shear_of(method, p)?;
    let schedule = schedule(p, end_time);
    if let Some(comm) = options.ranks.as_ref().filter(|c| c.size() > 1) {
        // Each rank builds the neighbour data of its own share only (docs/distributed.md).
        let solver = TlSolver::for_ranks(body, material, shear, tl_numerics(p))?;
        let solver = attach(solver)?;
        let mut solver = sph_tl::distribute(solver, comm.clone())?;
        let mut meta = meta(case, method, p, solver.len());
        meta.insert(
            "guarded_particles".into(),
            json!(solver.local().guarded_particles()),
        );
        let fields = crate::runner::case_fields(TL_FIELDS, &solver.field_names());
        return Ok(drive::<D>(
            &mut solver,
            meta,
            schedule,
            &fields,
            options,
            summarise,
        )?);
    }
    let solver = TlSolver::new(body, material, shear, tl_numerics(p))?;
    let mut solver = attach(solver)?;
    let mut meta = meta(case, method, p, solver.len());
    meta.insert(
        "guarded_particles".into(),
        json!(solver.guarded_particles()),
    );
    let fields = crate::runner::case_fields(TL_FIELDS, &solver.field_names());
    Ok(drive::<D>(
        &mut solver,
        meta,
        schedule,
        &fields,
        options,
        summarise,
    )?)
}
