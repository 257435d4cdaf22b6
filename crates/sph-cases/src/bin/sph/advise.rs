//! `sph advise`: the method and resolution expected to be cheapest for a tolerance, before
//! any run (`sph_cases::advise`).

use super::*;
use sph_cases::advise::{advise, stored, Advice};

#[derive(clap::Args)]
pub(super) struct AdviseArgs {
    /// Case name (see `sph list`).
    case: String,
    /// The relative error wanted, e.g. 1% or 0.01.
    #[arg(long)]
    tolerance: String,
    /// Only these methods (separated by commas; default: every method of the case).
    #[arg(long, short)]
    method: Option<String>,
    /// The settings of the run to advise on: key=value (repeatable).
    #[arg(long = "set", short = 's', value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Also write the advice as JSON to this file.
    #[arg(long)]
    summary: Option<PathBuf>,
}

pub(super) fn advise_command(a: AdviseArgs) -> Result<ExitCode, CaseError> {
    let case = find_case(&a.case)?;
    let tolerance = converge::parse_tolerance(&a.tolerance)?;
    let methods: Vec<&'static str> = match &a.method {
        Some(list) => list
            .split(',')
            .map(|m| resolve_method(case, Some(m.trim())))
            .collect::<Result<_, _>>()?,
        None => case.info().methods.to_vec(),
    };
    for &m in &methods {
        job(&RunArgs::for_target(&a.case, Some(m), &a.set, None)?)?;
    }
    let data = stored();
    let advice = advise(&data, &a.case, &methods, &a.set, tolerance).ok_or_else(|| {
        CaseError::Config(format!("no stored trade-off scene resembles {}", a.case))
    })?;
    let predicted = advice.run.as_ref().and_then(|r| predict(&a, &advice, r));
    let mut json = serde_json::to_value(&advice).expect("serialises");
    json["predicted_cpu_seconds"] = serde_json::json!(predicted);
    json["tolerance"] = serde_json::json!(tolerance);
    if let Some(path) = &a.summary {
        RunFiles {
            summary: Some(path.clone()),
            ..Default::default()
        }
        .check()?;
        write_summary(
            path,
            &serde_json::to_string_pretty(&json).expect("serialises"),
        )?;
    }
    Ok(print_or_fail(
        &text(&a, &advice, predicted, tolerance),
        ExitCode::SUCCESS,
    ))
}

/// The suggested run's CPU time for this case's own settings: the stored run's CPU time
/// scaled by the particle-steps of the two settings' dry runs (the stored scene's and these),
/// so the estimate counts what the stored run counted.
fn predict(a: &AdviseArgs, advice: &Advice, r: &sph_cases::advise::StoredRun) -> Option<f64> {
    let data = stored();
    let scene = data.scenes.iter().find(|s| s.key == advice.scene)?;
    let program = std::env::current_exe().ok()?;
    let work = |case: &str, set: &[String]| -> Option<f64> {
        let mut args: Vec<String> = vec![
            "run".into(),
            case.into(),
            "--method".into(),
            r.method.clone(),
        ];
        for s in r.extra.iter().chain(set) {
            args.extend(["--set".into(), s.clone()]);
        }
        args.extend([
            "--set".into(),
            format!("{}={}", advice.resolution_key, Value::Float(r.resolution)),
        ]);
        Some(sph_cases::converge::dry_run(&program, &args)?.particle_steps)
    };
    let stored_work = work(&scene.case, &scene.fixed)?;
    let this_work = work(&a.case, &a.set)?;
    let p = r.cpu_seconds * this_work / stored_work;
    p.is_finite().then_some(p)
}

fn text(a: &AdviseArgs, advice: &Advice, predicted: Option<f64>, tolerance: f64) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<12} {} (stored scene `{}`: {})",
        "from",
        format!("{:?}", advice.confidence).to_lowercase() + " confidence",
        advice.scene,
        advice.title
    );
    let _ = writeln!(s, "{:<12} {}", "why", advice.why);
    match &advice.run {
        Some(r) => {
            let extra: String = r.extra.iter().map(|x| format!(" --set {x}")).collect();
            let _ = writeln!(
                s,
                "{:<12} --method {}{} --set {}={}",
                "suggestion",
                r.method,
                extra,
                advice.resolution_key,
                Value::Float(r.resolution)
            );
            let _ = writeln!(
                s,
                "{:<12} {:+.2} % at {:.2} CPU s (2 threads), every finer run of {} within {:.1} % too",
                "stored",
                100.0 * r.error.unwrap_or(f64::NAN),
                r.cpu_seconds,
                r.line,
                100.0 * tolerance
            );
            if let Some(p) = predicted {
                let _ = writeln!(s, "{:<12} ≈ {p:.3e} CPU s for these settings", "predicted");
            }
            // The ladder sets the resolution itself.
            let sets: String = a
                .set
                .iter()
                .filter(|x| x.split('=').next().map(str::trim) != Some(&advice.resolution_key))
                .map(|x| format!(" --set {x}"))
                .collect();
            let _ = writeln!(
                s,
                "{:<12} sph converge {} --method {}{extra}{sets} --quantity <KEY> --tolerance {}",
                "to verify", a.case, r.method, a.tolerance
            );
        }
        None => {
            let _ = writeln!(
                s,
                "{:<12} none of the stored runs reaches {:.1} % (the finest run of each method \
                 and its error are in docs/tradeoffs.md): run sph converge with a budget",
                "suggestion",
                100.0 * tolerance
            );
        }
    }
    s
}
