//! `sph converge`: a case at a ladder of resolutions until every quantity's estimated error is
//! within the tolerance (`sph_cases::converge`, `sph_driver::convergence`).

use super::*;
use sph_cases::converge::{self, report, Quantity, Refinement, Runner, Subject};
use sph_driver::convergence::ladder::{LadderError, Plan, Report};

#[derive(clap::Args)]
pub(super) struct ConvergeArgs {
    /// Case name (see `sph list`), or a scene file (every body's dp is refined).
    case: String,
    /// A quantity to converge: a summary key (e.g. period), probe:NAME:position.y:min,
    /// series:NAME:COLUMN:max, … (repeatable).
    #[arg(long = "quantity", short = 'q', value_name = "KEY", required = true)]
    quantities: Vec<String>,
    /// The relative error to reach, e.g. 1% or 0.01.
    #[arg(long)]
    tolerance: String,
    /// The method, or several separated by commas (a ladder each; the report compares them).
    #[arg(long, short)]
    method: Option<String>,
    /// Set a parameter (or a scene key) for every level: key=value (repeatable; not the
    /// resolution key, nor a body's dp).
    #[arg(long = "set", short = 's', value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// A case's parameter file applied to every level.
    #[arg(long)]
    config: Option<PathBuf>,
    /// The first level's resolution (default: the case's default over ratio², at least 4); for
    /// a scene file, the finest body's dp (default: the file's times ratio²).
    #[arg(long)]
    start: Option<f64>,
    /// The refinement ratio between levels, 1 < ratio <= 4 (default 1.5).
    #[arg(long, default_value_t = 1.5)]
    ratio: f64,
    /// Most levels, 2 to 20 (default 6).
    #[arg(long, default_value_t = 6)]
    levels: usize,
    /// The CPU time the whole ladder may take (e.g. 30min, 600s, 2h) or the memory one level
    /// may take (e.g. 4GiB, 500MiB); repeatable for both. The ladder stops before a level
    /// predicted to exceed it.
    #[arg(long, value_name = "AMOUNT")]
    budget: Vec<String>,
    /// Directory of the levels' runs, reused when the same level is asked for again (default
    /// `<out>/converge-<case>`).
    #[arg(long)]
    store: Option<PathBuf>,
    /// Directory for the default store.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// The report (JSON; an HDF5 file and a PNG plot beside it); default `<store>/report.json`.
    #[arg(long)]
    report: Option<PathBuf>,
    /// Worker threads of every level, 1 to 1024.
    #[arg(long)]
    threads: Option<usize>,
}

/// `1%`, `0.5 %` or `0.01`: a relative tolerance.
pub(super) fn parse_tolerance(text: &str) -> Result<f64, CaseError> {
    let t = text.trim();
    let (number, scale) = match t.strip_suffix('%') {
        Some(n) => (n.trim(), 0.01),
        None => (t, 1.0),
    };
    let x = number.parse::<f64>().ok().map(|x| x * scale);
    match x {
        Some(x) if x.is_finite() && x > 0.0 && x < 1.0 => Ok(x),
        _ => Err(CaseError::InvalidValue {
            key: "--tolerance".into(),
            value: text.into(),
            allowed: "a relative error, 0 < tolerance < 100 % (e.g. 1% or 0.01)".into(),
        }),
    }
}

/// A budget: CPU seconds (`s`, `min`, `h`) or bytes (`MiB`, `GiB`).
fn parse_budget(text: &str) -> Result<(Option<f64>, Option<f64>), CaseError> {
    let t = text.trim();
    let bad = || CaseError::InvalidValue {
        key: "--budget".into(),
        value: text.into(),
        allowed: "CPU time (600s, 30min, 2h) or memory (500MiB, 4GiB), > 0".into(),
    };
    let units: [(&str, f64, bool); 5] = [
        ("min", 60.0, true),
        ("h", 3600.0, true),
        ("s", 1.0, true),
        ("MiB", (1u64 << 20) as f64, false),
        ("GiB", (1u64 << 30) as f64, false),
    ];
    for (suffix, scale, time) in units {
        if let Some(n) = t.strip_suffix(suffix) {
            let x: f64 = n.trim().parse().map_err(|_| bad())?;
            if !(x.is_finite() && x > 0.0) {
                return Err(bad());
            }
            return Ok(if time {
                (Some(x * scale), None)
            } else {
                (None, Some(x * scale))
            });
        }
    }
    Err(bad())
}

/// The subject of the ladder of one method, checked as `sph run` would check the run (for a
/// case, its refinement key; for a scene, every body's spacing), with its refinement.
fn subject(a: &ConvergeArgs, method: Option<&str>) -> Result<(Subject, Refinement), CaseError> {
    let run_args = RunArgs::for_target(&a.case, method, &a.set, a.config.clone())?;
    let refused = |key: &str| {
        a.set
            .iter()
            .find(|s| {
                let k = s.split('=').next().unwrap_or("").trim();
                k == key || (key == "dp" && k.starts_with("body") && k.ends_with(".dp"))
            })
            .map(|s| {
                CaseError::Config(format!(
                    "--set {s}: the ladder sets {key} (use --start and --ratio)"
                ))
            })
    };
    match job(&run_args)? {
        Job::Case {
            case,
            method,
            params: _,
        } => {
            let r = converge::refinement_of(case, method)?;
            if let Some(e) = refused(r.key) {
                return Err(e);
            }
            Ok((
                Subject::Case {
                    case,
                    method,
                    config: a.config.clone(),
                    set: a.set.clone(),
                },
                r,
            ))
        }
        Job::Scene(scene, file) => {
            if let Some(e) = refused("dp") {
                return Err(e);
            }
            let (spacings, dp_parameter) = converge::scene_spacings(&scene);
            Ok((
                Subject::Scene {
                    file,
                    name: scene.name().to_string(),
                    method: scene.method().to_string(),
                    set: a.set.clone(),
                    spacings: spacings.clone(),
                    dp_parameter,
                },
                converge::scene_refinement(&spacings, dp_parameter),
            ))
        }
    }
}

pub(super) fn converge_command(a: ConvergeArgs) -> Result<ExitCode, CaseError> {
    let tolerance = parse_tolerance(&a.tolerance)?;
    let (mut cpu_budget, mut memory_budget) = (None, None);
    for b in &a.budget {
        let (c, m) = parse_budget(b)?;
        cpu_budget = c.or(cpu_budget);
        memory_budget = m.or(memory_budget);
    }
    let quantities: Vec<Quantity> = a
        .quantities
        .iter()
        .map(|q| q.parse().map_err(CaseError::Config))
        .collect::<Result<_, _>>()?;
    let methods: Vec<Option<&str>> = match &a.method {
        Some(list) => list.split(',').map(|m| Some(m.trim())).collect(),
        None => vec![None],
    };
    // Every method's runs checked as `sph run` would, before any work.
    let subjects: Vec<(Subject, Refinement)> = methods
        .iter()
        .map(|m| subject(&a, *m))
        .collect::<Result<_, _>>()?;
    let threads = threads::configure(a.threads)?;
    let name = subjects[0].0.name().to_string();
    let store = a
        .store
        .clone()
        .unwrap_or_else(|| converge::default_store(&a.out, &name));
    let report_path = a
        .report
        .clone()
        .unwrap_or_else(|| store.join("report.json"));
    let program = std::env::current_exe().map_err(|e| CaseError::Io {
        path: "the sph program".into(),
        source: e,
    })?;
    let runner = Runner {
        program,
        store: store.clone(),
        threads,
        quantities,
        announce: |c| say(&format!("level: {c}")),
    };
    let plans: Vec<(Subject, Refinement, Plan)> = subjects
        .into_iter()
        .map(|(subject, r)| {
            let first = a
                .start
                .unwrap_or_else(|| runner.first_level(&subject, &r, a.ratio));
            let plan = Plan {
                first,
                ratio: a.ratio,
                max_levels: a.levels,
                whole: r.whole,
                finer_is_larger: r.finer_is_larger,
                tolerance,
                cpu_budget,
                memory_budget: memory_budget
                    .or_else(|| memory_budget_bytes(threads).map(|b| b as f64)),
            };
            (subject, r, plan)
        })
        .collect();
    let _signals = signals::install()?;
    let mut reports: Vec<(&str, Report)> = Vec::new();
    for (subject, r, plan) in &plans {
        let method = subject.method();
        let mut interrupted = None;
        match converge::converge(subject, r, plan, &runner, &a.quantities, &mut interrupted) {
            Ok(rep) => reports.push((method, rep)),
            Err(e) => {
                say(&format!("error: {method}: {e}"));
                return Ok(match (interrupted, &e) {
                    (Some(code), _) => ExitCode::from(code.clamp(0, 255) as u8),
                    (None, LadderError::Invalid(_) | LadderError::BudgetTooSmall { .. }) => {
                        ExitCode::from(2)
                    }
                    (None, _) => ExitCode::from(1),
                });
            }
        }
    }
    let refs: Vec<(&str, &Report)> = reports.iter().map(|(m, r)| (*m, r)).collect();
    let refinement = plans[0].1.key;
    let json = report::to_json(&name, refinement, tolerance, &refs);
    if let Some(dir) = report_path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| CaseError::Io {
            path: dir.display().to_string(),
            source: e,
        })?;
    }
    let h5 = report_path.with_extension("h5");
    let png = report_path.with_extension("png");
    for (what, r) in [
        ("report", report::write_json(&report_path, &json)),
        ("report", report::write_h5(&h5, &json, &refs)),
        ("plot", report::write_png(&png, &name, &refs)),
    ] {
        if let Err(e) = r {
            say(&format!("error: writing the {what}: {e}"));
            return Ok(ExitCode::from(1));
        }
    }
    Ok(print_or_fail(
        &summary_text(&refs, tolerance, &report_path),
        ExitCode::SUCCESS,
    ))
}

/// 80 % of the memory available to a run of `threads` threads (the default memory budget of
/// a level), bytes.
fn memory_budget_bytes(threads: usize) -> Option<u64> {
    Budget::available_to(threads).max_bytes
}

/// The console summary: each quantity's value ± error, order, the levels and the next one.
fn summary_text(reports: &[(&str, &Report)], tolerance: f64, report: &std::path::Path) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    for (m, r) in reports {
        let _ = writeln!(
            s,
            "{m}: {} ({})",
            if r.met { "met" } else { "not met" },
            r.stopped
        );
        for q in &r.quantities {
            let _ = writeln!(
                s,
                "  {:<28} {:.6e} ± {:.3} %  order {}  {}{}",
                q.quantity,
                q.value,
                100.0 * q.error_estimate,
                q.order.map_or("–".into(), |p| format!("{p:.2}")),
                if q.asymptotic {
                    "asymptotic"
                } else {
                    "NOT asymptotic"
                },
                q.warning
                    .as_ref()
                    .map(|w| format!(" ({w})"))
                    .unwrap_or_default()
            );
        }
        for l in &r.levels {
            let _ = writeln!(
                s,
                "  level {:<10} {:>10.2} CPU s  {:>8.1} MiB{}",
                l.resolution,
                l.cpu_seconds,
                l.peak_bytes / (1u64 << 20) as f64,
                if l.reused { "  (stored)" } else { "" }
            );
        }
        if let Some(n) = &r.next {
            let _ = writeln!(
                s,
                "  next level {} would take ≈ {:.3e} CPU s, {:.1} MiB",
                n.resolution,
                n.cpu_seconds,
                n.peak_bytes / (1u64 << 20) as f64
            );
        }
    }
    let _ = writeln!(
        s,
        "tolerance {:.3} %; report {} (and .h5, .png)",
        100.0 * tolerance,
        report.display()
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tolerances_and_budgets_parse_or_name_the_problem() {
        assert_eq!(parse_tolerance("1%").unwrap(), 0.01);
        assert_eq!(parse_tolerance(" 0.5 % ").unwrap(), 0.005);
        assert_eq!(parse_tolerance("0.02").unwrap(), 0.02);
        for bad in ["0", "-1%", "100%", "abc", "nan"] {
            let e = parse_tolerance(bad).unwrap_err().to_string();
            assert!(e.starts_with("invalid --tolerance"), "{bad}: {e}");
        }
        assert_eq!(parse_budget("30min").unwrap(), (Some(1800.0), None));
        assert_eq!(parse_budget("2h").unwrap(), (Some(7200.0), None));
        assert_eq!(parse_budget("90s").unwrap(), (Some(90.0), None));
        assert_eq!(
            parse_budget("4GiB").unwrap(),
            (None, Some(4.0 * (1u64 << 30) as f64))
        );
        for bad in ["10", "0s", "-1min", "5 years", "xGiB"] {
            assert!(parse_budget(bad).is_err(), "{bad}");
        }
    }
}
