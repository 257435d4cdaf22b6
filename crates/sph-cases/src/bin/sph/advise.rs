//! `sph advise`: the method and resolution expected to be cheapest for a tolerance, before
//! any run (`sph_cases::advise`).

use super::*;
use sph_cases::advise::{advise, nearest, particles_across, scene_kind, stored, Advice};

#[derive(clap::Args)]
pub(super) struct AdviseArgs {
    /// Case name (see `sph list`) or scene file.
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
    let tolerance = converge::parse_tolerance(&a.tolerance)?;
    if let Job::Scene(scene, file) = job(&RunArgs::for_target(&a.case, None, &a.set, None)?)? {
        return advise_scene(&a, &scene, &file, tolerance);
    }
    let case = find_case(&a.case)?;
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
    write_advice(&a, &json)?;
    Ok(print_or_fail(
        &text(&a, &advice, predicted, tolerance),
        ExitCode::SUCCESS,
    ))
}

/// `--summary`: the advice as JSON.
fn write_advice(a: &AdviseArgs, json: &serde_json::Value) -> Result<(), CaseError> {
    if let Some(path) = &a.summary {
        RunFiles {
            summary: Some(path.clone()),
            ..Default::default()
        }
        .check()?;
        write_summary(
            path,
            &serde_json::to_string_pretty(json).expect("serialises"),
        )?;
    }
    Ok(())
}

/// The stored run's CPU time for other settings: scaled by the particle-steps of the two
/// dry runs (the stored scene's at the stored resolution, and `this`), so the estimate counts
/// what the stored run counted.
fn scaled_cpu(advice: &Advice, r: &sph_cases::advise::StoredRun, this: &[String]) -> Option<f64> {
    let data = stored();
    let scene = data.scenes.iter().find(|s| s.key == advice.scene)?;
    let program = std::env::current_exe().ok()?;
    let mut args: Vec<String> = vec![
        "run".into(),
        scene.case.clone(),
        "--method".into(),
        r.method.clone(),
    ];
    for s in r.extra.iter().chain(&scene.fixed) {
        args.extend(["--set".into(), s.clone()]);
    }
    args.extend([
        "--set".into(),
        format!("{}={}", advice.resolution_key, Value::Float(r.resolution)),
    ]);
    let stored_work = sph_cases::converge::dry_run(&program, &args)?.particle_steps;
    let this_work = sph_cases::converge::dry_run(&program, this)?.particle_steps;
    let p = r.cpu_seconds * this_work / stored_work;
    p.is_finite().then_some(p)
}

/// `sph advise SCENE.toml`: the scene's kind read from what it holds, its thinnest body
/// measured from its particles, the nearest stored scene's cheapest run within the tolerance
/// among the methods the scene can run, and the spacing that gives the thinnest body as many
/// particles across as that run had.
fn advise_scene(
    a: &AdviseArgs,
    scene: &Scene,
    file: &std::path::Path,
    tolerance: f64,
) -> Result<ExitCode, CaseError> {
    let program = std::env::current_exe().map_err(|e| CaseError::Config(e.to_string()))?;
    let run_args = |method: &str, extra: &[String]| -> Vec<String> {
        let mut v = vec![
            "run".to_string(),
            file.display().to_string(),
            "--method".into(),
            method.into(),
        ];
        for s in a.set.iter().chain(extra) {
            v.extend(["--set".into(), s.clone()]);
        }
        v
    };
    // The methods: those asked for (each must take the scene), else every one that does.
    let methods: Vec<&str> = match &a.method {
        Some(list) => {
            let asked: Vec<&str> = list.split(',').map(str::trim).collect();
            for m in &asked {
                let Some(&known) = sph_scene::METHODS.iter().find(|k| *k == m) else {
                    return Err(CaseError::Config(format!(
                        "--method {m}: allowed values are {}",
                        sph_scene::METHODS.join(", ")
                    )));
                };
                job(&RunArgs::for_target(&a.case, Some(known), &a.set, None)?)?;
            }
            sph_scene::METHODS
                .iter()
                .copied()
                .filter(|k| asked.contains(k))
                .collect()
        }
        None => sph_scene::METHODS
            .iter()
            .copied()
            .filter(|m| sph_cases::converge::dry_run(&program, &run_args(m, &[])).is_some())
            .collect(),
    };
    if methods.is_empty() {
        return Err(CaseError::Config(format!(
            "{}: no method's dry run accepts this scene (sph run {} --dry-run says why)",
            a.case, a.case
        )));
    }
    let bodies = scene
        .body_thicknesses()
        .map_err(|e| CaseError::Config(e.to_string()))?;
    let thinnest = bodies
        .iter()
        .min_by(|x, y| x.thickness.total_cmp(&y.thickness))
        .expect("a scene has at least one body (checked by the scene)");
    let kind = scene_kind(scene.spec());
    let dimension = *scene.spec().dimension.get_ref();
    let data = stored();
    let advice =
        nearest(&data, &a.case, kind, dimension, &methods, tolerance).ok_or_else(|| {
            CaseError::Config(format!("no stored trade-off scene resembles {}", a.case))
        })?;
    // The spacing that gives the thinnest body the suggested run's particles across, every
    // body refined by one factor (as sph converge refines a scene).
    let (spacings, dp_parameter) = sph_cases::converge::scene_spacings(scene);
    let refinement = sph_cases::converge::scene_refinement(&spacings, dp_parameter);
    let suggestion = advice.run.as_ref().and_then(|r| {
        let across = particles_across(&advice.scene, r.resolution)?;
        // Three significant digits: a suggestion, not a measurement.
        let exact = refinement.default * (thinnest.thickness / across) / thinnest.dp;
        let value: f64 = format!("{exact:.2e}").parse().ok()?;
        let sets =
            sph_cases::converge::scene_level_sets(&spacings, dp_parameter, &refinement, value);
        let predicted = scaled_cpu(&advice, r, &run_args(&r.method, &sets));
        Some((r, across, value, sets, predicted))
    });
    let mut json = serde_json::to_value(&advice).expect("serialises");
    json["kind"] = serde_json::json!(kind);
    json["methods"] = serde_json::json!(methods);
    json["tolerance"] = serde_json::json!(tolerance);
    json["bodies"] = serde_json::json!(bodies
        .iter()
        .map(|b| serde_json::json!({
            "name": b.name, "dp": b.dp, "particles": b.particles, "thickness": b.thickness
        }))
        .collect::<Vec<_>>());
    if let Some((_, across, value, sets, predicted)) = &suggestion {
        json["particles_across"] = serde_json::json!(across);
        json["dp"] = serde_json::json!(value);
        json["set"] = serde_json::json!(sets);
        json["predicted_cpu_seconds"] = serde_json::json!(predicted);
    }
    write_advice(a, &json)?;
    use std::fmt::Write as _;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<12} {} confidence (stored scene `{}`: {})",
        "from",
        format!("{:?}", advice.confidence).to_lowercase(),
        advice.scene,
        advice.title
    );
    let _ = writeln!(s, "{:<12} {}", "why", advice.why);
    let _ = writeln!(
        s,
        "{:<12} {} {kind} problem ({}); methods that take it: {}",
        "scene",
        if kind == "impact" { "an" } else { "a" },
        match kind {
            "compression" => "tools or prescribed velocities drive it",
            "pressure" => "a pressure load",
            "static" => "relaxed to equilibrium",
            "impact" => "bodies meet",
            _ => "left to move",
        },
        methods.join(", ")
    );
    let _ = writeln!(
        s,
        "{:<12} body `{}`: {:.4e} m across (the largest ball inside it), {:.1} particles at \
         dp {}",
        "thinnest",
        thinnest.name,
        thinnest.thickness,
        thinnest.thickness / thinnest.dp,
        Value::Float(thinnest.dp)
    );
    match &suggestion {
        Some((r, across, value, sets, predicted)) => {
            let sets_text: String = sets.iter().map(|x| format!(" --set {x}")).collect();
            let extra: String = r.extra.iter().map(|x| format!(" --set {x}")).collect();
            let _ = writeln!(
                s,
                "{:<12} --method {}{extra}{sets_text}",
                "suggestion", r.method
            );
            let _ = writeln!(
                s,
                "{:<12} {across:.1} particles across the thinnest body, as the stored run at \
                 {}={} ({:+.2} % at {:.2} CPU s, every finer run of {} within {:.1} % too)",
                "because",
                advice.resolution_key,
                Value::Float(r.resolution),
                100.0 * r.error.unwrap_or(f64::NAN),
                r.cpu_seconds,
                r.line,
                100.0 * tolerance
            );
            if let Some(p) = predicted {
                let _ = writeln!(s, "{:<12} ≈ {p:.3e} CPU s for this scene", "predicted");
            }
            let _ = writeln!(
                s,
                "{:<12} sph converge {} --method {}{extra} --quantity <KEY> --tolerance {} \
                 --start {} --ratio 2 (its third level is the suggestion)",
                "to verify",
                a.case,
                r.method,
                a.tolerance,
                Value::Float(value * 4.0)
            );
        }
        None => {
            let _ = writeln!(
                s,
                "{:<12} none of the stored runs of `{}` reaches {:.1} % with {}: run sph \
                 converge with a budget",
                "suggestion",
                advice.scene,
                100.0 * tolerance,
                methods.join(", ")
            );
        }
    }
    Ok(print_or_fail(&s, ExitCode::SUCCESS))
}

/// The suggested run's CPU time for this case's own settings: the stored run's CPU time
/// scaled by the particle-steps of the two settings' dry runs (the stored scene's and these),
/// so the estimate counts what the stored run counted.
fn predict(a: &AdviseArgs, advice: &Advice, r: &sph_cases::advise::StoredRun) -> Option<f64> {
    let mut this: Vec<String> = vec![
        "run".into(),
        a.case.clone(),
        "--method".into(),
        r.method.clone(),
    ];
    for s in r.extra.iter().chain(&a.set) {
        this.extend(["--set".into(), s.clone()]);
    }
    this.extend([
        "--set".into(),
        format!("{}={}", advice.resolution_key, Value::Float(r.resolution)),
    ]);
    scaled_cpu(advice, r, &this)
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
